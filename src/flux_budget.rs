//! Where the caustic photons' flux goes (`underlight render --flux-budget`): of the light's
//! power through the photon grid, how much lands on a receiver and how much each reason for
//! dropping a photon costs. Read from the photon records of the geometry shader's recording
//! pass (`FrameOptions::record_photons`, `glsl/caustics/caustics.geom`), so it is the GPU's own
//! account, not a model of it.

use std::fmt;

/// Why `cast_photon` (glsl/photons/photon_cast.glsl) dropped a photon: the `PHOTON_*` codes, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DropReason {
    MissesWater = 1,
    OutsideWater = 2,
    BlockedAbove = 3,
    BackOfWave = 4,
    TotalReflection = 5,
    LeavesMap = 6,
    NotConverged = 7,
    AboveWater = 8,
    NotFinite = 9,
}

impl DropReason {
    pub const ALL: [DropReason; 9] = [
        DropReason::MissesWater,
        DropReason::OutsideWater,
        DropReason::BlockedAbove,
        DropReason::BackOfWave,
        DropReason::TotalReflection,
        DropReason::LeavesMap,
        DropReason::NotConverged,
        DropReason::AboveWater,
        DropReason::NotFinite,
    ];

    /// What happened to the photon, as the budget prints it.
    pub fn describe(self) -> &'static str {
        match self {
            DropReason::MissesWater => "never meets the water surface",
            DropReason::OutsideWater => "meets it outside the water's extent",
            DropReason::BlockedAbove => "blocked before the water (a deck, a wall)",
            DropReason::BackOfWave => "meets the back of a steep wave",
            DropReason::TotalReflection => "totally reflected",
            DropReason::LeavesMap => "refracted past the light's receiver map",
            DropReason::NotConverged => "image-space iteration does not converge",
            DropReason::AboveWater => "lands above the water",
            DropReason::NotFinite => "NaN or infinity",
        }
    }

    fn from_code(code: f32) -> Option<Self> {
        Self::ALL.into_iter().find(|r| *r as i32 as f32 == code)
    }
}

/// Photon count and flux (W, the light's power into them before the water) of one class.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Share {
    pub photons: u64,
    pub watts: f64,
}

impl Share {
    fn add(&mut self, watts: f64) {
        self.photons += 1;
        self.watts += watts;
    }
}

/// A directional light's power through the photon grid, W: E⊥ × the map window's area ×
/// the share of it the grid covers (`photon_window_size`). None for a point light, whose
/// power through the grid depends on each photon's angle.
pub fn grid_power(u: &crate::frame::uniforms::FrameUniforms) -> Option<f64> {
    (u.light_is_point == 0.0).then(|| {
        u.light_strength as f64
            * 4.0
            * u.light_half_extent[0] as f64
            * u.light_half_extent[1] as f64
            * (u.photon_window_size[0] as f64 * u.photon_window_size[1] as f64)
    })
}

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FluxBudget {
    pub cast: u64,
    /// Landed photons: count and flux transmitted into the water (after Fresnel).
    pub landed: Share,
    /// Per reason, in `DropReason::ALL` order: the flux the photons carried towards the water.
    pub dropped: [Share; 9],
    /// Records whose code is none of the above (a shader and this module out of step).
    pub unknown: u64,
    /// The light's power through the whole photon grid, W, where it is known exactly (a
    /// directional light: E⊥ × the window's area); the landed photons' Fresnel reflection is
    /// what it leaves unaccounted.
    pub light_power: Option<f64>,
}

impl FluxBudget {
    /// From the records `CausticsPass::read_photon_records` returns: two per photon.
    pub fn from_records(records: &[[f32; 4]]) -> Self {
        let mut budget = FluxBudget::default();
        for pair in records.chunks_exact(2) {
            let (code, flux) = (pair[0][3], pair[1][3] as f64);
            budget.cast += 1;
            if code > 0.5 {
                budget.landed.add(flux);
            } else {
                match DropReason::from_code(-code) {
                    Some(reason) => budget.dropped[reason as usize - 1].add(flux),
                    None => budget.unknown += 1,
                }
            }
        }
        budget
    }

    /// Flux of all dropped photons, W.
    pub fn dropped_watts(&self) -> f64 {
        self.dropped.iter().map(|s| s.watts).sum()
    }
}

impl fmt::Display for FluxBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total = self.light_power.unwrap_or(self.landed.watts + self.dropped_watts());
        let pct = |w: f64| if total > 0.0 { 100.0 * w / total } else { 0.0 };
        writeln!(f, "{:<44} {:>10} {:>12} {:>7}", "caustic photons", "photons", "W", "%")?;
        writeln!(f, "{:<44} {:>10} {:>12.5}", "cast (the light's power through the grid)", self.cast, total)?;
        if let Some(power) = self.light_power {
            let reflected = power - self.landed.watts - self.dropped_watts();
            writeln!(
                f,
                "{:<44} {:>10} {:>12.5} {:>6.2}%",
                "reflected at the surface (landed photons)",
                "",
                reflected,
                pct(reflected)
            )?;
        }
        writeln!(
            f,
            "{:<44} {:>10} {:>12.5} {:>6.2}%",
            "landed (transmitted flux)",
            self.landed.photons,
            self.landed.watts,
            pct(self.landed.watts)
        )?;
        for (reason, share) in DropReason::ALL.iter().zip(&self.dropped) {
            if share.photons > 0 {
                writeln!(
                    f,
                    "{:<44} {:>10} {:>12.5} {:>6.2}%",
                    format!("dropped: {}", reason.describe()),
                    share.photons,
                    share.watts,
                    pct(share.watts)
                )?;
            }
        }
        if self.unknown > 0 {
            writeln!(f, "{:<44} {:>10}", "records with an unknown code", self.unknown)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn records_are_counted_by_reason() {
        let photon = |code: f32, flux: f32| [[0.0, 0.0, 0.0, code], [0.0, 0.0, 0.0, flux]];
        let records: Vec<[f32; 4]> =
            [photon(1.0, 0.5), photon(-7.0, 1.0), photon(-7.0, 1.0), photon(-2.0, 0.25), photon(-12.0, 1.0)].concat();
        let b = FluxBudget::from_records(&records);
        assert_eq!(b.cast, 5);
        assert_eq!(b.landed, Share { photons: 1, watts: 0.5 });
        assert_eq!(b.dropped[DropReason::NotConverged as usize - 1], Share { photons: 2, watts: 2.0 });
        assert_eq!(b.dropped[DropReason::OutsideWater as usize - 1], Share { photons: 1, watts: 0.25 });
        assert_eq!(b.unknown, 1);
        assert!(b.to_string().contains("image-space iteration does not converge"));
    }
}
