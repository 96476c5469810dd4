// In-scattered radiance of one photon beam at one pixel (method step 6), shared by the
// rasterised godray paths (godrays.frag) and the compute path (godrays.comp). A beam
// radiance estimate with a box kernel as wide as the line (docs/units.md): a fragment stands
// for the beam's length under one pixel of the line, dℓ/ds (m of beam per pixel of line),
// and the pixel's radiance is the intensity of that length over the pixel's solid angle Ω
// at distance r:
//   L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) · (dℓ/ds) / (w · r² · Ω)
// θ is the scattering angle (beam direction vs. the direction towards the camera) and w the
// line width in pixels. Off the view axis a pixel subtends less (Ω = p²·cos³α, p the pixel's
// angular size on the axis) and the beam crosses it faster; both are exact here. (The
// paper's l_pix / sin θ for dℓ/ds, with r²·Ω ≈ l_pix², holds only on the axis: it lost up to
// cos α, 27 % at the sides of a 16:10 view with a 60° vertical field.)
#ifndef UNDERLIGHT_GODRAY_BEAM_GLSL
#define UNDERLIGHT_GODRAY_BEAM_GLSL
#include "underwater_shading.glsl"

// world: the fragment's point on the beam; from_surface: its distance from where the beam
// entered the water, m; direction: the beam's unit direction; flux: W after the surface;
// view_depth: distance along the camera axis, m. Returns L / E_surface (the buffer's unit).
vec3 beam_radiance(vec3 world, float from_surface, vec3 direction, float flux, float view_depth) {
    vec3 cam = frame.camera_position;
    vec3 to_cam = cam - world;
    float r = max(length(to_cam), 1e-6);
    float cos_t = dot(direction, to_cam / r);
    float line_w = clamp(frame.line_width, 1.0, frame.device_max_line_width);
    // Pixels of the line per metre of beam: the screen-space speed of a point moving along
    // the beam (the perspective divide's derivative), in the godray target's pixels.
    vec4 clip = frame.camera_view_proj * vec4(world, 1.0);
    vec4 clip_velocity = frame.camera_view_proj * vec4(direction, 0.0);
    vec2 ndc_velocity = (clip_velocity.xy * clip.w - clip.xy * clip_velocity.w) / (clip.w * clip.w);
    float pixels_per_metre = length(ndc_velocity * 0.5 * frame.godray_target_size);
    // The angular size of a pixel on the axis; Ω = p²·cos³α with cos α = view_depth / r.
    float p = 2.0 * frame.tan_half_fov_y / frame.godray_target_size.y;
    // A beam seen end-on would concentrate into one pixel: its speed is held at what a beam
    // at sin θ = 0.1 across the axis would have (the paper's clamp, at the same place).
    pixels_per_metre = max(pixels_per_metre, 0.1 / (p * view_depth));
    float cos_a = clamp(view_depth / r, 1e-3, 1.0);
    float r2_omega = r * r * p * p * cos_a * cos_a * cos_a;
    float d_view_water = view_underwater_length(world);
    vec3 attenuation = water_transmittance(from_surface + d_view_water);
    vec3 L = frame.scattering * henyey_greenstein(cos_t, frame.hg_g) * flux * attenuation
           / (pixels_per_metre * line_w * r2_omega);
    return L / frame.surface_irradiance;
}
#endif
