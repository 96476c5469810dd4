//! Zero best-practices and synchronization warnings: every built-in scene, the camera above
//! the water, and 60 frames of the viewer under Xvfb, with the Khronos layer's best-practices
//! and synchronization validation both on (as a user enables them, through
//! VK_LAYER_ENABLES). The one message ignored is listed, with its reason, in
//! `vk::validation::IGNORED`; any other warning makes the command exit 2 and fails here,
//! with the pass that raised it.

use std::process::{Command, Output};

const EXE: &str = env!("CARGO_BIN_EXE_underlight");
const ENABLES: &str =
    "VK_VALIDATION_FEATURE_ENABLE_BEST_PRACTICES_EXT:VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT";

fn assert_no_warnings(what: &str, out: Output) {
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let messages: Vec<&str> = text.lines().filter(|l| l.starts_with("validation:")).collect();
    assert!(messages.is_empty(), "{what}: {} validation message(s):\n{}", messages.len(), messages.join("\n"));
    assert!(out.status.success(), "{what} failed ({}):\n{text}", out.status);
}

fn render(args: &[&str]) -> Output {
    let out_png = std::env::temp_dir().join(format!("underlight-bp-{}.png", std::process::id()));
    Command::new(EXE)
        .env("VK_LAYER_ENABLES", ENABLES)
        .args(["--validation", "render", "--width", "64", "--height", "48", "--frames", "2", "--out"])
        .arg(&out_png)
        .args(args)
        .output()
        .expect("run underlight")
}

#[test]
fn built_in_scenes_raise_no_best_practices_warning() {
    for scene in ["tank", "port", "storage"] {
        assert_no_warnings(scene, render(&["--scene", scene]));
    }
    // Above the water: the refraction and reflection passes, the surface's inputs cleared to
    // the sampled layout, the highlight glow.
    assert_no_warnings(
        "tank from above",
        render(&["--scene", "tank", "--camera", "0.3,1.2,0.6", "--look-at", "0.3,-2,-0.2"]),
    );
}

#[test]
fn sixty_viewer_frames_raise_no_best_practices_warning() {
    let shot = std::env::temp_dir().join(format!("underlight-bp-view-{}.png", std::process::id()));
    let out = Command::new("xvfb-run")
        .env("VK_LAYER_ENABLES", ENABLES)
        .args(["-a", "-s", "-screen 0 640x480x24", EXE, "--validation", "view", "--scene", "tank"])
        .args(["--width", "64", "--height", "48", "--frames", "60", "--screenshot"])
        .arg(&shot)
        .output()
        .unwrap_or_else(|e| panic!("cannot run xvfb-run ({e}); install it with: apt-get install xvfb"));
    assert_no_warnings("viewer, 60 frames", out);
}
