//! The `underlight` command line.

use anyhow::{bail, Context as _, Result};
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use underlight::headless;
use underlight::image_io;
use underlight::passes::grid_splat::GridSplatSettings;
use underlight::shaders;
use underlight::vk::{vk, Context, ContextDesc};

#[derive(Parser)]
#[command(name = "underlight", version, about = "Real-time underwater caustics and godrays (Vulkan)")]
struct Cli {
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
    Render(SceneArgs),
    /// Open a window and run the method live (keys are printed at start).
    View(ViewArgs),
    /// Per-pass GPU times (median, p5, p95) for the paper's configurations, validation off.
    Bench(BenchArgs),
    /// The foundation's demo: a geometry-shader photon grid splatted into a float target.
    GridSplat(RenderArgs),
    /// Compile glsl/ into spirv/ (the committed SPIR-V the binary embeds).
    Shaders {
        /// Only check that spirv/ is up to date; exit 1 if not.
        #[arg(long)]
        check: bool,
    },
    /// List Vulkan devices and whether each has what underlight needs.
    Devices,
    /// The CPU reference of a scene's caustic and godray buffers (exact rays, no image-space
    /// iteration): float dumps and tonemapped PNGs, cached by scene and settings.
    Reference(ReferenceArgs),
    /// The speed–accuracy trade: every combination of the given settings, each one's GPU time
    /// and its error against the reference; writes CSV, a Markdown table and the Pareto plot.
    Sweep(SweepArgs),
}

/// The reference's own settings (shared by `reference` and `sweep`).
#[derive(clap::Args)]
struct ReferenceOptions {
    /// Caustic photons the reference traces over the whole water surface.
    #[arg(long, default_value_t = 8_000_000)]
    photons: u64,
    /// Godray beams the reference traces.
    #[arg(long, default_value_t = 1_000_000)]
    beams: u64,
    /// Worker threads (0: all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where reference buffers are cached (default: ~/.cache/underlight/reference).
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

impl ReferenceOptions {
    fn settings(&self) -> underlight::reference::ReferenceSettings {
        underlight::reference::ReferenceSettings {
            caustic_photons: self.photons,
            godray_beams: self.beams,
            threads: self.threads,
            seed: self.seed,
        }
    }

    fn cache_dir(&self) -> PathBuf {
        self.cache.clone().unwrap_or_else(underlight::accuracy::default_cache_dir)
    }
}

#[derive(clap::Args)]
struct ReferenceArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Folder for caustics.pfm / godrays.pfm and their PNGs.
    #[arg(long, default_value = "out/reference")]
    out: PathBuf,
    /// Output size the buffers belong to (the effect targets scale from it); defaults to the scene's.
    #[arg(long, value_parser = output_side)]
    width: Option<u32>,
    #[arg(long, value_parser = output_side)]
    height: Option<u32>,
    /// Animation time, seconds (the same default as `render`'s first frame).
    #[arg(long, default_value_t = 1.0)]
    time: f32,
    /// Also trace twice the photons and beams (another seed) and print how much the buffers
    /// change: the reference's own error, which must stay below the errors it measures.
    #[arg(long)]
    convergence: bool,
    #[command(flatten)]
    reference: ReferenceOptions,
}

#[derive(clap::Args)]
struct SweepArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Output size (small by default: every setting renders and is compared at this size).
    #[arg(long, value_parser = output_side, default_value_t = 240)]
    width: u32,
    #[arg(long, value_parser = output_side, default_value_t = 150)]
    height: u32,
    /// Caustic grid cells per axis, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = [48u32, 96, 192])]
    grid: Vec<u32>,
    /// Geometry-shader subdivisions per axis.
    #[arg(long, value_delimiter = ',')]
    subdiv: Vec<u32>,
    /// Image-space iterations.
    #[arg(long, value_delimiter = ',')]
    iterations: Vec<u32>,
    /// Caustic target scale relative to the output.
    #[arg(long, value_delimiter = ',')]
    target: Vec<f32>,
    /// Largest caustic point size, px (the smallest is lowered to it where larger).
    #[arg(long, value_delimiter = ',')]
    point_size: Vec<f32>,
    /// Godray line width, px.
    #[arg(long, value_delimiter = ',')]
    line_width: Vec<f32>,
    /// Filter on, off, or both.
    #[arg(long, value_delimiter = ',', value_enum, default_values_t = [OnOff::Off, OnOff::On])]
    filter: Vec<OnOff>,
    /// Caustic estimators: paper, triangles (comma-separated).
    #[arg(long, value_delimiter = ',', value_parser = caustic_estimator)]
    estimator: Vec<underlight::scene::CausticEstimator>,
    /// Timed frames per setting (median) and warm-up frames.
    #[arg(long, default_value_t = 5)]
    frames: u32,
    #[arg(long, default_value_t = 2)]
    warmup: u32,
    /// Animation time, seconds, and the step to the next frame for the flicker figure.
    #[arg(long, default_value_t = 1.0)]
    time: f32,
    #[arg(long, default_value_t = 1.0 / 30.0)]
    step: f32,
    /// Folder for sweep.csv, sweep.md, sweep.json and sweep.png.
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    #[command(flatten)]
    reference: ReferenceOptions,
}

#[derive(clap::Args)]
struct SceneArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Output PNG (tonemapped sRGB).
    #[arg(long, default_value = "out/underlight.png")]
    out: PathBuf,
    /// Also write the HDR targets (scene colour, caustic irradiance, …) as PFM into this folder.
    #[arg(long, value_name = "DIR")]
    hdr: Option<PathBuf>,
    /// Output size; defaults to the scene's.
    #[arg(long, value_parser = output_side)]
    width: Option<u32>,
    #[arg(long, value_parser = output_side)]
    height: Option<u32>,
    /// Frames to render (timings are the median over them).
    #[arg(long, default_value_t = 8)]
    frames: u32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 1.0)]
    time: f32,
    /// Print which passes the scene needs and why, then render.
    #[arg(long)]
    explain: bool,
    /// Also render one frame recording every caustic photon (the paper's points, the same
    /// photons) and print where their flux goes: landed, reflected, dropped by reason.
    #[arg(long)]
    flux_budget: bool,
    /// Put the camera here instead of the scene's position, e.g. `0.3,1.5,0.2` (above the
    /// water the surface reflects and refracts).
    #[arg(long, value_name = "X,Y,Z", value_delimiter = ',', allow_hyphen_values = true)]
    camera: Option<Vec<f32>>,
    /// Point the camera at this point instead of the scene's look_at.
    #[arg(long, value_name = "X,Y,Z", value_delimiter = ',', allow_hyphen_values = true)]
    look_at: Option<Vec<f32>>,
    /// Turn photons into irradiance with this estimator instead of the scene's: paper
    /// (distance-sized points) or triangles (warped-cell triangles).
    #[arg(long, value_name = "NAME", value_parser = caustic_estimator)]
    caustic_estimator: Option<underlight::scene::CausticEstimator>,
}

/// The largest output side a command accepts (as a scene file's `output`: docs/limits.md).
const MAX_OUTPUT_SIDE: u32 = 16384;

/// `--width` / `--height` values: whole pixels, at least 1.
fn output_side(text: &str) -> std::result::Result<u32, String> {
    let v: u32 = text.trim().parse().map_err(|_| format!("{text:?} is not a whole number of pixels"))?;
    if !(1..=MAX_OUTPUT_SIDE).contains(&v) {
        return Err(format!("must be at least 1 and at most {MAX_OUTPUT_SIDE} (got {v})"));
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

#[derive(clap::Args)]
struct BenchArgs {
    /// A built-in scene or a scene file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Configurations to run, comma-separated: paper-800, paper-1440, paper-1m-photons,
    /// paper-1440-high, triangles-800 (the triangle caustic estimator as the scenes ship it),
    /// above-800 (paper-800 seen from above the water), tiny; or "paper" for the paper's four.
    #[arg(long, default_value = "paper")]
    config: String,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 30)]
    frames: u32,
    /// Frames rendered first and discarded (pipeline and cache warm-up).
    #[arg(long, default_value_t = 5)]
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

#[derive(clap::Args)]
struct ViewArgs {
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
    #[arg(long, default_value_t = 0.0)]
    time: f32,
    /// Start with time paused (P toggles, N steps).
    #[arg(long)]
    paused: bool,
    /// Print which passes the viewer creates for the scene and why (the camera moves, so the
    /// passes for the water seen from above exist and run in the frames that need them).
    #[arg(long)]
    explain: bool,
}

#[derive(clap::Args)]
struct RenderArgs {
    /// Output PNG (tonemapped sRGB).
    #[arg(long, default_value = "out/grid_splat.png")]
    out: PathBuf,
    /// Also write the HDR target as a PFM float dump.
    #[arg(long)]
    pfm: Option<PathBuf>,
    #[arg(long, value_parser = output_side, default_value_t = 512)]
    width: u32,
    #[arg(long, value_parser = output_side, default_value_t = 512)]
    height: u32,
    /// Coarse photon grid cells per axis.
    #[arg(long, default_value_t = 200)]
    grid: u32,
    /// Geometry-shader subdivision per axis (photons per cell = subdivision²).
    #[arg(long, default_value_t = 2)]
    subdivision: u32,
    /// Point size in pixels.
    #[arg(long, default_value_t = 2.0)]
    point_size: f32,
    /// Energy each photon adds.
    #[arg(long, default_value_t = 0.08)]
    energy: f32,
    /// Displacement of the photons by the demo wave (0: a regular grid; above ~1 the
    /// displaced photons cross and focus into caustic lines).
    #[arg(long, default_value_t = 1.3)]
    wave_amplitude: f32,
    /// Frames to render (timings are the median over them).
    #[arg(long, default_value_t = 16)]
    frames: u32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 0.0)]
    time: f32,
    /// Tonemap exposure.
    #[arg(long, default_value_t = 1.0)]
    exposure: f32,
}

fn main() {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::exit(1);
        }
    }
}

fn context_desc(cli: &Cli) -> ContextDesc {
    let mut desc = ContextDesc::from_env();
    desc.validation |= cli.validation;
    if cli.device.is_some() {
        desc.device_name = cli.device.clone();
    }
    desc
}

fn run(cli: Cli) -> Result<i32> {
    match &cli.command {
        Command::Shaders { check } => {
            let (glsl, spirv) = shaders::source_dirs();
            if *check {
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
        Command::Devices => {
            let instance = underlight::vk::instance::Instance::new(false, &[])?;
            let devices = underlight::vk::device::enumerate(&instance)?;
            if devices.is_empty() {
                bail!(underlight::Error::NoDevice);
            }
            for d in &devices {
                let missing = underlight::vk::features::missing_features(&d.capabilities);
                let verdict =
                    if missing.is_empty() { "suitable".to_string() } else { format!("lacks {}", missing.join(", ")) };
                println!("{}: {verdict}", d.describe());
            }
            Ok(0)
        }
        Command::Render(args) => render_scene(&cli, args),
        Command::Reference(args) => reference(args),
        Command::Sweep(args) => sweep(&cli, args),
        Command::View(args) => view(&cli, args),
        Command::Bench(args) => bench(&cli, args),
        Command::GridSplat(args) => grid_splat(&cli, args),
    }
}

/// Creates the parent folder of each output path up front, so a bad path fails before any
/// GPU work.
/// Makes the outputs' folders and checks each output can be written there, before any
/// rendering: a wrong path fails in a second, not after the frames, and leaves nothing behind.
fn prepare_outputs<'a>(paths: impl IntoIterator<Item = &'a PathBuf>) -> Result<()> {
    for path in paths {
        if path.is_dir() {
            bail!("output {} is a directory: give a file name", path.display());
        }
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(std::path::Path::new("."));
        std::fs::create_dir_all(dir)
            .with_context(|| format!("output {}: cannot create {}", path.display(), dir.display()))?;
        let probe = dir.join(format!(".underlight-write-check-{}", std::process::id()));
        std::fs::write(&probe, b"")
            .with_context(|| format!("output {}: cannot write in {}", path.display(), dir.display()))?;
        std::fs::remove_file(&probe).ok();
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

fn render_scene(cli: &Cli, args: &SceneArgs) -> Result<i32> {
    let mut scene = underlight::scene::load(&args.scene)?;
    let point = |name: &str, v: &Option<Vec<f32>>| -> Result<Option<glam::Vec3>> {
        match v.as_deref() {
            None => Ok(None),
            Some([x, y, z]) if [x, y, z].iter().all(|c| c.is_finite()) => Ok(Some(glam::Vec3::new(*x, *y, *z))),
            Some(other) => bail!("--{name} takes three finite numbers X,Y,Z (got {other:?})"),
        }
    };
    if let Some(p) = point("camera", &args.camera)? {
        scene.camera.position = p;
    }
    if let Some(p) = point("look-at", &args.look_at)? {
        scene.camera.look_at = p;
    }
    if let Some(estimator) = args.caustic_estimator {
        scene.effects.caustic_estimator = estimator;
    }
    if scene.camera.position.distance(scene.camera.look_at) < 1e-6 {
        bail!("--camera and --look-at give the same point: the camera needs a direction to look in");
    }
    let width = args.width.unwrap_or(scene.output[0]);
    let height = args.height.unwrap_or(scene.output[1]);
    prepare_outputs([&args.out])?;
    if let Some(dir) = &args.hdr {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let plan = underlight::frame::FramePlan::for_scene(&scene);
    if args.explain {
        println!("passes for scene {:?}:\n{plan}", scene.name);
    }
    let ctx = Context::new(&context_desc(cli))?;
    println!("device: {}", ctx.device.info.describe());
    let extent = vk::Extent2D { width, height };
    let (timings, images) = {
        let mut renderer = headless::SceneRenderer::new(&ctx.device, &scene, extent)?;
        for note in &renderer.frame.clamped {
            eprintln!("warning: {note}");
        }
        let e = renderer.frame.extents;
        println!(
            "scene {:?}: {width}×{height}; caustics {}² × {}² photons into {}×{}; light maps {}²",
            scene.name,
            scene.effects.caustic_grid,
            scene.effects.caustic_subdivision,
            e.caustic[0],
            e.caustic[1],
            e.light_map
        );
        renderer.render(args.frames.max(1), args.time, 1.0 / 60.0, true)?
    };
    let images = images.expect("read back requested");
    let silent = images.silent_effects(&scene);
    if args.explain && !silent.is_empty() {
        println!("after the last frame:");
    }
    for note in &silent {
        if args.explain {
            println!("  {note}");
        }
        eprintln!("warning: {note}");
    }
    image_io::write_png(&args.out, images.width, images.height, &images.output)?;
    println!("wrote {}", args.out.display());
    if let Some(dir) = &args.hdr {
        let mut dumps =
            vec![("scene_color", &images.scene_color), ("albedo_transmittance", &images.albedo_transmittance)];
        for (name, img) in [
            ("caustics", &images.caustics),
            ("caustics_filtered", &images.caustics_filtered),
            ("godrays", &images.godrays),
            ("godrays_filtered", &images.godrays_filtered),
        ] {
            if let Some(img) = img {
                dumps.push((name, img));
            }
        }
        for (name, img) in dumps {
            let path = dir.join(format!("{name}.pfm"));
            image_io::write_pfm(&path, img)?;
            println!("wrote {}", path.display());
        }
        // The effect buffers also as PNGs at the exposure `reference` writes its own with, so
        // the two sit side by side.
        for (name, img, scale) in [
            ("caustics", &images.caustics, 1.0 / std::f32::consts::PI),
            ("caustics_filtered", &images.caustics_filtered, 1.0 / std::f32::consts::PI),
            ("godrays", &images.godrays, 1.0),
            ("godrays_filtered", &images.godrays_filtered, 1.0),
        ] {
            if let Some(img) = img {
                let path = dir.join(format!("{name}.png"));
                let exposure = effect_png_exposure(&scene) * scale;
                image_io::write_png(&path, img.width, img.height, &image_io::tonemap_srgb8(img, exposure))?;
                println!("wrote {}", path.display());
            }
        }
    }
    println!("\nmedian over {} frames:\n{}", timings.len(), headless::median_timings(&timings));
    if args.flux_budget {
        print_flux_budget(&ctx, &scene, extent, args.time)?;
    }
    Ok(finish(ctx))
}

/// `render --flux-budget`: one frame through the photon-recording geometry shader (the
/// paper's points: recording is theirs, and the photons are the same for every estimator).
fn print_flux_budget(ctx: &Context, scene: &underlight::scene::Scene, extent: vk::Extent2D, time: f32) -> Result<()> {
    let mut recorded = scene.clone();
    recorded.effects.caustic_estimator = underlight::scene::CausticEstimator::Paper;
    if !recorded.effects.caustics || !ctx.device.has_pipeline_stores() {
        bail!("--flux-budget needs caustics and a device with vertexPipelineStoresAndAtomics");
    }
    let options = underlight::frame::FrameOptions { record_photons: true, ..Default::default() };
    let mut renderer = headless::SceneRenderer::with_options(&ctx.device, &recorded, extent, options)?;
    let extents = renderer.frame.extents;
    let (_, images) = renderer.render(1, time, 0.0, true)?;
    drop(renderer);
    let Some(records) = images.and_then(|i| i.photon_records) else {
        bail!("--flux-budget: the caustics pass did not run, so no photon was recorded");
    };
    let mut budget = underlight::flux_budget::FluxBudget::from_records(&records);
    let u = underlight::frame::uniforms::FrameUniforms::new(&recorded, recorded.bounds(), &extents, time);
    budget.light_power = underlight::flux_budget::grid_power(&u);
    println!("\nflux budget at t = {time} s:\n{budget}");
    Ok(())
}

/// The exposure of the effect buffers' PNGs (`reference`, `render --hdr`): the compose
/// pass's, which shows the surface irradiance on a white receiver at mid grey.
fn effect_png_exposure(scene: &underlight::scene::Scene) -> f32 {
    2.0 * std::f32::consts::PI / underlight::frame::uniforms::surface_irradiance(scene)
}

fn reference(args: &ReferenceArgs) -> Result<i32> {
    let scene = underlight::scene::load(&args.scene)?;
    let output = [args.width.unwrap_or(scene.output[0]), args.height.unwrap_or(scene.output[1])];
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    // The device's point and line limits do not enter the reference.
    let extents = underlight::frame::target_extents(&scene, output, f32::INFINITY, f32::INFINITY);
    let started = std::time::Instant::now();
    let images = underlight::accuracy::cached_reference(
        &scene,
        args.time,
        &extents,
        &args.reference.settings(),
        &args.reference.cache_dir(),
    )?;
    println!("reference for {:?} at t = {} s in {:.1} s", scene.name, args.time, started.elapsed().as_secs_f64());
    // PNGs at the compose pass's exposure, as irradiance or radiance would show on a white
    // Lambertian receiver (E/π) or directly (godrays).
    let exposure = effect_png_exposure(&scene);
    for (name, image, scale) in
        [("caustics", &images.caustics, 1.0 / std::f32::consts::PI), ("godrays", &images.godrays, 1.0)]
    {
        let Some(image) = image else { continue };
        let pfm = args.out.join(format!("{name}.pfm"));
        image_io::write_pfm(&pfm, image)?;
        let png = args.out.join(format!("{name}.png"));
        image_io::write_png(&png, image.width, image.height, &image_io::tonemap_srgb8(image, exposure * scale))?;
        println!("wrote {} and {}", pfm.display(), png.display());
    }
    if args.convergence {
        let mut doubled = args.reference.settings();
        doubled.caustic_photons *= 2;
        doubled.godray_beams *= 2;
        doubled.seed = doubled.seed.wrapping_add(1);
        let more =
            underlight::accuracy::cached_reference(&scene, args.time, &extents, &doubled, &args.reference.cache_dir())?;
        for (name, a, b) in
            [("caustics", &images.caustics, &more.caustics), ("godrays", &images.godrays, &more.godrays)]
        {
            if let (Some(a), Some(b)) = (a, b) {
                let e = underlight::metrics::buffer_error(a, b)?;
                println!(
                    "{name}: {} → {} samples changes the buffer by relative RMSE {:.4}, mean relative {:.4}, flux {:+.4}",
                    if name == "caustics" { args.reference.photons } else { args.reference.beams },
                    if name == "caustics" { doubled.caustic_photons } else { doubled.godray_beams },
                    e.relative_rmse,
                    e.mean_relative_error,
                    e.flux_error
                );
            }
        }
    }
    Ok(0)
}

fn sweep(cli: &Cli, args: &SweepArgs) -> Result<i32> {
    use underlight::accuracy;
    if cli.validation {
        bail!("sweep measures GPU time with validation off: drop --validation");
    }
    let scene = underlight::scene::load(&args.scene)?;
    let filter: Vec<bool> = args.filter.iter().map(|f| *f == OnOff::On).collect();
    let axes = accuracy::SweepAxes {
        grid: args.grid.clone(),
        subdivision: args.subdiv.clone(),
        iterations: args.iterations.clone(),
        target_scale: args.target.clone(),
        point_size: args.point_size.clone(),
        line_width: args.line_width.clone(),
        filter,
        estimator: args.estimator.clone(),
    };
    axes.validate()?;
    std::fs::create_dir_all(&args.out).with_context(|| format!("creating {}", args.out.display()))?;
    let ctx = Context::new(&context_desc(cli))?;
    println!("device: {}", ctx.device.info.describe());
    let spec = accuracy::SweepSpec {
        scene: &scene,
        output: [args.width, args.height],
        axes,
        time: args.time,
        step: args.step,
        frames: args.frames,
        warmup: args.warmup,
        reference: args.reference.settings(),
        cache_dir: args.reference.cache_dir(),
    };
    let rows = accuracy::run_sweep(&ctx.device, &spec)?;
    let table = accuracy::table(&rows);
    println!("\n{table}");
    let write = |name: &str, text: &str| -> Result<()> {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
        Ok(())
    };
    write("sweep.csv", &accuracy::csv(&rows))?;
    write("sweep.md", &format!("device: {}\n\n{table}", ctx.device.info.describe()))?;
    write("sweep.json", &serde_json::to_string_pretty(&rows)?)?;
    let png = args.out.join("sweep.png");
    let title = format!("{}: error vs GPU time ({})", scene.name, ctx.device.info.name);
    accuracy::plot(&rows, &title, &png)?;
    println!("wrote {}", png.display());
    Ok(finish(ctx))
}

fn bench(cli: &Cli, args: &BenchArgs) -> Result<i32> {
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
            report.results.extend(bench::compare_paths(&ctx.device, &scene, c, args.frames, args.warmup)?);
        } else {
            report.results.push(bench::run_config(
                &ctx.device,
                &scene,
                c,
                args.frames,
                args.warmup,
                PhotonPath::GeometryShader,
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

fn view(cli: &Cli, args: &ViewArgs) -> Result<i32> {
    use underlight::viewer::{self, script, ViewerOptions};
    use underlight::vk::swapchain::PresentMode;
    let scene = underlight::scene::load(&args.scene)?;
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

fn grid_splat(cli: &Cli, args: &RenderArgs) -> Result<i32> {
    prepare_outputs(std::iter::once(&args.out).chain(args.pfm.as_ref()))?;
    let ctx = Context::new(&context_desc(cli))?;
    let settings = GridSplatSettings {
        grid: args.grid,
        subdivision: args.subdivision,
        point_size: args.point_size,
        energy: args.energy,
        wave_amplitude: args.wave_amplitude,
    };
    let extent = vk::Extent2D { width: args.width, height: args.height };
    println!("device: {}", ctx.device.info.describe());
    println!(
        "grid splat: {}² cells × {}² photons = {} photons, {}×{} RGBA16F target, {} frames",
        settings.grid,
        settings.subdivision,
        settings.photon_count(),
        args.width,
        args.height,
        args.frames
    );
    let (image, frame_timings) =
        headless::render_grid_splat(&ctx.device, extent, settings, args.frames, args.time, 1.0 / 60.0)?;
    let rgba = image_io::tonemap_srgb8(&image, args.exposure);
    image_io::write_png(&args.out, image.width, image.height, &rgba)?;
    println!("wrote {}", args.out.display());
    if let Some(pfm) = &args.pfm {
        image_io::write_pfm(pfm, &image)?;
        println!("wrote {}", pfm.display());
    }
    println!("\nmedian over {} frames:\n{}", frame_timings.len(), headless::median_timings(&frame_timings));
    Ok(finish(ctx))
}
