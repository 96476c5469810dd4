//! The speed–accuracy trade (`underlight reference`, `underlight sweep`): the reference
//! buffers, cached by scene and settings; a sweep over the method's settings measuring each
//! one's GPU time and its error against the reference; the Pareto front; CSV and plot.

use crate::frame::uniforms::{FrameExtents, FrameUniforms};
use crate::frame::FrameOptions;
use crate::headless::{median_timings, SceneRenderer};
use crate::image_io::{read_pfm, write_pfm, HdrImage};
use crate::metrics::{buffer_error, compose_srgb8, flip, frame_change, BufferError};
use crate::passes::PassId;
use crate::reference::{ReferenceImages, ReferenceSettings};
use crate::scene::{CausticEstimator, Scene};
use crate::vk::device::Device;
use crate::vk::vk;
use anyhow::{bail, Context as _, Result};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// FNV-1a over bytes: a cache key stable across runs and toolchains (std's hasher is not).
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

/// What the reference depends on: geometry, camera, light, water, medium, which effects
/// exist, the target sizes, the time and the reference's own settings. Not the method's
/// settings (grids, iterations, point sizes, filter): a sweep over those reuses one reference.
fn reference_key(scene: &Scene, extents: &FrameExtents, time: f32, settings: &ReferenceSettings) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let e = &scene.effects;
    let text = format!(
        "{:?}|{:?}|{:?}|{:?}|{}|{}|{:?}|{:?}|{}|{}|{}",
        scene.camera,
        scene.light,
        scene.water,
        scene.medium,
        e.caustics,
        e.godrays,
        extents.caustic,
        extents.godray,
        time.to_bits(),
        settings.caustic_photons,
        settings.godray_beams
    );
    h = fnv1a(text.as_bytes(), h);
    h = fnv1a(&settings.seed.to_le_bytes(), h);
    for m in &scene.meshes {
        h = fnv1a(bytemuck::cast_slice(&m.positions), h);
        h = fnv1a(bytemuck::cast_slice(&m.indices), h);
    }
    format!("{}-{h:016x}", scene.name.replace(|c: char| !c.is_ascii_alphanumeric(), "_"))
}

/// The default cache folder: `$XDG_CACHE_HOME/underlight/reference`, else
/// `~/.cache/underlight/reference`, else `target/underlight-reference`.
pub fn default_cache_dir() -> PathBuf {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(|| PathBuf::from("target"));
    base.join("underlight").join("reference")
}

/// A progress bar on stderr: `label [#####.....]  45 %`, redrawn at most every 1 %.
pub struct Progress {
    label: String,
    last: std::sync::atomic::AtomicU32,
}

impl Progress {
    pub fn new(label: impl Into<String>) -> Self {
        Self { label: label.into(), last: std::sync::atomic::AtomicU32::new(u32::MAX) }
    }

    pub fn update(&self, fraction: f64) {
        use std::io::IsTerminal as _;
        let percent = (fraction.clamp(0.0, 1.0) * 100.0) as u32;
        // Into a log (not a terminal) every 25 %, so redraws do not flood it.
        let step = if std::io::stderr().is_terminal() { 1 } else { 25 };
        let percent = percent / step * step;
        if self.last.swap(percent, std::sync::atomic::Ordering::Relaxed) == percent {
            return;
        }
        let filled = (percent / 4) as usize;
        let bar = format!("{} [{}{}] {percent:>3} %", self.label, "#".repeat(filled), ".".repeat(25 - filled));
        if step == 1 {
            eprint!("\r{bar}{}", if percent == 100 { "\n" } else { "" });
            std::io::stderr().flush().ok();
        } else {
            eprintln!("{bar}");
        }
    }
}

/// The reference buffers for `scene` at `time` and `extents`: read from `cache_dir` when a
/// run with the same inputs wrote them, otherwise traced (with a progress bar) and stored.
pub fn cached_reference(
    scene: &Scene,
    time: f32,
    extents: &FrameExtents,
    settings: &ReferenceSettings,
    cache_dir: &Path,
) -> Result<ReferenceImages> {
    let dir = cache_dir.join(reference_key(scene, extents, time, settings));
    let (caustics, godrays) = (dir.join("caustics.pfm"), dir.join("godrays.pfm"));
    let want = |on: bool, p: &Path| !on || p.exists();
    let plan = crate::frame::FramePlan::for_scene(scene);
    let (has_c, has_g) = (plan.runs(PassId::Caustics), plan.runs(PassId::Godrays));
    if dir.join("done").exists() && want(has_c, &caustics) && want(has_g, &godrays) {
        let load = |on: bool, p: &Path| if on { read_pfm(p).map(Some) } else { Ok(None) };
        return Ok(ReferenceImages { caustics: load(has_c, &caustics)?, godrays: load(has_g, &godrays)? });
    }
    let progress = Progress::new(format!("reference {} t={time}", scene.name));
    let images = crate::reference::render(scene, time, extents, settings, &|f| progress.update(f))?;
    progress.update(1.0);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating the reference cache {}", dir.display()))?;
    if let Some(c) = &images.caustics {
        write_pfm(&caustics, c)?;
    }
    if let Some(g) = &images.godrays {
        write_pfm(&godrays, g)?;
    }
    std::fs::write(dir.join("done"), b"")?;
    Ok(images)
}

/// The settings a sweep varies; every combination is one row. Empty: the scene's value.
#[derive(Clone, Debug, Default)]
pub struct SweepAxes {
    pub grid: Vec<u32>,
    pub subdivision: Vec<u32>,
    pub iterations: Vec<u32>,
    pub target_scale: Vec<f32>,
    pub point_size: Vec<f32>,
    pub line_width: Vec<f32>,
    pub filter: Vec<bool>,
    pub estimator: Vec<CausticEstimator>,
}

impl SweepAxes {
    /// Every value within what a scene file accepts (`docs/limits.md`), checked before any
    /// GPU work; the error names the option and the range.
    pub fn validate(&self) -> Result<()> {
        let ints: [(&str, &Vec<u32>, u32, u32); 3] = [
            ("--grid", &self.grid, 1, 4096),
            ("--subdiv", &self.subdivision, 1, crate::shader_math::MAX_SUBDIVISION),
            ("--iterations", &self.iterations, 1, 64),
        ];
        for (name, values, lo, hi) in ints {
            if let Some(v) = values.iter().find(|v| !(lo..=hi).contains(*v)) {
                bail!("{name} {v} is out of range {lo}..={hi}");
            }
        }
        let floats: [(&str, &Vec<f32>, f32, f32); 3] = [
            ("--target", &self.target_scale, 0.0, 4.0),
            ("--point-size", &self.point_size, 0.0, f32::INFINITY),
            ("--line-width", &self.line_width, 0.0, f32::INFINITY),
        ];
        for (name, values, lo, hi) in floats {
            if let Some(v) = values.iter().find(|v| !(**v > lo && **v <= hi)) {
                bail!("{name} {v} is out of range: must be > {lo} and ≤ {hi}");
            }
        }
        Ok(())
    }

    /// Every combination, applied to `base`.
    pub fn scenes(&self, base: &Scene) -> Vec<Scene> {
        let e = &base.effects;
        let or = |v: &Vec<u32>, d: u32| if v.is_empty() { vec![d] } else { v.clone() };
        let orf = |v: &Vec<f32>, d: f32| if v.is_empty() { vec![d] } else { v.clone() };
        let filters = if self.filter.is_empty() { vec![e.filter] } else { self.filter.clone() };
        let estimators = if self.estimator.is_empty() { vec![e.caustic_estimator] } else { self.estimator.clone() };
        let mut out = Vec::new();
        for &grid in &or(&self.grid, e.caustic_grid) {
            for &sub in &or(&self.subdivision, e.caustic_subdivision) {
                for &iterations in &or(&self.iterations, e.iterations) {
                    for &scale in &orf(&self.target_scale, e.caustic_target_scale) {
                        for &size in &orf(&self.point_size, e.point_size_max) {
                            for &width in &orf(&self.line_width, e.line_width) {
                                for (&filter, &estimator) in
                                    filters.iter().flat_map(|f| estimators.iter().map(move |e| (f, e)))
                                {
                                    let mut s = base.clone();
                                    let fx = &mut s.effects;
                                    fx.caustic_grid = grid;
                                    fx.caustic_subdivision = sub;
                                    fx.iterations = iterations;
                                    fx.caustic_target_scale = scale;
                                    fx.point_size_max = size;
                                    fx.point_size_min = fx.point_size_min.min(size);
                                    fx.line_width = width;
                                    fx.filter = filter;
                                    fx.caustic_estimator = estimator;
                                    // The triangle estimator's subdivision bound (its
                                    // geometry shader's output limit) skips larger ones.
                                    if estimator == CausticEstimator::Triangles
                                        && sub > crate::shader_math::TRIANGLE_MAX_SUBDIVISION
                                    {
                                        continue;
                                    }
                                    out.push(s);
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }
}

/// One setting's figures.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SweepRow {
    pub caustic_grid: u32,
    pub caustic_subdivision: u32,
    pub caustic_photons: u64,
    pub iterations: u32,
    pub caustic_target: [u32; 2],
    pub point_size_max: f32,
    pub line_width: f32,
    pub filter: bool,
    /// `CausticEstimator::name`.
    pub estimator: &'static str,
    /// Median GPU ms of the passes the settings change: shadow, caustics, godrays, filter.
    pub effect_ms: f64,
    /// Median GPU ms of the whole frame (all passes).
    pub frame_ms: f64,
    pub caustics: Option<BufferError>,
    pub godrays: Option<BufferError>,
    /// Mean FLIP of the final image composed with the GPU's buffers against the one composed
    /// with the reference's.
    pub flip: f64,
    /// Frame-to-frame change of the caustic buffer over one time step: GPU and reference.
    pub caustic_change_gpu: f64,
    pub caustic_change_reference: f64,
    /// On the Pareto front of caustic relative RMSE against effect_ms.
    pub pareto: bool,
}

pub struct SweepSpec<'a> {
    pub scene: &'a Scene,
    pub output: [u32; 2],
    pub axes: SweepAxes,
    pub time: f32,
    /// Time step for the flicker figure, s.
    pub step: f32,
    pub frames: u32,
    pub warmup: u32,
    pub reference: ReferenceSettings,
    pub cache_dir: PathBuf,
}

/// The buffers compose reads: the filtered ones where the frame filters.
fn shown<'a>(filtered: &'a Option<HdrImage>, raw: &'a Option<HdrImage>) -> Option<&'a HdrImage> {
    filtered.as_ref().or(raw.as_ref())
}

/// Runs every setting of the sweep: GPU time (median of `frames`), the buffers at `time`
/// and `time + step` against the reference at both.
pub fn run_sweep(device: &Arc<Device>, spec: &SweepSpec) -> Result<Vec<SweepRow>> {
    let scenes = spec.axes.scenes(spec.scene);
    let out = vk::Extent2D { width: spec.output[0], height: spec.output[1] };
    let mut rows = Vec::with_capacity(scenes.len());
    for (k, scene) in scenes.iter().enumerate() {
        let e = &scene.effects;
        eprintln!(
            "setting {}/{}: {} estimator, grid {}² × {}², {} iterations, target ×{}, points ≤ {} px, lines {} px, filter {}",
            k + 1,
            scenes.len(),
            e.caustic_estimator.name(),
            e.caustic_grid,
            e.caustic_subdivision,
            e.iterations,
            e.caustic_target_scale,
            e.point_size_max,
            e.line_width,
            if e.filter { "on" } else { "off" }
        );
        let mut renderer = SceneRenderer::with_options(device, scene, out, FrameOptions::default())?;
        let extents = renderer.frame.extents;
        renderer.render(spec.warmup, spec.time, 0.0, false)?;
        let (timings, images) = renderer.render(spec.frames.max(1), spec.time, 0.0, true)?;
        let (_, next) = renderer.render(1, spec.time + spec.step, 0.0, true)?;
        drop(renderer);
        let (images, next) = (images.expect("read back"), next.expect("read back"));
        let median = median_timings(&timings);
        let ms = |ids: &[PassId]| ids.iter().filter_map(|id| median.get(*id)).sum::<f64>();
        let effect_ms = ms(&[PassId::Shadow, PassId::Caustics, PassId::Godrays, PassId::Filter]);
        let frame_ms =
            ms(&[PassId::Shadow, PassId::Scene, PassId::Caustics, PassId::Godrays, PassId::Filter, PassId::Compose]);

        let reference = cached_reference(scene, spec.time, &extents, &spec.reference, &spec.cache_dir)?;
        let reference_next =
            cached_reference(scene, spec.time + spec.step, &extents, &spec.reference, &spec.cache_dir)?;
        let gpu_c = shown(&images.caustics_filtered, &images.caustics);
        let gpu_g = shown(&images.godrays_filtered, &images.godrays);
        let error = |gpu: Option<&HdrImage>, r: &Option<HdrImage>| -> Result<Option<BufferError>> {
            match (gpu, r) {
                (Some(g), Some(r)) => buffer_error(g, r).map(Some),
                _ => Ok(None),
            }
        };
        let uniforms = FrameUniforms::new(scene, scene.bounds(), &extents, spec.time);
        let exposure = uniforms.exposure;
        let composed = |c: Option<&HdrImage>, g: Option<&HdrImage>| {
            compose_srgb8(&images.scene_color, &images.albedo_transmittance, c, g, exposure)
        };
        let flip = flip(
            &composed(reference.caustics.as_ref(), reference.godrays.as_ref()),
            &composed(gpu_c, gpu_g),
            images.width,
            images.height,
        )?;
        let change = |a: Option<&HdrImage>, b: Option<&HdrImage>| match (a, b) {
            (Some(a), Some(b)) => frame_change(a, b),
            _ => Ok(0.0),
        };
        rows.push(SweepRow {
            caustic_grid: e.caustic_grid,
            caustic_subdivision: e.caustic_subdivision,
            caustic_photons: ((e.caustic_grid * e.caustic_subdivision) as u64).pow(2),
            iterations: e.iterations,
            caustic_target: extents.caustic,
            point_size_max: e.point_size_max,
            line_width: e.line_width,
            filter: e.filter,
            estimator: e.caustic_estimator.name(),
            effect_ms,
            frame_ms,
            caustics: error(gpu_c, &reference.caustics)?,
            godrays: error(gpu_g, &reference.godrays)?,
            flip,
            caustic_change_gpu: change(gpu_c, shown(&next.caustics_filtered, &next.caustics))?,
            caustic_change_reference: change(reference.caustics.as_ref(), reference_next.caustics.as_ref())?,
            pareto: false,
        });
    }
    mark_pareto(&mut rows);
    Ok(rows)
}

/// The error a row is ranked by: caustic relative RMSE, else godray's.
pub fn ranked_error(row: &SweepRow) -> f64 {
    row.caustics.or(row.godrays).map(|e| e.relative_rmse).unwrap_or(f64::NAN)
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
        "estimator,caustic_grid,caustic_subdivision,caustic_photons,iterations,caustic_target_w,caustic_target_h,point_size_max,\
         line_width,filter,effect_ms,frame_ms,caustic_rel_rmse,caustic_mean_rel_error,caustic_flux_error,\
         godray_rel_rmse,godray_mean_rel_error,godray_flux_error,flip,caustic_change_gpu,caustic_change_reference,pareto\n",
    );
    let opt = |e: Option<BufferError>| match e {
        Some(e) => format!("{:.5},{:.5},{:.5}", e.relative_rmse, e.mean_relative_error, e.flux_error),
        None => ",,".into(),
    };
    for r in rows {
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{},{},{:.5},{:.5},{:.5},{}\n",
            r.estimator,
            r.caustic_grid,
            r.caustic_subdivision,
            r.caustic_photons,
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
            r.pareto
        );
    }
    s
}

/// A table for the terminal and docs (Markdown).
pub fn table(rows: &[SweepRow]) -> String {
    let mut s = String::from(
        "| estimator | photons | iter | target | points ≤ | filter | effect ms | caustic rel RMSE | flux err | godray rel RMSE | FLIP | change GPU / ref | front |\n\
         | --- | ---: | ---: | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | --- | --- |\n",
    );
    for r in rows {
        let c = r.caustics.map(|e| (format!("{:.3}", e.relative_rmse), format!("{:+.1} %", 100.0 * e.flux_error)));
        let (c_rmse, c_flux) = c.unwrap_or(("–".into(), "–".into()));
        s += &format!(
            "| {} | {}² × {}² | {} | {}×{} | {} | {} | {:.1} | {} | {} | {} | {:.3} | {:.3} / {:.3} | {} |\n",
            r.estimator,
            r.caustic_grid,
            r.caustic_subdivision,
            r.iterations,
            r.caustic_target[0],
            r.caustic_target[1],
            r.point_size_max,
            if r.filter { "on" } else { "off" },
            r.effect_ms,
            c_rmse,
            c_flux,
            r.godrays.map(|e| format!("{:.3}", e.relative_rmse)).unwrap_or("–".into()),
            r.flip,
            r.caustic_change_gpu,
            r.caustic_change_reference,
            if r.pareto { "●" } else { "" }
        );
    }
    s
}

/// Error against GPU time as a PNG: every setting a dot, the Pareto front joined by a line.
/// Text needs a TrueType font; DejaVu Sans is looked for where Debian and Ubuntu put it.
pub fn plot(rows: &[SweepRow], title: &str, path: &Path) -> Result<()> {
    use plotters::prelude::*;
    register_font()?;
    let points: Vec<(f64, f64, bool, bool)> =
        rows.iter().map(|r| (r.effect_ms, ranked_error(r), r.pareto, r.filter)).filter(|p| p.1.is_finite()).collect();
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
        .y_desc("caustic relative RMSE vs reference")
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(|e| draw(&e))?;
    let mut front: Vec<(f64, f64)> = points.iter().filter(|p| p.2).map(|p| (p.0, p.1)).collect();
    front.sort_by(|a, b| a.0.total_cmp(&b.0));
    chart
        .draw_series(LineSeries::new(front.clone(), RED.stroke_width(2)))
        .map_err(|e| draw(&e))?
        .label("Pareto front")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED.stroke_width(2)));
    chart
        .draw_series(points.iter().filter(|p| !p.3).map(|p| Circle::new((p.0, p.1), 5, BLUE.filled())))
        .map_err(|e| draw(&e))?
        .label("filter off")
        .legend(|(x, y)| Circle::new((x + 10, y), 5, BLUE.filled()));
    chart
        .draw_series(points.iter().filter(|p| p.3).map(|p| TriangleMarker::new((p.0, p.1), 7, GREEN.filled())))
        .map_err(|e| draw(&e))?
        .label("filter on")
        .legend(|(x, y)| TriangleMarker::new((x + 10, y), 7, GREEN.filled()));
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
