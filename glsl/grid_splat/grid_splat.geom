#version 450
// Subdivides each coarse cell into SUBDIVISION×SUBDIVISION photons, each a point.
#include "shader_math.glsl"
#include "grid_splat_params.glsl"

layout(points) in;
layout(points, max_vertices = 64) out; // MAX_SUBDIVISION²; layouts need a literal

// Fixed at pipeline creation so the loops unroll (the paper measured ~50% cost for a
// subdivision factor read at run time).
layout(constant_id = 0) const uint SUBDIVISION = 2;

layout(location = 0) flat in uvec2 v_cell[];
layout(location = 0) flat out vec4 g_energy;

void main() {
    for (uint j = 0; j < SUBDIVISION; ++j) {
        for (uint i = 0; i < SUBDIVISION; ++i) {
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, pc.grid);
            uv += pc.wave_amplitude * demo_wave_gradient(uv, pc.time);
            gl_Position = vec4(uv * 2.0 - 1.0, 0.0, 1.0);
            gl_PointSize = pc.point_size;
            // Alpha counts photons, so a read-back can tell coverage from energy.
            g_energy = vec4(vec3(pc.energy), 1.0);
            EmitVertex();
        }
    }
}
