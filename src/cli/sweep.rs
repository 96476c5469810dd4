//! `underlight sweep`: every combination of the given settings, timed and compared with the
//! reference.

use super::reference::ReferenceOptions;
use super::{caustic_estimator, context_desc, finish, godray_method, output_side, photon_spread, Cli, OnOff};
use anyhow::{bail, Context as _, Result};
use std::path::PathBuf;
use underlight::vk::Context;

#[derive(clap::Args)]
pub(super) struct SweepArgs {
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
    /// Godray target scale relative to the output.
    #[arg(long, value_delimiter = ',')]
    godray_target: Vec<f32>,
    /// Largest caustic point size, px (the smallest is lowered to it where larger).
    #[arg(long, value_delimiter = ',')]
    point_size: Vec<f32>,
    /// Godray line width, px.
    #[arg(long, value_delimiter = ',')]
    line_width: Vec<f32>,
    /// Filter on, off, or both.
    #[arg(long, value_delimiter = ',', value_enum, default_values_t = [OnOff::Off, OnOff::On])]
    filter: Vec<OnOff>,
    /// Caustic estimators: paper, footprint, triangles (comma-separated).
    #[arg(long, value_delimiter = ',', value_parser = caustic_estimator)]
    estimator: Vec<underlight::scene::CausticEstimator>,
    /// Caustic photon densities: even, view (comma-separated).
    #[arg(long, value_delimiter = ',', value_parser = photon_spread)]
    photon_density: Vec<underlight::scene::PhotonSpread>,
    /// Godray beam densities: even, view (comma-separated).
    #[arg(long, value_delimiter = ',', value_parser = photon_spread)]
    godray_photon_density: Vec<underlight::scene::PhotonSpread>,
    /// Godray methods: beams, footprint, marched (comma-separated; marched needs a directional
    /// light).
    #[arg(long, value_delimiter = ',', value_parser = godray_method)]
    godray_method: Vec<underlight::scene::GodrayMethod>,
    /// The triangles' refinement at receivers' borders (effects.caustic_refinement): on, off,
    /// or both.
    #[arg(long, value_delimiter = ',', value_enum)]
    refinement: Vec<OnOff>,
    /// Timed frames per setting (median) and warm-up frames.
    #[arg(long, default_value_t = 5, value_parser = super::frame_count)]
    frames: u32,
    #[arg(long, default_value_t = 2, value_parser = super::warmup_count)]
    warmup: u32,
    /// Animation time, seconds, and the step to the next frame for the flicker figure.
    #[arg(long, default_value_t = 1.0, value_parser = super::seconds, allow_hyphen_values = true)]
    time: f32,
    #[arg(long, default_value_t = 1.0 / 30.0, value_parser = super::seconds, allow_hyphen_values = true)]
    step: f32,
    /// Folder for sweep.csv, sweep.md, sweep.json and sweep.png.
    #[arg(long, default_value = "out/sweep")]
    out: PathBuf,
    #[command(flatten)]
    reference: ReferenceOptions,
}

pub(super) fn run(cli: &Cli, args: &SweepArgs) -> Result<i32> {
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
        godray_target_scale: args.godray_target.clone(),
        point_size: args.point_size.clone(),
        line_width: args.line_width.clone(),
        filter,
        estimator: args.estimator.clone(),
        photon_density: args.photon_density.clone(),
        godray_photon_density: args.godray_photon_density.clone(),
        godray_method: args.godray_method.clone(),
        refinement: args.refinement.iter().map(|r| *r == OnOff::On).collect(),
    };
    axes.validate()?;
    axes.validate_for(&scene)?;
    super::prepare_output_dir(&args.out)?;
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

#[cfg(test)]
mod tests {
    use super::super::{Cli, Command};
    use clap::Parser as _;
    use underlight::scene::GodrayMethod;

    fn sweep(args: &[&str]) -> Result<super::SweepArgs, clap::Error> {
        let cli = Cli::try_parse_from(["underlight", "sweep"].iter().chain(args))?;
        match cli.command {
            Command::Sweep(args) => Ok(*args),
            _ => unreachable!("parsed as another subcommand"),
        }
    }

    #[test]
    fn godray_methods_are_a_comma_separated_axis_empty_by_default() {
        let all = sweep(&["--godray-method", "beams,footprint,marched"]).unwrap();
        assert_eq!(all.godray_method, [GodrayMethod::Beams, GodrayMethod::Footprint, GodrayMethod::Marched]);
        assert_eq!(sweep(&["--godray-method=marched"]).unwrap().godray_method, [GodrayMethod::Marched]);
        assert!(sweep(&[]).unwrap().godray_method.is_empty());
        let wrong = sweep(&["--godray-method", "beams,rays"]).err().expect("accepted rays").to_string();
        assert!(
            wrong.contains("--godray-method")
                && wrong.contains("no godray method \"rays\"; there are beams, footprint, marched"),
            "{wrong}"
        );
    }

    #[test]
    fn godray_targets_are_a_comma_separated_axis() {
        assert_eq!(sweep(&["--godray-target", "0.16,0.64,1"]).unwrap().godray_target, [0.16, 0.64, 1.0]);
        assert!(sweep(&[]).unwrap().godray_target.is_empty());
    }
}
