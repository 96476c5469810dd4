//! Build script: two jobs.
//!
//! 1. Link shaderc statically against Debian's `libshaderc-dev`. Its shared library leaves
//!    glslang symbols undefined, so the static archives are named here, inside one linker
//!    group because they depend on each other cyclically.
//! 2. Embed every committed `spirv/*.spv` in the binary (a generated table of
//!    `include_bytes!`), so a user's binary needs neither a shader compiler nor the source
//!    tree at run time.

use std::{env, fs, path::PathBuf};

const SHADERC_STATIC_LIBS: &[&str] = &[
    "glslang",
    "MachineIndependent",
    "GenericCodeGen",
    "OSDependent",
    "OGLCompiler",
    "SPIRV",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
    "HLSL",
    "glslang-default-resource-limits",
];

fn main() {
    link_shaderc();
    embed_spirv();
}

fn link_shaderc() {
    let dir = env::var("SHADERC_LIB_DIR").unwrap_or_else(|_| "/usr/lib/x86_64-linux-gnu".into());
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    let missing: Vec<_> =
        SHADERC_STATIC_LIBS.iter().filter(|l| !PathBuf::from(&dir).join(format!("lib{l}.a")).exists()).collect();
    if !missing.is_empty() {
        panic!(
            "static glslang/SPIRV-Tools libraries missing from {dir}: {missing:?}.\n\
             Install them with: apt-get install libshaderc-dev spirv-tools\n\
             (or run scripts/setup.sh, which does this)"
        );
    }
    println!("cargo:rustc-link-search=native={dir}");
    println!("cargo:rustc-link-arg=-Wl,--start-group");
    for lib in SHADERC_STATIC_LIBS {
        println!("cargo:rustc-link-arg={dir}/lib{lib}.a");
    }
    println!("cargo:rustc-link-arg=-Wl,--end-group");
    println!("cargo:rustc-link-arg=-lstdc++");
    println!("cargo:rustc-link-arg=-lm");
}

fn embed_spirv() {
    let root = PathBuf::from(env::var("CARGO_MANIFEST_DIR").unwrap());
    let spirv = root.join("spirv");
    println!("cargo:rerun-if-changed=spirv");
    let mut names: Vec<String> = fs::read_dir(&spirv)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".spv"))
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    let mut table = String::from("/// Committed SPIR-V, embedded at build time: (file name, words as bytes).\n");
    table.push_str("pub static EMBEDDED_SPIRV: &[(&str, &[u8])] = &[\n");
    for n in &names {
        println!("cargo:rerun-if-changed=spirv/{n}");
        // The path is resolved when the crate compiles, not written out here: a target
        // directory copied to another checkout (an A/B build of two commits) keeps this
        // script's output while its spirv/ is unchanged, and an absolute path written here
        // would embed the other checkout's shaders.
        table.push_str(&format!(
            "    ({n:?}, include_bytes!(concat!(env!(\"CARGO_MANIFEST_DIR\"), \"/spirv/{n}\"))),\n"
        ));
    }
    table.push_str("];\n");
    let out = PathBuf::from(env::var("OUT_DIR").unwrap()).join("embedded_spirv.rs");
    fs::write(out, table).unwrap();
}
