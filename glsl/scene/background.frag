#version 450
// What a camera ray that meets no mesh and no water surface sees, drawn first in the scene
// pass: the sky if the ray starts in the air, the water's own glow if it starts under water
// (an infinitely long underwater view fades to it, thesis eq. 5 with d → ∞).
#include "underwater_shading.glsl"

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_albedo_transmittance;

void main() {
    vec3 dir = pixel_ray(v_uv);
    vec3 L = view_ray_starts_under(dir) ? water_fog_radiance() : sky_radiance(dir) + sun_disc_radiance(dir);
    out_color = vec4(L, 0.0);
    out_albedo_transmittance = vec4(0.0);
}
