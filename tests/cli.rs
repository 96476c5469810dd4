//! Bad command lines get a clear error and a non-zero exit before anything is rendered.

use std::process::Command;

fn run(args: &[&str]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_underlight")).args(args).output().unwrap();
    (out.status.code().unwrap_or(-1), String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn bad_command_lines_are_named_errors() {
    let dir = std::env::temp_dir().join(format!("underlight-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A file where a command wants an output folder.
    let file = std::env::temp_dir().join(format!("underlight-cli-file-{}", std::process::id()));
    std::fs::write(&file, b"").unwrap();
    let cases: Vec<(Vec<String>, &str)> = vec![
        (vec!["render".into(), "--scene".into(), "lagoon".into()], "tank, port, storage"),
        (vec!["render".into(), "--out".into(), "/proc/underlight.png".into()], "cannot"),
        (vec!["render".into(), "--out".into(), dir.display().to_string()], "is a directory"),
        (vec!["render".into(), "--width".into(), "0".into()], "at least 1"),
        (vec!["reference".into(), "--height".into(), "20000".into()], "at most 16384 (got 20000)"),
        (vec!["sweep".into(), "--width".into(), "1.5".into()], "not a whole number of pixels"),
        (vec!["view".into(), "--present-mode".into(), "vsync".into()], "fifo, mailbox, immediate"),
        (vec!["sweep".into(), "--filter".into(), "maybe".into()], "on, off"),
        (vec!["sweep".into(), "--estimator".into(), "splats".into()], "there are paper, footprint, triangles"),
        (vec!["bench".into(), "--config".into(), "paper-9000".into()], "unknown"),
        (vec!["bench".into(), "--config".into(), "tiny".into(), "--frames".into(), "0".into()], "at least 1"),
        (vec!["render".into(), "--frobnicate".into()], "--frobnicate"),
        (vec!["render".into(), "--camera".into(), "1,2".into()], "--camera takes three finite numbers"),
        (vec!["render".into(), "--look-at".into(), "0,nan,1".into()], "--look-at takes three finite numbers"),
        (vec!["render".into(), "--camera".into(), "1,x,3".into()], "--camera"),
        (vec!["render".into(), "--camera=0,1,0".into(), "--look-at=0,1,0".into()], "the same point"),
        // The photon grid from the command line is held to a scene file's ranges.
        (vec!["render".into(), "--caustic-grid".into(), "0".into()], "effects.caustic_grid = 0 is out of range"),
        (vec!["view".into(), "--caustic-grid".into(), "5000".into()], "effects.caustic_grid = 5000 is out of range"),
        (
            vec!["render".into(), "--caustic-subdivision".into(), "1".into()],
            "caustic_estimator = \"footprint\": must be >= 2",
        ),
        (
            vec!["render".into(), "--caustic-estimator=triangles".into(), "--caustic-subdivision=4".into()],
            "caustic_estimator = \"triangles\": must be <= 3",
        ),
        (vec!["view".into(), "--sweep".into(), "/nonexistent/sweep.json".into()], "--sweep /nonexistent/sweep.json"),
        (vec!["tune".into(), "--max-error=0".into()], "--max-error 0: must be a positive number"),
        (vec!["render".into(), "--time=nan".into()], "--time <TIME>': must be a finite number of seconds"),
        (vec!["view".into(), "--time".into(), "inf".into()], "must be a finite number of seconds (got inf)"),
        (vec!["edges".into(), "--time=-inf".into()], "must be a finite number of seconds (got -inf)"),
        (vec!["reference".into(), "--time".into(), "soon".into()], "\"soon\" is not a number of seconds"),
        (vec!["sweep".into(), "--step=nan".into()], "--step <STEP>': must be a finite number of seconds"),
        (vec!["grid-splat".into(), "--exposure".into(), "0".into()], "must be positive and finite (got 0)"),
        (vec!["render".into(), "--frames".into(), "0".into()], "--frames <FRAMES>': must be at least 1"),
        (vec!["bench".into(), "--warmup".into(), "4000000000".into()], "--warmup <WARMUP>': must be at most 100000"),
        (vec!["sweep".into(), "--warmup=-1".into()], "\"-1\" is not a whole number of frames"),
        (vec!["render".into(), "--frames".into(), "100001".into()], "at most 100000 (got 100001)"),
        (vec!["sweep".into(), "--frames=0".into()], "must be at least 1"),
        (vec!["grid-splat".into(), "--frames".into(), "2.5".into()], "\"2.5\" is not a whole number of frames"),
        (vec!["sweep".into(), "--point-size".into(), "inf".into()], "--point-size inf is out of range"),
        (vec!["reference".into(), "--threads".into(), "100000".into()], "must be at most 256 (got 100000"),
        (vec!["sweep".into(), "--threads=-1".into()], "\"-1\" is not a whole number of threads"),
        (vec!["reference".into(), "--out".into(), file.display().to_string()], "is a file: give a folder"),
        (vec!["render".into(), "--hdr".into(), file.display().to_string()], "is a file: give a folder"),
        (
            vec!["sweep".into(), "--out".into(), "/proc/underlight".into()],
            "output folder: cannot create /proc/underlight",
        ),
        // Checked before the minutes of measuring, not after.
        (
            vec!["tune".into(), "--max-error".into(), "0.5".into(), "--write".into(), dir.display().to_string()],
            "is a directory: give a file name",
        ),
    ];
    for (args, expected) in cases {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (code, stderr) = run(&args);
        assert_ne!(code, 0, "{args:?} succeeded");
        assert!(!stderr.contains("panicked"), "{args:?} panicked:\n{stderr}");
        assert!(stderr.contains(expected), "{args:?}: the error does not say {expected:?}:\n{stderr}");
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "a failed command left files behind");
    assert_eq!(std::fs::read(&file).unwrap().len(), 0, "a failed command wrote into a file it was given as a folder");
    std::fs::remove_file(&file).ok();
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn hdr_buffers_are_written_as_pfm_and_openexr() {
    let dir = std::env::temp_dir().join(format!("underlight-hdr-{}", std::process::id()));
    let out = dir.join("out.png");
    let args = ["render", "--scene", "tank", "--width", "64", "--height", "40", "--frames", "1", "--hdr"];
    let mut args: Vec<String> = args.iter().map(|s| s.to_string()).collect();
    args.extend([dir.display().to_string(), "--out".into(), out.display().to_string()]);
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let (code, stderr) = run(&args);
    assert_eq!(code, 0, "render --hdr failed:\n{stderr}");
    for name in ["scene_color", "albedo_transmittance", "caustics", "godrays", "godrays_filtered"] {
        let pfm = underlight::image_io::read_pfm(&dir.join(format!("{name}.pfm"))).unwrap();
        let exr = underlight::image_io::read_exr(&dir.join(format!("{name}.exr"))).unwrap();
        assert_eq!((exr.width, exr.height), (pfm.width, pfm.height), "{name}");
        // Float32 both: the same values, bit for bit (PFM has no alpha; the EXR none either).
        assert!(exr.pixels.iter().zip(&pfm.pixels).all(|(e, p)| e[..3] == p[..3]), "{name}: EXR and PFM differ");
        assert!(pfm.channel_sums()[0] > 0.0, "{name} is black");
    }
    // A reader that is not ours: ImageMagick's OpenEXR delegate, where it is installed.
    let identify = std::path::Path::new("/usr/bin/identify");
    if identify.exists() {
        let caustics = dir.join("caustics.exr");
        let probe = Command::new(identify).arg(&caustics).output().unwrap();
        let text = String::from_utf8_lossy(&probe.stdout);
        if probe.status.success() {
            assert!(text.contains("EXR 41x26"), "ImageMagick reads {}: {text}", caustics.display());
        } else {
            eprintln!("ImageMagick cannot read EXR here: {}", String::from_utf8_lossy(&probe.stderr));
        }
    }
    // --hdr-format picks one.
    let only = dir.join("only-exr");
    let (code, stderr) = run(&[
        "render",
        "--width",
        "32",
        "--height",
        "20",
        "--frames",
        "1",
        "--hdr",
        only.to_str().unwrap(),
        "--hdr-format",
        "exr",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stderr}");
    assert!(only.join("caustics.exr").exists() && !only.join("caustics.pfm").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn tune_picks_a_setting_or_says_how_close_it_came() {
    let dir = std::env::temp_dir().join(format!("underlight-tune-{}", std::process::id()));
    let common = |bound: &str| -> Vec<String> {
        let mut v: Vec<String> =
            ["tune", "--quick", "--width", "64", "--height", "40", "--photons", "200000", "--beams", "50000"]
                .iter()
                .map(|s| s.to_string())
                .collect();
        v.extend(["--cache".into(), dir.join("cache").display().to_string()]);
        v.extend(["--out".into(), dir.join("out").display().to_string(), "--max-error".into(), bound.into()]);
        v
    };
    let output = |args: Vec<String>| Command::new(env!("CARGO_BIN_EXE_underlight")).args(args).output().unwrap();
    // Any setting meets a loose bound: the cheapest is picked, printed as scene-file text and
    // written as a whole scene file.
    let tuned = dir.join("tuned.toml");
    let mut args = common("100");
    args.extend(["--write".into(), tuned.display().to_string()]);
    let loose = output(args);
    let stdout = String::from_utf8_lossy(&loose.stdout);
    assert!(loose.status.success(), "{}", String::from_utf8_lossy(&loose.stderr));
    let block = &stdout[stdout.find("[effects]").expect("an [effects] block")..];
    let block = &block[..block.find("\nwrote ").map_or(block.len(), |end| end + 1)];
    assert!(block.contains("caustic_estimator = ") && block.contains("caustic_grid = "), "{block}");
    assert!(dir.join("out/tune.md").is_file() && dir.join("out/tune.png").is_file());
    // The block is a valid [effects] table of a scene file: splice it into the tank's.
    let tank = std::fs::read_to_string(underlight::scene::file::scene_path("tank")).unwrap();
    let spliced = format!("{}{block}", &tank[..tank.find("[effects]").unwrap()]);
    let origin = underlight::scene::file::scene_path("tank");
    let printed = underlight::scene::file::load_str(&spliced, &origin).expect("the printed block loads");
    let written = underlight::scene::load(tuned.to_str().unwrap()).expect("the written scene loads");
    assert_eq!(written.effects, printed.effects, "the written file holds the printed settings");
    assert_eq!(written.meshes.len(), printed.meshes.len(), "the written file finds the tank's meshes");
    // An unreachable bound: a non-zero exit naming the best error measured.
    let tight = output(common("0.0001"));
    let stderr = String::from_utf8_lossy(&tight.stderr);
    assert_eq!(tight.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("no setting reaches an error of 0.000") && stderr.contains("the best measured is"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `render --pipeline-statistics` prints each pass's work per stage after the times: the
/// built-in tank's caustic pass runs its geometry shader once per coarse cell of the scene's
/// grid and shades fragments.
#[test]
fn render_prints_each_pass_s_work() {
    let dir = std::env::temp_dir().join(format!("underlight-statistics-{}", std::process::id()));
    let out = dir.join("out.png");
    // The caustic pass's row of the statistics table, with the table for messages.
    let caustics_row = |settings: &[&str]| -> (Vec<u64>, String) {
        let o = Command::new(env!("CARGO_BIN_EXE_underlight"))
            .args(["render", "--width", "64", "--height", "40", "--frames", "1", "--pipeline-statistics"])
            .args(settings)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
        assert!(o.status.success(), "{settings:?}: {stdout}{}", String::from_utf8_lossy(&o.stderr));
        let table =
            stdout.split("work per pass, last frame (pipeline statistics):").nth(1).expect("no statistics table");
        let header: Vec<&str> = table.lines().nth(1).unwrap().split_whitespace().collect();
        assert_eq!(header, ["pass", "VS", "GS", "GS", "prims", "clip", "prims", "FS", "CS"]);
        let row = table
            .lines()
            .find(|l| l.starts_with("caustics"))
            .expect("no caustics row")
            .split_whitespace()
            .skip(1)
            .map(|v| v.parse().unwrap())
            .collect();
        (row, stdout)
    };
    let grid = underlight::scene::load("tank").unwrap().effects.caustic_grid as u64;
    let (row, table) = caustics_row(&[]);
    assert_eq!(row[1], grid * grid, "geometry-shader invocations: {table}");
    assert!(row[2] > 0 && row[4] > 0, "primitives emitted and fragments shaded: {table}");
    // The command line's photon grid replaces the scene's: one invocation per coarse cell,
    // and fewer hats emitted from 24² × 2² photons than from the scene's.
    let (coarse, coarse_table) = caustics_row(&["--caustic-grid", "24", "--caustic-subdivision", "2"]);
    assert_eq!(coarse[1], 24 * 24, "geometry-shader invocations at --caustic-grid 24: {coarse_table}");
    assert!(coarse_table.contains("caustics 24² × 2² photons"), "{coarse_table}");
    assert!(
        coarse[2] > 0 && coarse[2] < row[2],
        "primitives emitted at 24² × 2² against {grid}² × the scene's subdivision: {} / {}",
        coarse[2],
        row[2]
    );
    std::fs::remove_dir_all(&dir).ok();
}
