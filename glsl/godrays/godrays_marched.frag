#version 450
// Godrays, ray-marched (effects.godray_method = "marched"): the cheap end of the godray trade
// (the Frühstück & Prast survey's §8, in the style of Tóth & Umenhoffer). Each pixel of the
// godray target marches its camera ray through the water and sums the single scattering of
// the light that reaches each step:
//   L = σs · p_HG(θ) · Σ E_t · e^(−γ·d_light) · e^(−γ·d_view) · Δs
// E_t is the sunlight through a flat surface (Fresnel transmittance, no focusing) per unit
// area across its refracted direction, d_light the step's path down from the surface along
// it, d_view the water between the step and the camera. A step is lit unless the light's
// position map holds a receiver nearer to the light (a post's shadow shaft). No photons: no
// shafts from the waves' focusing, but no photon noise and a cost set by the target's size.
// Directional lights only (the scene file refuses a point light). Same unit as the beams'
// buffer: L / E_surface.
#include "underwater_shading.glsl"
#include "scene_depth.glsl"
#include "pixel_noise.glsl"

// The light's receiver positions; layer 0 holds the maps along flat water (passes::shadow).
layout(set = 0, binding = BINDING_LIGHT_POSITION) uniform sampler2DArray light_positions;

// Steps along the under-water part of each pixel's ray (passes::godrays::MARCH_STEPS).
layout(constant_id = 0) const int STEPS = 32;

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_radiance;

// A step counts as shadowed only when the receiver the map holds lies this far (m) nearer to
// the light than the step: the map's texels are centimetres wide, and a step just above a lit
// floor must not read the floor as its occluder.
const float SHADOW_BIAS = 0.05;

// Whether the light reaches world point p under the water: no receiver between p and the
// light in the light's position map, which sees underwater points along the refracted light
// (light_map_point). Outside the map's window, and where the map holds no receiver, the water
// is open.
bool reaches(vec3 p) {
    vec3 m = light_map_point(p);
    vec4 c = frame.light_view_proj * vec4(m, 1.0);
    vec2 uv = c.xy / c.w * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) return true;
    vec4 receiver = texelFetch(light_positions, ivec3(uv * frame.light_map_size, 0), 0);
    if (receiver.w < 0.5) return true;
    return dot(light_map_point(receiver.xyz) - m, frame.light_axis) > -SHADOW_BIAS;
}

void main() {
    out_radiance = vec4(0.0);
    vec3 dir = pixel_ray(v_uv);
    vec3 camera = frame.camera_position;
    // The ray ends at what the scene shows (the far plane where it shows nothing).
    float end = scene_view_depth(v_uv) / max(dot(dir, camera_forward()), 1e-3);
    // Its under-water part, the crossing taken at the mean plane (as view_underwater_length).
    float to_level = abs(dir.y) > 1e-6 ? (frame.water_level - camera.y) / dir.y : -1.0;
    float start = 0.0;
    if (view_ray_starts_under(dir)) {
        if (to_level > 0.0) end = min(end, to_level);
    } else {
        if (!(to_level > 0.0)) return;
        start = to_level;
    }
    if (!(end > start)) return;

    vec3 r = frame.refracted_light_axis;
    float cos_t = max(-r.y, 1e-3);
    float cos_i = max(-frame.light_axis.y, 0.0);
    // Irradiance across the refracted direction: the flux through a unit of surface
    // (E⊥ · cos θi · T) spread over cos θt of cross-section.
    float e_t = frame.light_strength * cos_i * fresnel_transmittance(cos_i, frame.ior) / cos_t;
    // Scattering towards the camera: the light travels along r, the camera looks back along
    // the ray.
    float phase = henyey_greenstein(dot(r, -dir), frame.hg_g);

    WaterParams water = frame_water();
    float step_length = (end - start) / float(STEPS);
    float offset = pixel_noise(gl_FragCoord.xy);
    vec3 sum = vec3(0.0);
    for (int k = 0; k < STEPS; ++k) {
        float t = start + (float(k) + offset) * step_length;
        vec3 p = camera + t * dir;
        float d_light = max(frame.water_level - p.y, 0.0) / cos_t;
        // Light enters only through the water's extent.
        if (!water_covers(water, p.xz - d_light * r.xz) || !reaches(p)) continue;
        sum += water_transmittance(d_light + (t - start));
    }
    vec3 L = frame.scattering * phase * e_t * sum * step_length;
    out_radiance = vec4(L / frame.surface_irradiance, 1.0);
}
