// The per-frame parameters every pass of the method reads (set 0, binding 0), each field by
// its name. Rust side: shader_abi::FrameUniforms, field for field; a vec3 is followed by a
// float and a vec2 starts at an even slot, so std430 inserts no padding, and
// shader_abi::tests::glsl_block_matches_the_rust_struct fails on any difference.
//
// A read-only storage buffer, not a uniform buffer. Mesa's lavapipe (22.3) "inlines" uniform
// values that decide a branch or a loop (the light kind, the water model, the iteration
// count): it compiles a new variant of the shader at every draw that binds the uniform
// buffer and never frees it. That leaked 24 MB per frame in the photon geometry shaders
// (docs/reliability.md has the measurements and a minimal reproduction). Storage-buffer
// loads are never inlined; on a GPU a read-only buffer read at a dynamically uniform address
// is an ordinary cached load.
//
// Every shader reads the block's values once, into `frame`, a private copy that its
// initializer fills at the top of main, before any branch or loop. llvmpipe (gallivm's
// lp_bld_nir_soa.c) loads from a storage buffer lane by lane: a loop over the SIMD group's
// eight lanes, with a bounds check per component. Only where it knows that the whole group
// runs the load, at a uniform address outside every branch and loop of a shader that is not a
// fragment shader, can it load once (in the versions that have that shortcut). The photon
// shaders read the light's matrices and the water's parameters inside their loops, at every
// step of every photon: copied once, the caustic pass costs about a sixth less on lavapipe,
// with every buffer the same to the bit (docs/performance.md, "The frame's values read once").
// The warp's tables stay in the buffer (`frame_buffer`): each photon reads a few knots, and a
// copy would load all 2 048 floats.
//
// Fragment shaders, where that shortcut never applies, read the same values as a uniform block
// (FRAME_VALUES, bound to the start of the same buffer): llvmpipe loads a uniform block's
// value at a uniform address once for the group in every stage. The leak above was measured in
// the photon geometry shaders, which keep the storage buffer; with the fragment shaders on the
// block, 300-frame soaks of the tank and the storage hold their memory (docs/reliability.md).
#ifndef UNDERLIGHT_FRAME_GLSL
#define UNDERLIGHT_FRAME_GLSL
#include "shader_math.glsl"

// The block's fields but the warp's tables (std430 pads a struct to 16 bytes; these end at
// 576, so the tables lie where they would without the struct).
struct FrameValues {
    mat4 camera_view_proj;
    mat4 light_view_proj;
    mat4 light_inv_view_proj;
    mat4 camera_inv_view_proj;     // pixel rays: where each starts (above or under the water)
    vec3 camera_position;
    float time;                    // s
    float z_near;
    float z_far;
    float tan_half_fov_y;
    float aspect;
    vec3 light_position;           // the light frame's origin (directional) or the point light
    float light_is_point;          // 0 directional, 1 point
    vec3 light_axis;               // directional: travel direction; point: the frustum's axis
    float scene_lowest_y;          // height of the scene's lowest point, m
    float surface_irradiance;      // E_surface, W/m²: the caustic buffer stores irradiance / E_surface (docs/units.md)
    float light_strength;          // E⊥ W/m² (directional) or I W/sr (point)
    vec2 light_half_extent;        // half sizes of the orthographic window, m (directional), or tan of the half angles (point)
    float water_level;
    float wave_amplitude;
    float wavelength;
    float wave_speed;
    float noise_amplitude;
    float noise_scale;             // metres per noise tile
    float ior;
    float water_model;             // WATER_CIRCULAR_COSINE or WATER_AXIS_COSINE_NOISE
    vec2 wave_center;
    vec2 water_extent_min;
    vec2 water_extent_max;
    float ambient_irradiance;      // W/m² just under the surface
    float exposure;
    vec3 attenuation;              // γ per channel, 1/m
    float scattering;              // σ_s, 1/m
    float point_size_min;
    float point_size_max;
    float line_width;
    float hg_g;                    // Henyey–Greenstein g
    float caustic_photons_per_axis;
    float godray_photons_per_axis;
    float iterations;              // image-space iteration steps
    float light_map_size;
    float device_max_point_size;
    float device_max_line_width;
    vec2 caustic_target_size;
    vec2 godray_target_size;
    vec2 output_size;
    vec3 water_phase;              // the water's phase at this frame's time (shader_math.glsl, water_height_grad)
    float surface_views_ready;     // 1 if this frame recorded the refraction and reflection passes
    vec2 camera_water_gradient;    // the surface's gradient at the camera's xz (the CPU twin's, for the pixels' side, underwater_shading.glsl)
    float camera_water_height;     // the surface's height above the level there
    float photon_density_warp;     // 0: the even grid; 1: the warp below (effects.caustic_photon_density = "view"); 2: the same, u and v exchanged
    vec2 photon_window_min;        // the photon grids' part of the light's map window (uv): the water's footprint
    vec2 photon_window_size;
    vec3 refracted_light_axis;     // a directional light's direction under flat water (0: a point light)
    float refracted_texel_stretch; // max(1, |r_y| / |d_y|): a map texel's beam under the water against above
    vec2 photon_jitter;            // this frame's photon-grid offset, in photon cells (effects.photon_jitter)
    float godray_density_warp;     // photon_density_warp for the godray beams, by godray_density_* (effects.godray_photon_density = "view")
    float caustic_grid_aspect;     // k: the caustic triangles' coarse grid is N/k columns × N·k rows (frame::photon_density)
    vec3 steep_light_axis;         // the second light maps' bend under the water, steeper (0: no second maps)
    float steep_texel_stretch;     // refracted_texel_stretch for the second maps
};
layout(set = 0, binding = BINDING_UNIFORMS, std430) readonly buffer FrameUniforms {
    FrameValues values;
    // The caustic photon grid's warp (frame::photon_density, photon_cast.glsl's
    // photon_density_warp): inverse cumulative densities, PHOTON_DENSITY_KNOTS knots each. Rows:
    // the window's v at grid v = k / (knots − 1). Columns: one row of knots per band of the
    // window's v, the window's u at grid u = k / (knots − 1). Warp mode 2: u and v exchanged.
    float photon_density_rows[32];
    float photon_density_columns[992];
    // The godray grid's warp, alike.
    float godray_density_rows[32];
    float godray_density_columns[992];
} frame_buffer;
#ifdef FRAGMENT_STAGE // defined by the shader compiler for .frag stages (shaders::compile_all)
// std140 lays out these members as std430 does, and pads the struct to 16 bytes alike
// (shader_abi::tests::glsl_block_matches_the_rust_struct checks its end).
layout(set = 0, binding = BINDING_FRAME_VALUES, std140) uniform FrameValuesBlock {
    FrameValues values;
} frame_values;
FrameValues frame = frame_values.values;
#else
FrameValues frame = frame_buffer.values; // the copy every function reads (see the top)
#endif

const int PHOTON_DENSITY_KNOTS = 32;

// The underwater direction the first maps (false) or the second, steeper ones (true) bend
// along (frame::uniforms::steep_light_axis says why there are two).
vec3 light_map_bend(bool steep) {
    return steep ? frame.steep_light_axis : frame.refracted_light_axis;
}

// Where the first light maps (`steep`: the second) put world point p: p itself above the
// water; below it (directional light), p slid back along the maps' bend (for the first, the
// refracted light direction) to the water level and on along the light's own, so that an
// underwater receiver lands in the texel of the photons that reach it (through flat water),
// not in that of the straight light ray. The Rust twin is shader_math::light_map_point.
vec3 light_map_point(vec3 p, bool steep) {
    vec3 r = light_map_bend(steep);
    if (!(r.y < -1e-3)) return p;
    float along = max(frame.water_level - p.y, 0.0) / -r.y;
    return p + along * (frame.light_axis - r);
}

vec3 light_map_point(vec3 p) {
    return light_map_point(p, false);
}

// The direction along which the light's maps see point p (unit): from a point light; along a
// directional light above the water and the maps' bend below it.
vec3 light_map_direction(vec3 p, bool steep) {
    if (frame.light_is_point > 0.0) return normalize(p - frame.light_position);
    vec3 r = light_map_bend(steep);
    return r.y < -1e-3 && p.y < frame.water_level ? r : frame.light_axis;
}

WaterParams frame_water() {
    WaterParams w;
    w.model = int(frame.water_model);
    w.level = frame.water_level;
    w.amplitude = frame.wave_amplitude;
    w.wavelength = frame.wavelength;
    w.speed = frame.wave_speed;
    w.noise_amplitude = frame.noise_amplitude;
    w.noise_scale = frame.noise_scale;
    w.ior = frame.ior;
    w.center = frame.wave_center;
    w.extent_min = frame.water_extent_min;
    w.extent_max = frame.water_extent_max;
    return w;
}

float frame_time() { return frame.time; }
vec3 frame_water_phase() { return frame.water_phase; }
// Whether the refraction and reflection views were rendered this frame (the camera can see
// the surface from above).
bool frame_surface_views_ready() { return frame.surface_views_ready > 0.5; }

// Distance from the camera along its view axis for a depth-buffer value (Vulkan [0, 1]
// depth, standard perspective).
float linear_view_depth(float depth) {
    float n = frame.z_near, f = frame.z_far;
    return n * f / (f - depth * (f - n));
}

// The depth-buffer value of a point `view_depth` m along the camera axis: linear_view_depth's
// inverse, clamped to the depth range (a point beyond the far plane tests as at it).
float depth_of_view_depth(float view_depth) {
    float n = frame.z_near, f = frame.z_far;
    return clamp(f * (view_depth - n) / (max(view_depth, 1e-9) * (f - n)), 0.0, 1.0);
}

// World area one pixel of a target `height_px` tall covers at distance d along its ray, on
// a surface whose normal makes cosine `cos_view` with the ray; `cos_axis` is the cosine
// between the ray and the camera axis (a pinhole's pixel solid angle shrinks by cos³).
// Grazing views are clamped (cos ≥ 0.2) so a splat cannot blow up to infinity.
// Transmittance of `metres` of water per RGB channel, e^(−γ·d): the one place the medium's
// attenuation is applied (photons to their hit, beams, the view ray, the ambient light).
vec3 water_transmittance(float metres) {
    return exp(-frame.attenuation * metres);
}

float pixel_world_area(float d, float cos_view, float cos_axis, float height_px) {
    float side = 2.0 * frame.tan_half_fov_y / height_px;
    return side * side * cos_axis * cos_axis * cos_axis * d * d / max(cos_view, 0.2);
}

vec3 camera_forward() {
    // Row 3 of view_proj is the clip w = distance along the axis; its xyz is the axis.
    vec4 r = vec4(frame.camera_view_proj[0].w, frame.camera_view_proj[1].w, frame.camera_view_proj[2].w, 0.0);
    return normalize(r.xyz);
}
#endif
