//! Frame preparation (method step 1) and the uniforms every pass reads.
//!
//! The light frustum follows the camera: both light kinds look at the middle of the view
//! frustum, `p_mid = p_viewer + (z_near + z_far)/2 · l_viewer` (with z_far clamped to the
//! scene, so a far plane set generously does not aim the light at empty space). A
//! directional light sits `distance` back along its direction and projects orthographically
//! over the part of the scene the camera can see; a point light stays where it is and
//! projects in perspective over the same region.

use crate::scene::{LightKind, Scene};
use glam::{Mat4, Vec3, Vec4};

pub use crate::shader_abi::FrameUniforms;

/// Sizes of the frame's targets and the device limits the shaders clamp to.
#[derive(Clone, Copy, Debug)]
pub struct FrameExtents {
    pub output: [u32; 2],
    pub caustic: [u32; 2],
    pub godray: [u32; 2],
    pub light_map: u32,
    pub max_point_size: f32,
    pub max_line_width: f32,
}

// Right-handed, y-up view space; Vulkan clip space (y down, depth in [0, 1]).
use glam::camera::rh::proj::vulkan::{orthographic, perspective};
use glam::camera::rh::view::look_at_mat4;

/// The camera's view and projection.
pub fn camera_matrices(scene: &Scene, aspect: f32) -> (Mat4, Mat4) {
    let c = &scene.camera;
    let forward = (c.look_at - c.position).normalize();
    // Looking straight up or down makes y a degenerate up vector; use z then.
    let up = if forward.cross(Vec3::Y).length_squared() < 1e-6 { Vec3::Z } else { Vec3::Y };
    let view = look_at_mat4(c.position, c.look_at, up);
    let proj = perspective(c.fov_y_degrees.to_radians(), aspect, c.z_near, c.z_far);
    (view, proj)
}

/// The eight corners of the box `lo`..`hi`.
fn scene_corners_of(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The light's view-projection and its photon-flux parameters, following the camera.
#[derive(Clone, Copy, Debug)]
pub struct LightFrame {
    pub view_proj: Mat4,
    pub position: Vec3,
    pub axis: Vec3,
    /// Directional: half sizes (m) of the orthographic window. Point: tan of the half angles.
    pub half_extent: [f32; 2],
}

/// The photon grids' window inside the light's map window, as (min, size) in the map's uv:
/// the bounding rectangle of the water slab (its extent, between the lowest trough and the
/// highest crest) seen from the light. The maps must cover every receiver a refracted photon
/// can reach, but a photon outside the water's footprint can only miss the water: on the
/// built-in scenes half the grid did (`render --flux-budget`). The whole window where the
/// footprint is not in front of a point light.
pub fn photon_window(scene: &Scene, light: &LightFrame) -> (glam::Vec2, glam::Vec2) {
    let w = &scene.water;
    let bound = w.amplitude.abs() + w.noise_amplitude.abs();
    let full = (glam::Vec2::ZERO, glam::Vec2::ONE);
    let (mut lo, mut hi) = (glam::Vec2::splat(f32::INFINITY), glam::Vec2::splat(f32::NEG_INFINITY));
    for corner in 0..8 {
        let x = if corner & 1 == 0 { w.extent_min.x } else { w.extent_max.x };
        let z = if corner & 2 == 0 { w.extent_min.y } else { w.extent_max.y };
        let y = if corner & 4 == 0 { w.level - bound } else { w.level + bound };
        let clip = light.view_proj * glam::Vec4::new(x, y, z, 1.0);
        if !(clip.w > 1e-6) {
            return full;
        }
        let uv = glam::Vec2::new(clip.x, clip.y) / clip.w * 0.5 + 0.5;
        lo = lo.min(uv);
        hi = hi.max(uv);
    }
    let (lo, hi) = (lo.clamp(glam::Vec2::ZERO, glam::Vec2::ONE), hi.clamp(glam::Vec2::ZERO, glam::Vec2::ONE));
    if !(hi.x > lo.x && hi.y > lo.y && lo.is_finite() && hi.is_finite()) {
        return full;
    }
    (lo, hi - lo)
}

/// `bounds`: the scene's bounds (`Scene::bounds`), computed once per scene, not per frame.
pub fn light_frame(scene: &Scene, bounds: (Vec3, Vec3), aspect: f32) -> LightFrame {
    let c = &scene.camera;
    let (lo, hi) = bounds;
    let radius = (hi - lo).length().max(1e-3);
    let forward = (c.look_at - c.position).normalize();
    let far = c.z_far.min(radius * 2.0);
    let p_mid = c.position + 0.5 * (c.z_near + far) * forward;

    // The bounds of the scene and of its water: the depth range must hold the surface (photon
    // rays start at the light's near plane and must cross it inside the frustum), and the
    // camera may look through water with no receiver near.
    let w = &scene.water;
    let reach = w.amplitude.abs() + w.noise_amplitude.abs() + 0.01;
    let (lo_all, hi_all) = (
        lo.min(Vec3::new(w.extent_min.x, w.level - reach, w.extent_min.y)),
        hi.max(Vec3::new(w.extent_max.x, w.level + reach, w.extent_max.y)),
    );

    // The region the photons must cover: what the camera can see. A grid of view rays runs
    // from the near plane until each leaves the bounds of the scene and its water (or
    // reaches the far plane); their near points and exit points span the visible region.
    // (The four corner rays alone are not enough: they may leave the water within a metre
    // while the centre of the view looks across the whole pool.)
    let (view, proj) = camera_matrices(scene, aspect);
    let inv = (proj * view).inverse();
    const RAYS: usize = 9;
    // A fixed array: this runs every frame and must not allocate.
    let mut corners = [Vec3::ZERO; 3 * RAYS * RAYS];
    for j in 0..RAYS {
        for i in 0..RAYS {
            let k = 3 * (j * RAYS + i);
            let x = -1.0 + 2.0 * i as f32 / (RAYS - 1) as f32;
            let y = -1.0 + 2.0 * j as f32 / (RAYS - 1) as f32;
            let near = inv * Vec4::new(x, y, 0.0, 1.0);
            let near = near.truncate() / near.w;
            let dir = (near - c.position).normalize();
            let exit = ray_box_exit(c.position, dir, lo_all, hi_all).clamp(c.z_near, far);
            corners[k] = near.clamp(lo_all, hi_all);
            corners[k + 1] = (c.position + dir * exit).clamp(lo_all, hi_all);
            corners[k + 2] = photon_entry(scene, corners[k + 1]).clamp(lo_all, hi_all);
        }
    }
    let scene_corners = scene_corners_of(lo_all, hi_all);

    match scene.light.kind {
        LightKind::Directional => {
            let dir = scene.light.direction.normalize();
            // The frame's origin sits back along the light's direction, 1 m beyond the farthest
            // corner of the scene and its water, so every photon ray starts above the water and
            // in front of everything it can meet. `light.distance` only scales the irradiance
            // (E⊥ = I / distance²): placing the frame at that distance from the view's middle
            // put it under the water for a camera looking down with a far z_far, and every
            // photon was dropped without a word (tests/extremes.rs).
            let back = scene_corners.iter().map(|q| (*q - p_mid).dot(-dir)).fold(0.0f32, f32::max);
            let position = p_mid - dir * (back + 1.0);
            let up = if dir.cross(Vec3::Z).length_squared() < 1e-6 { Vec3::X } else { Vec3::Z };
            let view = look_at_mat4(position, p_mid, up);
            let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
            for p in &corners {
                let q = view.transform_point3(*p);
                min = min.min(q);
                max = max.max(q);
            }
            // Refraction bends photons sideways; a margin keeps receivers near the edge lit.
            let margin = 0.1 * (max - min).truncate().max_element() + 0.25;
            // The depth range holds the scene's corners as the maps place them: below the
            // water they sit farther along the bent path (light_map_point), in either pair of
            // maps.
            let (refracted, steep) = (refracted_light_axis(scene), steep_light_axis(scene));
            let (mut zmin, mut zmax) = (f32::INFINITY, f32::NEG_INFINITY);
            for p in &scene_corners {
                let bent = |r| crate::shader_math::light_map_point(*p, w.level, dir, r);
                for q in [*p, bent(refracted), bent(steep)] {
                    let q = view.transform_point3(q);
                    zmin = zmin.min(-q.z);
                    zmax = zmax.max(-q.z);
                }
            }
            let half = [0.5 * (max.x - min.x) + margin, 0.5 * (max.y - min.y) + margin];
            let center = 0.5 * (min + max);
            // Centre the window on the visible region (the look-at point may not be its middle).
            let shift = Mat4::from_translation(Vec3::new(-center.x, -center.y, 0.0));
            let proj = orthographic(-half[0], half[0], -half[1], half[1], (zmin - 1.0).max(0.01), zmax + 1.0);
            LightFrame { view_proj: proj * shift * view, position, axis: dir, half_extent: half }
        }
        LightKind::Point => {
            let position = scene.light.position;
            let axis = (p_mid - position).normalize_or(Vec3::NEG_Y);
            let up = if axis.cross(Vec3::Z).length_squared() < 1e-6 { Vec3::X } else { Vec3::Z };
            let view = look_at_mat4(position, position + axis, up);
            let (mut tx, mut ty) = (0.05f32, 0.05f32);
            let mut zmax = 0.1f32;
            for p in corners.iter().chain(&scene_corners) {
                let q = view.transform_point3(*p);
                zmax = zmax.max(-q.z);
            }
            for p in &corners {
                let q = view.transform_point3(*p);
                if -q.z > 1e-3 {
                    tx = tx.max((q.x / -q.z).abs());
                    ty = ty.max((q.y / -q.z).abs());
                } else {
                    // Part of the view is beside or behind the light: cover a wide cone.
                    tx = tx.max(1.7);
                    ty = ty.max(1.7);
                }
            }
            let (tx, ty) = (tx.min(1.7) * 1.1, ty.min(1.7) * 1.1);
            let proj = perspective(2.0 * ty.atan(), tx / ty, 0.01, zmax * 1.1 + 1.0);
            LightFrame { view_proj: proj * view, position, axis, half_extent: [tx, ty] }
        }
    }
}

/// Where the photons that light the underwater point `p` enter the water, as if it were flat:
/// `p` traced back up the refracted light ray to the water level (`p` itself when above the
/// water). The light's window must cover these as well as the visible receivers: at a low
/// sun a visible floor point's texel lies far up-sun along the straight light ray (11 m at a
/// 10° sun over a 2 m floor), while the photons that reach it enter the water only 2 m away.
pub(super) fn photon_entry(scene: &Scene, p: Vec3) -> Vec3 {
    let level = scene.water.level;
    if p.y >= level {
        return p;
    }
    let incident = match scene.light.kind {
        LightKind::Directional => scene.light.direction.normalize(),
        LightKind::Point => (p - scene.light.position).normalize_or(Vec3::NEG_Y),
    };
    let refracted = crate::shader_math::refract(incident, Vec3::Y, 1.0 / scene.water.ior);
    if refracted.y >= -1e-3 {
        return p; // light from below the surface: its photons do not cross it here
    }
    p - refracted * ((level - p.y) / -refracted.y)
}

/// A directional light's travel direction under flat water, along which the light's maps
/// see the underwater receivers (`shader_math::light_map_point`); zero for a point light,
/// whose maps see along straight rays (its refracted rays share no direction), and for light
/// that cannot enter the water from above.
///
/// Why the maps bend: a photon's image-space iteration can only find a receiver that the map
/// holds. Mapped along the straight light ray, an underwater floor beside a post or a wall is
/// hidden behind it in the light's view, although refracted photons, which travel more
/// steeply, reach it: those photons could not converge, and the light they carry was missing
/// in a band along every shadow edge (tank: 5.6 % of the grid's power; 1.2 % bent).
pub fn refracted_light_axis(scene: &Scene) -> Vec3 {
    if scene.light.kind != LightKind::Directional {
        return Vec3::ZERO;
    }
    let r = crate::shader_math::refract(scene.light.direction.normalize(), Vec3::Y, 1.0 / scene.water.ior);
    if r.y < -1e-3 {
        r.normalize()
    } else {
        Vec3::ZERO
    }
}

/// The second light maps' bend: `refracted_light_axis` with its horizontal part scaled by
/// `STEEP_MAP_HORIZONTAL`, steeper than flat water's; zero where the maps do not bend.
///
/// Why two maps: the waves bend some photons more steeply than flat water, and beside the
/// lee side of a wall or a post the floor those photons reach lies behind the occluder in the
/// first maps: their iteration cannot converge, and a band of light beside the shadow was
/// missing (the tank's west wall: at t = 5 s the 320×200 frame's lower-left block held 0.40
/// of the reference's light). One map bent more steeply sees past that edge but hides the
/// floor beside a shadow's other edge (the port's seabed), so the first maps stay along flat
/// water and only the photons that do not converge in them search these (`cast_photon`,
/// photon_cast.glsl; docs/accuracy.md, "Light maps along a steeper direction").
pub fn steep_light_axis(scene: &Scene) -> Vec3 {
    let r = refracted_light_axis(scene);
    if r == Vec3::ZERO {
        return Vec3::ZERO;
    }
    Vec3::new(r.x * STEEP_MAP_HORIZONTAL, r.y, r.z * STEEP_MAP_HORIZONTAL).normalize()
}

/// How much of flat water's horizontal travel the second maps' bend keeps. The waves of the
/// built-in scenes tilt the refracted light by up to about 3°, which at the tank's sun is 0.7
/// of its horizontal travel per metre of depth; measured as the only maps, 0.7 and 0.5 brought
/// the tank's band back alike, and as the second maps too (caustic relative RMSE at 320×200,
/// means over t = 1–5 s, tank / port / storage: 0.7 0.346 / 0.481 / 0.440, 0.5 0.343 / 0.481 /
/// 0.440; docs/accuracy.md).
pub const STEEP_MAP_HORIZONTAL: f32 = 0.7;

/// How much wider a map texel's beam is under the water than above it (in the plane of
/// incidence): max(1, |r_y| / |d_y|). 1 when the maps do not bend.
fn refracted_texel_stretch(light_axis: Vec3, refracted: Vec3) -> f32 {
    if refracted == Vec3::ZERO || light_axis.y.abs() < 1e-6 {
        return 1.0;
    }
    (refracted.y.abs() / light_axis.y.abs()).max(1.0)
}

/// The photon grids' offset at animation time `time`, in photon cells, each axis in
/// [−½, ½): the R2 sequence (the plastic number's low-discrepancy sequence) at frame
/// round(60 t). A frame at time t always gets the same grid, so a headless render is
/// reproducible; successive frames cover a cell evenly, so the grid's staircase becomes
/// noise that time averages out.
pub fn photon_jitter(time: f32) -> [f32; 2] {
    const STEP: [f64; 2] = [0.754_877_666_246_692_7, 0.569_840_290_998_053_3]; // 1/g, 1/g² (g³ = g + 1)
    let frame = (time as f64 * 60.0).round();
    STEP.map(|s| ((0.5 + frame * s).rem_euclid(1.0) - 0.5) as f32)
}

/// Distance along a ray from `o` (inside or outside the box) to where it leaves [lo, hi].
pub(super) fn ray_box_exit(o: Vec3, d: Vec3, lo: Vec3, hi: Vec3) -> f32 {
    let mut t = f32::INFINITY;
    for axis in 0..3 {
        if d[axis].abs() > 1e-9 {
            let bound = if d[axis] > 0.0 { hi[axis] } else { lo[axis] };
            t = t.min(((bound - o[axis]) / d[axis]).max(0.0));
        }
    }
    t
}

/// Irradiance on a plane facing a directional light: the paper models the sun as a very
/// distant point light of intensity I (W/sr) at `distance`, so E⊥ = I / distance².
pub fn directional_irradiance(scene: &Scene) -> f32 {
    scene.light.intensity / (scene.light.distance * scene.light.distance)
}

/// E_surface: the light's irradiance on the water at normal incidence (for a point light,
/// on the water plane straight below it, at least 1 m away). The scale of the caustic
/// buffer and of the tonemapping exposure.
pub fn surface_irradiance(scene: &Scene) -> f32 {
    match scene.light.kind {
        LightKind::Directional => directional_irradiance(scene),
        LightKind::Point => scene.light.intensity / (scene.light.position.y - scene.water.level).abs().max(1.0).powi(2),
    }
}

/// The tonemap's exposure, 1/(W/(m²·sr)): 2π / E_surface, so a diffuse receiver of albedo 1
/// lit by the surface's irradiance maps to 1 − e^(−2) (compose.frag's `1 − e^(−exposure·L)`).
pub fn tonemap_exposure(scene: &Scene) -> f32 {
    2.0 * std::f32::consts::PI / surface_irradiance(scene).max(1e-12)
}

/// Fraction of the direct irradiance that arrives as diffuse sky light (ambient under water).
pub const AMBIENT_FRACTION: f32 = 0.1;

impl FrameUniforms {
    /// The frame's uniforms at `time`. `bounds` is `scene.bounds()`, passed in so the
    /// per-frame path does not walk the meshes.
    pub fn new(scene: &Scene, bounds: (Vec3, Vec3), extents: &FrameExtents, time: f32) -> Self {
        let aspect = extents.output[0] as f32 / extents.output[1] as f32;
        let (view, proj) = camera_matrices(scene, aspect);
        let light = light_frame(scene, bounds, aspect);
        let c = &scene.camera;
        let w = &scene.water;
        let e = &scene.effects;
        let caustic_photons = (e.caustic_grid * e.caustic_subdivision) as f32;
        let godray_photons = (e.godray_grid * e.godray_subdivision) as f32;
        let (kind, strength) = match scene.light.kind {
            LightKind::Directional => (0.0, directional_irradiance(scene)),
            LightKind::Point => (1.0, scene.light.intensity),
        };
        let surface_irradiance = surface_irradiance(scene);
        let exposure = tonemap_exposure(scene);
        let model = w.model.glsl_id() as f32;
        let m = &scene.medium;
        let photon_window = photon_window(scene, &light);
        let refracted = refracted_light_axis(scene);
        let steep = steep_light_axis(scene);
        Self {
            camera_view_proj: (proj * view).to_cols_array_2d(),
            light_view_proj: light.view_proj.to_cols_array_2d(),
            light_inv_view_proj: light.view_proj.inverse().to_cols_array_2d(),
            camera_inv_view_proj: (proj * view).inverse().to_cols_array_2d(),
            camera_position: c.position.to_array(),
            time,
            z_near: c.z_near,
            z_far: c.z_far,
            tan_half_fov_y: (0.5 * c.fov_y_degrees.to_radians()).tan(),
            aspect,
            light_position: light.position.to_array(),
            light_is_point: kind,
            light_axis: light.axis.to_array(),
            scene_lowest_y: bounds.0.y,
            surface_irradiance,
            light_strength: strength,
            light_half_extent: light.half_extent,
            water_level: w.level,
            wave_amplitude: w.amplitude,
            wavelength: w.wavelength,
            wave_speed: w.speed,
            noise_amplitude: w.noise_amplitude,
            noise_scale: w.noise_scale,
            ior: w.ior,
            water_model: model,
            wave_center: w.center.to_array(),
            water_extent_min: w.extent_min.to_array(),
            water_extent_max: w.extent_max.to_array(),
            ambient_irradiance: AMBIENT_FRACTION * surface_irradiance,
            exposure,
            attenuation: m.gamma.to_array(),
            scattering: m.scattering,
            point_size_min: e.point_size_min,
            point_size_max: e.point_size_max,
            line_width: e.line_width,
            hg_g: m.hg_g,
            caustic_photons_per_axis: caustic_photons,
            godray_photons_per_axis: godray_photons,
            iterations: e.iterations as f32,
            light_map_size: extents.light_map as f32,
            device_max_point_size: extents.max_point_size,
            device_max_line_width: extents.max_line_width,
            caustic_target_size: extents.caustic.map(|v| v as f32),
            godray_target_size: extents.godray.map(|v| v as f32),
            output_size: extents.output.map(|v| v as f32),
            water_phase: crate::shader_math::water_phase(w, time).to_array(),
            surface_views_ready: 0.0,
            // Flat until the frame fills it in (it holds the noise's CPU twin).
            camera_water_gradient: [0.0; 2],
            camera_water_height: 0.0,
            // The paper's even grid until the frame sets a view-adapted warp (Frame::record).
            photon_density_warp: 0.0,
            photon_window_min: photon_window.0.to_array(),
            photon_window_size: photon_window.1.to_array(),
            refracted_light_axis: refracted.to_array(),
            refracted_texel_stretch: refracted_texel_stretch(light.axis, refracted),
            photon_jitter: if e.photon_jitter { photon_jitter(time) } else { [0.0; 2] },
            godray_density_warp: 0.0,
            caustic_grid_aspect: 1.0,
            steep_light_axis: steep.to_array(),
            steep_texel_stretch: refracted_texel_stretch(light.axis, steep),
            photon_density_rows: super::photon_density::PhotonDensity::EVEN.rows,
            photon_density_columns: super::photon_density::PhotonDensity::EVEN.columns_flat(),
            godray_density_rows: super::photon_density::PhotonDensity::EVEN.rows,
            godray_density_columns: super::photon_density::PhotonDensity::EVEN.columns_flat(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::photon_jitter;

    #[test]
    fn photon_jitter_covers_the_cell_evenly() {
        // 64 frames: every offset inside the cell, none repeated, and each of the cell's
        // sixteen 1/4 × 1/4 squares visited 2 to 6 times (4 on average): a low-discrepancy
        // sequence, where a constant or a clumping one fails.
        let mut counts = [0u32; 16];
        let mut seen = Vec::new();
        for frame in 0..64 {
            let o = photon_jitter(frame as f32 / 60.0);
            assert!(o.iter().all(|v| (-0.5..0.5).contains(v)), "frame {frame}: {o:?}");
            assert!(!seen.contains(&o), "frame {frame} repeats {o:?}");
            seen.push(o);
            let cell = |v: f32| (((v + 0.5) * 4.0) as usize).min(3);
            counts[cell(o[1]) * 4 + cell(o[0])] += 1;
        }
        assert!(counts.iter().all(|&c| (2..=6).contains(&c)), "visits per sixteenth of the cell: {counts:?}");
        assert_eq!(photon_jitter(1.0), photon_jitter(1.0), "a frame's grid depends on its time alone");
    }
}
