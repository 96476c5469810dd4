//! `underlight shaders`: compile glsl/ into spirv/, or check that spirv/ is up to date.

use anyhow::Result;
use underlight::shaders;

#[derive(clap::Args)]
pub(super) struct ShadersArgs {
    /// Only check that spirv/ is up to date; exit 1 if not.
    #[arg(long)]
    check: bool,
}

pub(super) fn run(args: &ShadersArgs) -> Result<i32> {
    let (glsl, spirv) = shaders::source_dirs();
    if args.check {
        let stale = shaders::stale_files(&glsl, &spirv)?;
        if stale.is_empty() {
            println!("spirv/ is up to date");
            return Ok(0);
        }
        for s in &stale {
            eprintln!("stale: {s}");
        }
        eprintln!("run `underlight shaders` and commit spirv/");
        return Ok(1);
    }
    for name in shaders::write_all(&glsl, &spirv)? {
        println!("wrote spirv/{name}");
    }
    println!("rebuild to embed the new SPIR-V (cargo build)");
    Ok(0)
}
