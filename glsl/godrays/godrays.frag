#version 450
// A godray line's fragment: the beam's in-scattered radiance (godray_beam.glsl) where the
// beam is in front of the scene.
#include "godray_beam.glsl"
#include "../photons/photon_visibility.glsl"

layout(location = 0) in vec4 g_world_travelled; // world position; w: distance from the surface, m
layout(location = 1) flat in vec4 g_beam;       // xyz: r_t; w: flux, W
layout(location = 0) out vec4 out_radiance;

void main() {
    float view_depth = 1.0 / gl_FragCoord.w;
    if (behind_scene(gl_FragCoord.xy, frame.godray_target_size, view_depth, GODRAY_DEPTH_TOLERANCE)) discard;
    vec3 L = beam_radiance(g_world_travelled.xyz, g_world_travelled.w, g_beam.xyz, g_beam.w, view_depth);
    out_radiance = vec4(L, 1.0);
}
