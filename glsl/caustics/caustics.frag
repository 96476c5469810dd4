#version 450
// Adds a photon's irradiance where its receiver is visible. Only fragments in front of the
// scene reach it: the pass's depth test, against the depth that photon_visibility.frag wrote,
// is the visibility test, made before the shader runs.

// The point's vertex carries only what varies per photon (4 components besides its position
// and size): its depth is the point's, and every photon counts 1 in alpha.
layout(location = 0) flat in vec3 g_irradiance;
layout(location = 0) out vec4 out_irradiance;
layout(early_fragment_tests) in;

void main() {
    out_irradiance = vec4(g_irradiance, 1.0);
}
