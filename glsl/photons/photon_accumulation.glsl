// The compute photon paths' accumulation: an RGBA float per pixel of the effect target in a
// storage buffer, added into with float atomics (VK_EXT_shader_atomic_float) where the
// rasterised paths blend additively. photon_resolve.frag copies it into the target.
#ifndef UNDERLIGHT_PHOTON_ACCUMULATION_GLSL
#define UNDERLIGHT_PHOTON_ACCUMULATION_GLSL
#extension GL_EXT_shader_atomic_float : require
#include "frame_textures.glsl"
#include "photon_dispatch.glsl"

layout(set = 0, binding = BINDING_PHOTON_ACCUMULATION, std430) buffer PhotonAccumulation {
    float accumulation[];
};

// Adds v to pixel p of a target `width` pixels wide.
void accumulate(ivec2 p, int width, vec4 v) {
    uint base = 4u * uint(p.y * width + p.x);
    atomicAdd(accumulation[base + 0u], v.r);
    atomicAdd(accumulation[base + 1u], v.g);
    atomicAdd(accumulation[base + 2u], v.b);
    atomicAdd(accumulation[base + 3u], v.a);
}
#endif
