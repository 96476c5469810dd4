#version 450
// Adds a photon's irradiance where its receiver is visible: the point is tested against the
// scene's depth (the caustic target is smaller than the scene's, so the test is done here,
// with a tolerance because the photon lies on the very surface the depth buffer holds).
#include "frame.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;

layout(location = 0) flat in vec4 g_irradiance;
layout(location = 1) flat in float g_view_depth;
layout(location = 0) out vec4 out_irradiance;

void main() {
    vec2 uv = gl_FragCoord.xy / frame.effect2.zw;
    float scene_z = linear_view_depth(texture(scene_depth, uv).r);
    if (g_view_depth > scene_z * 1.02 + 0.02) discard;
    out_irradiance = g_irradiance;
}
