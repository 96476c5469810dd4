#version 450
// A godray beam's fragment: the beam's in-scattered radiance (godray_beam.glsl). Only
// fragments in front of the scene reach it: the pass's depth test, against the depth that
// photon_visibility.frag wrote, is the visibility test, made before the shader runs.
// Compiled twice (shaders::VARIANTS): for the paper's lines
// (godrays.geom, godrays_vertex.vert), and with BEAM_FOOTPRINT as godrays_footprint.frag for
// the ribbons as wide as each beam's cross-section (godrays_footprint.geom).
#include "godray_beam.glsl"

layout(location = 0) in vec4 g_world_travelled; // world position; w: distance from the surface, m
layout(location = 1) flat in vec4 g_beam;       // xyz: r_t; w: flux, W
#ifdef BEAM_FOOTPRINT
layout(location = 2) in float g_width;          // the ribbon's width here, m
#endif
layout(location = 0) out vec4 out_radiance;
layout(early_fragment_tests) in;

void main() {
    float view_depth = 1.0 / gl_FragCoord.w;
#ifdef BEAM_FOOTPRINT
    vec3 L = ribbon_radiance(g_world_travelled.xyz, g_world_travelled.w, g_beam.xyz, g_beam.w, g_width);
#else
    vec3 L = beam_radiance(g_world_travelled.xyz, g_world_travelled.w, g_beam.xyz, g_beam.w, view_depth);
#endif
    out_radiance = vec4(L, 1.0);
}
