// Shading helpers shared by the scene, water-surface, background and compose shaders.
#ifndef UNDERLIGHT_UNDERWATER_SHADING_GLSL
#define UNDERLIGHT_UNDERWATER_SHADING_GLSL
#include "frame.glsl"
#include "frame_textures.glsl"

// Whether the camera ray in unit direction `dir` starts under the water. Decided where the
// ray leaves the near plane, against the surface's height there, not by the camera's side of
// the mean plane: a camera at the waterline sees part of its image from each side, and every
// pass that asks (scene, background, godrays, compose) must split the image along the same
// line, or a band of pixels gets the other medium's shading (a seam). The near plane's points
// lie within a few centimetres of the camera, so the surface there is its tangent plane at the
// camera (frame.camera_water_height and _gradient, from the CPU twin): no texture reads, which a CPU rasteriser
// would pay on every fragment even where a branch skips them.
bool view_ray_starts_under(vec3 dir) {
    vec3 c = frame.camera_position;
    vec3 start = c + dir * (frame.z_near / max(dot(dir, camera_forward()), 1e-3));
    float surface = frame.water_level + frame.camera_water_height + dot(frame.camera_water_gradient, start.xz - c.xz);
    return start.y < surface;
}

// Unit camera ray through a pixel at uv (0..1 over the target).
vec3 pixel_ray(vec2 uv) {
    vec4 p = frame.camera_inv_view_proj * vec4(uv * 2.0 - 1.0, 0.0, 1.0);
    return normalize(p.xyz / p.w - frame.camera_position);
}

// Diffuse (sky) irradiance at a point, W/m²: the ambient share of the light, attenuated by
// the water above the point; a receiver facing down gets less of it.
vec3 ambient_irradiance(vec3 p, vec3 n) {
    float depth = max(frame.water_level - p.y, 0.0);
    return frame.ambient_irradiance * water_transmittance(depth) * (0.6 + 0.4 * n.y);
}

// Radiance the water itself sends towards the viewer from in-scattered ambient light
// (what a long underwater view fades to).
vec3 water_fog_radiance() {
    vec3 g = max(frame.attenuation, vec3(1e-3));
    return frame.ambient_irradiance * frame.scattering / g / (4.0 * PI);
}

// Length of the camera ray to p that runs under water, the ray's start decided per pixel
// (view_ray_starts_under) and its crossing taken at the mean plane.
float view_underwater_length(vec3 p) {
    vec3 c = frame.camera_position;
    float len = length(p - c);
    bool c_in = view_ray_starts_under((p - c) / max(len, 1e-6));
    bool p_in = p.y < frame.water_level;
    if (c_in == p_in) return c_in ? len : 0.0;
    float dy = p.y - c.y;
    float s = abs(dy) > 1e-6 ? clamp((frame.water_level - c.y) / dy, 0.0, 1.0) : 0.5;
    return c_in ? s * len : (1.0 - s) * len;
}

// Thesis eq. 4–5 per channel: radiance L seen through d metres of water fades to the water's
// own colour (its in-scattered glow) with transmittance e^(−γd).
vec3 through_water_length(vec3 L, float d) {
    vec3 t = water_transmittance(d);
    return water_fog_radiance() + t * (L - water_fog_radiance());
}

// Applies the water between the camera and p to radiance L leaving p.
vec3 through_water(vec3 L, vec3 p) {
    return through_water_length(L, view_underwater_length(p));
}

// Radiance of the sky in direction dir (above the horizon): uniform, from the ambient share.
vec3 sky_radiance(vec3 dir) {
    return vec3(0.55, 0.7, 1.0) * frame.ambient_irradiance / PI;
}

// The sun's disc (half-angle ~0.5°) seen in direction dir, radiance: E⊥ over its solid angle
// (2π(1 − cos 0.5°) ≈ 2.4e-4 sr).
vec3 sun_disc_radiance(vec3 dir) {
    bool in_disc = frame.light_is_point == 0.0 && dot(dir, -frame.light_axis) > 0.99996;
    return vec3(in_disc ? frame.light_strength / 2.4e-4 : 0.0);
}
#endif
