// The per-frame parameters every pass of the method reads (set 0, binding 0).
// Rust side: frame::uniforms::FrameUniforms (vec4s and mat4s only, so std140 and std430 lay
// it out alike, with no hidden padding).
//
// A read-only storage buffer, not a uniform buffer. Mesa's lavapipe (22.3) "inlines" uniform
// values that decide a branch or a loop (the light kind, the water model, the iteration
// count): it compiles a new variant of the shader at every draw that binds the uniform
// buffer and never frees it. That leaked 24 MB per frame in the photon geometry shaders
// (docs/reliability.md has the measurements and a minimal reproduction). Storage-buffer
// loads are never inlined; on a GPU a read-only buffer read at a dynamically uniform address
// is an ordinary cached load.
#ifndef UNDERLIGHT_FRAME_GLSL
#define UNDERLIGHT_FRAME_GLSL
#include "common.glsl"

layout(set = 0, binding = 0, std430) readonly buffer FrameUniforms {
    mat4 camera_view_proj;
    mat4 light_view_proj;
    mat4 light_inv_view_proj;
    mat4 camera_inv_view_proj;
    vec4 camera_pos;       // xyz; w = time, s
    vec4 camera_params;    // z_near, z_far, tan(fov_y / 2), aspect
    vec4 light_pos;        // xyz; w = 0 directional, 1 point
    vec4 light_dir;        // xyz: directional travel direction / point light axis; w: height of the scene's lowest point, m
    vec4 light_flux;       // x: E_surface, W/m² (the caustic buffer stores irradiance / E_surface, see docs/units.md); y: E_perp W/m² (directional) or I W/sr (point); zw: half sizes of the orthographic window, m (directional) or tan of the half angles (point)
    vec4 water0;           // level, amplitude, wavelength, speed
    vec4 water1;           // noise_amplitude, noise_scale, ior, model
    vec4 water2;           // center.xy, extent_min.xy
    vec4 water3;           // extent_max.xy, ambient irradiance W/m² just under the surface, exposure
    vec4 gamma;            // attenuation γ per channel (1/m); w: scattering σ_s (1/m)
    vec4 effect0;          // point_size_min, point_size_max, line_width, hg_g
    vec4 effect1;          // caustic photons per axis, godray photons per axis, iterations, light map size
    vec4 effect2;          // device point size max, device line width max, caustic target w, h
    vec4 effect3;          // godray target w, h, output w, h
    vec4 water4;           // xyz: the water's phase at this frame's time (common.glsl, water_height_grad); w: 1 if this frame recorded the refraction and reflection passes
    vec4 camera_water;     // x: the surface's height above the level at the camera's xz; yz: its gradient (the CPU twin's, for the pixels' side, underwater.glsl); w unused
} frame;

WaterParams frame_water() {
    WaterParams w;
    w.model = int(frame.water1.w);
    w.level = frame.water0.x;
    w.amplitude = frame.water0.y;
    w.wavelength = frame.water0.z;
    w.speed = frame.water0.w;
    w.noise_amplitude = frame.water1.x;
    w.noise_scale = frame.water1.y;
    w.ior = frame.water1.z;
    w.center = frame.water2.xy;
    w.extent_min = frame.water2.zw;
    w.extent_max = frame.water3.xy;
    return w;
}

float frame_time() { return frame.camera_pos.w; }
vec3 frame_water_phase() { return frame.water4.xyz; }
// Whether the refraction and reflection views were rendered this frame (the camera can see
// the surface from above).
bool frame_surface_views_ready() { return frame.water4.w > 0.5; }

// Distance from the camera along its view axis for a depth-buffer value (Vulkan [0, 1]
// depth, standard perspective).
float linear_view_depth(float depth) {
    float n = frame.camera_params.x, f = frame.camera_params.y;
    return n * f / (f - depth * (f - n));
}

// World area one pixel of a target `height_px` tall covers at distance d along its ray, on
// a surface whose normal makes cosine `cos_view` with the ray; `cos_axis` is the cosine
// between the ray and the camera axis (a pinhole's pixel solid angle shrinks by cos³).
// Grazing views are clamped (cos ≥ 0.2) so a splat cannot blow up to infinity.
float pixel_world_area(float d, float cos_view, float cos_axis, float height_px) {
    float side = 2.0 * frame.camera_params.z / height_px;
    return side * side * cos_axis * cos_axis * cos_axis * d * d / max(cos_view, 0.2);
}

vec3 camera_forward() {
    // Row 3 of view_proj is the clip w = distance along the axis; its xyz is the axis.
    vec4 r = vec4(frame.camera_view_proj[0].w, frame.camera_view_proj[1].w, frame.camera_view_proj[2].w, 0.0);
    return normalize(r.xyz);
}
#endif
