#version 450
// The compute godray path: one invocation per photon casts it and rasterises its beam
// itself, as the line rasteriser does for the geometry-shader path: the segment from the
// surface to the hit is clipped to the depth range, projected, and covered as a rectangle
// line_width wide (Vulkan's rule for lines with strictLines); each covered pixel centre
// gets the perspective-correct point of the beam under it, the same visibility test and
// the same radiance (godray_beam.glsl), added with float atomics.
#define PHOTON_BEAMS
#include "../photons/photon_cast.glsl"
#include "godray_beam.glsl"
#include "../photons/photon_visibility.glsl"
#include "../photons/photon_accumulation.glsl"

layout(local_size_x = 64) in;
layout(constant_id = 0) const uint SUBDIVISION = 2;
layout(push_constant) uniform GridPush { uint grid; } pc;

// Narrows [s0, s1] of a segment to where fa + s·(fb − fa) ≥ 0; false when nothing is left.
bool clip_half_space(float fa, float fb, inout float s0, inout float s1) {
    if (fa < 0.0 && fb < 0.0) return false;
    if (fa < 0.0) s0 = max(s0, fa / (fa - fb));
    else if (fb < 0.0) s1 = min(s1, fa / (fa - fb));
    return s0 < s1;
}

void main() {
    uint index = photon_invocation_index();
    if (index >= pc.grid * pc.grid * SUBDIVISION * SUBDIVISION) return;
    Photon ph;
    if (!cast_photon(photon_index_uv(index, SUBDIVISION, pc.grid), float(pc.grid * SUBDIVISION), ph)) return;
    vec4 a = frame.camera_view_proj * vec4(ph.surface, 1.0);
    vec4 b = frame.camera_view_proj * vec4(ph.hit, 1.0);
    float s0 = 0.0, s1 = 1.0;
    if (!clip_half_space(a.z, b.z, s0, s1) || !clip_half_space(a.w - a.z, b.w - b.z, s0, s1)) return;
    vec4 ca = mix(a, b, s0), cb = mix(a, b, s1);
    vec3 wa = mix(ph.surface, ph.hit, s0), wb = mix(ph.surface, ph.hit, s1);
    float ta = s0 * ph.travelled, tb = s1 * ph.travelled;

    vec2 size = frame.godray_target_size;
    vec2 pa = (ca.xy / ca.w * 0.5 + 0.5) * size;
    vec2 pb = (cb.xy / cb.w * 0.5 + 0.5) * size;
    vec2 d = pb - pa;
    float len = length(d);
    if (!(len > 1e-6)) return; // a beam seen end-on: a zero-area rectangle
    vec2 dir = d / len, nrm = vec2(-dir.y, dir.x);
    float half_w = 0.5 * clamp(frame.line_width, 1.0, frame.device_max_line_width);

    // Walk the major axis one pixel column at a time; in each, the rectangle's four
    // half-planes g·p ≤ c bound the minor coordinate to an interval.
    int major = abs(d.x) >= abs(d.y) ? 0 : 1, minor = 1 - major;
    vec2 g[4] = vec2[](-dir, dir, nrm, -nrm);
    float c[4] = float[](-dot(dir, pa), dot(dir, pa) + len, dot(nrm, pa) + half_w, -dot(nrm, pa) + half_w);
    float lo = min(pa[major], pb[major]) - half_w, hi = max(pa[major], pb[major]) + half_w;
    int first = max(int(ceil(lo - 0.5)), 0), last = min(int(ceil(hi - 0.5)) - 1, int(size[major]) - 1);
    float inv_wa = 1.0 / ca.w, inv_wb = 1.0 / cb.w;
    for (int i = first; i <= last; ++i) {
        float m = float(i) + 0.5;
        float y_lo = -1e30, y_hi = 1e30;
        for (int k = 0; k < 4; ++k) {
            float rest = c[k] - g[k][major] * m;
            if (abs(g[k][minor]) < 1e-12) {
                if (rest < 0.0) y_hi = -1e30;
            } else if (g[k][minor] > 0.0) {
                y_hi = min(y_hi, rest / g[k][minor]);
            } else {
                y_lo = max(y_lo, rest / g[k][minor]);
            }
        }
        int j0 = max(int(ceil(y_lo - 0.5)), 0), j1 = min(int(ceil(y_hi - 0.5)) - 1, int(size[minor]) - 1);
        for (int j = j0; j <= j1; ++j) {
            ivec2 p = major == 0 ? ivec2(i, j) : ivec2(j, i);
            vec2 centre = vec2(p) + 0.5;
            // The line's interpolation parameter: the centre projected onto the segment,
            // made perspective-correct through 1/w (linear in screen space).
            float u = clamp(dot(centre - pa, dir) / len, 0.0, 1.0);
            float inv_w = mix(inv_wa, inv_wb, u);
            float t = u * inv_wb / inv_w;
            float view_depth = 1.0 / inv_w;
            if (behind_scene(centre, size, view_depth, GODRAY_DEPTH_TOLERANCE)) continue;
            vec3 L = beam_radiance(mix(wa, wb, t), mix(ta, tb, t), ph.direction, ph.flux, view_depth);
            accumulate(p, int(size.x), vec4(L, 1.0));
        }
    }
}
