//! `underlight bench`: per-pass GPU times of the frame for the paper's configurations,
//! from timestamp queries, with validation off. Warm-up frames are discarded; each pass's
//! median, 5th and 95th percentile over the measured frames are reported, beside the frame
//! rates the paper measured on its GTX 260 (2009).

use crate::frame::FrameOptions;
use crate::frame::PassTimings;
use crate::headless::SceneRenderer;
use crate::image_io::HdrImage;
use crate::passes::PassId;
use crate::passes::PhotonPath;
use crate::scene::{CausticEstimator, Scene};
use crate::vk::device::Device;
use anyhow::{bail, Result};
use ash::vk;
use serde::Serialize;
use std::fmt::Write as _;
use std::sync::Arc;

/// A benchmark configuration: the output size and effect settings applied to a scene.
#[derive(Clone, Debug, Serialize)]
pub struct BenchConfig {
    pub name: &'static str,
    pub width: u32,
    pub height: u32,
    pub caustic_grid: u32,
    pub godray_grid: u32,
    /// Geometry-shader subdivision of both grids (the paper: 2, i.e. ×4 photons).
    pub subdivision: u32,
    /// The caustic estimator (the paper's points), and its own subdivision where it differs.
    pub caustic_estimator: CausticEstimator,
    pub caustic_subdivision: Option<u32>,
    /// Effect targets as fractions of the output; `None` keeps the scene's.
    pub caustic_target_scale: Option<f32>,
    pub godray_target_scale: Option<f32>,
    pub point_size: Option<(f32, f32)>,
    pub line_width: Option<f32>,
    pub filter: bool,
    /// The camera mirrored in the water's mean plane, so it looks at the same point through
    /// the surface from above (the refraction and reflection passes run).
    pub camera_above: bool,
    /// The paper's frame rate for this configuration, as it states it.
    pub paper_fps: &'static str,
}

/// The paper's table (method.md, "The paper's settings and results"), and a tiny one for
/// smoke tests.
pub fn configs() -> Vec<BenchConfig> {
    let base = BenchConfig {
        name: "",
        width: 800,
        height: 800,
        caustic_grid: 200,
        godray_grid: 100,
        subdivision: 2,
        caustic_estimator: CausticEstimator::Paper,
        caustic_subdivision: None,
        // 512² and 128² at 800².
        caustic_target_scale: Some(0.64),
        godray_target_scale: Some(0.16),
        point_size: None,
        line_width: None,
        filter: true,
        camera_above: false,
        paper_fps: "",
    };
    vec![
        BenchConfig { name: "paper-800", paper_fps: "> 110", ..base.clone() },
        BenchConfig { name: "paper-1440", width: 1440, height: 850, paper_fps: "> 60", ..base.clone() },
        BenchConfig {
            name: "paper-1m-photons",
            caustic_grid: 500,
            godray_grid: 300,
            filter: false, // "filtering no longer needed"
            paper_fps: "20–30",
            ..base.clone()
        },
        BenchConfig {
            name: "paper-1440-high",
            width: 1440,
            height: 850,
            caustic_grid: 400,
            godray_grid: 200,
            godray_target_scale: Some(0.32), // 460×272 at 1440×850
            point_size: Some((2.0, 10.0)),
            line_width: Some(12.0),
            paper_fps: "20",
            ..base.clone()
        },
        // Not in the paper: the triangle estimator as the built-in scenes ship it, at about
        // paper-800's cost (docs/accuracy.md), with paper-800's godrays.
        BenchConfig {
            name: "triangles-800",
            caustic_estimator: CausticEstimator::Triangles,
            caustic_grid: 100,
            caustic_subdivision: Some(3),
            paper_fps: "-",
            ..base.clone()
        },
        // Not in the paper: its camera stays under the water.
        BenchConfig { name: "above-800", camera_above: true, paper_fps: "-", ..base.clone() },
        BenchConfig { name: "tiny", width: 96, height: 96, caustic_grid: 16, godray_grid: 8, paper_fps: "-", ..base },
    ]
}

impl BenchConfig {
    /// The scene with this configuration's settings.
    pub fn apply(&self, scene: &Scene) -> Scene {
        let mut s = scene.clone();
        let e = &mut s.effects;
        e.caustic_grid = self.caustic_grid;
        e.godray_grid = self.godray_grid;
        e.caustic_subdivision = self.caustic_subdivision.unwrap_or(self.subdivision);
        e.godray_subdivision = self.subdivision;
        e.caustic_estimator = self.caustic_estimator;
        if let Some(v) = self.caustic_target_scale {
            e.caustic_target_scale = v;
        }
        if let Some(v) = self.godray_target_scale {
            e.godray_target_scale = v;
        }
        if let Some((lo, hi)) = self.point_size {
            e.point_size_min = lo;
            e.point_size_max = hi;
        }
        if let Some(w) = self.line_width {
            e.line_width = w;
        }
        e.filter = self.filter;
        s.output = [self.width, self.height];
        if self.camera_above {
            move_camera_above_water(&mut s);
        }
        s
    }
}

/// Mirrors the camera's height in the water's mean plane (if under it), so it looks at the
/// same point through the surface from above.
pub fn move_camera_above_water(scene: &mut Scene) {
    let level = scene.water.level;
    scene.camera.position.y = level + (level - scene.camera.position.y).abs();
}

/// Median, 5th and 95th percentile of one pass's GPU milliseconds.
#[derive(Clone, Debug, Serialize)]
pub struct PassStats {
    pub pass: String,
    pub median_ms: f64,
    pub p5_ms: f64,
    pub p95_ms: f64,
}

#[derive(Clone, Debug, Serialize)]
pub struct BenchResult {
    pub config: BenchConfig,
    pub photon_path: PhotonPath,
    pub scene: String,
    pub frames: usize,
    /// Photons cast per frame: caustics and godrays (grid × subdivision, squared).
    pub caustic_photons: u64,
    pub godray_photons: u64,
    pub passes: Vec<PassStats>,
    /// Of the per-frame sum of the passes.
    pub total: PassStats,
    /// For a path other than the geometry shader's, how its unfiltered caustic and godray
    /// buffers differ from the geometry shader's on the same frame (`--compare-paths`).
    pub caustic_difference: Option<BufferDifference>,
    pub godray_difference: Option<BufferDifference>,
}

/// How a photon buffer differs from a reference one.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct BufferDifference {
    /// Σ|b − a| / Σ|a| over the RGB values of every pixel.
    pub relative_l1: f64,
    /// Σb / Σa: the energy one keeps against the other.
    pub sum_ratio: f64,
}

/// The difference of `b` from reference `a` (same size); `None` when `a` is empty.
pub fn buffer_difference(a: &HdrImage, b: &HdrImage) -> Option<BufferDifference> {
    let (mut diff, mut sum_a, mut sum_b) = (0.0f64, 0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            diff += (p[c] as f64 - q[c] as f64).abs();
            sum_a += p[c] as f64;
            sum_b += q[c] as f64;
        }
    }
    (sum_a > 0.0 && a.pixels.len() == b.pixels.len())
        .then(|| BufferDifference { relative_l1: diff / sum_a, sum_ratio: sum_b / sum_a })
}

#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub device: String,
    pub driver: String,
    pub results: Vec<BenchResult>,
}

/// The value at quantile `q` (0..=1) of sorted `v`, nearest rank.
fn quantile(v: &[f64], q: f64) -> f64 {
    v[((v.len() - 1) as f64 * q).round() as usize]
}

fn stats(name: &str, mut v: Vec<f64>) -> PassStats {
    v.sort_by(f64::total_cmp);
    PassStats { pass: name.into(), median_ms: quantile(&v, 0.5), p5_ms: quantile(&v, 0.05), p95_ms: quantile(&v, 0.95) }
}

/// Renders `warmup + frames` frames of `config` on `scene` and summarises the measured ones.
pub fn run_config(
    device: &Arc<Device>,
    scene: &Scene,
    config: &BenchConfig,
    frames: u32,
    warmup: u32,
    path: PhotonPath,
) -> Result<BenchResult> {
    Ok(measure(device, scene, config, frames, warmup, path, false)?.0)
}

/// Every photon path on `config`, the geometry shader's first: each one's times and how
/// its caustic and godray buffers differ from the geometry shader's on the first frame
/// (time 0, the frame the splat floor replays). The compute path is skipped, with a note,
/// on a device without float atomics.
pub fn compare_paths(
    device: &Arc<Device>,
    scene: &Scene,
    config: &BenchConfig,
    frames: u32,
    warmup: u32,
) -> Result<Vec<BenchResult>> {
    let mut out: Vec<BenchResult> = Vec::new();
    let mut reference: Option<[Option<HdrImage>; 2]> = None;
    for path in PhotonPath::ALL {
        if path == PhotonPath::Compute && !device.has_float_atomics() {
            eprintln!("  {}: skipped, {} lacks shaderBufferFloat32AtomicAdd", path.name(), device.info.name);
            continue;
        }
        if path != PhotonPath::GeometryShader && config.caustic_estimator == CausticEstimator::Triangles {
            eprintln!("  {}: skipped, the triangle estimator is the geometry shader's alone", path.name());
            continue;
        }
        eprintln!("  {} path…", path.name());
        let (mut result, buffers) = measure(device, scene, config, frames, warmup, path, true)?;
        let buffers = buffers.expect("measure reads the buffers back when asked");
        match &reference {
            None => reference = Some(buffers),
            Some(r) => {
                let diff = |i: usize| match (&r[i], &buffers[i]) {
                    (Some(a), Some(b)) => buffer_difference(a, b),
                    _ => None,
                };
                result.caustic_difference = diff(0);
                result.godray_difference = diff(1);
            }
        }
        out.push(result);
    }
    Ok(out)
}

/// `run_config`, and with `read_buffers` one more frame at time 0 whose unfiltered caustic
/// and godray buffers are read back (outside the measured frames).
fn measure(
    device: &Arc<Device>,
    scene: &Scene,
    config: &BenchConfig,
    frames: u32,
    warmup: u32,
    path: PhotonPath,
    read_buffers: bool,
) -> Result<(BenchResult, Option<[Option<HdrImage>; 2]>)> {
    if frames == 0 {
        bail!("--frames must be at least 1");
    }
    // The splat floor's first frame also records its splats: never measure it.
    let warmup = if path == PhotonPath::SplatFloor { warmup.max(1) } else { warmup };
    let s = config.apply(scene);
    let extent = vk::Extent2D { width: config.width, height: config.height };
    let options = FrameOptions { photon_path: path, ..Default::default() };
    let mut renderer = SceneRenderer::with_options(device, &s, extent, options)?;
    let (timings, _) = renderer.render(warmup + frames, 0.0, 1.0 / 60.0, false)?;
    let measured: Vec<&PassTimings> = timings.iter().skip(warmup as usize).collect();
    let mut passes = Vec::new();
    for id in renderer.frame.plan.passes.iter().copied() {
        let v: Vec<f64> = measured.iter().filter_map(|t| t.get(id)).collect();
        if !v.is_empty() {
            passes.push(stats(id.name(), v));
        }
    }
    let totals = measured.iter().map(|t| t.total_ms()).collect();
    let n = |grid: u32, subdivision: u32| (grid as u64 * subdivision as u64).pow(2);
    let caustic_subdivision = config.caustic_subdivision.unwrap_or(config.subdivision);
    let buffers = if read_buffers {
        let (_, images) = renderer.render(1, 0.0, 0.0, true)?;
        images.map(|i| [i.caustics, i.godrays])
    } else {
        None
    };
    let result = BenchResult {
        config: config.clone(),
        photon_path: path,
        scene: s.name.clone(),
        frames: measured.len(),
        caustic_photons: if renderer.frame.plan.runs(PassId::Caustics) {
            n(config.caustic_grid, caustic_subdivision)
        } else {
            0
        },
        godray_photons: if renderer.frame.plan.runs(PassId::Godrays) {
            n(config.godray_grid, config.subdivision)
        } else {
            0
        },
        passes,
        total: stats("total", totals),
        caustic_difference: None,
        godray_difference: None,
    };
    Ok((result, buffers))
}

impl BenchReport {
    /// The human-readable table: one row per configuration, per-pass medians, the total's
    /// median [p5–p95], the frame rate that total allows, and the paper's.
    pub fn table(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(out, "device: {} ({})", self.device, self.driver);
        // The water's refraction and reflection columns only when some configuration has them.
        let surface = self.results.iter().any(|r| r.passes.iter().any(|p| p.pass == "refraction"));
        let ids: &[&str] = if surface {
            &["shadow", "refraction", "reflection", "scene", "caustics", "godrays", "filter", "compose"]
        } else {
            &["shadow", "scene", "caustics", "godrays", "filter", "compose"]
        };
        let _ = write!(out, "{:<32} {:>10}", "config", "photons");
        for id in ids {
            let _ = write!(out, " {:>10}", id);
        }
        let _ = writeln!(out, " {:>26} {:>9} {:>10}", "total ms median [p5–p95]", "GPU fps", "paper fps");
        for r in &self.results {
            let name = match r.photon_path {
                PhotonPath::GeometryShader => r.config.name.to_string(),
                PhotonPath::VertexOnly => format!("{} (vertex)", r.config.name),
                PhotonPath::Compute => format!("{} (compute)", r.config.name),
                PhotonPath::SplatFloor => format!("{} (splat floor)", r.config.name),
            };
            let _ = write!(out, "{:<32} {:>10}", name, r.caustic_photons + r.godray_photons);
            for id in ids {
                match r.passes.iter().find(|p| p.pass == *id) {
                    Some(p) => {
                        let _ = write!(out, " {:>10.2}", p.median_ms);
                    }
                    None => {
                        let _ = write!(out, " {:>10}", "-");
                    }
                }
            }
            let t = &r.total;
            let span = format!("{:.2} [{:.2}–{:.2}]", t.median_ms, t.p5_ms, t.p95_ms);
            let _ = writeln!(out, " {:>26} {:>9.1} {:>10}", span, 1000.0 / t.median_ms, r.config.paper_fps);
        }
        if self.results.iter().any(|r| r.photon_path != PhotonPath::GeometryShader) {
            out.push_str(&self.paths_table());
        }
        out
    }

    /// The photon paths side by side: each path's caustic and godray pass times, as a
    /// multiple of the geometry shader's, and how its buffers differ from the geometry
    /// shader's (relative L1, and the ratio of the sums).
    fn paths_table(&self) -> String {
        let mut out = String::from("\nphoton paths against the geometry shader (same configuration, same run):\n");
        let _ = writeln!(
            out,
            "{:<18} {:<18} {:>12} {:>8} {:>12} {:>8} {:>22} {:>22}",
            "config", "path", "caustics ms", "× GS", "godrays ms", "× GS", "caustic L1 (sum ×)", "godray L1 (sum ×)"
        );
        let ms = |r: &BenchResult, pass: &str| r.passes.iter().find(|p| p.pass == pass).map(|p| p.median_ms);
        for r in &self.results {
            let gs = self
                .results
                .iter()
                .find(|g| g.config.name == r.config.name && g.photon_path == PhotonPath::GeometryShader);
            let cell = |pass: &str| match (ms(r, pass), gs.and_then(|g| ms(g, pass))) {
                (Some(v), Some(g)) => (format!("{v:.2}"), format!("{:.2}", v / g)),
                (Some(v), None) => (format!("{v:.2}"), "-".into()),
                _ => ("-".into(), "-".into()),
            };
            let diff = |d: &Option<BufferDifference>| match d {
                Some(d) => format!("{:.2e} ({:.4})", d.relative_l1, d.sum_ratio),
                None if r.photon_path == PhotonPath::GeometryShader => "reference".into(),
                None => "-".into(),
            };
            let (c, cx) = cell("caustics");
            let (g, gx) = cell("godrays");
            let _ = writeln!(
                out,
                "{:<18} {:<18} {:>12} {:>8} {:>12} {:>8} {:>22} {:>22}",
                r.config.name,
                r.photon_path.name(),
                c,
                cx,
                g,
                gx,
                diff(&r.caustic_difference),
                diff(&r.godray_difference)
            );
        }
        out
    }

    /// One CSV row per configuration and pass (the total as pass "total").
    pub fn csv(&self) -> String {
        let mut out = String::from("device,driver,config,photon_path,scene,width,height,caustic_photons,godray_photons,frames,pass,median_ms,p5_ms,p95_ms,caustic_relative_l1,caustic_sum_ratio,godray_relative_l1,godray_sum_ratio\n");
        // Empty where there is no difference (the geometry shader's own rows).
        let diff = |d: &Option<BufferDifference>| match d {
            Some(d) => format!("{:.6e},{:.6}", d.relative_l1, d.sum_ratio),
            None => ",".to_string(),
        };
        for r in &self.results {
            for p in r.passes.iter().chain(std::iter::once(&r.total)) {
                let _ = writeln!(
                    out,
                    "\"{}\",\"{}\",{},{:?},{},{},{},{},{},{},{},{:.6},{:.6},{:.6},{},{}",
                    self.device,
                    self.driver,
                    r.config.name,
                    r.photon_path,
                    r.scene,
                    r.config.width,
                    r.config.height,
                    r.caustic_photons,
                    r.godray_photons,
                    r.frames,
                    p.pass,
                    p.median_ms,
                    p.p5_ms,
                    p.p95_ms,
                    diff(&r.caustic_difference),
                    diff(&r.godray_difference)
                );
            }
        }
        out
    }
}

/// One scaling series: a parameter varied over values with everything else at paper-800,
/// and the GPU time of the pass it drives (and the total) at each value.
#[derive(Clone, Debug, Serialize)]
pub struct Series {
    /// What was varied and what it is measured in ("caustic photons (millions)", …).
    pub parameter: String,
    pub pass: String,
    pub points: Vec<(f64, f64)>,
    /// Least-squares line through the points: ms = intercept + slope · x.
    pub slope_ms: f64,
    pub intercept_ms: f64,
}

fn fit(points: &[(f64, f64)]) -> (f64, f64) {
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / n, sy / n);
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    (slope, my - slope * mx)
}

/// Cost against the work: caustic photons, godray photons, caustic target pixels, point size
/// and line width, each varied alone from paper-800 (or from `base`, scaled down for tests).
pub fn scaling(
    device: &Arc<Device>,
    scene: &Scene,
    base: &BenchConfig,
    frames: u32,
    warmup: u32,
) -> Result<Vec<Series>> {
    type Vary = fn(&mut BenchConfig, f64);
    type Measure = fn(&BenchConfig) -> f64;
    // (name, pass, values, how each value changes the configuration, the work it measures)
    let sweeps: [(&str, &str, Vec<f64>, Vary, Measure); 5] = [
        (
            "caustic photons (millions)",
            "caustics",
            vec![0.5, 1.0, 1.5, 2.0],
            |c, f| c.caustic_grid = (c.caustic_grid as f64 * f).round() as u32,
            |c| (c.caustic_grid as f64 * c.subdivision as f64).powi(2) / 1e6,
        ),
        (
            "godray photons (millions)",
            "godrays",
            vec![0.5, 1.0, 1.5, 2.0],
            |c, f| c.godray_grid = (c.godray_grid as f64 * f).round() as u32,
            |c| (c.godray_grid as f64 * c.subdivision as f64).powi(2) / 1e6,
        ),
        (
            "caustic target (megapixels)",
            "caustics",
            vec![0.5, 1.0, 1.5, 2.0],
            |c, f| c.caustic_target_scale = Some(c.caustic_target_scale.unwrap_or(0.64) * f as f32),
            |c| {
                let s = c.caustic_target_scale.unwrap_or(0.64) as f64;
                (c.width as f64 * s).round() * (c.height as f64 * s).round() / 1e6
            },
        ),
        (
            "largest point size (px)",
            "caustics",
            vec![0.5, 1.0, 2.0, 3.0],
            |c, f| {
                let (lo, hi) = c.point_size.unwrap_or((5.0, 20.0));
                c.point_size = Some((lo * f as f32, hi * f as f32));
            },
            |c| c.point_size.unwrap_or((5.0, 20.0)).1 as f64,
        ),
        (
            "godray line width (px)",
            "godrays",
            vec![1.0, 2.0, 4.0, 8.0],
            |c, f| c.line_width = Some(f as f32),
            |c| c.line_width.unwrap_or(1.0) as f64,
        ),
    ];
    let mut out = Vec::new();
    for (parameter, pass, factors, vary, measure) in sweeps {
        let mut points = Vec::new();
        for f in factors {
            let mut c = base.clone();
            vary(&mut c, f);
            let r = run_config(device, scene, &c, frames, warmup, PhotonPath::GeometryShader)?;
            let ms = r.passes.iter().find(|p| p.pass == pass).map(|p| p.median_ms).unwrap_or(0.0);
            points.push((measure(&c), ms));
        }
        let (slope_ms, intercept_ms) = fit(&points);
        out.push(Series { parameter: parameter.into(), pass: pass.into(), points, slope_ms, intercept_ms });
    }
    Ok(out)
}

/// The scaling table: each series' points and its fitted cost per unit.
pub fn scaling_table(series: &[Series]) -> String {
    let mut out = String::new();
    for s in series {
        let pts: Vec<String> = s.points.iter().map(|(x, y)| format!("{x:.3}→{y:.2}")).collect();
        let _ = writeln!(
            out,
            "{:<30} {:<9} {:>9.2} ms per unit (+{:.2} ms)   [{}]",
            s.parameter,
            s.pass,
            s.slope_ms,
            s.intercept_ms,
            pts.join(", ")
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_nearest_rank() {
        let s = stats("x", (1..=21).rev().map(|v| v as f64).collect());
        assert_eq!((s.p5_ms, s.median_ms, s.p95_ms), (2.0, 11.0, 20.0));
    }

    #[test]
    fn fit_recovers_a_line() {
        let (slope, intercept) = fit(&[(1.0, 5.0), (2.0, 7.0), (4.0, 11.0)]);
        assert!((slope - 2.0).abs() < 1e-12 && (intercept - 3.0).abs() < 1e-12);
    }

    #[test]
    fn paper_configs_carry_the_papers_settings() {
        let c = configs();
        let high = c.iter().find(|c| c.name == "paper-1440-high").unwrap();
        assert_eq!((high.width, high.height, high.caustic_grid, high.godray_grid), (1440, 850, 400, 200));
        // 0.32 × 1440×850 is the paper's 460×272 godray target (to the pixel, rounded).
        assert_eq!(((1440.0 * 0.32f32).round(), (850.0 * 0.32f32).round()), (461.0, 272.0));
        assert!(!c.iter().find(|c| c.name == "paper-1m-photons").unwrap().filter);
        // The paper's configurations use the paper's estimator whatever the scene ships.
        assert!(c
            .iter()
            .filter(|c| c.name.starts_with("paper"))
            .all(|c| c.caustic_estimator == CausticEstimator::Paper));
    }
}
