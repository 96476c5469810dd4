//! `underlight bench`: per-pass GPU times for the paper's configurations, and `--soak`'s
//! memory over many frames.

use super::{context_desc, finish, prepare_outputs, Cli};
use anyhow::{bail, Context as _, Result};
use std::path::PathBuf;
use underlight::vk::{vk, Context};

#[derive(clap::Args)]
pub(super) struct BenchArgs {
    /// A built-in scene or a scene file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Configurations to run, comma-separated: paper-800, paper-1440, paper-1m-photons,
    /// paper-1440-high, triangles-800 (the triangle caustic estimator as the scenes shipped it
    /// until the footprint points), footprint-points-800 (the footprint-sized points as the
    /// scenes ship them), receiver-800 (those with the receiver test), refined-800,
    /// marched-800 and footprint-800 (triangles-800 refined, with ray-marched godrays, with
    /// footprint-sized beams), triangles-1440, footprint-points-1440, footprint-points-200-1440
    /// and footprint-points-225-1440 (triangles-800, footprint-points-800 and the latter at
    /// 200² and 225² × 3² photons, at the port's and the storage's 1440×850), above-800
    /// (paper-800 seen from above the water), tiny; or "paper" for the paper's four.
    #[arg(long, default_value = "paper")]
    config: String,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 30, value_parser = super::frame_count)]
    frames: u32,
    /// Frames rendered first and discarded (pipeline and cache warm-up).
    #[arg(long, default_value_t = 5, value_parser = super::warmup_count)]
    warmup: u32,
    /// Also run each configuration with the peers of the geometry-shader photon path (vertex
    /// only, compute with atomic splats) and the raw splat floor, and report each one's time
    /// and how its buffers differ from the geometry shader's.
    #[arg(long)]
    compare_paths: bool,
    /// Also measure how each photon pass's cost grows with photons, target size, point size
    /// and line width (from the first configuration), and fit the cost per unit.
    #[arg(long)]
    scaling: bool,
    /// Also count each pass's work per shader stage in the last measured frame (vertex,
    /// geometry-shader invocations and primitives, clipped primitives, fragments, compute
    /// invocations) with pipeline-statistics queries: the work a pass asks of any device,
    /// beside the time it took on this one. Off by default: on some GPUs the queries
    /// serialise the passes they bracket.
    #[arg(long)]
    pipeline_statistics: bool,
    /// Also write the results as JSON / CSV.
    #[arg(long)]
    json: Option<PathBuf>,
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Instead of timing: render the scene N frames and print resident memory and the GPU
    /// allocator's device memory at frame 100 and at frame N (and between).
    #[arg(long, value_name = "N")]
    soak: Option<u64>,
    /// The soak's output size, WxH.
    #[arg(long, value_name = "WxH", default_value = "320x200")]
    soak_size: String,
}

pub(super) fn run(cli: &Cli, args: &BenchArgs) -> Result<i32> {
    use underlight::bench;
    if cli.validation {
        bail!("bench measures with validation off: drop --validation (the layers would dominate the times)");
    }
    if let Some(frames) = args.soak {
        return soak(cli, args, frames);
    }
    let all = bench::configs();
    let names: Vec<&str> = if args.config == "paper" {
        all.iter().filter(|c| c.name.starts_with("paper")).map(|c| c.name).collect()
    } else {
        args.config.split(',').map(str::trim).collect()
    };
    let mut chosen = Vec::new();
    for n in names {
        match all.iter().find(|c| c.name == n) {
            Some(c) => chosen.push(c.clone()),
            None => bail!(
                "--config {n:?}: unknown; configurations are {}",
                all.iter().map(|c| c.name).collect::<Vec<_>>().join(", ")
            ),
        }
    }
    prepare_outputs(args.json.iter().chain(&args.csv))?;
    let scene = underlight::scene::load(&args.scene)?;
    let mut desc = context_desc(cli);
    desc.validation = false;
    let ctx = Context::new(&desc)?;
    if args.pipeline_statistics {
        super::require_pipeline_statistics(&ctx)?;
    }
    let info = &ctx.device.info;
    let mut report = bench::BenchReport {
        device: info.name.clone(),
        driver: format!("{} {}", info.driver_name, info.driver_info),
        results: Vec::new(),
    };
    for c in &chosen {
        eprintln!("{}: {}×{}, {} warm-up + {} frames…", c.name, c.width, c.height, args.warmup, args.frames);
        use underlight::passes::PhotonPath;
        if args.compare_paths {
            report.results.extend(bench::compare_paths(
                &ctx.device,
                &scene,
                c,
                args.frames,
                args.warmup,
                args.pipeline_statistics,
            )?);
        } else {
            report.results.push(bench::run_config(
                &ctx.device,
                &scene,
                c,
                args.frames,
                args.warmup,
                PhotonPath::GeometryShader,
                args.pipeline_statistics,
            )?);
        }
    }
    print!("{}", report.table());
    let series = if args.scaling {
        eprintln!("scaling from {}…", chosen[0].name);
        let s = bench::scaling(&ctx.device, &scene, &chosen[0], args.frames, args.warmup)?;
        print!("\nscaling (from {}):\n{}", chosen[0].name, bench::scaling_table(&s));
        s
    } else {
        Vec::new()
    };
    if let Some(p) = &args.json {
        let json = serde_json::json!({ "report": report, "scaling": series });
        std::fs::write(p, serde_json::to_string_pretty(&json)?).with_context(|| format!("writing {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    if let Some(p) = &args.csv {
        std::fs::write(p, report.csv()).with_context(|| format!("writing {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    Ok(finish(ctx))
}

/// `bench --soak N`: memory after frame 100 and frame N (and at quarters between).
fn soak(cli: &Cli, args: &BenchArgs, frames: u64) -> Result<i32> {
    if frames == 0 {
        bail!("--soak {frames}: must be at least 1 frame");
    }
    let (width, height) = args
        .soak_size
        .split_once('x')
        .and_then(|(w, h)| Some((w.trim().parse::<u32>().ok()?, h.trim().parse::<u32>().ok()?)))
        .filter(|&(w, h)| w >= 1 && h >= 1)
        .with_context(|| {
            format!("--soak-size {:?}: expected WxH with both at least 1, e.g. 320x200", args.soak_size)
        })?;
    prepare_outputs(args.json.iter())?;
    let scene = underlight::scene::load(&args.scene)?;
    let mut desc = context_desc(cli);
    desc.validation = false;
    let ctx = Context::new(&desc)?;
    println!("device: {}", ctx.device.info.describe());
    let first = frames.min(100);
    let mut at = vec![first];
    at.extend((1..=4).map(|q| frames * q / 4).filter(|&f| f > first));
    at.dedup();
    eprintln!("soak: {} frames of {:?} at {width}×{height}…", frames, scene.name);
    let report = underlight::memory::soak(&ctx.device, &scene, vk::Extent2D { width, height }, frames, &at)?;
    println!("{report}");
    if let Some(p) = &args.json {
        std::fs::write(p, serde_json::to_string_pretty(&report)?)
            .with_context(|| format!("writing {}", p.display()))?;
        println!("wrote {}", p.display());
    }
    Ok(finish(ctx))
}
