//! Where the caustic photons' and the godray beams' flux goes (`underlight render
//! --flux-budget`): of the light's power through each photon grid, how much lands on a
//! receiver and how much each reason for dropping a photon costs; for the beams, also how much
//! of their length the camera's view clips off; for the landed caustic photons, what the
//! camera sees of them and how far each lies from the exact hit along its refracted ray. Read
//! from the photon records of the geometry shaders' recording variants
//! (`FrameOptions::record_photons`, `glsl/caustics/caustics.geom`, `glsl/godrays/godrays.geom`),
//! so it is the GPU's own account, not a model of it.

use glam::{Mat4, Vec3};
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

/// How much of the drawn godray beams the camera's view volume holds, weighted by flux ×
/// length (W·m: a beam's in-scattered power grows with both, before attenuation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BeamsInView {
    pub in_view: f64,
    pub clipped: f64,
    /// Drawn beams no part of which is in view (behind the camera, or beside the view).
    pub wholly_outside: u64,
}

/// Where the landed caustic photons' flux fell for the camera (`FluxBudget::seen_by`): on a
/// receiver it sees, on one hidden behind the scene, or outside its view volume.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhotonsSeen {
    pub visible: Share,
    pub hidden: Share,
    pub outside: Share,
}

/// Where the landed caustic photons lie against the exact hits along their own refracted
/// rays (`FluxBudget::placed_by`): the image-space iteration against the light's position map
/// (photon_cast.glsl) is the method's approximation of a ray cast, and the scene's triangles
/// (the reference's BVH) give the ray cast itself. A record holds the photon's surface point
/// and its hit, both on its refracted ray, so the two differ only in the distance along it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PhotonsPlaced {
    /// Within `PLACED_CLOSE` of the exact hit.
    pub close: Share,
    /// Within `PLACED_NEAR`, farther than `PLACED_CLOSE`.
    pub near: Share,
    /// Farther than `PLACED_NEAR`.
    pub off: Share,
    /// The exact ray meets no triangle: a hit the light's maps hold and the scene does not.
    pub on_nothing: Share,
    /// Median distance from the exact hit over the photons that have one, m.
    pub median_error: f64,
}

/// A photon within this of its exact hit counts as placed, m: under the built-in scenes'
/// spacing between photons (13 mm on the tank's floor at 100² × 3²) and a few of the light
/// maps' texels (4–5 mm at 1024²), whose plane the iteration's last step lands on.
pub const PLACED_CLOSE: f64 = 0.01;
/// Farther than this a photon lights a different place: several photon spacings, or another
/// facet of a rock.
pub const PLACED_NEAR: f64 = 0.05;

/// A landed footprint point's record code where its footprint was larger than the device's
/// largest point, which drew it (glsl/caustics/caustics.geom, FOOTPRINT_POINTS with
/// PHOTON_DEBUG); a landed photon's is otherwise 1. GLSL: PHOTON_RECORD_FOOTPRINT_CLAMPED
/// (photon_cast.glsl; `shader_math`'s mirrored-constants test holds them equal).
pub const FOOTPRINT_CLAMPED: f32 = 3.0;

#[derive(Clone, Debug, Default, PartialEq)]
pub struct FluxBudget {
    pub cast: u64,
    /// Landed photons: count and flux transmitted into the water (after Fresnel). For the
    /// beams, those drawn whose image-space iteration converged.
    pub landed: Share,
    /// Beams drawn although their iteration did not converge (a beam keeps its photon there:
    /// its line is right up to the last few centimetres). None for caustic photons.
    pub landed_unconverged: Share,
    /// Of the landed photons, the footprint points whose footprint the device's largest point
    /// clamped (`effects.caustic_estimator = "footprint"`): their light lies on fewer pixels,
    /// brighter, than their footprint.
    pub footprint_clamped: Share,
    /// Per reason, in `DropReason::ALL` order: the flux the photons carried towards the water.
    pub dropped: [Share; 9],
    /// Records whose code is none of the above (a shader and this module out of step).
    pub unknown: u64,
    /// The light's power through the whole photon grid, W, where it is known exactly (a
    /// directional light: E⊥ × the window's area); the landed photons' Fresnel reflection is
    /// what it leaves unaccounted.
    pub light_power: Option<f64>,
    /// The beams' share in the camera's view; None for caustic photons.
    pub view: Option<BeamsInView>,
    /// The landed caustic photons as the camera sees them; None until `seen_by`.
    pub seen: Option<PhotonsSeen>,
    /// The landed caustic photons against their exact hits; None until `placed_by`.
    pub placed: Option<PhotonsPlaced>,
}

impl FluxBudget {
    /// From the records `CausticsPass::read_photon_records` returns: two per photon, both
    /// zero where the grid has no photon (an invocation past the last row of the triangles'
    /// grid shaped for the view: `caustic_grid_cell` in glsl/caustics/caustic_splat.glsl).
    pub fn from_records(records: &[[f32; 4]]) -> Self {
        let mut budget = FluxBudget::default();
        for pair in records.chunks_exact(2) {
            if pair[0] == [0.0; 4] && pair[1] == [0.0; 4] {
                continue;
            }
            let (code, flux) = (pair[0][3], pair[1][3] as f64);
            budget.cast += 1;
            if code > FOOTPRINT_CLAMPED - 0.5 {
                budget.landed.add(flux);
                budget.footprint_clamped.add(flux);
            } else if code > 1.5 {
                budget.landed_unconverged.add(flux);
            } else if code > 0.5 {
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

    /// From the records `GodraysPass::read_photon_records` returns (two per beam), and the
    /// camera whose view clips the beams (`FrameUniforms::camera_view_proj`).
    pub fn from_beam_records(records: &[[f32; 4]], camera_view_proj: Mat4) -> Self {
        let mut budget = Self::from_records(records);
        let mut view = BeamsInView::default();
        for pair in records.chunks_exact(2) {
            if pair[0][3] < 0.5 {
                continue; // dropped: no line
            }
            let (hit, surface) = (Vec3::from_slice(&pair[0][..3]), Vec3::from_slice(&pair[1][..3]));
            let weight = pair[1][3] as f64 * surface.distance(hit) as f64;
            let inside = fraction_in_view(camera_view_proj, surface, hit) as f64;
            view.in_view += weight * inside;
            view.clipped += weight * (1.0 - inside);
            view.wholly_outside += (inside == 0.0) as u64;
        }
        budget.view = Some(view);
        budget
    }

    /// Sorts the landed caustic photons of `records` (`from_records`' input) by what the
    /// camera at `camera` with `view_proj` sees of their hits: outside its view volume, hidden
    /// behind the scene (`bvh`, its triangles) or visible. A hit counts as visible where
    /// nothing lies nearer along the camera's ray than the caustic splats' depth tolerance
    /// allows (`behind_scene` in photon_visibility.glsl: 2 % + 2 cm, here along the ray).
    pub fn seen_by(&mut self, records: &[[f32; 4]], view_proj: Mat4, camera: Vec3, bvh: &crate::bvh::Bvh) {
        let mut seen = PhotonsSeen::default();
        for pair in records.chunks_exact(2) {
            if pair[0][3] < 0.5 {
                continue;
            }
            let (hit, flux) = (Vec3::from_slice(&pair[0][..3]), pair[1][3] as f64);
            let c = view_proj * hit.extend(1.0);
            let inside = c.w > 0.0 && c.x.abs() <= c.w && c.y.abs() <= c.w && (0.0..=c.w).contains(&c.z);
            let to_hit = (hit - camera).as_dvec3();
            let distance = to_hit.length();
            let share = if !inside {
                &mut seen.outside
            } else if bvh.occluded(camera.as_dvec3(), to_hit / distance, 1e-4, nearest_seen(distance)) {
                &mut seen.hidden
            } else {
                &mut seen.visible
            };
            share.add(flux);
        }
        self.seen = Some(seen);
    }

    /// Sorts the landed caustic photons of `records` (`from_records`' input) by how far their
    /// hit lies from the first of the scene's triangles (`bvh`) along the same refracted ray,
    /// traced from where the photon entered the water.
    pub fn placed_by(&mut self, records: &[[f32; 4]], bvh: &crate::bvh::Bvh) {
        let mut placed = PhotonsPlaced::default();
        let mut errors = Vec::new();
        for pair in records.chunks_exact(2) {
            if !(0.5..1.5).contains(&pair[0][3]) {
                continue;
            }
            let hit = Vec3::from_slice(&pair[0][..3]).as_dvec3();
            let (surface, flux) = (Vec3::from_slice(&pair[1][..3]).as_dvec3(), pair[1][3] as f64);
            let travelled = surface.distance(hit);
            let exact = (travelled > 0.0)
                .then(|| bvh.closest(surface, (hit - surface) / travelled, 1e-4, f64::INFINITY))
                .flatten();
            let Some(exact) = exact else {
                placed.on_nothing.add(flux);
                continue;
            };
            let error = (travelled - exact.t).abs();
            errors.push(error);
            let share = if error <= PLACED_CLOSE {
                &mut placed.close
            } else if error <= PLACED_NEAR {
                &mut placed.near
            } else {
                &mut placed.off
            };
            share.add(flux);
        }
        errors.sort_by(f64::total_cmp);
        placed.median_error = errors.get(errors.len() / 2).copied().unwrap_or(0.0);
        self.placed = Some(placed);
    }

    /// Flux of all dropped photons, W.
    pub fn dropped_watts(&self) -> f64 {
        self.dropped.iter().map(|s| s.watts).sum()
    }

    /// Flux of all landed (or drawn) photons, W.
    pub fn landed_watts(&self) -> f64 {
        self.landed.watts + self.landed_unconverged.watts
    }
}

/// The nearest a surface may lie along the camera's ray before it hides a hit at `distance`:
/// `behind_scene`'s test, distance > scene·(1 + tolerance) + tolerance, solved for the scene.
fn nearest_seen(distance: f64) -> f64 {
    let tolerance = crate::shader_math::CAUSTIC_DEPTH_TOLERANCE as f64;
    (distance - tolerance) / (1.0 + tolerance)
}

/// The share of the segment a → b (world space) inside the camera's view volume: clip space
/// −w ≤ x, y ≤ w and 0 ≤ z ≤ w (Vulkan's depth range). Clip coordinates are linear in the
/// segment's parameter, so each bound cuts it at one parameter (Liang–Barsky), and the share
/// of the parameter is the share of the world length.
pub fn fraction_in_view(view_proj: Mat4, a: Vec3, b: Vec3) -> f32 {
    let (ca, cb) = (view_proj * a.extend(1.0), view_proj * b.extend(1.0));
    // Each bound as f(t) = f0 + t·(f1 − f0) ≥ 0.
    let bounds = [
        (ca.w + ca.x, cb.w + cb.x),
        (ca.w - ca.x, cb.w - cb.x),
        (ca.w + ca.y, cb.w + cb.y),
        (ca.w - ca.y, cb.w - cb.y),
        (ca.z, cb.z),
        (ca.w - ca.z, cb.w - cb.z),
    ];
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    for (f0, f1) in bounds {
        if f0 < 0.0 && f1 < 0.0 {
            return 0.0;
        }
        if f0 < 0.0 {
            t0 = t0.max(f0 / (f0 - f1));
        } else if f1 < 0.0 {
            t1 = t1.min(f0 / (f0 - f1));
        }
    }
    (t1 - t0).max(0.0)
}

impl fmt::Display for FluxBudget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let total = self.light_power.unwrap_or(self.landed_watts() + self.dropped_watts());
        let pct = |w: f64| if total > 0.0 { 100.0 * w / total } else { 0.0 };
        // The beams' budget is the one that knows their view (from_beam_records).
        let (what, count, landed_ones) = if self.view.is_some() {
            ("godray beams", "beams", "drawn beams")
        } else {
            ("caustic photons", "photons", "landed photons")
        };
        writeln!(f, "{:<44} {:>10} {:>12} {:>7}", what, count, "W", "%")?;
        writeln!(f, "{:<44} {:>10} {:>12.5}", "cast (the light's power through the grid)", self.cast, total)?;
        if let Some(power) = self.light_power {
            let reflected = power - self.landed_watts() - self.dropped_watts();
            writeln!(
                f,
                "{:<44} {:>10} {:>12.5} {:>6.2}%",
                format!("reflected at the surface ({landed_ones})"),
                "",
                reflected,
                pct(reflected)
            )?;
        }
        let landed = if self.view.is_some() { "drawn (transmitted flux)" } else { "landed (transmitted flux)" };
        writeln!(
            f,
            "{:<44} {:>10} {:>12.5} {:>6.2}%",
            landed,
            self.landed.photons,
            self.landed.watts,
            pct(self.landed.watts)
        )?;
        if self.footprint_clamped.photons > 0 {
            writeln!(
                f,
                "{:<44} {:>10} {:>12.5} {:>6.2}%",
                "  of them footprints clamped to the largest point",
                self.footprint_clamped.photons,
                self.footprint_clamped.watts,
                pct(self.footprint_clamped.watts)
            )?;
        }
        if self.landed_unconverged.photons > 0 {
            writeln!(
                f,
                "{:<44} {:>10} {:>12.5} {:>6.2}%",
                "drawn although the iteration did not converge",
                self.landed_unconverged.photons,
                self.landed_unconverged.watts,
                pct(self.landed_unconverged.watts)
            )?;
        }
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
        if let Some(s) = self.seen {
            for (what, share) in [
                ("landed where the camera sees it", s.visible),
                ("landed where the scene hides it", s.hidden),
                ("landed outside the camera's view", s.outside),
            ] {
                writeln!(f, "{:<44} {:>10} {:>12.5} {:>6.2}%", what, share.photons, share.watts, pct(share.watts))?;
            }
        }
        if let Some(p) = &self.placed {
            for (what, share) in [
                (format!("landed within {} cm of the exact hit", PLACED_CLOSE * 100.0), p.close),
                (format!("landed {}-{} cm from it", PLACED_CLOSE * 100.0, PLACED_NEAR * 100.0), p.near),
                (format!("landed farther than {} cm from it", PLACED_NEAR * 100.0), p.off),
                ("landed where the exact ray meets nothing".to_owned(), p.on_nothing),
            ] {
                writeln!(f, "{:<44} {:>10} {:>12.5} {:>6.2}%", what, share.photons, share.watts, pct(share.watts))?;
            }
            writeln!(f, "median distance of a landed photon from its exact hit: {:.3} mm", 1000.0 * p.median_error)?;
        }
        if let Some(v) = self.view {
            let weight = v.in_view + v.clipped;
            let share = |x: f64| if weight > 0.0 { 100.0 * x / weight } else { 0.0 };
            writeln!(
                f,
                "of the drawn beams' flux × length: {:.2} % in the camera's view, {:.2} % clipped off by it; {} beams wholly outside it",
                share(v.in_view),
                share(v.clipped),
                v.wholly_outside
            )?;
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
        // The all-zero pair is no photon: an invocation past the last row of a grid shaped for
        // the view.
        let records: Vec<[f32; 4]> = [
            photon(1.0, 0.5),
            photon(-7.0, 1.0),
            photon(0.0, 0.0),
            photon(-7.0, 1.0),
            photon(-2.0, 0.25),
            photon(-12.0, 1.0),
        ]
        .concat();
        let b = FluxBudget::from_records(&records);
        assert_eq!(b.cast, 5);
        assert_eq!(b.landed, Share { photons: 1, watts: 0.5 });
        assert_eq!(b.dropped[DropReason::NotConverged as usize - 1], Share { photons: 2, watts: 2.0 });
        assert_eq!(b.dropped[DropReason::OutsideWater as usize - 1], Share { photons: 1, watts: 0.25 });
        assert_eq!(b.unknown, 1);
        assert!(b.to_string().contains("image-space iteration does not converge"));
    }

    #[test]
    fn the_view_clips_a_beam_by_its_length() {
        // Looking down −z from the origin, 90° field of view, near 0.1, far 100.
        let view_proj = glam::camera::rh::proj::vulkan::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
        let inside = |a: [f32; 3], b: [f32; 3]| fraction_in_view(view_proj, Vec3::from(a), Vec3::from(b));
        assert!((inside([0.0, 0.0, -1.0], [0.0, 0.0, -5.0]) - 1.0).abs() < 1e-6, "wholly in view");
        // Along x at depth 2 the view spans x ∈ [−2, 2]: half of [0, 4] is in it.
        assert!((inside([0.0, 0.0, -2.0], [4.0, 0.0, -2.0]) - 0.5).abs() < 1e-5);
        // From behind the camera to in front of it: cut at the near plane.
        assert!((inside([0.0, 0.0, 1.0], [0.0, 0.0, -1.0]) - 0.45).abs() < 1e-5);
        assert_eq!(inside([0.0, 0.0, 1.0], [0.0, 0.0, 3.0]), 0.0, "wholly behind");
        assert_eq!(inside([5.0, 0.0, -1.0], [5.0, 0.0, -2.0]), 0.0, "wholly beside");
    }

    #[test]
    fn landed_photons_are_seen_hidden_or_out_of_view() {
        // Camera at the origin looking down −z; a wall across the view at z = −5.
        let view_proj = glam::camera::rh::proj::vulkan::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
        let wall = [[-10.0, -10.0, -5.0], [10.0, -10.0, -5.0], [0.0, 10.0, -5.0]].map(glam::DVec3::from);
        let bvh = crate::bvh::Bvh::build([wall]);
        let photon = |hit: [f32; 3], fate: f32, flux: f32| [[hit[0], hit[1], hit[2], fate], [0.0, 0.0, 0.0, flux]];
        let records: Vec<[f32; 4]> = [
            photon([0.0, 0.0, -3.0], 1.0, 1.0),   // in front of the wall: seen
            photon([0.0, 0.0, -5.0], 1.0, 2.0),   // on the wall: seen (within the tolerance)
            photon([0.0, 0.0, -8.0], 1.0, 4.0),   // behind it: hidden
            photon([50.0, 0.0, -3.0], 1.0, 8.0),  // beside the view
            photon([0.0, 0.0, 3.0], 1.0, 16.0),   // behind the camera
            photon([0.0, 0.0, -3.0], -7.0, 32.0), // dropped: not sorted
        ]
        .concat();
        let mut b = FluxBudget::from_records(&records);
        b.seen_by(&records, view_proj, Vec3::ZERO, &bvh);
        let s = b.seen.unwrap();
        assert_eq!((s.visible.photons, s.visible.watts), (2, 3.0));
        assert_eq!((s.hidden.photons, s.hidden.watts), (1, 4.0));
        assert_eq!((s.outside.photons, s.outside.watts), (2, 24.0));
        assert!(b.to_string().contains("landed where the scene hides it"));
    }

    #[test]
    fn landed_photons_are_placed_against_the_exact_hit_along_their_ray() {
        // A floor at y = 0 under x, z ∈ [−10, 10]; photons enter the water 2 m above it.
        let floor = [
            [[-10.0, 0.0, -10.0], [10.0, 0.0, -10.0], [10.0, 0.0, 10.0]].map(glam::DVec3::from),
            [[-10.0, 0.0, -10.0], [10.0, 0.0, 10.0], [-10.0, 0.0, 10.0]].map(glam::DVec3::from),
        ];
        let bvh = crate::bvh::Bvh::build(floor);
        let photon = |surface: [f32; 3], hit: [f32; 3], fate: f32, flux: f32| {
            [[hit[0], hit[1], hit[2], fate], [surface[0], surface[1], surface[2], flux]]
        };
        let records: Vec<[f32; 4]> = [
            photon([0.0, 2.0, 0.0], [0.0, 0.0, 0.0], 1.0, 1.0),    // on the floor
            photon([0.0, 2.0, 0.0], [0.0, 0.004, 0.0], 1.0, 2.0),  // 4 mm short of it
            photon([1.0, 2.0, 0.0], [1.5, 0.02, 0.0], 1.0, 4.0),   // 2 cm of its 2.06 m ray short
            photon([0.0, 2.0, 0.0], [0.0, -0.2, 0.0], 1.0, 8.0),   // 20 cm past it
            photon([20.0, 2.0, 0.0], [20.0, 0.0, 0.0], 1.0, 16.0), // beside the floor: nothing there
            photon([0.0, 2.0, 0.0], [0.0, 1.0, 0.0], -7.0, 32.0),  // dropped: not placed
        ]
        .concat();
        let mut b = FluxBudget::from_records(&records);
        b.placed_by(&records, &bvh);
        let p = b.placed.clone().unwrap();
        assert_eq!((p.close.photons, p.close.watts), (2, 3.0));
        assert_eq!((p.near.photons, p.near.watts), (1, 4.0));
        assert_eq!((p.off.photons, p.off.watts), (1, 8.0));
        assert_eq!((p.on_nothing.photons, p.on_nothing.watts), (1, 16.0));
        // Errors 0, 4 mm, ~2 cm, 20 cm: the median is the third smallest.
        assert!((p.median_error - 0.0206).abs() < 1e-3, "{}", p.median_error);
        assert!(b.to_string().contains("landed within 1 cm of the exact hit"));
    }

    #[test]
    fn beams_count_their_fates_and_their_length_in_view() {
        let view_proj = glam::camera::rh::proj::vulkan::perspective(std::f32::consts::FRAC_PI_2, 1.0, 0.1, 100.0);
        let beam = |fate: f32, surface: [f32; 3], hit: [f32; 3], flux: f32| {
            [[hit[0], hit[1], hit[2], fate], [surface[0], surface[1], surface[2], flux]]
        };
        let records: Vec<[f32; 4]> = [
            beam(1.0, [0.0, 0.0, -1.0], [0.0, 0.0, -3.0], 1.0),  // 2 m in view
            beam(2.0, [0.0, 0.0, -2.0], [4.0, 0.0, -2.0], 0.5),  // 4 m, half in view; unconverged
            beam(-7.0, [0.0, 0.0, -1.0], [0.0, 0.0, -9.0], 2.0), // dropped: no line
        ]
        .concat();
        let b = FluxBudget::from_beam_records(&records, view_proj);
        assert_eq!((b.cast, b.landed.photons, b.landed_unconverged.photons), (3, 1, 1));
        let v = b.view.unwrap();
        assert!((v.in_view - (2.0 + 1.0)).abs() < 1e-4 && (v.clipped - 1.0).abs() < 1e-4, "{v:?}");
        assert_eq!(v.wholly_outside, 0);
        let text = b.to_string();
        assert!(text.starts_with("godray beams") && text.contains("drawn although"), "{text}");
    }
}
