#version 450
// Camera-space scene colour (ambient and, above water, direct sun) with underwater
// attenuation, and the factor compose multiplies the caustic irradiance by: albedo/π times
// the transmittance of the water between receiver and camera (0 above water: caustics
// exist only under it).
#include "underwater.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_albedo;

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_albedo_transmittance;

void main() {
    vec3 n = normalize(v_normal);
    // Two-sided: light the side facing the camera.
    if (dot(n, frame.camera_pos.xyz - v_world) < 0.0) n = -n;
    vec3 brdf = v_albedo / PI;
    vec3 E = ambient_irradiance(v_world, n);
    bool under = v_world.y < frame.water0.x;
    if (!under && frame.light_pos.w == 0.0) {
        E += frame.light_flux.y * max(dot(n, -frame.light_dir.xyz), 0.0);
    }
    out_color = vec4(through_water(brdf * E, v_world), 1.0);
    float d = underwater_length(frame.camera_pos.xyz, v_world, frame.water0.x);
    out_albedo_transmittance = under ? vec4(brdf * exp(-frame.gamma.rgb * d), 1.0) : vec4(0.0);
}
