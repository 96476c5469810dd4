// Depth-aware reads of the low-resolution effect buffers (filter and compose). An effect
// texel holds the light of the surface that the scene's depth shows at the texel's centre:
// the photon passes test their splats against that depth. So a pixel borrows a texel's light
// only where both lie on the same surface; bilinear upsampling across a silhouette would
// paint the far wall's light onto a pillar's rim and the pillar's onto the wall (a halo).
//
// Same surface: the texel's depth lies on the plane the pixel's own depth and depth gradient
// describe. Reciprocal view depth is affine in screen space across a plane, so the test holds
// on floors seen at grazing angles too, where depth itself changes fast and non-linearly.
#ifndef UNDERLIGHT_DEPTH_AWARE_GLSL
#define UNDERLIGHT_DEPTH_AWARE_GLSL
#include "scene_depth.glsl"

// A pixel's surface: reciprocal view depth and its gradient per pixel of `size`.
struct SurfacePlane {
    float inverse_depth;
    vec2 gradient;
};

float inverse_view_depth(vec2 uv) {
    return 1.0 / scene_view_depth(uv);
}

// The gradient from one-sided differences, the smaller of each pair: across a silhouette one
// side jumps and the other still follows the surface.
SurfacePlane surface_plane(vec2 uv, vec2 size) {
    vec2 step = 1.0 / size;
    float w = inverse_view_depth(uv);
    float left = w - inverse_view_depth(uv - vec2(step.x, 0.0));
    float right = inverse_view_depth(uv + vec2(step.x, 0.0)) - w;
    float down = w - inverse_view_depth(uv - vec2(0.0, step.y));
    float up = inverse_view_depth(uv + vec2(0.0, step.y)) - w;
    vec2 gradient = vec2(abs(left) < abs(right) ? left : right, abs(down) < abs(up) ? down : up);
    return SurfacePlane(w, gradient);
}

// How far (relative) reciprocal depth `w` at `offset_px` pixels from the plane's pixel lies
// off that plane: 0 on it. Callers bound it per buffer (frame::CAUSTIC_SAME_SURFACE).
float off_surface(SurfacePlane plane, vec2 offset_px, float w) {
    float predicted = plane.inverse_depth + dot(plane.gradient, offset_px);
    return abs(w - predicted) / max(plane.inverse_depth, 1e-6);
}

// `effect` upsampled to the pixel at `uv` of an output `out_size` pixels large: bilinear over
// the four nearest texels that lie on the pixel's surface (off it by at most `same_surface`,
// frame::CAUSTIC_SAME_SURFACE), renormalised; where none does (a surface thinner than a
// texel), the texel that comes closest.
vec3 upsample_on_surface(sampler2D effect, vec2 uv, vec2 out_size, SurfacePlane plane, float same_surface) {
    vec2 size = vec2(textureSize(effect, 0));
    vec2 p = uv * size - 0.5;
    vec2 base = floor(p);
    vec2 f = p - base;
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    vec3 closest = vec3(0.0);
    float closest_miss = 1e30;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            vec2 texel = clamp(base + vec2(i, j), vec2(0.0), size - 1.0);
            vec2 texel_uv = (texel + 0.5) / size;
            vec3 value = texelFetch(effect, ivec2(texel), 0).rgb;
            float miss = off_surface(plane, (texel_uv - uv) * out_size, inverse_view_depth(texel_uv));
            float bilinear = (i == 1 ? f.x : 1.0 - f.x) * (j == 1 ? f.y : 1.0 - f.y);
            if (miss <= same_surface) {
                sum += bilinear * value;
                weight += bilinear;
            }
            if (miss < closest_miss) {
                closest_miss = miss;
                closest = value;
            }
        }
    }
    return weight > 1e-4 ? sum / weight : closest;
}
#endif
