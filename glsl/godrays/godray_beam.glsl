// In-scattered radiance of one photon beam at one pixel (method step 6), shared by the
// rasterised godray paths (godrays.frag) and the compute path (godrays.comp). A beam
// radiance estimate with a box kernel as wide as the drawn beam (docs/units.md): a fragment
// stands for the beam's length and width under one pixel, and the pixel's radiance is the
// intensity of that piece of beam over the pixel's solid angle Ω at distance r.
//   - A line (the paper's beams) w pixels wide: the piece is dℓ/ds metres of beam per pixel
//     of line, and
//       L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) · (dℓ/ds) / (w · r² · Ω)
//   - A ribbon (effects.godray_method = "footprint"): a strip W metres wide across the beam,
//     facing the camera, as wide as the beam's cross-section seen from the camera
//     (godrays_footprint.geom). The beam's flux is spread evenly over its width, and a pixel
//     covers 1 / |v_ℓ × v_u| m² of the strip (v_ℓ, v_u: the screen velocities, px per metre,
//     of a point moving along the beam and across the strip), so
//       L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) / (W · |v_ℓ × v_u| · r² · Ω)
//     A pinhole camera sees f²·|N·(P − C)| / z³ pixels per m² of a surface with normal N at P
//     (f = 1/p, z the view depth), and for the ribbon |N·(P − C)| = r·sin θ, while
//     r²·Ω = p²·z³ / r. The perspective cancels:
//       L = σs · p_HG(θ) · Φ · e^(−γ·d_surface) · e^(−γ·d_view) / (W · sin θ)
//     the radiance of a slab of beams W wide seen at θ, and what ribbon_radiance computes.
// θ is the scattering angle (beam direction vs. the direction towards the camera). Off the
// view axis a pixel subtends less (Ω = p²·cos³α, p the pixel's angular size on the axis) and
// the beam crosses it faster; both are exact here. (The paper's l_pix / sin θ for dℓ/ds, with
// r²·Ω ≈ l_pix², holds only on the axis: it lost up to cos α, 27 % at the sides of a 16:10
// view with a 60° vertical field.)
#ifndef UNDERLIGHT_GODRAY_BEAM_GLSL
#define UNDERLIGHT_GODRAY_BEAM_GLSL
#include "underwater_shading.glsl"

// The screen velocity, in godray-target pixels per metre, of a point at `world` moving along
// `v`: the perspective divide's derivative. `world` must lie in front of the camera.
vec2 godray_screen_velocity(vec3 world, vec3 v) {
    vec4 clip = frame.camera_view_proj * vec4(world, 1.0);
    vec4 clip_velocity = frame.camera_view_proj * vec4(v, 0.0);
    vec2 ndc_velocity = (clip_velocity.xy * clip.w - clip.xy * clip_velocity.w) / (clip.w * clip.w);
    return ndc_velocity * 0.5 * frame.godray_target_size;
}

// The angular size of a godray-target pixel on the view axis.
float godray_pixel_angle() {
    return 2.0 * frame.tan_half_fov_y / frame.godray_target_size.y;
}

// A beam seen end-on would concentrate into one pixel: its screen speed is held at what a
// beam at sin θ = 0.1 across the axis would have (the paper's clamp, at the same place).
float beam_speed_floor(float view_depth) {
    return 0.1 / (godray_pixel_angle() * view_depth);
}

// The unit vector across a ribbon at `world`: perpendicular to the beam and to the view ray,
// so the strip faces the camera. Any perpendicular of the beam where it points at the camera.
vec3 ribbon_across(vec3 world, vec3 direction) {
    vec3 across = cross(direction, frame.camera_position - world);
    float len = length(across);
    if (len > 1e-6 * length(frame.camera_position - world)) return across / len;
    vec3 other = abs(direction.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 0.0, 1.0);
    return normalize(cross(direction, other));
}

// σs · p_HG(θ) · Φ · e^(−γ·(d_surface + d_view)) / E_surface: the beam's in-scattered
// intensity per metre of beam (before the estimator's kernel spreads it over pixels), and
// cos θ. world: the fragment's point on the beam; from_surface: its distance from where the
// beam entered the water, m; direction: the beam's unit direction; flux: W after the surface.
vec3 beam_in_scattering(vec3 world, float from_surface, vec3 direction, float flux, out float cos_t) {
    vec3 to_cam = frame.camera_position - world;
    cos_t = dot(direction, to_cam / max(length(to_cam), 1e-6));
    vec3 attenuation = water_transmittance(from_surface + view_underwater_length(world));
    return frame.scattering * henyey_greenstein(cos_t, frame.hg_g) * flux * attenuation / frame.surface_irradiance;
}

// A line's radiance, L / E_surface (the buffer's unit); view_depth: distance along the camera
// axis, m.
vec3 beam_radiance(vec3 world, float from_surface, vec3 direction, float flux, float view_depth) {
    float cos_t;
    vec3 scattered = beam_in_scattering(world, from_surface, direction, flux, cos_t);
    float line_w = clamp(frame.line_width, 1.0, frame.device_max_line_width);
    float pixels_per_metre = max(length(godray_screen_velocity(world, direction)), beam_speed_floor(view_depth));
    // Ω = p²·cos³α with cos α = view_depth / r.
    float r = max(length(frame.camera_position - world), 1e-6);
    float p = godray_pixel_angle();
    float cos_a = clamp(view_depth / r, 1e-3, 1.0);
    float r2_omega = r * r * p * p * cos_a * cos_a * cos_a;
    return scattered / (r2_omega * pixels_per_metre * line_w);
}

// A ribbon's radiance, `width` metres wide at `world`, L / E_surface. A beam seen end-on is
// held at sin θ = 0.1, the lines' clamp (beam_speed_floor).
vec3 ribbon_radiance(vec3 world, float from_surface, vec3 direction, float flux, float width) {
    float cos_t;
    vec3 scattered = beam_in_scattering(world, from_surface, direction, flux, cos_t);
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    return scattered / (max(width, 1e-9) * max(sin_t, 0.1));
}
#endif
