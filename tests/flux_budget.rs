//! The caustic photons' flux budget (`src/flux_budget.rs`, `render --flux-budget`) on the
//! built-in scenes, from the GPU's own photon records under validation: every photon is
//! accounted for, the light's power through the grid equals what lands, is reflected and is
//! dropped, and the grid covers the water rather than the light's whole window.

mod common;

use common::{assert_clean_shutdown, validated_context};
use underlight::flux_budget::{DropReason, FluxBudget};
use underlight::frame::uniforms::FrameUniforms;
use underlight::frame::FrameOptions;
use underlight::headless::{SceneImages, SceneRenderer};
use underlight::scene::{CausticEstimator, GodrayMethod, PhotonSpread, Scene};
use underlight::vk::vk;

/// One frame of `scene` at 160×100, t = 1 s, with every photon recorded: its images and its
/// uniforms (the light's power, the camera).
fn recorded_frame(ctx: &underlight::vk::Context, scene: &Scene) -> (SceneImages, FrameUniforms) {
    let out = vk::Extent2D { width: 160, height: 100 };
    let options = FrameOptions { record_photons: true, ..Default::default() };
    let mut renderer = SceneRenderer::with_options(&ctx.device, scene, out, options).unwrap();
    let extents = renderer.frame.extents;
    let (_, images) = renderer.render(1, 1.0, 0.0, true).unwrap();
    (images.expect("read back"), FrameUniforms::new(scene, scene.bounds(), &extents, 1.0))
}

#[test]
fn every_photon_and_watt_is_accounted_for() {
    let ctx = validated_context();
    for name in ["tank", "port", "storage"] {
        let mut scene = underlight::scene::load(name).unwrap();
        // The triangles, which the scenes shipped until the footprint points: their photons
        // are recorded through the points' recording variant, on the triangles' grid, N/k ×
        // N·k coarse cells for the survey's k (the port's and the storage's are not 1).
        scene.effects.caustic_estimator = CausticEstimator::Triangles;
        scene.effects.caustic_grid = 48;
        scene.effects.caustic_subdivision = 2;
        scene.effects.godrays = false;
        scene.effects.shadow_map_size = 512;
        let (images, u) = recorded_frame(&ctx, &scene);
        let records = images.photon_records.expect("photon records");
        let mut budget = FluxBudget::from_records(&records);
        let camera = glam::Vec3::from(u.camera_position);
        let view_proj = glam::Mat4::from_cols_array_2d(&u.camera_view_proj);
        let bvh = underlight::bvh::Bvh::of_scene(&scene);
        budget.seen_by(&records, view_proj, camera, &bvh);
        budget.placed_by(&records, &bvh);
        let power = underlight::flux_budget::grid_power(&u).expect("the built-in scenes' light is directional");
        eprintln!("{name}:\n{budget}");
        let survey = underlight::frame::photon_density::view_adapted(&scene, scene.bounds(), &bvh, &u, None);
        let k = survey.caustics.expect("the scene is in view").grid_aspect;
        let (_, cells) = underlight::shader_math::caustic_grid_cell(glam::UVec2::ZERO, 48, k);
        eprintln!("{name}: grid aspect {k}, {} × {} coarse cells", cells.x, cells.y);
        assert_eq!(budget.cast, (cells.x * cells.y * 4) as u64, "{name}: photons recorded");
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
        // them, and the photons the waves bend behind an occluder in them search the second,
        // steeper maps (frame::uniforms::steep_light_axis). Measured: 0.37 % (tank), 0.05 %
        // (port), 0.40 % (storage) of the power does not converge; with the first maps alone
        // 1.2 %, 0.5 % and 0.8 %; mapped along the straight light ray, 5.6 %, 1.3 % and 4.7 %
        // (at the shipped 1024² maps), most of it beside shadow edges and on walls.
        let lost = budget.dropped[DropReason::NotConverged as usize - 1].watts / power;
        assert!(lost < 0.006, "{name}: {:.2} % of the grid's power does not converge", 100.0 * lost);
        // The image-space iteration places the landed photons where a ray cast along their
        // refracted rays through the scene's triangles does. Measured at these settings (512²
        // maps): 99.1 % (tank), 99.8 % (port), 98.6 % (storage) of the landed flux within
        // 1 cm of the exact hit. Without the iteration's last step onto the receiver's plane
        // at its texel (photon_cast.glsl's onto_receiver_plane), the tank reads 89.5 %.
        let placed = budget.placed.clone().expect("placed against the BVH");
        let close = placed.close.watts / budget.landed.watts;
        assert!(close > 0.98, "{name}: {:.2} % of the landed flux within 1 cm of its exact hit", 100.0 * close);
        // Every landed photon is seen, hidden or out of view; and the scenes spread their
        // photons for the view (caustic_photon_density = "view"), so the photons the camera
        // sees are a larger share of the landed photons than their flux is of the landed flux
        // (measured at 320×200: tank 77 % of the photons for 59 % of the flux, port 68 % for
        // 41 %, storage 64 % for 46 %; on an even grid both shares are alike).
        let seen = budget.seen.expect("sorted by the camera");
        let parts = [seen.visible, seen.hidden, seen.outside];
        assert_eq!(parts.iter().map(|s| s.photons).sum::<u64>(), budget.landed.photons, "{name}");
        let watts: f64 = parts.iter().map(|s| s.watts).sum();
        assert!((watts - budget.landed.watts).abs() <= 1e-9 * budget.landed.watts, "{name}: {watts} W");
        let photon_share = seen.visible.photons as f64 / budget.landed.photons as f64;
        let flux_share = seen.visible.watts / budget.landed.watts;
        assert!(
            photon_share > flux_share + 0.05,
            "{name}: {:.0} % of the photons and {:.0} % of the flux land where the camera sees",
            100.0 * photon_share,
            100.0 * flux_share
        );
    }
    assert_clean_shutdown(ctx);
}

/// The godray beams' budget from the beams' own records: every beam is drawn, drawn though
/// unconverged, or dropped for a reason; the light's power through the grid is what they
/// carry plus the surface's reflection; and the view's share of the beams is the light's, not
/// the grid's: spreading the beams for the view (`godray_photon_density = "view"`) moves
/// beams into view without changing how much of the light's flux × length the view holds.
#[test]
fn every_beam_is_accounted_for_and_the_view_moves_beams_not_light() {
    let ctx = validated_context();
    for name in ["tank", "port"] {
        let mut in_view = Vec::new();
        for spread in [PhotonSpread::Even, PhotonSpread::View] {
            let mut scene = underlight::scene::load(name).unwrap();
            scene.effects.caustics = false;
            scene.effects.godray_grid = 48;
            scene.effects.godray_subdivision = 2;
            scene.effects.godray_photon_density = spread;
            scene.effects.shadow_map_size = 512;
            let (images, u) = recorded_frame(&ctx, &scene);
            let records = images.beam_records.expect("beam records");
            let view_proj = glam::Mat4::from_cols_array_2d(&u.camera_view_proj);
            let budget = FluxBudget::from_beam_records(&records, view_proj);
            let power = underlight::flux_budget::grid_power(&u).expect("the built-in scenes' light is directional");
            eprintln!("{name}, {spread:?}:\n{budget}");
            assert_eq!(budget.cast, 96 * 96, "{name}: beams recorded");
            assert_eq!(budget.unknown, 0, "{name}: records with a code the budget does not know");
            let dropped: u64 = budget.dropped.iter().map(|s| s.photons).sum();
            let drawn = budget.landed.photons + budget.landed_unconverged.photons;
            assert_eq!(drawn + dropped, budget.cast, "{name}: beams neither drawn nor dropped");
            // As for the caustic photons: Fresnel loses about 2 % at the scenes' sun.
            let reflected = (power - budget.landed_watts() - budget.dropped_watts()) / power;
            assert!((0.0..0.05).contains(&reflected), "{name}: {:.2} % unaccounted", 100.0 * reflected);
            let v = budget.view.expect("the beams' view");
            assert!(v.in_view > 0.0 && v.clipped >= 0.0, "{name}: {v:?}");
            in_view.push((v.in_view / (v.in_view + v.clipped), v.wholly_outside));
        }
        let ((even_share, even_outside), (view_share, view_outside)) = (in_view[0], in_view[1]);
        // Measured at 320×200 with the shipped 100² × 2² beams: tank 65.1 % / 65.0 % of the
        // flux × length in view, 5611 / 4350 beams wholly outside it; port 38.4 % / 38.7 %,
        // 16 536 / 9946. A warp that moved light with its beams (a cell's flux not scaled by its
        // area) would move the share with the beams.
        assert!(
            (view_share - even_share).abs() < 0.02,
            "{name}: {:.1} % of the beams' light in view on the even grid, {:.1} % spread",
            100.0 * even_share,
            100.0 * view_share
        );
        assert!(
            view_outside < even_outside,
            "{name}: beams wholly out of view: even {even_outside}, spread {view_outside}"
        );
    }
    assert_clean_shutdown(ctx);
}

/// The footprint-sized beams (`godray_method = "footprint"`) record through their own
/// geometry shader (`godrays_footprint_debug.geom`): the same beams as the lines, so the same
/// records, beam for beam, and the same budget.
#[test]
fn footprint_beams_record_the_same_beams_as_lines() {
    let ctx = validated_context();
    let mut scene = underlight::scene::load("tank").unwrap();
    scene.effects.caustics = false;
    scene.effects.godray_grid = 48;
    scene.effects.shadow_map_size = 512;
    let mut records = Vec::new();
    for method in [GodrayMethod::Beams, GodrayMethod::Footprint] {
        scene.effects.godray_method = method;
        let (images, _) = recorded_frame(&ctx, &scene);
        records.push(images.beam_records.expect("beam records"));
    }
    assert_clean_shutdown(ctx);
    let (lines, ribbons) = (&records[0], &records[1]);
    assert_eq!(lines.len(), 2 * 96 * 96);
    // Fate codes and hits equal; the surface point and flux of a dropped beam too (both
    // shaders record what cast_photon returned).
    let differing = lines.iter().zip(ribbons.iter()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} of {} records differ between lines and ribbons", lines.len());
    let drawn = lines.chunks_exact(2).filter(|pair| pair[0][3] > 0.5).count();
    assert!(drawn > lines.len() / 4, "only {drawn} beams drawn");
}

#[test]
fn footprint_points_report_the_footprints_the_device_clamped() {
    // effects.caustic_estimator = "footprint": each point is as large as its photon's cell on
    // its receiver, up to the device's largest point. The flux budget records the points
    // that bound clamped (record code FOOTPRINT_CLAMPED), with their photons still landed.
    // With the tank's shipped 165² × 3² photons at 160×100 only a few on the walls the camera
    // grazes reach it (measured on lavapipe, whose largest point is 255 px: 318 of 230 802,
    // 0.39 % of the light, with each hat covering its reach; 257 of 191 303, 0.47 %, at the
    // 150² × 3² shipped until 2026-12-07; at 100² × 3² 17 of
    // 85 054, 0.09 %, with the rectangles before the hats); a 1×1 grid of 2 × 2 photons gives each a quarter of the pool, larger than
    // any point (2 of the 4 that land, 32 % of the light).
    let ctx = validated_context();
    let mut clamped = Vec::new();
    let shipped = underlight::scene::load("tank").unwrap().effects;
    assert_eq!(shipped.caustic_estimator, CausticEstimator::Footprint);
    for (grid, subdivision) in [(shipped.caustic_grid, shipped.caustic_subdivision), (1, 2)] {
        let mut scene = underlight::scene::load("tank").unwrap();
        scene.effects.caustic_grid = grid;
        scene.effects.caustic_subdivision = subdivision;
        scene.effects.godrays = false;
        scene.effects.shadow_map_size = 512;
        let (images, u) = recorded_frame(&ctx, &scene);
        let budget = FluxBudget::from_records(&images.photon_records.expect("photon records"));
        eprintln!(
            "{grid}² × {subdivision}²: {} of {} landed footprints clamped to {} px\n{budget}",
            budget.footprint_clamped.photons, budget.landed.photons, u.device_max_point_size
        );
        assert!(budget.landed.photons > 0, "{grid}² × {subdivision}²: nothing landed");
        assert!(budget.footprint_clamped.photons <= budget.landed.photons);
        clamped.push((budget.footprint_clamped.photons, budget.footprint_clamped.watts / budget.landed.watts));
    }
    assert!(
        clamped[0].1 < 0.01,
        "the shipped photons' footprints clamped {:.2} % of their light",
        100.0 * clamped[0].1
    );
    assert!(clamped[1].0 > 0, "a quarter of the pool per photon was not clamped");
    assert_clean_shutdown(ctx);
}
