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
//! `∫ n = N` gives `n ∝ q` for any power `s`. The error a pixel adds also grows with the
//! irradiance E it shows, and `∫ q·E²·(q/n)^s` is least at `n ∝ q·E^(2/(1+s))`: the survey
//! weighs each pixel by the light its receiver can expect (`receiver_weight`, to the power
//! `BRIGHTNESS_POWER`, which is measured). A pixel's godray sums the beams its view ray
//! crosses, so the beams follow the length of view ray through the water above where they
//! enter.
//!
//! How: `view_adapted` casts a grid of camera rays against the scene's triangles (each ray
//! stands for the same number of pixels), over the view and a tenth past its edges for the
//! caustics (`SURVEY_MARGIN`). It takes every receiver a ray meets under the water
//! back up the refracted light to where its photons enter the water (through flat water), and
//! counts the rays whose receiver the light reaches on the side the camera sees
//! (`lit_through_flat_water`: a receiver in shadow shows no caustic, and the photons cast
//! towards it light something else or nothing) in a `SEGMENTS`² histogram over the photon
//! window, each weighed by the light its receiver can expect (`receiver_weight`); for the
//! beams, it adds the length of each step along the ray's underwater part above the step.
//! Near a cell's border a weight is shared with the cell across it (`deposit`), so that the
//! warp moves no more than the camera does.
//! Blurred (`BLUR`: the waves bend photons sideways) and floored at `FLOOR` of the mean
//! (`FOOTPRINT_FLOOR` for the footprint points' histogram; so that receivers no ray met still
//! get photons), each histogram is a piecewise-constant density.
//! The warp is its inverse cumulative distribution: the window's v from the rows' marginal,
//! the window's u from each row's conditional, interpolated between rows so that the mesh
//! stays continuous; or, for the caustic triangles where that makes their cells squarer on
//! screen, the same with u and v exchanged (`shaped_for_the_mesh`). `cast_photon`
//! (photon_cast.glsl, twin `shader_math::photon_density_warp`) maps its grid position through
//! it and scales the photon's flux by its warped cell's area over the even cell's: a photon
//! carries the light through its own cell, however large.
//!
//! The warps depend on the camera and the light, not the time, so the frame computes them
//! when either moves (`Frame::record`), not every frame.

use crate::bvh::Bvh;
use crate::scene::Scene;
use crate::shader_abi::{FrameUniforms, PHOTON_DENSITY_KNOTS as KNOTS, PHOTON_DENSITY_SEGMENTS as SEGMENTS};
use glam::{DVec2, DVec3, Mat4, Vec2, Vec3, Vec4};

/// Camera rays per axis of the survey (x, y), over the view widened by `SURVEY_MARGIN`: each
/// stands for a 1/4000 share of the view's pixels. With the beams' steps and the lit test, a
/// survey took 9–16 ms on one core of the 2-core machine with 80 × 50 rays over the view alone
/// (the built-in scenes at 320×200, release build; `render` prints it), whenever the camera or
/// the light moves. The margin's rays add 5–10 % (they count no beams): three runs each, tank
/// 8.9–9.3 → 9.3–10.2 ms, port 10.4–12.6 → 11.6–12.8, storage 10.9–13.9 → 11.9–13.3.
const RAYS: [usize; 2] = [88, 55];
/// How far past the view's edges the survey's rays reach, as a share of the view's half-width
/// and half-height. The blur (`BLUR`) spreads each histogram cell's count over its neighbours,
/// and the cells beyond the view's edges got no rays: at the edges the blur diluted the
/// density, and those are where a slanted view's nearest receivers lie, with the most pixels
/// per square metre. There a caustic's sharp focus was drawn across cells several pixels wide:
/// the tank's near corner at t = 3 s held 42 % of its frame's squared error, and four times
/// the photons did not mend it. With the rays reaching a tenth past the edges (and receivers
/// there, whose light the waves bend into the view, counted too), the tank's caustic relative
/// RMSE at 320×200 over t = 1–5 s went 0.307–0.402 (mean 0.341) → 0.325–0.342 (0.336)
/// (docs/accuracy.md, "The survey past the view's edges").
const SURVEY_MARGIN: f32 = 0.1;
/// Passes of a 3×3 box blur over the histogram. The blur stands for the waves, which bend a
/// photon sideways from where flat water would take it, and it keeps the warp smooth: the
/// survey's counts are a few per cell, and a warp that follows their noise gives a mesh of
/// uneven cells (31² cells, 2400 rays, 320×200, caustic rel. RMSE tank / port / storage:
/// one pass 0.403 / 0.440 / 0.516, two 0.357 / 0.373 / 0.493, three 0.331 / 0.365 / 0.473).
const BLUR: usize = 3;
/// The least density, as a share of the mean: receivers between the rays, and light the waves
/// bend in from outside the view, keep some photons. For the triangles at 320×200, 0.05, 0.15
/// and 0.3 measured alike (within 0.015 on every scene); 0.15 lost the least flux on the port.
/// The godray beams keep it too.
const FLOOR: f64 = 0.15;
/// The floor for the footprint points, whose hats span the gaps between photons wherever the
/// survey's few rays left the density low: 0.3 reads lower than 0.15 at 320×200 and at the
/// scenes' own sizes on all three scenes, 0.05 and 0.45 higher (caustic relative RMSE, t = 1 s,
/// tank / port / storage, own sizes against 512M-photon references: 0.05 0.407 / 0.645 /
/// 0.619, 0.15 0.374 / 0.610 / 0.573, 0.3 0.345 / 0.592 / 0.553, 0.45 0.344 / 0.592 / 0.650;
/// docs/accuracy.md, "The survey's floor for the footprint points").
const FOOTPRINT_FLOOR: f64 = 0.3;
/// The power of a receiver's expected irradiance in its survey weight (`receiver_weight`).
/// The module's derivation with each pixel's error scaled by the irradiance E it shows: the
/// summed squared error `∫ q·E²·(q/n)^s` is least at `n ∝ q·E^(2/(1+s))`, so photons should
/// favour the receivers the light meets head-on over those it grazes. Measured at 320×200,
/// caustic relative RMSE of tank / port / storage, the mean over t = 1–5 s: 0 (pixels alone)
/// 0.441 / 0.490 / 0.468, 0.5 0.404 / 0.487 / 0.453, 0.667 0.403 / 0.489 / 0.459, 1 0.396 /
/// 0.483 / 0.454; at t = 1 s 1.5 and 2 read 0.391 and 0.397 on the tank against 0.347 at 1.
/// 0.5, not 1: at 1 the grazed back wall of the tank at 800×800 shows its sparser mesh as
/// steps, and the pixels left dark where the reference lights them and all their neighbours
/// rise from 1.2 % to 1.8 % (1.3 % at 0.5; docs/accuracy.md, "Photons by the light their
/// receivers get").
const BRIGHTNESS_POWER: f64 = 0.5;
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
    /// k of the caustic triangles' coarse grid, N/k columns by N·k rows
    /// (`FrameUniforms::caustic_grid_aspect`; `CellShapes::grid_aspect`); 1 for the beams and
    /// the even grid.
    pub grid_aspect: f32,
    /// The window's u and v exchange roles (`FrameUniforms::photon_density_warp` = 2): `rows`
    /// gives the window's u at grid u, `columns` its v per band of u (`shaped_for_the_mesh`).
    pub exchanged: bool,
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
        PhotonDensity { rows, columns: [rows; SEGMENTS], grid_aspect: 1.0, exchanged: false }
    };

    /// `FrameUniforms::photon_density_warp` (and `godray_density_warp`) for this warp.
    pub fn warp_mode(&self) -> f32 {
        if self.exchanged {
            2.0
        } else {
            1.0
        }
    }

    /// Grid position `g` to the photon window's uv, and the warped cell's area over the even
    /// grid's (`half_cell` each side of `g`): `shader_math::photon_density_warp` of this warp.
    pub fn warp(&self, g: Vec2, half_cell: Vec2) -> (Vec2, f32) {
        crate::shader_math::photon_density_warp(&self.rows, &self.columns_flat(), self.exchanged, g, half_cell)
    }

    /// Sets the frame's uniforms to warp the caustic photons by this density.
    pub fn apply_to_caustics(&self, u: &mut FrameUniforms) {
        u.photon_density_warp = self.warp_mode();
        u.caustic_grid_aspect = self.grid_aspect;
        u.photon_density_rows = self.rows;
        u.photon_density_columns = self.columns_flat();
    }

    /// Sets the frame's uniforms to warp the godray beams by this density.
    pub fn apply_to_godrays(&self, u: &mut FrameUniforms) {
        u.godray_density_warp = self.warp_mode();
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
        PhotonDensity { rows: inverse_cumulative(&marginal), columns, grid_aspect: 1.0, exchanged: false }
    }

    /// The same with the window's u and v exchanged: `rows` from the marginal of u, `columns`
    /// from the conditional of v in each band of u.
    fn from_histogram_exchanged(h: &[[f64; SEGMENTS]; SEGMENTS]) -> Self {
        PhotonDensity { exchanged: true, ..Self::from_histogram(&transposed(h)) }
    }

    /// The warp's derivatives at window position `w` (rows first): d(window u)/d(grid u),
    /// d(window v)/d(grid v), and the shear d(window u)/d(grid v) that the interpolation between
    /// the bands of v adds where neighbouring bands differ. The mesh cell's edges there are
    /// the grid's spacings times these; they follow the histogram only as finely as the knots
    /// do, which in the sparse parts of the window is coarser than the bands.
    fn derivatives_at(&self, w: Vec2) -> WarpDerivatives {
        let s = SEGMENTS as f64;
        // The segment of a piecewise-linear increasing function (values at k / SEGMENTS) that
        // holds x: its index, x's share of it, and its slope.
        let segment = |at: &dyn Fn(usize) -> f64, x: f64| {
            let k = (1..SEGMENTS).take_while(|&k| at(k) <= x).last().unwrap_or(0);
            let rise = at(k + 1) - at(k);
            let t = if rise > 0.0 { ((x - at(k)) / rise).clamp(0.0, 1.0) } else { 0.0 };
            (k, t, rise * s)
        };
        let v = w.y as f64;
        let (_, _, v_slope) = segment(&|k| self.rows[k] as f64, v);
        let unclamped = v * s - 0.5;
        let band = unclamped.clamp(0.0, s - 1.0);
        let j = (band as usize).min(SEGMENTS - 2);
        let f = band - j as f64;
        let (a, b) = (&self.columns[j], &self.columns[j + 1]);
        let at = |c: &[f32; KNOTS], k: usize| c[k] as f64;
        let (k, t, u_slope) = segment(&|k| at(a, k) + (at(b, k) - at(a, k)) * f, w.x as f64);
        // d(window u)/d(window v) at fixed grid u: the two bands' knots, interpolated at the
        // photon's grid u, over the band's width (none where the band is held at the edges).
        let between = |c: &[f32; KNOTS]| at(c, k) + (at(c, k + 1) - at(c, k)) * t;
        let du_dv = if unclamped == band { (between(b) - between(a)) * s } else { 0.0 };
        WarpDerivatives { u_by_grid_u: u_slope, v_by_grid_v: v_slope, u_by_grid_v: du_dv * v_slope }
    }

    /// The warp's densest cell against its mean: how much finer the mesh is there than the
    /// even grid's (by area).
    pub fn peak_density(&self) -> f32 {
        let (mut peak, columns) = (0.0f32, self.columns_flat());
        for j in 0..SEGMENTS {
            for k in 0..SEGMENTS {
                let g = Vec2::new((k as f32 + 0.5) / SEGMENTS as f32, (j as f32 + 0.5) / SEGMENTS as f32);
                let (_, jacobian) = crate::shader_math::photon_density_warp(
                    &self.rows,
                    &columns,
                    self.exchanged,
                    g,
                    Vec2::splat(0.5 / SEGMENTS as f32),
                );
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
/// to survey; the even grid then. `previous`: the last survey's, whose caustic grid aspect the
/// new one keeps unless the view has moved well away from it (`grid_aspect_level`).
pub fn view_adapted(
    scene: &Scene,
    bounds: (Vec3, Vec3),
    bvh: &Bvh,
    u: &FrameUniforms,
    previous: Option<&ViewDensities>,
) -> ViewDensities {
    let none = ViewDensities { caustics: None, godrays: None };
    let inv = Mat4::from_cols_array_2d(&u.camera_inv_view_proj);
    let light = Mat4::from_cols_array_2d(&u.light_view_proj);
    let (window_min, window_size) = (Vec2::from(u.photon_window_min), Vec2::from(u.photon_window_size));
    if !(window_size.x > 0.0 && window_size.y > 0.0) {
        return none;
    }
    // Where in the photon window the photons enter the water that reach underwater point p
    // (through flat water), and that place's histogram cell.
    let window_uv = |p: DVec3| -> Option<Vec2> {
        let entry = super::uniforms::photon_entry(scene, p.as_vec3());
        let clip = light * entry.extend(1.0);
        if !(clip.w > 1e-6) {
            return None;
        }
        let uv = (Vec2::new(clip.x, clip.y) / clip.w * 0.5 + 0.5 - window_min) / window_size;
        (uv.x >= 0.0 && uv.y >= 0.0 && uv.x < 1.0 && uv.y < 1.0).then_some(uv)
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
    // Where each survey ray's receiver takes its photons from, row after row
    // (`CellShapes::survey`).
    let mut receiver_uv = [None; RAYS[0] * RAYS[1]];
    let mut crossings = [[0.0f64; SEGMENTS]; SEGMENTS];
    let (mut landed, mut crossed) = (0usize, 0usize);
    for y in 0..RAYS[1] {
        for x in 0..RAYS[0] {
            let ndc = (1.0 + SURVEY_MARGIN)
                * Vec2::new(
                    (x as f32 + 0.5) / RAYS[0] as f32 * 2.0 - 1.0,
                    (y as f32 + 0.5) / RAYS[1] as f32 * 2.0 - 1.0,
                );
            let far = inv * Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
            let far = (far.truncate() / far.w).as_dvec3();
            let Some(ray) = underwater_ray(bvh, camera, far, level, w.ior as f64, (box_lo, box_hi)) else {
                continue;
            };
            if let Some(t) = ray.hit {
                let receiver = ray.origin + ray.direction * t;
                // The receiver's side that the camera sees.
                let seen_side = if ray.normal.dot(ray.direction) > 0.0 { -ray.normal } else { ray.normal };
                if let Some(uv) = window_uv(receiver)
                    .filter(|_| lit_through_flat_water(scene, bvh, receiver, seen_side, (box_lo, box_hi)))
                {
                    deposit(&mut receivers, uv, receiver_weight(scene, receiver, ray.normal));
                    receiver_uv[y * RAYS[0] + x] = Some(uv);
                    landed += 1;
                }
            }
            // The beams follow the view's own rays only. Counted for the beams too, the rays
            // past the edges gained nothing: the port's godray error at the output, mean over
            // t = 1–5 s, read 0.055 with them and 0.054 without (0.052 before the margin).
            if ndc.abs().max_element() > 1.0 {
                continue;
            }
            let ds = ray.length / BEAM_STEPS as f64;
            for k in 0..BEAM_STEPS {
                let p = ray.origin + ray.direction * ((k as f64 + 0.5) * ds);
                if let Some(uv) = (p.y < level).then(|| window_uv(p)).flatten() {
                    deposit(&mut crossings, uv, ds);
                    crossed += 1;
                }
            }
        }
    }
    let output = Vec2::from(u.output_size);
    // Pixels between neighbouring rays (the margin's rays lie as far apart).
    let ray_step = (output * (1.0 + SURVEY_MARGIN) / Vec2::new(RAYS[0] as f32, RAYS[1] as f32)).as_dvec2();
    ViewDensities {
        caustics: (landed >= MIN_RAYS).then(|| {
            let floor = match scene.effects.caustic_estimator {
                crate::scene::CausticEstimator::Footprint => FOOTPRINT_FLOOR,
                _ => FLOOR,
            };
            let density = survey_density(receivers, floor);
            let shaped = || shaped_for_the_mesh(&density, &receiver_uv, ray_step, previous.and_then(|p| p.caustics));
            match scene.effects.caustic_estimator {
                // The triangles' mesh cells want a shaped grid: its aspect and the warp's order.
                crate::scene::CausticEstimator::Triangles => shaped(),
                // The footprint points take the warp's order alone (their geometry shader casts
                // the square grid): their cells, too, come out long and thin where the view
                // wants photons along one axis of the window, and the storage's grazed crates
                // read 0.275 → 0.234 at 320×200, 0.827 → 0.731 at 1440×850 with it; the shaped
                // grid's aspect took the port from 0.233 to 0.242 (docs/accuracy.md, "The
                // footprint points' warp order").
                crate::scene::CausticEstimator::Footprint => PhotonDensity { grid_aspect: 1.0, ..shaped() },
                // The paper's points keep the square grid and the rows-first warp.
                crate::scene::CausticEstimator::Paper => PhotonDensity::from_histogram(&density),
            }
        }),
        godrays: (crossed >= MIN_RAYS).then(|| PhotonDensity::from_histogram(&survey_density(crossings, FLOOR))),
    }
}

/// A survey ray's weight in the caustic histogram: the irradiance its receiver point `p`
/// (geometric normal `normal`, either side) can expect from the light, relative to a receiver
/// facing the light at the surface, to the power `BRIGHTNESS_POWER`. That is the cosine
/// between the normal and the way to where its photons enter the water, times the water's
/// transmittance along that way (the mean of the channels), as flat water would bring the
/// light; the caustic the waves make scales with it. Bounded below so that a receiver edge-on
/// to the light keeps a share (the histogram's floor keeps more).
fn receiver_weight(scene: &Scene, p: DVec3, normal: DVec3) -> f64 {
    let entry = super::uniforms::photon_entry(scene, p.as_vec3()).as_dvec3();
    let to_entry = entry - p;
    let path = to_entry.length();
    let cos = if path > 1e-9 { normal.dot(to_entry / path).abs() } else { normal.y.abs() };
    let gamma = scene.medium.gamma.as_dvec3();
    let transmittance = (-(gamma.x + gamma.y + gamma.z) / 3.0 * path).exp();
    (cos * transmittance).clamp(1e-3, 1.0).powf(BRIGHTNESS_POWER)
}

/// Whether the light reaches underwater receiver point `p` through flat water on its side
/// `seen_side` (the unit normal towards the camera): that side faces where its photons enter
/// the water (`photon_entry`), and nothing lies between `p` and there, nor between there and
/// the light. A pixel that sees a receiver in shadow sees no caustic, and the photons cast
/// towards it are blocked before the water (a deck, a roof) or land on what casts the shadow.
/// Counted, such pixels drew photons that light nothing the camera sees, or too many onto
/// what casts the shadow: on the port 18 % of the caustic photons were blocked before the
/// water (9 % since). Not counted, the caustic error at 320×200 fell by 7.5 %, 1.4 % and
/// 6.2 % on the tank, the port and the storage (the mean over t = 1–5 s; docs/accuracy.md,
/// "Photons for lit receivers only"). The waves bend some light into the shadow's edge; the
/// histogram's blur keeps photons there.
///
/// The side is tested first. A receiver that turns its seen side away from the light (the
/// tank's back wall, which the sun lights from behind) is in its own shadow, and the occlusion
/// test alone decided that by rounding: its ray left along or into the receiver's own plane. A
/// camera moved by a micrometre flipped 203 of the tank's 3 250 counted rays, all on that wall,
/// and moved the warp's knots by 1.4 % of the photon window in the median step (2e-5 since,
/// with `deposit`; docs/accuracy.md, "The survey and a camera that moves a hair"). Light that
/// grazes the side (cosine below `GRAZING`) counts as away from it.
fn lit_through_flat_water(scene: &Scene, bvh: &Bvh, p: DVec3, seen_side: DVec3, bounds: (DVec3, DVec3)) -> bool {
    const SELF_HIT: f64 = 1e-4; // m: leaves the receiver's own triangle (hits are f64)
    let entry = super::uniforms::photon_entry(scene, p.as_vec3()).as_dvec3();
    let below = entry - p;
    let depth = below.length();
    if depth > SELF_HIT && seen_side.dot(below) <= GRAZING * depth {
        return false;
    }
    if depth > SELF_HIT && bvh.occluded(p, below / depth, SELF_HIT, depth) {
        return false;
    }
    let (to_light, reach) = match scene.light.kind {
        crate::scene::LightKind::Directional => {
            let d = -scene.light.direction.normalize().as_dvec3();
            let exit =
                super::uniforms::ray_box_exit(entry.as_vec3(), d.as_vec3(), bounds.0.as_vec3(), bounds.1.as_vec3());
            (d, exit as f64)
        }
        crate::scene::LightKind::Point => {
            let d = scene.light.position.as_dvec3() - entry;
            (d.normalize_or_zero(), d.length())
        }
    };
    !(to_light.length_squared() > 0.5 && reach > SELF_HIT && bvh.occluded(entry, to_light, SELF_HIT, reach))
}

/// The cosine between a receiver's seen side and the way to its light below which the survey
/// counts it as unlit (`lit_through_flat_water`), so that a wall the light runs along is
/// decided by this bound, not by the sign of a rounding error; `receiver_weight` gives such a
/// receiver its floor.
const GRAZING: f64 = 1e-3;

/// Adds `weight` at window position `uv` ∈ [0, 1)² to histogram `h` (`[v band][u band]`): to
/// the cell it falls in, and within `DEPOSIT_RAMP` / 2 of the cell's border a share to the
/// cell across it, which grows linearly to a half at the border (along both axes, so up to
/// four cells). Whole into one cell, a ray's weight jumped a cell whenever its receiver
/// crossed a border, and the warp's knots with it; shared so, they move with the camera by
/// as little as it moves.
fn deposit(h: &mut [[f64; SEGMENTS]; SEGMENTS], uv: Vec2, weight: f64) {
    // Along one axis: the cell `x` falls in, the neighbour across its nearer border (itself at
    // the window's edges), and the neighbour's share.
    let split = |x: f32| -> (usize, usize, f64) {
        let at = x as f64 * SEGMENTS as f64;
        let cell = (at.max(0.0) as usize).min(SEGMENTS - 1);
        let f = at - cell as f64;
        let (neighbour, share) = if f < 0.5 {
            (cell.checked_sub(1), (0.5 - f / DEPOSIT_RAMP).clamp(0.0, 0.5))
        } else {
            ((cell + 1 < SEGMENTS).then_some(cell + 1), (0.5 - (1.0 - f) / DEPOSIT_RAMP).clamp(0.0, 0.5))
        };
        neighbour.map_or((cell, cell, 0.0), |n| (cell, n, share))
    };
    let ((i, next_i, share_i), (j, next_j, share_j)) = (split(uv.x), split(uv.y));
    h[j][i] += weight * (1.0 - share_i) * (1.0 - share_j);
    h[j][next_i] += weight * share_i * (1.0 - share_j);
    h[next_j][i] += weight * (1.0 - share_i) * share_j;
    h[next_j][next_i] += weight * share_i * share_j;
}

/// The width, in cells, of the band about each histogram border over which a ray's weight
/// passes from one cell to the next (`deposit`). 1 shares it bilinearly among the four cells
/// whose centres surround it, which blurs the histogram by a little more: the caustic relative
/// RMSE at 320×200, the mean over t = 1–5 s, read 0.338 / 0.441 / 0.386 (tank, port, storage)
/// and the port's worst time 0.453, above its target; at 0.25 0.335 / 0.440 / 0.383, and
/// 0.336 / 0.437 / 0.382 with the weight whole in one cell (0.336 / 0.440 / 0.380 before the
/// side test of `lit_through_flat_water`): within the figures' noise. A 0.1 mm step of the
/// camera changed the tank's caustic buffer by 22 % of its mean before either (RMS, the median
/// of eight steps), 9.0 % with the side test alone, 5.9 % with this at 0.25 and 5.8 % at 1
/// (docs/accuracy.md, "The survey and a camera that moves a hair").
const DEPOSIT_RAMP: f64 = 0.25;

/// The largest k either way (`CellShapes::grid_aspect`): N/2 × 2N coarse cells.
const GRID_ASPECT_MAX: f32 = 2.0;
/// The least k either way that leaves the square grid (`grid_aspect_level`). Any other grid
/// moves every photon, and a near-square estimate is noise: the tank's reads 1.07 or 0.92
/// depending on which receivers the survey counts, and a grid of 2^(−1/4) read worse than the
/// square there (docs/accuracy.md, "The grid's aspect in levels").
const GRID_ASPECT_MIN: f32 = 1.25;
/// The grid aspects the survey chooses among beyond `GRID_ASPECT_MIN` (`grid_aspect_level`):
/// a quarter octave apart, up to `GRID_ASPECT_MAX` either way.
const GRID_ASPECT_LEVELS_PER_OCTAVE: f32 = 4.0;
/// How far past the boundary between two levels the estimate must move, in quarter octaves,
/// before the grid leaves the level the previous survey chose (`grid_aspect_level`).
const GRID_ASPECT_HYSTERESIS: f32 = 0.25;
/// The screen's part of a survey ray's L_v / L_u counts as at most 16 either way
/// (`CellShapes::survey`): neighbours on two receivers give steps of no meaning, and unbounded
/// they would rule the mean. The warp's part is not bounded (`CellShapes::survey`).
const OUTLIER_LOG_RATIO: f64 = 2.772_588_722_239_781; // ln 16

/// The caustic triangles' warp of `density`: in the order whose mesh cells come out squarer
/// on screen (`CellShapes::misfit`), rows first (the window's v from its marginal, u from
/// each band's conditional) or with u and v exchanged, and with the grid aspect that order
/// wants (`grid_aspect_level`). `previous`: the last survey's warp, whose order is kept
/// unless the other fits better by `WARP_ORDER_SWITCH`.
///
/// Why the order: the rows are straight lines across the whole window, so their spacing is
/// the marginal's, the same for every u along a band. Where a band holds both a receiver that
/// wants many photons (the floor under the camera) and one that wants few per window area
/// along v but many along u, the latter's cells come out long and thin. On the storage the
/// crates by the far wall, which the light grazes, are a 20 cm strip of the window along u:
/// rows first gave them a column of photons about every 36 cm, and they stayed dark
/// (docs/accuracy.md, "The warp's order").
fn shaped_for_the_mesh(
    density: &[[f64; SEGMENTS]; SEGMENTS],
    receiver_uv: &[Option<Vec2>; RAYS[0] * RAYS[1]],
    ray_step: DVec2,
    previous: Option<PhotonDensity>,
) -> PhotonDensity {
    let exchanged_uv = receiver_uv.map(|uv| uv.map(|w| Vec2::new(w.y, w.x)));
    let exchanged_density = transposed(density);
    // Per order: the grid aspect in its own frame (for the exchanged order, that of the grid
    // with u and v exchanged, whose inverse the frame uses) and how far its cells stay from
    // square with it.
    let fit = |exchanged: bool| {
        let shapes = if exchanged {
            CellShapes::survey(&exchanged_density, &exchanged_uv, ray_step)
        } else {
            CellShapes::survey(density, receiver_uv, ray_step)
        };
        let previous_k = previous.filter(|p| p.exchanged == exchanged).map(|p| {
            if exchanged {
                1.0 / p.grid_aspect
            } else {
                p.grid_aspect
            }
        });
        shapes.map(|s| {
            let k = grid_aspect_level(s.grid_aspect(), previous_k);
            (k, s.misfit(k))
        })
    };
    let (rows_first, exchanged) = (fit(false), fit(true));
    // Rows first unless the other order fits better by WARP_ORDER_SWITCH, and the same from
    // an exchanged previous warp.
    let choose_exchanged = match (rows_first, exchanged) {
        (Some((_, rows_misfit)), Some((_, exchanged_misfit))) => {
            if previous.is_some_and(|p| p.exchanged) {
                !(rows_misfit < WARP_ORDER_SWITCH * exchanged_misfit)
            } else {
                exchanged_misfit < WARP_ORDER_SWITCH * rows_misfit
            }
        }
        _ => false,
    };
    if choose_exchanged {
        let k = exchanged.map_or(1.0, |(k, _)| k);
        PhotonDensity { grid_aspect: 1.0 / k, ..PhotonDensity::from_histogram_exchanged(density) }
    } else {
        let k = rows_first.map_or(1.0, |(k, _)| k);
        PhotonDensity { grid_aspect: k, ..PhotonDensity::from_histogram(density) }
    }
}

/// How much better the other order's cells must fit (`CellShapes::misfit`) than those of the
/// previous survey's order, rows first for the first survey, before the warp changes order
/// (`shaped_for_the_mesh`). A change moves every photon, so an order kept while the camera
/// moves re-samples the caustic only when it pays. Where the two fit about alike, as on the
/// tank (1.03 rows first against 1.04 exchanged at 320×200, 1.18 against 1.25 at 800×800),
/// neither reads better against the reference; the storage's exchanged order fits at 0.75
/// of the rows-first one's misfit and lowers its error (docs/accuracy.md, "The warp's order").
const WARP_ORDER_SWITCH: f64 = 0.85;

/// The survey rays' estimate of the shape of the mesh's cells on screen, for one order of the
/// warp (`shaped_for_the_mesh`): the sum and the sum of squares of ln(L_v / L_u) over the rays,
/// L_u and L_v a cell's edges along the window's u and v on screen.
///
/// Why: the grid is N × N over the photon window and the warp spreads each axis by itself, so
/// nothing made a cell square where the camera sees it. With photons in proportion to the
/// pixels, each axis's spacing on screen is about the screen's size along it over N, scaled by
/// the shape of the region the view takes its photons from: the storage's corridor, narrow
/// across the window and long along it, had cells 2.2× longer along v than along u on average
/// (docs/accuracy.md, "The photon grid's aspect on screen"); N/k × N·k with k = √2.2 lowered
/// its caustic error by 9 % for the same photons.
///
/// How: for each survey ray whose two neighbours (across and down the screen) also reached a
/// receiver, the three entry points give the screen's step per window step (the inverse of
/// their differences, in pixels); the warp's derivatives there (`PhotonDensity::
/// derivatives_at`, the warp of `density`, rows first: along each axis, and the shear of u
/// along grid v) over N turn them into a mesh cell's two edges on screen. The screen's part is
/// held within 1/16 and 16 (`OUTLIER_LOG_RATIO`).
#[derive(Clone, Copy, Debug)]
struct CellShapes {
    rays: usize,
    log_ratio_sum: f64,
    log_ratio_squares: f64,
}

impl CellShapes {
    /// `None` where fewer than `MIN_RAYS` rays have both neighbours on receivers.
    fn survey(
        density: &[[f64; SEGMENTS]; SEGMENTS],
        receiver_uv: &[Option<Vec2>; RAYS[0] * RAYS[1]],
        ray_step: DVec2,
    ) -> Option<CellShapes> {
        let warp = PhotonDensity::from_histogram(density);
        let mut shapes = CellShapes { rays: 0, log_ratio_sum: 0.0, log_ratio_squares: 0.0 };
        for y in 0..RAYS[1] - 1 {
            for x in 0..RAYS[0] - 1 {
                let at = y * RAYS[0] + x;
                let (Some(w), Some(across), Some(down)) =
                    (receiver_uv[at], receiver_uv[at + 1], receiver_uv[at + RAYS[0]])
                else {
                    continue;
                };
                // The window's displacement per pixel across the screen (a) and down it (b):
                // the columns of d(window)/d(screen). Its inverse's columns are the screen's
                // displacement per unit of window u and of window v.
                let a = (across - w).as_dvec2() / ray_step.x;
                let b = (down - w).as_dvec2() / ray_step.y;
                let det = a.x * b.y - a.y * b.x;
                if !(det.abs() > 1e-18) {
                    continue;
                }
                let per_u = DVec2::new(b.y, -a.y) / det;
                let per_v = DVec2::new(-b.x, a.x) / det;
                // The screen's part held within its bounds (per_v rescaled so that its length
                // over per_u's stays within them); the warp's part is its own, unbounded:
                // bounding it hid how long the rows-first warp's cells grow where a band is
                // shared.
                let screen_ratio = per_v.length() / per_u.length();
                if !(screen_ratio.is_finite() && screen_ratio > 0.0) {
                    continue;
                }
                let bound = OUTLIER_LOG_RATIO.exp();
                let per_v = per_v * (screen_ratio.clamp(1.0 / bound, bound) / screen_ratio);
                // A mesh cell's edges on screen, per unit of grid u and of grid v.
                let d = warp.derivatives_at(w);
                let edge_u = per_u * d.u_by_grid_u;
                let edge_v = per_u * d.u_by_grid_v + per_v * d.v_by_grid_v;
                let ratio = edge_v.length() / edge_u.length();
                if ratio.is_finite() && ratio > 0.0 {
                    let log_ratio = ratio.ln();
                    shapes.log_ratio_sum += log_ratio;
                    shapes.log_ratio_squares += log_ratio * log_ratio;
                    shapes.rays += 1;
                }
            }
        }
        (shapes.rays >= MIN_RAYS).then_some(shapes)
    }

    /// k for the caustic triangles' coarse grid of N/k × N·k cells (`FrameUniforms::
    /// caustic_grid_aspect`, before `grid_aspect_level`): the one that makes their mesh cells
    /// square on screen on average, √ of the geometric mean of L_v / L_u over the rays. The
    /// geometric mean, because that is what the cells' measured edges gave: the recorded
    /// photons' mean cell reads k = 1.11, 0.83 and 1.48 on the tank, the port and the storage,
    /// this estimate from the histogram's densities 1.07, 0.86 and 1.47 (the median of the
    /// ratios 0.95, 0.78 and 1.51). From the warp's derivatives, as since the warp's order, it
    /// reads 1.00, 0.80 and 1.31 at 320×200 (the pixels weigh alike, where the recorded cells
    /// weigh by photon), and the levels stay the square, 0.8 and 1.25.
    fn grid_aspect(&self) -> f32 {
        let mean = self.log_ratio_sum / self.rays as f64;
        ((0.5 * mean).exp() as f32).clamp(1.0 / GRID_ASPECT_MAX, GRID_ASPECT_MAX)
    }

    /// How far the cells stay from square with grid aspect k: the mean over the rays of
    /// (ln(L_v / L_u) − 2 ln k)², the spread of the shapes that no one k removes, plus what
    /// the levels and their bounds leave of the mean.
    fn misfit(&self, k: f32) -> f64 {
        let n = self.rays as f64;
        let c = 2.0 * (k as f64).ln();
        self.log_ratio_squares / n - 2.0 * c * self.log_ratio_sum / n + c * c
    }
}

/// The grid aspect the frame uses for the estimate `k` (`CellShapes::grid_aspect`): the square
/// grid for k within `GRID_ASPECT_MIN` either way; beyond it, `GRID_ASPECT_MIN` times the
/// nearest whole number of quarter octaves (1.25, 1.49, 1.77, then `GRID_ASPECT_MAX`, and their
/// inverses); and the `previous` survey's level while one within `GRID_ASPECT_HYSTERESIS` of a
/// level of `k` would still choose it.
///
/// Why levels: the grid has round(N / k) columns, and each change of k that changes them
/// moves every photon by up to a cell, so while the viewer's camera moves, a k that followed
/// the estimate re-sampled the whole caustic at every survey (every `PHOTON_SURVEY_INTERVAL`
/// frames). Why the hysteresis: an estimate on a boundary (the port's 0.795 lies 0.03 of a
/// level past 1 / 1.25) would flip between two grids as the camera moves.
fn grid_aspect_level(k: f32, previous: Option<f32>) -> f32 {
    // In quarter octaves (x = 4·log2 k).
    let steps = GRID_ASPECT_LEVELS_PER_OCTAVE;
    let top = GRID_ASPECT_MAX.log2() * steps;
    let square = GRID_ASPECT_MIN.log2() * steps;
    let level_of = |k: f32| (k.log2() * steps).clamp(-top, top);
    let nearest = |x: f32| {
        if x.abs() < square {
            0.0
        } else {
            (x.signum() * (square + (x.abs() - square).round())).clamp(-top, top)
        }
    };
    let x = level_of(k);
    let h = GRID_ASPECT_HYSTERESIS;
    let level = match previous.filter(|p| p.is_finite() && *p > 0.0).map(level_of) {
        Some(p) if [x - h, x, x + h].iter().any(|&y| (nearest(y) - p).abs() < 1e-3) => p,
        _ => nearest(x),
    };
    (level / steps).exp2()
}

/// The density from a survey's histogram: BLUR passes of a 3×3 box over the cells (clamped at
/// the window's border), then `floor` of the mean added to every cell (`FLOOR`,
/// `FOOTPRINT_FLOOR`).
fn survey_density(counts: [[f64; SEGMENTS]; SEGMENTS], floor: f64) -> [[f64; SEGMENTS]; SEGMENTS] {
    let mut density = counts;
    for _ in 0..BLUR {
        density = box_blur(&density);
    }
    let mean = density.iter().flatten().sum::<f64>() / (SEGMENTS * SEGMENTS) as f64;
    for d in density.iter_mut().flatten() {
        *d += floor * mean;
    }
    density
}

/// `PhotonDensity::derivatives_at`: the window's displacement per unit of grid u (along u
/// only) and per unit of grid v (along v, and along u by the shear).
#[derive(Clone, Copy, Debug)]
struct WarpDerivatives {
    u_by_grid_u: f64,
    v_by_grid_v: f64,
    u_by_grid_v: f64,
}

/// The histogram `h` (`[v band][u band]`) with u and v exchanged.
fn transposed(h: &[[f64; SEGMENTS]; SEGMENTS]) -> [[f64; SEGMENTS]; SEGMENTS] {
    let mut t = [[0.0f64; SEGMENTS]; SEGMENTS];
    for (j, row) in h.iter().enumerate() {
        for (i, value) in row.iter().enumerate() {
            t[i][j] = *value;
        }
    }
    t
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
    /// The geometric normal of what the ray meets first (up where it meets nothing).
    normal: DVec3,
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
    let closest = bvh.closest(o, d, 1e-6, reach);
    let first = closest.map(|h| h.t);
    let normal = closest.map(|h| h.normal).unwrap_or(DVec3::Y);
    let length = first.unwrap_or(reach);
    let hit = first.filter(|&t| (o + d * t).y < level);
    (length > 0.0).then_some(UnderwaterRay { origin: o, direction: d, length, hit, normal })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2Swizzles;

    /// The histogram cell (`[v band][u band]`) of window position `uv` ∈ [0, 1)².
    fn histogram_cell(uv: Vec2) -> (usize, usize) {
        let cell = (uv * SEGMENTS as f32).as_uvec2().min(glam::UVec2::splat(SEGMENTS as u32 - 1));
        (cell.y as usize, cell.x as usize)
    }

    #[test]
    fn a_deposit_keeps_its_weight_and_moves_smoothly_across_a_cell_s_border() {
        let histogram = |uv: Vec2| {
            let mut h = [[0.0f64; SEGMENTS]; SEGMENTS];
            deposit(&mut h, uv, 2.0);
            h
        };
        let border = 7.0 / SEGMENTS as f32;
        for uv in [Vec2::new(0.3, 0.6), Vec2::new(0.001, 0.999), Vec2::new(border, 0.5)] {
            let total: f64 = histogram(uv).iter().flatten().sum();
            assert!((total - 2.0).abs() < 1e-12, "{uv}: {total}");
        }
        // Either side of a cell's border the histograms all but agree: 6e-4 of a cell's width
        // moves 0.0025 of the weight (over the ramp of a quarter cell) from one cell to the
        // other, summed as 0.01; whole into the cell it falls in, all of it would jump (4).
        let (before, after) = (histogram(Vec2::new(border - 1e-5, 0.5)), histogram(Vec2::new(border + 1e-5, 0.5)));
        let change: f64 = before.iter().flatten().zip(after.iter().flatten()).map(|(a, b)| (a - b).abs()).sum();
        assert!(change < 0.02, "crossing the border moved {change} of 2");
        // Away from its borders it is all its cell's; at a border, half each side's.
        let inside = histogram(Vec2::new(3.2, 9.8) / SEGMENTS as f32);
        assert!((inside[9][3] - 2.0).abs() < 1e-12, "{}", inside[9][3]);
        let on_border = histogram(Vec2::new(3.0, 9.5) / SEGMENTS as f32);
        assert!(
            (on_border[9][3] - 1.0).abs() < 1e-5 && (on_border[9][2] - 1.0).abs() < 1e-5,
            "{:?}",
            &on_border[9][..5]
        );
    }

    #[test]
    fn the_even_grid_is_the_identity() {
        let even = PhotonDensity::EVEN;
        for g in [Vec2::new(0.013, 0.97), Vec2::new(0.5, 0.5), Vec2::new(0.71, 0.2)] {
            let (w, jacobian) = even.warp(g, Vec2::splat(0.01));
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
        // Either order of the warp (rows first, or u and v exchanged).
        for warp in [PhotonDensity::from_histogram(&h), PhotonDensity::from_histogram_exchanged(&h)] {
            // A grid of photons: the share landing in the dense block, and the sum of their
            // cells' areas (the flux they carry, as a share of the window's).
            let n = 300;
            let (mut inside, mut area) = (0usize, 0.0f64);
            let edge = third as f32 / SEGMENTS as f32;
            for j in 0..n {
                for i in 0..n {
                    let g = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                    let (w, cell) = warp.warp(g, Vec2::splat(0.5 / n as f32));
                    assert!(w.min_element() >= 0.0 && w.max_element() <= 1.0, "{g} → {w}");
                    area += cell as f64 / (n * n) as f64;
                    if w.x < edge && w.y >= 1.0 - edge {
                        inside += 1;
                    }
                }
            }
            // The bands' interpolation blurs one of the block's inner edges by half a band.
            let share = inside as f64 / (n * n) as f64;
            let order = if warp.exchanged { "exchanged" } else { "rows first" };
            assert!(
                (share - expected).abs() < 0.03,
                "{order}: share of photons in the dense block: {share}, not {expected}"
            );
            assert!((area - 1.0).abs() < 0.01, "{order}: the photons' cells cover {area} of the window");
        }
    }

    #[test]
    fn the_exchanged_warp_is_the_mirror_of_the_transposed_density_s() {
        // A density with no symmetry between u and v: the exchanged warp of h must place every
        // photon where the rows-first warp of h's transpose places the mirrored grid position,
        // mirrored, with the same cell area (the twin's exchange of g, the half cell and the
        // result); and the survey must choose mirrored warps for mirrored views (the grid
        // aspect's inversion, the cell shapes' u and v). The histogram's transpose is checked
        // by the dense block of `a_warp_puts_photons_where_the_density_is...`, in either order.
        let mut h = [[0.0f64; SEGMENTS]; SEGMENTS];
        for (j, row) in h.iter_mut().enumerate() {
            for (i, value) in row.iter_mut().enumerate() {
                *value = 0.2 + ((i * 7 + j * 3) % 11) as f64 * (1.0 + i as f64 / 8.0);
            }
        }
        let t = transposed(&h);
        let (exchanged, mirror) = (PhotonDensity::from_histogram_exchanged(&h), PhotonDensity::from_histogram(&t));
        let half_cell = Vec2::new(0.004, 0.0015);
        for g in [Vec2::new(0.013, 0.97), Vec2::new(0.5, 0.5), Vec2::new(0.71, 0.2), Vec2::new(0.33, 0.66)] {
            let (w, cell) = exchanged.warp(g, half_cell);
            let (m, mirror_cell) = mirror.warp(g.yx(), half_cell.yx());
            assert!((w - m.yx()).abs().max_element() < 1e-6, "{g}: {w} against {}", m.yx());
            assert!((cell - mirror_cell).abs() < 1e-5 * cell, "{g}: cell {cell} against {mirror_cell}");
        }
        // The survey of a view and of its mirror: rays over the window's lower left, four times
        // as long across u as down v.
        let survey = |mirrored: bool| {
            let mut uv = [None; RAYS[0] * RAYS[1]];
            for y in 0..RAYS[1] {
                for x in 0..RAYS[0] {
                    let w = Vec2::new(0.05 + 0.8 * x as f32 / RAYS[0] as f32, 0.1 + 0.2 * y as f32 / RAYS[1] as f32);
                    uv[y * RAYS[0] + x] = Some(if mirrored { w.yx() } else { w });
                }
            }
            shaped_for_the_mesh(if mirrored { &t } else { &h }, &uv, DVec2::splat(4.0), None)
        };
        let (view, mirrored) = (survey(false), survey(true));
        eprintln!(
            "view: exchanged {} k {}; mirrored: exchanged {} k {}",
            view.exchanged, view.grid_aspect, mirrored.exchanged, mirrored.grid_aspect
        );
        assert_ne!(view.exchanged, mirrored.exchanged, "mirrored views must choose mirrored orders");
        assert!(
            (view.grid_aspect * mirrored.grid_aspect - 1.0).abs() < 1e-5,
            "{} {}",
            view.grid_aspect,
            mirrored.grid_aspect
        );
    }

    #[test]
    fn the_cell_shapes_read_the_warp_s_own_derivatives() {
        // `derivatives_at` (what the order's choice measures cells by) against finite
        // differences of the twin's warp, shear included, on a density whose bands differ.
        let mut h = [[0.0f64; SEGMENTS]; SEGMENTS];
        for (j, row) in h.iter_mut().enumerate() {
            for (i, value) in row.iter_mut().enumerate() {
                *value = 0.2 + ((i * 5 + j * 3) % 7) as f64 * (1.0 + j as f64 / 6.0);
            }
        }
        let warp = PhotonDensity::from_histogram(&h);
        let (step, half) = (1e-4f32, Vec2::splat(1e-3));
        let mut sheared = 0;
        for g in [Vec2::new(0.21, 0.37), Vec2::new(0.66, 0.52), Vec2::new(0.43, 0.81), Vec2::new(0.9, 0.3)] {
            let w = warp.warp(g, half).0;
            let by_u = (warp.warp(g + Vec2::X * step, half).0 - w) / step;
            let by_v = (warp.warp(g + Vec2::Y * step, half).0 - w) / step;
            let d = warp.derivatives_at(w);
            let close = |a: f64, b: f32| (a - b as f64).abs() < 0.02 * (a.abs() + b.abs() as f64).max(0.05);
            assert!(
                close(d.u_by_grid_u, by_u.x) && by_u.y.abs() < 1e-3,
                "{g}: u by grid u {} against {by_u}",
                d.u_by_grid_u
            );
            assert!(close(d.v_by_grid_v, by_v.y), "{g}: v by grid v {} against {}", d.v_by_grid_v, by_v.y);
            assert!(close(d.u_by_grid_v, by_v.x), "{g}: shear {} against {}", d.u_by_grid_v, by_v.x);
            sheared += (by_v.x.abs() > 0.05) as usize;
        }
        assert!(sheared > 0, "the density's bands should shear the mesh");
    }

    #[test]
    fn the_warp_keeps_its_order_where_the_other_fits_about_as_well() {
        // An even density seen evenly, 2.5× wider on screen than the window region it takes its
        // photons from is tall: both orders make the same cells (their misfits are equal), so
        // the first survey keeps rows first, and a survey after an exchanged one stays
        // exchanged, each with the grid aspect that makes its cells square.
        let even = [[1.0f64; SEGMENTS]; SEGMENTS];
        let mut uv = [None; RAYS[0] * RAYS[1]];
        for y in 0..RAYS[1] {
            for x in 0..RAYS[0] {
                uv[y * RAYS[0] + x] =
                    Some(Vec2::new(0.1 + 0.8 * x as f32 / RAYS[0] as f32, 0.3 + 0.2 * y as f32 / RAYS[1] as f32));
            }
        }
        let step = DVec2::splat(4.0);
        let first = shaped_for_the_mesh(&even, &uv, step, None);
        assert!(!first.exchanged, "the first survey left rows first for an order that fits no better");
        let after_exchanged = shaped_for_the_mesh(&even, &uv, step, Some(PhotonDensity { exchanged: true, ..first }));
        assert!(after_exchanged.exchanged, "an exchanged warp changed order for one that fits no better");
        // The cells' screen edges: 0.8 / 80 of u and 0.2 / 50 of v per 4 px, so L_v / L_u = 2.5
        // on the square grid, and k = √2.5 → the level 1.49. The grid's columns run along the
        // window's u in either order, so the exchanged warp wants the same k.
        let level = GRID_ASPECT_MIN * 2f32.powf(0.25);
        assert!((first.grid_aspect - level).abs() < 1e-4, "rows first: k {}", first.grid_aspect);
        assert!((after_exchanged.grid_aspect - level).abs() < 1e-4, "exchanged: k {}", after_exchanged.grid_aspect);
    }

    #[test]
    fn the_warp_s_order_makes_a_narrow_receiver_s_cells_squarer() {
        // The storage's case in small: the floor under the camera wants many photons over the
        // window's high u, and a wall the light grazes, far off, a strip one band wide along
        // u at low u across the same bands of v. Rows first, the rows follow the floor's
        // marginal and the strip's cells come out long along u. The survey (rays evenly over
        // the window, so that a ray's cell is the window's) must choose the order whose
        // cells, measured through the warp itself, are squarer over the rays, and the strip's
        // with them.
        let mut h = [[0.3f64; SEGMENTS]; SEGMENTS];
        for (j, row) in h.iter_mut().enumerate() {
            for (i, value) in row.iter_mut().enumerate() {
                if i >= SEGMENTS / 2 && (8..24).contains(&j) {
                    *value = 10.0;
                }
                if i == 2 && (10..22).contains(&j) {
                    *value = 6.0;
                }
            }
        }
        // The window stands for the view, and the survey's rays cover it as they cover a view:
        // 4000 of them (80 × 50 in the survey's grid of 88 × 55, the rest past its edges,
        // outside the window). Spread over the window, all 88 × 55 rays put two across the
        // strip instead of three, and the misfits' ratio read 0.876, above WARP_ORDER_SWITCH:
        // a strip one band wide is near what the survey's neighbour differences resolve.
        let in_view = RAYS.map(|n| (n as f32 / (1.0 + SURVEY_MARGIN)).round() as usize);
        let mut uv = [None; RAYS[0] * RAYS[1]];
        for y in 0..RAYS[1] {
            for x in 0..RAYS[0] {
                let w = Vec2::new((x as f32 + 0.5) / in_view[0] as f32, (y as f32 + 0.5) / in_view[1] as f32);
                uv[y * RAYS[0] + x] = (w.x < 1.0 && w.y < 1.0).then_some(w);
            }
        }
        let step = DVec2::splat(4.0);
        // Screen pixels per unit of the window's u and v.
        let screen = Vec2::new(in_view[0] as f32 * 4.0, in_view[1] as f32 * 4.0);
        // ln(L_v / L_u) of each photon's cell on screen, for a warp and its grid of N/k × N·k:
        // over the whole window, and over the strip.
        let cell_shapes = |warp: &PhotonDensity| {
            let n = 120.0f32;
            let spacing = Vec2::new(warp.grid_aspect / n, 1.0 / (n * warp.grid_aspect));
            let (columns, rows) = ((1.0 / spacing.x) as usize, (1.0 / spacing.y) as usize);
            let (mut all, mut strip) = ((0.0f64, 0usize), (0.0f64, 0usize));
            for r in 0..rows {
                for c in 0..columns {
                    let g = Vec2::new((c as f32 + 0.5) * spacing.x, (r as f32 + 0.5) * spacing.y);
                    let at = |g: Vec2| warp.warp(g, spacing * 0.5).0;
                    let w = at(g);
                    let along_u = (at(g + Vec2::X * spacing.x) - w) * screen;
                    let along_v = (at(g + Vec2::Y * spacing.y) - w) * screen;
                    let log_shape = (along_v.length() as f64 / along_u.length() as f64).ln().powi(2);
                    // Each photon weighs by its cell's area: the rays are even over the window.
                    let weight = (along_u.x * along_v.y - along_u.y * along_v.x).abs() as f64;
                    all = (all.0 + weight * log_shape, all.1 + 1);
                    let cell = histogram_cell(w);
                    if cell.1 == 2 && (12..20).contains(&cell.0) {
                        strip = (strip.0 + log_shape, strip.1 + 1);
                    }
                }
            }
            (all.0, strip.0 / strip.1.max(1) as f64)
        };
        let chosen = shaped_for_the_mesh(&h, &uv, step, None);
        let other = {
            let exchanged = !chosen.exchanged;
            let density = if exchanged { transposed(&h) } else { h };
            let rays = if exchanged { uv.map(|w| w.map(|w| w.yx())) } else { uv };
            let k = grid_aspect_level(CellShapes::survey(&density, &rays, step).unwrap().grid_aspect(), None);
            let warp =
                if exchanged { PhotonDensity::from_histogram_exchanged(&h) } else { PhotonDensity::from_histogram(&h) };
            PhotonDensity { grid_aspect: if exchanged { 1.0 / k } else { k }, ..warp }
        };
        let ((chosen_all, chosen_strip), (other_all, other_strip)) = (cell_shapes(&chosen), cell_shapes(&other));
        eprintln!(
            "chosen: exchanged {} k {}: {chosen_all:.3}, strip {chosen_strip:.3}; other: k {}: {other_all:.3}, strip {other_strip:.3}",
            chosen.exchanged, chosen.grid_aspect, other.grid_aspect
        );
        assert!(chosen.exchanged, "the rows-first warp was kept");
        assert!(
            chosen_all < other_all,
            "the chosen order's cells are less square: {chosen_all:.3} against {other_all:.3}"
        );
        assert!(
            chosen_strip < other_strip,
            "the strip's cells are less square: {chosen_strip:.3} against {other_strip:.3}"
        );
    }

    #[test]
    fn receivers_the_light_meets_head_on_and_shallow_weigh_most() {
        let tank = crate::scene::load("tank").unwrap();
        let floor = |depth: f64| DVec3::new(0.2, tank.water.level as f64 - depth, 0.1);
        let up = receiver_weight(&tank, floor(1.0), DVec3::Y);
        let down = receiver_weight(&tank, floor(1.0), DVec3::NEG_Y);
        // Either side of a receiver: the cosine's magnitude.
        assert!((up - down).abs() < 1e-12, "{up} {down}");
        // The refracted sun's cosine on a floor and a metre of the tank's water (γ = 0.13 /m),
        // to the power BRIGHTNESS_POWER.
        let refracted = crate::shader_math::refract(tank.light.direction.normalize(), Vec3::Y, 1.0 / tank.water.ior);
        let path = 1.0 / -refracted.y as f64;
        let expected = (-refracted.y as f64 * (-0.13 * path).exp()).powf(BRIGHTNESS_POWER);
        assert!((up - expected).abs() < 1e-6 * expected, "{up} against {expected}");
        // Deeper: less; a wall the light grazes: much less, but never nothing.
        assert!(receiver_weight(&tank, floor(2.0), DVec3::Y) < up);
        let grazed = refracted.cross(Vec3::Y).normalize().as_dvec3(); // the refracted ray runs along it
        let wall = receiver_weight(&tank, floor(1.0), grazed);
        assert!(wall > 0.0 && wall < 0.1 * up, "{wall} against {up}");
    }

    #[test]
    fn the_grid_aspect_makes_cells_square_on_screen() {
        // Survey rays 4 px apart whose receivers take their photons from a region of the window
        // `wide` across (u) and `tall` down (v), under an even density: the grid's spacing is
        // the same along u and v, so on screen a cell's v edge is wide/tall times its u edge,
        // and k = √(wide/tall) makes it square.
        let even = [[1.0f64; SEGMENTS]; SEGMENTS];
        let aspect = |wide: f32, tall: f32| {
            let mut uv = [None; RAYS[0] * RAYS[1]];
            for y in 0..RAYS[1] {
                for x in 0..RAYS[0] {
                    let (u, v) = (x as f32 / RAYS[0] as f32, y as f32 / RAYS[1] as f32);
                    uv[y * RAYS[0] + x] = Some(Vec2::new(0.2 + wide * u, 0.2 + tall * v));
                }
            }
            CellShapes::survey(&even, &uv, DVec2::splat(4.0)).unwrap()
        };
        // Per ray step: 0.5 / 80 across and 0.1 / 50 down, so L_v / L_u = 3.125.
        let shapes = aspect(0.5, 0.1);
        let k = shapes.grid_aspect();
        assert!((k - 3.125f32.sqrt()).abs() < 1e-3, "k {k}");
        // Every cell has that shape, so k makes them all square, and the square grid leaves
        // them (ln 3.125)² from it.
        assert!(shapes.misfit(k) < 1e-6, "{}", shapes.misfit(k));
        assert!((shapes.misfit(1.0) - 3.125f64.ln().powi(2)).abs() < 1e-3, "{}", shapes.misfit(1.0));
        let aspect = |wide: f32, tall: f32| aspect(wide, tall).grid_aspect();
        let k = aspect(0.1 * 80.0 / 50.0 / 3.125, 0.1);
        assert!((k - 1.0 / 3.125f32.sqrt()).abs() < 1e-3, "k {k}");
        // Past GRID_ASPECT_MAX: held there.
        assert_eq!(aspect(0.8, 0.01), GRID_ASPECT_MAX);
    }

    #[test]
    fn the_grid_aspect_keeps_to_quarter_octaves_and_to_the_previous_level() {
        let level = |k: f32, previous: Option<f32>| grid_aspect_level(k, previous);
        let quarter = |n: f32| GRID_ASPECT_MIN * (n / 4.0).exp2();
        let close = |a: f32, b: f32| (a - b).abs() < 1e-5;
        // Within 1.25 either way, the square; beyond, 1.25 times whole quarter octaves.
        assert_eq!(level(1.2, None), 1.0);
        assert_eq!(level(0.85, None), 1.0);
        assert!(close(level(1.26, None), 1.25));
        assert!(close(level(0.795, None), 0.8), "the port's estimate");
        assert!(close(level(1.38, None), quarter(1.0)), "the storage's estimate");
        assert!(close(level(1.8, None), quarter(2.0)));
        assert_eq!(level(1.95, None), GRID_ASPECT_MAX);
        assert_eq!(level(0.2, None), 1.0 / GRID_ASPECT_MAX);
        // Across a boundary, the previous level holds until a quarter level past it.
        let past = |k: f32, quarters: f32| k * (quarters / 4.0).exp2();
        assert_eq!(level(past(1.25, 0.2), Some(1.0)), 1.0);
        assert!(close(level(past(1.25, 0.3), Some(1.0)), 1.25));
        assert!(close(level(past(1.25, -0.2), Some(1.25)), 1.25));
        assert_eq!(level(past(1.25, -0.3), Some(1.25)), 1.0);
        assert!(close(level(past(quarter(0.5), 0.2), Some(1.25)), 1.25));
        assert!(close(level(past(quarter(0.5), 0.2), None), quarter(1.0)));
        assert!(close(level(past(quarter(0.5), 0.3), Some(1.25)), quarter(1.0)));
        // Far from the previous level, the nearest.
        assert!(close(level(quarter(2.0), Some(1.0)), quarter(2.0)));
        assert!(close(level(1.0, Some(quarter(1.0))), 1.0));
        // Every level is the square, GRID_ASPECT_MAX, or 1.25 times whole quarter octaves.
        for k in [0.5f32, 0.6, 0.77, 0.9, 1.0, 1.1, 1.3, 1.5, 1.9, 2.0] {
            let l = level(k, None);
            let n = (l.max(1.0 / l) / GRID_ASPECT_MIN).log2() * 4.0;
            assert!(l == 1.0 || close(l.max(1.0 / l), GRID_ASPECT_MAX) || (n - n.round()).abs() < 1e-4, "k {k}: {l}");
        }
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
