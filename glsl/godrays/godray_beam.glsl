// In-scattered radiance of one photon beam at one pixel (method step 6), shared by the
// rasterised godray paths (godrays.frag) and the compute path (godrays.comp). A beam
// radiance estimate with a box kernel as wide as the line (docs/units.md):
//   L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) / (sin θ · w · l_pix)
// θ is the scattering angle (beam direction vs. the direction towards the camera), w the
// line width in pixels and l_pix the width one pixel spans at the fragment's distance.
#ifndef UNDERLIGHT_GODRAY_BEAM_GLSL
#define UNDERLIGHT_GODRAY_BEAM_GLSL
#include "underwater_shading.glsl"

// world: the fragment's point on the beam; from_surface: its distance from where the beam
// entered the water, m; direction: the beam's unit direction; flux: W after the surface;
// view_depth: distance along the camera axis, m. Returns L / E_surface (the buffer's unit).
vec3 beam_radiance(vec3 world, float from_surface, vec3 direction, float flux, float view_depth) {
    vec3 cam = frame.camera_position;
    vec3 to_cam = cam - world;
    float d = length(to_cam);
    float cos_t = dot(direction, to_cam / max(d, 1e-6));
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    float line_w = clamp(frame.line_width, 1.0, frame.device_max_line_width);
    float l_pix = view_depth * 2.0 * frame.tan_half_fov_y / frame.godray_target_size.y;
    float d_view_water = view_underwater_length(world);
    vec3 attenuation = water_transmittance(from_surface + d_view_water);
    // sin θ is clamped: a beam seen end-on would otherwise concentrate into one pixel.
    vec3 L = frame.scattering * henyey_greenstein(cos_t, frame.hg_g) * flux * attenuation
           / (max(sin_t, 0.1) * line_w * l_pix);
    return L / frame.surface_irradiance;
}
#endif
