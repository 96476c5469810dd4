#version 450
// For the raw splat floor: casts every caustic photon once and records the point it draws
// (clip position, irradiance, size, view depth; dropped photons as a clipped point), so
// splat_floor.vert can draw the same points of the same sizes with no photon math.
#include "caustic_splat.glsl"
#include "../photons/photon_dispatch.glsl"

layout(local_size_x = 64) in;
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

struct SplatRecord {
    vec4 clip;
    vec4 irradiance;
    vec4 size_depth; // x: point size, px; y: view depth, m
};
layout(set = 0, binding = BINDING_SPLAT_RECORDS, std430) writeonly buffer SplatRecords {
    SplatRecord records[];
};

void main() {
    uint index = photon_invocation_index();
    if (index >= pc.grid * pc.grid * SUBDIVISION * SUBDIVISION) return;
    Photon ph;
    CausticSplat splat;
    vec2 uv = photon_index_uv(index, SUBDIVISION, pc.grid);
    if (cast_photon(uv, float(pc.grid * SUBDIVISION), ph) && caustic_splat(ph, splat)) {
        records[index] = SplatRecord(splat.clip, splat.irradiance, vec4(splat.size, splat.clip.w, 0.0, 0.0));
    } else {
        records[index] = SplatRecord(vec4(0.0, 0.0, -1.0, 1.0), vec4(0.0), vec4(1.0, 0.0, 0.0, 0.0));
    }
}
