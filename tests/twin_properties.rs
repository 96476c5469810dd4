//! Property tests of the CPU twin of the shader math (`src/shader_math.rs`, the twin of
//! `glsl/shared/shader_math.glsl` and `glsl/photons/photon_cast.glsl`; tests/method.rs checks the GPU agrees with it)
//! over wide parameter ranges, including the extremes users reach: grazing and straight-down
//! sun, flat to violent water, late times, g at ±0.99, tiny and huge view distances.
//! Each property is one a broken formula fails: a NaN, a direction that is not unit, a
//! hit off the surface, a size outside its range.

mod common;

use glam::{Vec2, Vec3};
use proptest::prelude::*;
use underlight::frame::uniforms::{FrameExtents, FrameUniforms};
use underlight::image_io::HdrImage;
use underlight::scene::{Water, WaterModel};
use underlight::shader_math::*;

/// A unit direction `elevation_deg` below the horizon, at `azimuth_deg`.
fn downward(elevation_deg: f32, azimuth_deg: f32) -> Vec3 {
    let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
    Vec3::new(e.cos() * a.cos(), -e.sin(), e.cos() * a.sin())
}

fn water(model: WaterModel, amplitude: f32, wavelength: f32, noise_amplitude: f32) -> Water {
    Water {
        model,
        level: 0.0,
        amplitude,
        wavelength,
        speed: 0.7,
        noise_amplitude,
        noise_scale: 3.0,
        center: Vec2::new(0.3, -0.2),
        extent_min: Vec2::splat(-1e4),
        extent_max: Vec2::splat(1e4),
        ior: 1.333,
    }
}

fn model() -> impl Strategy<Value = WaterModel> {
    prop_oneof![Just(WaterModel::CircularCosine), Just(WaterModel::AxisCosineNoise)]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Refraction into water: a unit direction, Snell's law, and it goes into the water.
    #[test]
    fn refraction_obeys_snells_law(
        elevation in 0.5f32..90.0, azimuth in 0f32..360.0,
        tilt in 0f32..85.0, tilt_azimuth in 0f32..360.0, ior in 1.0001f32..3.0,
    ) {
        let i = downward(elevation, azimuth);
        let n = -downward(90.0 - tilt, tilt_azimuth); // a normal tilted `tilt` from +y
        let cos_i = (-i).dot(n);
        prop_assume!(cos_i > 1e-3); // the ray meets the front of the surface
        let t = refract(i, n, 1.0 / ior);
        prop_assert!(t.is_finite());
        prop_assert!((t.length() - 1.0).abs() < 1e-4, "|t| = {}", t.length());
        let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
        let sin_t = (1.0 - t.dot(n).powi(2)).max(0.0).sqrt();
        prop_assert!((ior * sin_t - sin_i).abs() < 2e-3, "n sin θt = {} vs sin θi = {}", ior * sin_t, sin_i);
        prop_assert!(t.dot(n) < 0.0, "the refracted ray leaves the water");
    }

    /// Fresnel transmittance into a denser medium: in [0, 1], finite, and not decreasing
    /// towards normal incidence.
    #[test]
    fn fresnel_transmittance_is_a_fraction_growing_towards_normal(cos_i in -0.5f32..1.5, step in 0f32..0.5, ior in 1.0001f32..3.0) {
        let t = fresnel_transmittance(cos_i, ior);
        prop_assert!(t.is_finite() && (0.0..=1.0).contains(&t), "T = {t}");
        prop_assert!(fresnel_transmittance(cos_i + step, ior) >= t - 1e-6);
    }

    /// Henyey–Greenstein: finite and positive for every angle and g in (−1, 1), the
    /// extremes ±0.99 included.
    #[test]
    fn phase_function_is_finite_and_positive(cos_t in -1f32..=1.0, g in prop_oneof![Just(-0.99f32), Just(0.99f32), -0.99f32..=0.99]) {
        let p = henyey_greenstein(cos_t, g);
        prop_assert!(p.is_finite() && p > 0.0, "p({cos_t}, {g}) = {p}");
    }

    /// The distance-regulated point size stays in [s_min, s_max] at any distance, also
    /// nearer than z_near and farther than z_far.
    #[test]
    fn point_size_stays_in_its_range(
        d in prop_oneof![Just(0.0f32), Just(1e9f32), 0f32..1e6], near in 1e-5f32..10.0, depth_ratio in 1.001f32..1e6,
        s_min in 0.1f32..50.0, spread in 0f32..200.0,
    ) {
        let far = near * depth_ratio;
        let s = regulated_point_size(d, near, far, s_min, s_min + spread);
        prop_assert!(s.is_finite(), "size {s}");
        prop_assert!(s >= s_min * (1.0 - 1e-4) - 1e-4 && s <= (s_min + spread) * (1.0 + 1e-4) + 1e-4,
            "size {s} outside [{s_min}, {}] at d = {d} (near {near}, far {far})", s_min + spread);
    }

    /// The water surface is finite everywhere and at any time, however steep or small.
    #[test]
    fn water_surface_is_finite(
        model in model(), amplitude in prop_oneof![Just(0.0f32), 0f32..2.0], wavelength in 0.01f32..100.0,
        noise in 0f32..0.5, x in -1e4f32..1e4, z in -1e4f32..1e4, time in prop_oneof![Just(0.0f32), 0f32..1e6],
    ) {
        let noise_tex = NoiseTexture::generate();
        let w = water(model, amplitude, wavelength, noise);
        let hg = water_height_grad(&w, &noise_tex, Vec2::new(x, z), time);
        prop_assert!(hg.is_finite(), "{hg}");
        prop_assert!(hg.x.abs() <= amplitude + noise + 1e-4, "height {} beyond the amplitudes", hg.x);
        prop_assert!(water_normal_from_grad(Vec2::new(hg.y, hg.z)).is_finite());
    }

    /// The ray–surface intersection lands on the surface, from grazing (1°) to straight
    /// down, for flat to steep water. Waves steeper than any real sea (slope A·k > 1.5,
    /// beyond the 0.9 at which real waves break) may also report a miss, never a hit off
    /// the surface.
    #[test]
    fn surface_intersection_lands_on_the_surface(
        model in model(), amplitude in prop_oneof![Just(0.0f32), 0f32..0.3], wavelength in 0.05f32..50.0,
        noise in 0f32..0.1, elevation in prop_oneof![Just(90.0f32), Just(1.0f32), 1f32..90.0], azimuth in 0f32..360.0,
        height in 0.05f32..100.0, x in -50f32..50.0, z in -50f32..50.0, time in 0f32..1e5,
    ) {
        let noise_tex = NoiseTexture::generate();
        let w = water(model, amplitude, wavelength, noise);
        let o = Vec3::new(x, amplitude + noise + height, z);
        let d = downward(elevation, azimuth);
        let t = water_intersect(&w, &noise_tex, o, d, time);
        prop_assert!(t.is_finite(), "t = {t}");
        let slope = amplitude * std::f32::consts::TAU / wavelength + noise * 16.0 * 2.0 / 3.0;
        if t < 0.0 {
            prop_assert!(slope > 1.5, "a ray from above the water missed waves of slope {slope}");
            return Ok(());
        }
        let p = o + t * d;
        let surface = w.level + water_height_grad(&w, &noise_tex, Vec2::new(p.x, p.z), time).x;
        // Within 1 mm, or 1 % of the waves' height where they are large.
        let tolerance = 1e-3f32.max(0.01 * (amplitude + noise));
        prop_assert!((p.y - surface).abs() < tolerance, "hit {} m off the surface (t = {t})", p.y - surface);
    }
}

/// The light's receiver-position map of a flat floor `depth` m below the water: what the
/// shadow pass writes (world position, w = 1) for each texel, computed analytically.
fn flat_floor_light_map(u: &FrameUniforms, size: u32, depth: f32) -> HdrImage {
    let inv = glam::Mat4::from_cols_array_2d(&u.light_inv_view_proj);
    let mut pixels = Vec::with_capacity((size * size) as usize);
    for y in 0..size {
        for x in 0..size {
            let ndc = (Vec2::new(x as f32 + 0.5, y as f32 + 0.5) / size as f32) * 2.0 - 1.0;
            let a = inv * glam::Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
            let b = inv * glam::Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
            let o = a.truncate() / a.w;
            let d = (b.truncate() / b.w - o).normalize();
            let t = (-depth - o.y) / d.y;
            let p = o + t * d;
            pixels.push(if t > 0.0 && p.x.abs() <= 6.0 && p.z.abs() <= 6.0 { [p.x, p.y, p.z, 1.0] } else { [0.0; 4] });
        }
    }
    HdrImage { width: size, height: size, pixels }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Whole photons, through the image-space iteration against a flat floor's light map:
    /// every photon is either dropped or lands on the floor with a finite, positive flux no
    /// larger than its share of the light; none lands at the origin or the far plane.
    #[test]
    fn photons_land_on_receivers_or_are_dropped(
        elevation in prop_oneof![Just(90.0f32), Just(1.0f32), 1f32..90.0], azimuth in 0f32..360.0,
        amplitude in prop_oneof![Just(0.0f32), 0f32..0.3], wavelength in 0.05f32..20.0, time in prop_oneof![Just(0.0f32), 0f32..1e5],
        iterations in 1u32..8,
    ) {
        let mut scene = common::pool(amplitude);
        scene.water.wavelength = wavelength;
        scene.light.direction = downward(elevation, azimuth);
        scene.effects.iterations = iterations;
        let map_size = 128;
        let extents = FrameExtents {
            output: scene.output,
            caustic: scene.output,
            godray: scene.output,
            light_map: map_size,
            max_point_size: 64.0,
            max_line_width: 16.0,
        };
        let u = FrameUniforms::new(&scene, scene.bounds(), &extents, time);
        let noise = NoiseTexture::generate();
        let map = flat_floor_light_map(&u, map_size, common::FLOOR_DEPTH);
        let normals = HdrImage { width: map_size, height: map_size, pixels: map.pixels.iter().map(|p| [0.0, p[3], 0.0, 0.0]).collect() };
        // The floor lies open to every direction: the first maps place every photon.
        let caster = PhotonCaster { uniforms: &u, noise: &noise, light_map: &map, light_normals: &normals, steep_maps: None };
        let per_axis = 24.0f32;
        // The shader's convergence test: the hit lies within 3 texels or 5 % of the distance
        // travelled of the plane of the receiver at its texel (photon_cast.glsl).
        let texel = 2.0 * u.light_half_extent[0].max(u.light_half_extent[1]) / map_size as f32;
        // The most one photon can carry: E⊥ through its share of the light's window.
        let share = u.light_strength * 4.0 * u.light_half_extent[0] * u.light_half_extent[1] / (per_axis * per_axis);
        for j in 0..24 {
            for i in 0..24 {
                let uv = (Vec2::new(i as f32, j as f32) + 0.5) / per_axis;
                let Some(ph) = caster.cast(uv, glam::Vec2::splat(per_axis)) else { continue };
                prop_assert!(ph.hit.is_finite() && ph.surface.is_finite() && ph.direction.is_finite());
                prop_assert!(ph.flux.is_finite() && ph.flux > 0.0 && ph.flux <= share * 1.0001, "flux {} (share {share})", ph.flux);
                let off = (ph.hit.y + common::FLOOR_DEPTH).abs();
                prop_assert!(off <= (3.0 * texel).max(0.05 * ph.travelled) * 1.01, "a photon lands {off} m off the floor");
                prop_assert!(ph.travelled.is_finite() && ph.travelled > 0.0);
            }
        }
    }
}
