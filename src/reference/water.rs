//! The animated water surface for exact ray casts, and the optics of crossing it.
//!
//! Heights and gradients come from the CPU twin (`shader_math::water_height_grad`), so the
//! reference sees the very surface the GPU does (same waves, same noise texels). Rays,
//! intersections and refraction are f64: the root of `f(t) = y(t) − level − h(x(t), z(t))`
//! is bracketed by a march that cannot step over it and then refined to ~1e-10 m in `t`
//! (the twin evaluates `h` in f32, so the surface itself is only defined to ~1e-7 m).

use crate::scene::Water;
use crate::shader_math::{water_height_grad, NoiseTexture};
use glam::{DVec2, DVec3, Vec2};

pub struct Surface<'a> {
    pub water: Water,
    noise: &'a NoiseTexture,
    time: f32,
    pub level: f64,
    /// The waves stay within `level ± bound`.
    pub bound: f64,
    /// Upper bound of |∇h|: steps of |f| / (|d_y| + slope·|d_xz|) along a ray cannot cross
    /// the surface.
    slope: f64,
}

/// Smallest march step, m. A root is skipped only where the ray dips under a crest by less
/// than slope·1e-7 m and comes out again within the step: a tangent graze.
const MIN_STEP: f64 = 1e-7;
/// Bracket width the refinement stops at, m.
const ROOT_TOLERANCE: f64 = 1e-10;
const MAX_MARCH_STEPS: usize = 200_000;

impl<'a> Surface<'a> {
    pub fn new(water: &Water, noise: &'a NoiseTexture, time: f32) -> Self {
        let bound = (water.amplitude.abs() + water.noise_amplitude.abs()) as f64;
        let k = std::f64::consts::TAU / water.wavelength as f64;
        let wave_slope = water.amplitude.abs() as f64 * k;
        let noise_slope = if water.noise_amplitude != 0.0 {
            water.noise_amplitude.abs() as f64 / water.noise_scale as f64 * noise_lipschitz(noise)
        } else {
            0.0
        };
        // 2 % margin: the twin's f32 arithmetic, and the circular model's |sin| ≤ 1 bound is
        // reached.
        let slope = 1.02 * (wave_slope + noise_slope) + 1e-9;
        Self { water: *water, noise, time, level: water.level as f64, bound, slope }
    }

    pub fn is_flat(&self) -> bool {
        self.bound == 0.0
    }

    /// (height above the mean plane, dh/dx, dh/dz) at (x, z).
    pub fn height_grad(&self, x: f64, z: f64) -> (f64, DVec2) {
        if self.is_flat() {
            return (0.0, DVec2::ZERO);
        }
        let hg = water_height_grad(&self.water, self.noise, Vec2::new(x as f32, z as f32), self.time);
        (hg.x as f64, DVec2::new(hg.y as f64, hg.z as f64))
    }

    /// Height of `p` above the surface (negative: under water).
    pub fn above(&self, p: DVec3) -> f64 {
        p.y - self.level - self.height_grad(p.x, p.z).0
    }

    /// Unit normal pointing up, out of the water (GLSL `water_normal_from_grad`).
    pub fn normal(&self, x: f64, z: f64) -> DVec3 {
        let (_, g) = self.height_grad(x, z);
        DVec3::new(-g.x, 1.0, -g.y).normalize()
    }

    pub fn covers(&self, x: f64, z: f64) -> bool {
        let w = &self.water;
        x >= w.extent_min.x as f64
            && x <= w.extent_max.x as f64
            && z >= w.extent_min.y as f64
            && z <= w.extent_max.y as f64
    }

    /// The first `t` in [t0, t1] where the ray `o + t·d` (d unit) is on the other side of
    /// the surface than `from_above` says it starts: under it (`above ≤ 0`) for a ray
    /// starting above, out of the water (`above ≥ 0`) for one starting under it. `t0`
    /// itself when it already is.
    pub fn crossing(&self, o: DVec3, d: DVec3, t0: f64, t1: f64, from_above: bool) -> Option<f64> {
        let side = if from_above { 1.0 } else { -1.0 };
        // Signed so that the start side is positive and the crossing is where g ≤ 0.
        let g = |t: f64| side * self.above(o + t * d);
        if !(t1 >= t0) {
            return None;
        }
        if g(t0) <= 0.0 {
            return Some(t0);
        }
        // Only the part of the ray inside the slab the waves fill can cross.
        let (lo, hi) = (self.level - self.bound, self.level + self.bound);
        let (mut ta, tb) = if d.y.abs() < 1e-15 {
            if o.y < lo || o.y > hi {
                return None;
            }
            (t0, t1)
        } else {
            let (a, b) = ((lo - o.y) / d.y, (hi - o.y) / d.y);
            (t0.max(a.min(b)), t1.min(a.max(b)))
        };
        if ta > tb {
            return None;
        }
        if self.is_flat() {
            // A plane: the crossing is where y = level.
            let t = (self.level - o.y) / d.y;
            return (t >= t0 && t <= t1).then_some(t);
        }
        // Along the ray g' = side·(d_y − ∇h·d_xz) lies within side·d_y ± slope·|d_xz|.
        let across = self.slope * DVec2::new(d.x, d.z).length();
        let mut ga = g(ta);
        if ga <= 0.0 {
            return Some(ta);
        }
        // Moving away from the surface faster than any wave rises: g only grows. (Most
        // refracted photons, checked for leaving the water again, end here.)
        if side * d.y - across >= 0.0 {
            return None;
        }
        // Moving towards it faster than any wave recedes: g only falls, so the slab's far
        // side brackets the one root.
        if side * d.y + across < 0.0 {
            let gb = g(tb);
            return (gb <= 0.0).then(|| refine(&g, ta, ga, tb, gb));
        }
        // Otherwise march: g is Lipschitz along the ray with constant |d_y| + slope·|d_xz|,
        // so a step of g/L cannot reach a root.
        let lipschitz = d.y.abs() + across;
        for _ in 0..MAX_MARCH_STEPS {
            if ta >= tb {
                return None;
            }
            let next = (ta + (ga / lipschitz).max(MIN_STEP)).min(tb);
            let gn = g(next);
            if gn <= 0.0 {
                return Some(refine(&g, ta, ga, next, gn));
            }
            (ta, ga) = (next, gn);
        }
        None
    }
}

/// Illinois regula falsi on a bracket g(a) > 0 ≥ g(b); returns a point within
/// `ROOT_TOLERANCE` of the sign change, on its far side (g ≤ 0).
fn refine(g: &impl Fn(f64) -> f64, mut a: f64, mut ga: f64, mut b: f64, mut gb: f64) -> f64 {
    let mut kept = 0i8;
    for _ in 0..100 {
        if b - a <= ROOT_TOLERANCE {
            break;
        }
        let mut t = a + (b - a) * ga / (ga - gb);
        // Keep strictly inside; fall back to bisection when the secant sits on an end.
        if !(t > a && t < b) {
            t = 0.5 * (a + b);
        }
        let gt = g(t);
        if gt == 0.0 {
            return t;
        }
        if gt > 0.0 {
            (a, ga) = (t, gt);
            if kept == -1 {
                gb *= 0.5;
            }
            kept = -1;
        } else {
            (b, gb) = (t, gt);
            if kept == 1 {
                ga *= 0.5;
            }
            kept = 1;
        }
    }
    b
}

/// Largest |∇| of the noise texture's bilinear interpolant, per unit of uv: the largest
/// value step between neighbouring texels per axis, times the texels per unit.
fn noise_lipschitz(noise: &NoiseTexture) -> f64 {
    let n = noise.size as usize;
    let v = |x: usize, y: usize| noise.texels[(y % n) * n + (x % n)][0] as f64;
    let (mut dx, mut dy) = (0.0f64, 0.0f64);
    for y in 0..n {
        for x in 0..n {
            dx = dx.max((v(x + 1, y) - v(x, y)).abs());
            dy = dy.max((v(x, y + 1) - v(x, y)).abs());
        }
    }
    (dx * dx + dy * dy).sqrt() * n as f64
}

/// Refraction of unit `i` at unit normal `n` (facing against `i`) with `eta` = n₁/n₂;
/// `None` on total internal reflection. Snell's law in vector form, as GLSL `refract`.
pub fn refract(i: DVec3, n: DVec3, eta: f64) -> Option<DVec3> {
    let c = n.dot(i);
    let k = 1.0 - eta * eta * (1.0 - c * c);
    (k >= 0.0).then(|| (eta * i - (eta * c + k.sqrt()) * n).normalize())
}

/// Unpolarised Fresnel transmittance from a medium of index 1 into one of index `n`, at
/// incidence cosine `cos_i` (GLSL `fresnel_transmittance`, in f64).
pub fn fresnel_transmittance(cos_i: f64, n: f64) -> f64 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin_t2 = (1.0 - cos_i * cos_i) / (n * n);
    if sin_t2 >= 1.0 {
        return 0.0;
    }
    let cos_t = (1.0 - sin_t2).sqrt();
    let rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    let rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
    1.0 - 0.5 * (rs * rs + rp * rp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::WaterModel;
    use crate::shader_math;

    fn water() -> Water {
        Water {
            model: WaterModel::CircularCosine,
            level: 0.2,
            amplitude: 0.05,
            wavelength: 0.9,
            speed: 0.7,
            noise_amplitude: 0.03,
            noise_scale: 3.0,
            center: Vec2::new(0.3, -0.2),
            extent_min: Vec2::splat(-5.0),
            extent_max: Vec2::splat(5.0),
            ior: 1.333,
        }
    }

    #[test]
    fn crossings_lie_on_the_surface_and_are_the_first() {
        let noise = NoiseTexture::generate();
        let s = Surface::new(&water(), &noise, 2.5);
        for k in 0..200 {
            let f = k as f64;
            let o = DVec3::new((f * 0.37).sin() * 3.0, 1.0, (f * 0.73).cos() * 3.0);
            // Down to 5° above the horizon: long grazing paths through the slab.
            let elevation = 0.09 + 1.4 * (f * 0.618).fract();
            let az = f * 2.4;
            let d = DVec3::new(elevation.cos() * az.cos(), -elevation.sin(), elevation.cos() * az.sin());
            let t = s.crossing(o, d, 0.0, 100.0, true).expect("a downward ray crosses");
            assert!(s.above(o + t * d).abs() < 1e-6, "ray {k}: off the surface by {}", s.above(o + t * d));
            // Nothing before it: a dense scan stays above.
            for j in 0..2000 {
                let u = t * j as f64 / 2000.0;
                assert!(s.above(o + u * d) > -1e-6, "ray {k}: under water at {u} before the crossing at {t}");
            }
            // And back up from below.
            let p = o + (t + 0.3) * d;
            if s.above(p) < 0.0 {
                let up = s.crossing(p, -d, 0.0, 100.0, false).expect("back out");
                assert!(up <= 0.3 + 1e-6, "ray {k}: exit at {up}");
            }
        }
    }

    #[test]
    fn optics_match_the_twin() {
        for k in 0..50 {
            let c = k as f64 / 49.0;
            let (a, b) = (fresnel_transmittance(c, 1.333), shader_math::fresnel_transmittance(c as f32, 1.333) as f64);
            assert!((a - b).abs() < 1e-6, "{c}: {a} vs {b}");
            let i = DVec3::new((1.0 - c * c).sqrt(), -c.max(1e-3), 0.2).normalize();
            let n = DVec3::new(0.1, 1.0, -0.05).normalize();
            let r = refract(i, n, 1.0 / 1.333).unwrap();
            let t = shader_math::refract(i.as_vec3(), n.as_vec3(), 1.0 / 1.333).normalize();
            assert!((r - t.as_dvec3()).length() < 1e-5, "{r} vs {t}");
        }
        assert!(refract(DVec3::new(0.9, 0.1, 0.0).normalize(), DVec3::NEG_Y, 1.333).is_none());
    }
}
