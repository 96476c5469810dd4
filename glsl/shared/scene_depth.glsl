// The camera's depth buffer, read by the passes that work at an effect target's resolution
// (photon visibility, filter) and by compose, which upsamples those targets to the output.
#ifndef UNDERLIGHT_SCENE_DEPTH_GLSL
#define UNDERLIGHT_SCENE_DEPTH_GLSL
#include "frame.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;

// View depth (m along the camera axis) of what the scene shows at `uv`.
float scene_view_depth(vec2 uv) {
    return linear_view_depth(textureLod(scene_depth, uv, 0.0).r);
}
#endif
