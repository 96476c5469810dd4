//! The caustic photons' flux budget (`src/flux_budget.rs`, `render --flux-budget`) on the
//! built-in scenes, from the GPU's own photon records under validation: every photon is
//! accounted for, the light's power through the grid equals what lands, is reflected and is
//! dropped, and the grid covers the water rather than the light's whole window.

mod common;

use common::{assert_clean_shutdown, validated_context};
use underlight::flux_budget::{DropReason, FluxBudget};
use underlight::frame::uniforms::FrameUniforms;
use underlight::frame::FrameOptions;
use underlight::headless::SceneRenderer;
use underlight::scene::CausticEstimator;
use underlight::vk::vk;

#[test]
fn every_photon_and_watt_is_accounted_for() {
    let ctx = validated_context();
    for name in ["tank", "port", "storage"] {
        let mut scene = underlight::scene::load(name).unwrap();
        // Recording is the paper's points' geometry shader; the photons are the same.
        scene.effects.caustic_estimator = CausticEstimator::Paper;
        scene.effects.caustic_grid = 48;
        scene.effects.caustic_subdivision = 2;
        scene.effects.godrays = false;
        scene.effects.shadow_map_size = 512;
        let out = vk::Extent2D { width: 160, height: 100 };
        let options = FrameOptions { record_photons: true, ..Default::default() };
        let mut renderer = SceneRenderer::with_options(&ctx.device, &scene, out, options).unwrap();
        let extents = renderer.frame.extents;
        let (_, images) = renderer.render(1, 1.0, 0.0, true).unwrap();
        drop(renderer);
        let records = images.unwrap().photon_records.expect("photon records");
        let budget = FluxBudget::from_records(&records);
        let u = FrameUniforms::new(&scene, scene.bounds(), &extents, 1.0);
        let power = underlight::flux_budget::grid_power(&u).expect("the built-in scenes' light is directional");
        eprintln!("{name}:\n{budget}");
        assert_eq!(budget.cast, 96 * 96, "{name}: photons recorded");
        assert_eq!(budget.unknown, 0, "{name}: records with a code the budget does not know");
        let dropped: u64 = budget.dropped.iter().map(|s| s.photons).sum();
        assert_eq!(budget.landed.photons + dropped, budget.cast, "{name}: photons neither landed nor dropped");
        // What the landed photons lost to reflection at the surface: Fresnel at the built-in
        // scenes' sun (14° from the zenith) is about 2 %, so 0–5 % of the power; a photon
        // flux off by a factor (the window's area missing from N²) breaks this at once.
        let reflected = (power - budget.landed.watts - budget.dropped_watts()) / power;
        assert!(
            (0.0..0.05).contains(&reflected),
            "{name}: {:.2} % of the light's power unaccounted",
            100.0 * reflected
        );
        // The grid covers the water's footprint: photons outside the water are its rim, not
        // the half of the grid they were when it covered the light's whole window.
        let outside = budget.dropped[DropReason::OutsideWater as usize - 1].watts / power;
        assert!(outside < 0.1, "{name}: {:.1} % of the grid's power falls outside the water", 100.0 * outside);
        assert!(budget.landed.watts > 0.5 * power, "{name}: only {:.1} % lands", 100.0 * budget.landed.watts / power);
        // The light's maps see underwater receivers along the refracted light
        // (shader_math::light_map_point), so the receivers that refracted photons reach are in
        // them. Measured: 1.2 % (tank), 0.5 % (port), 0.8 % (storage) of the power does not
        // converge; mapped along the straight light ray, 5.6 %, 1.3 % and 4.7 % (at the
        // shipped 1024² maps), most of it beside shadow edges and on walls.
        let lost = budget.dropped[DropReason::NotConverged as usize - 1].watts / power;
        assert!(lost < 0.02, "{name}: {:.1} % of the grid's power does not converge", 100.0 * lost);
    }
    assert_clean_shutdown(ctx);
}
