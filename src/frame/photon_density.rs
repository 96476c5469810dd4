//! Where the photons go: the paper's even grid over the water's footprint, or a grid warped
//! to where the view needs them (`effects.caustic_photon_density` and `godray_photon_density
//! = "view"`).
//!
//! Why: the triangle estimator resolves a caustic as finely as its mesh, and an even grid
//! spends the same photons on a metre of seabed at the far end of the port (two pixels) as on
//! a metre under the camera (thirty). A caustic's error on screen is ruled by the photon
//! spacing in pixels, so the error summed over pixels is least when the photons per
//! receiver area follow the pixels per receiver area: with `q` pixels and `n` photons per m²,
//! a pixel's error grows with the spacing `√(q/n)`, and minimising `∫ q·(q/n)^s` subject to
//! `∫ n = N` gives `n ∝ q` for any power `s`. A pixel's godray sums the beams its view ray
//! crosses, so the beams follow the length of view ray through the water above where they
//! enter.
//!
//! How: `view_adapted` casts a grid of camera rays against the scene's triangles (each ray
//! stands for the same number of pixels). It takes every receiver a ray meets under the water
//! back up the refracted light to where its photons enter the water (through flat water), and
//! counts the rays per cell of a `SEGMENTS`² histogram over the photon window; for the beams,
//! it adds the length of each step along the ray's underwater part to the cell above the step.
//! Blurred (`BLUR`: the waves bend photons sideways) and floored at `FLOOR` of the mean (so that
//! receivers no ray met still get photons), each histogram is a piecewise-constant density.
//! The warp is its inverse cumulative distribution: the window's v from the rows' marginal,
//! the window's u from each row's conditional, interpolated between rows so that the mesh
//! stays continuous. `cast_photon` (photon_cast.glsl, twin `shader_math::photon_density_warp`)
//! maps its grid position through it and scales the photon's flux by its warped cell's area
//! over the even cell's: a photon carries the light through its own cell, however large.
//!
//! The warps depend on the camera and the light, not the time, so the frame computes them
//! when either moves (`Frame::record`), not every frame.

use crate::bvh::Bvh;
use crate::scene::Scene;
use crate::shader_abi::{FrameUniforms, PHOTON_DENSITY_KNOTS as KNOTS, PHOTON_DENSITY_SEGMENTS as SEGMENTS};
use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};

/// Camera rays per axis of the survey (x, y): each stands for a 1/4000 share of the pixels.
/// With the beams' steps, a survey takes 13–15 ms on one core of the 2-core machine (the
/// built-in scenes, release build), whenever the camera or the light moves.
const RAYS: [usize; 2] = [80, 50];
/// Passes of a 3×3 box blur over the histogram. The blur stands for the waves, which bend a
/// photon sideways from where flat water would take it, and it keeps the warp smooth: the
/// survey's counts are a few per cell, and a warp that follows their noise gives a mesh of
/// uneven cells (31² cells, 2400 rays, 320×200, caustic rel. RMSE tank / port / storage:
/// one pass 0.403 / 0.440 / 0.516, two 0.357 / 0.373 / 0.493, three 0.331 / 0.365 / 0.473).
const BLUR: usize = 3;
/// The least density, as a share of the mean: receivers between the rays, and light the waves
/// bend in from outside the view, keep some photons. 0.05, 0.15 and 0.3 measured alike
/// (within 0.015 on every scene); 0.15 lost the least flux on the port.
const FLOOR: f64 = 0.15;
/// Below this many rays landing in the window, the view is too little of the water to survey
/// (looking at the sky, or at the walls above the water): the even grid.
const MIN_RAYS: usize = 16;

/// The warp as the shader reads it (`FrameUniforms::photon_density_rows` and `_columns`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhotonDensity {
    /// The window's v at grid v = k / SEGMENTS.
    pub rows: [f32; KNOTS],
    /// Per band j of the window's v (centred at (j + ½) / SEGMENTS): the window's u at grid
    /// u = k / SEGMENTS.
    pub columns: [[f32; KNOTS]; SEGMENTS],
}

impl PhotonDensity {
    /// The even grid: the identity.
    pub const EVEN: PhotonDensity = {
        let mut rows = [0.0f32; KNOTS];
        let mut k = 0;
        while k < KNOTS {
            rows[k] = k as f32 / SEGMENTS as f32;
            k += 1;
        }
        PhotonDensity { rows, columns: [rows; SEGMENTS] }
    };

    /// Sets the frame's uniforms to warp the caustic photons by this density.
    pub fn apply_to_caustics(&self, u: &mut FrameUniforms) {
        u.photon_density_warped = 1.0;
        u.photon_density_rows = self.rows;
        u.photon_density_columns = self.columns_flat();
    }

    /// Sets the frame's uniforms to warp the godray beams by this density.
    pub fn apply_to_godrays(&self, u: &mut FrameUniforms) {
        u.godray_density_warped = 1.0;
        u.godray_density_rows = self.rows;
        u.godray_density_columns = self.columns_flat();
    }

    /// `columns` row after row, as `FrameUniforms::photon_density_columns` holds them.
    pub const fn columns_flat(&self) -> [f32; KNOTS * SEGMENTS] {
        let mut flat = [0.0f32; KNOTS * SEGMENTS];
        let mut i = 0;
        while i < KNOTS * SEGMENTS {
            flat[i] = self.columns[i / KNOTS][i % KNOTS];
            i += 1;
        }
        flat
    }

    /// From a density histogram over the window (`[v band][u band]`, every entry > 0).
    fn from_histogram(h: &[[f64; SEGMENTS]; SEGMENTS]) -> Self {
        let mut marginal = [0.0f64; SEGMENTS];
        for (j, row) in h.iter().enumerate() {
            marginal[j] = row.iter().sum();
        }
        let mut columns = [[0.0f32; KNOTS]; SEGMENTS];
        for (j, row) in h.iter().enumerate() {
            columns[j] = inverse_cumulative(row);
        }
        PhotonDensity { rows: inverse_cumulative(&marginal), columns }
    }

    /// The warp's densest cell against its mean: how much finer the mesh is there than the
    /// even grid's (by area).
    pub fn peak_density(&self) -> f32 {
        let (mut peak, columns) = (0.0f32, self.columns_flat());
        for j in 0..SEGMENTS {
            for k in 0..SEGMENTS {
                let g = Vec2::new((k as f32 + 0.5) / SEGMENTS as f32, (j as f32 + 0.5) / SEGMENTS as f32);
                let (_, jacobian) =
                    crate::shader_math::photon_density_warp(&self.rows, &columns, g, 0.5 / SEGMENTS as f32);
                peak = peak.max(1.0 / jacobian.max(1e-12));
            }
        }
        peak
    }
}

/// The knots of the inverse of the cumulative distribution of a piecewise-constant density
/// over [0, 1] (`p[i]` on [i, i+1] / SEGMENTS, all > 0): x at cumulative share k / SEGMENTS.
fn inverse_cumulative(p: &[f64; SEGMENTS]) -> [f32; KNOTS] {
    let total: f64 = p.iter().sum();
    let mut knots = [0.0f32; KNOTS];
    let (mut bin, mut below) = (0usize, 0.0f64); // `below`: the mass of bins before `bin`
    for (k, knot) in knots.iter_mut().enumerate().take(SEGMENTS).skip(1) {
        let target = total * k as f64 / SEGMENTS as f64;
        while bin + 1 < SEGMENTS && below + p[bin] < target {
            below += p[bin];
            bin += 1;
        }
        let within = ((target - below) / p[bin]).clamp(0.0, 1.0);
        *knot = ((bin as f64 + within) / SEGMENTS as f64) as f32;
    }
    knots[SEGMENTS] = 1.0;
    knots
}

/// The warps of one frame's survey: the caustic photons' and the godray beams'.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewDensities {
    /// Photons in proportion to the pixels that see where they land.
    pub caustics: Option<PhotonDensity>,
    /// Beams in proportion to the length of view ray through the water above where they
    /// enter: a pixel's godray sums the beams its ray crosses, so the beams go where rays cross
    /// the water (measured: the length alone, or weighted by 1/distance or 1/√distance to the
    /// camera, read within 0.002 of each other on every built-in scene).
    pub godrays: Option<PhotonDensity>,
}

/// Steps along each survey ray's underwater part, for the beams' density.
const BEAM_STEPS: usize = 24;

/// The warps for the frame `u` (its camera, light and photon window), from one survey of the
/// scene (`bounds`: `Scene::bounds`). Each is `None` where the view holds too little lit water
/// to survey; the even grid then.
pub fn view_adapted(scene: &Scene, bounds: (Vec3, Vec3), bvh: &Bvh, u: &FrameUniforms) -> ViewDensities {
    let none = ViewDensities { caustics: None, godrays: None };
    let inv = Mat4::from_cols_array_2d(&u.camera_inv_view_proj);
    let light = Mat4::from_cols_array_2d(&u.light_view_proj);
    let (window_min, window_size) = (Vec2::from(u.photon_window_min), Vec2::from(u.photon_window_size));
    if !(window_size.x > 0.0 && window_size.y > 0.0) {
        return none;
    }
    // The cell of the photon window whose photons enter the water where those that reach
    // underwater point p do (through flat water).
    let cell_of = |p: DVec3| -> Option<(usize, usize)> {
        let entry = super::uniforms::photon_entry(scene, p.as_vec3());
        let clip = light * entry.extend(1.0);
        if !(clip.w > 1e-6) {
            return None;
        }
        let uv = (Vec2::new(clip.x, clip.y) / clip.w * 0.5 + 0.5 - window_min) / window_size;
        if !(uv.x >= 0.0 && uv.y >= 0.0 && uv.x < 1.0 && uv.y < 1.0) {
            return None;
        }
        let cell = (uv * SEGMENTS as f32).as_uvec2().min(glam::UVec2::splat(SEGMENTS as u32 - 1));
        Some((cell.y as usize, cell.x as usize))
    };
    let w = &scene.water;
    let slab = scene.water.amplitude.abs() + scene.water.noise_amplitude.abs();
    let (box_lo, box_hi) = (
        bounds.0.min(Vec3::new(w.extent_min.x, w.level - slab, w.extent_min.y)).as_dvec3(),
        bounds.1.max(Vec3::new(w.extent_max.x, w.level + slab, w.extent_max.y)).as_dvec3(),
    );
    let camera = Vec3::from(u.camera_position).as_dvec3();
    let level = w.level as f64;
    let mut receivers = [[0.0f64; SEGMENTS]; SEGMENTS];
    let mut crossings = [[0.0f64; SEGMENTS]; SEGMENTS];
    let (mut landed, mut crossed) = (0usize, 0usize);
    for y in 0..RAYS[1] {
        for x in 0..RAYS[0] {
            let ndc =
                Vec2::new((x as f32 + 0.5) / RAYS[0] as f32 * 2.0 - 1.0, (y as f32 + 0.5) / RAYS[1] as f32 * 2.0 - 1.0);
            let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
            let far = (far.truncate() / far.w).as_dvec3();
            let Some(ray) = underwater_ray(bvh, camera, far, level, w.ior as f64, (box_lo, box_hi)) else {
                continue;
            };
            if let Some(t) = ray.hit {
                if let Some((j, i)) = cell_of(ray.origin + ray.direction * t) {
                    receivers[j][i] += 1.0;
                    landed += 1;
                }
            }
            let ds = ray.length / BEAM_STEPS as f64;
            for k in 0..BEAM_STEPS {
                let p = ray.origin + ray.direction * ((k as f64 + 0.5) * ds);
                if let Some((j, i)) = (p.y < level).then(|| cell_of(p)).flatten() {
                    crossings[j][i] += ds;
                    crossed += 1;
                }
            }
        }
    }
    ViewDensities {
        caustics: (landed >= MIN_RAYS).then(|| PhotonDensity::from_survey(receivers)),
        godrays: (crossed >= MIN_RAYS).then(|| PhotonDensity::from_survey(crossings)),
    }
}

impl PhotonDensity {
    /// From a survey's histogram: BLUR passes of a 3×3 box over the cells (clamped at the
    /// window's border), then the floor.
    fn from_survey(counts: [[f64; SEGMENTS]; SEGMENTS]) -> Self {
        let mut density = counts;
        for _ in 0..BLUR {
            density = box_blur(&density);
        }
        let mean = density.iter().flatten().sum::<f64>() / (SEGMENTS * SEGMENTS) as f64;
        for d in density.iter_mut().flatten() {
            *d += FLOOR * mean;
        }
        PhotonDensity::from_histogram(&density)
    }
}

/// The mean over each cell's 3×3 neighbourhood, within the window.
fn box_blur(h: &[[f64; SEGMENTS]; SEGMENTS]) -> [[f64; SEGMENTS]; SEGMENTS] {
    let mut out = [[0.0f64; SEGMENTS]; SEGMENTS];
    for (j, out_row) in out.iter_mut().enumerate() {
        let rows = &h[j.saturating_sub(1)..=(j + 1).min(SEGMENTS - 1)];
        for (i, value) in out_row.iter_mut().enumerate() {
            let columns = i.saturating_sub(1)..=(i + 1).min(SEGMENTS - 1);
            let cells = rows.len() * columns.clone().count();
            *value = rows.iter().map(|row| row[columns.clone()].iter().sum::<f64>()).sum::<f64>() / cells as f64;
        }
    }
    out
}

/// The part of a camera ray that runs under the water: from the camera (under the water) or
/// from where the ray, refracted as if the water were flat, enters it, for `length` metres, to
/// the first receiver (`hit`, the distance along `direction`), the water's level, the far
/// plane or the scene's box, whichever comes first.
struct UnderwaterRay {
    origin: DVec3,
    direction: DVec3,
    length: f64,
    hit: Option<f64>,
}

/// The underwater part of the camera's ray towards `far`; `None` where it has none (it meets
/// something above the water first, or never goes under it).
fn underwater_ray(
    bvh: &Bvh,
    camera: DVec3,
    far: DVec3,
    level: f64,
    ior: f64,
    bounds: (DVec3, DVec3),
) -> Option<UnderwaterRay> {
    let length = (far - camera).length();
    if !(length > 1e-9 && length.is_finite()) {
        return None;
    }
    let mut d = (far - camera) / length;
    let mut o = camera;
    let mut reach = length;
    if camera.y > level {
        // Above the water: a ray that meets something before the water sees no caustic.
        if !(d.y < -1e-6) {
            return None;
        }
        let t = (level - camera.y) / d.y;
        if t >= reach || bvh.occluded(camera, d, 1e-6, t) {
            return None;
        }
        o = camera + d * t;
        let r = crate::shader_math::refract(d.as_vec3(), Vec3::Y, 1.0 / ior as f32).as_dvec3();
        if !(r.y < -1e-6) {
            return None;
        }
        d = r.normalize();
        reach -= t;
    } else if d.y > 1e-6 {
        // Under the water, looking up: what lies beyond the surface is above it.
        reach = reach.min((level - camera.y) / d.y);
    }
    let exit = super::uniforms::ray_box_exit(o.as_vec3(), d.as_vec3(), bounds.0.as_vec3(), bounds.1.as_vec3()) as f64;
    reach = reach.min(exit);
    let first = bvh.closest(o, d, 1e-6, reach).map(|h| h.t);
    let length = first.unwrap_or(reach);
    let hit = first.filter(|&t| (o + d * t).y < level);
    (length > 0.0).then_some(UnderwaterRay { origin: o, direction: d, length, hit })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_even_grid_is_the_identity() {
        let even = PhotonDensity::EVEN;
        for g in [Vec2::new(0.013, 0.97), Vec2::new(0.5, 0.5), Vec2::new(0.71, 0.2)] {
            let (w, jacobian) = crate::shader_math::photon_density_warp(&even.rows, &even.columns_flat(), g, 0.01);
            assert!((w - g).abs().max_element() < 1e-6, "{g} → {w}");
            assert!((jacobian - 1.0).abs() < 1e-5, "{jacobian}");
        }
    }

    #[test]
    fn a_warp_puts_photons_where_the_density_is_and_keeps_their_flux() {
        // Density 9 in the window's block u < 1/3, v ≥ 2/3 (a ninth of it), 1 elsewhere: the
        // block holds 9 / (9 + 8) = 0.53 of the mass.
        let third = SEGMENTS / 3;
        let mut h = [[1.0f64; SEGMENTS]; SEGMENTS];
        for row in h.iter_mut().skip(SEGMENTS - third) {
            for v in row.iter_mut().take(third) {
                *v = 9.0;
            }
        }
        let block = (third * third) as f64 * 9.0;
        let expected = block / (block + (SEGMENTS * SEGMENTS - third * third) as f64);
        let warp = PhotonDensity::from_histogram(&h);
        let columns = warp.columns_flat();
        // A grid of photons: the share landing in the dense block, and the sum of their
        // cells' areas (the flux they carry, as a share of the window's).
        let n = 300;
        let (mut inside, mut area) = (0usize, 0.0f64);
        let edge = third as f32 / SEGMENTS as f32;
        for j in 0..n {
            for i in 0..n {
                let g = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                let (w, cell) = crate::shader_math::photon_density_warp(&warp.rows, &columns, g, 0.5 / n as f32);
                assert!(w.min_element() >= 0.0 && w.max_element() <= 1.0, "{g} → {w}");
                area += cell as f64 / (n * n) as f64;
                if w.x < edge && w.y >= 1.0 - edge {
                    inside += 1;
                }
            }
        }
        // The bands' interpolation blurs the block's lower edge by half a band.
        let share = inside as f64 / (n * n) as f64;
        assert!((share - expected).abs() < 0.03, "share of photons in the dense block: {share}, not {expected}");
        assert!((area - 1.0).abs() < 0.01, "the photons' cells cover {area} of the window");
    }

    #[test]
    fn inverse_cumulative_of_a_step() {
        let mut p = [1.0f64; SEGMENTS];
        p[0] = (SEGMENTS - 1) as f64; // half the mass in the first bin
        let knots = inverse_cumulative(&p);
        assert_eq!(knots[0], 0.0);
        assert_eq!(knots[SEGMENTS], 1.0);
        assert!(knots.windows(2).all(|w| w[1] > w[0]), "{knots:?}");
        // Cumulative share k / S below a half lies in the first bin, at 2k/S of its width.
        let k = SEGMENTS / 2;
        let s = SEGMENTS as f32;
        assert!((knots[k] - 2.0 * k as f32 / (s * s)).abs() < 1e-6, "{}", knots[k]);
        assert!(knots[k + 1] > 1.0 / s, "{}", knots[k + 1]);
    }
}
