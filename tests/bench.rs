//! `underlight bench` on a tiny configuration: every pass of the frame reports a positive
//! GPU time, the total covers the passes, and the JSON and CSV parse and name the device.

use std::process::Command;

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
/// (vertex-only, the splat floor) report no difference, the compute path a small one.
#[test]
fn bench_compares_the_photon_paths() {
    let dir = std::env::temp_dir().join(format!("underlight-bench-paths-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let json = dir.join("p.json");
    let out = Command::new(env!("CARGO_BIN_EXE_underlight"))
        .args(["bench", "--config", "tiny", "--frames", "3", "--warmup", "1", "--compare-paths", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("photon paths against the geometry shader"), "{stdout}");
    let doc: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let results = doc["report"]["results"].as_array().unwrap();
    let paths: Vec<&str> = results.iter().map(|r| r["photon_path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["GeometryShader", "VertexOnly", "Compute", "SplatFloor"], "lavapipe has float atomics");
    for r in results {
        let caustics = r["passes"].as_array().unwrap().iter().find(|p| p["pass"] == "caustics").unwrap();
        assert!(caustics["median_ms"].as_f64().unwrap() > 0.0, "{r}");
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
