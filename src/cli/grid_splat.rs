//! `underlight grid-splat`: the foundation's demo, a geometry-shader photon grid splatted into
//! a float target.

use super::{context_desc, finish, output_side, prepare_outputs, Cli};
use anyhow::Result;
use std::path::PathBuf;
use underlight::grid_splat::GridSplatSettings;
use underlight::headless;
use underlight::image_io;
use underlight::vk::{vk, Context};

#[derive(clap::Args)]
pub(super) struct RenderArgs {
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
    #[arg(long, default_value_t = 16, value_parser = super::frame_count)]
    frames: u32,
    /// Animation time of the first frame, seconds.
    #[arg(long, default_value_t = 0.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    /// Tonemap exposure.
    #[arg(long, default_value_t = 1.0, value_parser = super::exposure)]
    exposure: f32,
}

pub(super) fn run(cli: &Cli, args: &RenderArgs) -> Result<i32> {
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
        underlight::grid_splat::render_grid_splat(&ctx.device, extent, settings, args.frames, args.time, 1.0 / 60.0)?;
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
