// The camera's depth buffer, read by the passes that work at an effect target's resolution
// (photon visibility, filter) and by compose, which upsamples those targets to the output.
#ifndef UNDERLIGHT_SCENE_DEPTH_GLSL
#define UNDERLIGHT_SCENE_DEPTH_GLSL
#include "frame.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;

// The depth buffer's texel under `uv`, clamped to the buffer, as the nearest-filtering
// sampler bound there picks it (a GPU's sampler, which snaps coordinates to its sub-texel
// precision, may pick the neighbour of a coordinate exactly on a texel's edge; both are
// nearest). Read by texel rather than sampled: on llvmpipe a sampled read computes its coordinates, wrap and level per lane, and
// the caustic triangles' fragment shader, which makes six of these reads, is a tenth cheaper
// for it (docs/performance.md, "The caustic triangles' masked work").
ivec2 scene_depth_texel(vec2 uv) {
    ivec2 size = textureSize(scene_depth, 0);
    return clamp(ivec2(floor(uv * vec2(size))), ivec2(0), size - 1);
}

// View depth (m along the camera axis) of what the scene shows at `uv`.
float scene_view_depth(vec2 uv) {
    return linear_view_depth(texelFetch(scene_depth, scene_depth_texel(uv), 0).r);
}

// The world point the scene shows at `uv`: the texel scene_view_depth reads, unprojected at
// that texel's centre.
vec3 scene_world_point(vec2 uv) {
    ivec2 texel = scene_depth_texel(uv);
    vec2 centre = (vec2(texel) + 0.5) / vec2(textureSize(scene_depth, 0));
    vec4 p = frame.camera_inv_view_proj * vec4(centre * 2.0 - 1.0, texelFetch(scene_depth, texel, 0).r, 1.0);
    return p.xyz / p.w;
}
#endif
