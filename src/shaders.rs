//! GLSL → SPIR-V. The GLSL in `glsl/` is compiled by `underlight shaders` (shaderc) into
//! `spirv/`, which is committed and embedded in the binary at build time, so running
//! underlight needs no shader compiler. A test recompiles everything and fails when the
//! committed SPIR-V is stale.
//!
//! `glsl/` has a folder per pass (`shadow/`, `scene/`, `surface/`, `photons/`, `caustics/`,
//! `godrays/`, `filter/`, `compose/`, and `grid_splat/` for the demo) and `shared/` for what
//! every pass includes: the frame's parameters and bindings (`frame.glsl`,
//! `frame_textures.glsl`) and the shader math whose Rust twin is `shader_math.rs`
//! (`shader_math.glsl`). Every `.vert`/`.geom`/`.frag`/`.comp` is a program named by its file
//! name; [`VARIANTS`] adds the programs that are another's source with defines.

use crate::vk::device::Device;
use crate::vk::pipeline::{ComputePipelineDesc, GraphicsPipelineDesc, Pipeline};
use anyhow::{bail, Context as _, Result};
use std::path::{Path, PathBuf};
use std::sync::Arc;

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

pub use crate::vk::pipeline::spirv_words;

/// A graphics pipeline whose stages are the embedded programs its description names.
pub fn graphics_pipeline(device: &Arc<Device>, desc: &GraphicsPipelineDesc<'_>) -> crate::error::Result<Pipeline> {
    Pipeline::graphics(device, &embedded, desc)
}

/// A compute pipeline whose shader is the embedded program its description names.
pub fn compute_pipeline(device: &Arc<Device>, desc: &ComputePipelineDesc<'_>) -> crate::error::Result<Pipeline> {
    Pipeline::compute(device, &embedded, desc)
}

/// The source tree's `glsl/` and `spirv/` folders (this crate's, as built).
pub fn source_dirs() -> (PathBuf, PathBuf) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    (root.join("glsl"), root.join("spirv"))
}

pub struct CompiledShader {
    /// Program name, e.g. `grid_splat.geom`; the SPIR-V file is `<name>.spv`.
    pub name: String,
    pub spirv: Vec<u8>,
}

/// A program compiled from another program's source with preprocessor defines, in place of a
/// stub file per variant. Its SPIR-V is `spirv/<name>.spv` like any other program's.
pub struct Variant {
    /// Program name; the stage is its extension, which is the source's.
    pub name: &'static str,
    /// Source under `glsl/`.
    pub source: &'static str,
    pub defines: &'static [&'static str],
}

/// Every variant program. The passes pick among them by name (`passes::compose`,
/// `passes::scene`, `passes::caustics`).
pub const VARIANTS: &[Variant] = &[
    // Every photon's cast recorded for the tests (glsl/caustics/caustics.geom).
    Variant { name: "caustics_debug.geom", source: "caustics/caustics.geom", defines: &["PHOTON_DEBUG"] },
    // Footprint-sized points (effects.caustic_estimator = "footprint"), and recording.
    Variant { name: "caustics_footprint.geom", source: "caustics/caustics.geom", defines: &["FOOTPRINT_POINTS"] },
    Variant {
        name: "caustics_footprint_debug.geom",
        source: "caustics/caustics.geom",
        defines: &["FOOTPRINT_POINTS", "PHOTON_DEBUG"],
    },
    Variant { name: "caustics_footprint.frag", source: "caustics/caustics.frag", defines: &["FOOTPRINT_POINTS"] },
    // Their hats held to the pixels that show their receiver (effects.caustic_receiver_test).
    Variant {
        name: "caustics_footprint_receiver.geom",
        source: "caustics/caustics.geom",
        defines: &["FOOTPRINT_POINTS", "FOOTPRINT_RECEIVER_TEST"],
    },
    Variant {
        name: "caustics_footprint_receiver.frag",
        source: "caustics/caustics.frag",
        defines: &["FOOTPRINT_POINTS", "FOOTPRINT_RECEIVER_TEST"],
    },
    // The caustic triangles with refinement at receivers' borders (effects.caustic_refinement):
    // the grid's draw hands cells on, the refinement draw casts them finer. Its own program,
    // since its stores need vertexPipelineStoresAndAtomics.
    Variant {
        name: "caustics_triangles_refined.geom",
        source: "caustics/caustics_triangles.geom",
        defines: &["CAUSTIC_REFINEMENT"],
    },
    // Every godray beam's cast recorded for the flux budget (glsl/godrays/godrays.geom).
    Variant { name: "godrays_debug.geom", source: "godrays/godrays.geom", defines: &["PHOTON_DEBUG"] },
    // The same for the footprint-sized beams (glsl/godrays/godrays_footprint.geom).
    Variant {
        name: "godrays_footprint_debug.geom",
        source: "godrays/godrays_footprint.geom",
        defines: &["PHOTON_DEBUG"],
    },
    // The ribbons' fragments: their radiance spread over their width (glsl/godrays/godrays.frag).
    Variant { name: "godrays_footprint.frag", source: "godrays/godrays.frag", defines: &["BEAM_FOOTPRINT"] },
    // The reflection pass writes colour only (glsl/scene/scene.frag).
    Variant { name: "reflection.frag", source: "scene/scene.frag", defines: &["COLOR_ONLY"] },
    // Compose binds only the effects a scene has (glsl/compose/compose.frag).
    Variant { name: "compose_caustics.frag", source: "compose/compose.frag", defines: &["HAS_CAUSTICS"] },
    Variant { name: "compose_godrays.frag", source: "compose/compose.frag", defines: &["HAS_GODRAYS"] },
    Variant {
        name: "compose_caustics_godrays.frag",
        source: "compose/compose.frag",
        defines: &["HAS_CAUSTICS", "HAS_GODRAYS"],
    },
    // The surface seen from above (with the refraction and reflection passes), with the
    // effects the scene has (glsl/surface/water.frag).
    Variant { name: "water_above.frag", source: "surface/water.frag", defines: &["THROUGH_SURFACE"] },
    Variant {
        name: "water_above_caustics.frag",
        source: "surface/water.frag",
        defines: &["THROUGH_SURFACE", "HAS_CAUSTICS"],
    },
    Variant {
        name: "water_above_godrays.frag",
        source: "surface/water.frag",
        defines: &["THROUGH_SURFACE", "HAS_GODRAYS"],
    },
    Variant {
        name: "water_above_caustics_godrays.frag",
        source: "surface/water.frag",
        defines: &["THROUGH_SURFACE", "HAS_CAUSTICS", "HAS_GODRAYS"],
    },
];

/// The folder of includes every shader may name without a path (`glsl/shared/`); any other
/// include is relative to the including file.
const SHARED_INCLUDES: &str = "shared";

fn stage_kind(path: &Path) -> Option<shaderc::ShaderKind> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    STAGES.iter().find(|(e, _)| *e == ext).map(|(_, kind)| *kind)
}

/// Stage sources (not includes) anywhere under `glsl_dir`, as paths relative to it, sorted.
/// A program is named by its file name, so two stages with one name are an error.
pub fn stage_sources(glsl_dir: &Path) -> Result<Vec<(PathBuf, shaderc::ShaderKind)>> {
    let mut out = Vec::new();
    let mut folders = vec![PathBuf::new()];
    while let Some(folder) = folders.pop() {
        let dir = glsl_dir.join(&folder);
        for entry in std::fs::read_dir(&dir).with_context(|| format!("reading {}", dir.display()))? {
            let entry = entry?;
            let relative = folder.join(entry.file_name());
            if entry.file_type()?.is_dir() {
                folders.push(relative);
            } else if let Some(kind) = stage_kind(&relative) {
                out.push((relative, kind));
            }
        }
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    let mut names = std::collections::HashSet::new();
    for (path, _) in &out {
        if !names.insert(path.file_name()) {
            bail!("two shader stages under {} are named {:?}", glsl_dir.display(), path.file_name().unwrap());
        }
    }
    Ok(out)
}

/// `a/b/../c` → `a/c`, without touching the file system (include names stay relative).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            std::path::Component::ParentDir => {
                out.pop();
            }
            std::path::Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// Compile options with the frame's binding macros, the include rule and `defines`.
fn compile_options<'a>(glsl_dir: &Path, defines: &[&str]) -> Result<shaderc::CompileOptions<'a>> {
    let mut options = shaderc::CompileOptions::new().context("creating shaderc options")?;
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_2 as u32);
    options.set_source_language(shaderc::SourceLanguage::GLSL);
    options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    options.set_warnings_as_errors();
    // The frame's binding numbers come from their one definition, shader_abi::bindings, as
    // BINDING_<NAME> macros (glsl/shared/frame_textures.glsl).
    for (name, number) in crate::shader_abi::bindings::ALL {
        options.add_macro_definition(&format!("BINDING_{name}"), Some(&number.to_string()));
    }
    // And the geometry shaders' bounds, from shader_abi::limits, under their own names.
    for (name, value) in crate::shader_abi::limits::ALL {
        options.add_macro_definition(name, Some(&value.to_string()));
    }
    for define in defines {
        options.add_macro_definition(define, None);
    }
    let root = glsl_dir.to_path_buf();
    options.set_include_callback(move |requested, _kind, requester, _depth| {
        // Names are relative to glsl/ (the requester's is what this callback resolved it to).
        let beside = normalize(&Path::new(requester).parent().unwrap_or(Path::new("")).join(requested));
        let shared = Path::new(SHARED_INCLUDES).join(requested);
        let resolved = [beside, shared].into_iter().find(|p| root.join(p).is_file()).ok_or_else(|| {
            format!("{requester}: cannot include {requested:?}: not beside it, nor in glsl/{SHARED_INCLUDES}/")
        })?;
        std::fs::read_to_string(root.join(&resolved))
            .map(|content| shaderc::ResolvedInclude { resolved_name: resolved.to_string_lossy().into_owned(), content })
            .map_err(|e| format!("{requester}: cannot include {}: {e}", resolved.display()))
    });
    Ok(options)
}

/// Compiles every stage under `glsl_dir` and every [`VARIANTS`] entry.
pub fn compile_all(glsl_dir: &Path) -> Result<Vec<CompiledShader>> {
    let compiler = shaderc::Compiler::new().context("creating the shaderc compiler")?;
    let stages = stage_sources(glsl_dir)?;
    let mut programs: Vec<(String, PathBuf, shaderc::ShaderKind, &[&str])> = stages
        .iter()
        .map(|(path, kind)| (path.file_name().unwrap().to_string_lossy().into_owned(), path.clone(), *kind, &[][..]))
        .collect();
    for variant in VARIANTS {
        // A scratch glsl/ (tests) may lack a variant's source: the variant is then not built.
        if let Some((path, kind)) = stages.iter().find(|(p, _)| p == Path::new(variant.source)) {
            programs.push((variant.name.to_string(), path.clone(), *kind, variant.defines));
        }
    }
    let mut out = Vec::new();
    for (name, path, kind, defines) in programs {
        // Fragment shaders read the frame's values from a uniform block (glsl/shared/frame.glsl).
        let stage: &[&str] = if kind == shaderc::ShaderKind::Fragment { &["FRAGMENT_STAGE"] } else { &[] };
        let defines: Vec<&str> = defines.iter().chain(stage).copied().collect();
        let options = compile_options(glsl_dir, &defines)?;
        let file = glsl_dir.join(&path);
        let source = std::fs::read_to_string(&file).with_context(|| format!("reading {}", file.display()))?;
        let artifact = compiler
            .compile_into_spirv(&source, kind, &path.to_string_lossy(), "main", Some(&options))
            .map_err(|e| anyhow::anyhow!("compiling {name} from {}:\n{e}", file.display()))?;
        out.push(CompiledShader { name, spirv: artifact.as_binary_u8().to_vec() });
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
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
