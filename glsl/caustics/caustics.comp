#version 450
// The compute caustic path: one invocation per photon casts it (photon_cast.glsl) and adds its
// splat (caustic_splat.glsl) with atomic adds, pixel by pixel as the rasteriser would: the
// size² pixel centres inside the point's square, each behind the same visibility test.
// Measured against the geometry-shader path by `underlight bench --compare-paths`.
#include "caustic_splat.glsl"
#include "../photons/photon_visibility.glsl"
#include "../photons/photon_accumulation.glsl"

layout(local_size_x = 64) in;
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

void main() {
    uint index = photon_invocation_index();
    if (index >= pc.grid * pc.grid * SUBDIVISION * SUBDIVISION) return;
    Photon ph;
    CausticSplat splat;
    vec2 uv = photon_index_uv(index, SUBDIVISION, pc.grid);
    if (!cast_photon(uv, float(pc.grid * SUBDIVISION), ph) || !caustic_splat(ph, splat)) return;
    vec2 size = frame.caustic_target_size;
    // Window position as the viewport transform gives it; a point of side s covers the
    // pixel centres c with centre − s/2 ≤ c < centre + s/2 on each axis.
    vec2 centre = (splat.clip.xy / splat.clip.w * 0.5 + 0.5) * size;
    ivec2 first = ivec2(ceil(centre - 0.5 * splat.size - 0.5));
    int side = int(splat.size);
    for (int y = 0; y < side; ++y) {
        for (int x = 0; x < side; ++x) {
            ivec2 p = first + ivec2(x, y);
            if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, ivec2(size)))) continue;
            if (behind_scene(vec2(p) + 0.5, size, splat.clip.w, CAUSTIC_DEPTH_TOLERANCE)) continue;
            accumulate(p, int(size.x), splat.irradiance);
        }
    }
}
