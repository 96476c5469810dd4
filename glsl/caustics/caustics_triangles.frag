#version 450
// Adds a caustic triangle's (or fallback square's) irradiance where its receiver is visible.
// The view depth is per fragment: a triangle spans depths, unlike a point.
#include "../photons/photon_visibility.glsl"

layout(location = 0) in vec4 g_irradiance; // a: a sliver's footprint code, or 0
layout(location = 0) out vec4 out_irradiance;

void main() {
    float view_depth = 1.0 / gl_FragCoord.w; // clip w, the distance along the camera axis
    if (behind_scene(gl_FragCoord.xy, frame.caustic_target_size, view_depth, CAUSTIC_DEPTH_TOLERANCE)) discard;
    float weight = g_irradiance.a > 0.5 ? sliver_footprint_weight(gl_FragCoord.xy, g_irradiance.a) : 1.0;
    out_irradiance = vec4(g_irradiance.rgb * weight, 1.0);
}
