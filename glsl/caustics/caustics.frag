#version 450
// Adds a photon's irradiance where its receiver is visible.
#include "../photons/photon_visibility.glsl"

// The point's vertex carries only what varies per photon (4 components besides its position
// and size): its view depth is 1 / gl_FragCoord.w, and every photon counts 1 in alpha.
layout(location = 0) flat in vec3 g_irradiance;
layout(location = 0) out vec4 out_irradiance;

void main() {
    float view_depth = 1.0 / gl_FragCoord.w;
    if (behind_scene(gl_FragCoord.xy, frame.caustic_target_size, view_depth, CAUSTIC_DEPTH_TOLERANCE)) discard;
    out_irradiance = vec4(g_irradiance, 1.0);
}
