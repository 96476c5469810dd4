#version 450
// Caustics (method step 5): each coarse cell becomes SUBDIVISION² photons; each photon that
// reaches a receiver is emitted as a point at the hit, sized by distance to the viewer, and
// carrying the irradiance estimate its splat contributes (see docs/units.md).
// Compiled twice (shaders::VARIANTS): as caustics.geom, and as caustics_debug.geom with
// PHOTON_DEBUG, which records every photon's cast in a storage buffer for comparison with the
// CPU twin.
#include "caustic_splat.glsl"

#ifdef PHOTON_DEBUG
// Per photon, two records: (hit, 1 if it landed, else −PHOTON_<reason> of photon_cast.glsl), and
// (surface point, flux: transmitted if it landed, else what it carried towards the water); both
// zero for an invocation with no cell. The flux budget records the triangle estimator's photons
// through this variant too, so it numbers its photons over their grid, N/k × N·k coarse cells
// (caustic_grid_cell; k is 1 for the paper's points), each photon at its index in that grid as
// caustics_triangles.geom places it.
layout(set = 0, binding = BINDING_PHOTON_DEBUG, std430) writeonly buffer PhotonDebug {
    vec4 records[];
} photon_debug;
#endif

layout(points) in;
layout(points, max_vertices = 64) out; // MAX_SUBDIVISION²
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

layout(location = 0) flat in uvec2 v_cell[];
layout(location = 0) flat out vec3 g_irradiance; // irradiance / E_surface per covered pixel

void main() {
#ifdef PHOTON_DEBUG
    uvec2 cell, cells;
    bool has_cell = caustic_grid_cell(v_cell[0], pc.grid, cell, cells);
    vec2 photons_per_axis = vec2(cells * SUBDIVISION);
#else
    float photons_per_axis = float(pc.grid * SUBDIVISION);
#endif
    for (uint j = 0; j < SUBDIVISION; ++j) {
        for (uint i = 0; i < SUBDIVISION; ++i) {
            Photon ph;
#ifdef PHOTON_DEBUG
            uint index = ((v_cell[0].y * pc.grid + v_cell[0].x) * SUBDIVISION + j) * SUBDIVISION + i;
            if (!has_cell) {
                photon_debug.records[2 * index] = vec4(0.0);
                photon_debug.records[2 * index + 1] = vec4(0.0);
                continue;
            }
            vec2 uv = caustic_grid_photon_uv(cell, uvec2(i, j), SUBDIVISION, photons_per_axis);
            bool landed = cast_photon(uv, photons_per_axis, ph);
            photon_debug.records[2 * index] = vec4(ph.hit, landed ? 1.0 : -float(photon_fate));
            photon_debug.records[2 * index + 1] = vec4(ph.surface, ph.flux);
#else
            vec2 uv = photon_grid_uv(v_cell[0], uvec2(i, j), SUBDIVISION, uvec2(pc.grid));
            bool landed = cast_photon(uv, photons_per_axis, ph);
#endif
            CausticSplat splat;
            if (!landed || !caustic_splat(ph, splat)) continue;
            gl_Position = splat.clip;
            gl_PointSize = splat.size;
            g_irradiance = splat.irradiance.rgb;
            EmitVertex();
        }
    }
}
