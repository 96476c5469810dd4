//! `underlight reference`: the CPU reference of a scene's effect buffers, and the
//! reference's own settings (which `sweep` shares).

use super::{effect_png_exposure, output_side};
use anyhow::Result;
use std::path::PathBuf;
use underlight::image_io;

/// The reference's own settings (shared by `reference` and `sweep`).
#[derive(clap::Args)]
pub(super) struct ReferenceOptions {
    /// Caustic photons the reference traces over the whole water surface.
    // 32M: at 8M the port's 320×200 reference had an own error of 0.22 (from its halves)
    // against the GPU's 0.44, and the figure read 0.49 (docs/accuracy.md).
    #[arg(long, default_value_t = 32_000_000)]
    photons: u64,
    /// Godray beams the reference traces.
    #[arg(long, default_value_t = 1_000_000)]
    beams: u64,
    /// Worker threads (0: all cores), at most 256.
    #[arg(long, default_value_t = 0, value_parser = thread_count)]
    threads: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where reference buffers are cached (default: ~/.cache/underlight/reference).
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

/// `--threads`: 0 (one per core) up to the reference's own limit, refused here before a
/// scene is loaded rather than after.
fn thread_count(text: &str) -> std::result::Result<usize, String> {
    super::whole_number_in(text, "threads", 0..=underlight::reference::MAX_THREADS)
        .map_err(|e| format!("{e}; 0 is one per core"))
}

impl ReferenceOptions {
    pub(super) fn settings(&self) -> underlight::reference::ReferenceSettings {
        underlight::reference::ReferenceSettings {
            caustic_photons: self.photons,
            godray_beams: self.beams,
            threads: self.threads,
            seed: self.seed,
        }
    }

    pub(super) fn cache_dir(&self) -> PathBuf {
        self.cache.clone().unwrap_or_else(underlight::accuracy::default_cache_dir)
    }
}

#[derive(clap::Args)]
pub(super) struct ReferenceArgs {
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
    #[arg(long, default_value_t = 1.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    /// Also trace twice the photons and beams (another seed) and print how much the buffers
    /// change: the reference's own error, which must stay below the errors it measures.
    #[arg(long)]
    convergence: bool,
    #[command(flatten)]
    reference: ReferenceOptions,
}

pub(super) fn run(args: &ReferenceArgs) -> Result<i32> {
    let scene = underlight::scene::load(&args.scene)?;
    let output = [args.width.unwrap_or(scene.output[0]), args.height.unwrap_or(scene.output[1])];
    super::prepare_output_dir(&args.out)?;
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
        let exr = args.out.join(format!("{name}.exr"));
        image_io::write_exr(&exr, image)?;
        let png = args.out.join(format!("{name}.png"));
        image_io::write_png(&png, image.width, image.height, &image_io::tonemap_srgb8(image, exposure * scale))?;
        println!("wrote {}, {} and {}", pfm.display(), exr.display(), png.display());
    }
    if let (Some(all), Some(half)) = (&images.caustics, &images.caustics_half) {
        let pfm = args.out.join("caustics_half.pfm");
        image_io::write_pfm(&pfm, half)?;
        // The halves' difference has the whole buffer's noise (ReferenceImages::caustics_half).
        match underlight::metrics::buffer_error(half, all) {
            Ok(own) => println!(
                "wrote {} (half the photons); the caustic buffer's own error, from its two halves: relative RMSE {:.4}",
                pfm.display(),
                own.relative_rmse
            ),
            Err(_) => println!("wrote {} (half the photons); the caustic buffer is black", pfm.display()),
        }
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
