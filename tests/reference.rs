//! The CPU reference renderer (`underlight::reference`) against closed forms it must
//! reproduce: flat water's uniform floor irradiance (zenith sun, oblique sun, grazing view,
//! point light), a 1-D sinusoidal wave's caustic profile computed independently from its
//! surface-to-floor mapping, the open-water single-scattering integral of tests/godrays.rs
//! (seen across the beams and along them), convergence under doubling, independence of the
//! thread count, and bad input. CPU only (no Vulkan device); the figures are printed
//! (`cargo test --test reference -- --nocapture`).

mod common;

use common::{pool, FLOOR_DEPTH};
use glam::{DVec2, DVec3, DVec4, Mat4, Vec2, Vec3};
use underlight::frame::uniforms::{directional_irradiance, FrameExtents, FrameUniforms};
use underlight::image_io::HdrImage;
use underlight::metrics::buffer_error;
use underlight::reference::{render, ReferenceImages, ReferenceSettings, MAX_THREADS};
use underlight::scene::{Light, LightKind, Scene};
use underlight::shader_math::{fresnel_transmittance, henyey_greenstein, water_phase};

fn extents(output: [u32; 2], caustic: [u32; 2], godray: [u32; 2]) -> FrameExtents {
    FrameExtents { output, caustic, godray, light_map: 256, max_point_size: 64.0, max_line_width: 8.0 }
}

fn settings(caustic_photons: u64, godray_beams: u64) -> ReferenceSettings {
    ReferenceSettings { caustic_photons, godray_beams, threads: 0, seed: 7 }
}

fn run(scene: &Scene, time: f32, ext: &FrameExtents, s: &ReferenceSettings) -> ReferenceImages {
    let start = std::time::Instant::now();
    let images = render(scene, time, ext, s, &|f| assert!((0.0..=1.0).contains(&f), "progress {f}")).unwrap();
    eprintln!(
        "  reference: {} caustic photons, {} godray beams in {:.2} s",
        s.caustic_photons,
        s.godray_beams,
        start.elapsed().as_secs_f64()
    );
    for img in images.caustics.iter().chain(&images.godrays) {
        assert!(!img.has_non_finite(), "NaN or Inf in a reference buffer");
    }
    images
}

/// The pixel rays of a target through the frame's own camera matrix: the test's own
/// unprojection, so it checks the reference's pixel correspondence too.
struct Rays {
    eye: DVec3,
    inverse: glam::DMat4,
    size: [u32; 2],
}

impl Rays {
    fn new(scene: &Scene, ext: &FrameExtents, size: [u32; 2], time: f32) -> Self {
        let u = FrameUniforms::new(scene, scene.bounds(), ext, time);
        let vp = Mat4::from_cols_array_2d(&u.camera_view_proj).as_dmat4();
        Self { eye: scene.camera.position.as_dvec3(), inverse: vp.inverse(), size }
    }

    /// Unit direction through pixel coordinates `p` (corner at integers).
    fn dir(&self, p: DVec2) -> DVec3 {
        let ndc = p / DVec2::new(self.size[0] as f64, self.size[1] as f64) * 2.0 - 1.0;
        let far = self.inverse * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.eye).normalize()
    }

    /// Where the ray through `p` meets the plane y = `y`.
    fn on_plane(&self, p: DVec2, y: f64) -> DVec3 {
        let d = self.dir(p);
        self.eye + d * ((y - self.eye.y) / d.y)
    }
}

/// E⊥ · T(0) · e^(−γ·D): flat water's floor irradiance under a zenith sun.
fn flat_floor_irradiance(scene: &Scene) -> f64 {
    directional_irradiance(scene) as f64
        * fresnel_transmittance(1.0, scene.water.ior) as f64
        * (-(scene.medium.gamma.x as f64) * FLOOR_DEPTH as f64).exp()
}

fn channel(img: &HdrImage, c: usize) -> Vec<f64> {
    img.pixels.iter().map(|p| p[c] as f64).collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn flat_water_lights_the_floor_uniformly_with_the_analytic_irradiance() {
    // The pool of tests/method.rs: flat water over the whole 12 × 12 m pool, zenith sun, the
    // camera 1.5 m above the floor looking down. Photons cover the whole water, so only
    // the ~2 % that land in the 1.7 × 1.7 m the camera sees count.
    let mut scene = pool(0.0);
    scene.effects.godrays = false;
    let ext = extents([96, 96], [48, 48], [16, 16]);
    let photons = 8_000_000;
    let img = run(&scene, 1.0, &ext, &settings(photons, 0)).caustics.expect("the pool has caustics");
    let expected = flat_floor_irradiance(&scene);
    let e = channel(&img, 0);
    let counts = channel(&img, 3);
    let (m, landed) = (mean(&e), counts.iter().sum::<f64>());
    // Poisson: the mean over the image carries 1/√(photons landed) relative noise (jittered
    // stratification only lowers it). 4σ: with 8M photons ~170 000 land, so 1 %. A missing
    // Fresnel factor reads +2.1 %, a missing e^(−γ·D) +30 %, a flux per photon of E⊥·A/N
    // on the wrong area (the light's window instead of the water) far more.
    let tolerance = 4.0 / landed.sqrt();
    let per_pixel = landed / e.len() as f64;
    let rel_std = (e.iter().map(|v| (v / m - 1.0).powi(2)).sum::<f64>() / e.len() as f64).sqrt();
    let poisson = 1.0 / per_pixel.sqrt();
    // No trend from the centre outwards: without the receiver's |cos θ_v| (a footprint
    // missing one of the pinhole's cos³) the centre reads 0.88 of the border ring here, and
    // the mean +10 %.
    let (w, h) = (img.width as f64, img.height as f64);
    let (mut inner, mut outer) = (Vec::new(), Vec::new());
    for (i, v) in e.iter().enumerate() {
        let (x, y) = ((i as u32 % img.width) as f64 + 0.5 - w / 2.0, (i as u32 / img.width) as f64 + 0.5 - h / 2.0);
        let r = (x * x + y * y).sqrt() / (w / 2.0);
        if r < 0.35 {
            inner.push(*v);
        } else if r > 0.7 {
            outer.push(*v);
        }
    }
    let ring = mean(&inner) / mean(&outer);
    let ring_tolerance = 4.0 * poisson * (1.0 / inner.len() as f64 + 1.0 / outer.len() as f64).sqrt();
    eprintln!(
        "flat floor: mean {m:e} W/m², analytic {expected:e} (ratio {:.5}, tolerance ±{tolerance:.4}); {landed} photons landed, \
         {per_pixel:.1}/pixel; per-pixel relative std {rel_std:.4} (Poisson {poisson:.4}); centre/border {ring:.4} (±{ring_tolerance:.4})",
        m / expected
    );
    assert!((m / expected - 1.0).abs() < tolerance, "floor irradiance {m:e}, analytic {expected:e}");
    // Jittered strata land a near-constant count per pixel: the spread must not exceed
    // Poisson's (a weight varying from photon to photon, e.g. a wrong per-photon area,
    // would add to it), and must be there at all (a buffer filled with the expected value
    // rather than estimated would read 0).
    assert!(rel_std < 1.1 * poisson && rel_std > 0.1 * poisson, "per-pixel spread {rel_std} vs Poisson {poisson}");
    assert!((ring - 1.0).abs() < ring_tolerance, "centre/border irradiance ratio {ring}");
    // Every pixel sees the floor: no empty pixel.
    assert!(counts.iter().all(|&c| c > 0.0), "a pixel got no photon");
}

/// Floor irradiance at horizontal distance `r` from the foot of a point light `height` above
/// flat water `depth` above the floor: the ray leaving at θᵢ from the vertical enters at
/// H·tan θᵢ, refracts to θₜ (sin θₜ = sin θᵢ / n) and lands at r(θᵢ) = H·tan θᵢ + D·tan θₜ.
/// The solid angle sin θᵢ dθᵢ dφ spreads over r dr dφ, so
///   E(r) = I · T(cos θᵢ) · e^(−γ·D/cos θₜ) · sin θᵢ / (r · dr/dθᵢ),
///   dr/dθᵢ = H / cos²θᵢ + D / cos²θₜ · cos θᵢ / (n · cos θₜ).
fn refracted_inverse_square(intensity: f64, height: f64, depth: f64, n: f64, gamma: f64, r: f64) -> f64 {
    let theta_t = |ti: f64| (ti.sin() / n).asin();
    let land = |ti: f64| height * ti.tan() + depth * theta_t(ti).tan();
    let (mut lo, mut hi) = (0.0f64, 1.5f64);
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if land(mid) < r {
            lo = mid
        } else {
            hi = mid
        }
    }
    let ti = 0.5 * (lo + hi);
    let tt = theta_t(ti);
    let transmitted =
        intensity * fresnel_transmittance(ti.cos() as f32, n as f32) as f64 * (-gamma * depth / tt.cos()).exp();
    let dr = height / ti.cos().powi(2) + depth / tt.cos().powi(2) * ti.cos() / (n * tt.cos());
    transmitted * ti.sin() / (r * dr)
}

#[test]
fn a_point_light_follows_the_refracted_inverse_square_law() {
    // tests/method.rs's point light 4 m above flat water over the pool floor, its water cut
    // to the 3 × 3 m through which light reaches the view (a time saver only).
    let mut scene = pool(0.0);
    let height = 4.0;
    scene.light = Light {
        kind: LightKind::Point,
        direction: Vec3::NEG_Y,
        position: Vec3::new(0.0, height as f32, 0.0),
        intensity: 9.2,
        distance: 100.0,
    };
    scene.water.extent_min = Vec2::splat(-1.5);
    scene.water.extent_max = Vec2::splat(1.5);
    scene.effects.godrays = false;
    let ext = extents([32, 32], [32, 32], [8, 8]);
    let img = run(&scene, 0.5, &ext, &settings(4_000_000, 0)).caustics.unwrap();
    let rays = Rays::new(&scene, &ext, ext.caustic, 0.5);
    let (mut got, mut exact, mut photons) = (0.0, 0.0, 0.0);
    // The central 16 × 16 pixels: the floor within 0.43 m of the axis.
    for y in 8..24 {
        for x in 8..24 {
            let p = rays.on_plane(DVec2::new(x as f64 + 0.5, y as f64 + 0.5), -(FLOOR_DEPTH as f64));
            let r = DVec2::new(p.x, p.z).length();
            exact += refracted_inverse_square(9.2, height, FLOOR_DEPTH as f64, 1.333, 0.13, r);
            got += img.at(x, y)[0] as f64;
            photons += img.at(x, y)[3] as f64;
        }
    }
    // 4σ of the Poisson noise of the ~180 000 photons there: 1 %. Without refraction's
    // magnification (1/(H + D)² for 1/(H + D/n)²) it would read 16 % low, without the
    // attenuation 30 % high.
    let tol = 4.0 / photons.sqrt();
    eprintln!(
        "point light: central floor {:e} W/m², exact law {:e} (ratio {:.5}, tolerance ±{tol:.4}); {photons} photons",
        got / 256.0,
        exact / 256.0,
        got / exact
    );
    assert!((got / exact - 1.0).abs() < tol, "point light: {got:e} vs {exact:e}");
}

#[test]
fn an_oblique_sun_and_a_grazing_view_keep_flat_water_exact() {
    // Flat water, so every receiver point of the floor gets the same irradiance
    //   E = E⊥ · |d_y| · T(θᵢ) · e^(−γ·D / cos θₜ)
    // whatever the view: first a sun 16° off the zenith seen from above, then a zenith sun
    // with the camera 0.5 m above the floor looking 3 m ahead, where the floor is seen at
    // down to 4° (the GPU clamps cos θ_v at 0.2 there; the reference needs no clamp).
    let ext = extents([64, 64], [64, 64], [8, 8]);
    let mut oblique = pool(0.0);
    oblique.light.direction = Vec3::new(0.25, -1.0, 0.15).normalize();
    oblique.effects.godrays = false;
    let mut grazing = pool(0.0);
    grazing.camera.position = Vec3::new(0.0, -1.5, 0.0);
    grazing.camera.look_at = Vec3::new(3.0, -2.0, 0.0);
    grazing.effects.godrays = false;
    for (name, scene) in [("oblique sun", oblique), ("grazing view", grazing)] {
        let d = scene.light.direction.as_dvec3().normalize();
        let n = scene.water.ior as f64;
        let cos_t = (1.0 - (1.0 - d.y * d.y) / (n * n)).sqrt();
        let expected = directional_irradiance(&scene) as f64
            * d.y.abs()
            * fresnel_transmittance(d.y.abs() as f32, n as f32) as f64
            * (-(scene.medium.gamma.x as f64) * FLOOR_DEPTH as f64 / cos_t).exp();
        let img = run(&scene, 1.0, &ext, &settings(4_000_000, 0)).caustics.unwrap();
        // Rows whose pixels all see the floor, by the test's own unprojection.
        let rays = Rays::new(&scene, &ext, ext.caustic, 1.0);
        let floor = -(FLOOR_DEPTH as f64);
        let on_floor = |p: DVec2| {
            let d = rays.dir(p);
            let q = rays.on_plane(p, floor);
            d.y < 0.0 && q.x.abs() < 6.0 && q.z.abs() < 6.0 && (q - rays.eye).length() < scene.camera.z_far as f64 * 0.9
        };
        let (mut worst, mut rows) = (0.0f64, 0);
        for y in 0..img.height {
            let corners = [
                (0.0, y as f64),
                (img.width as f64, y as f64),
                (0.0, y as f64 + 1.0),
                (img.width as f64, y as f64 + 1.0),
            ];
            if !corners.iter().all(|&(x, y)| on_floor(DVec2::new(x, y))) {
                continue;
            }
            let (mut sum, mut photons) = (0.0, 0.0);
            for x in 0..img.width {
                sum += img.at(x, y)[0] as f64;
                photons += img.at(x, y)[3] as f64;
            }
            let err = sum / img.width as f64 / expected - 1.0;
            // 4σ of the row's Poisson noise (a few %): without the receiver's |cos θ_v| the
            // rows would read 1/cos θ_v too much (×1.3 from above, up to ×12 at the grazing
            // view's far rows), with the GPU's clamp cos θ_v ≥ 0.2 up to ×2.4 there.
            let tol = 4.0 / photons.sqrt();
            worst = worst.max(err.abs() / tol);
            assert!(
                err.abs() < tol,
                "{name}: row {y} reads {:+.2} % off {expected:e} (tolerance {:.2} %)",
                100.0 * err,
                100.0 * tol
            );
            rows += 1;
        }
        let m = mean(&channel(&img, 0));
        eprintln!("{name}: analytic floor irradiance {expected:e} W/m²; {rows} rows on the floor, worst at {worst:.2} of its 4σ tolerance; image mean {m:e}");
        assert!(rows >= 20, "{name}: only {rows} rows checked");
    }
}

/// The 1-D sinusoidal wave of `wave_scene`: amplitude, wavelength.
const WAVE: (f32, f32) = (0.015, 0.8);

/// The pool under a single wave h = a·cos(kx − φ) (no noise), its water cut to the 2 × 2 m
/// the camera looks down on (photons elsewhere never reach the view: this only saves time).
fn wave_scene() -> Scene {
    let mut scene = pool(WAVE.0);
    scene.water.wavelength = WAVE.1;
    scene.water.noise_amplitude = 0.0;
    scene.water.extent_min = Vec2::splat(-1.0);
    scene.water.extent_max = Vec2::splat(1.0);
    scene.effects.godrays = false;
    scene
}

/// The analytic caustic of the 1-D wave under a zenith sun, computed independently of the
/// reference: a surface point x_s refracts the vertical ray at slope h'(x_s) and lands on the
/// floor at x_f(x_s) = x_s + (h(x_s) + D)·tan(offset) after a path L = (h + D)/cos(offset).
/// The irradiance at x_f is the transmitted flux density over the mapping's stretch, summed
/// over preimages (one here: the mapping is monotonic before the first fold):
///   E(x_f) = E⊥ · T(θᵢ) · e^(−γ·L) / |dx_f/dx_s|.
struct WaveCaustic {
    a: f64,
    k: f64,
    phase: f64,
    depth: f64,
    n: f64,
    gamma: f64,
    e_perp: f64,
}

impl WaveCaustic {
    fn new(scene: &Scene, time: f32) -> Self {
        let w = &scene.water;
        Self {
            a: w.amplitude as f64,
            k: std::f64::consts::TAU / w.wavelength as f64,
            phase: water_phase(w, time).x as f64,
            depth: FLOOR_DEPTH as f64 + w.level as f64,
            n: w.ior as f64,
            gamma: scene.medium.gamma.x as f64,
            e_perp: directional_irradiance(scene) as f64,
        }
    }

    /// (x_f, path length, cos θᵢ) for surface point x_s.
    fn map(&self, xs: f64) -> (f64, f64, f64) {
        let h = self.a * (self.k * xs - self.phase).cos();
        let slope = -self.a * self.k * (self.k * xs - self.phase).sin();
        // Incidence angle from the vertical = the normal's tilt; Snell gives the refracted
        // angle; the ray turns towards the inward normal (h', −1), i.e. towards +x where the
        // surface rises with x.
        let cos_i = 1.0 / (1.0 + slope * slope).sqrt();
        let theta_i = cos_i.acos();
        let theta_t = (theta_i.sin() / self.n).asin();
        let offset = (theta_i - theta_t) * slope.signum();
        let drop = h + self.depth;
        (xs + drop * offset.tan(), drop / offset.cos(), cos_i)
    }

    /// E(x_f), with x_s found by bisection on the monotonic mapping.
    fn irradiance(&self, xf: f64) -> f64 {
        let (mut lo, mut hi) = (xf - 0.5, xf + 0.5);
        for _ in 0..80 {
            let mid = 0.5 * (lo + hi);
            if self.map(mid).0 < xf {
                lo = mid
            } else {
                hi = mid
            }
        }
        let xs = 0.5 * (lo + hi);
        let e = 1e-6;
        let stretch = (self.map(xs + e).0 - self.map(xs - e).0) / (2.0 * e);
        let (_, path, cos_i) = self.map(xs);
        self.e_perp * fresnel_transmittance(cos_i as f32, self.n as f32) as f64 * (-self.gamma * path).exp()
            / stretch.abs()
    }

    /// Smallest dx_f/dx_s over a period: > 0 before the first fold.
    fn min_stretch(&self) -> f64 {
        let period = std::f64::consts::TAU / self.k;
        (0..2000)
            .map(|i| {
                let xs = period * i as f64 / 2000.0;
                (self.map(xs + 1e-6).0 - self.map(xs - 1e-6).0) / 2e-6
            })
            .fold(f64::INFINITY, f64::min)
    }
}

/// Per image column (the axis along which world x varies, checked): the reference's mean
/// over the rows, the analytic irradiance averaged over the column's floor footprint, and
/// the photons that landed in it.
fn wave_profile(scene: &Scene, ext: &FrameExtents, img: &HdrImage, time: f32) -> Vec<(f64, f64, f64)> {
    let rays = Rays::new(scene, ext, ext.caustic, time);
    let floor = -(FLOOR_DEPTH as f64);
    // Looking straight down with z as the up vector, image columns run along world x.
    let c0 = rays.on_plane(DVec2::new(0.0, 0.0), floor);
    let c1 = rays.on_plane(DVec2::new(0.0, img.height as f64), floor);
    assert!((c0.x - c1.x).abs() < 1e-9, "image columns are not lines of constant x");
    let wave = WaveCaustic::new(scene, time);
    let mid = img.height as f64 / 2.0;
    (0..img.width)
        .map(|x| {
            let (xa, xb) = (
                rays.on_plane(DVec2::new(x as f64, mid), floor).x,
                rays.on_plane(DVec2::new(x as f64 + 1.0, mid), floor).x,
            );
            // Midpoint rule, 32 samples across the pixel's footprint.
            let analytic =
                (0..32).map(|i| wave.irradiance(xa + (xb - xa) * (i as f64 + 0.5) / 32.0)).sum::<f64>() / 32.0;
            let (mut sum, mut photons) = (0.0, 0.0);
            for y in 0..img.height {
                sum += img.at(x, y)[0] as f64;
                photons += img.at(x, y)[3] as f64;
            }
            (sum / img.height as f64, analytic, photons)
        })
        .collect()
}

#[test]
fn a_sinusoidal_wave_focuses_light_as_its_surface_to_floor_mapping_says() {
    let scene = wave_scene();
    let time = 1.0;
    let wave = WaveCaustic::new(&scene, time);
    let stretch = wave.min_stretch();
    // Before the first fold (no cusp inside the floor's depth), with strong contrast:
    // min dx_f/dx_s ≈ 1 − (1 − 1/n)·D·a·k² = 0.54 (a fold at 0).
    assert!(stretch > 0.4 && stretch < 0.7, "min dx_f/dx_s = {stretch}");
    let ext = extents([64, 64], [64, 64], [16, 16]);
    let photons = 1_000_000;
    let img = run(&scene, time, &ext, &settings(photons, 0)).caustics.unwrap();
    let profile = wave_profile(&scene, &ext, &img, time);
    let (mut worst, mut sum_ref, mut sum_exact, mut landed, mut squares) = (0.0f64, 0.0, 0.0, 0.0, 0.0);
    let (lo, hi) = profile.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
    for (x, &(got, exact, n)) in profile.iter().enumerate() {
        // Per column, 4σ of the Poisson noise of the ~12 000 photons in it (≈ 3.7 %): the
        // contrast is ×2.7 (0.68 to 1.85 of the flat value), so refraction that did not
        // focus, or a stretch on the wrong axis, misses by tens of per cent.
        let tol = 4.0 / n.sqrt();
        let err = got / exact - 1.0;
        worst = worst.max(err.abs() / tol);
        assert!(
            err.abs() < tol,
            "column {x}: reference {got:e}, analytic {exact:e} ({:+.2} %, tolerance {:.2} %)",
            100.0 * err,
            100.0 * tol
        );
        sum_ref += got;
        sum_exact += exact;
        landed += n;
        squares += err * err;
    }
    // The whole image: 4σ of ~750 000 photons is 0.5 %; without the Fresnel factor the
    // mean reads +2 %.
    let tol = 4.0 / landed.sqrt();
    let ratio = sum_ref / sum_exact;
    eprintln!(
        "1-D wave: analytic profile {lo:e}..{hi:e} W/m² (×{:.2}); reference/analytic over the image {ratio:.5} (±{tol:.4}); \
         columns off by {:.2} % rms, the worst at {:.2} of its 4σ tolerance; {landed} photons landed",
        hi / lo,
        100.0 * (squares / profile.len() as f64).sqrt(),
        worst
    );
    assert!((ratio - 1.0).abs() < tol, "mean over the image: reference/analytic {ratio}");
}

/// tests/godrays.rs's `horizontal_pool`: the sunlit pool seen level along +x from 1 m under
/// water, the godray target at the output's size.
fn horizontal_pool() -> Scene {
    let mut s = pool(0.0);
    s.camera.position = Vec3::new(0.0, -1.0, 0.0);
    s.camera.look_at = Vec3::new(1.0, -1.0, 0.0);
    s.effects.godray_target_scale = 1.0;
    s.effects.caustics = false;
    s
}

/// Mean of channel 0 over a block.
fn block_mean(img: &HdrImage, xs: std::ops::Range<u32>, ys: std::ops::Range<u32>) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for y in ys {
        for x in xs.clone() {
            sum += img.at(x, y)[0] as f64;
            n += 1;
        }
    }
    sum / n as f64
}

const SIDE: u32 = 96;
const BLOCK: (std::ops::Range<u32>, std::ops::Range<u32>) = (40..56, 44..52);

/// The single-scattering integral along pixel (x, y)'s centre ray, exactly: vertical beams
/// of E⊥·T(0) entering flat water, seen at cos θ = v_y, attenuated over the depth d₀ − s·v_y
/// they travelled (d₀ the camera's depth) and the s the view ray did, out to where the ray
/// leaves the water's extent (or meets the floor or the surface):
///   L = σs · p(v_y) · E⊥ · T(0) · e^(−γ·d₀) · (1 − e^(−γ(1 − v_y)S)) / (γ(1 − v_y)).
fn exact_inscattering(scene: &Scene, rays: &Rays, x: u32, y: u32) -> f64 {
    let v = rays.dir(DVec2::new(x as f64 + 0.5, y as f64 + 0.5));
    let half = scene.water.extent_max.x as f64;
    let mut s_end = (half / v.x.abs()).min(half / v.z.abs().max(1e-12));
    let (eye_y, floor) = (rays.eye.y, -(FLOOR_DEPTH as f64));
    if v.y > 0.0 {
        s_end = s_end.min(-eye_y / v.y);
    } else if v.y < 0.0 {
        s_end = s_end.min((floor - eye_y) / v.y);
    }
    let gamma = scene.medium.gamma.x as f64;
    let depth0 = -eye_y;
    let k = gamma * (1.0 - v.y);
    scene.medium.scattering as f64
        * henyey_greenstein(v.y as f32, scene.medium.hg_g) as f64
        * directional_irradiance(scene) as f64
        * fresnel_transmittance(1.0, scene.water.ior) as f64
        * (-gamma * depth0).exp()
        * (1.0 - (-k * s_end).exp())
        / k
}

#[test]
fn inscattering_matches_the_single_scattering_integral() {
    let scene = horizontal_pool();
    let ext = extents([SIDE, SIDE], [SIDE, SIDE], [SIDE, SIDE]);
    let beams = 250_000;
    let g = run(&scene, 1.0, &ext, &settings(0, beams)).godrays.expect("the pool has godrays");
    let got = block_mean(&g, BLOCK.0, BLOCK.1);
    // tests/godrays.rs's figure for the level central ray.
    let gamma = 0.13f64;
    let level = scene.medium.scattering as f64
        * henyey_greenstein(0.0, scene.medium.hg_g) as f64
        * directional_irradiance(&scene) as f64
        * fresnel_transmittance(1.0, 1.333) as f64
        * (-gamma).exp()
        * (1.0 - (-gamma * 6.0).exp())
        / gamma;
    // And per pixel of the block, the integral along its own (slightly tilted) ray.
    let rays = Rays::new(&scene, &ext, ext.godray, 1.0);
    let (mut exact, mut n) = (0.0, 0);
    for y in BLOCK.1 {
        for x in BLOCK.0 {
            exact += exact_inscattering(&scene, &rays, x, y);
            n += 1;
        }
    }
    let exact = exact / n as f64;
    let counts: f64 = BLOCK
        .1
        .clone()
        .flat_map(|y| BLOCK.0.clone().map(move |x| (x, y)))
        .map(|(x, y)| g.at(x, y)[3] as f64)
        .sum::<f64>()
        / n as f64;
    eprintln!(
        "in-scattered radiance over the block {got:e} W/(m²·sr): level-ray analytic {level:e} ({:+.2} %), \
         per-pixel exact {exact:e} ({:+.2} %); {counts:.0} beams per pixel",
        100.0 * (got / level - 1.0),
        100.0 * (got / exact - 1.0)
    );
    // 1 % against the per-pixel integrals: each pixel's ray meets ~1500 beams, so the
    // kernel's noise is well under 1 %, and in open water its blur has no bias except at the
    // extent's edge (symmetric: it keeps the integral). A missing Fresnel factor reads
    // +2.2 % (measured), a phase function without its 1/(4π) ×12.6, the disc kernel
    // normalised per width (1/(2r), r = 7 cm here) instead of per area (1/(πr²)) ×0.11.
    assert!((got / exact - 1.0).abs() < 0.01, "block {got:e}, exact {exact:e}");
    // And tests/godrays.rs's level-ray figure, within 1.5 %: the block's rays tilt by up to
    // ±2.7° vertically and ±5.5° sideways, which moves the exact integral by +0.25 % here.
    assert!((got / level - 1.0).abs() < 0.015, "block {got:e}, level-ray analytic {level:e}");
}

#[test]
fn inscattering_along_the_beams_matches_the_integral() {
    // The pool of tests/method.rs seen from above: the view rays run within 0° to 39° of the
    // vertical beams, the regime where a 1-D beam kernel's 1/sin θ diverges (the GPU clamps
    // it at sin θ = 0.1) and the reference's disc kernel must hold.
    let mut scene = pool(0.0);
    scene.effects.caustics = false;
    let ext = extents([96, 96], [32, 32], [32, 32]);
    let g = run(&scene, 1.0, &ext, &settings(0, 250_000)).godrays.unwrap();
    let rays = Rays::new(&scene, &ext, ext.godray, 1.0);
    let (mut got, mut exact, mut centre_got, mut centre_exact, mut squares) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for y in 0..g.height {
        for x in 0..g.width {
            let e = exact_inscattering(&scene, &rays, x, y);
            got += g.at(x, y)[0] as f64;
            exact += e;
            squares += (g.at(x, y)[0] as f64 / e - 1.0).powi(2);
            if (12..20).contains(&x) && (12..20).contains(&y) {
                centre_got += g.at(x, y)[0] as f64;
                centre_exact += e;
            }
        }
    }
    eprintln!(
        "looking along the beams: image {:e} W/(m²·sr) vs exact {:e} ({:+.2} %); central 8×8 (within 11° of the beams) {:+.2} %; \
         per-pixel rms {:.2} %",
        got / 1024.0,
        exact / 1024.0,
        100.0 * (got / exact - 1.0),
        100.0 * (centre_got / centre_exact - 1.0),
        100.0 * (squares / 1024.0).sqrt()
    );
    // 1.5 % over the image, 3 % over the central 64 pixels, whose rays nearly run along the
    // beams and see the same ~28 beams per kernel disc (their noise is correlated). A
    // missing Fresnel factor reads +2.2 %, a 1-D kernel's unclamped 1/sin θ diverges.
    assert!((got / exact - 1.0).abs() < 0.015, "image {got:e} vs exact {exact:e}");
    assert!((centre_got / centre_exact - 1.0).abs() < 0.03, "centre {centre_got:e} vs exact {centre_exact:e}");
}

#[test]
fn doubling_the_photons_changes_the_result_by_less_than_its_error() {
    // Caustics: the wave's profile at N and 2N photons (different seeds, so independent).
    let scene = wave_scene();
    let ext = extents([64, 64], [64, 64], [16, 16]);
    let n = 500_000;
    let a = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 11, ..settings(n, 0) }).caustics.unwrap();
    let b = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 12, ..settings(2 * n, 0) }).caustics.unwrap();
    let (pa, pb) = (wave_profile(&scene, &ext, &a, 1.0), wave_profile(&scene, &ext, &b, 1.0));
    let mut worst = 0.0f64;
    for (x, (ca, cb)) in pa.iter().zip(&pb).enumerate() {
        // The stated error of each column is 4σ of its Poisson noise; two independent
        // estimates differ by at most 4·√(σ_N² + σ_2N²).
        let tol = 4.0 * (1.0 / ca.2 + 1.0 / cb.2).sqrt();
        let change = cb.0 / ca.0 - 1.0;
        worst = worst.max(change.abs() / tol);
        assert!(change.abs() < tol, "column {x}: {:e} at N, {:e} at 2N", ca.0, cb.0);
    }
    let (ma, mb) = (mean(&channel(&a, 0)), mean(&channel(&b, 0)));
    let landed = channel(&a, 3).iter().sum::<f64>();
    let tol = 4.0 * (1.5 / landed).sqrt();
    eprintln!(
        "caustics N → 2N: mean changes {:+.3} % (tolerance ±{:.3} %), worst column at {worst:.2} of its tolerance",
        100.0 * (mb / ma - 1.0),
        100.0 * tol
    );
    assert!((mb / ma - 1.0).abs() < tol);

    // Godrays: the block of the open-water test at N and 2N beams (the kernel shrinks by √2).
    let scene = horizontal_pool();
    let ext = extents([SIDE, SIDE], [SIDE, SIDE], [SIDE, SIDE]);
    let n = 100_000;
    let ga = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 11, ..settings(0, n) }).godrays.unwrap();
    let gb = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 12, ..settings(0, 2 * n) }).godrays.unwrap();
    let (la, lb) = (block_mean(&ga, BLOCK.0, BLOCK.1), block_mean(&gb, BLOCK.0, BLOCK.1));
    // The whole image too: it holds the pixels that see the floor, where the kernel meets
    // the beams' ends.
    let (ia, ib) = (mean(&channel(&ga, 0)), mean(&channel(&gb, 0)));
    eprintln!(
        "godrays N → 2N: block changes {:+.3} %, image mean {:+.3} % (stated error 1 %)",
        100.0 * (lb / la - 1.0),
        100.0 * (ib / ia - 1.0)
    );
    assert!((lb / la - 1.0).abs() < 0.01, "block {la:e} at N, {lb:e} at 2N");
    assert!((ib / ia - 1.0).abs() < 0.01, "image mean {ia:e} at N, {ib:e} at 2N");
}

#[test]
fn the_two_halves_of_the_photons_measure_the_references_own_error() {
    // The wave at N and 4N photons (independent seeds). Each run's halves give its own
    // error (ReferenceImages::caustics_half); the two runs then differ by about
    // √(own_N² + own_4N²). Halves that are not independent fail it: every other cell of one
    // stratification read 1.6× the difference here. With 4× the photons the own error falls
    // at least as Poisson noise does (½); the stratified map of a smooth wave makes it fall
    // faster (measured 0.35).
    let scene = wave_scene();
    let ext = extents([64, 64], [64, 64], [16, 16]);
    let n = 250_000;
    let own = |images: &ReferenceImages| {
        let (all, half) = (images.caustics.as_ref().unwrap(), images.caustics_half.as_ref().unwrap());
        buffer_error(half, all).unwrap().relative_rmse
    };
    let a = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 11, ..settings(n, 0) });
    let b = run(&scene, 1.0, &ext, &ReferenceSettings { seed: 12, ..settings(4 * n, 0) });
    let (own_a, own_b) = (own(&a), own(&b));
    let predicted = (own_a * own_a + own_b * own_b).sqrt();
    let measured = buffer_error(a.caustics.as_ref().unwrap(), b.caustics.as_ref().unwrap()).unwrap().relative_rmse;
    eprintln!(
        "own error at N {own_a:.4}, at 4N {own_b:.4} (ratio {:.2}); N against 4N {measured:.4}, predicted {predicted:.4}",
        own_a / own_b
    );
    assert!(own_a > 0.02, "the halves should differ by the photon noise: {own_a}");
    assert!((1.8..4.2).contains(&(own_a / own_b)), "4× the photons should cut the own error 2-4×: {own_a} → {own_b}");
    assert!((0.8..1.25).contains(&(measured / predicted)), "measured {measured}, predicted {predicted}");
}

#[test]
fn from_above_the_water_the_surface_hides_both_buffers() {
    // The camera 1 m above the pool looking down: every pixel sees the water surface first,
    // which ends the view ray as the GPU's depth buffer does (no refraction of the view),
    // so nothing under it is seen. Looking level from there, the lower half sees the
    // surface and the upper half no water: both black too.
    for look_at in [Vec3::new(0.0, -2.0, 0.01), Vec3::new(1.0, 1.0, 0.0)] {
        let mut scene = pool(0.04);
        scene.camera.position = Vec3::new(0.0, 1.0, 0.0);
        scene.camera.look_at = look_at;
        let ext = extents([32, 32], [32, 32], [32, 32]);
        let images = run(&scene, 1.0, &ext, &settings(200_000, 50_000));
        let (c, g) = (images.caustics.unwrap(), images.godrays.unwrap());
        assert_eq!(c.channel_sums(), [0.0; 4], "caustics seen through the surface from above");
        assert_eq!(g.channel_sums(), [0.0; 4], "godrays seen through the surface from above");
    }
}

#[test]
fn zero_photons_or_too_many_threads_is_an_error_not_a_panic() {
    let scene = pool(0.0);
    let ext = extents([32, 32], [16, 16], [8, 8]);
    let too_many_threads = ReferenceSettings { threads: MAX_THREADS + 1, ..settings(10, 10) };
    for (s, what) in
        [(settings(0, 1000), "caustic_photons"), (settings(1000, 0), "godray_beams"), (too_many_threads, "threads")]
    {
        match render(&scene, 0.0, &ext, &s, &|_| {}) {
            Err(e) => {
                let message = e.to_string();
                eprintln!("{what} = 0: {message}");
                assert!(message.contains(what), "the error should name {what}: {message}");
            }
            Ok(_) => panic!("{what} = 0 must be refused"),
        }
    }
    // A target with no pixels, and a time that is not a number.
    assert!(render(&scene, 0.0, &extents([32, 32], [0, 16], [8, 8]), &settings(10, 10), &|_| {}).is_err());
    assert!(render(&scene, f32::NAN, &ext, &settings(10, 10), &|_| {}).is_err());
    // A scene whose plan has neither buffer needs no photons at all.
    let mut off = pool(0.0);
    off.effects.caustics = false;
    off.effects.godrays = false;
    let none = render(&off, 0.0, &ext, &settings(0, 0), &|_| {}).unwrap();
    assert!(none.caustics.is_none() && none.godrays.is_none());
}

#[test]
fn the_result_does_not_depend_on_the_thread_count() {
    let mut scene = wave_scene();
    scene.effects.godrays = true;
    scene.water.noise_amplitude = 0.02;
    let ext = extents([32, 32], [32, 32], [16, 16]);
    let one =
        render(&scene, 2.0, &ext, &ReferenceSettings { threads: 1, ..settings(40_000, 10_000) }, &|_| {}).unwrap();
    let two =
        render(&scene, 2.0, &ext, &ReferenceSettings { threads: 3, ..settings(40_000, 10_000) }, &|_| {}).unwrap();
    for (a, b) in [(one.caustics.unwrap(), two.caustics.unwrap()), (one.godrays.unwrap(), two.godrays.unwrap())] {
        let sa = a.channel_sums();
        assert!(sa[0] > 0.0 && sa[3] > 0.0, "nothing rendered");
        // Per-thread sums are added in a different order: equal to f32 rounding.
        for (p, q) in a.pixels.iter().zip(&b.pixels) {
            assert!((p[0] - q[0]).abs() <= 1e-5 * p[0].abs().max(1e-12), "{p:?} vs {q:?}");
            assert_eq!(p[3], q[3]);
        }
    }
}
