//! Light paths: photons sampled over the whole water surface and traced exactly, from the
//! light through the animated surface (Fresnel, refraction) to the first triangle.
//!
//! Photon start points are stratified over a horizontal plane just above the highest crest
//! (one jittered sample per cell). Every ray from the light that meets the water inside its
//! extent crosses that plane inside `LightSampler::rect`, so sampling the rectangle
//! uniformly and weighting each photon by the light's flux through its cell is an unbiased
//! (and, with stratification, low-variance) estimate of the light entering the water:
//!
//! - directional: flux through a horizontal cell of area `A` = `E⊥ · |d_y| · A`;
//! - point: `I · ω`, with the cell's solid angle `ω = A · cos θ / r²`, `cos θ = h / r`.
//!
//! Photons whose ray meets the surface outside the water's extent are dropped (they carry
//! exactly the light that misses the water).

use super::water::{fresnel_transmittance, refract};
use super::Context;
use crate::scene::{LightKind, Scene};
use glam::{DVec2, DVec3};

/// `n` cells over a rectangle: `rows` rows, row `j` split into `row(j).1` equal cells, so
/// the count is exactly `n` and every cell is within one cell's width of square.
#[derive(Clone, Copy, Debug)]
pub struct Strata {
    pub lo: DVec2,
    pub size: DVec2,
    pub n: u64,
    pub rows: u64,
}

impl Strata {
    pub fn new(lo: DVec2, hi: DVec2, n: u64) -> Self {
        let size = hi - lo;
        let rows = ((n as f64 * size.y / size.x).sqrt().round() as u64).clamp(1, n.max(1));
        Self { lo, size, n, rows }
    }

    pub fn area(&self) -> f64 {
        self.size.x * self.size.y
    }

    /// Global index of row `j`'s first cell, and its number of cells.
    pub fn row(&self, j: u64) -> (u64, u64) {
        let first = (self.n as u128 * j as u128 / self.rows as u128) as u64;
        let next = (self.n as u128 * (j + 1) as u128 / self.rows as u128) as u64;
        (first, next - first)
    }

    /// The point at `jitter` ∈ [0,1)² inside cell `i` of row `j` (of `count` cells), and the
    /// cell's area.
    pub fn sample(&self, j: u64, i: u64, count: u64, jitter: DVec2) -> (DVec2, f64) {
        let cell = DVec2::new(self.size.x / count as f64, self.size.y / self.rows as f64);
        let p = self.lo + cell * (DVec2::new(i as f64, j as f64) + jitter);
        (p, cell.x * cell.y)
    }
}

/// splitmix64: a tiny, well-mixed hash, so each cell's jitter depends only on the seed and
/// the cell (the result does not depend on the thread count).
fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Two uniform numbers in [0, 1) for cell `index` of stream `stream`.
pub fn jitter(seed: u64, stream: u64, index: u64) -> DVec2 {
    let a = splitmix64(seed ^ splitmix64(stream.wrapping_add(splitmix64(index))));
    let b = splitmix64(a);
    let unit = |x: u64| (x >> 11) as f64 / (1u64 << 53) as f64;
    DVec2::new(unit(a), unit(b))
}

#[derive(Clone, Copy, Debug)]
pub enum LightSource {
    /// Unit direction of travel and E⊥, W/m².
    Directional { direction: DVec3, irradiance: f64 },
    /// Position and intensity, W/sr.
    Point { position: DVec3, intensity: f64 },
}

#[derive(Clone, Copy, Debug)]
pub struct LightSampler {
    pub source: LightSource,
    /// Height of the sampling plane: just above the highest crest.
    pub plane_y: f64,
    /// The rectangle (x, z) on the plane that every photon entering the water crosses.
    pub rect_lo: DVec2,
    pub rect_hi: DVec2,
}

impl LightSampler {
    /// `Ok(None)` when no light can enter the water (a sun at or below the horizon); an
    /// error for a point light among the waves, which this parameterisation cannot sample.
    pub fn new(scene: &Scene, level: f64, bound: f64) -> crate::error::Result<Option<Self>> {
        let w = &scene.water;
        let (lo, hi) = (
            DVec2::new(w.extent_min.x as f64, w.extent_min.y as f64),
            DVec2::new(w.extent_max.x as f64, w.extent_max.y as f64),
        );
        // A hair above the crests, so the plane is above the surface despite f32 heights.
        let plane_y = level + bound + 1e-4;
        let trough = level - bound;
        let l = &scene.light;
        let (source, shifted_lo, shifted_hi) = match l.kind {
            LightKind::Directional => {
                let d = l.direction.as_dvec3().normalize();
                if !(d.y < -1e-9) {
                    return Ok(None);
                }
                // A ray meeting the surface at height y_s crossed the plane (plane_y − y_s)/|d_y|
                // earlier: up to (plane_y − trough)·d_xz/|d_y| up-light of where it enters.
                let shift = DVec2::new(d.x, d.z) * ((plane_y - trough) / d.y);
                let e = crate::frame::uniforms::directional_irradiance(scene) as f64;
                (LightSource::Directional { direction: d, irradiance: e }, lo + shift, hi + shift)
            }
            LightKind::Point => {
                let p = l.position.as_dvec3();
                if !(p.y > plane_y + 1e-3) {
                    return Err(crate::Error::InvalidParameter {
                        name: "light.position",
                        message: format!(
                            "the reference renderer samples photons on a plane above the wave crests (y = {plane_y:.4} m); the point light at y = {} m is not above it",
                            p.y
                        ),
                    });
                }
                // The ray to a surface point at height y_s crosses the plane at the light's
                // foot + (point − foot)·(p_y − plane_y)/(p_y − y_s): scaled towards the foot
                // by at least (p_y − plane_y)/(p_y − trough).
                let foot = DVec2::new(p.x, p.z);
                let f = (p.y - plane_y) / (p.y - trough);
                (
                    LightSource::Point { position: p, intensity: l.intensity as f64 },
                    foot + (lo - foot) * f,
                    foot + (hi - foot) * f,
                )
            }
        };
        Ok(Some(Self {
            source,
            plane_y,
            rect_lo: lo.min(shifted_lo).min(shifted_hi),
            rect_hi: hi.max(shifted_hi).max(shifted_lo),
        }))
    }

    /// The photon ray through `xz` on the sampling plane: origin, unit direction, and the
    /// light's flux per unit area of the plane there (W/m²).
    pub fn ray(&self, xz: DVec2) -> (DVec3, DVec3, f64) {
        let o = DVec3::new(xz.x, self.plane_y, xz.y);
        match self.source {
            LightSource::Directional { direction, irradiance } => (o, direction, irradiance * direction.y.abs()),
            LightSource::Point { position, intensity } => {
                let v = o - position;
                let r = v.length();
                (o, v / r, intensity * (position.y - self.plane_y) / (r * r * r))
            }
        }
    }
}

/// A photon's path under the water.
#[derive(Clone, Copy, Debug)]
pub struct LightPath {
    /// Where it enters the water.
    pub surface: DVec3,
    /// Unit refracted direction.
    pub direction: DVec3,
    /// Flux after the surface (Fresnel transmittance applied), W.
    pub flux: f64,
    /// Length of the path in the water, m: to the receiver, to where it leaves the water
    /// again through a wave's flank, or to the edge of the scene's box.
    pub length: f64,
    /// The receiver's unit geometric normal, when the path ends on a triangle under water.
    pub receiver: Option<DVec3>,
}

impl LightPath {
    pub fn end(&self) -> DVec3 {
        self.surface + self.length * self.direction
    }
}

/// Where the refracted ray starts looking for the surface again, m: clear of the entry point
/// (a refracted ray leaves the surface at ≥ 41° from it, so it is ≥ 6e-6 m under it there).
const EXIT_SEARCH_START: f64 = 1e-5;

/// Traces the photon through `xz` of the sampling plane, whose cell has `area` m².
pub fn trace(ctx: &Context, sampler: &LightSampler, xz: DVec2, area: f64) -> Option<LightPath> {
    let (o, d, density) = sampler.ray(xz);
    let s = &ctx.surface;
    let t = s.crossing(o, d, 0.0, f64::INFINITY, true)?;
    let ps = o + t * d;
    if !s.covers(ps.x, ps.z) {
        return None;
    }
    // Blocked on the way to the water (a deck, a wall above it).
    let to_light = match sampler.source {
        LightSource::Directional { .. } => f64::INFINITY,
        LightSource::Point { position, .. } => (position - ps).length() * (1.0 - 1e-9),
    };
    if ctx.bvh.occluded(ps, -d, 1e-9, to_light) {
        return None;
    }
    let n = s.normal(ps.x, ps.z);
    let cos_i = -d.dot(n);
    if !(cos_i > 0.0) {
        return None; // the back of a wave (only where the noise's interpolated gradient lies)
    }
    let ior = s.water.ior as f64;
    let rt = refract(d, n, 1.0 / ior)?;
    let flux = density * area * fresnel_transmittance(cos_i, ior);
    let box_exit = ctx.box_exit(ps, rt);
    let hit = ctx.bvh.closest(ps, rt, 1e-9, box_exit);
    let end = hit.map_or(box_exit, |h| h.t);
    // The path leaves the water through a neighbouring wave's flank: it ends there (the
    // light refracts back into the air; its re-entry is a second-order path, not traced).
    if let Some(exit) = s.crossing(ps, rt, EXIT_SEARCH_START, end, false) {
        return Some(LightPath { surface: ps, direction: rt, flux, length: exit, receiver: None });
    }
    Some(LightPath { surface: ps, direction: rt, flux, length: end, receiver: hit.map(|h| h.normal) })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::water::Surface;
    use crate::scene::{Camera, Effects, Light, Medium, Water, WaterModel};
    use crate::shader_math::NoiseTexture;
    use glam::{Vec2, Vec3};

    fn scene(light: Light) -> Scene {
        Scene {
            name: "waves".into(),
            output: [64, 64],
            camera: Camera {
                position: Vec3::new(0.0, -0.5, 0.0),
                look_at: Vec3::new(0.0, -2.0, 0.1),
                fov_y_degrees: 60.0,
                z_near: 0.05,
                z_far: 10.0,
            },
            light,
            water: Water {
                model: WaterModel::CircularCosine,
                level: 0.3,
                amplitude: 0.06,
                wavelength: 0.7,
                speed: 0.5,
                noise_amplitude: 0.04,
                noise_scale: 2.0,
                center: Vec2::new(0.5, -0.3),
                extent_min: Vec2::new(-2.0, -1.5),
                extent_max: Vec2::new(3.0, 2.5),
                ior: 1.333,
            },
            medium: Medium::default(),
            effects: Effects::default(),
            meshes: Vec::new(),
        }
    }

    /// Rays through the sampling plane just outside the rectangle meet the surface outside
    /// the water's extent: the rectangle holds every photon that can enter the water.
    #[test]
    fn the_sampling_rectangle_covers_the_whole_water() {
        let noise = NoiseTexture::generate();
        let lights = [
            Light {
                kind: LightKind::Directional,
                direction: Vec3::new(0.6, -0.5, 0.3).normalize(),
                position: Vec3::ZERO,
                intensity: 9.2,
                distance: 100.0,
            },
            Light {
                kind: LightKind::Point,
                direction: Vec3::NEG_Y,
                position: Vec3::new(2.0, 1.2, -1.0),
                intensity: 9.2,
                distance: 100.0,
            },
            // Beside the water: rays reach it slanting, through the plane nearer the light.
            Light {
                kind: LightKind::Point,
                direction: Vec3::NEG_Y,
                position: Vec3::new(5.0, 1.0, -3.0),
                intensity: 9.2,
                distance: 100.0,
            },
        ];
        for light in lights {
            let s = scene(light);
            let surface = Surface::new(&s.water, &noise, 1.7);
            let sampler = LightSampler::new(&s, surface.level, surface.bound).unwrap().unwrap();
            let (lo, hi) = (sampler.rect_lo, sampler.rect_hi);
            let mut outside = 0;
            for k in 0..4000 {
                let u = (k as f64 + 0.5) / 4000.0;
                // Around the perimeter, 1 mm out.
                let along = |a: f64, b: f64| a + (b - a) * (4.0 * u).fract();
                let edge = match (4.0 * u) as u32 {
                    0 => DVec2::new(along(lo.x, hi.x), lo.y),
                    1 => DVec2::new(hi.x, along(lo.y, hi.y)),
                    2 => DVec2::new(along(lo.x, hi.x), hi.y),
                    _ => DVec2::new(lo.x, along(lo.y, hi.y)),
                };
                let centre = 0.5 * (lo + hi);
                let outward = (edge - centre).signum() * 1e-3;
                let (o, d, _) = sampler.ray(edge + outward);
                let t = surface.crossing(o, d, 0.0, f64::INFINITY, true).expect("a ray from above crosses");
                let ps = o + t * d;
                assert!(
                    !surface.covers(ps.x, ps.z),
                    "{:?}: a ray from outside the rectangle enters the water at {ps}",
                    light.kind
                );
                outside += 1;
            }
            assert_eq!(outside, 4000);
            // And the light does enter through it.
            let (o, d, _) = sampler.ray(0.5 * (lo + hi));
            let t = surface.crossing(o, d, 0.0, f64::INFINITY, true).unwrap();
            assert!(surface.covers(o.x + t * d.x, o.z + t * d.z));
        }
    }
}
