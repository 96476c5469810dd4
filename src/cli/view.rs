//! `underlight view`: the method live in a window, optionally scripted.

use super::{context_desc, output_side, prepare_outputs, Cli, PresentModeArg};
use anyhow::{bail, Result};
use std::path::PathBuf;

#[derive(clap::Args)]
pub(super) struct ViewArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Window size; defaults to the scene's output size.
    #[arg(long, value_parser = output_side)]
    width: Option<u32>,
    #[arg(long, value_parser = output_side)]
    height: Option<u32>,
    /// fifo (default, no tearing), mailbox or immediate.
    #[arg(long, value_enum, default_value_t = PresentModeArg::Fifo)]
    present_mode: PresentModeArg,
    /// Exit after this many frames.
    #[arg(long)]
    frames: Option<u32>,
    /// With --frames: save the last presented frame to this PNG.
    #[arg(long, requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Steps to run, then exit: frames:N, resize:WxH, minimize, restore, toggle:caustics|godrays|filter,
    /// water, amplitude:F, move:R/U/F, look:YAW/PITCH, preset:default|high, screenshot:PATH.
    #[arg(long, conflicts_with = "frames")]
    script: Option<String>,
    /// Animation time at start, seconds.
    #[arg(long, default_value_t = 0.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    /// Start with time paused (P toggles, N steps).
    #[arg(long)]
    paused: bool,
    /// Print which passes the viewer creates for the scene and why (the camera moves, so the
    /// passes for the water seen from above exist and run in the frames that need them).
    #[arg(long)]
    explain: bool,
    /// A sweep's sweep.json (`underlight sweep --out DIR`): the title shows the error measured
    /// for the swept setting nearest to the current one. Default: out/sweep/sweep.json if present.
    #[arg(long, value_name = "FILE")]
    sweep: Option<PathBuf>,
    // The viewer starts with these and returns to them with L (the default preset).
    #[command(flatten)]
    effects: super::effect_overrides::EffectOverrides,
}

pub(super) fn run(cli: &Cli, args: &ViewArgs) -> Result<i32> {
    use underlight::viewer::{self, script, ViewerOptions};
    use underlight::vk::swapchain::PresentMode;
    let mut scene = underlight::scene::load(&args.scene)?;
    args.effects.apply(&mut scene);
    super::effect_overrides::check(&scene)?;
    if args.explain {
        println!(
            "passes for scene {:?} in the viewer:\n{}",
            scene.name,
            underlight::frame::FramePlan::new(&scene, true)
        );
    }
    let present_mode = match args.present_mode {
        PresentModeArg::Fifo => PresentMode::Fifo,
        PresentModeArg::Mailbox => PresentMode::Mailbox,
        PresentModeArg::Immediate => PresentMode::Immediate,
    };
    let size = match (args.width, args.height) {
        (None, None) => None,
        (w, h) => {
            // Each given side was checked as it was parsed (`output_side`); the scene's are.
            Some((w.unwrap_or(scene.output[0]), h.unwrap_or(scene.output[1])))
        }
    };
    if args.frames == Some(0) {
        bail!("--frames must be at least 1");
    }
    if let Some(path) = &args.screenshot {
        prepare_outputs([path])?;
    }
    let script = match &args.script {
        Some(text) => script::parse(text)?,
        None => Vec::new(),
    };
    // The sweep is optional: a missing default file gives no estimate; a named file that
    // cannot be read, or is not a sweep, is an error naming it.
    let sweep = match &args.sweep {
        Some(path) => read_sweep(path)?,
        None => read_sweep(std::path::Path::new("out/sweep/sweep.json")).unwrap_or_default(),
    };
    let report = viewer::run(ViewerOptions {
        scene,
        context: context_desc(cli),
        present_mode,
        size,
        script,
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        time: args.time,
        paused: args.paused,
        sweep,
    })?;
    println!("presented {} frames", report.frames_presented);
    let per_pass: Vec<String> = report.pass_frames.iter().map(|(id, n)| format!("{id} {n}")).collect();
    println!("frames per pass: {}", per_pass.join(", "));
    if report.shutdown.is_clean() {
        Ok(0)
    } else {
        eprint!("{}", report.shutdown);
        eprintln!("error: Vulkan validation or leak report is not clean");
        Ok(2)
    }
}

/// A sweep's rows from its JSON file.
fn read_sweep(path: &std::path::Path) -> Result<Vec<underlight::accuracy::SweepRow>> {
    use anyhow::Context as _;
    let text = std::fs::read_to_string(path).with_context(|| format!("--sweep {}: cannot read it", path.display()))?;
    serde_json::from_str(&text)
        .with_context(|| format!("--sweep {}: not the sweep.json `underlight sweep` writes", path.display()))
}
