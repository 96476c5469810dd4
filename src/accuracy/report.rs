//! A sweep's results: the Pareto front of error against GPU time, the CSV, the Markdown
//! table and the plot.

use super::measure::SweepRow;
use crate::metrics::BufferError;
use anyhow::{bail, Result};
use std::path::Path;

/// The error a row is ranked by: the caustic relative RMSE at the output's size (the light
/// the image shows, comparable between caustic target sizes), else at the target's (rows
/// read from sweeps written before), else the godrays'.
pub fn ranked_error(row: &SweepRow) -> f64 {
    row.caustics_at_output.or(row.caustics).or(row.godrays).map(|e| e.relative_rmse).unwrap_or(f64::NAN)
}

/// A row is on the front when no other row is at least as fast and at least as accurate,
/// and strictly better in one.
pub fn mark_pareto(rows: &mut [SweepRow]) {
    let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.effect_ms, ranked_error(r))).collect();
    for (i, row) in rows.iter_mut().enumerate() {
        let (t, e) = points[i];
        row.pareto = e.is_finite()
            && !points.iter().enumerate().any(|(j, &(t2, e2))| j != i && t2 <= t && e2 <= e && (t2 < t || e2 < e));
    }
}

pub fn csv(rows: &[SweepRow]) -> String {
    let mut s = String::from(
        "estimator,godray_method,caustic_grid,caustic_subdivision,caustic_photons,photon_density,godray_photon_density,iterations,caustic_target_w,caustic_target_h,point_size_max,\
         line_width,filter,effect_ms,frame_ms,caustic_rel_rmse,caustic_mean_rel_error,caustic_flux_error,\
         godray_rel_rmse,godray_mean_rel_error,godray_flux_error,flip,caustic_change_gpu,caustic_change_reference,\
         caustic_rel_rmse_at_output,caustic_flux_error_at_output,godray_target_w,godray_target_h,\
         godray_rel_rmse_at_output,godray_flux_error_at_output,caustic_reference_own_error,caustic_holes,\
         caustic_gaps,reference_caustic_gaps,caustic_refinement,pareto\n",
    );
    let opt = |e: Option<BufferError>| match e {
        Some(e) => format!("{:.5},{:.5},{:.5}", e.relative_rmse, e.mean_relative_error, e.flux_error),
        None => ",,".into(),
    };
    let at_output =
        |e: Option<BufferError>| e.map(|e| format!("{:.5},{:.5}", e.relative_rmse, e.flux_error)).unwrap_or(",".into());
    let fraction = |f: Option<f64>| f.map(|f| format!("{f:.5}")).unwrap_or_default();
    for r in rows {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{},{},{:.5},{:.5},{:.5},{},{},{},{},{},{},{},{},{},{}\n",
            r.estimator,
            r.godray_method,
            r.caustic_grid,
            r.caustic_subdivision,
            r.caustic_photons,
            r.photon_density,
            r.godray_photon_density,
            r.iterations,
            r.caustic_target[0],
            r.caustic_target[1],
            r.point_size_max,
            r.line_width,
            r.filter,
            r.effect_ms,
            r.frame_ms,
            opt(r.caustics),
            opt(r.godrays),
            r.flip,
            r.caustic_change_gpu,
            r.caustic_change_reference,
            at_output(r.caustics_at_output),
            r.godray_target[0],
            r.godray_target[1],
            at_output(r.godrays_at_output),
            fraction(r.caustic_reference_own_error),
            fraction(r.caustic_holes),
            fraction(r.caustic_gaps.map(|g| g[0])),
            fraction(r.caustic_gaps.map(|g| g[1])),
            r.caustic_refinement,
            r.pareto
        );
    }
    s
}

/// A table for the terminal and docs (Markdown).
pub fn table(rows: &[SweepRow]) -> String {
    let mut s = String::from(
        "| estimator | godrays | photons | iter | target | points ≤ | filter | effect ms | caustic rel RMSE (reference's own) | flux err | at the output | holes (gaps, reference's) | godray target | godray rel RMSE | at the output | FLIP | change GPU / ref | front |\n\
         | --- | --- | ---: | ---: | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | --- | --- |\n",
    );
    let rmse = |e: Option<BufferError>| e.map(|e| format!("{:.3}", e.relative_rmse)).unwrap_or("–".into());
    for r in rows {
        let own = r.caustic_reference_own_error.map(|o| format!(" ({o:.3})")).unwrap_or_default();
        let c = r.caustics.map(|e| (format!("{:.3}{own}", e.relative_rmse), format!("{:+.1} %", 100.0 * e.flux_error)));
        let (c_rmse, c_flux) = c.unwrap_or(("–".into(), "–".into()));
        // How the photons lie and are refined, after their count.
        let spread = if r.photon_density == "even" { String::new() } else { format!(", {}", r.photon_density) };
        let photons_how = format!("{spread}{}", if r.caustic_refinement { ", refined" } else { "" });
        let holes = match (r.caustic_holes, r.caustic_gaps) {
            (Some(h), Some([gpu, reference])) => format!("{:.2} % ({gpu:.3}, {reference:.3})", 100.0 * h),
            _ => "–".into(),
        };
        s += &format!(
            "| {} | {} | {}² × {}²{} | {} | {}×{} | {} | {} | {:.1} | {} | {} | {} | {} | {}×{} | {} | {} | {:.3} | {:.3} / {:.3} | {} |\n",
            r.estimator,
            if r.godray_photon_density == "even" {
                r.godray_method.clone()
            } else {
                format!("{}, {}", r.godray_method, r.godray_photon_density)
            },
            r.caustic_grid,
            r.caustic_subdivision,
            photons_how,
            r.iterations,
            r.caustic_target[0],
            r.caustic_target[1],
            r.point_size_max,
            if r.filter { "on" } else { "off" },
            r.effect_ms,
            c_rmse,
            c_flux,
            rmse(r.caustics_at_output),
            holes,
            r.godray_target[0],
            r.godray_target[1],
            rmse(r.godrays),
            rmse(r.godrays_at_output),
            r.flip,
            r.caustic_change_gpu,
            r.caustic_change_reference,
            if r.pareto { "●" } else { "" }
        );
    }
    s
}

/// The plot's series: one per estimator and filter setting, in the order the rows first
/// show them, each with its legend label ("triangles, filter on").
pub fn plot_series(rows: &[SweepRow]) -> Vec<(String, bool)> {
    let mut series: Vec<(String, bool)> = Vec::new();
    for r in rows.iter().filter(|r| ranked_error(r).is_finite()) {
        if !series.iter().any(|(e, f)| *e == r.estimator && *f == r.filter) {
            series.push((r.estimator.clone(), r.filter));
        }
    }
    series
}

/// Error against GPU time as a PNG: every setting a dot, coloured by its estimator and shaped
/// by its filter (circle off, triangle on), and the Pareto front over all of them joined by a
/// line. Text needs a TrueType font; DejaVu Sans is looked for where Debian and Ubuntu put it.
pub fn plot(rows: &[SweepRow], title: &str, path: &Path) -> Result<()> {
    use plotters::prelude::*;
    register_font()?;
    let points: Vec<(f64, f64, &SweepRow)> =
        rows.iter().map(|r| (r.effect_ms, ranked_error(r), r)).filter(|p| p.1.is_finite()).collect();
    if points.is_empty() {
        bail!("nothing to plot: no setting has a measurable error");
    }
    let (t_max, e_max) = points.iter().fold((0.0f64, 0.0f64), |(t, e), p| (t.max(p.0), e.max(p.1)));
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    let draw = |e: &dyn std::fmt::Display| anyhow::anyhow!("plot {}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| draw(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..t_max * 1.08, 0.0..e_max * 1.1)
        .map_err(|e| draw(&e))?;
    chart
        .configure_mesh()
        .x_desc("GPU ms per frame (shadow + caustics + godrays + filter)")
        .y_desc("caustic relative RMSE at the output vs reference")
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(|e| draw(&e))?;
    let mut front: Vec<(f64, f64)> = points.iter().filter(|p| p.2.pareto).map(|p| (p.0, p.1)).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), RED.stroke_width(2)))
        .map_err(|e| draw(&e))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    // Blue for the paper's points, dark yellow for the triangles, green for the footprint
    // points, grey for anything else.
    let colour = |estimator: &str| match estimator {
        "paper" => BLUE,
        "triangles" => RGBColor(200, 140, 0),
        "footprint" => RGBColor(0, 150, 80),
        _ => RGBColor(110, 110, 110),
    };
    for (estimator, filter) in plot_series(rows) {
        let c = colour(&estimator).filled();
        let members = points.iter().filter(|p| p.2.estimator == estimator && p.2.filter == filter);
        let label = format!("{estimator}, filter {}", if filter { "on" } else { "off" });
        if filter {
            chart
                .draw_series(members.map(|p| TriangleMarker::new((p.0, p.1), 7, c)))
                .map_err(|e| draw(&e))?
                .label(label)
                .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 7, c));
        } else {
            chart
                .draw_series(members.map(|p| Circle::new((p.0, p.1), 5, c)))
                .map_err(|e| draw(&e))?
                .label(label)
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, c));
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(|e| draw(&e))?;
    root.present().map_err(|e| draw(&e))?;
    Ok(())
}

fn register_font() -> Result<()> {
    static REGISTERED: std::sync::OnceLock<std::result::Result<(), String>> = std::sync::OnceLock::new();
    REGISTERED
        .get_or_init(|| {
            const CANDIDATES: [&str; 3] = [
                "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                "/usr/share/fonts/TTF/DejaVuSans.ttf",
                "/usr/share/fonts/dejavu/DejaVuSans.ttf",
            ];
            let Some(bytes) = CANDIDATES.iter().find_map(|p| std::fs::read(p).ok()) else {
                return Err(format!(
                    "the plot needs the DejaVu Sans font (looked in {}): install it with `apt-get install fonts-dejavu-core`",
                    CANDIDATES.join(", ")
                ));
            };
            // plotters keeps the font for the process's life.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, bytes)
                .map_err(|_| "DejaVu Sans could not be parsed".to_string())
        })
        .clone()
        .map_err(|e| anyhow::anyhow!(e))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(estimator: &str, godray_method: &str) -> SweepRow {
        let e = Some(BufferError { relative_rmse: 0.5, ..Default::default() });
        SweepRow {
            scene: "tank".into(),
            caustic_grid: 100,
            caustic_subdivision: 3,
            caustic_photons: 300u64.pow(2),
            iterations: 5,
            caustic_target: [154, 96],
            caustic_target_scale: 0.64,
            godray_target: [38, 24],
            godray_target_scale: 0.16,
            point_size_max: 20.0,
            line_width: 1.0,
            filter: true,
            estimator: estimator.into(),
            photon_density: "even".into(),
            godray_photon_density: "even".into(),
            godray_method: godray_method.into(),
            caustic_refinement: false,
            effect_ms: 1.0,
            frame_ms: 2.0,
            caustics: e,
            caustic_reference_own_error: None,
            caustics_at_output: e,
            caustic_holes: Some(0.0123),
            caustic_gaps: Some([0.05, 0.04]),
            godrays: e,
            godrays_at_output: e,
            flip: 0.1,
            caustic_change_gpu: 0.2,
            caustic_change_reference: 0.2,
            pareto: true,
        }
    }

    #[test]
    fn the_godray_method_is_a_column_after_the_estimator() {
        let text = csv(&[row("triangles", "marched"), row("paper", "beams")]);
        let lines: Vec<&str> = text.lines().collect();
        assert!(lines[0].starts_with("estimator,godray_method,caustic_grid,"), "{}", lines[0]);
        let columns = lines[0].split(',').count();
        for line in &lines[1..] {
            assert_eq!(line.split(',').count(), columns, "{line}");
        }
        assert!(lines[1].starts_with("triangles,marched,100,") && lines[2].starts_with("paper,beams,100,"), "{text}");
        let md = table(&[row("triangles", "marched")]);
        assert!(md.starts_with("| estimator | godrays | photons |"), "{md}");
        assert!(md.contains("\n| triangles | marched | 100² × 3² |"), "{md}");
        assert!(md.contains("| 1.23 % (0.050, 0.040) |"), "{md}");
        let holes = lines[0].split(',').position(|c| c == "caustic_holes").expect("a holes column");
        assert_eq!(lines[1].split(',').nth(holes), Some("0.01230"), "{text}");
        // The Markdown separator row has a cell per column.
        let cells = |line: &str| line.matches('|').count();
        let md_lines: Vec<&str> = md.lines().collect();
        assert!(md_lines.iter().all(|l| cells(l) == cells(md_lines[0])), "{md}");
    }

    #[test]
    fn the_plot_has_a_series_per_estimator_and_filter() {
        let mut unfiltered = row("paper", "beams");
        unfiltered.filter = false;
        let mut unmeasured = row("grid", "beams");
        unmeasured.caustics_at_output = None;
        unmeasured.caustics = None;
        unmeasured.godrays = None;
        let rows = [row("paper", "beams"), row("triangles", "beams"), unfiltered, row("paper", "marched"), unmeasured];
        let series = plot_series(&rows);
        assert_eq!(
            series,
            [("paper".to_string(), true), ("triangles".to_string(), true), ("paper".to_string(), false)]
        );
    }

    #[test]
    fn sweeps_written_before_the_godray_method_read_as_beams() {
        let mut old = serde_json::to_value(row("paper", "marched")).unwrap();
        old.as_object_mut().unwrap().remove("godray_method");
        let read: SweepRow = serde_json::from_value(old).unwrap();
        assert_eq!(read.godray_method, "beams");
    }
}
