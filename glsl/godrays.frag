#version 450
// In-scattered radiance of one photon beam at this pixel (a beam radiance estimate with a
// box kernel as wide as the line, see docs/units.md):
//   L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) / (sin θ · w · l_pix)
// θ is the scattering angle (beam direction vs. the direction towards the camera), w the
// line width in pixels and l_pix the width one pixel spans at the fragment's distance.
#include "underwater.glsl"
#include "frame_textures.glsl"

layout(set = 0, binding = BINDING_SCENE_DEPTH) uniform sampler2D scene_depth;

layout(location = 0) in vec4 g_world_travelled;
layout(location = 1) flat in vec4 g_beam;
layout(location = 0) out vec4 out_radiance;

void main() {
    vec3 g_world = g_world_travelled.xyz;
    float g_from_surface = g_world_travelled.w;
    vec3 g_direction = g_beam.xyz;
    float g_flux = g_beam.w;
    float view_depth = 1.0 / gl_FragCoord.w;
    vec2 uv = gl_FragCoord.xy / frame.effect3.xy;
    float scene_z = linear_view_depth(texture(scene_depth, uv).r);
    if (view_depth > scene_z * 1.01 + 0.01) discard; // behind what the camera sees
    vec3 cam = frame.camera_pos.xyz;
    vec3 to_cam = cam - g_world;
    float d = length(to_cam);
    float cos_t = dot(g_direction, to_cam / max(d, 1e-6));
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    float line_w = clamp(frame.effect0.z, 1.0, frame.effect2.y);
    float l_pix = view_depth * 2.0 * frame.camera_params.z / frame.effect3.y;
    float d_view_water = underwater_length(cam, g_world, frame.water0.x);
    vec3 attenuation = exp(-frame.gamma.rgb * (g_from_surface + d_view_water));
    // sin θ is clamped: a beam seen end-on would otherwise concentrate into one pixel.
    vec3 L = frame.gamma.w * henyey_greenstein(cos_t, frame.effect0.w) * g_flux * attenuation
           / (max(sin_t, 0.1) * line_w * l_pix);
    // Stored relative to E_surface, like the caustic buffer (compose multiplies it back).
    out_radiance = vec4(L / frame.light_flux.x, 1.0);
}
