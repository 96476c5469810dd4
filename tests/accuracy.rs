//! The GPU frame against the CPU reference (`underlight::reference`) on lavapipe, under
//! validation: the default settings' caustic error on the tank stays under a stated bound,
//! the error falls as the photon grid grows, and `underlight sweep` writes its CSV, table and
//! Pareto plot.

mod common;

use common::{assert_clean_shutdown, validated_context};
use std::process::Command;
use underlight::accuracy::cached_reference;
use underlight::frame::FrameOptions;
use underlight::headless::SceneRenderer;
use underlight::metrics::{buffer_error, gap_fraction, light_in_shadow, lit_holes};
use underlight::reference::ReferenceSettings;
use underlight::scene::Scene;
use underlight::vk::vk;

const TIME: f32 = 1.0;
const OUTPUT: [u32; 2] = [160, 160];
/// `default_settings_error_on_the_tank`'s figure on lavapipe (docs/accuracy.md): 1.68 with
/// the paper's points, 1.69 with the triangle estimator the scenes ship since, 1.46 since the
/// photon grid covers the water's footprint only, 1.345 since the hits lie on the receivers'
/// planes, the triangles deposit their own flux and the light's maps bend at the water, 0.980
/// since the scenes ship the photons spread for the view (`caustic_photon_density = "view"`:
/// the same photons, most of them where the camera sees the floor) and light only the side of
/// a receiver the camera sees. Against a 64M-photon reference it reads 0.956, and the 8M and
/// 64M references differ by 0.223: the figure is the 100² × 3² mesh's coarseness at the 512²
/// caustic target, not the reference's noise (200² × 3² reads 0.404). 1.436 since the scenes
/// draw their caustics at the output's 800² (`caustic_target_scale = 1`), against a reference
/// traced at that size: 1.381 against a 64M-photon one, from which the 8M one differs by
/// 0.415. Blurred by 3 px, the 800² and the 512² buffers (upsampled) read the same against it
/// (0.493 and 0.484); the rest is pixel-scale, where the sharper buffer's fold lines are
/// sampled at pixel centres (docs/accuracy.md, "Edges"). 1.198 since triangles under a pixel
/// are deposited over their footprint instead of at the pixel centres they cover, and
/// corners on facets up to 45° apart draw their triangles (docs/accuracy.md, "Triangles of
/// about a pixel"). 1.181 since flux handed back is drawn over the photons' cells and each
/// mesh cell is cut along its shorter diagonal ("Handed-back flux over the photons' cells",
/// "Cells split along their shorter diagonal"). 1.119 since the survey sends photons only
/// towards receivers the light reaches ("Photons for lit receivers only"): a return to 1.43
/// fails the guard. 0.953 since thin slivers and triangles are strips weighed by a tent
/// across ("Strips weighed by a tent across"): the one-pixel strips' 1.119 fails the guard.
/// 0.952 since the estimators read the normal the cast found where it placed the hit ("The
/// receiver's normal where the cast placed the hit"). 0.946 since mesh cells across a
/// receiver's border are cut into polygons up to where it ends ("Cells cut at receivers'
/// borders"). 0.636 since the scenes ship footprint-sized points at 150² × 3², spread by hats
/// on the photons' lattice ("Hats on the photons' lattice"): the triangles' 0.946 fails the
/// guard. 0.594 since a photon at its coarse cell's border casts its neighbour across it
/// onto its plane instead of mirroring its other span ("Neighbours across the coarse cell's
/// border"). 0.592 since every neighbour missing from a photon's receiver is cast onto its
/// plane ("Every missing neighbour on the photon's plane"). 0.575 since the survey floors the
/// footprint points' density at 0.3 of its mean, not 0.15 ("The survey's floor for the
/// footprint points"). 0.553 since the scenes ship 165² × 3² photons, which the hats drawn as
/// quads pay for ("The quads' saving spent on photons"): a return to 150² (0.575) stays
/// inside the 15 % headroom, which is for other drivers, not for this.
const DEFAULT_RMSE_MEASURED: f64 = 0.553;

fn tank() -> Scene {
    underlight::scene::load("tank").unwrap()
}

/// A folder of its own for one call: the tests run on parallel threads of one process, and
/// each removes its folder when done, so a folder named by the process alone was removed
/// under another test still writing its reference into it (a fresh-clone run of the suite on 2026-12-06 failed so).
fn cache_dir(name: &str) -> std::path::PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static CALLS: AtomicUsize = AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("underlight-accuracy-{name}-{}-{call}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The reference at the test's size: enough photons that its own noise is far below the GPU
/// error it measures (tests/reference.rs states the convergence figure).
fn reference_settings() -> ReferenceSettings {
    ReferenceSettings { caustic_photons: 8_000_000, godray_beams: 100_000, threads: 0, seed: 7 }
}

/// A variant's caustic buffer against the reference.
#[derive(Clone, Copy, Debug)]
struct CausticFigures {
    rmse: f64,
    flux: f64,
    /// `metrics::gap_fraction` of the GPU's buffer and of the reference's.
    gaps: f64,
    reference_gaps: f64,
    /// `metrics::lit_holes`.
    holes: f64,
    /// `metrics::light_in_shadow`.
    shadow_light: f64,
}

/// Caustic figures of the GPU frame for each variant of the scene, against one reference (the
/// variants change only the method's settings).
fn caustic_figures(variants: &[(String, Scene)]) -> Vec<CausticFigures> {
    let ctx = validated_context();
    let cache = cache_dir("variants");
    let mut errors = Vec::new();
    for (label, scene) in variants {
        let out = vk::Extent2D { width: scene.output[0], height: scene.output[1] };
        let mut renderer = SceneRenderer::with_options(&ctx.device, scene, out, FrameOptions::default()).unwrap();
        let extents = renderer.frame.extents;
        let (_, images) = renderer.render(1, TIME, 0.0, true).unwrap();
        drop(renderer);
        let images = images.unwrap();
        let reference = cached_reference(scene, TIME, &extents, &reference_settings(), &cache).unwrap();
        let gpu = images.caustics_filtered.as_ref().or(images.caustics.as_ref()).unwrap();
        let r = reference.caustics.as_ref().unwrap();
        let e = buffer_error(gpu, r).unwrap();
        let figures = CausticFigures {
            rmse: e.relative_rmse,
            flux: e.flux_error,
            gaps: gap_fraction(gpu),
            reference_gaps: gap_fraction(r),
            holes: lit_holes(gpu, r).unwrap(),
            shadow_light: light_in_shadow(gpu, r).unwrap(),
        };
        eprintln!(
            "{label}: caustic relative RMSE {:.3}, mean relative error {:.3}, flux error {:+.3}, gap fraction {:.4} \
             (reference {:.4}), holes {:.4}, light in the reference's shadows {:.5}",
            e.relative_rmse,
            e.mean_relative_error,
            e.flux_error,
            figures.gaps,
            figures.reference_gaps,
            figures.holes,
            figures.shadow_light
        );
        errors.push(figures);
    }
    assert_clean_shutdown(ctx);
    std::fs::remove_dir_all(&cache).ok();
    errors
}

/// Each variant's caustic error is below the one before it.
fn assert_error_falls(errors: &[CausticFigures], variants: &[(String, Scene)]) {
    for (pair, names) in errors.windows(2).zip(variants.windows(2)) {
        let (e0, e1) = (pair[0].rmse, pair[1].rmse);
        assert!(e1 < e0, "caustic error does not fall from {} ({e0:.3}) to {} ({e1:.3})", names[0].0, names[1].0);
    }
}

#[test]
fn error_falls_as_the_photon_grid_grows() {
    // One-pixel splats and no filter: the GPU's buffer is then a density estimate whose
    // error is mostly photon noise, which falls as 1/√N. (With the default distance-sized
    // splats the error at this size is mostly their blur, which more photons do not reduce:
    // 1.436, 1.428, 1.428 for grids 50, 100, 200.) A broken flux normalisation (photon flux
    // not ∝ 1/N²) makes the error grow or stay flat with the grid, and fails here.
    let variants: Vec<(String, Scene)> = [25u32, 50, 100, 200]
        .iter()
        .map(|&grid| {
            let mut s = tank();
            s.output = OUTPUT;
            s.effects.caustic_estimator = underlight::scene::CausticEstimator::Paper;
            // The paper's even grid, whose photon noise the figures above measure.
            s.effects.caustic_photon_density = underlight::scene::PhotonSpread::Even;
            s.effects.caustic_subdivision = 2;
            s.effects.caustic_grid = grid;
            s.effects.point_size_min = 1.0;
            s.effects.point_size_max = 1.0;
            s.effects.filter = false;
            (format!("tank {}×{}, 1 px splats, grid {grid}² × 2²", OUTPUT[0], OUTPUT[1]), s)
        })
        .collect();
    let errors = caustic_figures(&variants);
    assert_error_falls(&errors, &variants);
}

#[test]
fn triangle_error_falls_as_the_mesh_refines() {
    // The triangle estimator draws the piecewise-linear wavefront its photon mesh spans, so
    // its error is the mesh's coarseness against the caustic pattern, and falls as the grid
    // refines. Its flux stays where the reference puts it at every grid: each photon lends its
    // flux to its triangles, so the grid changes where light is drawn, not how much. A broken
    // flux share (photon flux not ∝ 1/N², or a triangle's share not a sixth of its corners')
    // fails the flux bound at once.
    let variants: Vec<(String, Scene)> = [24u32, 48, 96]
        .iter()
        .map(|&grid| {
            let mut s = tank();
            s.output = OUTPUT;
            s.effects.caustic_estimator = underlight::scene::CausticEstimator::Triangles;
            // The even grid the figures below were measured on (the view's density is the
            // next test's).
            s.effects.caustic_photon_density = underlight::scene::PhotonSpread::Even;
            s.effects.caustic_subdivision = 3;
            s.effects.caustic_grid = grid;
            (format!("tank {}×{}, triangles, grid {grid}² × 3²", OUTPUT[0], OUTPUT[1]), s)
        })
        .collect();
    let errors = caustic_figures(&variants);
    assert_error_falls(&errors, &variants);
    // Measured: relative RMSE 1.73, 0.92, 0.42; flux −1.4 %, −1.0 %, −0.5 % with the caustics
    // at the output's size and triangles under a pixel over their footprint. Before, with the
    // caustics at 0.64 of the output: 1.40, 0.68, 0.28; flux −0.1 %, −1.5 %, −0.7 %
    // (+1.1 %, −0.8 %, −0.0 % before the triangles lit only the side of a receiver the camera
    // sees; before each triangle deposited its own flux and the fallback points their
    // footprint: 1.58, 0.94, 0.45 and +5.6 %, +7.1 %, +0.2 %, docs/accuracy.md). A share of a
    // third instead of a sixth doubles the flux, a photon flux not ∝ 1/N² scales it by the
    // grid's ratio squared: ±12 % catches both at every grid.
    for (figures, (name, _)) in errors.iter().zip(&variants) {
        let flux = figures.flux;
        assert!(flux.abs() < 0.12, "{name}: flux error {flux:+.3}");
    }
}

#[test]
fn photons_spread_for_the_view_lower_the_error_and_keep_the_flux() {
    // The same photons, spread over the water's footprint in proportion to the pixels that see
    // where they land (frame::photon_density): the near floor's caustic lines are drawn by a
    // finer mesh, the water out of view by a coarser one. Measured on lavapipe: relative RMSE
    // 0.918 even, 0.639 spread; flux −1.0 %, −0.6 % (0.678 and 0.457, −1.5 % and −0.7 %, with
    // the caustics at 0.64 of the output and triangles under half a pixel over their
    // footprint). A survey that missed the view, or a warp the shader ignored, leaves the
    // error where it was; photons whose flux did not follow their warped cells put several
    // times the light where the camera looks.
    use underlight::scene::PhotonSpread;
    let variants: Vec<(String, Scene)> = [PhotonSpread::Even, PhotonSpread::View]
        .iter()
        .map(|&density| {
            let mut s = tank();
            s.output = OUTPUT;
            s.effects.caustic_estimator = underlight::scene::CausticEstimator::Triangles;
            s.effects.caustic_subdivision = 3;
            s.effects.caustic_grid = 48;
            s.effects.caustic_photon_density = density;
            (format!("tank {}×{}, triangles 48² × 3², {} photons", OUTPUT[0], OUTPUT[1], density.name()), s)
        })
        .collect();
    let errors = caustic_figures(&variants);
    let (even, even_flux, view, view_flux) = (errors[0].rmse, errors[0].flux, errors[1].rmse, errors[1].flux);
    assert!(view < 0.8 * even, "the view's density should cut the error by a fifth: {even:.3} → {view:.3}");
    for (flux, (name, _)) in [even_flux, view_flux].iter().zip(&variants) {
        assert!(flux.abs() < 0.03, "{name}: flux error {flux:+.3}");
    }
}

#[test]
fn refinement_at_receivers_borders_fills_holes_and_keeps_the_flux() {
    // The storage at 320×200 with the triangles as the scenes shipped them until the footprint
    // points (100² × 3²), and with `caustic_refinement`: the mesh cells whose
    // corners land on two receivers (its posts, its crates, the rack's boards) cast again 3 × 3
    // finer (caustics_triangles.geom). Measured on lavapipe against this 8M-photon reference:
    // holes 0.52 % → 0.18 %, relative RMSE 0.394 → 0.374, flux −1.4 % → −0.8 % since the mesh
    // cells across receivers' borders are cut (1.05 % → 0.30 %, 0.407 → 0.379, −1.0 % → −0.7 %
    // before; against a 64M-photon one 1.73 % → 0.73 %, 0.376 → 0.345). A second draw that
    // drew nothing would leave its cells' light out (holes up, flux down by their share); one
    // that drew the grid's cells again would add their light twice.
    let variants: Vec<(String, Scene)> = [false, true]
        .iter()
        .map(|&refine| {
            let mut s = underlight::scene::load("storage").unwrap();
            s.output = [320, 200];
            s.effects.caustic_estimator = underlight::scene::CausticEstimator::Triangles;
            s.effects.caustic_grid = 100;
            s.effects.caustic_refinement = refine;
            (format!("storage 320×200, triangles 100² × 3², refinement {}", if refine { "on" } else { "off" }), s)
        })
        .collect();
    let errors = caustic_figures(&variants);
    let (unrefined, refined) = (errors[0], errors[1]);
    assert!(
        refined.holes < 0.5 * unrefined.holes,
        "holes {:.2} % → {:.2} %",
        100.0 * unrefined.holes,
        100.0 * refined.holes
    );
    assert!(refined.rmse < unrefined.rmse, "relative RMSE {:.3} → {:.3}", unrefined.rmse, refined.rmse);
    for f in [unrefined, refined] {
        assert!(f.flux.abs() < 0.03, "flux error {:+.3}", f.flux);
    }
    assert!(refined.flux.abs() <= unrefined.flux.abs() + 0.005, "flux {:+.4} → {:+.4}", unrefined.flux, refined.flux);
}

#[test]
fn default_settings_error_on_the_tank() {
    // The tank as it ships (800×800, its effects): the bounds are regression guards, stated
    // with what they catch. Energy must be where the reference puts it: measured −0.5 % with
    // the triangles spread for the view at the 512² target, −0.0 % at the output's 800², +0.0 %
    // on the even grid, +0.1 % with the footprint points shipped since (+4.1 % before its triangles
    // deposited their own flux; +0.3 % with the paper's points over the light's whole window;
    // the reference's own noise in the sum is under 0.1 % with 8M photons). A 5 % bound
    // catches a photon-count normalisation error (the flux scales by the subdivision², 4×),
    // a lost attenuation to the receiver (+40 % over the tank's 2 m), a light window that
    // misses where photons enter (a third lost at a low sun), or a twentieth of the photons
    // dropped. (At 160×160 the same settings read −12.7 %: splats up to 20 px are a fifth of
    // the 102² target there and spill past its border.)
    let scene = underlight::scene::load("tank").unwrap();
    let errors = caustic_figures(&[(format!("tank {}×{} as shipped", scene.output[0], scene.output[1]), scene)]);
    let CausticFigures { rmse, flux, gaps, reference_gaps, holes, shadow_light } = errors[0];
    assert!(flux.abs() < 0.05, "default settings: caustic flux error {flux:+.3}");
    // Relative RMSE here is the mesh's coarseness at the pixel scale and the reference's noise
    // (above); the guard is the measured
    // figure with 15 % headroom for other drivers' rasterisation, and trips when light lands
    // in the wrong place.
    assert!(rmse < DEFAULT_RMSE_MEASURED * 1.15, "default settings: caustic relative RMSE {rmse:.3}");
    // Gaps. The gap fraction (zero pixels in lit regions, issue 16's figure) counts a hard
    // shadow's border, which the reference leaves dark too: it reads 0.092 for the reference
    // itself. The GPU's must not exceed the reference's (measured 0.083; the paper's points
    // read 0.22; measured 0.066 against 0.172 since the caustic target is the output's 800²).
    // Against the pixels the reference lights with all their neighbours, the share the GPU
    // leaves at zero is measured 0.012 at 512² and 0.017 at 800², on the shelf's front, the
    // rocks' sides and the floor beside their shadows, where lone photons drew squares; none
    // on the floors. 0.012 at 800² since they draw their cells (docs/accuracy.md, "Handed-back
    // flux over the photons' cells"), 0.006 since the cells are cut ("Cells cut at receivers'
    // borders"); gap fraction 0.049 against the reference's 0.187. The footprint points as
    // shipped since: holes 0.0011, gap fraction 0.029; 0.0010 and 0.027 since their border
    // photons cast their neighbours across it; 0.0002 and 0.025 since every missing neighbour;
    // 0.0003 and 0.026 since the survey's floor for them is 0.3; the same at 165² × 3².
    assert!(gaps <= reference_gaps + 0.005, "gap fraction {gaps:.4} against the reference's {reference_gaps:.4}");
    assert!(holes < 0.02, "{:.1} % of the pixels the reference lights hold nothing", 100.0 * holes);
    // The holes a footprint point leaves where a neighbour inside its coarse cell is missing
    // from its receiver: 0.0010 when it took the span on its other side, 0.0002 since it
    // casts that neighbour onto its plane (docs/accuracy.md, "Every missing neighbour on the
    // photon's plane"). The bound catches a return.
    assert!(holes < 0.0006, "{:.3} % of the pixels the reference lights hold nothing", 100.0 * holes);
    // Light inside the reference's shadows: the footprint points' hats, a photon's span wide,
    // ran tens of pixels into the shadows beside lit receivers (under the shelf, beside the
    // pillar) and put 0.0028 of the light there in this test (the plain visibility test, as
    // before the shadow test); held to where a photon could land (docs/accuracy.md, "Hats held
    // out of the shadows"), 0.00036; 0.00044 since border photons cast their neighbours
    // across it, 0.00046 since every missing neighbour, 0.00036 since the survey's floor for
    // them is 0.3, 0.00037 at 165² × 3². (Against a 64M-photon reference:
    // 0.0026 and 0.0002; the triangles 0.0001.)
    assert!(shadow_light < 0.001, "{:.2} % of the caustic light lies in the reference's shadows", 100.0 * shadow_light);
}

#[test]
fn hats_held_to_their_receiver_keep_their_light_off_what_lies_behind() {
    // effects.caustic_receiver_test on the tank as it ships otherwise (800×800, the reference
    // of default_settings_error_on_the_tank). Held to the pixels that show its receiver, a
    // footprint point's hat no longer runs past a rock's outline onto the floor in its shadow
    // (docs/accuracy.md, "Hats on their own receiver"): the light in the reference's shadows,
    // 0.00036 of the buffer's without the test (default_settings_error_on_the_tank), reads
    // 0.00025 with it (0.00024 since the hats are quads; at 165² × 3² 0.00027 against 0.00037
    // without), and the bound between them fails a test that lets every fragment through. The
    // error (0.574 against the shipped 0.575 at 150²; 0.553 against 0.553 at 165²), the flux
    // (−0.4 %) and the holes (0.0003) keep default_settings_error_on_the_tank's bounds.
    let mut scene = underlight::scene::load("tank").unwrap();
    scene.effects.caustic_receiver_test = true;
    let figures = caustic_figures(&[("tank 800×800, hats held to their receiver".to_string(), scene)]);
    let CausticFigures { rmse, flux, holes, shadow_light, .. } = figures[0];
    assert!(flux.abs() < 0.05, "caustic flux error {flux:+.3}");
    assert!(rmse < DEFAULT_RMSE_MEASURED * 1.15, "caustic relative RMSE {rmse:.3}");
    assert!(holes < 0.0006, "{:.3} % of the pixels the reference lights hold nothing", 100.0 * holes);
    assert!(
        shadow_light < 0.0003,
        "{:.3} % of the caustic light lies in the reference's shadows",
        100.0 * shadow_light
    );
}

#[test]
fn the_port_and_the_storage_cover_what_the_reference_lights_at_their_own_sizes() {
    // Issue 16's gaps at the scenes' own sizes (1440×850), as shipped; the tank's are in
    // default_settings_error_on_the_tank. The gap fraction counts a hard shadow's border and
    // the reference's own noise, which leave the reference dark too (the test's 8M-photon
    // references read about 0.45 and 0.36, the 64M-photon ones 0.150 and 0.115), so it is held
    // to the reference's own. The holes (the pixels the reference lights with all their
    // neighbours that the GPU leaves at zero) are the figure that tells: against 8M-photon
    // references from `underlight reference` the footprint points read 0.08 / 0.03 % (0.05 /
    // 0.01 % since every missing neighbour is cast, 0.05 / 0.03 % since the survey's floor for
    // them is 0.3, 0.03 / 0.02 % at 165² × 3²), the triangles that shipped before 0.41 %
    // on the storage (1.67 % against 64M photons) and the paper's points 6.5 %; the bound
    // catches a return to either. (Light in the reference's
    // shadows is not asserted here: against 8M photons the port's sparse grazed faces read as
    // shadow, 0.43 % with the hats held out of the shadows and without.)
    let scenes: Vec<(String, Scene)> = ["port", "storage"]
        .iter()
        .map(|name| {
            let scene = underlight::scene::load(name).unwrap();
            (format!("{name} {}×{} as shipped", scene.output[0], scene.output[1]), scene)
        })
        .collect();
    let figures = caustic_figures(&scenes);
    for ((label, _), f) in scenes.iter().zip(&figures) {
        assert!(f.holes < 0.0025, "{label}: {:.2} % of the pixels the reference lights hold nothing", 100.0 * f.holes);
        assert!(
            f.gaps <= f.reference_gaps + 0.005,
            "{label}: gap fraction {:.4} against the reference's {:.4}",
            f.gaps,
            f.reference_gaps
        );
        assert!(f.flux.abs() < 0.03, "{label}: caustic flux error {:+.3}", f.flux);
    }
}

#[test]
fn sweep_writes_csv_table_and_pareto_plot() {
    let out = cache_dir("sweep");
    let status = Command::new(env!("CARGO_BIN_EXE_underlight"))
        .args(["sweep", "--scene", "tank", "--width", "64", "--height", "40", "--grid", "16,48", "--filter", "off,on"])
        .args(["--target", "0.5,1", "--frames", "1", "--warmup", "0", "--photons", "300000", "--beams", "30000"])
        .args(["--out", out.to_str().unwrap(), "--cache", out.join("cache").to_str().unwrap()])
        .output()
        .unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&status.stdout), String::from_utf8_lossy(&status.stderr));
    assert!(status.status.success(), "sweep failed:\n{text}");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let rows: Vec<&str> = csv.lines().skip(1).collect();
    assert_eq!(rows.len(), 8, "2 grids × filter off/on × 2 caustic targets:\n{csv}");
    let on_front = rows.iter().filter(|r| r.ends_with(",true")).count();
    assert!(on_front >= 1, "no setting on the Pareto front:\n{csv}");
    for row in &rows {
        let fields: Vec<f64> = row.split(',').filter_map(|f| f.parse().ok()).collect();
        assert!(fields.iter().all(|v| v.is_finite()), "{row}");
    }
    // The caustic error at the output: the buffer's own where the target is the output's;
    // where it is half, the upsampled buffer against a reference traced at 64×40, which a
    // blurred buffer cannot match as it matches the reference at its own size.
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name} column"));
    let (width, own, at_output) =
        (column("caustic_target_w"), column("caustic_rel_rmse"), column("caustic_rel_rmse_at_output"));
    for row in &rows {
        let f: Vec<&str> = row.split(',').collect();
        let (own, at_output): (f64, f64) = (f[own].parse().unwrap(), f[at_output].parse().unwrap());
        match f[width] {
            "64" => assert_eq!(own, at_output, "{row}"),
            "32" => assert!(at_output > own, "the upsampled buffer's error {at_output} ≤ its own {own}: {row}"),
            other => panic!("caustic target width {other}: {row}"),
        }
    }
    // The reference's own error, from its two halves, beside every row; a sweep whose
    // reference is noisy for a figure it measures says so.
    let reference_own = column("caustic_reference_own_error");
    let mut noisy = false;
    for row in &rows {
        let f: Vec<&str> = row.split(',').collect();
        let (own, figure): (f64, f64) = (f[reference_own].parse().unwrap(), f[own].parse().unwrap());
        assert!(own > 0.0 && own < figure, "the reference's own error {own} against the figure {figure}: {row}");
        noisy |= own > figure / 3.0;
    }
    assert_eq!(text.contains("the reference's own caustic error"), noisy, "{text}");
    let png = std::fs::read(out.join("sweep.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG") && png.len() > 10_000, "the plot is not a drawn PNG ({} bytes)", png.len());
    assert!(std::fs::read_to_string(out.join("sweep.md")).unwrap().contains("| photons |"));
    // A second run reuses the cached reference. It measures issue 16's holes on both
    // estimators: the paper's points at 1 px, 2 304 photons over 2 560 pixels, leave most of
    // what the reference lights dark (0.41 when written); the triangles cover it (0.007).
    let again = Command::new(env!("CARGO_BIN_EXE_underlight"))
        .args(["sweep", "--scene", "tank", "--width", "64", "--height", "40", "--grid", "16", "--filter", "off"])
        .args(["--estimator", "paper,triangles", "--point-size", "1"])
        .args(["--frames", "1", "--warmup", "0", "--photons", "300000", "--beams", "30000"])
        .args(["--out", out.to_str().unwrap(), "--cache", out.join("cache").to_str().unwrap()])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&again.stderr);
    assert!(again.status.success() && !text.contains("reference tank"), "the reference was traced again:\n{text}");
    let csv = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    let figure = |row: &str, name: &str| -> f64 { row.split(',').nth(column(name)).unwrap().parse().unwrap() };
    let estimator = |name: &str| csv.lines().find(|r| r.starts_with(&format!("{name},"))).expect(name);
    let (paper, triangles) = (estimator("paper"), estimator("triangles"));
    let holes = |row: &str| figure(row, "caustic_holes");
    assert!(holes(paper) > 0.2 && holes(triangles) < 0.05, "holes: points {paper}, triangles {triangles}");
    // The gap fraction of each buffer beside the reference's own, the same for both.
    let gaps = |row: &str| (figure(row, "caustic_gaps"), figure(row, "reference_caustic_gaps"));
    let ((paper_gaps, reference_gaps), (triangle_gaps, reference_again)) = (gaps(paper), gaps(triangles));
    assert_eq!(reference_gaps, reference_again, "{csv}");
    assert!(paper_gaps > triangle_gaps && reference_gaps > 0.0 && reference_gaps < 1.0, "{csv}");
    // Bad values are refused before any work, naming the option.
    let bad = Command::new(env!("CARGO_BIN_EXE_underlight")).args(["sweep", "--grid", "0"]).output().unwrap();
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(bad.status.code() == Some(1) && err.contains("--grid 0 is out of range"), "{err}");
    std::fs::remove_dir_all(&out).ok();
}
