//! `underlight tune`: from the sweep's rows, the setting a user asked for: the cheapest whose
//! errors meet a bound, or the most accurate within a GPU-time budget.

use super::measure::SweepRow;

/// A setting's error for tuning: the worse of its caustic and godray relative RMSE (the
/// buffers the setting drew), so a bound holds for both.
pub fn tune_error(row: &SweepRow) -> f64 {
    [row.caustics, row.godrays].iter().flatten().map(|e| e.relative_rmse).fold(0.0, f64::max)
}

/// What the user asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TuneGoal {
    /// The cheapest setting (effect ms) whose error is at most this.
    MaxError(f64),
    /// The most accurate setting whose effect ms is at most this.
    BudgetMs(f64),
}

/// Why no setting was picked, with the nearest the sweep came.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TuneMiss {
    #[error("no setting reaches an error of {wanted:.3}: the best measured is {best:.3} (at {ms:.1} ms)")]
    ErrorUnreachable { wanted: f64, best: f64, ms: f64 },
    #[error("no setting fits in {budget:.1} ms: the fastest measured takes {fastest:.1} ms (error {error:.3})")]
    BudgetTooSmall { budget: f64, fastest: f64, error: f64 },
    #[error("the sweep measured no setting")]
    NoRows,
}

/// The row `goal` picks among `rows`.
pub fn pick(rows: &[SweepRow], goal: TuneGoal) -> Result<&SweepRow, TuneMiss> {
    let by = |key: fn(&SweepRow) -> f64| {
        move |a: &&SweepRow, b: &&SweepRow| key(a).total_cmp(&key(b)).then(tune_error(a).total_cmp(&tune_error(b)))
    };
    let ms = |r: &SweepRow| r.effect_ms;
    match goal {
        TuneGoal::MaxError(wanted) => {
            let best = rows.iter().min_by(by(tune_error)).ok_or(TuneMiss::NoRows)?;
            rows.iter().filter(|r| tune_error(r) <= wanted).min_by(by(ms)).ok_or(TuneMiss::ErrorUnreachable {
                wanted,
                best: tune_error(best),
                ms: best.effect_ms,
            })
        }
        TuneGoal::BudgetMs(budget) => {
            let fastest = rows.iter().min_by(by(ms)).ok_or(TuneMiss::NoRows)?;
            rows.iter().filter(|r| r.effect_ms <= budget).min_by(by(tune_error)).ok_or(TuneMiss::BudgetTooSmall {
                budget,
                fastest: fastest.effect_ms,
                error: tune_error(fastest),
            })
        }
    }
}

/// The measured setting nearest to `effects` on `scene`: the same estimator, photon density
/// and godray method, the nearest photon count (by ratio), then the same filter and iteration count.
/// None where the sweep measured no setting of that scene, estimator and godray method.
pub fn nearest_setting<'a>(rows: &'a [SweepRow], scene: &str, effects: &crate::scene::Effects) -> Option<&'a SweepRow> {
    let photons = ((effects.caustic_grid * effects.caustic_subdivision) as f64).powi(2);
    let distance = |r: &SweepRow| {
        let ratio = (r.caustic_photons.max(1) as f64 / photons.max(1.0)).ln().abs();
        (ratio, r.filter != effects.filter, r.iterations.abs_diff(effects.iterations))
    };
    rows.iter()
        .filter(|r| {
            r.scene == scene
                && r.estimator == effects.caustic_estimator.name()
                && r.photon_density == effects.caustic_photon_density.name()
                && r.godray_photon_density == effects.godray_photon_density.name()
                && r.godray_method == effects.godray_method.name()
        })
        .min_by(|a, b| distance(a).partial_cmp(&distance(b)).unwrap_or(std::cmp::Ordering::Equal))
}

/// The `[effects]` table of a scene file with the picked setting: what the sweep varied, and
/// the caustic target it was measured at (a block pasted over a scene's `[effects]` must not
/// change the target under the figures).
pub fn effects_block(row: &SweepRow) -> String {
    format!(
        "[effects]\ncaustic_estimator = \"{}\"\ncaustic_grid = {}\ncaustic_subdivision = {}\ncaustic_photon_density = \"{}\"\ngodray_method = \"{}\"\ngodray_photon_density = \"{}\"\niterations = {}\nfilter = {}\ncaustic_target_scale = {:?}\n",
        row.estimator,
        row.caustic_grid,
        row.caustic_subdivision,
        row.photon_density,
        row.godray_method,
        row.godray_photon_density,
        row.iterations,
        row.filter,
        row.caustic_target_scale
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::BufferError;

    fn row(ms: f64, caustic: f64, godray: f64) -> SweepRow {
        let e = |r| Some(BufferError { relative_rmse: r, ..Default::default() });
        SweepRow {
            scene: "tank".into(),
            caustic_grid: (ms as u32).max(1),
            caustic_subdivision: 3,
            caustic_photons: ((ms as u64).max(1) * 3).pow(2),
            iterations: 5,
            caustic_target: [1, 1],
            caustic_target_scale: 1.0,
            godray_target: [1, 1],
            godray_target_scale: 0.16,
            point_size_max: 1.0,
            line_width: 1.0,
            filter: true,
            estimator: "triangles".into(),
            photon_density: "view".into(),
            godray_photon_density: "view".into(),
            godray_method: "beams".into(),
            caustic_refinement: false,
            effect_ms: ms,
            frame_ms: ms,
            caustics: e(caustic),
            caustic_reference_own_error: None,
            caustics_at_output: e(caustic),
            caustic_holes: None,
            caustic_gaps: None,
            godrays: e(godray),
            godrays_at_output: None,
            flip: 0.0,
            caustic_change_gpu: 0.0,
            caustic_change_reference: 0.0,
            pareto: false,
        }
    }

    #[test]
    fn picks_the_cheapest_that_meets_the_bound_and_the_best_within_the_budget() {
        let rows = [row(100.0, 1.2, 0.1), row(300.0, 0.6, 0.12), row(900.0, 0.4, 0.5), row(1200.0, 0.45, 0.1)];
        // The godray error counts too: 900 ms reads 0.5 and does not meet 0.5 - ε.
        assert_eq!(pick(&rows, TuneGoal::MaxError(0.7)).unwrap().effect_ms, 300.0);
        assert_eq!(pick(&rows, TuneGoal::MaxError(0.46)).unwrap().effect_ms, 1200.0);
        assert_eq!(pick(&rows, TuneGoal::BudgetMs(1000.0)).unwrap().effect_ms, 900.0);
        assert_eq!(pick(&rows, TuneGoal::BudgetMs(299.0)).unwrap().effect_ms, 100.0);
        assert_eq!(
            pick(&rows, TuneGoal::MaxError(0.3)),
            Err(TuneMiss::ErrorUnreachable { wanted: 0.3, best: 0.45, ms: 1200.0 })
        );
        assert_eq!(
            pick(&rows, TuneGoal::BudgetMs(50.0)),
            Err(TuneMiss::BudgetTooSmall { budget: 50.0, fastest: 100.0, error: 1.2 })
        );
        assert_eq!(pick(&[], TuneGoal::MaxError(1.0)), Err(TuneMiss::NoRows));
        let mut effects = crate::scene::Effects {
            caustic_estimator: crate::scene::CausticEstimator::Triangles,
            caustic_photon_density: crate::scene::PhotonSpread::View,
            godray_photon_density: crate::scene::PhotonSpread::View,
            caustic_grid: 310,
            caustic_subdivision: 3,
            ..Default::default()
        };
        assert_eq!(nearest_setting(&rows, "tank", &effects).unwrap().caustic_grid, 300);
        effects.caustic_photon_density = crate::scene::PhotonSpread::Even;
        assert!(nearest_setting(&rows, "tank", &effects).is_none(), "another photon density's rows");
        effects.caustic_photon_density = crate::scene::PhotonSpread::View;
        assert!(nearest_setting(&rows, "port", &effects).is_none(), "another scene's sweep");
        effects.caustic_estimator = crate::scene::CausticEstimator::Paper;
        assert!(nearest_setting(&rows, "tank", &effects).is_none(), "another estimator's rows");
        effects.caustic_estimator = crate::scene::CausticEstimator::Triangles;
        effects.godray_method = crate::scene::GodrayMethod::Marched;
        assert!(nearest_setting(&rows, "tank", &effects).is_none(), "another godray method's rows");
        let block = effects_block(&rows[1]);
        assert!(block.starts_with("[effects]\n") && block.contains("caustic_grid = 300"), "{block}");
        assert!(block.contains("godray_method = \"beams\"\n"), "{block}");
        assert!(block.contains("caustic_photon_density = \"view\"\n"), "{block}");
    }
}
