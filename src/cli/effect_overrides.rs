//! The scene's effect settings that `render` and `view` take from the command line in place
//! of the scene file's, checked against the same ranges as the file's fields.

use super::{caustic_estimator, godray_method, photon_spread};
use anyhow::{Context as _, Result};
use underlight::scene::{CausticEstimator, GodrayMethod, PhotonSpread, Scene};

#[derive(clap::Args)]
pub(super) struct EffectOverrides {
    /// Turn photons into irradiance with this estimator instead of the scene's: paper
    /// (distance-sized points), footprint (footprint-sized points) or triangles (warped-cell
    /// triangles).
    #[arg(long, value_name = "NAME", value_parser = caustic_estimator)]
    caustic_estimator: Option<CausticEstimator>,
    /// Spread the caustic photons this way instead of the scene's: even (the paper's grid) or
    /// view (as many per receiver area as the pixels that see it).
    #[arg(long, value_name = "NAME", value_parser = photon_spread)]
    caustic_photon_density: Option<PhotonSpread>,
    /// Spread the godray beams this way instead of the scene's: even or view (in proportion to
    /// the view rays' length through the water above where they enter).
    #[arg(long, value_name = "NAME", value_parser = photon_spread)]
    godray_photon_density: Option<PhotonSpread>,
    /// Draw the godrays this way instead of the scene's: beams (the paper's lines), footprint
    /// (beams as wide as their cross-sections) or marched (a ray march, directional lights).
    #[arg(long, value_name = "NAME", value_parser = godray_method)]
    godray_method: Option<GodrayMethod>,
    /// Cast the caustic photons on this coarse grid (cells per axis) instead of the scene's
    /// `effects.caustic_grid`: the photons are its square times the subdivision's, so the
    /// caustic's accuracy and its pass's cost follow it (docs/accuracy.md).
    #[arg(long, value_name = "N")]
    caustic_grid: Option<u32>,
    /// Subdivide each coarse cell into this many photons per axis in the geometry shader
    /// instead of the scene's `effects.caustic_subdivision`.
    #[arg(long, value_name = "N")]
    caustic_subdivision: Option<u32>,
}

impl EffectOverrides {
    /// Puts the given settings into the scene's effects.
    pub(super) fn apply(&self, scene: &mut Scene) {
        let e = &mut scene.effects;
        if let Some(estimator) = self.caustic_estimator {
            e.caustic_estimator = estimator;
        }
        if let Some(density) = self.caustic_photon_density {
            e.caustic_photon_density = density;
        }
        if let Some(density) = self.godray_photon_density {
            e.godray_photon_density = density;
        }
        if let Some(method) = self.godray_method {
            e.godray_method = method;
        }
        if let Some(grid) = self.caustic_grid {
            e.caustic_grid = grid;
        }
        if let Some(subdivision) = self.caustic_subdivision {
            e.caustic_subdivision = subdivision;
        }
    }
}

/// Checks a scene whose settings the command line changed as a scene file's fields are (the
/// ranges live there), before a device is opened: a bad value, or one that does not fit the
/// scene's other settings (a subdivision past the estimator's geometry shader), is a named
/// error and not a failed frame.
pub(super) fn check(scene: &Scene) -> Result<()> {
    scene.validate().context("the scene with the command line's settings")?;
    Ok(())
}
