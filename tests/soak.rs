//! Memory stays flat over hundreds of frames, headless and in the viewer under Xvfb, with
//! validation on.
//!
//! Why the bound holds and why it can fail: the leak this guards against (lavapipe compiling
//! and keeping a new variant of every shader whose control flow read the uniform buffer, at
//! every draw; docs/reliability.md) cost 12 MB per photon pass per frame, independent of the
//! grid and target sizes, because what leaked was compiled code. Between the samples below
//! lie 240 frames; a bound of 4 MiB on the growth allows 17 KiB a frame, so it fails on that
//! leak by a factor of 700, and on any per-frame buffer, image or descriptor the frame path
//! might start creating (the smallest of ours, a uniform block, is 0.5 KiB plus the driver's
//! and the layer's bookkeeping, several KiB per object). Warm-up growth (the layer's and the
//! allocator's first-use state) happens before the first sample at frame 60.

mod common;

use common::*;
use std::process::Command;
use underlight::memory::soak;
use underlight::vk::vk;

const FIRST_SAMPLE: u64 = 60;
const FRAMES: u64 = 300;
const MAX_GROWTH_BYTES: i64 = 4 << 20;

/// The pool with both photon passes, the filter, and small grids and targets: every pass of
/// the under-water frame runs, and a frame costs little.
fn small_scene() -> underlight::scene::Scene {
    let mut scene = pool(0.05);
    scene.water.noise_amplitude = 0.01;
    let e = &mut scene.effects;
    e.caustic_grid = 24;
    e.godray_grid = 12;
    e.shadow_map_size = 64;
    e.caustics = true;
    e.godrays = true;
    e.filter = true;
    scene
}

#[test]
fn headless_memory_is_flat_over_300_frames() {
    let ctx = validated_context();
    let scene = small_scene();
    let report =
        soak(&ctx.device, &scene, vk::Extent2D { width: 48, height: 32 }, FRAMES, &[FIRST_SAMPLE, FRAMES]).unwrap();
    println!("{report}");
    let plan = underlight::frame::FramePlan::for_scene(&scene);
    for pass in
        [underlight::passes::PassId::Caustics, underlight::passes::PassId::Godrays, underlight::passes::PassId::Filter]
    {
        assert!(plan.runs(pass), "the soak must cover the {pass} pass");
    }
    let growth = report.resident_growth().expect("resident memory is readable on Linux");
    assert!(
        growth < MAX_GROWTH_BYTES,
        "resident memory grew {:.2} MiB from frame {FIRST_SAMPLE} to {FRAMES} (bound 4 MiB):\n{report}",
        growth as f64 / (1 << 20) as f64
    );
    let [first, last] = [report.samples[0].device, report.samples[1].device];
    assert_eq!(first, last, "device memory changed between frame {FIRST_SAMPLE} and {FRAMES}");
    assert_clean_shutdown(ctx);
}

#[test]
fn viewer_memory_is_flat_over_300_frames_under_xvfb() {
    let dir = std::env::temp_dir().join(format!("underlight-soak-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The tank, with the small grids of the headless soak.
    let tank_obj = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/tank.obj");
    let text =
        std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/tank.toml"))
            .unwrap()
            .replace("obj = \"tank.obj\"", &format!("obj = {:?}", tank_obj.display().to_string()));
    let scene = dir.join("small_tank.toml");
    // The built-in scenes end with their [effects] table: the small grids go into it.
    let text = match text.find("\ncaustic_grid = ") {
        Some(at) => {
            let end = text[at + 1..].find('\n').map_or(text.len(), |e| at + 1 + e);
            format!("{}\ncaustic_grid = 24{}", &text[..at], &text[end..])
        }
        None => format!("{text}\n[effects]\ncaustic_grid = 24\n"),
    };
    assert!(text.trim_end().rsplit("\n[").next().unwrap().starts_with("effects]"), "[effects] is not the last table");
    std::fs::write(&scene, format!("{}\ngodray_grid = 12\nshadow_map_size = 64\n", text.trim_end())).unwrap();
    let out = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 640x480x24", env!("CARGO_BIN_EXE_underlight"), "--validation", "view"])
        .args(["--scene", scene.to_str().unwrap(), "--width", "48", "--height", "32", "--frames", &FRAMES.to_string()])
        .output()
        .unwrap_or_else(|e| panic!("cannot run xvfb-run ({e}); install it with: apt-get install xvfb"));
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(out.status.success(), "viewer failed ({}):\n{text}", out.status);
    assert!(!text.contains("validation:"), "validation messages:\n{text}");
    // The viewer prints `memory at frame N: resident B bytes` at frame 100 and at exit.
    let samples: Vec<(u64, i64)> = text
        .lines()
        .filter_map(|l| l.strip_prefix("memory at frame "))
        .filter_map(|l| {
            let (frame, rest) = l.split_once(": resident ")?;
            Some((frame.parse().ok()?, rest.split_whitespace().next()?.parse().ok()?))
        })
        .collect();
    assert_eq!(samples.iter().map(|s| s.0).collect::<Vec<_>>(), vec![100, FRAMES], "memory lines:\n{text}");
    let growth = samples[1].1 - samples[0].1;
    // 200 frames between the samples: the same bound allows 20 KiB a frame.
    assert!(
        growth < MAX_GROWTH_BYTES,
        "the viewer's resident memory grew {growth} bytes from frame 100 to {FRAMES}:\n{text}"
    );
}
