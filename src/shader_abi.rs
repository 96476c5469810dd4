//! The shader ABI: what the Rust side and `glsl/` agree on, in one leaf module that imports
//! nothing of the method's.
//!
//! - `FrameUniforms`: the frame's parameter block, field for field with `glsl/shared/frame.glsl`
//!   (std430; a test below fails on any difference in a name or an offset). How each field
//!   is computed for a frame is `frame::uniforms`.
//! - `limits`: the photon geometry shaders' subdivision bounds, passed to `glsl/` as macros.
//! - `bindings`: the descriptor binding numbers, defined only here; the shader compiler passes
//!   each to `glsl/` as a `BINDING_<NAME>` macro (`shaders::compile_all`).

/// Defines `FrameUniforms` and `FRAME_UNIFORM_FIELDS` (each field's name and byte offset)
/// from one list, so the test against `glsl/shared/frame.glsl` sees every field the struct has.
macro_rules! frame_uniforms {
    ($($(#[doc = $doc:literal])* $name:ident: $ty:ty,)*) => {
        /// The image of `glsl/shared/frame.glsl`'s `FrameUniforms` block (std430), field for field.
        #[repr(C)]
        #[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct FrameUniforms {
            $($(#[doc = $doc])* pub $name: $ty,)*
        }

        /// Every field of `FrameUniforms` with its byte offset, in declaration order.
        pub const FRAME_UNIFORM_FIELDS: &[(&str, usize)] =
            &[$((stringify!($name), std::mem::offset_of!(FrameUniforms, $name)),)*];
    };
}

frame_uniforms! {
    camera_view_proj: [[f32; 4]; 4],
    light_view_proj: [[f32; 4]; 4],
    light_inv_view_proj: [[f32; 4]; 4],
    /// Pixel rays: compose and the background find where each starts (above or under water).
    camera_inv_view_proj: [[f32; 4]; 4],
    camera_position: [f32; 3],
    /// Seconds.
    time: f32,
    z_near: f32,
    z_far: f32,
    tan_half_fov_y: f32,
    aspect: f32,
    /// The light frame's origin (directional) or the point light.
    light_position: [f32; 3],
    /// 0 directional, 1 point.
    light_is_point: f32,
    /// Directional: the travel direction; point: the axis of its frustum.
    light_axis: [f32; 3],
    /// Height of the scene's lowest point, m (the image-space iteration's first guess).
    scene_lowest_y: f32,
    /// E_surface, W/m²: the scale of the photon buffers and of the exposure.
    surface_irradiance: f32,
    /// E⊥ W/m² (directional) or I W/sr (point).
    light_strength: f32,
    /// Half sizes of the orthographic window, m (directional), or tan of the half angles (point).
    light_half_extent: [f32; 2],
    water_level: f32,
    wave_amplitude: f32,
    wavelength: f32,
    wave_speed: f32,
    noise_amplitude: f32,
    noise_scale: f32,
    ior: f32,
    /// `WaterModel::glsl_id`.
    water_model: f32,
    wave_center: [f32; 2],
    water_extent_min: [f32; 2],
    water_extent_max: [f32; 2],
    /// W/m² just under the surface.
    ambient_irradiance: f32,
    exposure: f32,
    /// γ per channel, 1/m.
    attenuation: [f32; 3],
    /// σ_s, 1/m.
    scattering: f32,
    point_size_min: f32,
    point_size_max: f32,
    line_width: f32,
    hg_g: f32,
    caustic_photons_per_axis: f32,
    godray_photons_per_axis: f32,
    iterations: f32,
    light_map_size: f32,
    device_max_point_size: f32,
    device_max_line_width: f32,
    caustic_target_size: [f32; 2],
    godray_target_size: [f32; 2],
    output_size: [f32; 2],
    /// The water's phase at this time (`shader_math::water_phase`).
    water_phase: [f32; 3],
    /// 1 when the frame records the refraction and reflection passes (set by `Frame::record`).
    surface_views_ready: f32,
    /// The surface's gradient and height above the level at the camera's xz: the tangent
    /// plane the shaders decide each pixel's side of the water against. Set by
    /// `Frame::record` from the CPU twin.
    camera_water_gradient: [f32; 2],
    camera_water_height: f32,
    /// How the caustic photon grid is warped (`frame::photon_density::PhotonDensity::warp_mode`):
    /// 0, not (the paper's even grid); 1, by `photon_density_rows`/`columns` (`effects.
    /// caustic_photon_density = "view"`); 2, the same with the window's u and v exchanged
    /// (the rows' knots give the window's u, the columns' the window's v per band of u).
    photon_density_warp: f32,
    /// The part of the light's map window the photon grids cover, in its uv: the water's
    /// footprint (`frame::uniforms::photon_window`). Photons outside it could only miss the
    /// water.
    photon_window_min: [f32; 2],
    photon_window_size: [f32; 2],
    /// A directional light's travel direction under flat water (zero for a point light).
    /// The light's maps see underwater receivers along it, as the refracted photons meet
    /// them (`shader_math::light_map_point`).
    refracted_light_axis: [f32; 3],
    /// How much wider a map texel's beam is under the water than above it: max(1, |r_y| / |d_y|).
    refracted_texel_stretch: f32,
    /// This frame's offset of the photon grids, in photon cells (`effects.photon_jitter`;
    /// zero without it): `cast_photon` shifts every photon by it.
    photon_jitter: [f32; 2],
    /// How the godray beams' grid is warped, as `photon_density_warp`, by `godray_density_rows`/
    /// `columns` (`effects.godray_photon_density = "view"`).
    godray_density_warp: f32,
    /// k: the caustic triangles' coarse grid is N/k columns by N·k rows, the same photons as
    /// N × N, so that their mesh cells are square on screen on average
    /// (`frame::photon_density`, from the view's survey; 1, a square grid, without it and for
    /// the paper's points). Read through `caustic_grid_cell` (caustic_splat.glsl) by
    /// `caustics_triangles.geom` and by the points' recording variant.
    caustic_grid_aspect: f32,
    /// The direction the second pair of light maps bends along under the water, steeper than
    /// `refracted_light_axis` (zero where the maps do not bend): photons whose iteration
    /// does not converge in the first maps search these (`frame::uniforms::steep_light_axis`).
    steep_light_axis: [f32; 3],
    /// `refracted_texel_stretch` for the second maps.
    steep_texel_stretch: f32,
    /// The caustic photon grid's warp (`frame::photon_density`): the inverse cumulative
    /// density of the window's v, `PHOTON_DENSITY_KNOTS` knots at grid v = k / SEGMENTS (of
    /// its u, at grid u, where `photon_density_warp` is 2).
    photon_density_rows: [f32; PHOTON_DENSITY_KNOTS],
    /// And of the window's u, one row of knots per band of the window's v
    /// (`PHOTON_DENSITY_SEGMENTS` bands), row after row (u and v exchanged in mode 2).
    photon_density_columns: [f32; PHOTON_DENSITY_KNOTS * PHOTON_DENSITY_SEGMENTS],
    /// The godray grid's warp, alike (`frame::photon_density`, for the beams).
    godray_density_rows: [f32; PHOTON_DENSITY_KNOTS],
    godray_density_columns: [f32; PHOTON_DENSITY_KNOTS * PHOTON_DENSITY_SEGMENTS],
}
const _: () = assert!(
    std::mem::size_of::<FrameUniforms>()
        == 4 * 64 + 16 * 20 + 2 * 4 * PHOTON_DENSITY_KNOTS * (PHOTON_DENSITY_SEGMENTS + 1)
);

/// The bytes of `FrameUniforms` before its warp tables: frame.glsl's `FrameValues`, which the
/// fragment shaders read as a uniform block bound to the start of the same buffer
/// (`bindings::FRAME_VALUES`). The layout test below checks that the GLSL struct ends there.
pub const FRAME_VALUES_BYTES: u64 = std::mem::offset_of!(FrameUniforms, photon_density_rows) as u64;

/// Segments of the caustic photon grid's warp per axis (`frame::photon_density`); its knots
/// are one more. GLSL: `PHOTON_DENSITY_KNOTS` and the arrays' sizes in frame.glsl (the layout
/// test below checks them).
pub const PHOTON_DENSITY_SEGMENTS: usize = 31;
pub const PHOTON_DENSITY_KNOTS: usize = PHOTON_DENSITY_SEGMENTS + 1;

/// Geometry-shader output bounds, defined here only: the shader compiler passes each to
/// `glsl/` as a macro of the same name (`shaders::compile_all`). A shader's `max_vertices` is
/// a literal that must cover its bound (each geometry shader says how it derives its own).
pub mod limits {
    /// Largest per-axis photon subdivision one geometry-shader invocation emits (GLSL
    /// `MAX_SUBDIVISION`; the geometry shader's `max_vertices` is its square).
    pub const MAX_SUBDIVISION: u32 = 8;

    /// Largest subdivision of the triangle estimator (GLSL `TRIANGLE_MAX_SUBDIVISION`): at 3 an
    /// invocation emits at most 108 vertices of 8 components, 864 of the 1024 every
    /// geometry-shader device offers (the bound is derived in caustics_triangles.geom).
    pub const TRIANGLE_MAX_SUBDIVISION: u32 = 3;

    /// Largest subdivision of the footprint points (GLSL `FOOTPRINT_MAX_SUBDIVISION`): each
    /// photon's hat is a quad of 4 vertices of at most 11 components (position, irradiance,
    /// the hat's lattice coordinates, and the receiver's plane in
    /// caustics_footprint_receiver.geom), and 4 × 4² × 11 = 704 stays within the 1024 output
    /// components every geometry-shader device offers (`max_vertices = 64` in caustics.geom);
    /// 5 × 5 would take 1100.
    pub const FOOTPRINT_MAX_SUBDIVISION: u32 = 4;

    /// Largest godray subdivision: each photon emits a 2-vertex line of 12 components, and
    /// 2 × 6² × 12 = 864 stays within the 1024 output components every geometry-shader device
    /// offers (`max_vertices = 72` in godrays.geom).
    pub const GODRAY_MAX_SUBDIVISION: u32 = 6;

    /// Largest godray subdivision of the footprint-sized beams: each photon emits a ribbon of
    /// 4 vertices of 16 components, and 4 × 4² × 16 = 1024, the output components every
    /// geometry-shader device offers (`max_vertices = 64` in godrays_footprint.geom).
    pub const GODRAY_FOOTPRINT_MAX_SUBDIVISION: u32 = 4;
    /// Every bound by its macro name, for the shader compiler.
    pub const ALL: &[(&str, u32)] = &[
        ("MAX_SUBDIVISION", MAX_SUBDIVISION),
        ("TRIANGLE_MAX_SUBDIVISION", TRIANGLE_MAX_SUBDIVISION),
        ("FOOTPRINT_MAX_SUBDIVISION", FOOTPRINT_MAX_SUBDIVISION),
        ("GODRAY_MAX_SUBDIVISION", GODRAY_MAX_SUBDIVISION),
        ("GODRAY_FOOTPRINT_MAX_SUBDIVISION", GODRAY_FOOTPRINT_MAX_SUBDIVISION),
    ];
}

/// Binding numbers of the frame's descriptor set, defined here only: the shader compiler gets
/// each as the macro `BINDING_<NAME>` (`shaders::compile_all`), which `glsl/` uses.
pub mod bindings {
    pub const UNIFORMS: u32 = 0;
    pub const NOISE: u32 = 1;
    /// The light's receiver maps, each an array with a layer per pair of maps (the first; the
    /// second, steeper one where the maps bend): passes::shadow::FIRST_MAPS, STEEP_MAPS.
    pub const LIGHT_POSITION: u32 = 2;
    pub const LIGHT_NORMAL: u32 = 3;
    pub const SCENE_DEPTH: u32 = 4;
    pub const SCENE_COLOR: u32 = 5;
    pub const ALBEDO_TRANSMITTANCE: u32 = 6;
    pub const CAUSTICS: u32 = 7;
    pub const GODRAYS: u32 = 8;
    /// The unfiltered buffer a filter pass instance reads (each instance has its own set).
    pub const FILTER_INPUT: u32 = 9;
    /// The caustics pass's photon records (debug variant only; the pass binds its own buffer).
    pub const PHOTON_DEBUG: u32 = 10;
    /// A compute photon path's accumulation buffer (its pass binds its own).
    pub const PHOTON_ACCUMULATION: u32 = 11;
    /// The raw splat floor's recorded splats (its pass binds its own).
    pub const SPLAT_RECORDS: u32 = 12;
    /// The refraction and reflection passes' targets, which the water surface reads.
    pub const REFRACTION_COLOR: u32 = 13;
    pub const REFRACTION_ALBEDO: u32 = 14;
    pub const REFRACTION_DEPTH: u32 = 15;
    pub const REFLECTION_COLOR: u32 = 16;
    /// The frame's values (`UNIFORMS` up to its warp tables, the same buffer) as a uniform
    /// block, which the fragment shaders read (glsl/shared/frame.glsl says why).
    pub const FRAME_VALUES: u32 = 17;
    /// The caustic triangles' cells handed to their refinement draw, headed by that draw's
    /// indirect command (caustics_triangles_refined.geom; the caustics pass binds its own).
    pub const REFINED_CELLS: u32 = 18;
    /// Every binding by its macro name, for the shader compiler.
    pub const ALL: &[(&str, u32)] = &[
        ("UNIFORMS", UNIFORMS),
        ("NOISE", NOISE),
        ("LIGHT_POSITION", LIGHT_POSITION),
        ("LIGHT_NORMAL", LIGHT_NORMAL),
        ("SCENE_DEPTH", SCENE_DEPTH),
        ("SCENE_COLOR", SCENE_COLOR),
        ("ALBEDO_TRANSMITTANCE", ALBEDO_TRANSMITTANCE),
        ("CAUSTICS", CAUSTICS),
        ("GODRAYS", GODRAYS),
        ("FILTER_INPUT", FILTER_INPUT),
        ("PHOTON_DEBUG", PHOTON_DEBUG),
        ("PHOTON_ACCUMULATION", PHOTON_ACCUMULATION),
        ("SPLAT_RECORDS", SPLAT_RECORDS),
        ("REFRACTION_COLOR", REFRACTION_COLOR),
        ("REFRACTION_ALBEDO", REFRACTION_ALBEDO),
        ("REFRACTION_DEPTH", REFRACTION_DEPTH),
        ("REFLECTION_COLOR", REFLECTION_COLOR),
        ("FRAME_VALUES", FRAME_VALUES),
        ("REFINED_CELLS", REFINED_CELLS),
    ];
}

#[cfg(test)]
mod abi_tests {
    use super::*;

    /// std430 size and alignment of the block's member types.
    fn std430(ty: &str) -> (usize, usize) {
        match ty {
            "float" => (4, 4),
            "vec2" => (8, 8),
            "vec3" => (12, 16),
            "vec4" => (16, 16),
            "mat4" => (64, 16),
            other => panic!("glsl/shared/frame.glsl: the block holds a {other}; teach this test its std430 layout"),
        }
    }

    /// The block's members, name and std430 offset, in declaration order: the fields of the
    /// `FrameValues` struct it opens with (the values every shader copies into `frame`), then
    /// its own.
    fn glsl_members(source: &str) -> (Vec<(String, usize)>, usize) {
        let block = source.split("readonly buffer FrameUniforms {").nth(1).expect("the FrameUniforms block");
        let block = block.split("} frame_buffer;").next().expect("the block's end");
        let (mut members, mut offset) = (Vec::new(), 0usize);
        for line in block.lines() {
            let code = line.split("//").next().unwrap_or("").trim();
            if code == "FrameValues values;" {
                assert!(members.is_empty(), "the block must open with its FrameValues");
                // std430 rounds a struct's size up to its alignment: 16, a vec3's or a mat4's.
                (members, offset) = struct_members(source);
            } else {
                push_member(line, &mut members, &mut offset);
            }
        }
        (members, offset.div_ceil(16) * 16)
    }

    /// The `FrameValues` struct's members and its std430 size (a multiple of 16).
    fn struct_members(source: &str) -> (Vec<(String, usize)>, usize) {
        let values = source.split("struct FrameValues {").nth(1).expect("the FrameValues struct");
        let values = values.split("};").next().expect("the struct's end");
        let (mut members, mut offset) = (Vec::new(), 0usize);
        for line in values.lines() {
            push_member(line, &mut members, &mut offset);
        }
        (members, offset.div_ceil(16) * 16)
    }

    /// Adds the member that `line` declares (none for a comment or a blank line) at its std430
    /// offset after `offset`, and moves `offset` past it.
    fn push_member(line: &str, members: &mut Vec<(String, usize)>, offset: &mut usize) {
        let code = line.split("//").next().unwrap_or("").trim();
        if code.is_empty() {
            return;
        }
        let decl = code.strip_suffix(';').unwrap_or_else(|| panic!("not a member declaration: {code:?}"));
        let (ty, name) = decl.split_once(' ').unwrap_or_else(|| panic!("not a member declaration: {code:?}"));
        let (size, align) = std430(ty.trim());
        // An array of scalars (`float a[16]`): std430 strides it by its element's size.
        let (name, count) = match name.trim().split_once('[') {
            Some((name, n)) => (name, n.trim_end_matches(']').parse::<usize>().expect("an array's length")),
            None => (name.trim(), 1),
        };
        assert!(count == 1 || ty.trim() == "float", "{code:?}: only arrays of float are std430-strided by their size");
        *offset = offset.div_ceil(align) * align;
        members.push((name.to_string(), *offset));
        *offset += size * count;
    }

    #[test]
    fn glsl_block_matches_the_rust_struct() {
        let (members, size) = glsl_members(include_str!("../glsl/shared/frame.glsl"));
        let rust: Vec<(String, usize)> = FRAME_UNIFORM_FIELDS.iter().map(|(n, o)| (n.to_string(), *o)).collect();
        assert_eq!(members, rust, "glsl/shared/frame.glsl's FrameUniforms and shader_abi::FrameUniforms differ");
        assert_eq!(size, std::mem::size_of::<FrameUniforms>());
        // The fragment shaders' uniform block holds the struct alone (std140 lays these types
        // out as std430 does, and pads the struct to 16 bytes alike).
        let (values, values_size) = struct_members(include_str!("../glsl/shared/frame.glsl"));
        assert_eq!(values.last().map(|(name, _)| name.as_str()), Some("steep_texel_stretch"));
        assert_eq!(values_size as u64, FRAME_VALUES_BYTES);
        let glsl = include_str!("../glsl/shared/frame.glsl");
        let knots = format!("const int PHOTON_DENSITY_KNOTS = {PHOTON_DENSITY_KNOTS};");
        assert!(glsl.contains(&knots), "frame.glsl must say {knots}");
    }

    #[test]
    fn the_layout_check_catches_a_misplaced_vec2() {
        // The shape of frame.glsl: a struct of values, then the block that opens with it.
        let block = |values: &str, own: &str| {
            format!("struct FrameValues {{\n{values}\n}};\nreadonly buffer FrameUniforms {{\n FrameValues values;\n{own}\n}} frame_buffer;")
        };
        // A vec2 after one float is aligned to 8 in std430: the Rust struct would put it at 4.
        let (members, _) = glsl_members(&block(" float a;\n vec2 b;", ""));
        assert_eq!(members, vec![("a".to_string(), 0), ("b".to_string(), 8)]);
        let (members, size) = glsl_members(&block(" vec3 a;\n float b; // tail\n mat4 c;", ""));
        assert_eq!(members, vec![("a".to_string(), 0), ("b".to_string(), 12), ("c".to_string(), 16)]);
        assert_eq!(size, 80);
        let (members, size) = glsl_members(&block(" float a;\n float b[3];\n vec2 c;", ""));
        assert_eq!(members, vec![("a".to_string(), 0), ("b".to_string(), 4), ("c".to_string(), 16)]);
        assert_eq!(size, 32);
        // The block's own members start after the struct padded to 16 bytes.
        let (members, size) = glsl_members(&block(" vec3 a;\n float b;\n float c;", " float d[3];"));
        assert_eq!(
            members,
            vec![("a".to_string(), 0), ("b".to_string(), 12), ("c".to_string(), 16), ("d".to_string(), 32)]
        );
        assert_eq!(size, 48);
    }
}
