//! `scripts/gpu-check.sh --quick`: the one command a session with a GPU runs, smoke-tested here
//! on lavapipe with the binary cargo built for the tests. A GPU session has 15 minutes of
//! device time, so a flag renamed in the CLI or a JSON file the script no longer stitches
//! together must fail here, not there.

use std::process::Command;

#[test]
fn gpu_check_quick_writes_its_json_and_markdown() {
    let out = std::env::temp_dir().join(format!("underlight-gpu-check-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/gpu-check.sh");
    let run = Command::new("bash")
        .arg(script)
        .args(["--quick", "--bin", env!("CARGO_BIN_EXE_underlight"), "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let text = format!("{}{}", String::from_utf8_lossy(&run.stdout), String::from_utf8_lossy(&run.stderr));
    assert!(run.status.success(), "gpu-check --quick failed:\n{text}");

    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("gpu-check.json")).unwrap()).unwrap();
    assert!(doc["devices"].as_str().unwrap().contains("suitable"), "{}", doc["devices"]);

    // Every photon path ran the tiny configuration, on the paper's even grid, and reports a
    // positive caustic pass time; the peers say how their buffers differ from the geometry
    // shader's (the vertex-only path and the floor draw the same points: no difference).
    let results = doc["bench"]["report"]["results"].as_array().unwrap();
    let paths: Vec<&str> = results.iter().map(|r| r["photon_path"].as_str().unwrap()).collect();
    assert_eq!(paths, ["GeometryShader", "VertexOnly", "Compute", "SplatFloor"]);
    for r in results {
        assert_eq!(r["config"]["name"], "tiny");
        assert_eq!(r["config"]["photon_density"], "even", "the paper's configurations cast on even grids");
        let caustics = r["passes"].as_array().unwrap().iter().find(|p| p["pass"] == "caustics").unwrap();
        assert!(caustics["median_ms"].as_f64().unwrap() > 0.0, "{r}");
    }
    for r in &results[1..] {
        let l1 = r["caustic_difference"]["relative_l1"].as_f64().unwrap();
        let limit = if r["photon_path"] == "Compute" { 0.02 } else { 0.0 };
        assert!(l1 <= limit, "{}: caustic L1 {l1} against the geometry shader's", r["photon_path"]);
    }
    assert_eq!(doc["bench"]["scaling"].as_array().unwrap().len(), 6);
    // The same configuration's work per pass and stage, every path: the geometry shader's
    // caustic pass runs once per coarse cell.
    let work = doc["work"]["report"]["results"].as_array().unwrap();
    assert_eq!(work.len(), 4);
    let counts =
        &work[0]["stage_counts"].as_array().unwrap().iter().find(|c| c["pass"] == "caustics").unwrap()["counts"];
    let grid = work[0]["config"]["caustic_grid"].as_u64().unwrap();
    assert_eq!(counts["geometry_invocations"].as_u64().unwrap(), grid * grid, "{counts}");

    // The accuracy step: the shipped estimator on the tank against its reference. At 24² × 3²
    // photons and 96×60 the error is large, but light must land where the reference has it
    // with about its flux: an estimator that deposits nothing, or twice the light, fails.
    // The footprint points as shipped, and the triangles with the same photons.
    let rows = doc["accuracy"]["tank"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    for (row, estimator) in rows.iter().zip(["footprint", "triangles"]) {
        assert_eq!(row["estimator"], estimator);
        assert_eq!(row["caustic_refinement"], false);
        let caustics = &row["caustics"];
        let (rmse, flux) = (caustics["relative_rmse"].as_f64().unwrap(), caustics["flux_error"].as_f64().unwrap());
        assert!(rmse.is_finite() && rmse < 1.0, "caustic relative RMSE {rmse}");
        assert!(flux.abs() < 0.1, "caustic flux error {flux:+.3}");
        assert!(row["godrays"]["relative_rmse"].as_f64().unwrap() < 0.3, "{}", row["godrays"]);
    }

    // Issue 16's own-size step: its configurations benched on the port itself (the tiny one
    // here), each with a caustic pass that took time.
    let own_size = doc["own_size"]["port"]["report"]["results"].as_array().unwrap();
    assert_eq!(own_size.len(), 1, "{}", doc["own_size"]);
    assert_eq!(own_size[0]["config"]["name"], "tiny");
    assert_eq!(own_size[0]["scene"], "port", "the own-size step benched another scene than the port");
    let caustics = own_size[0]["passes"].as_array().unwrap().iter().find(|p| p["pass"] == "caustics").unwrap();
    assert!(caustics["median_ms"].as_f64().unwrap() > 0.0, "{}", own_size[0]);

    let markdown = std::fs::read_to_string(out.join("gpu-check.md")).unwrap();
    for heading in
        ["# GPU check", "## Per-pass GPU time", "## Issue 16's photons at the own size: port", "## Accuracy: tank"]
    {
        assert!(markdown.contains(heading), "gpu-check.md lacks {heading:?}:\n{markdown}");
    }
    std::fs::remove_dir_all(&out).ok();
}

#[test]
fn gpu_check_refuses_a_missing_binary_and_unknown_arguments() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/gpu-check.sh");
    let missing =
        Command::new("bash").arg(script).args(["--quick", "--bin", "/nonexistent/underlight"]).output().unwrap();
    assert_eq!(missing.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("--bin /nonexistent/underlight is not an executable"));
    let unknown = Command::new("bash").arg(script).arg("--fast").output().unwrap();
    assert_eq!(unknown.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&unknown.stderr).contains("unknown argument --fast"));
}
