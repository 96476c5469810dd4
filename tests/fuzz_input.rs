//! Bounded fuzzing of what users feed in: the scene-file parser and the OBJ loader. Inputs are
//! mutations of the built-in tank scene's TOML and generated OBJ text with broken numbers,
//! NaN/Inf, bad indices, polygons, degenerate faces and junk lines. Whatever comes in, loading
//! returns a scene or an error naming the file, and never panics. A scene that loads holds only
//! what the renderer assumes: finite positions, unit normals, indices in range, sizes in range.

use proptest::prelude::*;
use std::path::{Path, PathBuf};
use underlight::scene::{load_str, obj::load_obj, Scene};

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("underlight-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// What a loaded scene guarantees the renderer.
fn check_scene(scene: &Scene) -> Result<(), TestCaseError> {
    prop_assert!(!scene.meshes.is_empty());
    for m in &scene.meshes {
        prop_assert!(m.positions.iter().all(|p| p.is_finite()));
        prop_assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3), "normals not unit");
        prop_assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()), "index out of range");
        prop_assert!(m.indices.len() % 3 == 0);
    }
    let c = &scene.camera;
    prop_assert!(c.z_near > 0.0 && c.z_far > c.z_near && c.fov_y_degrees > 0.0 && c.fov_y_degrees < 180.0);
    prop_assert!(scene.water.wavelength > 0.0 && scene.water.ior > 1.0);
    Ok(())
}

/// One edit of a text: replace a byte range by a fragment that users (or corrupt files) produce.
fn mutate(text: &str, at: usize, len: usize, fragment: &str) -> String {
    let bytes = text.as_bytes();
    let at = at % (bytes.len() + 1);
    let end = (at + len).min(bytes.len());
    let mut out = bytes[..at].to_vec();
    out.extend_from_slice(fragment.as_bytes());
    out.extend_from_slice(&bytes[end..]);
    String::from_utf8_lossy(&out).into_owned()
}

fn fragment() -> impl Strategy<Value = String> {
    prop_oneof![
        Just(String::new()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("-inf".to_string()),
        Just("1e39".to_string()),
        Just("-0".to_string()),
        Just("0".to_string()),
        Just("\"text\"".to_string()),
        Just("[1, 2]".to_string()),
        Just("=".to_string()),
        Just("[[objects]]\n".to_string()),
        Just("\n[camera]\n".to_string()),
        Just("\u{0}".to_string()),
        (-1e6f64..1e6).prop_map(|v| v.to_string()),
        proptest::collection::vec(any::<u8>(), 0..8).prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scene_files_load_or_fail_cleanly(edits in proptest::collection::vec((any::<usize>(), 0usize..12, fragment()), 1..4)) {
        let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
        let mut text = std::fs::read_to_string(assets.join("tank.toml")).unwrap();
        for (at, len, frag) in &edits {
            text = mutate(&text, *at, *len, frag);
        }
        // The origin is the real file's, so its OBJ reference resolves.
        let origin = assets.join("tank.toml");
        match std::panic::catch_unwind(|| load_str(&text, &origin)) {
            Err(_) => prop_assert!(false, "the parser panicked on:\n{text}"),
            Ok(Ok(scene)) => check_scene(&scene)?,
            Ok(Err(e)) => prop_assert!(format!("{e:#}").contains("tank"), "the error does not name the file: {e:#}"),
        }
    }
}

fn obj_line() -> impl Strategy<Value = String> {
    let num = prop_oneof![
        (-100f32..100.0).prop_map(|v| v.to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("1e40".to_string()),
        Just("x".to_string()),
    ];
    let index = prop_oneof![(-12i32..12).prop_map(|i| i.to_string()), Just("0".to_string()), Just("99999".to_string())];
    prop_oneof![
        4 => (num.clone(), num.clone(), num.clone()).prop_map(|(a, b, c)| format!("v {a} {b} {c}")),
        1 => (num.clone(), num.clone(), num).prop_map(|(a, b, c)| format!("vn {a} {b} {c}")),
        4 => proptest::collection::vec(index.clone(), 1..6).prop_map(|ix| format!("f {}", ix.join(" "))),
        1 => Just("o part".to_string()),
        1 => Just("usemtl nowhere".to_string()),
        1 => Just("vn 0 0 0".to_string()),
        1 => Just("usemtl".to_string()),
        1 => proptest::collection::vec(index.clone(), 1..4).prop_map(|ix| format!("l {}", ix.join(" "))),
        1 => index.prop_map(|i| format!("p {i}")),
        1 => proptest::collection::vec(any::<u8>(), 0..10).prop_map(|b| String::from_utf8_lossy(&b).into_owned()),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn generated_obj_files_load_or_fail_cleanly(lines in proptest::collection::vec(obj_line(), 0..30), case in any::<u64>()) {
        let path = scratch().join(format!("fuzz-{case}.obj"));
        std::fs::write(&path, lines.join("\n")).unwrap();
        let result = std::panic::catch_unwind(|| load_obj(&path));
        std::fs::remove_file(&path).ok();
        match result {
            Err(_) => prop_assert!(false, "the OBJ loader panicked on:\n{}", lines.join("\n")),
            Ok(Ok(model)) => {
                for m in &model.meshes {
                    prop_assert!(m.positions.iter().all(|p| p.is_finite()), "non-finite position loaded");
                    prop_assert!(m.normals.iter().all(|n| (n.length() - 1.0).abs() < 1e-3), "normal not unit");
                    prop_assert!(m.indices.iter().all(|&i| (i as usize) < m.positions.len()));
                }
            }
            Ok(Err(e)) => prop_assert!(format!("{e:#}").contains("fuzz-"), "the error does not name the file: {e:#}"),
        }
    }
}
