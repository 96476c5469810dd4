#version 450
// Copies a compute photon path's accumulation buffer into its effect target, which the
// filter and compose passes then read exactly as they read a rasterised one.
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_PHOTON_ACCUMULATION, std430) readonly buffer PhotonAccumulation {
    vec4 accumulation[];
};
layout(push_constant) uniform ResolvePush { uvec2 size; } pc;
layout(location = 0) in vec2 v_uv; // 0..1 over the target (pixel centres at (i + 0.5) / size)
layout(location = 0) out vec4 out_value;

void main() {
    uvec2 p = min(uvec2(v_uv * vec2(pc.size)), pc.size - 1u);
    out_value = accumulation[p.y * pc.size.x + p.x];
}
