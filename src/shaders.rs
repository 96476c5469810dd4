//! GLSL → SPIR-V. The GLSL in `glsl/` is compiled by `underlight shaders` (shaderc) into
//! `spirv/`, which is committed and embedded in the binary at build time, so running
//! underlight needs no shader compiler. A test recompiles everything and fails when the
//! committed SPIR-V is stale.

use anyhow::{bail, Context as _, Result};
use std::path::{Path, PathBuf};

include!(concat!(env!("OUT_DIR"), "/embedded_spirv.rs"));

/// Shader stages by file extension.
const STAGES: &[(&str, shaderc::ShaderKind)] = &[
    ("vert", shaderc::ShaderKind::Vertex),
    ("geom", shaderc::ShaderKind::Geometry),
    ("frag", shaderc::ShaderKind::Fragment),
    ("comp", shaderc::ShaderKind::Compute),
];

/// The embedded SPIR-V of a shader, by source name (e.g. `grid_splat.geom`).
pub fn embedded(name: &str) -> Option<&'static [u8]> {
    EMBEDDED_SPIRV.iter().find(|(file, _)| file.strip_suffix(".spv") == Some(name)).map(|(_, bytes)| *bytes)
}

/// SPIR-V bytes as 32-bit words (copied: `include_bytes!` gives no 4-byte alignment).
pub fn spirv_words(bytes: &[u8]) -> Option<Vec<u32>> {
    if !bytes.len().is_multiple_of(4) || bytes.len() < 20 {
        return None;
    }
    let words: Vec<u32> = bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    (words[0] == 0x0723_0203).then_some(words)
}

/// The source tree's `glsl/` and `spirv/` folders (this crate's, as built).
pub fn source_dirs() -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    (root.join("glsl"), root.join("spirv"))
}

pub struct CompiledShader {
    /// Source file name, e.g. `grid_splat.geom`; the SPIR-V file is `<name>.spv`.
    pub name: String,
    pub spirv: Vec<u8>,
}

/// Stage sources (not includes) in `glsl_dir`, sorted.
pub fn stage_sources(glsl_dir: &Path) -> Result<Vec<(PathBuf, shaderc::ShaderKind)>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(glsl_dir).with_context(|| format!("reading {}", glsl_dir.display()))? {
        let path = entry?.path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if let Some((_, kind)) = STAGES.iter().find(|(e, _)| *e == ext) {
            out.push((path, *kind));
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(out)
}

/// Compiles every stage in `glsl_dir`. `#include "x.glsl"` resolves inside `glsl_dir`.
pub fn compile_all(glsl_dir: &Path) -> Result<Vec<CompiledShader>> {
    let compiler = shaderc::Compiler::new().context("creating the shaderc compiler")?;
    let mut options = shaderc::CompileOptions::new().context("creating shaderc options")?;
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_2 as u32);
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_warnings_as_errors();
    // The frame's binding numbers come from their one definition, shader_abi::bindings, as
    // BINDING_<NAME> macros (glsl/frame_textures.glsl).
    for (name, number) in crate::shader_abi::bindings::ALL {
        options.add_macro_definition(&format!("BINDING_{name}"), Some(&number.to_string()));
    }
    let include_dir = glsl_dir.to_path_buf();
    options.set_include_callback(move |requested, _kind, requester, _depth| {
        let path = include_dir.join(requested);
        std::fs::read_to_string(&path)
            .map(|content| shaderc::ResolvedInclude { resolved_name: requested.to_string(), content })
            .map_err(|e| format!("{requester}: cannot include {}: {e}", path.display()))
    });
    let mut out = Vec::new();
    for (path, kind) in stage_sources(glsl_dir)? {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let source = std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
        let artifact = compiler
            .compile_into_spirv(&source, kind, &name, "main", Some(&options))
            .map_err(|e| anyhow::anyhow!("compiling {}:\n{e}", path.display()))?;
        out.push(CompiledShader { name, spirv: artifact.as_binary_u8().to_vec() });
    }
    Ok(out)
}

/// `spirv/` files that differ from a fresh compile of `glsl/`, are missing, or have no source.
pub fn stale_files(glsl_dir: &Path, spirv_dir: &Path) -> Result<Vec<String>> {
    let compiled = compile_all(glsl_dir)?;
    let mut stale = Vec::new();
    for c in &compiled {
        let file = spirv_dir.join(format!("{}.spv", c.name));
        match std::fs::read(&file) {
            Ok(bytes) if bytes == c.spirv => {}
            Ok(_) => stale.push(format!("{} differs from {}", file.display(), c.name)),
            Err(_) => stale.push(format!("{} is missing", file.display())),
        }
    }
    for orphan in spirv_files(spirv_dir)? {
        let stem = orphan.file_name().unwrap().to_string_lossy().trim_end_matches(".spv").to_string();
        if !compiled.iter().any(|c| c.name == stem) {
            stale.push(format!("{} has no source in {}", orphan.display(), glsl_dir.display()));
        }
    }
    Ok(stale)
}

/// Compiles `glsl/` into `spirv/`, removing SPIR-V whose source is gone. Returns file names.
pub fn write_all(glsl_dir: &Path, spirv_dir: &Path) -> Result<Vec<String>> {
    let compiled = compile_all(glsl_dir)?;
    std::fs::create_dir_all(spirv_dir)?;
    for orphan in spirv_files(spirv_dir)? {
        let stem = orphan.file_name().unwrap().to_string_lossy().trim_end_matches(".spv").to_string();
        if !compiled.iter().any(|c| c.name == stem) {
            std::fs::remove_file(&orphan)?;
        }
    }
    let mut names = Vec::new();
    for c in compiled {
        let file = spirv_dir.join(format!("{}.spv", c.name));
        std::fs::write(&file, &c.spirv).with_context(|| format!("writing {}", file.display()))?;
        names.push(format!("{}.spv", c.name));
    }
    if names.is_empty() {
        bail!("no shader stages found in {}", glsl_dir.display());
    }
    Ok(names)
}

/// The `.spv` files in `spirv_dir`, sorted.
pub fn spirv_files(spirv_dir: &Path) -> Result<Vec<PathBuf>> {
    let mut out: Vec<PathBuf> = match std::fs::read_dir(spirv_dir) {
        Ok(rd) => rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("spv"))
            .collect(),
        Err(_) => Vec::new(),
    };
    out.sort();
    Ok(out)
}
