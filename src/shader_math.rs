//! Rust twin of `glsl/shared/shader_math.glsl`: the same formulas, for CPU tests and (later) the
//! reference renderer. Change both together.

use glam::{Mat2, UVec2, Vec2, Vec2Swizzles, Vec3, Vec3Swizzles};
use std::f32::consts::PI;

/// The photon passes' subdivision bounds are part of the shader interface (`shader_abi::limits`).
pub use crate::shader_abi::limits::{
    FOOTPRINT_MAX_SUBDIVISION, GODRAY_FOOTPRINT_MAX_SUBDIVISION, GODRAY_MAX_SUBDIVISION, MAX_SUBDIVISION,
    TRIANGLE_MAX_SUBDIVISION,
};

/// See `photon_grid_uv` in shader_math.glsl.
pub fn photon_grid_uv(cell: UVec2, sub: UVec2, subdiv: u32, grid: UVec2) -> Vec2 {
    (cell.as_vec2() + (sub.as_vec2() + 0.5) / subdiv as f32) / grid.as_vec2()
}

/// See `caustic_grid_cell` in caustic_splat.glsl: the coarse cell of draw invocation
/// `invocation` on the caustic grid of N/k × N·k cells (`grid` = N, `aspect` = k,
/// `FrameUniforms::caustic_grid_aspect`), with the grid's cells per axis; `None` for the last
/// row's leftover invocations.
pub fn caustic_grid_cell(invocation: UVec2, grid: u32, aspect: f32) -> (Option<UVec2>, UVec2) {
    let columns = ((grid as f32 / aspect).round() as u32).clamp(1, grid * grid);
    let cells = UVec2::new(columns, grid * grid / columns);
    let number = invocation.y * grid + invocation.x;
    let cell = UVec2::new(number % columns, number / columns);
    ((cell.y < cells.y).then_some(cell), cells)
}

/// See `caustic_grid_photon_uv` in caustic_splat.glsl.
pub fn caustic_grid_photon_uv(cell: UVec2, sub: UVec2, subdivision: u32, photons_per_axis: Vec2) -> Vec2 {
    ((cell * subdivision + sub).as_vec2() + 0.5) / photons_per_axis
}

/// See `demo_wave_gradient` in shader_math.glsl.
pub fn demo_wave_gradient(uv: Vec2, t: f32) -> Vec2 {
    let k1 = Vec2::new(7.0, 3.0) * 2.0 * PI;
    let k2 = Vec2::new(-4.0, 9.0) * 2.0 * PI;
    k1 * (k1.dot(uv) + 1.3 * t).cos() / k1.dot(k1) + k2 * (k2.dot(uv) + 0.9 * t).cos() / k2.dot(k2)
}

// ---------------------------------------------------------------------------------------
// Water surface (GLSL: shader_math.glsl, "Water surface").

/// GLSL `WATER_CIRCULAR_COSINE` / `WATER_AXIS_COSINE_NOISE`.
pub const WATER_CIRCULAR_COSINE: i32 = 0;
pub const WATER_AXIS_COSINE_NOISE: i32 = 1;

/// The water's parameters: the scene's `Water`, which the frame uniforms carry to GLSL's
/// `WaterParams` (the model as `WATER_*`).
pub use crate::scene::{Water as WaterParams, WaterModel};

impl WaterModel {
    /// GLSL `WATER_CIRCULAR_COSINE` / `WATER_AXIS_COSINE_NOISE`.
    pub fn glsl_id(self) -> i32 {
        match self {
            WaterModel::CircularCosine => WATER_CIRCULAR_COSINE,
            WaterModel::AxisCosineNoise => WATER_AXIS_COSINE_NOISE,
        }
    }

    pub fn from_glsl_id(id: i32) -> Self {
        if id == WATER_CIRCULAR_COSINE {
            WaterModel::CircularCosine
        } else {
            WaterModel::AxisCosineNoise
        }
    }
}

/// The tileable noise texture: (value, d/du, d/dv) per texel, rows from v = 0. The same
/// data is uploaded to the GPU, so both sides sample identical texels.
#[derive(Clone, Debug)]
pub struct NoiseTexture {
    pub size: u32,
    pub texels: Vec<[f32; 4]>,
}

/// Side of the noise texture, texels.
pub const NOISE_SIZE: u32 = 128;

impl NoiseTexture {
    /// Three octaves of periodic gradient noise (Perlin's improved noise: quintic fade,
    /// hashed gradients) with analytic derivatives, values roughly in [-1, 1].
    pub fn generate() -> Self {
        let size = NOISE_SIZE;
        let mut texels = Vec::with_capacity((size * size) as usize);
        for j in 0..size {
            for i in 0..size {
                let uv = Vec2::new((i as f32 + 0.5) / size as f32, (j as f32 + 0.5) / size as f32);
                let mut v = 0.0;
                let mut g = Vec2::ZERO;
                for (octave, (cells, weight)) in [(8u32, 0.6f32), (16, 0.3), (32, 0.15)].into_iter().enumerate() {
                    let (n, dn) = periodic_gradient_noise(uv * cells as f32, cells, octave as u32);
                    v += weight * n;
                    g += weight * dn * cells as f32;
                }
                texels.push([v, g.x, g.y, 0.0]);
            }
        }
        Self { size, texels }
    }

    fn texel(&self, x: i32, y: i32) -> Vec3 {
        let n = self.size as i32;
        let (x, y) = (x.rem_euclid(n), y.rem_euclid(n));
        let t = self.texels[(y * n + x) as usize];
        Vec3::new(t[0], t[1], t[2])
    }

    /// GLSL `sample_noise`: bilinear with wrap-around, texel centres at (i + 0.5)/size.
    pub fn sample(&self, uv: Vec2) -> Vec3 {
        let p = (uv - uv.floor()) * self.size as f32 - 0.5;
        let f = p - p.floor();
        let (x0, y0) = (p.x.floor() as i32, p.y.floor() as i32);
        let bottom = self.texel(x0, y0).lerp(self.texel(x0 + 1, y0), f.x);
        let top = self.texel(x0, y0 + 1).lerp(self.texel(x0 + 1, y0 + 1), f.x);
        bottom.lerp(top, f.y)
    }
}

/// Hash of a lattice point to one of 8 unit gradients.
fn lattice_gradient(x: u32, y: u32, seed: u32) -> Vec2 {
    let mut h = x.wrapping_mul(0x8da6_b343) ^ y.wrapping_mul(0xd816_3841) ^ seed.wrapping_mul(0xcb1a_b31f);
    h ^= h >> 13;
    h = h.wrapping_mul(0x5bd1_e995);
    h ^= h >> 15;
    // 0.3927 is the generator's fixed offset of the eight gradient directions, not π/8 to be
    // rounded to it: a different value changes every water surface, and with it the cached
    // references and the figures measured against them.
    #[allow(clippy::approx_constant)]
    let a = (h % 8) as f32 * std::f32::consts::FRAC_PI_4 + 0.3927;
    Vec2::new(a.cos(), a.sin())
}

/// Gradient noise at `p` on a lattice that repeats every `period` cells; returns the value
/// and its gradient with respect to `p`.
fn periodic_gradient_noise(p: Vec2, period: u32, seed: u32) -> (f32, Vec2) {
    let cell = p.floor();
    let f = p - cell;
    let (cx, cy) = (cell.x as i64, cell.y as i64);
    let wrap = |c: i64| c.rem_euclid(period as i64) as u32;
    let fade = |t: f32| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let dfade = |t: f32| 30.0 * t * t * (t * (t - 2.0) + 1.0);
    let corner = |dx: i64, dy: i64| {
        let g = lattice_gradient(wrap(cx + dx), wrap(cy + dy), seed);
        let d = f - Vec2::new(dx as f32, dy as f32);
        (g.dot(d), g)
    };
    let (v00, g00) = corner(0, 0);
    let (v10, g10) = corner(1, 0);
    let (v01, g01) = corner(0, 1);
    let (v11, g11) = corner(1, 1);
    let (u, v) = (fade(f.x), fade(f.y));
    let (du, dv) = (dfade(f.x), dfade(f.y));
    let value = v00 + u * (v10 - v00) + v * (v01 - v00) + u * v * (v00 - v10 - v01 + v11);
    let grad = g00
        + u * (g10 - g00)
        + v * (g01 - g00)
        + u * v * (g00 - g10 - g01 + g11)
        + Vec2::new(du * (v10 - v00 + v * (v00 - v10 - v01 + v11)), dv * (v01 - v00 + u * (v00 - v10 - v01 + v11)));
    // Scaled so the value spans about [-1, 1] (2-D gradient noise peaks near ±0.7).
    (value * 1.4, grad * 1.4)
}

/// The water's phase at time `t` (GLSL `phase`, uniforms `water4`): the waves' phase
/// k·speed·t modulo 2π and the noise's drift (0.6, 0.8)·speed·t / noise_scale modulo 1 tile,
/// reduced in double precision so the surface keeps its shape at late times.
pub fn water_phase(w: &WaterParams, t: f32) -> Vec3 {
    let (t, speed) = (t as f64, w.speed as f64);
    let k = std::f64::consts::TAU / w.wavelength as f64;
    let wave = (k * speed * t).rem_euclid(std::f64::consts::TAU);
    let drift = speed * t / w.noise_scale as f64;
    Vec3::new(wave as f32, (0.6 * drift).rem_euclid(1.0) as f32, (0.8 * drift).rem_euclid(1.0) as f32)
}

/// GLSL `water_noise_uv`.
pub fn water_noise_uv(w: &WaterParams, xz: Vec2, t: f32) -> Vec2 {
    let phase = water_phase(w, t);
    xz / w.noise_scale + Vec2::new(phase.y, phase.z)
}

/// GLSL `water_height_grad`: (height above the mean plane, dh/dx, dh/dz). Takes the time;
/// the GLSL takes the phase `water_phase` computes from it.
pub fn water_height_grad(w: &WaterParams, noise: &NoiseTexture, xz: Vec2, t: f32) -> Vec3 {
    let k = 2.0 * PI / w.wavelength;
    let phase_t = water_phase(w, t).x;
    let mut hg = if w.model == WaterModel::CircularCosine {
        let d = xz - w.center;
        let r = d.length();
        let ph = k * r - phase_t;
        let dir = if r > 1e-6 { d / r } else { Vec2::ZERO };
        let g = -w.amplitude * k * ph.sin() * dir;
        Vec3::new(w.amplitude * ph.cos(), g.x, g.y)
    } else {
        let ph = k * xz.x - phase_t;
        Vec3::new(w.amplitude * ph.cos(), -w.amplitude * k * ph.sin(), 0.0)
    };
    let n = noise.sample(water_noise_uv(w, xz, t));
    hg.x += w.noise_amplitude * n.x;
    let s = w.noise_amplitude / w.noise_scale;
    hg.y += s * n.y;
    hg.z += s * n.z;
    hg
}

/// GLSL `mod` (x − y·floor(x/y)), which differs from Rust's `%` for negative x.
pub fn glsl_mod(x: f32, y: f32) -> f32 {
    x - y * (x / y).floor()
}

/// GLSL `water_normal_from_grad`.
pub fn water_normal_from_grad(grad: Vec2) -> Vec3 {
    Vec3::new(-grad.x, 1.0, -grad.y).normalize()
}

/// GLSL `water_covers`.
pub fn water_covers(w: &WaterParams, xz: Vec2) -> bool {
    xz.cmpge(w.extent_min).all() && xz.cmple(w.extent_max).all()
}

/// GLSL `WATER_MAX_MARCH_STEPS`, `WATER_REFINE_STEPS`, `WATER_REFINE_RESIDUAL` and
/// `WATER_NOISE_FEATURE`.
pub const WATER_MAX_MARCH_STEPS: u32 = 64;
pub const WATER_REFINE_STEPS: u32 = 8;
pub const WATER_REFINE_RESIDUAL: f32 = 1e-4;
pub const WATER_NOISE_FEATURE: f32 = 1.0 / 16.0;
/// GLSL `WATER_NOISE_SLOPE`: the steepest slope of the noise texture's surface per unit of
/// noise amplitude, in tiles (`tests::the_noise_slope_bound_holds` measures it).
pub const WATER_NOISE_SLOPE: f32 = 28.1;

/// GLSL `water_slope_bound`: the surface's steepest slope.
pub fn water_slope_bound(w: &WaterParams) -> f32 {
    w.amplitude.abs() * 2.0 * std::f32::consts::PI / w.wavelength
        + w.noise_amplitude.abs() / w.noise_scale * WATER_NOISE_SLOPE
}

/// GLSL `water_deviation_bound`: the most the waves turn a ray falling along unit direction `d`
/// away from its refraction in flat water, rad, from the normals tilted by the slope bound
/// towards, away from and across the ray's horizontal direction; a right angle where the
/// waves are steep enough to meet the ray edge-on.
pub fn water_deviation_bound(w: &WaterParams, d: Vec3) -> f32 {
    let tilt = water_slope_bound(w).atan();
    if tilt >= (-d.y).atan2(Vec2::new(d.x, d.z).length()) {
        return std::f32::consts::FRAC_PI_2;
    }
    let eta = 1.0 / w.ior;
    let flat_refracted = d.refract(Vec3::Y, eta);
    let h = if d.x * d.x + d.z * d.z > 1e-12 { Vec2::new(d.x, d.z).normalize() } else { Vec2::X };
    let towards = Vec3::new(h.x, 0.0, h.y);
    let across = Vec3::new(-h.y, 0.0, h.x);
    [towards, -towards, across, -across]
        .into_iter()
        .map(|t| d.refract(tilt.cos() * Vec3::Y + tilt.sin() * t, eta).normalize())
        .map(|r| r.dot(flat_refracted).clamp(-1.0, 1.0).acos())
        .fold(0.0, f32::max)
}

/// Whether Newton's search alone finds the water crossing of every ray along unit direction
/// `d` that starts above the waves: the ray falls more than twice as steeply as the surface
/// can rise along it (`water_intersect`'s choice per ray), with 1 % to spare, so that the
/// shader's own test of each ray in its own rounding agrees. A directional light's photon
/// rays all share its direction: where this holds for it, the photon passes compile only
/// Newton's search (GLSL `WATER_NEWTON_ONLY`, photon_cast.glsl), the one each ray would take.
pub fn newton_finds_every_crossing(w: &WaterParams, d: Vec3) -> bool {
    d.y < 0.0 && water_slope_bound(w) * Vec2::new(d.x, d.z).length() <= -0.5 * d.y * 0.99
}

/// GLSL `ITERATION_RESIDUAL` (photon_cast.glsl): the image-space iteration stops at this
/// residual per metre of distance.
pub const ITERATION_RESIDUAL: f32 = 1e-5;

/// GLSL `CAUSTIC_DEPTH_TOLERANCE` (photon_visibility.glsl): how far behind the scene's depth a
/// caustic splat may lie and still count as on its receiver, relative and in metres
/// (`behind_scene`: depth > scene·(1 + t) + t).
pub const CAUSTIC_DEPTH_TOLERANCE: f32 = 0.02;

/// GLSL `water_height_above_surface`.
fn water_height_above_surface(w: &WaterParams, noise: &NoiseTexture, o: Vec3, d: Vec3, t: f32, time: f32) -> f32 {
    let p = o + t * d;
    p.y - w.level - water_height_grad(w, noise, p.xz(), time).x
}

/// GLSL `water_intersect`: ray parameter of the hit with the surface, negative for none.
/// Newton's method from the mean plane's crossing where the ray falls more than twice as
/// steeply as the surface can rise along it (one crossing); otherwise a march through the
/// slab the waves fill, then Illinois regula falsi in the step that crosses. A result off the
/// surface by more than 1 % of the waves' height is a miss. The GLSL runs both searches in
/// one loop (see there why); this makes the same evaluations in the same order.
pub fn water_intersect(w: &WaterParams, noise: &NoiseTexture, o: Vec3, d: Vec3, time: f32) -> f32 {
    if d.y >= -1e-6 {
        return -1.0;
    }
    let bound = w.amplitude.abs() + w.noise_amplitude.abs();
    let t_top = ((w.level + bound - o.y) / d.y).max(0.0);
    let t_bottom = (w.level - bound - o.y) / d.y;
    if t_bottom < t_top {
        return -1.0;
    }
    if bound == 0.0 {
        return t_bottom;
    }
    let ray = SlabRay { o, d, time, t_top, t_bottom, bound };
    if o.y > w.level + bound && water_slope_bound(w) * Vec2::new(d.x, d.z).length() <= -0.5 * d.y {
        return water_intersect_newton(w, noise, &ray);
    }
    water_intersect_marched(w, noise, &ray)
}

/// A ray through the waves' slab, as `water_intersect`'s two searches take it: origin,
/// direction, the water's time, where it enters and leaves the slab, and the slab's half
/// height (the waves' and the noise's amplitudes).
#[derive(Clone, Copy)]
struct SlabRay {
    o: Vec3,
    d: Vec3,
    time: f32,
    t_top: f32,
    t_bottom: f32,
    bound: f32,
}

/// `water_intersect`'s Newton steps on the height above the surface, kept inside the bracket
/// the evaluations leave (a bisection where a step would leave it).
fn water_intersect_newton(w: &WaterParams, noise: &NoiseTexture, ray: &SlabRay) -> f32 {
    let SlabRay { o, d, time, t_top, t_bottom, bound } = *ray;
    let (mut ta, mut tb) = (t_top, t_bottom);
    // GLSL clamp: min(max(x, lo), hi).
    let mut t = ((w.level - o.y) / d.y).max(t_top).min(t_bottom);
    let (mut best_t, mut best_f) = (-1.0f32, 1e30f32);
    for refinement in 0..=WATER_REFINE_STEPS {
        let p = o + t * d;
        let hg = water_height_grad(w, noise, p.xz(), time);
        let f = p.y - w.level - hg.x;
        if f.abs() < best_f {
            (best_t, best_f) = (t, f.abs());
        }
        if best_f <= WATER_REFINE_RESIDUAL * bound || refinement == WATER_REFINE_STEPS {
            break;
        }
        if f > 0.0 {
            ta = t;
        } else {
            tb = t;
        }
        let next = t - f / (d.y - (hg.y * d.x + hg.z * d.z));
        t = if next > ta && next < tb { next } else { 0.5 * (ta + tb) };
    }
    if best_f <= 0.01 * bound + 1e-4 {
        best_t
    } else {
        -1.0
    }
}

/// `water_intersect`'s march and refinement.
fn water_intersect_marched(w: &WaterParams, noise: &NoiseTexture, ray: &SlabRay) -> f32 {
    let SlabRay { o, d, time, t_top, t_bottom, bound } = *ray;
    let f = |t: f32| water_height_above_surface(w, noise, o, d, t, time);
    let (mut ta, mut fa) = (t_top, f(t_top));
    if fa <= 0.0 {
        return ta;
    }
    let feature = (if w.amplitude > 0.0 { w.wavelength } else { 1e30 }).min(if w.noise_amplitude > 0.0 {
        w.noise_scale * WATER_NOISE_FEATURE
    } else {
        1e30
    });
    let horizontal = (t_bottom - t_top) * Vec2::new(d.x, d.z).length();
    let steps = (4.0 * horizontal / feature).ceil().clamp(8.0, WATER_MAX_MARCH_STEPS as f32) as u32;
    let dt = (t_bottom - t_top) / steps as f32;
    let (mut tb, mut fb) = (t_bottom, f(t_bottom));
    for i in 1..steps {
        let t = t_top + i as f32 * dt;
        let ft = f(t);
        if ft <= 0.0 {
            (tb, fb) = (t, ft);
            break;
        }
        (ta, fa) = (t, ft);
    }
    if fb > 0.0 {
        // Rounding at the slab's floor, which lies at or below the surface (see the GLSL).
        return if fb <= 0.01 * bound + 1e-4 { tb } else { -1.0 };
    }
    // The evaluated point nearest the surface, not the last estimate (see the GLSL).
    let (mut best_t, mut best_f) = (tb, fb.abs());
    let mut kept = 0;
    for _ in 0..WATER_REFINE_STEPS {
        let t = ta + (tb - ta) * fa / (fa - fb);
        let ft = f(t);
        if ft.abs() < best_f {
            (best_t, best_f) = (t, ft.abs());
        }
        if best_f <= WATER_REFINE_RESIDUAL * bound {
            return best_t; // near enough the surface (see the GLSL)
        }
        if ft > 0.0 {
            (ta, fa) = (t, ft);
            if kept == -1 {
                fb *= 0.5;
            }
            kept = -1;
        } else {
            (tb, fb) = (t, ft);
            if kept == 1 {
                fa *= 0.5;
            }
            kept = 1;
        }
    }
    let t = ta + (tb - ta) * fa / (fa - fb);
    let ft = f(t);
    if ft.abs() < best_f {
        (best_t, best_f) = (t, ft.abs());
    }
    if best_f <= 0.01 * bound + 1e-4 {
        best_t
    } else {
        -1.0
    }
}

/// GLSL `refract(i, n, eta)`: zero vector on total internal reflection.
pub fn refract(i: Vec3, n: Vec3, eta: f32) -> Vec3 {
    let k = 1.0 - eta * eta * (1.0 - n.dot(i) * n.dot(i));
    if k < 0.0 {
        Vec3::ZERO
    } else {
        eta * i - (eta * n.dot(i) + k.sqrt()) * n
    }
}

/// GLSL `water_fog_radiance` (underwater_shading.glsl): the radiance the water sends towards the
/// viewer from in-scattered ambient light, per channel: E_ambient · σs / γ / 4π (γ ≥ 1e-3).
pub fn water_fog_radiance(ambient_irradiance: f32, gamma: Vec3, scattering: f32) -> Vec3 {
    ambient_irradiance * scattering / gamma.max(Vec3::splat(1e-3)) / (4.0 * std::f32::consts::PI)
}

/// GLSL `fresnel_transmittance`.
pub fn fresnel_transmittance(cos_i: f32, n: f32) -> f32 {
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

/// GLSL `henyey_greenstein`.
pub fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denom = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * PI * denom * denom.sqrt())
}

/// GLSL `regulated_point_size`.
pub fn regulated_point_size(d_view: f32, z_near: f32, z_far: f32, s_min: f32, s_max: f32) -> f32 {
    let a = s_max - z_far * (s_max - s_min) / (z_far - z_near);
    let b = z_near * z_far * (s_max - s_min) / (z_far - z_near);
    a + b / d_view.clamp(z_near, z_far)
}

// ---------------------------------------------------------------------------------------
/// GLSL `light_map_point` (frame.glsl): where the light's maps put world point `p`. Above the
/// water, `p`; below it, `p` slid back along `refracted` (the light's direction under flat
/// water) to the level and on along the light's own direction `light_axis`: the point of the
/// straight light ray that the map's texel of `p`'s photons holds, at the same path length.
pub fn light_map_point(p: Vec3, water_level: f32, light_axis: Vec3, refracted: Vec3) -> Vec3 {
    if !(refracted.y < -1e-3) {
        return p;
    }
    let along = (water_level - p.y).max(0.0) / -refracted.y;
    p + along * (light_axis - refracted)
}

// Caustic slivers (GLSL: shader_math.glsl, "Caustic slivers").
const FOOTPRINT_OFFSET_STEPS: f32 = 128.0;
const FOOTPRINT_AXIS_CODES: f32 = 2.0 * FOOTPRINT_OFFSET_STEPS;
const FOOTPRINT_SIDE_STEPS: f32 = 16.0;

/// GLSL `sliver_footprint_code`: the code of a sliver's footprint, a square of side `side`
/// pixels centred on `c` (target pixels; pixel edges at integers).
pub fn sliver_footprint_code(c: Vec2, side: f32) -> f32 {
    let edge = (c + 0.5).floor();
    let half = FOOTPRINT_OFFSET_STEPS / 2.0;
    let offset = ((c - edge) * FOOTPRINT_OFFSET_STEPS).round().clamp(Vec2::splat(-half), Vec2::splat(half - 1.0));
    let parity = Vec2::new(glsl_mod(edge.x, 2.0), glsl_mod(edge.y, 2.0));
    let axis = parity * FOOTPRINT_OFFSET_STEPS + offset + half;
    let s = (side * FOOTPRINT_SIDE_STEPS).round().clamp(1.0, FOOTPRINT_SIDE_STEPS);
    1.0 + axis.x + axis.y * FOOTPRINT_AXIS_CODES + (s - 1.0) * FOOTPRINT_AXIS_CODES * FOOTPRINT_AXIS_CODES
}

/// GLSL `sliver_footprint_weight`: the share of the footprint `code` that the pixel whose
/// centre is `pixel` takes.
pub fn sliver_footprint_weight(pixel: Vec2, code: f32) -> f32 {
    let k = code.round() - 1.0;
    let per_side = FOOTPRINT_AXIS_CODES * FOOTPRINT_AXIS_CODES;
    let s = ((k / per_side).floor() + 1.0) / FOOTPRINT_SIDE_STEPS;
    let k = glsl_mod(k, per_side);
    let axis = Vec2::new(glsl_mod(k, FOOTPRINT_AXIS_CODES), (k / FOOTPRINT_AXIS_CODES).floor());
    let parity = (axis / FOOTPRINT_OFFSET_STEPS).floor();
    let offset = (axis - parity * FOOTPRINT_OFFSET_STEPS - FOOTPRINT_OFFSET_STEPS / 2.0) / FOOTPRINT_OFFSET_STEPS;
    let overlap = |pixel: f32, parity: f32, offset: f32| {
        let above: f32 = if glsl_mod(pixel.floor(), 2.0) == parity { 1.0 } else { 0.0 };
        let (lo, hi) = (above - 1.0, above);
        (hi.min(offset + 0.5 * s) - lo.max(offset - 0.5 * s)).max(0.0) / s
    };
    overlap(pixel.x, parity.x, offset.x) * overlap(pixel.y, parity.y, offset.y)
}

/// GLSL `STRIP_CODE_MIDDLE` and `STRIP_CODE_SCALE` (shader_math.glsl, after the slivers'
/// footprints): a caustic strip's code across it, between the triangles' 0 and the
/// footprints' codes above 0.5.
const STRIP_CODE_MIDDLE: f32 = 0.25;
const STRIP_CODE_SCALE: f32 = 0.125;

/// GLSL `strip_across_code`: the code of distance `d` (pixels, −1 to 1) from a caustic
/// strip's middle line.
pub fn strip_across_code(d: f32) -> f32 {
    STRIP_CODE_MIDDLE + STRIP_CODE_SCALE * d
}

/// GLSL `is_strip_code`: whether a fragment's code is a strip's.
pub fn is_strip_code(code: f32) -> bool {
    (code - STRIP_CODE_MIDDLE).abs() < 1.5 * STRIP_CODE_SCALE
}

/// GLSL `strip_across`: the distance from the strip's middle that `code` carries.
pub fn strip_across(code: f32) -> f32 {
    (code - STRIP_CODE_MIDDLE) / STRIP_CODE_SCALE
}

/// GLSL `strip_weight`: the tent 1 − |d| a strip's pixel takes.
pub fn strip_weight(code: f32) -> f32 {
    (1.0 - strip_across(code).abs()).max(0.0)
}

// Footprint hats (GLSL: shader_math.glsl, "Footprint hats").

/// GLSL `FOOTPRINT_HAT_SAMPLES`: the samples per pixel axis at which a footprint point's hat
/// is read.
pub const FOOTPRINT_HAT_SAMPLES: f32 = 4.0;

/// GLSL `footprint_hat_basis`: the hat's basis for a photon's spans to its grid neighbours on
/// the target (columns, pixels), each singular value below 1 / FOOTPRINT_HAT_SAMPLES raised
/// to it along its own direction.
pub fn footprint_hat_basis(spans: Mat2) -> Mat2 {
    let least = 1.0 / FOOTPRINT_HAT_SAMPLES;
    let frobenius = (spans.x_axis.length_squared() + spans.y_axis.length_squared()).sqrt();
    if spans.determinant().abs() >= least * frobenius {
        return spans;
    }
    let gram = spans.transpose() * spans;
    let half_trace = 0.5 * (gram.x_axis.x + gram.y_axis.y);
    let det = gram.x_axis.x * gram.y_axis.y - gram.y_axis.x * gram.y_axis.x;
    let spread = (half_trace * half_trace - det).max(0.0).sqrt();
    let sigma = Vec2::new(half_trace + spread, (half_trace - spread).max(0.0)).map(f32::sqrt);
    let a = Vec2::new(half_trace + spread - gram.y_axis.y, gram.y_axis.x);
    let b = Vec2::new(gram.y_axis.x, half_trace + spread - gram.x_axis.x);
    let longer = if a.dot(a) >= b.dot(b) { a } else { b };
    let v1 = if longer.dot(longer) > 0.0 { longer.normalize() } else { Vec2::X };
    let v2 = v1.perp();
    let u1 = if sigma.x > 0.0 { spans * v1 / sigma.x } else { Vec2::X };
    let u2 = if sigma.y > 1e-6 * sigma.x { spans * v2 / sigma.y } else { u1.perp() };
    let raise = sigma.max(Vec2::splat(least)) - sigma;
    let outer = |u: Vec2, v: Vec2| Mat2::from_cols(u * v.x, u * v.y);
    spans + outer(u1, v1) * raise.x + outer(u2, v2) * raise.y
}

/// GLSL `footprint_hat_share`: the share of a hat (basis inverse `to_lattice`) that a pixel
/// whose centre lies at `lattice` on the hat's (s, t) takes, its mean over the pixel's samples.
/// For the pixel centred on `pixel` and the hat centred on `centre`, `lattice` is
/// `to_lattice * (pixel - centre)`.
pub fn footprint_hat_share(lattice: Vec2, to_lattice: Mat2) -> f32 {
    let n = FOOTPRINT_HAT_SAMPLES as usize;
    let (step_x, step_y) = (to_lattice.x_axis / FOOTPRINT_HAT_SAMPLES, to_lattice.y_axis / FOOTPRINT_HAT_SAMPLES);
    let first = lattice - 0.5 * (FOOTPRINT_HAT_SAMPLES - 1.0) * (step_x + step_y);
    let mut sum = 0.0;
    for j in 0..n {
        for i in 0..n {
            let tent = (Vec2::ONE - (first + i as f32 * step_x + j as f32 * step_y).abs()).max(Vec2::ZERO);
            sum += tent.x * tent.y;
        }
    }
    sum / (FOOTPRINT_HAT_SAMPLES * FOOTPRINT_HAT_SAMPLES)
}

/// GLSL `footprint_hat_quad_reach`: how far along s and t the quad a footprint point's hat is
/// drawn as reaches (its corners are the lattice points (±s, ±t)), the hat's cell |s|, |t| ≤ 1
/// on the lattice of inverse basis `to_lattice` widened by `pixel_reach` times the pixel's
/// extent in lattice units.
pub fn footprint_hat_quad_reach(to_lattice: Mat2, pixel_reach: f32) -> Vec2 {
    let pixel_extent = Vec2::new(
        to_lattice.x_axis.x.abs() + to_lattice.y_axis.x.abs(),
        to_lattice.x_axis.y.abs() + to_lattice.y_axis.y.abs(),
    );
    Vec2::ONE + pixel_reach * pixel_extent
}

/// GLSL `footprint_hat_samples_reach`: how far from its pixel's centre a footprint hat's
/// farthest sample lies along each pixel axis, (S − 1) / 2S pixels.
pub fn footprint_hat_samples_reach() -> f32 {
    0.5 - 0.5 / FOOTPRINT_HAT_SAMPLES
}

/// GLSL `FOOTPRINT_RECEIVER_SLOPE`: how far off a footprint point's receiver plane, per metre
/// from the photon, a pixel's surface may lie and still show that receiver (on_one_receiver's
/// quarter).
pub const FOOTPRINT_RECEIVER_SLOPE: f32 = 0.25;
/// GLSL `FOOTPRINT_RECEIVER_DEPTH_SLACK`: the least such offset, a share of the pixel's depth.
pub const FOOTPRINT_RECEIVER_DEPTH_SLACK: f32 = 2e-3;

/// GLSL `footprint_pixel_on_receiver`: whether the pixel centred on `pixel`, whose surface has
/// reciprocal view depth `w_scene`, shows the receiver plane of the footprint point whose hat
/// is centred on `centre` (reciprocal view depth `w_centre` there, `w_gradient` per pixel).
pub fn footprint_pixel_on_receiver(
    pixel: Vec2,
    centre: Vec2,
    w_centre: f32,
    w_gradient: Vec2,
    w_scene: f32,
    target_size: Vec2,
    tan_half_fov_y: f32,
) -> bool {
    let w_plane = w_centre + w_gradient.dot(pixel - centre);
    if !(w_plane > 0.0) || !(w_scene > 0.0) {
        return false;
    }
    let tan_half = Vec2::new(tan_half_fov_y * target_size.x / target_size.y, tan_half_fov_y);
    let ndc_slope = w_gradient * 0.5 * target_size;
    let w_at_axis = w_centre + w_gradient.dot(0.5 * target_size - centre);
    let plane_distance = 1.0 / (ndc_slope / tan_half).extend(w_at_axis).length().max(1e-30);
    let ray = ((pixel / target_size * 2.0 - Vec2::ONE) * tan_half).extend(1.0);
    let photon_ray = ((centre / target_size * 2.0 - Vec2::ONE) * tan_half).extend(1.0);
    let off_plane = (w_plane / w_scene - 1.0).abs() * plane_distance;
    let from_photon = (ray / w_scene - photon_ray / w_centre).length();
    off_plane <= FOOTPRINT_RECEIVER_SLOPE * from_photon + FOOTPRINT_RECEIVER_DEPTH_SLACK / w_scene
}

/// GLSL `footprint_receiver_plane`: the receiver plane's reciprocal view depth per target
/// pixel over its value `w_centre` at the photon, from two of its directions' spans on the
/// target and changes of reciprocal depth; None where the plane is seen edge on.
pub fn footprint_receiver_plane(s1: Vec2, s2: Vec2, dw1: f32, dw2: f32, w_centre: f32) -> Option<Vec2> {
    let det = s1.x * s2.y - s1.y * s2.x;
    if !(det.abs() > 1e-6 * (s1.dot(s1) + s2.dot(s2))) {
        return None;
    }
    Some(Vec2::new(dw1 * s2.y - dw2 * s1.y, dw2 * s1.x - dw1 * s2.x) / (det * w_centre))
}

// Photon casting (GLSL: photon_cast.glsl, `cast_photon`).

/// A photon that reached a receiver (GLSL `Photon`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    pub surface: Vec3,
    pub direction: Vec3,
    pub hit: Vec3,
    /// Flux after the surface (Fresnel applied), W.
    pub flux: f32,
    pub travelled: f32,
    /// Its hit was found in the second, steeper light maps.
    pub steep_map: bool,
}

/// GLSL `converged`: whether the iteration's estimate `hit` lies on the receiver stored at
/// its light-map texel (`receiver`, `receiver_normal`; zero normal: none stored). `texel_size`
/// is a map texel's world size at the hit, `light_to_hit` the light's unit direction there.
pub fn converged(
    hit: Vec3,
    receiver: Vec3,
    receiver_normal: Vec3,
    light_to_hit: Vec3,
    dist: f32,
    texel_size: f32,
) -> bool {
    let across_allowed = (3.0 * texel_size).max(0.05 * dist);
    let off = hit - receiver;
    let len_n = receiver_normal.length();
    if !(len_n > 0.5) {
        return off.length() <= across_allowed;
    }
    let n = receiver_normal / len_n;
    let across = off.dot(n).abs();
    let along = (off - off.dot(n) * n).length();
    let facing = n.dot(light_to_hit).abs().max(0.01);
    across <= across_allowed && along <= (3.0 * texel_size / facing).max(0.05 * dist)
}

/// GLSL `onto_receiver_plane`: the iteration's estimate `hit` (`dist` along the refracted ray
/// from `ps`) moved onto the plane of the receiver stored at its texel (`receiver`,
/// `receiver_normal`), where that point is still on the same receiver (`on_receiver`).
pub fn onto_receiver_plane(
    ps: Vec3,
    rt: Vec3,
    hit: Vec3,
    dist: f32,
    receiver: Vec3,
    receiver_normal: Vec3,
    on_receiver: impl Fn(Vec3, f32) -> bool,
) -> (Vec3, f32) {
    let len_n = receiver_normal.length();
    if !(len_n > 0.5) {
        return (hit, dist);
    }
    let n = receiver_normal / len_n;
    let denom = rt.dot(n);
    if denom.abs() <= 1e-3 {
        return (hit, dist);
    }
    let t = (receiver - ps).dot(n) / denom;
    let on_plane = ps + t * rt;
    if t > 0.0 && on_receiver(on_plane, t) {
        (on_plane, t)
    } else {
        (hit, dist)
    }
}

/// GLSL `photon_density_warp` (photon_cast.glsl): grid position `g` ∈ [0, 1]² of the caustic
/// photon grid to the photon window's uv through the inverse cumulative densities of
/// `frame::photon_density` (`rows`: the window's v at grid v = k / SEGMENTS; `columns`: per
/// band of the window's v, the window's u at grid u = k / SEGMENTS, interpolated between the
/// bands' centres so that the warped grid stays continuous), and the area of the photon's
/// warped cell (`half_cell` each side of `g`, along u and along v) over the even grid's.
/// `exchanged` (the uniforms' warp mode 2): the window's u and v, and the grid's, exchange
/// roles, so `rows` gives the window's u and `columns` its v per band of u.
pub fn photon_density_warp(rows: &[f32], columns: &[f32], exchanged: bool, g: Vec2, half_cell: Vec2) -> (Vec2, f32) {
    use crate::shader_abi::{PHOTON_DENSITY_KNOTS as KNOTS, PHOTON_DENSITY_SEGMENTS as SEGMENTS};
    let s = SEGMENTS as f32;
    let lerp_v = |g: f32| {
        let t = g.clamp(0.0, 1.0) * s;
        let k = (t as usize).min(SEGMENTS - 1);
        rows[k] + (rows[k + 1] - rows[k]) * (t - k as f32)
    };
    let lerp_u = |g: f32, v: f32| {
        let band = (v * s - 0.5).clamp(0.0, s - 1.0);
        let j = (band as usize).min(SEGMENTS - 2);
        let t = g.clamp(0.0, 1.0) * s;
        let k = (t as usize).min(SEGMENTS - 1);
        let (a, b) = (j * KNOTS + k, (j + 1) * KNOTS + k);
        let ua = columns[a] + (columns[a + 1] - columns[a]) * (t - k as f32);
        let ub = columns[b] + (columns[b + 1] - columns[b]) * (t - k as f32);
        ua + (ub - ua) * (band - j as f32)
    };
    let (g, half_cell) = if exchanged { (g.yx(), half_cell.yx()) } else { (g, half_cell) };
    let v = lerp_v(g.y);
    let v_span = lerp_v(g.y + half_cell.y) - lerp_v(g.y - half_cell.y);
    let u_span = lerp_u(g.x + half_cell.x, v) - lerp_u(g.x - half_cell.x, v);
    let uv = Vec2::new(lerp_u(g.x, v), v);
    (if exchanged { uv.yx() } else { uv }, u_span * v_span / (4.0 * half_cell.x * half_cell.y))
}

/// Everything `cast_photon` reads: the frame's uniforms, the noise, and the light's
/// receiver maps as read back from the shadow pass: positions (RGBA32F, w = 1 where a
/// receiver) and normals (xyz, zero where none).
pub struct PhotonCaster<'a> {
    pub uniforms: &'a crate::shader_abi::FrameUniforms,
    pub noise: &'a NoiseTexture,
    pub light_map: &'a crate::image_io::HdrImage,
    pub light_normals: &'a crate::image_io::HdrImage,
    /// The second, steeper maps (positions, normals), which the photons the first cannot
    /// place search; None where the frame has none (`FrameUniforms::steep_light_axis` zero).
    pub steep_maps: Option<(&'a crate::image_io::HdrImage, &'a crate::image_io::HdrImage)>,
}

/// How `PhotonCaster::intersect` ended (GLSL `intersect_receivers`' PHOTON_* codes).
enum Intersection {
    Landed(Vec3, f32),
    LeavesMap,
    NotConverged,
}

impl PhotonCaster<'_> {
    fn water(&self) -> WaterParams {
        let u = self.uniforms;
        WaterParams {
            model: WaterModel::from_glsl_id(u.water_model as i32),
            level: u.water_level,
            amplitude: u.wave_amplitude,
            wavelength: u.wavelength,
            speed: u.wave_speed,
            noise_amplitude: u.noise_amplitude,
            noise_scale: u.noise_scale,
            ior: u.ior,
            center: Vec2::from_array(u.wave_center),
            extent_min: Vec2::from_array(u.water_extent_min),
            extent_max: Vec2::from_array(u.water_extent_max),
        }
    }

    /// GLSL `light_map_bend` (frame.glsl).
    fn light_map_bend(&self, steep: bool) -> Vec3 {
        let u = self.uniforms;
        Vec3::from_array(if steep { u.steep_light_axis } else { u.refracted_light_axis })
    }

    /// GLSL `light_map_point` (frame.glsl).
    fn light_map_point(&self, p: Vec3, steep: bool) -> Vec3 {
        let u = self.uniforms;
        light_map_point(p, u.water_level, Vec3::from_array(u.light_axis), self.light_map_bend(steep))
    }

    /// GLSL `light_map_direction` (frame.glsl).
    fn light_map_direction(&self, p: Vec3, steep: bool) -> Vec3 {
        let u = self.uniforms;
        let bend = self.light_map_bend(steep);
        if u.light_is_point > 0.0 {
            (p - Vec3::from_array(u.light_position)).normalize()
        } else if bend.y < -1e-3 && p.y < u.water_level {
            bend
        } else {
            Vec3::from_array(u.light_axis)
        }
    }

    /// GLSL `light_texel`.
    fn light_texel(&self, p: Vec3, steep: bool) -> Option<(u32, u32)> {
        let c =
            glam::Mat4::from_cols_array_2d(&self.uniforms.light_view_proj) * self.light_map_point(p, steep).extend(1.0);
        if c.w <= 0.0 {
            return None;
        }
        let uv = Vec2::new(c.x, c.y) / c.w * 0.5 + 0.5;
        if uv.x < 0.0 || uv.y < 0.0 || uv.x >= 1.0 || uv.y >= 1.0 {
            return None;
        }
        let size = self.uniforms.light_map_size;
        Some(((uv.x * size) as u32, (uv.y * size) as u32))
    }

    /// GLSL `map_receiver` and `map_normal`: the stored receiver (w > 0 where one) and its
    /// normal at a texel of either maps.
    fn receiver(&self, texel: (u32, u32), steep: bool) -> [f32; 4] {
        match (steep, self.steep_maps) {
            (true, Some((positions, _))) => positions.at(texel.0, texel.1),
            _ => self.light_map.at(texel.0, texel.1),
        }
    }

    fn normal(&self, texel: (u32, u32), steep: bool) -> Vec3 {
        let n = match (steep, self.steep_maps) {
            (true, Some((_, normals))) => normals.at(texel.0, texel.1),
            _ => self.light_normals.at(texel.0, texel.1),
        };
        Vec3::new(n[0], n[1], n[2])
    }

    /// GLSL `cast_photon`: the photon at light-space `uv` of a grid with `photons_per_axis.x`
    /// × `.y` photons, or `None` where the shader drops it.
    pub fn cast(&self, uv: Vec2, photons_per_axis: Vec2) -> Option<Photon> {
        let u = self.uniforms;
        let inv = glam::Mat4::from_cols_array_2d(&u.light_inv_view_proj);
        let (window_min, window_size) = (Vec2::from(u.photon_window_min), Vec2::from(u.photon_window_size));
        let mut uv = uv + Vec2::from(u.photon_jitter) / photons_per_axis;
        let mut cell_scale = 1.0;
        if u.photon_density_warp > 0.0 {
            (uv, cell_scale) = photon_density_warp(
                &u.photon_density_rows,
                &u.photon_density_columns,
                u.photon_density_warp > 1.5,
                uv,
                0.5 / photons_per_axis,
            );
        }
        let uv = window_min + uv * window_size;
        let ndc = uv * 2.0 - 1.0;
        let a = inv * glam::Vec4::new(ndc.x, ndc.y, 0.0, 1.0);
        let b = inv * glam::Vec4::new(ndc.x, ndc.y, 1.0, 1.0);
        let o = a.truncate() / a.w;
        let d = (b.truncate() / b.w - o).normalize();
        let w = self.water();
        let time = u.time;
        let t = water_intersect(&w, self.noise, o, d, time);
        if !(t > 0.0) {
            return None;
        }
        let ps = o + t * d;
        if !water_covers(&w, ps.xz()) {
            return None;
        }
        if let Some(texel) = self.light_texel(ps, false) {
            let first = self.receiver(texel, false);
            if first[3] > 0.0 && (Vec3::new(first[0], first[1], first[2]) - o).dot(d) < t - 1e-3 {
                return None;
            }
        }
        let hg = water_height_grad(&w, self.noise, ps.xz(), time);
        let n = water_normal_from_grad(Vec2::new(hg.y, hg.z));
        let cos_i = (-d).dot(n);
        if cos_i <= 0.0 {
            return None;
        }
        let rt = refract(d, n, 1.0 / w.ior);
        if rt == Vec3::ZERO {
            return None;
        }
        let rt = rt.normalize();
        // The first maps, then, for a photon they cannot place, the second (steeper) ones.
        let steep_exists = self.steep_maps.is_some() && u.steep_light_axis[1] < -1e-3;
        let (hit, dist, steep_map) = match self.intersect(ps, rt, false) {
            Intersection::Landed(hit, dist) => (hit, dist, false),
            Intersection::LeavesMap | Intersection::NotConverged if steep_exists => {
                match self.intersect(ps, rt, true) {
                    Intersection::Landed(hit, dist) => (hit, dist, true),
                    Intersection::LeavesMap | Intersection::NotConverged => return None,
                }
            }
            Intersection::LeavesMap | Intersection::NotConverged => return None,
        };
        if hit.y > w.level + w.amplitude.abs() + w.noise_amplitude.abs() {
            return None;
        }
        let n2 = photons_per_axis.x * photons_per_axis.y / (window_size.x * window_size.y);
        let mut flux = u.light_strength * 4.0 * u.light_half_extent[0] * u.light_half_extent[1] / n2 * cell_scale;
        if u.light_is_point > 0.0 {
            let c = d.dot(Vec3::from_array(u.light_axis)).max(0.0);
            flux *= c * c * c;
        }
        let photon = Photon {
            surface: ps,
            direction: rt,
            hit,
            flux: flux * fresnel_transmittance(cos_i, w.ior),
            travelled: dist,
            steep_map,
        };
        (hit.is_finite() && photon.flux.is_finite()).then_some(photon)
    }

    /// GLSL `intersect_receivers`: Shah's iteration against the first maps (`steep`: the
    /// second) from the surface point `ps` along the refracted `rt`. The same results in a
    /// plainer order: the shader tests the blocker above the water with its first guess's read
    /// and keeps its last read for the final estimate, to save lavapipe a projection and a
    /// fetch each (docs/performance.md); here `cast` tests the blocker and the final estimate
    /// is read again.
    fn intersect(&self, ps: Vec3, rt: Vec3, steep: bool) -> Intersection {
        let u = self.uniforms;
        let bottom = ps.y - u.scene_lowest_y;
        let mut dist = if bottom > 1e-3 { bottom / (-rt.y).max(1e-3) } else { 1.0 };
        if let Some(texel) = self.light_texel(ps, steep) {
            let below = self.receiver(texel, steep);
            let depth = ps.y - below[1];
            if below[3] > 0.0 {
                dist = if depth > 1e-3 {
                    depth / (-rt.y).max(1e-3)
                } else {
                    (Vec3::new(below[0], below[1], below[2]) - ps).length().max(1e-3)
                };
            }
        }
        let mut previous: Option<(f32, f32)> = None;
        for _ in 0..u.iterations as i32 {
            let r = self.light_texel(ps + dist * rt, steep).map(|t| self.receiver(t, steep)).unwrap_or([0.0; 4]);
            if r[3] <= 0.0 {
                // Left the map or its receivers: end at the last estimate that had one.
                let Some((d0, _)) = previous else { return Intersection::LeavesMap };
                dist = d0;
                break;
            }
            let g = (Vec3::new(r[0], r[1], r[2]) - ps).length() - dist;
            if g.abs() <= ITERATION_RESIDUAL * dist.max(1.0) {
                break; // at the fixed point (photon_cast.glsl)
            }
            let mut next = dist + g;
            if let Some((d0, g0)) = previous {
                if (g - g0).abs() > 1e-6 * dist.max(1.0) {
                    next = dist - g * (dist - d0) / (g - g0);
                }
            }
            previous = Some((dist, g));
            dist = next.max(1e-3);
        }
        let hit = ps + dist * rt;
        let Some(texel) = self.light_texel(hit, steep) else { return Intersection::LeavesMap };
        let r = self.receiver(texel, steep);
        if r[3] <= 0.0 {
            return Intersection::LeavesMap;
        }
        let point = u.light_is_point > 0.0;
        let light_pos = Vec3::from_array(u.light_position);
        let stretch = if steep { u.steep_texel_stretch } else { u.refracted_texel_stretch };
        let texel_size = 2.0 * u.light_half_extent[0].max(u.light_half_extent[1]) / u.light_map_size
            * if point { (hit - light_pos).length() } else { 1.0 }
            * if !point && hit.y < u.water_level { stretch } else { 1.0 };
        let normal = self.normal(texel, steep);
        let light_to_hit = self.light_map_direction(hit, steep);
        let receiver = Vec3::new(r[0], r[1], r[2]);
        let (hit, dist) = onto_receiver_plane(ps, rt, hit, dist, receiver, normal, |h, t| {
            converged(h, receiver, normal, light_to_hit, t, texel_size)
        });
        if converged(hit, receiver, normal, light_to_hit, dist, texel_size) {
            Intersection::Landed(hit, dist)
        } else {
            Intersection::NotConverged
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_caustic_grid_numbers_every_shaped_cell_once() {
        // N = 4, k = 1.5: round(4 / 1.5) = 3 columns, 16 / 3 = 5 rows; the 16th invocation has
        // no cell. Every cell of the 3 × 5 grid comes from exactly one invocation.
        let mut seen = std::collections::HashSet::new();
        let mut leftover = 0;
        for number in 0..16u32 {
            let (cell, cells) = caustic_grid_cell(UVec2::new(number % 4, number / 4), 4, 1.5);
            assert_eq!(cells, UVec2::new(3, 5));
            match cell {
                Some(c) => assert!(c.x < 3 && c.y < 5 && seen.insert(c), "cell {c} twice or outside"),
                None => leftover += 1,
            }
        }
        assert_eq!((seen.len(), leftover), (15, 1));
        // The square grid is the invocations' own numbering.
        assert_eq!(caustic_grid_cell(UVec2::new(2, 3), 4, 1.0), (Some(UVec2::new(2, 3)), UVec2::splat(4)));
        // A photon's place from its index: the neighbour cell's first photon is this cell's last + 1.
        let per_axis = Vec2::new(9.0, 15.0);
        let last = caustic_grid_photon_uv(UVec2::new(1, 2), UVec2::new(3, 3), 3, per_axis);
        let next = caustic_grid_photon_uv(UVec2::new(2, 3), UVec2::ZERO, 3, per_axis);
        assert_eq!(last, next);
    }

    /// The constants this file mirrors by hand hold the same values as their GLSL originals
    /// (a shader edited alone would leave the twin, and the tests comparing with it, behind).
    #[test]
    fn mirrored_constants_match_the_glsl() {
        let sources = [
            include_str!("../glsl/shared/shader_math.glsl"),
            include_str!("../glsl/photons/photon_cast.glsl"),
            include_str!("../glsl/photons/photon_visibility.glsl"),
        ];
        // `const float|int NAME = A;` or `= A / B;`, evaluated.
        let glsl = |name: &str| -> f64 {
            let line = sources
                .iter()
                .flat_map(|s| s.lines())
                .find(|l| l.starts_with("const ") && l.contains(&format!(" {name} = ")))
                .unwrap_or_else(|| panic!("no GLSL constant {name}"));
            let value = line.split(" = ").nth(1).unwrap().trim_end_matches(';').trim();
            let number = |t: &str| t.trim().parse::<f64>().unwrap_or_else(|_| panic!("{name}: {t:?}"));
            match value.split_once('/') {
                Some((a, b)) => number(a) / number(b),
                None => number(value),
            }
        };
        let twins: [(&str, f64); 10] = [
            ("WATER_MAX_MARCH_STEPS", WATER_MAX_MARCH_STEPS as f64),
            ("WATER_REFINE_STEPS", WATER_REFINE_STEPS as f64),
            ("WATER_REFINE_RESIDUAL", WATER_REFINE_RESIDUAL as f64),
            ("WATER_NOISE_FEATURE", WATER_NOISE_FEATURE as f64),
            ("ITERATION_RESIDUAL", ITERATION_RESIDUAL as f64),
            ("CAUSTIC_DEPTH_TOLERANCE", CAUSTIC_DEPTH_TOLERANCE as f64),
            ("PHOTON_RECORD_FOOTPRINT_CLAMPED", crate::flux_budget::FOOTPRINT_CLAMPED as f64),
            ("FOOTPRINT_HAT_SAMPLES", FOOTPRINT_HAT_SAMPLES as f64),
            ("FOOTPRINT_RECEIVER_SLOPE", FOOTPRINT_RECEIVER_SLOPE as f64),
            ("FOOTPRINT_RECEIVER_DEPTH_SLACK", FOOTPRINT_RECEIVER_DEPTH_SLACK as f64),
        ];
        for (name, rust) in twins {
            let g = glsl(name);
            assert!((g - rust).abs() <= 1e-7 * g.abs().max(1.0), "{name}: GLSL {g}, Rust {rust}");
        }
    }

    /// A footprint point's receiver test, with its plane found as the geometry shader finds it
    /// (two directions on the plane, projected): a symmetric camera looking along +z (view
    /// space), 320×200 pixels. Every pixel of the plane passes, however the plane is turned
    /// (a floor seen at a slant, a wall face on, a facet at 60°); a surface half a metre behind
    /// the plane's points within a metre of the photon (a floor past a rock's silhouette)
    /// fails, as does one that bends 45° away at the
    /// photon (a facet past a crease), while one that bends 10° passes (the seabed's facets).
    #[test]
    fn a_footprint_point_s_receiver_holds_its_own_plane_and_not_what_lies_past_it() {
        let size = Vec2::new(320.0, 200.0);
        let tan_y = 0.5f32;
        let tan = Vec2::new(tan_y * size.x / size.y, tan_y);
        let pixel_of = |p: Vec3| (p.xy() / (p.z * tan) * 0.5 + Vec2::splat(0.5)) * size;
        // The point of the plane (through `at`, normal `n`) that pixel `px` shows.
        let on_plane = |at: Vec3, n: Vec3, px: Vec2| {
            let ray = ((px / size * 2.0 - Vec2::ONE) * tan).extend(1.0);
            ray * (n.dot(at) / n.dot(ray))
        };
        let plane_of = |at: Vec3, n: Vec3| -> (Vec2, f32, Vec2) {
            let t1 = n.cross(if n.y.abs() < 0.9 { Vec3::Y } else { Vec3::X }).normalize();
            let t2 = n.cross(t1);
            let (centre, w) = (pixel_of(at), 1.0 / at.z);
            let step = 1e-3;
            let span = |t: Vec3| (pixel_of(at + t * step) - centre) / step;
            let dw = |t: Vec3| (1.0 / (at + t * step).z - w) / step;
            let g = footprint_receiver_plane(span(t1), span(t2), dw(t1), dw(t2), w).expect("a plane seen edge on");
            (centre, w, g * w)
        };
        let planes = [
            (Vec3::new(0.4, -0.8, 4.0), Vec3::new(0.0, 1.0, 0.0)), // a floor at a slant
            (Vec3::new(-0.5, 0.2, 6.0), Vec3::new(0.0, 0.0, -1.0)), // a wall face on
            (Vec3::new(0.2, 0.1, 3.0), Vec3::new(0.75f32.sqrt(), 0.0, -0.5)), // a facet at 60°
        ];
        for (at, n) in planes {
            let (centre, w, g) = plane_of(at, n);
            let test = |px: Vec2, p: Vec3| footprint_pixel_on_receiver(px, centre, w, g, 1.0 / p.z, size, tan_y);
            let mut checked = 0;
            for dy in (-30..=30).step_by(6) {
                for dx in (-30..=30).step_by(6) {
                    let px = centre + Vec2::new(dx as f32, dy as f32);
                    let p = on_plane(at, n, px);
                    if p.z <= 0.1 || (p - at).length() > 1.0 {
                        continue;
                    }
                    checked += 1;
                    assert!(test(px, p), "plane {n}: pixel {px} on the plane fails");
                    // Half a metre behind the plane there: what a hat's edge past its receiver
                    // meets (its pixel is another, but no nearer the photon).
                    let away = if n.dot(at) > 0.0 { n } else { -n };
                    let behind = p + 0.5 * away;
                    assert!(!test(pixel_of(behind), behind), "plane {n}: half a metre behind {p} passes");
                }
            }
            assert!(checked > 30, "plane {n}: {checked} pixels checked");
            // Bent at the photon about an axis in the plane: 10° stays on the receiver, 45° leaves it.
            let axis = n.cross(Vec3::Z).try_normalize().unwrap_or(Vec3::X);
            let along = axis.cross(n).normalize();
            for (degrees, same) in [(10.0f32, true), (45.0, false)] {
                for side in [-1.0f32, 1.0] {
                    let bent = glam::Quat::from_axis_angle(axis, degrees.to_radians()) * n;
                    let p = on_plane(at, bent, pixel_of(at + along * side * 0.3));
                    let px = pixel_of(p);
                    assert_eq!(test(px, p), same, "plane {n}, bent {degrees}° on side {side}");
                }
            }
        }
    }

    /// Photon lattices on the target for the hats' tests (spans as columns, the angle they are
    /// turned by): square, stretched, sheared, under a pixel, under the samples' spacing.
    const HAT_LATTICES: [(Mat2, f32); 5] = [
        (Mat2::from_cols(Vec2::new(2.3, 0.0), Vec2::new(0.0, 2.3)), 0.5),
        (Mat2::from_cols(Vec2::new(4.0, 0.0), Vec2::new(0.0, 1.3)), 0.9),
        (Mat2::from_cols(Vec2::new(2.0, 0.7), Vec2::new(-0.4, 1.6)), 2.1),
        (Mat2::from_cols(Vec2::new(0.7, 0.0), Vec2::new(0.0, 0.55)), 0.3),
        (Mat2::from_cols(Vec2::new(0.3, 0.1), Vec2::new(0.05, 0.2)), 1.0),
    ];

    /// Footprint points: the photons of a lattice however rotated, sheared or fine, each
    /// spreading its light by its hat (`footprint_hat_basis` of its spans, sampled by
    /// `footprint_hat_share`), light every pixel alike. Axis-aligned tents of each footprint's
    /// extent, the build before, rippled on an oblique lattice: that check is here too.
    #[test]
    fn footprint_hats_light_a_lattice_evenly_at_any_angle_and_scale() {
        let pixels_in = |c: Vec2, basis: Mat2| -> Vec<Vec2> {
            let reach = (basis.x_axis.abs() + basis.y_axis.abs()).ceil() + Vec2::ONE;
            let (lo, hi) = ((c - reach).floor(), (c + reach).ceil());
            let mut out = Vec::new();
            for y in lo.y as i32..=hi.y as i32 {
                for x in lo.x as i32..=hi.x as i32 {
                    out.push(Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                }
            }
            out
        };
        for (spans, angle) in HAT_LATTICES {
            let spans = Mat2::from_angle(angle) * spans;
            let basis = footprint_hat_basis(spans);
            let to_lattice = basis.inverse();
            // Every photon's light is its footprint's area; it lands as its hat's shares.
            let light = spans.determinant().abs();
            let per_share = light / basis.determinant().abs();
            let origin = Vec2::new(40.3, 40.7);
            let mut image = std::collections::HashMap::<(i32, i32), f32>::new();
            let (mut oblique, mut cell_area) = (std::collections::HashMap::<(i32, i32), f32>::new(), 0.0);
            for j in -160..=160 {
                for i in -160..=160 {
                    let c = origin + spans * Vec2::new(i as f32, j as f32);
                    if (c - origin).abs().max_element() > 30.0 {
                        continue;
                    }
                    for p in pixels_in(c, basis) {
                        let key = (p.x as i32, p.y as i32);
                        *image.entry(key).or_default() +=
                            per_share * footprint_hat_share(to_lattice * (p - c), to_lattice);
                    }
                    // The build before: a rectangle of the footprint's area and its extents'
                    // aspect, each axis a tent of its side integrated over the pixel.
                    let extent = spans.x_axis.abs() + spans.y_axis.abs();
                    let side = light.sqrt() * (extent / extent.yx()).map(f32::sqrt);
                    cell_area = light;
                    let below = |t: f32| {
                        let t = t.clamp(-1.0, 1.0);
                        if t < 0.0 {
                            0.5 * (1.0 + t) * (1.0 + t)
                        } else {
                            1.0 - 0.5 * (1.0 - t) * (1.0 - t)
                        }
                    };
                    for p in pixels_in(c, Mat2::from_diagonal(side)) {
                        let share = |a: usize| {
                            (below((p[a] + 0.5 - c[a]) / side[a]) - below((p[a] - 0.5 - c[a]) / side[a])) * side[a]
                        };
                        *oblique.entry((p.x as i32, p.y as i32)).or_default() += share(0) * share(1);
                    }
                }
            }
            // The pixels well inside the lit square: each holds the light of a pixel's area.
            let spread = |image: &std::collections::HashMap<(i32, i32), f32>| {
                let inside: Vec<f32> = image
                    .iter()
                    .filter(|((x, y), _)| {
                        (Vec2::new(*x as f32 + 0.5, *y as f32 + 0.5) - origin).abs().max_element() < 20.0
                    })
                    .map(|(_, v)| *v)
                    .collect();
                let mean = inside.iter().sum::<f32>() / inside.len() as f32;
                let worst = inside.iter().map(|v| (v / mean - 1.0).abs()).fold(0.0, f32::max);
                (mean, worst)
            };
            let (mean, worst) = spread(&image);
            let label = format!("spans {spans:?}");
            assert!((mean - 1.0).abs() < 2e-3, "{label}: the mean pixel holds {mean}");
            let even = if spans.x_axis.length().min(spans.y_axis.length()) >= 1.0 / FOOTPRINT_HAT_SAMPLES {
                2e-3
            } else {
                0.03
            };
            assert!(worst < even, "{label}: a pixel {worst} off the mean");
            if angle == 2.1 {
                let (_, before) = spread(&oblique);
                assert!(
                    before > 0.05 && cell_area > 1.0,
                    "{label}: the rectangles' ripple {before} (the check is blind)"
                );
            }
        }
    }

    /// The quad caustics.geom draws a hat as (footprint_hat_quad_reach) holds every pixel the hat's
    /// samples reach, and is a fraction of the square sprite the hat was drawn as before where
    /// the hat is a long oblique sliver (docs/performance.md, "Footprint hats drawn as quads").
    #[test]
    fn a_footprint_hat_s_quad_holds_every_pixel_it_lights_and_a_sliver_s_is_a_fraction_of_its_sprite() {
        let reach = footprint_hat_samples_reach();
        // HAT_LATTICES, and a sliver where the waves fold the light.
        let sliver = (Mat2::from_cols(Vec2::new(12.0, 0.0), Vec2::new(0.0, 0.2)), 0.8);
        let mut sliver_ratio = 0.0;
        for (n, (spans, angle)) in HAT_LATTICES.into_iter().chain([sliver]).enumerate() {
            let basis = footprint_hat_basis(Mat2::from_angle(angle) * spans);
            let to_lattice = basis.inverse();
            let quad_reach = footprint_hat_quad_reach(to_lattice, reach);
            let quad = Mat2::from_cols(basis.x_axis * quad_reach.x, basis.y_axis * quad_reach.y);
            let extent = basis.x_axis.abs() + basis.y_axis.abs();
            for centre in [Vec2::new(20.5, 20.5), Vec2::new(20.13, 20.71), Vec2::new(20.9, 20.02)] {
                let (mut lit, mut inside) = (0, 0);
                for y in 0..41 {
                    for x in 0..41 {
                        let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                        let lattice = to_lattice * (p - centre);
                        let in_quad = (lattice / quad_reach).abs().max_element() < 1.0;
                        inside += in_quad as u32;
                        if footprint_hat_share(lattice, to_lattice) > 0.0 {
                            lit += 1;
                            assert!(in_quad, "lattice {n}: pixel {p} lit by the hat at {centre} lies outside its quad");
                        }
                    }
                }
                assert!(lit > 0, "lattice {n}: the hat at {centre} lit nothing");
                // The quad is not the whole window either.
                assert!(inside < 41 * 41 / 4, "lattice {n}: the quad holds {inside} pixels");
            }
            // The sprite the hat was drawn as before: a square as wide as its reach along the
            // wider pixel axis, plus the samples' reach.
            let sprite = (2.0 * (extent.max_element() + reach)).powi(2);
            let quad_area = 4.0 * quad.determinant().abs();
            if n == 5 {
                sliver_ratio = quad_area / sprite;
            }
        }
        // A 12 × 0.25-pixel sliver turned by 0.8 rad: its sprite is 17 pixels wide.
        assert!(sliver_ratio < 0.15, "the sliver's quad covers {sliver_ratio} of its sprite");
    }

    /// A lone hat keeps its light wherever it lies against the pixels: exactly when it is under
    /// the samples' spacing along the pixel axes (widened to it, its tents sum to one over the
    /// samples), and within a percent from 1.7 pixels across at any angle. Between, a lone hat
    /// is read coarsely (over 200 random offsets, a 0.6-pixel hat deposits 0.97–1.06 of its
    /// light, a tenth of a pixel turned by 0.7 rad 0.84–1.29); among its lattice's neighbours
    /// the shares still sum to the light (`footprint_hats_light_a_lattice_evenly_at_any_angle_and_scale`).
    #[test]
    fn footprint_hats_deposit_their_light() {
        for (size, angle, tolerance) in [(0.1f32, 0.0f32, 1e-4), (3.4, 0.0, 0.01), (1.7, 0.4, 0.01), (5.0, 1.1, 0.01)] {
            let spans = Mat2::from_angle(angle) * Mat2::from_diagonal(Vec2::new(size, 0.8 * size));
            let basis = footprint_hat_basis(spans);
            let to_lattice = basis.inverse();
            for offset in [Vec2::new(0.5, 0.5), Vec2::new(0.13, 0.71), Vec2::new(0.97, 0.02)] {
                let centre = Vec2::new(20.0, 20.0) + offset;
                let mut total = 0.0;
                for y in 0..40 {
                    for x in 0..40 {
                        let pixel = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                        total += footprint_hat_share(to_lattice * (pixel - centre), to_lattice);
                    }
                }
                let ratio = total / basis.determinant().abs();
                assert!((ratio - 1.0).abs() < tolerance, "size {size}, angle {angle}, offset {offset}: {ratio}");
            }
        }
    }

    fn water(model: WaterModel) -> WaterParams {
        WaterParams {
            model,
            level: 0.0,
            amplitude: 0.05,
            wavelength: 1.3,
            speed: 0.7,
            noise_amplitude: 0.03,
            noise_scale: 3.0,
            ior: 1.333,
            center: Vec2::new(0.3, -0.2),
            extent_min: Vec2::splat(-5.0),
            extent_max: Vec2::splat(5.0),
        }
    }

    #[test]
    fn water_gradient_matches_finite_differences() {
        let noise = NoiseTexture::generate();
        for model in [WaterModel::CircularCosine, WaterModel::AxisCosineNoise] {
            let w = water(model);
            for &(x, z, t) in &[(0.7f32, 1.1f32, 0.0f32), (-2.3, 0.4, 3.7), (1.9, -3.3, 11.0)] {
                let e = 1e-3;
                let h = |dx: f32, dz: f32| water_height_grad(&w, &noise, Vec2::new(x + dx, z + dz), t).x;
                let fd = Vec2::new((h(e, 0.0) - h(-e, 0.0)) / (2.0 * e), (h(0.0, e) - h(0.0, -e)) / (2.0 * e));
                let g = water_height_grad(&w, &noise, Vec2::new(x, z), t);
                // The noise gradient is interpolated, not differentiated, so allow a little.
                assert!(
                    (fd - Vec2::new(g.y, g.z)).length() < 0.02 * (1.0 + fd.length()),
                    "model {model:?}: fd {fd} vs {g}"
                );
            }
        }
    }

    #[test]
    fn noise_tiles_and_is_bounded() {
        let noise = NoiseTexture::generate();
        let a = noise.sample(Vec2::new(0.23, 0.71));
        let b = noise.sample(Vec2::new(3.23, -1.29));
        assert!((a - b).length() < 1e-4, "{a} vs {b}");
        let max = noise.texels.iter().map(|t| t[0].abs()).fold(0.0, f32::max);
        assert!(max > 0.3 && max <= 1.5, "noise amplitude {max}");
    }

    #[test]
    fn surface_intersection_lands_on_the_surface() {
        let noise = NoiseTexture::generate();
        let w = water(WaterModel::CircularCosine);
        let o = Vec3::new(0.4, 10.0, -0.8);
        let d = Vec3::new(0.2, -1.0, 0.1).normalize();
        let t = water_intersect(&w, &noise, o, d, 2.0);
        let p = o + t * d;
        let h = water_height_grad(&w, &noise, p.xz(), 2.0).x;
        assert!((p.y - (w.level + h)).abs() < 1e-4, "{} vs {}", p.y, h);
    }

    #[test]
    fn the_deviation_bound_is_the_largest_turn_of_any_tilt() {
        // Normals tilted by the slope bound at every azimuth, for suns from overhead to 63° off
        // it and slopes up to 0.44 (24°, short of meeting the lowest sun's rays edge-on): none
        // turns the refracted ray further than the bound's four tilts do, and one of them
        // reaches it (within the sampling's step). Waves that steep under that sun (slope 1)
        // read a right angle. The port's waves under the built-in scenes' sun: 0.122 rad, where
        // (1 − 1/ior)·atan(slope) reads 0.103.
        let waves = |amplitude: f32, wavelength: f32| WaterParams {
            amplitude,
            wavelength,
            noise_amplitude: 0.0,
            ..water(WaterModel::CircularCosine)
        };
        for d in [
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(0.25, -1.0, 0.15),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(2.0, -1.0, 0.3),
        ] {
            let d = d.normalize();
            let flat_refracted = d.refract(Vec3::Y, 1.0 / 1.333);
            for (amplitude, wavelength) in [(0.01, 2.0), (0.05, 1.0), (0.07, 1.0)] {
                let w = waves(amplitude, wavelength);
                let bound = water_deviation_bound(&w, d);
                let tilt = water_slope_bound(&w).atan();
                let mut most = 0.0f32;
                for step in 0..720 {
                    let azimuth = step as f32 / 720.0 * std::f32::consts::TAU;
                    let n = tilt.cos() * Vec3::Y + tilt.sin() * Vec3::new(azimuth.cos(), 0.0, azimuth.sin());
                    most = most.max(d.refract(n, 1.0 / 1.333).normalize().dot(flat_refracted).clamp(-1.0, 1.0).acos());
                }
                assert!(
                    most <= bound + 1e-4 && most >= bound - 1e-3,
                    "d {d} slope {}: bound {bound}, turned {most}",
                    tilt.tan()
                );
            }
        }
        let port = WaterParams {
            amplitude: 0.05,
            wavelength: 2.0,
            noise_amplitude: 0.08,
            noise_scale: 8.0,
            ..water(WaterModel::AxisCosineNoise)
        };
        let bound = water_deviation_bound(&port, Vec3::new(0.25, -1.0, 0.15).normalize());
        assert!((bound - 0.122).abs() < 0.002, "{bound}");
        let low_sun = Vec3::new(2.0, -1.0, 0.3).normalize();
        assert_eq!(water_deviation_bound(&waves(0.16, 1.0), low_sun), std::f32::consts::FRAC_PI_2);
    }

    #[test]
    fn the_noise_slope_bound_holds() {
        // Both slopes the crossing's search meets: the stored derivatives (the gradient that
        // Newton's steps use) and the bilinear surface's own, between neighbouring texels.
        let noise = NoiseTexture::generate();
        let n = noise.size as i32;
        let size = noise.size as f32;
        let (mut stored, mut between) = (0.0f32, 0.0f32);
        for y in 0..n {
            for x in 0..n {
                let t = noise.texel(x, y);
                stored = stored.max(Vec2::new(t.y, t.z).length());
                let du = (noise.texel(x + 1, y).x - t.x)
                    .abs()
                    .max((noise.texel(x + 1, y + 1).x - noise.texel(x, y + 1).x).abs());
                let dv = (noise.texel(x, y + 1).x - t.x)
                    .abs()
                    .max((noise.texel(x + 1, y + 1).x - noise.texel(x + 1, y).x).abs());
                between = between.max(Vec2::new(du, dv).length() * size);
            }
        }
        let steepest = stored.max(between);
        assert!(steepest <= WATER_NOISE_SLOPE, "noise slope {steepest} (stored {stored}, between {between})");
        // Not loose either: a bound far above the slope sends steep rays to the march.
        assert!(steepest > 0.99 * WATER_NOISE_SLOPE, "noise slope {steepest} against {WATER_NOISE_SLOPE}");
    }

    #[test]
    fn newton_and_the_march_find_the_same_crossing() {
        // Rays that fall steeply enough for Newton's steps, over both wave models and the
        // noise: both searches must land on the one crossing. Each stops within
        // WATER_REFINE_RESIDUAL of the waves' height, and the height falls by at least half
        // the ray's fall per unit of t, so the two differ by at most 4 × that over the fall.
        let noise = NoiseTexture::generate();
        for model in [WaterModel::CircularCosine, WaterModel::AxisCosineNoise] {
            let w = water(model);
            let bound = w.amplitude.abs() + w.noise_amplitude.abs();
            for k in 0..400 {
                let a = k as f32 * 0.618_034;
                let o = Vec3::new(4.0 * (a * 7.3).sin(), 3.0, 4.0 * (a * 3.1).cos());
                let slope = 0.5 / water_slope_bound(&w) * (0.2 + 0.8 * (a * 1.7).sin().abs());
                let d = Vec3::new(slope * (a * 5.0).cos(), -1.0, slope * (a * 5.0).sin()).normalize();
                let time = 0.37 * k as f32;
                assert!(water_slope_bound(&w) * Vec2::new(d.x, d.z).length() <= -0.5 * d.y);
                let t_top = (w.level + bound - o.y) / d.y;
                let t_bottom = (w.level - bound - o.y) / d.y;
                let by_newton = water_intersect(&w, &noise, o, d, time);
                let ray = SlabRay { o, d, time, t_top, t_bottom, bound };
                let marched = water_intersect_marched(&w, &noise, &ray);
                assert!(by_newton > 0.0 && marched > 0.0, "{model:?} ray {k}: {by_newton} / {marched}");
                let allowed = 4.0 * WATER_REFINE_RESIDUAL * bound / -d.y;
                assert!(
                    (by_newton - marched).abs() <= allowed,
                    "{model:?} ray {k}: Newton {by_newton}, march {marched} (allowed {allowed})"
                );
                let p = o + by_newton * d;
                let h = water_height_grad(&w, &noise, p.xz(), time).x;
                assert!((p.y - w.level - h).abs() <= WATER_REFINE_RESIDUAL * bound, "{model:?} ray {k}");
            }
        }
        // A ray that falls less steeply than the surface can rise is marched: water_intersect
        // returns the march's own answer for it, to the bit, and that answer lies on the
        // surface.
        let w = water(WaterModel::CircularCosine);
        let bound = w.amplitude.abs() + w.noise_amplitude.abs();
        let (o, d, time) = (Vec3::new(-1.0, 3.0, 0.4), Vec3::new(1.0, -0.3, 0.0).normalize(), 1.3);
        assert!(water_slope_bound(&w) * d.x > -0.5 * d.y);
        let t_top = (w.level + bound - o.y) / d.y;
        let t_bottom = (w.level - bound - o.y) / d.y;
        let marched = water_intersect_marched(&w, &noise, &SlabRay { o, d, time, t_top, t_bottom, bound });
        let t = water_intersect(&w, &noise, o, d, time);
        assert_eq!(t.to_bits(), marched.to_bits());
        let p = o + t * d;
        assert!((p.y - w.level - water_height_grad(&w, &noise, p.xz(), time).x).abs() <= 0.01 * bound + 1e-4);
    }

    #[test]
    fn newton_serves_every_ray_only_where_each_ray_would_take_it() {
        // The photon passes compile only Newton's search where this says so; each ray must
        // then be one that water_intersect sends to Newton itself, or the compiled-in choice
        // would change the crossing. The built-in scenes' suns qualify; a sun low enough for
        // the waves to rise along its rays as fast as they fall does not, nor does one that
        // falls just short of the margin.
        let w = water(WaterModel::AxisCosineNoise);
        let slope = water_slope_bound(&w);
        for name in ["tank", "port", "storage"] {
            let scene = crate::scene::load(name).unwrap();
            let d = scene.light.direction.normalize();
            assert!(newton_finds_every_crossing(&scene.water, d), "{name}");
            assert!(crate::frame::newton_crossing(&scene), "{name}");
        }
        let mut newton = 0;
        for k in 0..200 {
            // Horizontal over vertical from 0 to 1 / slope (the per-ray test's limit at 0.5 / slope).
            let across = k as f32 / 200.0 / slope;
            let d = Vec3::new(across * 0.6, -1.0, across * 0.8).normalize();
            let per_ray = slope * Vec2::new(d.x, d.z).length() <= -0.5 * d.y;
            if newton_finds_every_crossing(&w, d) {
                newton += 1;
                assert!(per_ray, "ray {k}: compiled Newton where the ray is marched");
            }
        }
        // The directions up to the per-ray limit (half of them), less the margin's 1 %.
        assert!((95..=100).contains(&newton), "{newton} of 200 directions take Newton");
        assert!(!newton_finds_every_crossing(&w, Vec3::new(1.0, -0.01, 0.0).normalize()), "a grazing sun");
        assert!(!newton_finds_every_crossing(&w, Vec3::new(0.0, 1.0, 0.0)), "light from below");
        let mut point = crate::scene::load("tank").unwrap();
        point.light.kind = crate::scene::LightKind::Point;
        assert!(!crate::frame::newton_crossing(&point), "a point light's rays do not share a direction");
    }

    #[test]
    fn refraction_obeys_snell_and_fresnel_is_physical() {
        let n = Vec3::Y;
        let i = Vec3::new(0.6, -0.8, 0.0);
        let t = refract(i, n, 1.0 / 1.333);
        let (sin_i, sin_t) = (i.x.abs(), t.x.abs() / t.length());
        assert!((sin_i - 1.333 * sin_t).abs() < 1e-5);
        // Normal incidence: 1 − ((n−1)/(n+1))².
        let t0 = fresnel_transmittance(1.0, 1.333);
        assert!((t0 - (1.0 - (0.333f32 / 2.333).powi(2))).abs() < 1e-6);
        assert!(fresnel_transmittance(0.0, 1.333) < 1e-6);
        assert!(fresnel_transmittance(0.5, 1.333) < t0);
    }

    #[test]
    fn bent_light_map_puts_a_refracted_ray_in_one_texel() {
        // The light's maps see underwater receivers along the refracted light direction: all
        // points of one refracted ray (through flat water) share the map position of its
        // entry point and lie deeper in the map the farther along the ray they are, and above
        // the water nothing moves. A map along the straight light ray (no bend) spreads the
        // ray over 0.14 m of the window per metre of depth at the built-in scenes' sun.
        let level = 0.3;
        for dir in [Vec3::new(0.25, -1.0, 0.15), Vec3::new(0.9, -0.2, -0.3), Vec3::new(0.0, -1.0, 0.0)] {
            let d = dir.normalize();
            let r = refract(d, Vec3::Y, 1.0 / 1.333).normalize();
            let across = |p: Vec3| p - d * p.dot(d); // the map position: p without its depth along d
            let entry = Vec3::new(0.4, level, -1.2);
            let mut last_depth = entry.dot(d);
            for along in [0.1f32, 0.5, 2.0, 7.0] {
                let p = light_map_point(entry + along * r, level, d, r);
                assert!((across(p) - across(entry)).length() < 1e-5, "{dir}: {along} m down the ray moves in the map");
                let depth = p.dot(d);
                assert!(depth > last_depth, "{dir}: depth along the bent path does not grow");
                last_depth = depth;
            }
            let above = Vec3::new(1.0, level + 0.5, 2.0);
            assert_eq!(light_map_point(above, level, d, r), above);
            // Continuous at the level, and a point light (no refracted axis) does not bend.
            let at = Vec3::new(-0.7, level, 0.2);
            assert!((light_map_point(at - Vec3::Y * 1e-4, level, d, r) - at).length() < 1e-3);
            assert_eq!(light_map_point(at - Vec3::Y, level, d, Vec3::ZERO), at - Vec3::Y);
        }
    }

    #[test]
    fn strips_deposit_their_length_smoothly() {
        // The codes stay clear of the triangles' 0, the footprints' codes (from 1) and the
        // squares' negative sizes, and carry d back.
        for i in 0..=40 {
            let d = -1.0 + i as f32 * 0.05;
            let code = strip_across_code(d);
            assert!(is_strip_code(code) && code > 0.0 && code < 0.5, "d {d}: code {code}");
            assert!((strip_across(code) - d).abs() < 1e-6);
        }
        assert!(!is_strip_code(0.0) && !is_strip_code(1.0) && !is_strip_code(-1.0));
        // The pixel centres a strip of `length` px, middle line through `start` along `dir`,
        // covers (within 1 px of the line, between its ends), and their weights' sum: what the
        // strip deposits, in units of its per-pixel value.
        let deposit = |start: Vec2, dir: Vec2, length: f32, tent: bool| -> f32 {
            let across = Vec2::new(-dir.y, dir.x);
            let (lo, hi) = (start.min(start + dir * length) - 2.0, start.max(start + dir * length) + 2.0);
            let mut sum = 0.0;
            for y in lo.y.floor() as i32..=hi.y.ceil() as i32 {
                for x in lo.x.floor() as i32..=hi.x.ceil() as i32 {
                    let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5) - start;
                    let (t, d) = (p.dot(dir), p.dot(across));
                    if !(0.0..length).contains(&t) {
                        continue;
                    }
                    sum += if tent {
                        if d.abs() < 1.0 {
                            strip_weight(strip_across_code(d))
                        } else {
                            0.0
                        }
                    } else if (-0.5..0.5).contains(&d) {
                        1.0 // the one-pixel strip it replaced: every covered centre alike
                    } else {
                        0.0
                    };
                }
            }
            sum
        };
        // Along a row or a column, the tent's samples sum to exactly one per pixel of length
        // wherever the line lies between pixel centres.
        for i in 0..16 {
            let offset = i as f32 / 16.0;
            let row = deposit(Vec2::new(3.0, 7.0 + offset), Vec2::X, 12.0, true);
            assert!((row - 12.0).abs() < 1e-4, "offset {offset}: {row}");
            let column = deposit(Vec2::new(7.0 + offset, 3.0), Vec2::Y, 12.0, true);
            assert!((column - 12.0).abs() < 1e-4, "offset {offset}: {column}");
        }
        // Any direction and position, strips 8 px long: the tent deposits their length on
        // average, 4 % rms about it (the strips' cut ends and the samples' ripple). The
        // one-pixel strip covers one or two centres per row at random: 11 % rms, the dotted
        // hatching on a grazed wall.
        let (mut tent_sq, mut box_sq, mut tent_sum, n) = (0.0f32, 0.0f32, 0.0f32, 2000);
        for i in 0..n {
            let f = i as f32;
            let angle = (f * 0.6180339).fract() * std::f32::consts::PI;
            let start = Vec2::new(10.0 + (f * 0.4142135).fract(), 10.0 + (f * 0.7320508).fract());
            let dir = Vec2::new(angle.cos(), angle.sin());
            let tent = deposit(start, dir, 8.0, true) / 8.0;
            tent_sum += tent;
            tent_sq += (tent - 1.0).powi(2);
            box_sq += (deposit(start, dir, 8.0, false) / 8.0 - 1.0).powi(2);
        }
        let (tent_rms, box_rms) = ((tent_sq / n as f32).sqrt(), (box_sq / n as f32).sqrt());
        let tent_mean = tent_sum / n as f32;
        assert!((tent_mean - 1.0).abs() < 0.01, "the tent strips deposit {tent_mean} of their length");
        assert!(tent_rms < 0.06, "the tent strip deposits {tent_rms} (rms) off its length");
        assert!(box_rms > 2.0 * tent_rms, "the one-pixel strip read {box_rms} (rms), the tent {tent_rms}");
    }

    #[test]
    fn sliver_footprint_shares_are_its_overlaps_and_sum_to_one() {
        // Centres and sides over many pixel positions, both parities, off-screen too.
        let mut worst_sum = 0.0f32;
        for i in 0..4000 {
            let f = i as f32;
            let c = Vec2::new(-3.0 + (f * 0.6180339).fract() * 40.0, -5.0 + (f * 0.4142135).fract() * 30.0);
            let side = 0.02 + (f * 0.7320508).fract() * 0.98;
            let code = sliver_footprint_code(c, side);
            assert!(code >= 1.0 && code <= (1 << 20) as f32, "code {code} is above 2^20");
            // The fragments a 2-pixel square centred on c covers: centres within 1 of c.
            let mut sum = 0.0;
            for y in (c.y - 1.0).floor() as i32..=(c.y + 1.0).ceil() as i32 {
                for x in (c.x - 1.0).floor() as i32..=(c.x + 1.0).ceil() as i32 {
                    let centre = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                    if (centre - c).abs().max_element() >= 1.0 {
                        continue;
                    }
                    let w = sliver_footprint_weight(centre, code);
                    // The exact share of the square [c ± side/2] in this pixel, up to the
                    // code's quanta (1/128 px in position, 1/16 px in side), each of which
                    // moves a share by at most its half over the side, per axis.
                    let span =
                        |lo: f32, c: f32| ((lo + 1.0).min(c + side / 2.0) - lo.max(c - side / 2.0)).max(0.0) / side;
                    let exact = span(x as f32, c.x) * span(y as f32, c.y);
                    let quanta = 2.0 * (0.5 / 128.0 + 0.5 / 16.0) / side;
                    assert!(
                        (w - exact).abs() <= quanta + 1e-5,
                        "c {c} side {side} pixel {centre}: {w} against {exact}"
                    );
                    sum += w;
                }
            }
            worst_sum = worst_sum.max((sum - 1.0f32).abs());
        }
        assert!(worst_sum < 1e-5, "the shares of a sliver sum to 1 within {worst_sum}");
    }

    #[test]
    fn henyey_greenstein_integrates_to_one() {
        for g in [-0.9f32, 0.0, 0.5, 0.9] {
            // ∫ p dω = 2π ∫_{-1}^{1} p(μ) dμ.
            let n = 200_000;
            let sum: f64 =
                (0..n).map(|k| henyey_greenstein(-1.0 + 2.0 * (k as f32 + 0.5) / n as f32, g) as f64).sum::<f64>()
                    * 2.0
                    / n as f64
                    * 2.0
                    * std::f64::consts::PI;
            assert!((sum - 1.0).abs() < 2e-3, "g = {g}: {sum}");
        }
    }

    #[test]
    fn point_size_hits_both_ends() {
        assert!((regulated_point_size(0.1, 0.1, 50.0, 5.0, 20.0) - 20.0).abs() < 1e-3);
        assert!((regulated_point_size(50.0, 0.1, 50.0, 5.0, 20.0) - 5.0).abs() < 1e-3);
    }

    #[test]
    fn grid_uv_tiles_unit_square_evenly() {
        // 3 cells × 2 sub-cells per axis = 6 photons per axis at (k + 0.5)/6.
        let grid = UVec2::splat(3);
        let mut xs: Vec<f32> = (0..3)
            .flat_map(|c| (0..2).map(move |s| photon_grid_uv(UVec2::new(c, 0), UVec2::new(s, 0), 2, grid).x))
            .collect();
        xs.sort_by(f32::total_cmp);
        for (k, x) in xs.iter().enumerate() {
            assert!((x - (k as f32 + 0.5) / 6.0).abs() < 1e-6, "{k}: {x}");
        }
    }

    #[test]
    fn wave_gradient_is_gradient_of_its_potential() {
        // Potential h = sin(k1·uv + a)/|k1|² + sin(k2·uv + b)/|k2|²; compare with finite differences.
        let h = |uv: Vec2, t: f32| {
            let k1 = Vec2::new(7.0, 3.0) * 2.0 * PI;
            let k2 = Vec2::new(-4.0, 9.0) * 2.0 * PI;
            (k1.dot(uv) + 1.3 * t).sin() / k1.dot(k1) + (k2.dot(uv) + 0.9 * t).sin() / k2.dot(k2)
        };
        let e = 1e-3;
        for &(x, y, t) in &[(0.1, 0.2, 0.0), (0.7, 0.4, 2.0), (0.33, 0.9, 5.5)] {
            let uv = Vec2::new(x, y);
            let fd = Vec2::new(
                (h(uv + Vec2::X * e, t) - h(uv - Vec2::X * e, t)) / (2.0 * e),
                (h(uv + Vec2::Y * e, t) - h(uv - Vec2::Y * e, t)) / (2.0 * e),
            );
            assert!((fd - demo_wave_gradient(uv, t)).length() < 1e-3, "{fd} vs {}", demo_wave_gradient(uv, t));
        }
    }
}
