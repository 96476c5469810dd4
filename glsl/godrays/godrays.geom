#version 450
// Godrays (method step 6): the same photon casting on the godray grid, each photon that
// reaches a receiver emitted as a line from where it entered the water to where it lands.
// Compiled twice (shaders::VARIANTS): as godrays.geom, and as godrays_debug.geom with
// PHOTON_DEBUG, which records every beam's cast for the flux budget (src/flux_budget.rs).
#define PHOTON_BEAMS
#include "../photons/photon_cast.glsl"

#ifdef PHOTON_DEBUG
// Per beam, two records: (hit, its fate: 1 drawn, 2 drawn although the image-space iteration
// did not converge, −PHOTON_<reason> of photon_cast.glsl when dropped), and (surface point,
// flux: transmitted if drawn, else what it carried towards the water).
layout(set = 0, binding = BINDING_PHOTON_DEBUG, std430) writeonly buffer PhotonDebug {
    vec4 records[];
} photon_debug;
#endif

layout(points) in;
// 2 vertices × GODRAY_MAX_SUBDIVISION² photons; each vertex carries 12 components (3 vec4s), so
// 72 vertices stay within the 1024 output components every geometry-shader device offers.
layout(line_strip, max_vertices = 72) out;
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) flat in uvec2 v_cell[];
// Only gl_Position of the built-in block (the full block adds point size and clip/cull
// distances to every vertex's component count).
out gl_PerVertex { vec4 gl_Position; };
// Packed into two vec4 locations: the component budget counts whole locations.
layout(location = 0) out vec4 g_world_travelled;   // world position; w: distance from the surface, m
layout(location = 1) flat out vec4 g_beam;         // xyz: r_t; w: flux, W (after the surface)

void main() {
    float photons_per_axis = float(pc.grid * SUBDIVISION);
    for (uint j = 0; j < SUBDIVISION; ++j) {
        for (uint i = 0; i < SUBDIVISION; ++i) {
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, uvec2(pc.grid));
            Photon ph;
            bool landed = cast_photon(uv, photons_per_axis, ph);
#ifdef PHOTON_DEBUG
            uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + j) * SUBDIVISION + i;
            float fate = landed ? (photon_fate == PHOTON_NOT_CONVERGED ? 2.0 : 1.0) : -float(photon_fate);
            photon_debug.records[2 * index] = vec4(ph.hit, fate);
            photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#endif
            if (!landed) continue;
            vec4 a = frame.camera_view_proj * vec4(ph.surface, 1.0);
            vec4 b = frame.camera_view_proj * vec4(ph.hit, 1.0);
            // Lines crossing the camera plane would need clipping against it in world space;
            // the rasteriser clips lines properly, so only drop lines entirely behind.
            if (a.w <= frame.z_near && b.w <= frame.z_near) continue;
            g_beam = vec4(ph.direction, ph.flux);
            gl_Position = a;
            g_world_travelled = vec4(ph.surface, 0.0);
            EmitVertex();
            g_beam = vec4(ph.direction, ph.flux);
            gl_Position = b;
            g_world_travelled = vec4(ph.hit, ph.travelled);
            EmitVertex();
            EndPrimitive();
        }
    }
}
