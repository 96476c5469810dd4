//! The committed SPIR-V is what the GLSL compiles to, is valid, and is what the binary embeds.

use std::path::Path;
use std::process::Command;
use underlight::shaders;

#[test]
fn committed_spirv_is_fresh() {
    let (glsl, spirv) = shaders::source_dirs();
    let stale = shaders::stale_files(&glsl, &spirv).unwrap();
    assert!(stale.is_empty(), "spirv/ is stale — run `underlight shaders` and commit:\n{}", stale.join("\n"));
}

#[test]
fn freshness_check_fails_when_a_source_changes() {
    // Copy glsl/ aside, change what one shader computes, and check against the committed SPIR-V.
    let (glsl, spirv) = shaders::source_dirs();
    let scratch = std::env::temp_dir().join(format!("underlight-glsl-{}", std::process::id()));
    copy_tree(&glsl, &scratch);
    let frag = scratch.join("grid_splat/grid_splat.frag");
    let source = std::fs::read_to_string(&frag).unwrap();
    let changed = source.replace("out_color = g_energy;", "out_color = 2.0 * g_energy;");
    assert_ne!(source, changed, "the edit must apply");
    std::fs::write(&frag, changed).unwrap();
    // A new stage with no committed SPIR-V is stale too.
    std::fs::write(scratch.join("filter/extra.frag"), "#version 450\nvoid main() {}\n").unwrap();
    let stale = shaders::stale_files(&scratch, &spirv).unwrap();
    std::fs::remove_dir_all(&scratch).ok();
    assert!(stale.iter().any(|s| s.contains("grid_splat.frag.spv") && s.contains("differs")), "{stale:?}");
    assert!(stale.iter().any(|s| s.contains("extra.frag.spv") && s.contains("missing")), "{stale:?}");
    // And SPIR-V whose source is gone is reported as an orphan.
    let empty = std::env::temp_dir().join(format!("underlight-glsl-empty-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let orphans = shaders::stale_files(&empty, &spirv).unwrap();
    std::fs::remove_dir_all(&empty).ok();
    assert_eq!(orphans.len(), shaders::spirv_files(&spirv).unwrap().len(), "{orphans:?}");
}

/// Copies the folder `from` with its subfolders into `to`.
fn copy_tree(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_tree(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

#[test]
fn every_spirv_passes_spirv_val() {
    let (_, spirv) = shaders::source_dirs();
    let files = shaders::spirv_files(&spirv).unwrap();
    assert!(!files.is_empty());
    for file in files {
        let out = Command::new("spirv-val")
            .args(["--target-env", "vulkan1.2"])
            .arg(&file)
            .output()
            .unwrap_or_else(|e| panic!("cannot run spirv-val ({e}); install it with: apt-get install spirv-tools"));
        assert!(
            out.status.success(),
            "spirv-val rejects {}:\n{}{}",
            file.display(),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn binary_embeds_exactly_the_committed_spirv() {
    let (_, spirv) = shaders::source_dirs();
    let files = shaders::spirv_files(&spirv).unwrap();
    assert_eq!(files.len(), shaders::EMBEDDED_SPIRV.len());
    for file in files {
        let name = file.file_name().unwrap().to_string_lossy();
        let stem = name.trim_end_matches(".spv");
        let embedded = shaders::embedded(stem).unwrap_or_else(|| panic!("{name} is not embedded"));
        assert_eq!(embedded, std::fs::read(&file).unwrap().as_slice(), "{name} embedded copy differs");
        assert!(shaders::spirv_words(embedded).is_some(), "{name} is not SPIR-V");
    }
    assert!(Path::new(&spirv).is_dir());
}

#[test]
fn every_variant_is_its_source_with_its_defines() {
    // A variant whose defines were lost would compile to its source's SPIR-V.
    for variant in shaders::VARIANTS {
        let base = std::path::Path::new(variant.source).file_name().unwrap().to_string_lossy().into_owned();
        let (ours, theirs) = (shaders::embedded(variant.name), shaders::embedded(&base));
        assert!(ours.is_some() && theirs.is_some(), "{} or its source {base} is not embedded", variant.name);
        assert_ne!(
            ours, theirs,
            "{} compiles to the same SPIR-V as {base}: its defines {:?} did nothing",
            variant.name, variant.defines
        );
    }
}
