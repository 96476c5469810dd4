//! The `underlight` command line: the global options, the argument types and parsers the
//! subcommands share, the output helpers, and the dispatch to one module per subcommand.

mod bench;
mod devices;
mod edges;
mod effect_overrides;
mod grid_splat;
mod reference;
mod render;
mod shaders;
mod sweep;
mod tune;
mod view;

use anyhow::{bail, Context as _, Result};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use underlight::vk::{Context, ContextDesc};
// The largest output side a command accepts: a scene file's (docs/limits.md).
use underlight::scene::file::MAX_OUTPUT_SIDE;

#[derive(Parser)]
#[command(name = "underlight", version, about = "Real-time underwater caustics and godrays (Vulkan)")]
pub(crate) struct Cli {
    /// Enable the Khronos validation layer with synchronization validation (also: UNDERLIGHT_VALIDATION=1).
    #[arg(long, global = true)]
    validation: bool,
    /// Use the Vulkan device whose name contains this (also: UNDERLIGHT_DEVICE).
    #[arg(long, global = true, value_name = "NAME")]
    device: Option<String>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless to a PNG (and HDR float dumps) and print per-pass GPU times.
    Render(render::SceneArgs),
    /// Open a window and run the method live (keys are printed at start).
    View(view::ViewArgs),
    /// Per-pass GPU times (median, p5, p95) for the paper's configurations, validation off.
    Bench(bench::BenchArgs),
    /// The foundation's demo: a geometry-shader photon grid splatted into a float target.
    GridSplat(grid_splat::RenderArgs),
    /// Compile glsl/ into spirv/ (the committed SPIR-V the binary embeds).
    Shaders(shaders::ShadersArgs),
    /// List Vulkan devices and whether each has what underlight needs.
    Devices,
    /// The CPU reference of a scene's caustic and godray buffers (exact rays, no image-space
    /// iteration): float dumps and tonemapped PNGs, cached by scene and settings.
    Reference(reference::ReferenceArgs),
    /// The speed–accuracy trade: every combination of the given settings, each one's GPU time
    /// and its error against the reference; writes CSV, a Markdown table and the Pareto plot.
    Sweep(Box<sweep::SweepArgs>),
    /// What the low-resolution effect buffers cost at object edges: the scene as set against
    /// the same frame with its caustic and godray targets at full resolution.
    Edges(edges::EdgesArgs),
    /// State the trade: the cheapest settings under an error bound (or the most accurate
    /// within a GPU-time budget) on this device, as an [effects] block for the scene file.
    Tune(tune::TuneArgs),
}

fn context_desc(cli: &Cli) -> ContextDesc {
    let mut desc = ContextDesc::from_env();
    desc.validation |= cli.validation;
    if cli.device.is_some() {
        desc.device_name = cli.device.clone();
    }
    desc
}

pub(crate) fn run(cli: Cli) -> Result<i32> {
    match &cli.command {
        Command::Shaders(args) => shaders::run(args),
        Command::Devices => devices::run(),
        Command::Render(args) => render::run(&cli, args),
        Command::Reference(args) => reference::run(args),
        Command::Sweep(args) => sweep::run(&cli, args),
        Command::View(args) => view::run(&cli, args),
        Command::Bench(args) => bench::run(&cli, args),
        Command::GridSplat(args) => grid_splat::run(&cli, args),
        Command::Edges(args) => edges::run(&cli, args),
        Command::Tune(args) => tune::run(&cli, args),
    }
}

/// A whole number of `unit` within `range`, for the options that count things: the error
/// names the text that is not a number, or the range and the value outside it.
fn whole_number_in<T>(text: &str, unit: &str, range: std::ops::RangeInclusive<T>) -> std::result::Result<T, String>
where
    T: std::str::FromStr + PartialOrd + std::fmt::Display + Default,
{
    let v: T = text.trim().parse().map_err(|_| format!("{text:?} is not a whole number of {unit}"))?;
    if !range.contains(&v) {
        let (min, max) = (range.start(), range.end());
        return Err(if *min == T::default() {
            format!("must be at most {max} (got {v})")
        } else {
            format!("must be at least {min} and at most {max} (got {v})")
        });
    }
    Ok(v)
}

/// `--width` / `--height` values: whole pixels, at least 1.
fn output_side(text: &str) -> std::result::Result<u32, String> {
    whole_number_in(text, "pixels", 1..=MAX_OUTPUT_SIDE)
}

/// The most frames a command renders for `--frames` or `--warmup`: 100 000 is over ten hours
/// of a frame on lavapipe and minutes on a GPU. The timings are kept per frame, so a count
/// near u32's range would fill memory before it finished (`bench --soak` is the long run).
const MAX_FRAMES: u32 = 100_000;

/// `--frames` values: a whole number of frames, at least 1 (a command asked for none would
/// otherwise render one and report it as the median of zero) and at most MAX_FRAMES.
fn frame_count(text: &str) -> std::result::Result<u32, String> {
    whole_number_in(text, "frames", 1..=MAX_FRAMES)
}

/// `--warmup` values: a whole number of frames rendered and discarded, 0 to MAX_FRAMES.
fn warmup_count(text: &str) -> std::result::Result<u32, String> {
    whole_number_in(text, "frames", 0..=MAX_FRAMES)
}

/// `--time` and `--step` values: finite seconds. A NaN or infinite clock reaches every wave
/// phase, so the waves, and with them every photon, would be NaN: the frame would render with
/// nothing in its effect buffers, reported as "no photon landed" for the wrong reason.
fn seconds(text: &str) -> std::result::Result<f32, String> {
    let v: f32 = text.trim().parse().map_err(|_| format!("{text:?} is not a number of seconds"))?;
    if !v.is_finite() {
        return Err(format!("must be a finite number of seconds (got {v})"));
    }
    Ok(v)
}

/// `grid-splat --exposure`: a positive, finite tonemap exposure.
fn exposure(text: &str) -> std::result::Result<f32, String> {
    let v: f32 = text.trim().parse().map_err(|_| format!("{text:?} is not a number"))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(format!("must be positive and finite (got {v})"));
    }
    Ok(v)
}

/// `sweep --filter` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum OnOff {
    On,
    Off,
}

/// `view --present-mode` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum PresentModeArg {
    /// No tearing, paced by the display.
    Fifo,
    Mailbox,
    Immediate,
}

/// `--caustic-estimator` / `--estimator` values.
fn caustic_estimator(name: &str) -> std::result::Result<underlight::scene::CausticEstimator, String> {
    use underlight::scene::CausticEstimator;
    CausticEstimator::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = CausticEstimator::ALL.iter().map(|e| e.name()).collect();
        format!("no caustic estimator {name:?}; there are {}", names.join(", "))
    })
}

/// `--caustic-photon-density`, `--godray-photon-density` and the sweep's axes' values.
fn photon_spread(name: &str) -> std::result::Result<underlight::scene::PhotonSpread, String> {
    use underlight::scene::PhotonSpread;
    PhotonSpread::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = PhotonSpread::ALL.iter().map(|d| d.name()).collect();
        format!("no photon density {name:?}; there are {}", names.join(", "))
    })
}

/// `sweep --godray-method` values.
fn godray_method(name: &str) -> std::result::Result<underlight::scene::GodrayMethod, String> {
    use underlight::scene::GodrayMethod;
    GodrayMethod::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = GodrayMethod::ALL.iter().map(|m| m.name()).collect();
        format!("no godray method {name:?}; there are {}", names.join(", "))
    })
}

/// Makes the outputs' folders and checks each output can be written there, before any
/// rendering: a wrong path fails in a second, not after the frames, and leaves nothing behind.
fn prepare_outputs<'a>(paths: impl IntoIterator<Item = &'a PathBuf>) -> Result<()> {
    for path in paths {
        if path.is_dir() {
            bail!("output {} is a directory: give a file name", path.display());
        }
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
        writable_folder(dir, &format!("output {}", path.display()))?;
    }
    Ok(())
}

/// Makes `dir` and checks a file can be written in it; errors begin with `what`.
fn writable_folder(dir: &std::path::Path, what: &str) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("{what}: cannot create {}", dir.display()))?;
    let probe = dir.join(format!(".underlight-write-check-{}", std::process::id()));
    std::fs::write(&probe, b"").with_context(|| format!("{what}: cannot write in {}", dir.display()))?;
    std::fs::remove_file(&probe).ok();
    Ok(())
}

/// The same for an output folder (`--out DIR`, `--hdr DIR`): made, and checked writable, before
/// any rendering. A file in its place is named as such.
fn prepare_output_dir(dir: &std::path::Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        bail!("output folder {} is a file: give a folder", dir.display());
    }
    writable_folder(dir, "output folder")
}

/// `--pipeline-statistics` on a device that cannot count: a named error before any rendering.
fn require_pipeline_statistics(ctx: &Context) -> Result<()> {
    if !ctx.device.has_pipeline_statistics() {
        anyhow::bail!(
            "--pipeline-statistics: {} offers no pipeline-statistics queries (pipelineStatisticsQuery)",
            ctx.device.info.name
        );
    }
    Ok(())
}

fn finish(ctx: Context) -> i32 {
    let report = ctx.shutdown();
    if report.is_clean() {
        return 0;
    }
    eprint!("{report}");
    eprintln!("error: Vulkan validation or leak report is not clean");
    2
}

/// The exposure of the effect buffers' PNGs (`reference`, `render --hdr`): the compose
/// pass's, which shows the surface irradiance on a white receiver at mid grey.
fn effect_png_exposure(scene: &underlight::scene::Scene) -> f32 {
    underlight::frame::uniforms::tonemap_exposure(scene)
}
