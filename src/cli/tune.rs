//! `underlight tune`: the user states the trade (an error bound, or a GPU-time budget) and
//! gets the `[effects]` settings that meet it on this device, from a sweep over the
//! estimators and photon grids against the cached reference.

use super::reference::ReferenceOptions;
use super::{context_desc, finish, output_side, Cli};
use anyhow::{bail, Context as _, Result};
use std::path::PathBuf;
use underlight::accuracy::{self, SweepAxes, TuneGoal};
use underlight::scene::{CausticEstimator, PhotonSpread};
use underlight::vk::Context;

#[derive(clap::Args)]
pub(super) struct TuneArgs {
    /// A built-in scene (tank, port, storage) or a path to a scene .toml file.
    #[arg(long, default_value = "tank")]
    scene: String,
    /// The largest relative RMSE of the caustic and the godray buffer: the cheapest setting
    /// that meets it is picked.
    #[arg(long, value_name = "E", required_unless_present = "budget_ms", conflicts_with = "budget_ms")]
    max_error: Option<f64>,
    /// Instead: the most accurate setting whose effect passes take at most this many GPU ms.
    #[arg(long, value_name = "T")]
    budget_ms: Option<f64>,
    /// A small set of settings (3) and frames, for a first answer in about two minutes on lavapipe.
    #[arg(long)]
    quick: bool,
    /// The size every setting renders and is compared at.
    #[arg(long, value_parser = output_side, default_value_t = 320)]
    width: u32,
    #[arg(long, value_parser = output_side, default_value_t = 200)]
    height: u32,
    /// Also write the scene file with the picked settings here: the scene's own file with its
    /// [effects] keys that the printed block sets replaced, and its OBJ paths made absolute.
    #[arg(long, value_name = "FILE")]
    write: Option<PathBuf>,
    /// Folder for the table and the plot of the settings it chose from.
    #[arg(long, default_value = "out/tune")]
    out: PathBuf,
    #[command(flatten)]
    reference: ReferenceOptions,
}

pub(super) fn run(cli: &Cli, args: &TuneArgs) -> Result<i32> {
    if cli.validation {
        bail!("tune measures GPU time with validation off: drop --validation");
    }
    let goal = match (args.max_error, args.budget_ms) {
        (Some(e), _) if !(e > 0.0 && e.is_finite()) => bail!("--max-error {e}: must be a positive number"),
        (_, Some(t)) if !(t > 0.0 && t.is_finite()) => bail!("--budget-ms {t}: must be a positive number"),
        (Some(e), _) => TuneGoal::MaxError(e),
        (None, Some(t)) => TuneGoal::BudgetMs(t),
        (None, None) => bail!("give --max-error E or --budget-ms T"),
    };
    let scene = underlight::scene::load(&args.scene)?;
    // The candidates: the triangle estimator over photon meshes from coarse to fine, their
    // photons spread as the view needs them, and the paper's filtered points on its even
    // grid, each at its own best subdivision (docs/accuracy.md).
    let (triangle_grids, paper_grids, frames, warmup) =
        if args.quick { (vec![48, 100], vec![100], 2, 1) } else { (vec![48, 100, 150, 200], vec![100, 200], 5, 2) };
    let candidates = [
        SweepAxes {
            grid: triangle_grids,
            subdivision: vec![3],
            filter: vec![true],
            estimator: vec![CausticEstimator::Triangles],
            photon_density: vec![PhotonSpread::View],
            ..Default::default()
        },
        SweepAxes {
            grid: paper_grids,
            subdivision: vec![2],
            filter: vec![true],
            estimator: vec![CausticEstimator::Paper],
            photon_density: vec![PhotonSpread::Even],
            ..Default::default()
        },
    ];
    // The scene file it writes at the end, checked before the minutes of measuring.
    super::prepare_outputs(args.write.iter())?;
    super::prepare_output_dir(&args.out)?;
    let ctx = Context::new(&context_desc(cli))?;
    println!("device: {}", ctx.device.info.describe());
    let mut rows = Vec::new();
    for axes in candidates {
        let spec = accuracy::SweepSpec {
            scene: &scene,
            output: [args.width, args.height],
            axes,
            time: 1.0,
            step: 1.0 / 30.0,
            frames,
            warmup,
            reference: args.reference.settings(),
            cache_dir: args.reference.cache_dir(),
        };
        rows.extend(accuracy::run_sweep(&ctx.device, &spec)?);
    }
    accuracy::mark_pareto(&mut rows);
    let table = accuracy::table(&rows);
    println!("\nthe settings measured (error = the worse of the caustic and godray relative RMSE):\n{table}");
    let md = args.out.join("tune.md");
    std::fs::write(&md, format!("device: {}\n\n{table}", ctx.device.info.describe()))
        .with_context(|| format!("writing {}", md.display()))?;
    let png = args.out.join("tune.png");
    accuracy::plot(&rows, &format!("{}: error vs GPU time ({})", scene.name, ctx.device.info.name), &png)?;
    println!("wrote {} and {}", md.display(), png.display());
    match accuracy::pick(&rows, goal) {
        Ok(row) => {
            println!(
                "\npicked: {} estimator, {}² × {}² photons, {} godrays: error {:.3} (caustics {:.3}, godrays {:.3}) in {:.1} ms of effect passes",
                row.estimator,
                row.caustic_grid,
                row.caustic_subdivision,
                row.godray_method,
                accuracy::tune_error(row),
                row.caustics.map_or(0.0, |e| e.relative_rmse),
                row.godrays.map_or(0.0, |e| e.relative_rmse),
                row.effect_ms
            );
            println!("for the scene file:\n\n{}", accuracy::effects_block(row));
            if let Some(path) = &args.write {
                write_scene(&args.scene, row, path)?;
                println!("wrote {}", path.display());
            }
            Ok(finish(ctx))
        }
        Err(miss) => {
            eprintln!("error: {miss}");
            let _ = finish(ctx);
            Ok(1)
        }
    }
}

/// Writes the scene file `scene` (a built-in name or a path) with the picked setting: its own
/// text, every other key and comment kept, the tuned `[effects]` keys set, and each object's
/// `obj` made absolute so the file loads from wherever it is written. Loaded back to check.
fn write_scene(scene: &str, row: &underlight::accuracy::SweepRow, path: &std::path::Path) -> Result<()> {
    let source = underlight::scene::file::scene_path(scene);
    let text = std::fs::read_to_string(&source).with_context(|| format!("reading {}", source.display()))?;
    let mut doc: toml_edit::DocumentMut = text.parse().with_context(|| format!("parsing {}", source.display()))?;
    let base = source.parent().unwrap_or(std::path::Path::new(".")).canonicalize()?;
    if let Some(objects) = doc.get_mut("objects").and_then(|o| o.as_array_of_tables_mut()) {
        for object in objects.iter_mut() {
            if let Some(obj) = object.get("obj").and_then(|v| v.as_str()) {
                let absolute = base.join(obj);
                object["obj"] = toml_edit::value(absolute.to_string_lossy().into_owned());
            }
        }
    }
    if !doc.contains_table("effects") {
        doc["effects"] = toml_edit::table();
    }
    let effects = &mut doc["effects"];
    effects["caustic_estimator"] = toml_edit::value(row.estimator.clone());
    effects["caustic_grid"] = toml_edit::value(i64::from(row.caustic_grid));
    effects["caustic_subdivision"] = toml_edit::value(i64::from(row.caustic_subdivision));
    effects["caustic_photon_density"] = toml_edit::value(row.photon_density.clone());
    effects["godray_photon_density"] = toml_edit::value(row.godray_photon_density.clone());
    effects["godray_method"] = toml_edit::value(row.godray_method.clone());
    effects["iterations"] = toml_edit::value(i64::from(row.iterations));
    effects["filter"] = toml_edit::value(row.filter);
    // As written in the block (0.64, not the f32's 0.6399999856948853 widened).
    let target_scale: f64 = format!("{:?}", row.caustic_target_scale).parse()?;
    effects["caustic_target_scale"] = toml_edit::value(target_scale);
    let header = format!(
        "# Written by `underlight tune` from {}: its [effects] set to the setting it picked\n# ({} estimator, {}² × {}² photons). The lines below are the source's.\n",
        source.display(),
        row.estimator,
        row.caustic_grid,
        row.caustic_subdivision
    );
    std::fs::write(path, header + &doc.to_string()).with_context(|| format!("writing {}", path.display()))?;
    underlight::scene::load(&path.to_string_lossy())
        .with_context(|| format!("the scene written to {} does not load", path.display()))?;
    Ok(())
}
