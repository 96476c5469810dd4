// The visibility test of the photon passes: a photon splat or beam fragment counts only
// where the camera sees it, i.e. where it is not behind the scene's depth at that pixel.
// The effect targets are smaller than the scene's, so the test is done per fragment (or per
// covered pixel in the compute path), with a relative tolerance because a receiver's splat
// lies on the very surface the depth buffer holds.
#ifndef UNDERLIGHT_PHOTON_VISIBILITY_GLSL
#define UNDERLIGHT_PHOTON_VISIBILITY_GLSL
#include "depth_aware.glsl"

// The farthest view depth (m along the camera axis) at which a fragment still counts as in
// front of a scene surface `scene_z` m away.
float farthest_visible(float scene_z, float tolerance) {
    return scene_z * (1.0 + tolerance) + tolerance;
}

// Whether view depth `view_depth` (m along the camera axis) at pixel centre `pixel` of a
// target `size` pixels large lies behind what the scene shows there. (The rasterised godray
// beams and caustic points make the same test with the depth test: photon_visibility.frag.)
bool behind_scene(vec2 pixel, vec2 size, float view_depth, float tolerance) {
    return view_depth > farthest_visible(scene_view_depth(pixel / size), tolerance);
}

// Whether a fragment of a triangle that lies on its receiver lies off the surface its pixel
// shows, behind it or in front: where the pixel shows another surface, the light belongs to
// no visible receiver. (Testing only "behind" would let the light on a face the camera sees
// edge-on, a pillar's side, spill onto the wall beside the silhouette.) `inverse_depth` is
// the fragment's 1 / view depth (gl_FragCoord.w) and `gradient` its derivative per pixel.
// The depth buffer holds the output's pixels, so it is read at the one nearest the fragment,
// up to half an output pixel away; on a floor seen at a grazing angle depth changes by several
// per cent over that. So the fragment's depth is first carried there along its triangle's
// plane, on which reciprocal depth is affine in screen space.
bool off_scene(vec2 pixel, vec2 size, float inverse_depth, vec2 gradient, float tolerance) {
    vec2 depth_size = vec2(textureSize(scene_depth, 0));
    vec2 depth_uv = (floor(pixel / size * depth_size) + 0.5) / depth_size;
    float at_depth_pixel = inverse_depth + dot(gradient, depth_uv * size - pixel);
    float view_depth = 1.0 / max(at_depth_pixel, 1e-9);
    float scene_z = scene_view_depth(depth_uv);
    return abs(view_depth - scene_z) > scene_z * tolerance + tolerance;
}

// The same for a square splat, whose one depth (its photon's) is its receiver's at the centre
// only. Its other pixels may lie up to `reach_px` target pixels away, over which the surface
// they show changes depth by up to the scene depth's gradient times that: on a floor seen at a
// grazing angle, by several per cent. The tolerance widens by that much. The gradient is the
// pixel's surface plane (depth_aware.glsl), taken on the side of each pair that follows the
// surface, so a wall beside a pillar stays held to its own depth. Compared in reciprocal depth,
// where `tolerance` (relative and in metres, as in off_scene) becomes w·(tolerance + tolerance·w).
bool square_off_scene(vec2 pixel, vec2 size, float view_depth, float reach_px, float tolerance) {
    vec2 depth_size = vec2(textureSize(scene_depth, 0));
    vec2 uv = (floor(pixel / size * depth_size) + 0.5) / depth_size;
    SurfacePlane plane = surface_plane(uv, depth_size);
    float w = plane.inverse_depth;
    // Per target pixel: a target pixel spans depth_size / size depth-buffer pixels.
    float change = length(plane.gradient * depth_size / size) * reach_px;
    return abs(1.0 / view_depth - w) > w * (tolerance + tolerance * w) + change;
}

// Tolerances: a caustic splat sits on its receiver; a beam ends on it.
const float CAUSTIC_DEPTH_TOLERANCE = 0.02;
const float GODRAY_DEPTH_TOLERANCE = 0.01;
#endif
