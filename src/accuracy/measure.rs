//! Running a sweep: each setting's GPU time and its buffers against the reference's, as
//! error figures (relative RMSE, flux error, FLIP of the composed image, frame change).

use super::configs::SweepSpec;
use super::reference_cache::cached_reference;
use super::report::mark_pareto;
use crate::frame::uniforms::{FrameExtents, FrameUniforms};
use crate::frame::FrameOptions;
use crate::headless::{median_timings, SceneRenderer};
use crate::image_io::HdrImage;
use crate::metrics::{
    buffer_error, compose_srgb8, flip, frame_change, gap_fraction, lit_holes, upsampled, BufferError,
};
use crate::passes::PassId;
use crate::vk::device::Device;
use crate::vk::vk;
use anyhow::Result;
use std::sync::Arc;

/// One setting's figures.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SweepRow {
    /// The scene's name (a viewer looking up its settings' error matches on it).
    pub scene: String,
    pub caustic_grid: u32,
    pub caustic_subdivision: u32,
    pub caustic_photons: u64,
    pub iterations: u32,
    pub caustic_target: [u32; 2],
    /// The scene setting that gave that size (`effects.caustic_target_scale`).
    pub caustic_target_scale: f32,
    /// The godray target's size and the scene setting that gave it
    /// (`effects.godray_target_scale`); sweeps from before they were recorded read as zero.
    #[serde(default)]
    pub godray_target: [u32; 2],
    #[serde(default)]
    pub godray_target_scale: f32,
    pub point_size_max: f32,
    pub line_width: f32,
    pub filter: bool,
    /// `CausticEstimator::name`.
    pub estimator: String,
    /// `PhotonSpread::name`. Sweeps written before it existed read as the even grid.
    #[serde(default = "default_photon_density")]
    pub photon_density: String,
    /// The godray beams' `PhotonSpread::name`; the even grid for sweeps from before.
    #[serde(default = "default_photon_density")]
    pub godray_photon_density: String,
    /// `GodrayMethod::name`. Sweeps written before the method existed read as the beams.
    #[serde(default = "default_godray_method")]
    pub godray_method: String,
    /// `effects.caustic_refinement`; off in sweeps from before it existed.
    #[serde(default)]
    pub caustic_refinement: bool,
    /// Median GPU ms of the passes the settings change: shadow, caustics, godrays, filter.
    pub effect_ms: f64,
    /// Median GPU ms of the whole frame (all passes).
    pub frame_ms: f64,
    pub caustics: Option<BufferError>,
    /// The reference caustic buffer's own relative RMSE, from its two halves
    /// (`ReferenceImages::caustics_half`): `caustics` reads about √(error² + this²), so this
    /// must stay well below it. None in sweeps from before it was measured.
    #[serde(default)]
    pub caustic_reference_own_error: Option<f64>,
    /// The caustic buffer upsampled to the output as compose reads it, against a reference
    /// traced at the output's size: the error of the light the image shows, comparable
    /// between caustic target sizes (`caustics` is taken at each row's own target size).
    /// Sweeps written before it existed have none.
    #[serde(default)]
    pub caustics_at_output: Option<BufferError>,
    /// Holes in the caustic buffer compose reads: the share of the pixels the reference lights
    /// (with all their neighbours) that it leaves at exactly zero (`metrics::lit_holes`), at
    /// the caustic target's size. Issue 16's gap target, without a shadow's border. None in
    /// sweeps from before it was measured.
    #[serde(default)]
    pub caustic_holes: Option<f64>,
    /// The gap fraction (`metrics::gap_fraction`) of that buffer and of the reference's: the
    /// issue's own definition, which counts the dark band beside every hard shadow, so the
    /// reference's figure is the one to hold it against.
    #[serde(default)]
    pub caustic_gaps: Option<[f64; 2]>,
    pub godrays: Option<BufferError>,
    /// The godray buffer upsampled to the output against a reference traced there, as
    /// `caustics_at_output`: comparable between godray target sizes. None in older sweeps.
    #[serde(default)]
    pub godrays_at_output: Option<BufferError>,
    /// Mean FLIP of the final image composed with the GPU's buffers against the one composed
    /// with the reference's.
    pub flip: f64,
    /// Frame-to-frame change of the caustic buffer over one time step: GPU and reference.
    pub caustic_change_gpu: f64,
    pub caustic_change_reference: f64,
    /// On the Pareto front of `report::ranked_error` (the caustic error at the output)
    /// against effect_ms.
    pub pareto: bool,
}

/// The photon density of a row read without one: sweeps from before it was an axis spread
/// their photons evenly.
fn default_photon_density() -> String {
    crate::scene::PhotonSpread::Even.name().to_string()
}

/// The godray method of a row read without one: sweeps from before the method was an axis
/// measured the beams.
fn default_godray_method() -> String {
    crate::scene::GodrayMethod::Beams.name().to_string()
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
            "setting {}/{}: {} estimator{}, {} photons, {} godrays ({} beams), grid {}² × {}², {} iterations, target ×{}, godray target ×{}, points ≤ {} px, lines {} px, filter {}",
            k + 1,
            scenes.len(),
            e.caustic_estimator.name(),
            if e.caustic_refinement { " refined" } else { "" },
            e.caustic_photon_density.name(),
            e.godray_method.name(),
            e.godray_photon_density.name(),
            e.caustic_grid,
            e.caustic_subdivision,
            e.iterations,
            e.caustic_target_scale,
            e.godray_target_scale,
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
        // At the output's size: the same buffer where the target is the output's, else the
        // buffer upsampled against a reference traced there (cached like the other, and
        // traced once for both buffers).
        let at_output = FrameExtents { caustic: extents.output, godray: extents.output, ..extents };
        let mut reference_at_output = None;
        let mut at_output_error = |gpu: Option<&HdrImage>, own: &Option<HdrImage>, size: [u32; 2], godrays: bool| {
            let Some(g) = gpu else { return Ok(None) };
            if size == extents.output {
                return error(Some(g), own);
            }
            if reference_at_output.is_none() {
                reference_at_output =
                    Some(cached_reference(scene, spec.time, &at_output, &spec.reference, &spec.cache_dir)?);
            }
            let r = reference_at_output.as_ref().expect("traced above");
            let [w, h] = extents.output;
            error(Some(&upsampled(g, w, h)), if godrays { &r.godrays } else { &r.caustics })
        };
        let caustics_at_output = at_output_error(gpu_c, &reference.caustics, extents.caustic, false)?;
        let godrays_at_output = at_output_error(gpu_g, &reference.godrays, extents.godray, true)?;
        let (caustic_holes, caustic_gaps) = match (gpu_c, &reference.caustics) {
            (Some(g), Some(r)) => (Some(lit_holes(g, r)?), Some([gap_fraction(g), gap_fraction(r)])),
            _ => (None, None),
        };
        let change = |a: Option<&HdrImage>, b: Option<&HdrImage>| match (a, b) {
            (Some(a), Some(b)) => frame_change(a, b),
            _ => Ok(0.0),
        };
        rows.push(SweepRow {
            scene: scene.name.clone(),
            caustic_grid: e.caustic_grid,
            caustic_subdivision: e.caustic_subdivision,
            caustic_photons: ((e.caustic_grid * e.caustic_subdivision) as u64).pow(2),
            iterations: e.iterations,
            caustic_target: extents.caustic,
            caustic_target_scale: e.caustic_target_scale,
            godray_target: extents.godray,
            godray_target_scale: e.godray_target_scale,
            point_size_max: e.point_size_max,
            line_width: e.line_width,
            filter: e.filter,
            estimator: e.caustic_estimator.name().to_string(),
            photon_density: e.caustic_photon_density.name().to_string(),
            godray_photon_density: e.godray_photon_density.name().to_string(),
            godray_method: e.godray_method.name().to_string(),
            caustic_refinement: e.caustic_refinement,
            effect_ms,
            frame_ms,
            caustics: error(gpu_c, &reference.caustics)?,
            caustic_reference_own_error: match (&reference.caustics_half, &reference.caustics) {
                (Some(half), Some(all)) => Some(buffer_error(half, all)?.relative_rmse),
                _ => None,
            },
            caustics_at_output,
            caustic_holes,
            caustic_gaps,
            godrays: error(gpu_g, &reference.godrays)?,
            godrays_at_output,
            flip,
            caustic_change_gpu: change(gpu_c, shown(&next.caustics_filtered, &next.caustics))?,
            caustic_change_reference: change(reference.caustics.as_ref(), reference_next.caustics.as_ref())?,
            pareto: false,
        });
    }
    mark_pareto(&mut rows);
    warn_of_a_noisy_reference(&rows);
    Ok(rows)
}

/// A reference whose own error is over a third of a figure it measures makes that figure
/// read more than 5 % high (√(1 + 1/9)); says so once, with what the figure would read
/// against an exact reference (√(figure² − own²)), and what to do, on stderr.
fn warn_of_a_noisy_reference(rows: &[SweepRow]) {
    for r in rows {
        let (Some(own), Some(e)) = (r.caustic_reference_own_error, r.caustics) else { continue };
        let figure = e.relative_rmse;
        if own > figure / 3.0 {
            let exact = (figure * figure - own * own).max(0.0).sqrt();
            eprintln!(
                "warning: {}: the reference's own caustic error ({own:.3}, from its two halves) is over a third of the \
                 figure it measures ({figure:.3}, about {exact:.3} against an exact reference): trace more reference \
                 photons (--photons)",
                r.scene
            );
            return;
        }
    }
}
