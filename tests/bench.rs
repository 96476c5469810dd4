//! `underlight bench` on a tiny configuration: every pass of the frame reports a positive
//! GPU time, the total covers the passes, and the JSON and CSV parse and name the device.
//! And the pipeline statistics the bench and `render` print, under validation.

mod common;

use common::{assert_clean_shutdown, validated_context};
use std::process::Command;
use underlight::frame::FrameOptions;
use underlight::headless::SceneRenderer;
use underlight::passes::PassId;
use underlight::vk::vk;

#[test]
fn bench_smoke_reports_every_pass() {
    let dir = std::env::temp_dir().join(format!("underlight-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (json, csv) = (dir.join("b.json"), dir.join("b.csv"));
    let out = Command::new(env!("CARGO_BIN_EXE_underlight"))
        .args(["bench", "--config", "tiny", "--frames", "4", "--warmup", "1", "--scaling", "--json"])
        .arg(&json)
        .arg("--csv")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let report = &doc["report"];
    assert!(!report["device"].as_str().unwrap().is_empty(), "{report}");
    let r = &report["results"][0];
    assert_eq!(r["frames"], 4);
    let passes = r["passes"].as_array().unwrap();
    let names: Vec<&str> = passes.iter().map(|p| p["pass"].as_str().unwrap()).collect();
    assert_eq!(names, ["shadow", "scene", "caustics", "godrays", "filter", "compose"]);
    let mut largest: f64 = 0.0;
    for p in passes {
        let (lo, mid, hi) =
            (p["p5_ms"].as_f64().unwrap(), p["median_ms"].as_f64().unwrap(), p["p95_ms"].as_f64().unwrap());
        assert!(lo > 0.0 && lo <= mid && mid <= hi, "{p}");
        largest = largest.max(mid);
    }
    assert!(r["total"]["median_ms"].as_f64().unwrap() >= largest);
    // Scaling: six series of four points, each with a finite fitted slope, and the photon
    // series really varies the photon count (grid ×0.5 → ×2 is ×16 photons). No timing is
    // asserted: timings are figures to read, not pass/fail thresholds.
    let scaling = doc["scaling"].as_array().unwrap();
    assert_eq!(scaling.len(), 6);
    for s in scaling {
        assert_eq!(s["points"].as_array().unwrap().len(), 4, "{s}");
        assert!(s["slope_ms"].as_f64().unwrap().is_finite());
    }
    let photons = scaling[0]["points"].as_array().unwrap();
    let (first, last) = (photons[0][0].as_f64().unwrap(), photons[3][0].as_f64().unwrap());
    assert!((last / first - 16.0).abs() < 0.5, "photon counts {first} → {last} (grid ×0.5 → ×2)");
    // The subdivision series splits tiny's 32² caustic photons as 32² × 1², …, 4² × 8².
    let split: Vec<f64> = scaling[1]["points"].as_array().unwrap().iter().map(|p| p[0].as_f64().unwrap()).collect();
    assert_eq!(split, [1.0, 2.0, 4.0, 8.0]);
    let rows = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(rows.lines().count(), 1 + passes.len() + 1, "{rows}");
    assert!(
        rows.lines().nth(1).unwrap().contains("llvmpipe") || !report["device"].as_str().unwrap().contains("llvmpipe")
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `--compare-paths` runs every photon path on the same configuration, reports its times and
/// how its buffers differ from the geometry shader's; the peers that draw the same points
/// (vertex-only, the splat floor) report no difference, the compute path a small one. With
/// `--pipeline-statistics` each path's caustic pass also says which stages did its work:
/// the geometry shader once per coarse cell, the vertex shader once per photon, the compute
/// shader at least once per photon, and only the geometry-shader path's geometry stage.
#[test]
fn bench_compares_the_photon_paths() {
    let dir = std::env::temp_dir().join(format!("underlight-bench-paths-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("p.json");
    let out = Command::new(env!("CARGO_BIN_EXE_underlight"))
        .args(["bench", "--config", "tiny", "--frames", "3", "--warmup", "1", "--compare-paths"])
        .args(["--pipeline-statistics", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("photon paths against the geometry shader"), "{stdout}");
    assert!(stdout.contains("work per pass, last measured frame (pipeline statistics), tiny"), "{stdout}");
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let results = doc["report"]["results"].as_array().unwrap();
    let paths: Vec<&str> = results.iter().map(|r| r["photon_path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["GeometryShader", "VertexOnly", "Compute", "SplatFloor"], "lavapipe has float atomics");
    for r in results {
        let caustics = r["passes"].as_array().unwrap().iter().find(|p| p["pass"] == "caustics").unwrap();
        assert!(caustics["median_ms"].as_f64().unwrap() > 0.0, "{r}");
        // Every timed pass was counted, and the caustic pass's work sits in its path's stages.
        let counted = r["stage_counts"].as_array().unwrap();
        assert_eq!(counted.len(), r["passes"].as_array().unwrap().len(), "{r}");
        let work = &counted.iter().find(|c| c["pass"] == "caustics").unwrap()["counts"];
        let count = |stage: &str| work[stage].as_u64().unwrap();
        let (grid, photons) = (r["config"]["caustic_grid"].as_u64().unwrap(), r["caustic_photons"].as_u64().unwrap());
        assert!(count("fragment_invocations") > 0, "{work}");
        match r["photon_path"].as_str().unwrap() {
            "GeometryShader" => {
                assert_eq!(count("geometry_invocations"), grid * grid, "one invocation per coarse cell: {work}");
                let emitted = count("geometry_primitives");
                assert!(emitted > 0 && emitted <= photons, "one point per landed photon at most: {work}");
                assert_eq!(count("compute_invocations"), 0, "{work}");
            }
            "VertexOnly" | "SplatFloor" => {
                assert_eq!(count("geometry_invocations"), 0, "{work}");
                assert!(count("vertex_invocations") >= photons, "a vertex per photon: {work}");
                assert_eq!(count("compute_invocations"), 0, "{work}");
            }
            "Compute" => {
                assert_eq!(count("geometry_invocations"), 0, "{work}");
                assert!(count("compute_invocations") >= photons, "an invocation per photon: {work}");
            }
            other => panic!("unknown path {other}"),
        }
        let (c, g) = (&r["caustic_difference"], &r["godray_difference"]);
        match r["photon_path"].as_str().unwrap() {
            "GeometryShader" => assert!(c.is_null() && g.is_null()),
            "Compute" => {
                for d in [c, g] {
                    let l1 = d["relative_l1"].as_f64().unwrap();
                    assert!(l1 < 0.02, "{d}");
                }
            }
            _ => {
                for d in [c, g] {
                    assert!(d["relative_l1"].as_f64().unwrap() < 1e-6, "{d}");
                    assert!((d["sum_ratio"].as_f64().unwrap() - 1.0).abs() < 1e-6, "{d}");
                }
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// Pipeline statistics under validation, on the built-in tank as it ships (footprint points,
/// each hat a strip of two triangles): every pass is counted in every frame, the caustic
/// pass's geometry shader runs once per coarse cell and emits whole quads, at most one per
/// photon, and its work is the same in two frames of the same scene. Without the option no
/// pass is counted (no query pool: the frame records what it did before).
#[test]
fn pipeline_statistics_count_every_pass_s_work() {
    let ctx = validated_context();
    let mut scene = underlight::scene::load("tank").unwrap();
    scene.effects.caustic_grid = 40; // 120² photons: a small frame's worth
    let extent = vk::Extent2D { width: 160, height: 100 };
    let options = FrameOptions { pipeline_statistics: true, ..Default::default() };
    let mut renderer = SceneRenderer::with_options(&ctx.device, &scene, extent, options).unwrap();
    let (timings, _) = renderer.render(2, 1.0, 0.0, false).unwrap();
    let plan = renderer.frame.plan.passes.clone();
    drop(renderer);
    assert_eq!(timings.len(), 2);
    for t in &timings {
        assert_eq!(t.counts.len(), t.passes.len(), "every pass counted: {t:?}");
        assert!(t.counts.iter().all(|c| c.compute_invocations == 0), "no compute on the geometry-shader path: {t:?}");
        for id in &plan {
            let c = t.counts(*id).unwrap_or_else(|| panic!("{} not counted", id.name()));
            if matches!(id, PassId::Shadow | PassId::Scene | PassId::Caustics | PassId::Godrays | PassId::Compose) {
                assert!(c.fragment_invocations > 0, "{} shaded no fragment: {c:?}", id.name());
            }
        }
        let caustics = t.counts(PassId::Caustics).unwrap();
        let (grid, subdivision) = (scene.effects.caustic_grid as u64, scene.effects.caustic_subdivision as u64);
        assert_eq!(caustics.geometry_invocations, grid * grid, "one invocation per coarse cell: {caustics:?}");
        let photons = (grid * subdivision).pow(2);
        let emitted = caustics.geometry_primitives;
        assert!(emitted % 2 == 0, "each hat is a strip of two triangles: {caustics:?}");
        // Most of the tank's photons land where the camera sees them (a broken cast or a hat
        // that is never emitted would leave far fewer).
        assert!(emitted / 2 <= photons && emitted / 2 > photons / 3, "{} hats of {photons} photons", emitted / 2);
    }
    assert_eq!(
        timings[0].counts(PassId::Caustics).unwrap().geometry_primitives,
        timings[1].counts(PassId::Caustics).unwrap().geometry_primitives,
        "the same frame twice, the same hats"
    );
    let mut plain = SceneRenderer::new(&ctx.device, &scene, extent).unwrap();
    let (timings, _) = plain.render(1, 1.0, 0.0, false).unwrap();
    drop(plain);
    assert!(timings[0].counts.is_empty() && !timings[0].passes.is_empty());
    assert_clean_shutdown(ctx);
}
