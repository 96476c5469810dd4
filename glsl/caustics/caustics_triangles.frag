#version 450
// Adds a caustic triangle's (or fallback square's) irradiance where its receiver is visible.
// The view depth is per fragment: a triangle spans depths, unlike a point, so it can be held
// to lie on the surface the pixel shows (off_scene), not only in front of it.
#include "../photons/photon_visibility.glsl"

// a: 0 for a triangle; a strip's code across it (between 0 and 0.5, strip_weight); a
// square's code otherwise: a sliver's footprint (above 0.5, a 2-pixel square) or minus a lone
// photon's square size.
layout(location = 0) in vec4 g_irradiance;
layout(location = 0) out vec4 out_irradiance;

void main() {
    // gl_FragCoord.w is 1 / clip w, the reciprocal of the distance along the camera axis.
    vec2 gradient = vec2(dFdx(gl_FragCoord.w), dFdy(gl_FragCoord.w));
    vec2 size = frame.caustic_target_size;
    float code = g_irradiance.a;
    bool strip = is_strip_code(code);
    // A square's and a strip's pixels off the point where their one depth holds (a square's
    // centre, a strip's middle line) are held to the surface up to their distance from it:
    // half a square's diagonal, a strip's distance across.
    float square_side = code > 0.5 ? 2.0 : -code;
    float reach = strip ? abs(strip_across(code)) : 0.5 * sqrt(2.0) * square_side;
    // One test per kind of primitive, each written once: llvmpipe runs every side of a
    // branch for every fragment, masked, so every fragment ran the squares' test (five reads
    // of the scene's depth) as many times as it was written. Written once for the strips and
    // the squares, the pass is about 5 % cheaper (docs/performance.md, "The caustic
    // triangles' masked work").
    float tolerance = CAUSTIC_DEPTH_TOLERANCE;
    bool off = code == 0.0 ? off_scene(gl_FragCoord.xy, size, gl_FragCoord.w, gradient, tolerance)
                           : square_off_scene(gl_FragCoord.xy, size, 1.0 / gl_FragCoord.w, reach, tolerance);
    if (off) discard;
    float weight = strip ? strip_weight(code) : code > 0.5 ? sliver_footprint_weight(gl_FragCoord.xy, code) : 1.0;
    out_irradiance = vec4(g_irradiance.rgb * weight, 1.0);
}
