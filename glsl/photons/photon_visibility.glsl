// The visibility test of the photon passes: a photon splat or beam fragment counts only
// where the camera sees it, i.e. where it is not behind the scene's depth at that pixel.
// The effect targets are smaller than the scene's, so the test is done per fragment (or per
// covered pixel in the compute path), with a relative tolerance because a receiver's splat
// lies on the very surface the depth buffer holds.
#ifndef UNDERLIGHT_PHOTON_VISIBILITY_GLSL
#define UNDERLIGHT_PHOTON_VISIBILITY_GLSL
#include "frame.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;

// Whether view depth `view_depth` (m along the camera axis) at pixel centre `pixel` of a
// target `size` pixels large lies behind what the scene shows there.
bool behind_scene(vec2 pixel, vec2 size, float view_depth, float tolerance) {
    float scene_z = linear_view_depth(textureLod(scene_depth, pixel / size, 0.0).r);
    return view_depth > scene_z * (1.0 + tolerance) + tolerance;
}

// Tolerances: a caustic splat sits on its receiver; a beam ends on it.
const float CAUSTIC_DEPTH_TOLERANCE = 0.02;
const float GODRAY_DEPTH_TOLERANCE = 0.01;
#endif
