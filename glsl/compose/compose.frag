#version 450
// Compose (method step 8): scene colour + caustic irradiance × albedo/π × transmittance to
// the camera + godray radiance + the glow of the water's specular highlights, then
// tonemapped. Compiled once per set of effects (shaders::VARIANTS: compose_caustics.frag and so
// on define HAS_CAUSTICS / HAS_GODRAYS), so a scene without an effect never binds its target.
#include "underwater_shading.glsl"
#if defined(HAS_CAUSTICS) || defined(HAS_GODRAYS)
#include "depth_aware.glsl"
#endif

// Whether the frame has the water seen from above (its highlights glow); a specialization
// constant, so frames without it pay nothing for the taps.
layout(constant_id = 0) const bool GLOW = false;
// How far off a pixel's surface an effect texel may lie and still lend it light
// (frame::CAUSTIC_SAME_SURFACE, GODRAY_SAME_SURFACE; glsl/shared/depth_aware.glsl).
layout(constant_id = 1) const float CAUSTIC_SAME_SURFACE = 0.05;
layout(constant_id = 2) const float GODRAY_SAME_SURFACE = 0.25;

layout(set = 0, binding = BINDING_SCENE_COLOR) uniform sampler2D scene_color;
#ifdef HAS_CAUSTICS
layout(set = 0, binding = BINDING_ALBEDO_TRANSMITTANCE) uniform sampler2D albedo_transmittance;
layout(set = 0, binding = BINDING_CAUSTICS) uniform sampler2D caustics;
#endif
#ifdef HAS_GODRAYS
layout(set = 0, binding = BINDING_GODRAYS) uniform sampler2D godrays;
#endif

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;

// Thesis §9.3: the highlights (scene colour alpha, written by the water surface) spread over
// the two diagonals of a 7×7 window, 13 texels, each weighted 1/13: a soft star around the
// sun's glints.
float highlight_glow(vec2 uv) {
    vec2 texel = 1.0 / vec2(textureSize(scene_color, 0));
    float sum = 0.0;
    for (int k = -3; k <= 3; ++k) {
        sum += textureLod(scene_color, uv + vec2(k, k) * texel, 0.0).a;
        if (k != 0) sum += textureLod(scene_color, uv + vec2(k, -k) * texel, 0.0).a;
    }
    return sum / 13.0;
}

void main() {
    vec4 scene = texture(scene_color, v_uv);
    vec3 L = scene.rgb;
#if defined(HAS_CAUSTICS) || defined(HAS_GODRAYS)
    // The effect targets are smaller than the output: each is upsampled from the texels on
    // this pixel's own surface (depth_aware.glsl), so no light crosses a silhouette.
    vec2 out_size = vec2(textureSize(scene_color, 0));
    SurfacePlane plane = surface_plane(v_uv, out_size);
#endif
#ifdef HAS_CAUSTICS
    vec3 caustic = upsample_on_surface(caustics, v_uv, out_size, plane, CAUSTIC_SAME_SURFACE);
    L += texture(albedo_transmittance, v_uv).rgb * caustic * frame.surface_irradiance;
#endif
#ifdef HAS_GODRAYS
    // The medium scatters only where the pixel's ray starts under water; where it starts in
    // the air, the surface already added the godrays it refracts (water.frag).
    if (view_ray_starts_under(pixel_ray(v_uv))) {
        // Stored relative to E_surface too.
        L += upsample_on_surface(godrays, v_uv, out_size, plane, GODRAY_SAME_SURFACE) * frame.surface_irradiance;
    }
#endif
    if (GLOW) {
        L += vec3(highlight_glow(v_uv));
    }
    // 1 − e^(−exposure·L): linear in the shadows, rolls highlights off. The target is sRGB,
    // so the hardware encodes.
    out_color = vec4(1.0 - exp(-frame.exposure * max(L, vec3(0.0))), 1.0);
}
