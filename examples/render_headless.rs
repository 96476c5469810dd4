//! underlight used as a library: load a built-in scene (or a scene file), render it headless
//! on any Vulkan device, and take the HDR buffers and the per-pass GPU times.
//!
//! ```sh
//! cargo run --release --example render_headless -- tank out/example
//! ```

use std::path::{Path, PathBuf};
use underlight::headless::SceneRenderer;
use underlight::vk::{vk, Context, ContextDesc};

fn main() -> anyhow::Result<()> {
    let mut args = std::env::args().skip(1);
    let scene_name = args.next().unwrap_or_else(|| "tank".into());
    let out = PathBuf::from(args.next().unwrap_or_else(|| "out/example".into()));
    // UNDERLIGHT_DEVICE and UNDERLIGHT_VALIDATION are read from the environment.
    render(&scene_name, &out, ContextDesc::from_env(), [320, 200])
}

fn render(scene_name: &str, out: &Path, device: ContextDesc, size: [u32; 2]) -> anyhow::Result<()> {
    // A scene: a built-in name or a path to a .toml file (docs/scenes.md).
    let mut scene = underlight::scene::load(scene_name)?;
    scene.output = size;

    let ctx = Context::new(&device)?;
    println!("device: {}", ctx.device.info.describe());

    let (timings, images) = {
        let extent = vk::Extent2D { width: scene.output[0], height: scene.output[1] };
        let mut renderer = SceneRenderer::new(&ctx.device, &scene, extent)?;
        // Three frames from t = 1 s at 60 Hz; the last one is read back.
        renderer.render(3, 1.0, 1.0 / 60.0, true)?
    };
    let images = images.expect("read back requested");

    // Per-pass GPU milliseconds of each frame, from Vulkan timestamps.
    println!("{}", underlight::headless::median_timings(&timings));

    // The HDR buffers in physical units (docs/units.md) and the tonemapped output.
    std::fs::create_dir_all(out)?;
    underlight::image_io::write_exr(&out.join("scene_color.exr"), &images.scene_color)?;
    if let Some(caustics) = &images.caustics {
        let sum = caustics.channel_sums()[0];
        println!("caustic irradiance: {}×{}, Σ red {sum:.4e} W/m²", caustics.width, caustics.height);
        underlight::image_io::write_exr(&out.join("caustics.exr"), caustics)?;
    }
    if let Some(godrays) = &images.godrays {
        underlight::image_io::write_exr(&out.join("godrays.exr"), godrays)?;
    }
    underlight::image_io::write_png(&out.join("output.png"), images.width, images.height, &images.output)?;
    println!("wrote {}", out.display());

    // Every Vulkan object made from the device is gone: the shutdown reports what the
    // validation layer and the allocator found.
    let report = ctx.shutdown();
    anyhow::ensure!(report.is_clean(), "Vulkan teardown is not clean:\n{report}");
    Ok(())
}

/// The suite runs the example (`test = true` in Cargo.toml), small and with validation on.
#[cfg(test)]
mod tests {
    #[test]
    fn the_example_renders_the_tank_cleanly() {
        let out = std::env::temp_dir().join(format!("underlight-example-{}", std::process::id()));
        let mut device = super::ContextDesc::from_env();
        device.validation = true;
        super::render("tank", &out, device, [64, 40]).unwrap();
        for file in ["scene_color.exr", "caustics.exr", "godrays.exr", "output.png"] {
            assert!(out.join(file).is_file(), "the example did not write {file}");
        }
        let caustics = underlight::image_io::read_exr(&out.join("caustics.exr")).unwrap();
        assert!(caustics.channel_sums()[0] > 0.0, "the example's caustics are black");
        std::fs::remove_dir_all(&out).ok();
    }
}
