#version 450
// Adds a photon's irradiance where its receiver is visible.
#include "../photons/photon_visibility.glsl"

layout(location = 0) flat in vec4 g_irradiance;
layout(location = 1) flat in float g_view_depth;
layout(location = 0) out vec4 out_irradiance;

void main() {
    if (behind_scene(gl_FragCoord.xy, frame.caustic_target_size, g_view_depth, CAUSTIC_DEPTH_TOLERANCE)) discard;
    out_irradiance = g_irradiance;
}
