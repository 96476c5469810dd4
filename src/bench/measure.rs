//! Running a configuration's frames and summarising them: per-pass GPU times (median, 5th
//! and 95th percentile), the photon paths compared on the same frame (`--compare-paths`),
//! and the scaling series (`--scaling`) with their fitted cost per unit.

use super::configs::BenchConfig;
use crate::frame::FrameOptions;
use crate::frame::PassTimings;
use crate::headless::SceneRenderer;
use crate::image_io::HdrImage;
use crate::memory::{self, FrameMemory};
use crate::passes::PassId;
use crate::passes::PhotonPath;
use crate::scene::{CausticEstimator, Scene};
use crate::vk::device::Device;
use crate::vk::statistics::StageCounts;
use anyhow::{bail, Result};
use ash::vk;
use serde::Serialize;
use std::sync::Arc;

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
    /// The device memory of this configuration's frame: every target and buffer, and the peak.
    pub memory: FrameMemory,
    /// With `--pipeline-statistics`: each pass's work per shader stage in the last measured
    /// frame, in the frame's order (empty without, or on a device without the queries).
    pub stage_counts: Vec<PassCounts>,
}

/// One pass's work per shader stage (pipeline statistics).
#[derive(Clone, Debug, Serialize)]
pub struct PassCounts {
    pub pass: String,
    pub counts: StageCounts,
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
    statistics: bool,
) -> Result<BenchResult> {
    Ok(measure(device, scene, config, frames, warmup, path, false, statistics)?.0)
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
    statistics: bool,
) -> Result<Vec<BenchResult>> {
    let mut out: Vec<BenchResult> = Vec::new();
    let mut reference: Option<[Option<HdrImage>; 2]> = None;
    for path in PhotonPath::ALL {
        if path == PhotonPath::Compute && !device.has_float_atomics() {
            eprintln!("  {}: skipped, {} lacks shaderBufferFloat32AtomicAdd", path.name(), device.info.name);
            continue;
        }
        if path != PhotonPath::GeometryShader && config.caustic_estimator.geometry_shader_only() {
            eprintln!(
                "  {}: skipped, the {} estimator is the geometry shader's alone",
                path.name(),
                config.caustic_estimator.name()
            );
            continue;
        }
        if path != PhotonPath::GeometryShader && config.godray_method == crate::scene::GodrayMethod::Footprint {
            eprintln!("  {}: skipped, the footprint-sized beams are the geometry shader's alone", path.name());
            continue;
        }
        eprintln!("  {} path…", path.name());
        let (mut result, buffers) = measure(device, scene, config, frames, warmup, path, true, statistics)?;
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
#[allow(clippy::too_many_arguments)]
fn measure(
    device: &Arc<Device>,
    scene: &Scene,
    config: &BenchConfig,
    frames: u32,
    warmup: u32,
    path: PhotonPath,
    read_buffers: bool,
    statistics: bool,
) -> Result<(BenchResult, Option<[Option<HdrImage>; 2]>)> {
    if frames == 0 {
        bail!("--frames must be at least 1");
    }
    // The splat floor's first frame also records its splats: never measure it.
    let warmup = if path == PhotonPath::SplatFloor { warmup.max(1) } else { warmup };
    let s = config.apply(scene);
    let extent = vk::Extent2D { width: config.width, height: config.height };
    let options = FrameOptions { photon_path: path, pipeline_statistics: statistics, ..Default::default() };
    let before = memory::allocations(device);
    let mut renderer = SceneRenderer::with_options(device, &s, extent, options)?;
    let created = FrameMemory::since(device, &before, 0);
    let (timings, _) = renderer.render(warmup + frames, 0.0, 1.0 / 60.0, false)?;
    // The frame allocates nothing per frame, so this is the frame's memory; it is sampled
    // again after the read-back below in case a path allocates while rendering.
    let mut memory = FrameMemory::since(device, &before, created.peak_bytes);
    let measured: Vec<&PassTimings> = timings.iter().skip(warmup as usize).collect();
    let mut passes = Vec::new();
    for id in renderer.frame.plan.passes.iter().copied() {
        let v: Vec<f64> = measured.iter().filter_map(|t| t.get(id)).collect();
        if !v.is_empty() {
            passes.push(stats(id.name(), v));
        }
    }
    let totals = measured.iter().map(|t| t.total_ms()).collect();
    let stage_counts = measured
        .last()
        .map(|t| t.counted().map(|(id, counts)| PassCounts { pass: id.name().into(), counts }).collect())
        .unwrap_or_default();
    let n = |grid: u32, subdivision: u32| (grid as u64 * subdivision as u64).pow(2);
    let caustic_subdivision = config.caustic_subdivision.unwrap_or(config.subdivision);
    let buffers = if read_buffers {
        let (_, images) = renderer.render(1, 0.0, 0.0, true)?;
        memory = FrameMemory::since(device, &before, memory.peak_bytes);
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
        // The marched godrays cast no photons.
        godray_photons: if renderer.frame.plan.runs(PassId::Godrays) && config.godray_method.casts_beams() {
            n(config.godray_grid, config.subdivision)
        } else {
            0
        },
        passes,
        total: stats("total", totals),
        caustic_difference: None,
        godray_difference: None,
        memory,
        stage_counts,
    };
    Ok((result, buffers))
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

/// The caustic subdivisions `scaling` splits the same photons through, between the coarse
/// grid and the geometry shader: the balance between invocations and the work (and output)
/// of each. Within what each estimator's geometry shader takes (the triangles' at most 3,
/// caustics_triangles.geom; the footprint points at least 2, a neighbour in their cell), and
/// through what the scenes ship: the footprint points 3, where 6 cast the same photons at
/// 0.76-1.06x the cost on lavapipe (docs/performance.md, "The footprint points' coarse grid
/// against their subdivision").
pub fn subdivision_series(estimator: CausticEstimator) -> Vec<u32> {
    match estimator {
        CausticEstimator::Triangles => vec![1, 2, 3],
        CausticEstimator::Footprint => vec![2, 3, 4],
        CausticEstimator::Paper => vec![1, 2, 4, 8],
    }
}

/// Cost against the work: caustic photons, their split between the coarse grid and the
/// subdivision, godray photons, caustic target pixels, point size and line width, each varied
/// alone from paper-800 (or from `base`, scaled down for tests).
pub fn scaling(
    device: &Arc<Device>,
    scene: &Scene,
    base: &BenchConfig,
    frames: u32,
    warmup: u32,
) -> Result<Vec<Series>> {
    type Vary = fn(&mut BenchConfig, f64);
    type Measure = fn(&BenchConfig) -> f64;
    let subdivisions = subdivision_series(base.caustic_estimator).into_iter().map(f64::from).collect();
    // (name, pass, values, how each value changes the configuration, the work it measures)
    let sweeps: [(&str, &str, Vec<f64>, Vary, Measure); 6] = [
        (
            "caustic photons (millions)",
            "caustics",
            vec![0.5, 1.0, 1.5, 2.0],
            |c, f| c.caustic_grid = (c.caustic_grid as f64 * f).round() as u32,
            |c| (c.caustic_grid as f64 * c.caustic_subdivision.unwrap_or(c.subdivision) as f64).powi(2) / 1e6,
        ),
        (
            "caustic subdivision (photons held)",
            "caustics",
            subdivisions,
            |c, s| {
                let per_axis = c.caustic_grid * c.caustic_subdivision.unwrap_or(c.subdivision);
                c.caustic_subdivision = Some(s as u32);
                c.caustic_grid = (per_axis as f64 / s).round() as u32;
            },
            |c| c.caustic_subdivision.unwrap_or(c.subdivision) as f64,
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
            let r = run_config(device, scene, &c, frames, warmup, PhotonPath::GeometryShader, false)?;
            let ms = r.passes.iter().find(|p| p.pass == pass).map(|p| p.median_ms).unwrap_or(0.0);
            points.push((measure(&c), ms));
        }
        let (slope_ms, intercept_ms) = fit(&points);
        out.push(Series { parameter: parameter.into(), pass: pass.into(), points, slope_ms, intercept_ms });
    }
    Ok(out)
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
    fn subdivision_series_stay_within_each_geometry_shader_and_reach_what_the_scenes_ship() {
        for estimator in CausticEstimator::ALL {
            let series = subdivision_series(estimator);
            let bounds = estimator.min_subdivision()..=estimator.max_subdivision();
            assert!(series.iter().all(|s| bounds.contains(s)), "{estimator:?}: {series:?} outside {bounds:?}");
            assert!(series.windows(2).all(|w| w[0] < w[1]), "{estimator:?}: {series:?}");
        }
        for name in ["tank", "port", "storage"] {
            let effects = crate::scene::load(name).unwrap().effects;
            let series = subdivision_series(effects.caustic_estimator);
            assert!(
                series.contains(&effects.caustic_subdivision),
                "{name} ships {}: {series:?}",
                effects.caustic_subdivision
            );
        }
    }

    #[test]
    fn fit_recovers_a_line() {
        let (slope, intercept) = fit(&[(1.0, 5.0), (2.0, 7.0), (4.0, 11.0)]);
        assert!((slope - 2.0).abs() < 1e-12 && (intercept - 3.0).abs() < 1e-12);
    }
}
