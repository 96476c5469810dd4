//! What a sweep runs: the axes of settings it varies (every combination is one setting),
//! checked against the scene file's limits, and the sweep's scene, output, times and
//! reference settings.

use crate::reference::ReferenceSettings;
use crate::scene::{CausticEstimator, GodrayMethod, LightKind, PhotonSpread, Scene};
use anyhow::{bail, Result};
use std::path::PathBuf;

/// The settings a sweep varies; every combination is one row. Empty: the scene's value.
#[derive(Clone, Debug, Default)]
pub struct SweepAxes {
    pub grid: Vec<u32>,
    pub subdivision: Vec<u32>,
    pub iterations: Vec<u32>,
    pub target_scale: Vec<f32>,
    /// `effects.godray_target_scale`.
    pub godray_target_scale: Vec<f32>,
    pub point_size: Vec<f32>,
    pub line_width: Vec<f32>,
    pub filter: Vec<bool>,
    pub estimator: Vec<CausticEstimator>,
    pub photon_density: Vec<PhotonSpread>,
    pub godray_photon_density: Vec<PhotonSpread>,
    pub godray_method: Vec<GodrayMethod>,
    /// `effects.caustic_refinement` (the triangles' refinement at receivers' borders).
    pub refinement: Vec<bool>,
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
        let floats: [(&str, &Vec<f32>, f32, f32); 4] = [
            ("--target", &self.target_scale, 0.0, 4.0),
            ("--godray-target", &self.godray_target_scale, 0.0, 4.0),
            ("--point-size", &self.point_size, 0.0, f32::INFINITY),
            ("--line-width", &self.line_width, 0.0, f32::INFINITY),
        ];
        for (name, values, lo, hi) in floats {
            // As in a scene file, NaN and ±inf fail every range (docs/limits.md).
            if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v > lo && **v <= hi)) {
                if hi.is_finite() {
                    bail!("{name} {v} is out of range: must be > {lo} and ≤ {hi}");
                }
                bail!("{name} {v} is out of range: must be positive and finite");
            }
        }
        Ok(())
    }

    /// The axes against the scene they vary, checked before any GPU work: the marched
    /// godrays need a directional light (as in a scene file, `effects.godray_method`).
    pub fn validate_for(&self, scene: &Scene) -> Result<()> {
        if self.godray_method.contains(&GodrayMethod::Marched) && scene.light.kind == LightKind::Point {
            bail!(
                "--godray-method marched needs a directional light, and scene {:?} has a point light: sweep beams only",
                scene.name
            );
        }
        let footprint_max = GodrayMethod::Footprint.max_subdivision();
        if self.godray_method.contains(&GodrayMethod::Footprint) && scene.effects.godray_subdivision > footprint_max {
            bail!(
                "--godray-method footprint draws at most {footprint_max}² beams per cell, and scene {:?} has godray_subdivision = {}",
                scene.name,
                scene.effects.godray_subdivision
            );
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
        let godray_methods =
            if self.godray_method.is_empty() { vec![e.godray_method] } else { self.godray_method.clone() };
        let densities =
            if self.photon_density.is_empty() { vec![e.caustic_photon_density] } else { self.photon_density.clone() };
        let beam_densities = if self.godray_photon_density.is_empty() {
            vec![e.godray_photon_density]
        } else {
            self.godray_photon_density.clone()
        };
        let refinements = if self.refinement.is_empty() { vec![e.caustic_refinement] } else { self.refinement.clone() };
        // Filter, estimator, refinement, photon density, godray method and beam density, the
        // last varying fastest.
        type Switches = (bool, CausticEstimator, bool, PhotonSpread, GodrayMethod, PhotonSpread);
        let mut switches: Vec<Switches> = Vec::new();
        for &filter in &filters {
            for &estimator in &estimators {
                for &refine in &refinements {
                    for &density in &densities {
                        for &method in &godray_methods {
                            switches.extend(
                                beam_densities.iter().map(|&beams| (filter, estimator, refine, density, method, beams)),
                            );
                        }
                    }
                }
            }
        }
        let mut out = Vec::new();
        for &grid in &or(&self.grid, e.caustic_grid) {
            for &sub in &or(&self.subdivision, e.caustic_subdivision) {
                for &iterations in &or(&self.iterations, e.iterations) {
                    for &scale in &orf(&self.target_scale, e.caustic_target_scale) {
                        for &godray_scale in &orf(&self.godray_target_scale, e.godray_target_scale) {
                            for &size in &orf(&self.point_size, e.point_size_max) {
                                for &width in &orf(&self.line_width, e.line_width) {
                                    for &(filter, estimator, refine, density, godray_method, beams) in &switches {
                                        let mut s = base.clone();
                                        let fx = &mut s.effects;
                                        fx.caustic_grid = grid;
                                        fx.caustic_subdivision = sub;
                                        fx.iterations = iterations;
                                        fx.caustic_target_scale = scale;
                                        fx.godray_target_scale = godray_scale;
                                        fx.point_size_max = size;
                                        fx.point_size_min = fx.point_size_min.min(size);
                                        fx.line_width = width;
                                        fx.filter = filter;
                                        fx.caustic_estimator = estimator;
                                        fx.caustic_photon_density = density;
                                        fx.godray_photon_density = beams;
                                        fx.godray_method = godray_method;
                                        fx.caustic_refinement = refine;
                                        // Refinement is the triangles' (a scene file refuses it
                                        // for the paper's points).
                                        if refine && estimator != CausticEstimator::Triangles {
                                            continue;
                                        }
                                        // The estimator's subdivision bounds (the triangles'
                                        // geometry shader's output limit, the footprint
                                        // points' neighbours) skip the others.
                                        if sub > estimator.max_subdivision() || sub < estimator.min_subdivision() {
                                            continue;
                                        }
                                        // The marched godrays need a directional light: a point
                                        // light's scene skips them (`validate_for` refuses them).
                                        if godray_method == GodrayMethod::Marched && s.light.kind == LightKind::Point {
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
        }
        out
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::LightKind;

    #[test]
    fn the_godray_method_is_an_axis_and_marched_needs_a_directional_light() {
        let tank = crate::scene::load("tank").unwrap();
        let axes = SweepAxes {
            subdivision: vec![2, 4],
            estimator: vec![CausticEstimator::Paper, CausticEstimator::Triangles],
            godray_method: vec![GodrayMethod::Beams, GodrayMethod::Marched],
            ..Default::default()
        };
        axes.validate_for(&tank).unwrap();
        let methods = |scenes: &[Scene]| scenes.iter().map(|s| s.effects.godray_method).collect::<Vec<_>>();
        // Subdivision 2: both estimators, each with both methods; 4: the paper's points only.
        let scenes = axes.scenes(&tank);
        assert_eq!(methods(&scenes), [GodrayMethod::Beams, GodrayMethod::Marched].repeat(3));
        // Empty: the scene's own method.
        let own = SweepAxes { godray_method: vec![], ..axes.clone() }.scenes(&tank);
        assert!(own.iter().all(|s| s.effects.godray_method == tank.effects.godray_method), "{:?}", methods(&own));
        assert_eq!(own.len(), 3);
        // A point light: asking for the march is refused, and the combinations skip it.
        let mut point = tank.clone();
        point.light.kind = LightKind::Point;
        let refused = axes.validate_for(&point).unwrap_err().to_string();
        assert!(refused.contains("--godray-method marched needs a directional light"), "{refused}");
        assert_eq!(methods(&axes.scenes(&point)), [GodrayMethod::Beams; 3]);
        SweepAxes { godray_method: vec![GodrayMethod::Beams], ..axes }.validate_for(&point).unwrap();
    }

    #[test]
    fn float_axes_refuse_what_a_scene_file_refuses() {
        let refused = |axes: SweepAxes| axes.validate().unwrap_err().to_string();
        let with_point = |v: f32| SweepAxes { point_size: vec![2.0, v], ..Default::default() };
        // A scene file refuses NaN and ±inf in every field; the sweep's axes set the same fields.
        assert!(refused(with_point(f32::INFINITY))
            .contains("--point-size inf is out of range: must be positive and finite"));
        assert!(refused(with_point(f32::NAN)).contains("--point-size NaN"));
        assert!(refused(with_point(0.0)).contains("--point-size 0"));
        let line = SweepAxes { line_width: vec![f32::INFINITY], ..Default::default() };
        assert!(refused(line).contains("--line-width inf"));
        let target = SweepAxes { target_scale: vec![5.0], ..Default::default() };
        assert!(refused(target).contains("--target 5 is out of range: must be > 0 and ≤ 4"));
        with_point(1e6).validate().unwrap();
    }

    #[test]
    fn refinement_is_an_axis_of_the_triangles_only() {
        let tank = crate::scene::load("tank").unwrap();
        let axes = SweepAxes {
            estimator: vec![CausticEstimator::Paper, CausticEstimator::Triangles],
            refinement: vec![false, true],
            ..Default::default()
        };
        let settings: Vec<(CausticEstimator, bool)> =
            axes.scenes(&tank).iter().map(|s| (s.effects.caustic_estimator, s.effects.caustic_refinement)).collect();
        // The paper's points have no mesh to refine: their refined row is skipped.
        assert_eq!(
            settings,
            [
                (CausticEstimator::Paper, false),
                (CausticEstimator::Triangles, false),
                (CausticEstimator::Triangles, true)
            ]
        );
        // Empty: the scene's own, on or off (the triangles', which the scenes shipped until
        // the footprint points).
        let mut triangles = tank.clone();
        triangles.effects.caustic_estimator = CausticEstimator::Triangles;
        let mut refined = triangles.clone();
        refined.effects.caustic_refinement = true;
        for scene in [&triangles, &refined] {
            let own = SweepAxes::default().scenes(scene);
            assert_eq!(own.len(), 1);
            assert_eq!(own[0].effects.caustic_refinement, scene.effects.caustic_refinement);
        }
    }

    #[test]
    fn godray_targets_and_footprint_beams_are_checked_before_any_gpu_work() {
        let tank = crate::scene::load("tank").unwrap();
        let axes = SweepAxes {
            godray_target_scale: vec![0.16, 1.0],
            godray_method: vec![GodrayMethod::Beams, GodrayMethod::Footprint],
            ..Default::default()
        };
        axes.validate().unwrap();
        axes.validate_for(&tank).unwrap();
        let scales: Vec<(GodrayMethod, f32)> =
            axes.scenes(&tank).iter().map(|s| (s.effects.godray_method, s.effects.godray_target_scale)).collect();
        assert_eq!(
            scales,
            [
                (GodrayMethod::Beams, 0.16),
                (GodrayMethod::Footprint, 0.16),
                (GodrayMethod::Beams, 1.0),
                (GodrayMethod::Footprint, 1.0)
            ]
        );
        let zero = SweepAxes { godray_target_scale: vec![0.0], ..Default::default() }.validate().unwrap_err();
        assert!(zero.to_string().contains("--godray-target 0 is out of range"), "{zero}");
        let mut fine = tank.clone();
        fine.effects.godray_subdivision = 5;
        let refused = axes.validate_for(&fine).unwrap_err().to_string();
        assert!(refused.contains("--godray-method footprint draws at most 4²"), "{refused}");
    }
}
