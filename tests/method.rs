//! The method end to end on the real driver, against figures that only a correct renderer
//! gives: flat water under a zenith sun lights a pool floor uniformly with the analytic
//! irradiance E⊥·T(0)·e^(−γ·depth) (docs/units.md), and waves focus that light into caustics
//! without creating or losing energy.

mod common;

use common::{assert_clean_shutdown, validated_context};
use glam::{Vec2, Vec3};
use underlight::frame::uniforms::directional_irradiance;
use underlight::frame::FramePlan;
use underlight::headless::{SceneImages, SceneRenderer};
use underlight::image_io::HdrImage;
use underlight::passes::PassId;
use underlight::scene::*;
use underlight::shader_math::fresnel_transmittance;
use underlight::vk::vk;

const FLOOR_DEPTH: f32 = 2.0;

/// A square pool floor `FLOOR_DEPTH` below flat or wavy water, a camera under water looking
/// straight down at it, and a sun straight above.
fn pool(amplitude: f32) -> Scene {
    let half = 6.0;
    let floor = Mesh {
        name: "floor".into(),
        positions: vec![
            Vec3::new(-half, -FLOOR_DEPTH, -half),
            Vec3::new(half, -FLOOR_DEPTH, -half),
            Vec3::new(half, -FLOOR_DEPTH, half),
            Vec3::new(-half, -FLOOR_DEPTH, half),
        ],
        normals: vec![Vec3::Y; 4],
        indices: vec![0, 2, 1, 0, 3, 2],
        albedo: Vec3::splat(0.8),
    };
    Scene {
        name: "pool".into(),
        output: [96, 96],
        camera: Camera {
            position: Vec3::new(0.0, -0.5, 0.0),
            look_at: Vec3::new(0.0, -FLOOR_DEPTH, 0.0),
            fov_y_degrees: 60.0,
            z_near: 0.05,
            z_far: 10.0,
        },
        light: Light {
            kind: LightKind::Directional,
            direction: Vec3::NEG_Y,
            position: Vec3::ZERO,
            intensity: 9.2,
            distance: 100.0,
        },
        water: Water {
            model: WaterModel::AxisCosineNoise,
            level: 0.0,
            amplitude,
            wavelength: 0.8,
            speed: 0.5,
            noise_amplitude: 0.0,
            noise_scale: 4.0,
            center: Vec2::ZERO,
            extent_min: Vec2::splat(-half),
            extent_max: Vec2::splat(half),
            ior: 1.333,
        },
        medium: Medium { gamma: Vec3::splat(0.13), scattering: 0.05, hg_g: 0.5 },
        effects: Effects {
            caustic_grid: 160,
            caustic_subdivision: 2,
            caustic_target_scale: 1.0,
            point_size_min: 3.0,
            point_size_max: 12.0,
            shadow_map_size: 256,
            ..Effects::default()
        },
        meshes: vec![floor],
    }
}

fn render(scene: &Scene) -> (SceneImages, Vec<underlight::vk::timing::PassTimings>) {
    let ctx = validated_context();
    let out = vk::Extent2D { width: scene.output[0], height: scene.output[1] };
    let mut renderer = SceneRenderer::new(&ctx.device, scene, out).unwrap();
    let (timings, images) = renderer.render(2, 1.0, 0.0, true).unwrap();
    drop(renderer);
    assert_clean_shutdown(ctx);
    (images.unwrap(), timings)
}

/// Mean, relative standard deviation and peak/mean of channel 0 over the central half of
/// the image (splats near the border are clipped, so edge pixels get too little), taken over
/// `block`×`block` pixel averages: a density estimate resolves nothing finer than its splat.
fn central_stats(img: &HdrImage, block: u32) -> (f64, f64, f64) {
    let (w, h) = (img.width, img.height);
    let mut v = Vec::new();
    for by in (h / 4..3 * h / 4).step_by(block as usize) {
        for bx in (w / 4..3 * w / 4).step_by(block as usize) {
            let mut sum = 0.0;
            for y in by..by + block {
                for x in bx..bx + block {
                    sum += img.at(x, y)[0] as f64;
                }
            }
            v.push(sum / (block * block) as f64);
        }
    }
    let mean = v.iter().sum::<f64>() / v.len() as f64;
    let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / v.len() as f64;
    let max = v.iter().cloned().fold(0.0, f64::max);
    (mean, var.sqrt() / mean, max / mean)
}

/// Mean of the central 24×24-pixel-equivalent disc over the mean of the ring around it (out to
/// half the image), on channel 0.
fn radial_ratio(img: &HdrImage) -> f64 {
    let (cx, cy) = (img.width as f64 / 2.0, img.height as f64 / 2.0);
    let r_max = img.width.min(img.height) as f64 / 4.0;
    let (mut inner, mut ni, mut outer, mut no) = (0.0, 0, 0.0, 0);
    for y in 0..img.height {
        for x in 0..img.width {
            let r = ((x as f64 + 0.5 - cx).powi(2) + (y as f64 + 0.5 - cy).powi(2)).sqrt();
            let v = img.at(x, y)[0] as f64;
            if r < r_max * 0.5 {
                inner += v;
                ni += 1;
            } else if r < r_max {
                outer += v;
                no += 1;
            }
        }
    }
    (inner / ni as f64) / (outer / no as f64)
}

#[test]
fn flat_water_lights_the_floor_with_the_analytic_irradiance() {
    let scene = pool(0.0);
    let (images, timings) = render(&scene);
    let caustics = images.caustics.as_ref().expect("the pool has caustics");
    assert!(!caustics.has_non_finite() && !images.scene_color.has_non_finite());
    let expected = directional_irradiance(&scene) as f64
        * fresnel_transmittance(1.0, scene.water.ior) as f64
        * (-0.13f64 * FLOOR_DEPTH as f64).exp();
    // Splats are 3 px here (s = 3.3 at 1.5 m, rounded): judge uniformity over 4×4 blocks.
    let (mean, rel_std, _) = central_stats(caustics, 4);
    // 3%: the splats' square footprint and the f16 target leave a small bias; a wrong
    // normalisation (pixel area, photon flux, Fresnel, attenuation) is off by far more.
    assert!((mean / expected - 1.0).abs() < 0.03, "floor irradiance {mean:e} W/m², analytic {expected:e}");
    // Uniform: a regular grid under flat water gives an even floor.
    // Photons lie on a regular lattice 0.72 px apart and splat over 3 px, so a 4 px block
    // holds 5 or 6 photons per axis: up to ~±9 % before the splats' overlap smooths it. 5 %
    // bounds that; a photon dropped in a pattern or a splat normalised per pixel fails it.
    assert!(rel_std < 0.05, "flat water should light the floor evenly: relative std {rel_std}");
    // No trend from the image centre outwards: a footprint missing the pinhole's cos³ falls
    // off by ~8 % between the centre and the edge of the region checked.
    let ring = radial_ratio(caustics);
    eprintln!("flat floor: mean {mean:e} W/m² (analytic {expected:e}), block std {rel_std}, centre/ring {ring}");
    assert!((ring - 1.0).abs() < 0.02, "centre/outer irradiance ratio {ring}");
    for t in &timings {
        for pass in [PassId::Shadow, PassId::Scene, PassId::Caustics, PassId::Compose] {
            assert!(t.get(pass).is_some_and(|ms| ms > 0.0), "{pass} missing from\n{t}");
        }
    }
}

#[test]
fn waves_focus_light_but_conserve_it() {
    let (flat, _) = render(&pool(0.0));
    let (wavy, _) = render(&pool(0.04));
    let (flat_mean, flat_std, flat_peak) = central_stats(flat.caustics.as_ref().unwrap(), 4);
    let (wavy_mean, wavy_std, wavy_peak) = central_stats(wavy.caustics.as_ref().unwrap(), 4);
    assert!(wavy_std > 10.0 * flat_std.max(0.02), "contrast: flat {flat_std}, wavy {wavy_std}");
    assert!(wavy_peak > 2.0 * flat_peak, "peaks: flat {flat_peak}, wavy {wavy_peak}");
    eprintln!("flat: mean {flat_mean:e} std {flat_std} peak {flat_peak}; wavy: mean {wavy_mean:e} std {wavy_std} peak {wavy_peak}");
    // Energy: the same light enters the water; waves only move it around (within the
    // visible patch up to what crosses its border).
    assert!((wavy_mean / flat_mean - 1.0).abs() < 0.1, "mean: flat {flat_mean:e}, wavy {wavy_mean:e}");
}

#[test]
fn plan_skips_what_the_scene_does_not_need() {
    let scene = pool(0.0);
    let plan = FramePlan::for_scene(&scene);
    assert!(plan.runs(PassId::Shadow) && plan.runs(PassId::Caustics));
    let mut off = scene.clone();
    off.effects.caustics = false;
    let plan = FramePlan::for_scene(&off);
    assert_eq!(plan.passes, vec![PassId::Scene, PassId::Compose], "{plan}");
    let mut dry = scene.clone();
    dry.water.level = -10.0; // everything above the water
    let plan = FramePlan::for_scene(&dry);
    assert!(!plan.runs(PassId::Caustics), "{plan}");

    // Skipped passes allocate nothing: the frame without caustics has no caustic target and
    // no light maps.
    let ctx = validated_context();
    let out = vk::Extent2D { width: 32, height: 32 };
    let renderer = SceneRenderer::new(&ctx.device, &off, out).unwrap();
    assert!(renderer.frame.caustics.is_none() && renderer.frame.shadow.is_none());
    drop(renderer);
    assert_clean_shutdown(ctx);
}
