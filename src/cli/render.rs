//! `underlight render`: a scene rendered headless to a PNG (and HDR dumps), with per-pass GPU
//! times and, on request, the photons' flux budget.

use super::{context_desc, effect_png_exposure, finish, output_side, prepare_outputs, Cli};
use anyhow::{bail, Result};
use std::path::PathBuf;
use underlight::headless;
use underlight::image_io;
use underlight::vk::{vk, Context};

#[derive(clap::Args)]
pub(super) struct SceneArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Output PNG (tonemapped sRGB).
    #[arg(long, default_value = "out/underlight.png")]
    out: PathBuf,
    /// Also write the HDR targets (scene colour, caustic irradiance, …) into this folder, as PFM
    /// and OpenEXR (`--hdr-format`).
    #[arg(long, value_name = "DIR")]
    hdr: Option<PathBuf>,
    /// The HDR files' format: PFM, OpenEXR (float32 RGB), or both side by side.
    #[arg(long, value_enum, default_value_t = HdrFormat::Both, requires = "hdr")]
    hdr_format: HdrFormat,
    /// Output size; defaults to the scene's.
    #[arg(long, value_parser = output_side)]
    width: Option<u32>,
    #[arg(long, value_parser = output_side)]
    height: Option<u32>,
    /// Frames to render (timings are the median over them).
    #[arg(long, default_value_t = 8, value_parser = super::frame_count)]
    frames: u32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 1.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    /// Print which passes the scene needs and why, then render.
    #[arg(long)]
    explain: bool,
    /// Also render one frame recording every caustic photon (the paper's points, the same
    /// photons) and every godray beam, and print where their flux goes: landed (drawn),
    /// reflected, dropped by reason; for the landed photons, what the camera sees of them
    /// and how far each lies from the exact hit along its refracted ray (the scene's
    /// triangles); for the beams, the share of their length in view.
    #[arg(long)]
    flux_budget: bool,
    /// Also print each pass's work per shader stage in the last frame (pipeline-statistics
    /// queries): vertex and geometry-shader invocations, the primitives the geometry shaders
    /// emitted and that reached the rasteriser, fragments shaded, compute invocations.
    #[arg(long)]
    pipeline_statistics: bool,
    /// Put the camera here instead of the scene's position, e.g. `0.3,1.5,0.2` (above the
    /// water the surface reflects and refracts).
    #[arg(long, value_name = "X,Y,Z", value_delimiter = ',', allow_hyphen_values = true)]
    camera: Option<Vec<f32>>,
    /// Point the camera at this point instead of the scene's look_at.
    #[arg(long, value_name = "X,Y,Z", value_delimiter = ',', allow_hyphen_values = true)]
    look_at: Option<Vec<f32>>,
    #[command(flatten)]
    effects: super::effect_overrides::EffectOverrides,
}

/// `--hdr-format`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum HdrFormat {
    Pfm,
    Exr,
    Both,
}

pub(super) fn run(cli: &Cli, args: &SceneArgs) -> Result<i32> {
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
    args.effects.apply(&mut scene);
    if scene.camera.position.distance(scene.camera.look_at) < 1e-6 {
        bail!("--camera and --look-at give the same point: the camera needs a direction to look in");
    }
    super::effect_overrides::check(&scene)?;
    let width = args.width.unwrap_or(scene.output[0]);
    let height = args.height.unwrap_or(scene.output[1]);
    prepare_outputs([&args.out])?;
    if let Some(dir) = &args.hdr {
        super::prepare_output_dir(dir)?;
    }
    let plan = underlight::frame::FramePlan::for_scene(&scene);
    if args.explain {
        println!("passes for scene {:?}:\n{plan}", scene.name);
    }
    let ctx = Context::new(&context_desc(cli))?;
    println!("device: {}", ctx.device.info.describe());
    if args.pipeline_statistics {
        super::require_pipeline_statistics(&ctx)?;
    }
    let extent = vk::Extent2D { width, height };
    let (timings, images) = {
        let options =
            underlight::frame::FrameOptions { pipeline_statistics: args.pipeline_statistics, ..Default::default() };
        let mut renderer = headless::SceneRenderer::with_options(&ctx.device, &scene, extent, options)?;
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
        let rendered = renderer.render(args.frames, args.time, 1.0 / 60.0, true)?;
        if renderer.frame.photon_surveys > 0 {
            println!(
                "photon survey (CPU, where the view wants the photons): {:.1} ms",
                renderer.frame.photon_survey_time.as_secs_f64() * 1e3
            );
        }
        if let Some(warp) = renderer.frame.caustic_photon_warp() {
            let order = if warp.exchanged { "u and v exchanged" } else { "rows first" };
            println!("caustic photons spread for the view: coarse grid aspect {:.2}, {order}", warp.grid_aspect);
        }
        rendered
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
            if args.hdr_format != HdrFormat::Exr {
                let path = dir.join(format!("{name}.pfm"));
                image_io::write_pfm(&path, img)?;
                println!("wrote {}", path.display());
            }
            if args.hdr_format != HdrFormat::Pfm {
                let path = dir.join(format!("{name}.exr"));
                image_io::write_exr(&path, img)?;
                println!("wrote {}", path.display());
            }
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
    if let Some(last) = timings.last().filter(|t| !t.counts.is_empty()) {
        let rows = last.counted().map(|(id, c)| (id.name(), c));
        println!(
            "\nwork per pass, last frame (pipeline statistics):\n{}",
            underlight::vk::statistics::counts_table(rows)
        );
    }
    if args.flux_budget {
        print_flux_budget(&ctx, &scene, extent, args.time)?;
    }
    Ok(finish(ctx))
}

/// `render --flux-budget`: one frame through the photon-recording geometry shaders: the
/// caustic photons (through the paper's points' recording variant, on the grid of the scene's
/// estimator) and the godray beams.
fn print_flux_budget(ctx: &Context, scene: &underlight::scene::Scene, extent: vk::Extent2D, time: f32) -> Result<()> {
    use underlight::flux_budget::{grid_power, FluxBudget};
    let e = &scene.effects;
    let beams = e.godrays && e.godray_method.casts_beams();
    if !(e.caustics || beams) || !ctx.device.has_pipeline_stores() {
        bail!("--flux-budget needs caustics or godray beams, and a device with vertexPipelineStoresAndAtomics");
    }
    let options = underlight::frame::FrameOptions { record_photons: true, ..Default::default() };
    let mut renderer = headless::SceneRenderer::with_options(&ctx.device, scene, extent, options)?;
    let extents = renderer.frame.extents;
    let (_, images) = renderer.render(1, time, 0.0, true)?;
    drop(renderer);
    let images = images.expect("read back requested");
    let u = underlight::frame::uniforms::FrameUniforms::new(scene, scene.bounds(), &extents, time);
    println!("\nflux budget at t = {time} s:");
    let mut printed = false;
    if let Some(records) = &images.photon_records {
        let mut budget = FluxBudget::from_records(records);
        budget.light_power = grid_power(&u);
        let view_proj = glam::Mat4::from_cols_array_2d(&u.camera_view_proj);
        let camera = glam::Vec3::from(u.camera_position);
        let bvh = underlight::bvh::Bvh::of_scene(scene);
        budget.seen_by(records, view_proj, camera, &bvh);
        budget.placed_by(records, &bvh);
        println!("{budget}");
        if e.caustic_estimator == underlight::scene::CausticEstimator::Footprint {
            println!(
                "footprint points clamped to the device's largest point ({} px): {} of {} landed",
                u.device_max_point_size, budget.footprint_clamped.photons, budget.landed.photons
            );
        }
        printed = true;
    }
    if let Some(records) = &images.beam_records {
        let mut budget = FluxBudget::from_beam_records(records, glam::Mat4::from_cols_array_2d(&u.camera_view_proj));
        budget.light_power = grid_power(&u);
        println!("{budget}");
        printed = true;
    }
    if !printed {
        bail!("--flux-budget: neither photon pass ran, so no photon was recorded");
    }
    Ok(())
}
