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
    bool strip = is_strip_code(g_irradiance.a);
    if (g_irradiance.a == 0.0) {
        if (off_scene(gl_FragCoord.xy, size, gl_FragCoord.w, gradient, CAUSTIC_DEPTH_TOLERANCE)) discard;
    } else if (strip) {
        // A strip carries its middle line's depth across its width, so its pixels off that
        // line are held to the surface as a square's are, up to their distance from it.
        float reach = abs(strip_across(g_irradiance.a));
        if (square_off_scene(gl_FragCoord.xy, size, 1.0 / gl_FragCoord.w, reach, CAUSTIC_DEPTH_TOLERANCE)) discard;
    } else {
        // How far a square's pixel centre can lie from its centre: half its diagonal.
        float side = g_irradiance.a > 0.5 ? 2.0 : -g_irradiance.a;
        float reach = 0.5 * sqrt(2.0) * side;
        if (square_off_scene(gl_FragCoord.xy, size, 1.0 / gl_FragCoord.w, reach, CAUSTIC_DEPTH_TOLERANCE)) discard;
    }
    float weight = strip ? strip_weight(g_irradiance.a)
                 : g_irradiance.a > 0.5 ? sliver_footprint_weight(gl_FragCoord.xy, g_irradiance.a) : 1.0;
    out_irradiance = vec4(g_irradiance.rgb * weight, 1.0);
}
