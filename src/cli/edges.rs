//! `underlight edges`: how much the low-resolution effect buffers cost at object edges. The
//! scene is rendered as it is set, and again with its caustic and godray targets at the
//! output's resolution; the composed images are compared near the strongest edges and overall
//! (`metrics::edge_error`, docs/accuracy.md).

use super::{context_desc, output_side, prepare_output_dir, Cli};
use anyhow::Result;
use std::path::PathBuf;
use underlight::headless::SceneRenderer;
use underlight::vk::{vk, Context};
use underlight::{image_io, metrics};

#[derive(clap::Args)]
pub(super) struct EdgesArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// Output size; defaults to the scene's.
    #[arg(long, value_parser = output_side)]
    width: Option<u32>,
    #[arg(long, value_parser = output_side)]
    height: Option<u32>,
    /// Animation time, seconds.
    #[arg(long, default_value_t = 1.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    /// Scale the full-resolution frame's photon grids up by the targets' ratio per axis
    /// (godrays ×1/godray_target_scale, caustics ×1/caustic_target_scale), so its effect
    /// buffers are no noisier per pixel than the scene's.
    #[arg(long)]
    scale_grids: bool,
    /// Also write both composed images here (`<scene>_as_set.png`, `<scene>_full_res.png`).
    #[arg(long, value_name = "DIR")]
    out_dir: Option<PathBuf>,
}

pub(super) fn run(cli: &Cli, args: &EdgesArgs) -> Result<i32> {
    let scene = underlight::scene::load(&args.scene)?;
    let mut full = scene.clone();
    full.effects.caustic_target_scale = 1.0;
    full.effects.godray_target_scale = 1.0;
    if args.scale_grids {
        let e = &scene.effects;
        full.effects.godray_grid = (e.godray_grid as f32 / e.godray_target_scale).round() as u32;
        full.effects.caustic_grid = (e.caustic_grid as f32 / e.caustic_target_scale).round() as u32;
    }
    let extent =
        vk::Extent2D { width: args.width.unwrap_or(scene.output[0]), height: args.height.unwrap_or(scene.output[1]) };
    if let Some(dir) = &args.out_dir {
        prepare_output_dir(dir)?;
    }
    let ctx = Context::new(&context_desc(cli))?;
    println!("device: {}", ctx.device.info.describe());
    let exposure = underlight::frame::uniforms::tonemap_exposure(&scene);
    let mut radiance = Vec::new();
    for (label, s) in [("as_set", &scene), ("full_res", &full)] {
        let mut renderer = SceneRenderer::new(&ctx.device, s, extent)?;
        let (_, images) = renderer.render(2, args.time, 1.0 / 60.0, true)?;
        let images = images.expect("read back requested");
        if let Some(dir) = &args.out_dir {
            let path = dir.join(format!("{}_{label}.png", scene.name));
            image_io::write_png(&path, images.width, images.height, &images.output)?;
            println!("wrote {}", path.display());
        }
        radiance.push(metrics::output_radiance(&images.output, exposure));
    }
    let e = metrics::edge_error(&radiance[0], &radiance[1], extent.width as usize, extent.height as usize)?;
    println!(
        "scene {:?} {}×{}, effect targets ×{} (caustics) ×{} (godrays) against ×1:",
        scene.name, extent.width, extent.height, scene.effects.caustic_target_scale, scene.effects.godray_target_scale
    );
    println!(
        "  relative RMSE within {} px of the strongest edges ({} px): {:.3}; whole image: {:.3}",
        metrics::EDGE_BAND,
        e.edge_pixels,
        e.near_edges,
        e.whole
    );
    Ok(0)
}
