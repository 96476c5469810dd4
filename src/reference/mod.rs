//! A CPU reference renderer: for the same scene, time and target sizes as a GPU frame, the
//! exact values its caustic and godray buffers approximate (docs/units.md), so the GPU
//! method's error can be measured.
//!
//! Exact where the GPU approximates: photons over the whole water extent (no light frustum),
//! rays against the real triangles (a BVH, not the light's image-space iteration), the real
//! animated surface (f64 root finding on the twin's heights, not a fixed march), Fresnel and
//! refraction in f64, no splat blur and no clamps (`cos θ_v ≥ 0.2`, `sin θ ≥ 0.1`).
//!
//! What the buffers mean, per pixel of the GPU's targets (straight, unrefracted camera rays
//! through the pixel centres, as the GPU rasterises them):
//!
//! - caustics: the irradiance on the receivers under the water that the pixel sees,
//!   averaged over the pixel's solid angle (W/m²); see `caustics`;
//! - godrays: the single-scattered radiance along the pixel-centre ray (W/(m²·sr)); see
//!   `godrays`.
//!
//! The camera sees the water surface as the GPU's depth buffer does: a view ray ends where it
//! crosses the surface inside the water's extent (no refraction of the view), at its first
//! triangle, or at the far plane.

mod camera;
mod caustics;
mod godrays;
mod light;
mod water;

use crate::bvh::Bvh;
use crate::error::{Error, Result};
use crate::frame::uniforms::FrameExtents;
use crate::frame::FramePlan;
use crate::image_io::HdrImage;
use crate::passes::PassId;
use crate::scene::Scene;
use crate::shader_math::NoiseTexture;
use camera::PixelCamera;
use glam::DVec3;
use light::LightSampler;
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use water::Surface;

/// The most worker threads a reference takes. Each holds its own float buffer of the
/// effect target (32 bytes a pixel: 39 MB at 1440×850), and the work is all arithmetic, so
/// threads past the cores buy nothing but memory: 100 000 asked for at 1440×850 would hold
/// 3.9 TB.
pub const MAX_THREADS: usize = 256;

#[derive(Clone, Copy, Debug)]
pub struct ReferenceSettings {
    /// Caustic photons to trace over the whole water surface.
    pub caustic_photons: u64,
    /// Godray beams to trace.
    pub godray_beams: u64,
    /// Worker threads (std::thread::scope; 0 = available_parallelism), at most
    /// `MAX_THREADS`.
    pub threads: usize,
    pub seed: u64,
}

#[derive(Clone, Debug)]
pub struct ReferenceImages {
    /// Irradiance on the receiver seen through each caustic-target pixel, W/m² (rgb per channel of gamma; a = photons that landed in the pixel), size extents.caustic. None when the scene's plan has no caustics.
    pub caustics: Option<HdrImage>,
    /// The same estimate from half of the photons, a set independent of the other half
    /// (a: its photons that landed). `caustics` is the mean of the two halves, so
    /// `caustics − caustics_half` is half their difference, which has the variance of
    /// `caustics`' own noise: `metrics::buffer_error(half, caustics)` is the reference's own
    /// relative error, for no extra photons. A figure measured against the reference reads
    /// about √(error² + own²), so the own error must stay well below the errors it measures
    /// (`sweep` warns where it does not).
    pub caustics_half: Option<HdrImage>,
    /// In-scattered radiance along each godray-target pixel's view ray, W/(m²·sr), size extents.godray. None when no godrays.
    /// (a = beams that contributed to the pixel.)
    pub godrays: Option<HdrImage>,
}

/// `progress` is called from worker threads with the fraction done in [0, 1].
pub fn render(
    scene: &Scene,
    time: f32,
    extents: &FrameExtents,
    settings: &ReferenceSettings,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<ReferenceImages> {
    // As the GPU's frame does (`Frame::new`): a scene built in code meets a scene file's ranges.
    scene.validate()?;
    let plan = FramePlan::for_scene(scene);
    let (want_caustics, want_godrays) = (plan.runs(PassId::Caustics), plan.runs(PassId::Godrays));
    validate(time, extents, settings, want_caustics, want_godrays)?;
    if !want_caustics && !want_godrays {
        progress(1.0);
        return Ok(ReferenceImages { caustics: None, caustics_half: None, godrays: None });
    }
    let noise = NoiseTexture::generate();
    let ctx = Context::new(scene, &noise, time, extents)?;
    let threads = match settings.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    };
    let caustic_work = if want_caustics { settings.caustic_photons } else { 0 };
    let godray_work = if want_godrays { settings.godray_beams } else { 0 };
    let progress =
        Progress { done: AtomicU64::new(0), total: caustic_work.saturating_add(godray_work).max(1), report: progress };
    let blank = |size: [u32; 2]| HdrImage {
        width: size[0],
        height: size[1],
        pixels: vec![[0.0; 4]; (size[0] * size[1]) as usize],
    };
    let (caustics, caustics_half) = match (want_caustics, &ctx.sampler) {
        (false, _) => (None, None),
        (true, Some(sampler)) => {
            let (all, half) = caustics::render(&ctx, sampler, settings, threads, &progress);
            (Some(all), Some(half))
        }
        (true, None) => (Some(blank(extents.caustic)), Some(blank(extents.caustic))),
    };
    let godrays = want_godrays.then(|| match &ctx.sampler {
        Some(sampler) => godrays::render(&ctx, sampler, settings, threads, &progress),
        None => blank(extents.godray),
    });
    (progress.report)(1.0);
    Ok(ReferenceImages { caustics, caustics_half, godrays })
}

fn validate(
    time: f32,
    extents: &FrameExtents,
    settings: &ReferenceSettings,
    caustics: bool,
    godrays: bool,
) -> Result<()> {
    let invalid = |name, message: String| Err(Error::InvalidParameter { name, message });
    if !time.is_finite() {
        return invalid("time", format!("must be finite, got {time}"));
    }
    if settings.threads > MAX_THREADS {
        return invalid("threads", format!("{} is more than {MAX_THREADS} (0: one per core)", settings.threads));
    }
    if caustics && settings.caustic_photons == 0 {
        return invalid(
            "caustic_photons",
            "the scene has caustics: the reference needs at least one caustic photon".into(),
        );
    }
    if godrays && settings.godray_beams == 0 {
        return invalid("godray_beams", "the scene has godrays: the reference needs at least one godray beam".into());
    }
    for (name, size, used) in [
        ("extents.caustic", extents.caustic, caustics),
        ("extents.godray", extents.godray, godrays),
        ("extents.output", extents.output, true),
    ] {
        if used && (size[0] == 0 || size[1] == 0) {
            return invalid(name, format!("target size {}×{} has no pixels", size[0], size[1]));
        }
    }
    Ok(())
}

/// What both estimators share: the surface, the triangles, the camera and the light.
struct Context<'a> {
    scene: &'a Scene,
    surface: Surface<'a>,
    bvh: Bvh,
    camera: PixelCamera,
    /// None: no light enters the water.
    sampler: Option<LightSampler>,
    /// Box holding the scene, the water's slab and the camera: a beam that meets no triangle
    /// ends where it leaves it.
    box_lo: DVec3,
    box_hi: DVec3,
    /// Attenuation γ per RGB channel, 1/m.
    gamma: DVec3,
    extents: FrameExtents,
}

impl<'a> Context<'a> {
    fn new(scene: &'a Scene, noise: &'a NoiseTexture, time: f32, extents: &FrameExtents) -> Result<Self> {
        let surface = Surface::new(&scene.water, noise, time);
        let bvh = Bvh::of_scene(scene);
        let sampler = LightSampler::new(scene, surface.level, surface.bound)?;
        let camera = PixelCamera::new(scene, extents, time);
        let (lo, hi) = scene.bounds();
        let w = &scene.water;
        let slab_lo = DVec3::new(w.extent_min.x as f64, surface.level - surface.bound, w.extent_min.y as f64);
        let slab_hi = DVec3::new(w.extent_max.x as f64, surface.level + surface.bound, w.extent_max.y as f64);
        let box_lo = lo.as_dvec3().min(slab_lo).min(camera.position) - 1.0;
        let box_hi = hi.as_dvec3().max(slab_hi).max(camera.position) + 1.0;
        Ok(Self {
            scene,
            surface,
            bvh,
            camera,
            sampler,
            box_lo,
            box_hi,
            gamma: scene.medium.gamma.as_dvec3(),
            extents: *extents,
        })
    }

    /// Distance from `o` (inside the box) along unit `d` to where the ray leaves the box.
    pub fn box_exit(&self, o: DVec3, d: DVec3) -> f64 {
        let mut t = f64::INFINITY;
        for k in 0..3 {
            if d[k] != 0.0 {
                let bound = if d[k] > 0.0 { self.box_hi[k] } else { self.box_lo[k] };
                t = t.min(((bound - o[k]) / d[k]).max(0.0));
            }
        }
        t
    }

    /// The first distance in [t0, t1] at which the camera ray `o + t·d` meets the water
    /// surface inside the water's extent (where the GPU draws it, into its depth buffer).
    /// Crossings outside the extent are not the surface, only the medium's boundary.
    pub fn view_surface_hit(&self, o: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<f64> {
        let s = &self.surface;
        let mut from_above = s.above(o + t0 * d) > 0.0;
        let mut t = t0;
        loop {
            let c = s.crossing(o, d, t, t1, from_above)?;
            let p = o + c * d;
            if s.covers(p.x, p.z) {
                return Some(c);
            }
            from_above = !from_above;
            t = c + 1e-7;
        }
    }
}

/// Progress over both buffers' work, in photons and beams.
struct Progress<'a> {
    done: AtomicU64,
    total: u64,
    report: &'a (dyn Fn(f64) + Sync),
}

impl Progress<'_> {
    pub fn add(&self, work: u64) {
        let done = self.done.fetch_add(work, Ordering::Relaxed) + work;
        (self.report)((done as f64 / self.total as f64).min(1.0));
    }
}

/// Runs `work(state, item)` for items 0..items on `threads` scoped threads, each with its own
/// `init()` state (per-thread f64 buffers), handing items out one at a time; returns the
/// states.
fn parallel<T: Send>(
    threads: usize,
    items: u64,
    init: impl Fn() -> T + Sync,
    work: impl Fn(&mut T, u64) + Sync,
) -> Vec<T> {
    let next = AtomicUsize::new(0);
    let threads = threads.clamp(1, items.max(1) as usize);
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut state = init();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed) as u64;
                        if i >= items {
                            break state;
                        }
                        work(&mut state, i);
                    }
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().expect("a reference worker panicked")).collect()
    })
}

/// Sums per-thread f64 RGBA buffers into an image.
fn sum_buffers(size: [u32; 2], buffers: Vec<Vec<[f64; 4]>>) -> HdrImage {
    let n = (size[0] * size[1]) as usize;
    let mut total = vec![[0.0f64; 4]; n];
    for b in buffers {
        for (t, v) in total.iter_mut().zip(b) {
            for c in 0..4 {
                t[c] += v[c];
            }
        }
    }
    HdrImage { width: size[0], height: size[1], pixels: total.into_iter().map(|p| p.map(|v| v as f32)).collect() }
}

/// Traces every sample of `strata` (jitter stream `stream`) on `threads` threads, in work
/// items of about `per_item` samples, and hands each path that enters the water to `each`
/// with the sample's index and the thread's own state (`init()`); returns the states. Both
/// estimators draw their photons or beams through this.
#[allow(clippy::too_many_arguments)]
fn trace_strata<T: Send>(
    ctx: &Context,
    sampler: &light::LightSampler,
    strata: &light::Strata,
    seed: u64,
    stream: u64,
    per_item: f64,
    threads: usize,
    progress: &Progress,
    init: impl Fn() -> T + Sync,
    each: impl Fn(&mut T, &light::LightPath, u64) + Sync,
) -> Vec<T> {
    let chunks = row_chunks(strata.rows, strata.n as f64 / strata.rows as f64, per_item);
    parallel(threads, chunks.len() as u64, init, |state, item| {
        let (j0, j1) = chunks[item as usize];
        let mut traced = 0;
        for j in j0..j1 {
            let (first, count) = strata.row(j);
            for i in 0..count {
                let (xz, area) = strata.sample(j, i, count, light::jitter(seed, stream, first + i));
                if let Some(path) = light::trace(ctx, sampler, xz, area) {
                    each(state, &path, first + i);
                }
            }
            traced += count;
        }
        progress.add(traced);
    })
}

/// Groups the strata's rows into work items of about `per_item` samples: (first row, end row).
fn row_chunks(rows: u64, per_row: f64, per_item: f64) -> Vec<(u64, u64)> {
    let step = ((per_item / per_row.max(1.0)).floor() as u64).max(1);
    (0..rows).step_by(step as usize).map(|j| (j, (j + step).min(rows))).collect()
}
