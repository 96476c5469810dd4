#version 450
// Scene colour (ambient and, above water, direct sun) and the factor compose multiplies the
// caustic irradiance by: albedo/π times the transmittance of the water between receiver and
// viewer (0 above water: caustics exist only under it). One shader for the three views
// (view.glsl): the camera's applies the water on the way to the camera; the refraction view
// leaves that to the surface, which knows the refracted path; the reflection view sees only
// what is above the water, from the mirrored camera.
// Compiled as scene.frag (colour and albedo×transmittance) and as reflection.frag
// (shaders::VARIANTS: COLOR_ONLY, the reflection pass has one target).
#include "underwater_shading.glsl"
#include "view.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_albedo;

// rgb: radiance; a: 1 where a mesh was drawn (the reflection view's sky test), 0 in the
// camera view (where the water surface writes its glow there).
layout(location = 0) out vec4 out_color;
#ifndef COLOR_ONLY
layout(location = 1) out vec4 out_albedo_transmittance;
#endif

void main() {
    vec3 n = normalize(v_normal);
    vec3 viewer = frame.camera_position;
    if (VIEW == VIEW_REFLECTION) viewer.y = 2.0 * frame.water_level - viewer.y;
    // Two-sided: light the side facing the viewer.
    if (dot(n, viewer - v_world) < 0.0) n = -n;
    vec3 brdf = v_albedo / PI;
    vec3 E = ambient_irradiance(v_world, n);
    bool under = v_world.y < frame.water_level;
    if (!under && frame.light_is_point == 0.0) {
        E += frame.light_strength * max(dot(n, -frame.light_axis), 0.0);
    }
    if (VIEW == VIEW_CAMERA) {
        out_color = vec4(through_water(brdf * E, v_world), 0.0);
    } else {
        out_color = vec4(brdf * E, 1.0);
    }
#ifndef COLOR_ONLY
    // The refraction view leaves the water on the way to the camera to the surface.
    float d = VIEW == VIEW_CAMERA ? view_underwater_length(v_world) : 0.0;
    out_albedo_transmittance = under ? vec4(brdf * water_transmittance(d), 0.0) : vec4(0.0);
#endif
}
