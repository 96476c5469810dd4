//! Each built-in scene renders on the real driver with validation, at a reduced size: every
//! pass runs and is timed, no target holds NaN or Inf, caustics and godrays carry light, and
//! the picture is not flat.

mod common;

use common::{assert_clean_shutdown, validated_context};
use underlight::headless::SceneRenderer;
use underlight::passes::PassId;
use underlight::scene::{self, BUILTIN_SCENES};
use underlight::vk::vk;

#[test]
fn every_builtin_scene_renders_cleanly() {
    for name in BUILTIN_SCENES {
        let mut scene = scene::load(name).unwrap();
        // A fifth of the paper's resolution and a quarter of its photons: the same frame,
        // sized for a CPU rasteriser.
        let out = vk::Extent2D { width: scene.output[0] / 5, height: scene.output[1] / 5 };
        scene.effects.caustic_grid /= 2;
        scene.effects.godray_grid /= 2;
        scene.effects.shadow_map_size = 512;
        let ctx = validated_context();
        let mut renderer = SceneRenderer::new(&ctx.device, &scene, out).unwrap();
        let (timings, images) = renderer.render(2, 1.0, 0.1, true).unwrap();
        drop(renderer);
        assert_clean_shutdown(ctx);
        let images = images.unwrap();
        // The caustic buffer is filtered exactly when the plan says so (the paper's points;
        // the triangle estimator the scenes ship needs none).
        let plan = underlight::frame::FramePlan::for_scene(&scene);
        assert_eq!(images.caustics_filtered.is_some(), plan.filters_caustics, "{name}: filtered caustics");
        let last = timings.last().unwrap();
        for pass in [PassId::Shadow, PassId::Scene, PassId::Caustics, PassId::Godrays, PassId::Filter, PassId::Compose]
        {
            assert!(last.get(pass).is_some_and(|ms| ms > 0.0), "{name}: {pass} missing or untimed\n{last}");
        }
        for (what, img) in [
            ("scene colour", Some(&images.scene_color)),
            ("caustics", images.caustics.as_ref()),
            ("godrays", images.godrays.as_ref()),
            ("filtered godrays", images.godrays_filtered.as_ref()),
        ] {
            let img = img.unwrap_or_else(|| panic!("{name}: no {what} buffer"));
            assert!(!img.has_non_finite(), "{name}: NaN or Inf in {what}");
            assert!(img.channel_sums()[0] > 0.0, "{name}: {what} is black");
        }
        // The output is a picture, not a flat fill: its luminance spreads.
        let lum: Vec<f64> = images.output.chunks_exact(4).map(|p| p[0] as f64 + p[1] as f64 + p[2] as f64).collect();
        let mean = lum.iter().sum::<f64>() / lum.len() as f64;
        let sd = (lum.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / lum.len() as f64).sqrt();
        assert!(sd > 10.0 && mean > 20.0 && mean < 700.0, "{name}: output mean {mean}, spread {sd}");
    }
}
