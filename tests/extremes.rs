//! The frame at the extremes of its parameters, on lavapipe under validation: sun from
//! grazing to straight down, water from flat to violent and late in time, the medium's
//! limits, the camera at and around the waterline with extreme projections, the smallest
//! grids and targets, sizes beyond the device's limits, and a point light in and under the
//! water. Every scenario must read back no NaN or Inf in any target and leave no validation
//! message. Where the camera sees the floor square-on, the caustic flux on it must not exceed
//! the flux that enters the water. Near an edge, the result must move continuously with the
//! parameter.

mod common;

use ash::vk;
use common::*;
use glam::Vec3;
use underlight::frame::uniforms::{directional_irradiance, surface_irradiance};
use underlight::headless::{SceneImages, SceneRenderer};
use underlight::image_io::HdrImage;
use underlight::scene::{LightKind, Scene};
use underlight::shader_math::fresnel_transmittance;
use underlight::vk::Context;

/// Renders one frame of `scene` at `time` and checks every read-back target is finite.
fn render(ctx: &Context, scene: &Scene, time: f32, label: &str) -> SceneImages {
    let out = vk::Extent2D { width: scene.output[0], height: scene.output[1] };
    let mut r = SceneRenderer::new(&ctx.device, scene, out).unwrap_or_else(|e| panic!("{label}: {e:#}"));
    let (_, images) = r.render(1, time, 0.0, true).unwrap_or_else(|e| panic!("{label}: {e:#}"));
    let images = images.unwrap();
    let named: [(&str, Option<&HdrImage>); 6] = [
        ("scene colour", Some(&images.scene_color)),
        ("albedo × transmittance", Some(&images.albedo_transmittance)),
        ("caustics", images.caustics.as_ref()),
        ("filtered caustics", images.caustics_filtered.as_ref()),
        ("godrays", images.godrays.as_ref()),
        ("filtered godrays", images.godrays_filtered.as_ref()),
    ];
    for (name, img) in named {
        if let Some(img) = img {
            assert!(!img.has_non_finite(), "{label}: NaN or Inf in the {name} buffer");
        }
    }
    images
}

/// The pool seen square-on from just under the water, with a wide lens that takes in most of
/// the floor: every caustic pixel covers the same floor area, so the buffer sums to a flux.
fn overview(amplitude: f32) -> Scene {
    let mut s = pool(amplitude);
    s.camera.position = Vec3::new(0.0, -0.1, 0.0);
    s.camera.look_at = Vec3::new(0.0, -FLOOR_DEPTH, 0.0);
    s.camera.fov_y_degrees = 120.0;
    s.output = [64, 64];
    s.effects.caustic_grid = 96;
    s.effects.godray_grid = 16;
    s.effects.shadow_map_size = 256;
    s
}

/// Caustic flux on the floor in view, W: Σ E · (pixel's floor area) over the caustic buffer.
fn floor_flux_in_view(scene: &Scene, caustics: &HdrImage) -> f64 {
    let h = (scene.camera.position.y + FLOOR_DEPTH) as f64;
    let side = 2.0 * (scene.camera.fov_y_degrees as f64 / 2.0).to_radians().tan() * h / caustics.height as f64;
    caustics.channel_sums()[0] * side * side
}

/// The flux that enters the pool's 12 × 12 m water, W (before attenuation): E⊥ · |d_y| ·
/// area · T for a directional light; for a point light, the intensity over the water's solid
/// angle (numerically), times T ≤ 1.
fn flux_into_water(scene: &Scene) -> f64 {
    let (lo, hi) = (scene.water.extent_min, scene.water.extent_max);
    let area = ((hi.x - lo.x) * (hi.y - lo.y)) as f64;
    match scene.light.kind {
        LightKind::Directional => {
            let d = scene.light.direction;
            let t = fresnel_transmittance(-d.y, scene.water.ior) as f64;
            directional_irradiance(scene) as f64 * (-d.y as f64) * area * t
        }
        LightKind::Point => {
            let n = 200;
            let p = scene.light.position;
            let cell = area / (n * n) as f64;
            let mut flux = 0.0;
            for j in 0..n {
                for i in 0..n {
                    let x = lo.x + (hi.x - lo.x) * (i as f32 + 0.5) / n as f32;
                    let z = lo.y + (hi.y - lo.y) * (j as f32 + 0.5) / n as f32;
                    let v = Vec3::new(x, scene.water.level, z) - p;
                    let r2 = v.length_squared() as f64;
                    flux += scene.light.intensity as f64 * (-v.y as f64 / r2.sqrt()).max(0.0) / r2 * cell;
                }
            }
            flux
        }
    }
}

/// Renders an overview scene, checks the flux bound, and returns the flux on the floor.
fn overview_flux(ctx: &Context, scene: &Scene, time: f32, label: &str) -> f64 {
    let images = render(ctx, scene, time, label);
    let caustics = images.caustics.unwrap_or_else(|| panic!("{label}: no caustics"));
    let on_floor = floor_flux_in_view(scene, &caustics);
    let entering = flux_into_water(scene);
    eprintln!("{label}: caustic flux in view {on_floor:.3} W of {entering:.3} W entering the water");
    assert!(
        on_floor <= entering,
        "{label}: {on_floor} W on the floor in view, more than the {entering} W entering the water"
    );
    on_floor
}

fn sun(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    Vec3::new(e.cos() * a.cos(), -e.sin(), e.cos() * a.sin())
}

#[test]
fn sun_from_grazing_to_straight_down() {
    let ctx = validated_context();
    let mut fluxes = Vec::new();
    for elevation in [90.0f32, 60.0, 40.0, 30.0, 20.0, 10.0, 5.0, 1.0] {
        let mut s = overview(0.0);
        // Exactly straight down (the light's look-at has no horizontal part) at 90°.
        s.light.direction = if elevation == 90.0 { Vec3::NEG_Y } else { sun(elevation, 30.0) };
        let flux = overview_flux(&ctx, &s, 0.0, &format!("sun at {elevation}°"));
        fluxes.push((elevation, flux, flux_into_water(&s)));
    }
    assert_clean_shutdown(ctx);
    // Flat water: the share of the entering flux that reaches the floor in view changes
    // smoothly with the elevation (refraction shifts the lit area, the path lengthens): no
    // jump to black or to white between neighbours, down to 1°. (Before the convergence
    // test measured against the receiver's plane and the first guess fell back on the
    // scene's bottom, 10° and below were black: docs/limits.md.)
    for pair in fluxes.windows(2) {
        let ((e0, f0, in0), (e1, f1, in1)) = (pair[0], pair[1]);
        let (s0, s1) = (f0 / in0, f1 / in1);
        eprintln!("share of the entering flux on the floor in view: {s0:.4} at {e0}°, {s1:.4} at {e1}°");
        assert!(s1 > 0.0, "nothing reaches the floor at {e1}°");
        assert!(
            (s1 / s0 - 1.0).abs() < 0.35,
            "share of the entering flux jumps from {s0:.3} at {e0}° to {s1:.3} at {e1}°"
        );
    }
}

#[test]
fn water_from_flat_to_violent_and_late() {
    let ctx = validated_context();
    let flat = overview_flux(&ctx, &overview(0.0), 0.0, "flat");
    let tiny = overview_flux(&ctx, &overview(1e-5), 0.0, "amplitude 10 µm");
    // A ripple of 10 µm is flat water to within the splats' noise.
    assert!((tiny / flat - 1.0).abs() < 0.01, "10 µm waves change the flux by {:.2} %", 100.0 * (tiny / flat - 1.0));
    let mut violent = overview(0.3);
    violent.water.wavelength = 0.5; // slope A·k ≈ 3.8: far steeper than real water
    overview_flux(&ctx, &violent, 0.7, "violent");
    let mut short = overview(0.002);
    short.water.wavelength = 0.01;
    overview_flux(&ctx, &short, 0.0, "1 cm wavelength");
    let mut long = overview(0.5);
    long.water.wavelength = 1000.0;
    overview_flux(&ctx, &long, 0.0, "1 km wavelength");
    // A day and a half in: the animation keeps its precision, so one frame later the
    // pattern has moved a little, not jumped.
    let mut late = overview(0.04);
    late.water.noise_amplitude = 0.02;
    let t = 1.0e5f32;
    let a = render(&ctx, &late, t, "late").caustics.unwrap();
    let b = render(&ctx, &late, t + 1.0 / 60.0, "late + 1 frame").caustics.unwrap();
    let early = render(&ctx, &late, 0.0, "early").caustics.unwrap();
    let early_next = render(&ctx, &late, 1.0 / 60.0, "early + 1 frame").caustics.unwrap();
    let change = |x: &HdrImage, y: &HdrImage| underlight::bench::buffer_difference(x, y).unwrap().relative_l1;
    let (late_change, early_change) = (change(&a, &b), change(&early, &early_next));
    eprintln!("frame-to-frame change: {early_change:.3} at t = 0, {late_change:.3} at t = {t}");
    assert!(
        late_change < 3.0 * early_change + 0.05,
        "late frames flicker: {late_change} against {early_change} at t = 0"
    );
    // A clock that is not finite is refused by name before a frame is recorded (it rendered
    // empty effect buffers, reported as photons that reached no receiver). Past f32's range,
    // a finite first time whose later frames overflow is refused as well.
    let out = vk::Extent2D { width: late.output[0], height: late.output[1] };
    let mut r = SceneRenderer::new(&ctx.device, &late, out).unwrap();
    for (t0, dt, frames) in [(f32::NAN, 0.0, 1), (f32::INFINITY, 0.0, 1), (0.0, f32::NAN, 2), (f32::MAX, f32::MAX, 3)] {
        let err = r.render(frames, t0, dt, true).err().unwrap_or_else(|| panic!("t0 {t0}, dt {dt} rendered"));
        assert!(err.to_string().contains("invalid parameter time"), "t0 {t0}, dt {dt}: {err}");
    }
    drop(r);
    // A scene built in code with a NaN amplitude is refused by name before any GPU work, as
    // a scene file's is (`Scene::validate`).
    let mut nan = late.clone();
    nan.water.amplitude = f32::NAN;
    let err = SceneRenderer::new(&ctx.device, &nan, out).err().expect("a NaN amplitude was rendered");
    assert!(err.to_string().contains("water.amplitude = NaN is out of range"), "{err}");
    assert_clean_shutdown(ctx);
}

/// The triangle estimator (glsl/caustics/caustics_triangles.geom) through the same extremes as the
/// paper's points: grazing and straight-down sun, violent and centimetre waves, the
/// smallest grid and its largest subdivision. Each frame is finite and clean, puts no more
/// light on the floor than enters the water, and on flat water puts as much there as the
/// points do (both carry the same photons; only where they draw them differs).
#[test]
fn triangle_estimator_at_the_extremes() {
    use underlight::scene::CausticEstimator;
    let ctx = validated_context();
    let triangles = |mut s: Scene| {
        s.effects.caustic_estimator = CausticEstimator::Triangles;
        s.effects.caustic_subdivision =
            s.effects.caustic_subdivision.min(underlight::shader_math::TRIANGLE_MAX_SUBDIVISION);
        s
    };
    carries_the_points_light_under_every_sun(&ctx, "triangles", triangles);
    let mut violent = overview(0.3);
    violent.water.wavelength = 0.5;
    overview_flux(&ctx, &triangles(violent.clone()), 0.7, "triangles, violent waves");
    let mut short = overview(0.002);
    short.water.wavelength = 0.01;
    overview_flux(&ctx, &triangles(short), 0.0, "triangles, 1 cm wavelength");
    let mut one = overview(0.04);
    one.effects.caustic_grid = 1;
    one.effects.caustic_subdivision = 1;
    overview_flux(&ctx, &triangles(one.clone()), 0.0, "triangles, 1×1 photon grid");
    let mut most = overview(0.04);
    most.effects.caustic_grid = 24;
    most.effects.caustic_subdivision = underlight::shader_math::TRIANGLE_MAX_SUBDIVISION;
    overview_flux(&ctx, &triangles(most.clone()), 0.0, "triangles, subdivision at the output limit");
    // Refined at receivers' borders (effects.caustic_refinement): the cells that reach the
    // pool's walls are cast again finer, and the floor's light stays (measured: 0.01307 W both,
    // +0.00 %). The 1×1 grid's list holds a single cell (a quarter of its mesh): any cell
    // past it is drawn unrefined. Violent waves fold the mesh without refusing it.
    let refined = |s: Scene| {
        let mut s = triangles(s);
        s.effects.caustic_refinement = true;
        s
    };
    let mut low_sun = overview(0.04);
    low_sun.light.direction = sun(30.0, 30.0);
    let plain = overview_flux(&ctx, &triangles(low_sun.clone()), 0.0, "triangles, sun at 30°, waves");
    let fine = overview_flux(&ctx, &refined(low_sun), 0.0, "refined triangles, sun at 30°, waves");
    eprintln!("refinement: floor flux {plain:.5} W → {fine:.5} W ({:+.2} %)", 100.0 * (fine / plain - 1.0));
    assert!((fine / plain - 1.0).abs() < 0.01, "refinement moved the floor's flux: {plain} W → {fine} W");
    overview_flux(&ctx, &refined(violent), 0.7, "refined triangles, violent waves");
    overview_flux(&ctx, &refined(one), 0.0, "refined triangles, 1×1 photon grid");
    overview_flux(&ctx, &refined(most), 0.0, "refined triangles, subdivision at the output limit");
    assert_clean_shutdown(ctx);
}

/// Flat water under suns from the zenith to 1°: the estimator that `estimator` sets on a scene
/// puts the paper's points' light on the floor in view, within 5 %.
fn carries_the_points_light_under_every_sun(ctx: &Context, name: &str, estimator: impl Fn(Scene) -> Scene) {
    for elevation in [90.0f32, 30.0, 10.0, 1.0] {
        let mut s = overview(0.0);
        s.light.direction = if elevation == 90.0 { Vec3::NEG_Y } else { sun(elevation, 30.0) };
        let points = overview_flux(ctx, &s, 0.0, &format!("points, sun at {elevation}°"));
        let other = overview_flux(ctx, &estimator(s), 0.0, &format!("{name}, sun at {elevation}°"));
        assert!(other > 0.0, "{name}: nothing on the floor at {elevation}°");
        assert!(
            (other / points - 1.0).abs() < 0.05,
            "flat water, sun at {elevation}°: points {points} W, {name} {other} W"
        );
    }
}

#[test]
fn footprint_points_at_the_extremes() {
    // The footprint-sized points carry the paper's points' light from the zenith to a sun at
    // 1° (their footprints stretch with the light's slant), and stay finite and
    // validation-clean where the waves fold their cells, under a 1 cm wavelength, on the
    // coarsest grid they take (whose footprints pass the device's largest point: clamped) and
    // at the largest subdivision.
    use underlight::scene::CausticEstimator;
    let ctx = validated_context();
    let footprint = |mut s: Scene| {
        s.effects.caustic_estimator = CausticEstimator::Footprint;
        s
    };
    carries_the_points_light_under_every_sun(&ctx, "footprint points", footprint);
    let mut violent = overview(0.3);
    violent.water.wavelength = 0.5;
    overview_flux(&ctx, &footprint(violent), 0.7, "footprint points, violent waves");
    let mut short = overview(0.002);
    short.water.wavelength = 0.01;
    overview_flux(&ctx, &footprint(short), 0.0, "footprint points, 1 cm wavelength");
    let mut coarsest = overview(0.04);
    coarsest.effects.caustic_grid = 1;
    coarsest.effects.caustic_subdivision = CausticEstimator::Footprint.min_subdivision();
    overview_flux(&ctx, &footprint(coarsest), 0.0, "footprint points, 1×1 grid of 2×2 photons");
    let mut most = overview(0.04);
    most.effects.caustic_grid = 24;
    most.effects.caustic_subdivision = CausticEstimator::Footprint.max_subdivision();
    overview_flux(&ctx, &footprint(most), 0.0, "footprint points, subdivision at the output limit");
    assert_clean_shutdown(ctx);
}

#[test]
fn medium_at_its_limits() {
    let ctx = validated_context();
    let mut clear = overview(0.04);
    clear.medium.gamma = Vec3::ZERO;
    let clear_flux = overview_flux(&ctx, &clear, 0.0, "γ = 0");
    assert!(clear_flux > 0.0);
    let mut murky = overview(0.04);
    murky.medium.gamma = Vec3::splat(50.0);
    let murky_flux = overview_flux(&ctx, &murky, 0.0, "γ = 50 /m");
    assert!(murky_flux < 1e-6 * clear_flux, "2 m of γ = 50 /m water lets {murky_flux} W through");
    let mut godray_means = Vec::new();
    for g in [-0.99f32, 0.0, 0.98, 0.99] {
        let mut s = pool(0.04);
        s.output = [48, 48];
        s.camera.position = Vec3::new(-2.0, -1.0, 0.0);
        s.camera.look_at = Vec3::new(2.0, -1.2, 0.3);
        s.medium.hg_g = g;
        s.effects.godray_grid = 24;
        s.effects.caustic_grid = 48;
        let images = render(&ctx, &s, 0.0, &format!("g = {g}"));
        godray_means.push(images.godrays.unwrap().channel_sums()[0]);
    }
    let mut no_scatter = pool(0.04);
    no_scatter.medium.scattering = 0.0;
    let images = render(&ctx, &no_scatter, 0.0, "σs = 0");
    assert!(images.godrays.is_none(), "a medium that does not scatter still draws godrays");
    assert_clean_shutdown(ctx);
    eprintln!("godray sums for g = -0.99, 0, 0.98, 0.99: {godray_means:?}");
    assert!(godray_means.iter().all(|m| *m > 0.0));
    // Away from the forward peak the phase function scales with (1 − g²), which halves from
    // g = 0.98 to 0.99 (ratio 0.503): the godrays must follow that, not jump.
    let (g98, g99) = (godray_means[2], godray_means[3]);
    let expected = (1.0 - 0.99f64 * 0.99) / (1.0 - 0.98 * 0.98);
    assert!(
        (g99 / g98 / expected - 1.0).abs() < 0.3,
        "godrays from g = 0.98 to 0.99: ×{} (expected about ×{expected:.3})",
        g99 / g98
    );
}

/// Cameras at, just off and far from the water plane, and on the floor.
const WATERLINE_CAMERAS: [(&str, Vec3, Vec3); 6] = [
    ("at the water plane", Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, -0.5, 0.0)),
    ("1 cm above", Vec3::new(-3.0, 0.01, 0.0), Vec3::new(3.0, -0.5, 0.0)),
    ("1 cm below", Vec3::new(-3.0, -0.01, 0.0), Vec3::new(3.0, -0.5, 0.0)),
    ("above, looking down", Vec3::new(0.0, 3.0, 0.5), Vec3::new(0.0, -FLOOR_DEPTH, 0.0)),
    ("far below the floor", Vec3::new(0.0, -50.0, 0.0), Vec3::new(0.0, 0.0, 0.1)),
    ("on the floor, looking up", Vec3::new(1.0, -FLOOR_DEPTH + 1e-3, 0.0), Vec3::new(1.0, 0.0, 0.0)),
];

/// The wavy pool at 48×48, small grids, seen from `position` towards `look_at`.
fn waterline_view(position: Vec3, look_at: Vec3) -> Scene {
    let mut s = pool(0.04);
    s.water.noise_amplitude = 0.02;
    s.output = [48, 48];
    s.effects.caustic_grid = 48;
    s.effects.godray_grid = 16;
    s.camera.position = position;
    s.camera.look_at = look_at;
    s.camera.z_far = 100.0;
    s
}

#[test]
fn camera_at_and_around_the_waterline() {
    let ctx = validated_context();
    for (label, position, look_at) in WATERLINE_CAMERAS {
        render(&ctx, &waterline_view(position, look_at), 0.5, label);
    }
    let projections: [(&str, f32, f32, f32); 4] = [
        ("z_near 10 µm", 1e-5, 10.0, 60.0),
        ("z_far 1000 km", 0.05, 1e6, 60.0),
        ("fov 0.01°", 0.05, 10.0, 0.01),
        ("fov 179.9°", 0.05, 10.0, 179.9),
    ];
    for (label, near, far, fov) in projections {
        let mut s = pool(0.04);
        s.output = [48, 48];
        s.effects.caustic_grid = 48;
        s.camera.z_near = near;
        s.camera.z_far = far;
        s.camera.fov_y_degrees = fov;
        render(&ctx, &s, 0.0, label);
    }
    assert_clean_shutdown(ctx);
}

#[test]
fn smallest_grids_and_targets_and_sizes_beyond_the_device() {
    let ctx = validated_context();
    let mut one = overview(0.04);
    one.effects.caustic_grid = 1;
    one.effects.caustic_subdivision = 1;
    one.effects.godray_grid = 1;
    one.effects.godray_subdivision = 1;
    overview_flux(&ctx, &one, 0.0, "1×1 photon grids");
    let mut most = overview(0.04);
    most.effects.caustic_grid = 12;
    most.effects.caustic_subdivision = underlight::shader_math::MAX_SUBDIVISION;
    most.effects.godray_grid = 8;
    most.effects.godray_subdivision = underlight::shader_math::GODRAY_MAX_SUBDIVISION;
    overview_flux(&ctx, &most, 0.0, "subdivision at the geometry shaders' output limits");
    let mut pixel = pool(0.04);
    pixel.output = [1, 1];
    pixel.effects.caustic_grid = 16;
    render(&ctx, &pixel, 0.0, "1×1 output");
    let mut large_targets = pool(0.04);
    large_targets.output = [32, 32];
    large_targets.effects.caustic_target_scale = 4.0;
    large_targets.effects.godray_target_scale = 4.0;
    large_targets.effects.caustic_grid = 32;
    render(&ctx, &large_targets, 0.0, "effect targets 4× the output");

    let limits = *ctx.device.limits();
    let mut huge = overview(0.04);
    huge.effects.point_size_min = 2.0 * limits.point_size_range[1];
    huge.effects.point_size_max = 4.0 * limits.point_size_range[1];
    huge.effects.line_width = 4.0 * limits.line_width_range[1];
    overview_flux(&ctx, &huge, 0.0, "point sizes and line width beyond the device's");
    let plan = underlight::frame::FramePlan::for_scene(&huge);
    let notes = underlight::frame::device_clamps(&huge, &plan, &ctx.device);
    assert_eq!(notes.len(), 3, "each clamped setting is reported: {notes:?}");
    assert!(notes[0].contains("effects.point_size_min") && notes[2].contains("effects.line_width"), "{notes:?}");
    assert_clean_shutdown(ctx);
}

/// The largest grids a scene file accepts (4096² cells, 16.8 M photons per effect), at one
/// photon per cell: the photon index covers them, no photon is cast twice or lost (the flux
/// equals the 96-cell grid's within sampling noise), and the frame stays finite and clean.
/// (4096² × the full subdivision, 10⁹ photons, takes minutes per frame on lavapipe: the
/// largest subdivision is covered on a small grid above.)
#[test]
fn largest_photon_grids() {
    let ctx = validated_context();
    let mut base = overview(0.04);
    base.output = [16, 16];
    base.effects.caustic_grid = 192;
    base.effects.caustic_subdivision = 1;
    let reference = overview_flux(&ctx, &base, 0.0, "192² caustic photons");
    let mut largest = base.clone();
    largest.effects.caustic_grid = 4096;
    largest.effects.godray_grid = 4096;
    largest.effects.godray_subdivision = 1;
    let started = std::time::Instant::now();
    let flux = overview_flux(&ctx, &largest, 0.0, "4096² caustic and godray photons");
    eprintln!("largest grids: one frame in {:.1} s", started.elapsed().as_secs_f64());
    assert!((flux / reference - 1.0).abs() < 0.03, "4096² photons carry {flux} W in view, 192² carry {reference} W");
    assert_clean_shutdown(ctx);
}

#[test]
fn point_light_above_in_and_under_the_water() {
    let ctx = validated_context();
    let mut fluxes = Vec::new();
    for (label, y) in [("1 m above", 1.0f32), ("in the waves", 0.01), ("under the water", -0.5)] {
        let mut s = overview(0.04);
        s.light.kind = LightKind::Point;
        s.light.position = Vec3::new(0.3, y, 0.2);
        s.light.intensity = 9.2;
        assert!(surface_irradiance(&s).is_finite());
        let images = render(&ctx, &s, 0.0, label);
        match images.caustics {
            Some(c) => {
                let on_floor = floor_flux_in_view(&s, &c);
                let entering = flux_into_water(&s);
                eprintln!("point light {label}: {on_floor:.3} W in view of {entering:.3} W");
                assert!(on_floor <= entering, "point light {label}: {on_floor} W in view, {entering} W entering");
                fluxes.push(on_floor);
            }
            None => {
                assert!(y < 0.0, "a point light {label} draws no caustics");
                let plan = underlight::frame::FramePlan::for_scene(&s);
                assert!(plan.to_string().contains("under the water"), "{plan}");
            }
        }
    }
    assert_clean_shutdown(ctx);
    assert!(fluxes.iter().all(|f| *f > 0.0), "{fluxes:?}");
}

/// A camera looking straight down with a far z_far and a near sun (`light.distance` = 10 m)
/// used to put the directional light's frame under the water: every photon was dropped and
/// the caustic buffer was zero without a word. The frame is now placed from the scene's
/// bounds; the caustic flux on the floor is what enters the water.
#[test]
fn directional_light_never_sits_under_the_water() {
    let ctx = validated_context();
    let mut scene = overview(0.0);
    scene.camera.position = Vec3::new(0.0, -0.1, 0.0);
    scene.camera.z_far = 20.0;
    scene.light.distance = 10.0;
    let images = render(&ctx, &scene, 0.0, "z_far 20, distance 10");
    assert!(images.silent_effects(&scene).is_empty(), "{:?}", images.silent_effects(&scene));
    let share = floor_flux_in_view(&scene, images.caustics.as_ref().unwrap()) / flux_into_water(&scene);
    // The distance scales the irradiance only: the share of the entering flux that lands on
    // the floor in view is the same as with the sun 100 m away (0.23 at a zenith sun).
    let mut far = scene.clone();
    far.light.distance = 100.0;
    let far_images = render(&ctx, &far, 0.0, "z_far 20, distance 100");
    let far_share = floor_flux_in_view(&far, far_images.caustics.as_ref().unwrap()) / flux_into_water(&far);
    assert!(share > 0.1, "share of the entering flux on the floor: {share}");
    assert!((share / far_share - 1.0).abs() < 0.01, "share {share} at 10 m, {far_share} at 100 m");
    assert_clean_shutdown(ctx);
}

/// An effect that runs and lands nothing is reported, naming the effect and what to check:
/// here the water lies far from everything the camera sees.
#[test]
fn an_effect_that_deposits_nothing_is_reported() {
    let ctx = validated_context();
    let mut scene = overview(0.05);
    scene.water.extent_min = glam::Vec2::new(40.0, 40.0);
    scene.water.extent_max = glam::Vec2::new(41.0, 41.0);
    let images = render(&ctx, &scene, 0.0, "water far away");
    let notes = images.silent_effects(&scene);
    assert!(notes.iter().any(|n| n.starts_with("caustics ran but no photon landed")), "{notes:?}");
    assert!(notes.iter().any(|n| n.starts_with("godrays ran but no beam")), "{notes:?}");
    assert!(notes.iter().all(|n| n.contains("water.extent_min")), "{notes:?}");
    // And the shipped scenes deposit something.
    let tank = underlight::scene::load("tank").unwrap();
    let mut small = tank.clone();
    small.output = [64, 48];
    let images = render(&ctx, &small, 0.0, "tank");
    assert!(images.silent_effects(&small).is_empty(), "{:?}", images.silent_effects(&small));
    assert_clean_shutdown(ctx);
}

/// The ray-marched godrays (`effects.godray_method = "marched"`) through the extremes the
/// beams go through above: the camera at, just off and far from the water plane, the
/// projection's limits, a grazing and a straight-down sun, clear and murky water and the
/// phase function's limits. Every frame is finite and clean, and one whose camera looks
/// through the water at a scattering medium gets godrays.
/// The photons and beams spread for the view (`caustic_photon_density` and
/// `godray_photon_density = "view"`) through the cameras, projections and suns above: every
/// frame is finite and clean, and where the camera sees the lit floor whole (the overview) the
/// caustic flux in view is the even grid's, within 2 %: the warp moves photons, not light.
#[test]
fn photons_spread_for_the_view_at_the_extremes() {
    use underlight::scene::PhotonSpread;
    let ctx = validated_context();
    let spread = |s: &mut Scene| {
        s.effects.caustic_photon_density = PhotonSpread::View;
        s.effects.godray_photon_density = PhotonSpread::View;
    };
    // The cameras of `camera_at_and_around_the_waterline`, and one that sees no water at all
    // (the survey finds nothing and the grids stay even).
    let sky = ("above, looking at the sky", Vec3::new(0.0, 3.0, 0.0), Vec3::new(0.3, 9.0, 0.0));
    for (label, position, look_at) in WATERLINE_CAMERAS.into_iter().chain([sky]) {
        let mut s = waterline_view(position, look_at);
        spread(&mut s);
        render(&ctx, &s, 0.5, &format!("spread for the view, {label}"));
    }
    for (label, near, far, fov) in [("z_near 10 µm", 1e-5, 10.0, 60.0), ("fov 0.01°", 0.05, 10.0, 0.01)] {
        let mut s = pool(0.04);
        s.output = [48, 48];
        s.effects.caustic_grid = 48;
        (s.camera.z_near, s.camera.z_far, s.camera.fov_y_degrees) = (near, far, fov);
        spread(&mut s);
        render(&ctx, &s, 0.0, &format!("spread for the view, {label}"));
    }
    for (label, direction) in [("grazing sun", sun(2.0, 30.0)), ("straight down", sun(90.0, 0.0))] {
        let mut even = overview(0.05);
        even.light.direction = direction;
        let mut view = even.clone();
        spread(&mut view);
        let a = overview_flux(&ctx, &even, 0.5, &format!("even grid, {label}"));
        let b = overview_flux(&ctx, &view, 0.5, &format!("spread for the view, {label}"));
        assert!(b > 0.0 && (b / a - 1.0).abs() < 0.02, "{label}: flux in view {b} spread against {a} even");
    }
    assert_clean_shutdown(ctx);
}

#[test]
fn marched_godrays_at_the_extremes() {
    godrays_at_the_extremes(underlight::scene::GodrayMethod::Marched);
}

/// The ribbons' widths come from neighbouring rays and the camera's distance: a camera on the
/// water plane or on the floor looking up along the beams (sin θ → 0), a vanishing or huge
/// field of view, a grazing sun.
#[test]
fn footprint_beams_at_the_extremes() {
    godrays_at_the_extremes(underlight::scene::GodrayMethod::Footprint);
}

/// Every camera, projection, sun and medium extreme through one godray method: validation
/// clean and finite (`render`), and light wherever the view crosses sunlit water.
fn godrays_at_the_extremes(method: underlight::scene::GodrayMethod) {
    let ctx = validated_context();
    let name = method.name();
    let godrays_of = |label: &str, f: &dyn Fn(&mut Scene)| {
        let mut s = pool(0.04);
        s.water.noise_amplitude = 0.02;
        s.output = [48, 48];
        s.effects.caustic_grid = 48;
        s.effects.godray_grid = 48;
        s.effects.godray_method = method;
        s.camera.position = Vec3::new(-2.0, -1.0, 0.0);
        s.camera.look_at = Vec3::new(2.0, -1.2, 0.3);
        f(&mut s);
        let images = render(&ctx, &s, 0.5, &format!("{name}, {label}"));
        images.godrays.map_or(0.0, |g| g.channel_sums()[0])
    };
    let cameras: [(&str, Vec3, Vec3); 5] = [
        ("at the water plane", Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, -0.5, 0.0)),
        ("1 cm above", Vec3::new(-3.0, 0.01, 0.0), Vec3::new(3.0, -0.5, 0.0)),
        ("1 cm below", Vec3::new(-3.0, -0.01, 0.0), Vec3::new(3.0, -0.5, 0.0)),
        ("above, looking down", Vec3::new(0.0, 3.0, 0.5), Vec3::new(0.0, -FLOOR_DEPTH, 0.0)),
        ("on the floor, looking up", Vec3::new(1.0, -FLOOR_DEPTH + 1e-3, 0.0), Vec3::new(1.0, 0.0, 0.0)),
    ];
    for (label, position, look_at) in cameras {
        let sum = godrays_of(label, &|s| {
            s.camera.position = position;
            s.camera.look_at = look_at;
            s.camera.z_far = 100.0;
        });
        assert!(sum > 0.0, "{name}, {label}: no godrays through the water");
    }
    for (label, near, far, fov) in
        [("z_near 10 µm", 1e-5, 10.0, 60.0), ("z_far 1000 km", 0.05, 1e6, 60.0), ("fov 0.01°", 0.05, 10.0, 0.01)]
    {
        let sum = godrays_of(label, &|s| {
            s.camera.z_near = near;
            s.camera.z_far = far;
            s.camera.fov_y_degrees = fov;
        });
        assert!(sum > 0.0, "{name}, {label}: no godrays");
    }
    godrays_of("fov 179.9°", &|s| s.camera.fov_y_degrees = 179.9);
    for elevation in [90.0f32, 10.0, 1.0] {
        let sum = godrays_of(&format!("sun at {elevation}°"), &|s| {
            s.light.direction = if elevation == 90.0 { Vec3::NEG_Y } else { sun(elevation, 30.0) };
        });
        assert!(sum > 0.0, "{name}, sun at {elevation}°: no godrays");
    }
    let clear = godrays_of("γ = 0", &|s| s.medium.gamma = Vec3::ZERO);
    let murky = godrays_of("γ = 50 /m", &|s| s.medium.gamma = Vec3::splat(50.0));
    assert!(clear > 0.0 && murky < 1e-3 * clear, "{name}: γ = 0: {clear}, γ = 50 /m: {murky}");
    for g in [-0.99f32, 0.99] {
        let sum = godrays_of(&format!("g = {g}"), &|s| s.medium.hg_g = g);
        assert!(sum > 0.0, "{name}, g = {g}: no godrays");
    }
    assert_clean_shutdown(ctx);
}
