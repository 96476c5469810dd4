#version 450
// The water surface. From below: the sky inside Snell's window (with the sun's glint and
// Fresnel transmittance), total internal reflection of the water's own radiance outside it.
// From above (until the reflection/refraction passes exist): Fresnel-weighted sky over deep
// water.
#include "underwater.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_albedo_transmittance;

// Radiance of the sky seen through the surface, and of the sun's disc (half-angle ~0.5°).
vec3 sky_radiance(vec3 dir) {
    vec3 sky = vec3(0.55, 0.7, 1.0) * frame.water3.z / PI;
    float sun = frame.light_pos.w == 0.0 && dot(dir, -frame.light_dir.xyz) > 0.99996 ? 1.0 : 0.0;
    // Sun disc radiance: E⊥ over the disc's solid angle (2π(1 − cos 0.5°) ≈ 2.4e-4 sr).
    return sky + sun * frame.light_flux.y / 2.4e-4;
}

void main() {
    vec3 n = normalize(v_normal);
    vec3 cam = frame.camera_pos.xyz;
    vec3 v = normalize(v_world - cam);
    float ior = frame.water1.z;
    vec3 L;
    if (cam.y < frame.water0.x) {
        // Looking up from inside the water: refract into air (index ior → 1).
        vec3 t = refract(v, -n, ior);
        if (dot(t, t) == 0.0) {
            L = water_fog_radiance(); // total internal reflection: the water's own glow
        } else {
            float tr = fresnel_transmittance(max(dot(t, n), 0.0), ior); // symmetric in direction
            L = tr * sky_radiance(normalize(t)) + (1.0 - tr) * water_fog_radiance();
        }
        L = through_water(L, v_world);
    } else {
        float tr = fresnel_transmittance(max(dot(-v, n), 0.0), ior);
        L = (1.0 - tr) * sky_radiance(reflect(v, n)) + tr * water_fog_radiance();
    }
    out_color = vec4(L, 1.0);
    out_albedo_transmittance = vec4(0.0);
}
