//! Godrays: the single-scattered radiance along each godray-target pixel's centre ray.
//!
//! The quantity, for the view ray x(s) = c + s·v through a pixel's centre, is
//!
//! ```text
//!     L = ∫ σs · p_HG(θ) · F(x(s)) · e^(−γ·w(s)) ds
//! ```
//!
//! over the parts of the ray under the water in front of what the pixel sees (its first
//! triangle, the water surface inside the extent, or the far plane), where F is the
//! fluence of the refracted sunlight (each beam's flux attenuated by e^(−γ·t) along it),
//! θ the angle between the beam and the direction towards the camera, and w(s) the water
//! between the camera and x(s) (under the real surface, not the mean plane).
//!
//! Estimator: beam × ray with a 2-D kernel (Jarosz et al. 2011): each photon's refracted
//! path is a beam of flux Φ·T, and F is estimated by spreading each beam uniformly over a
//! disc of radius r perpendicular to it:
//!
//! ```text
//!     F(x) ≈ Σ_beams Φ · e^(−γ·t(x)) / (π r²)   over the beams within r of x.
//! ```
//!
//! The ray's integral is then exact per beam: the chord of the ray inside the beam's
//! cylinder is a quadratic's root interval, and e^(−γ·(t(s) + w(s))) is the exponential of
//! a linear function along it (per underwater span), integrated in closed form.
//!
//! Why a disc and not the 1-D box across the beam the GPU uses (`1/(w·sin θ)`): the 1-D
//! kernel's weight diverges as a view ray turns parallel to the beams (looking down at a
//! floor under a high sun, the pool scenes' usual view), where ever fewer beams carry ever
//! larger weights; the GPU clamps sin θ at 0.1 for that, a bias. The disc kernel's chord
//! length stays bounded (it is the overlap of two lines inside a cylinder), so its variance
//! does too, for every angle. Both converge to the integral above as r → 0.
//!
//! The radius is `KERNEL_SPACINGS` times the beams' mean spacing on the sampling plane,
//! `δ = sqrt(A / N)`: it shrinks as 1/√N. The estimate's bias is the fluence blurred over the
//! disc (zero where the fluence is smooth on that scale, i.e. in open water; shadow and
//! caustic shafts are softened by ~r), its noise that of the ≈ 3²·π ≈ 28 beams a ray parallel
//! to them meets (far more for oblique rays: ~6·ℓ·sin θ/δ over a path ℓ).

use super::light::{LightPath, LightSampler, Strata};
use super::{sum_buffers, trace_strata, Context, Progress, ReferenceSettings};
use crate::image_io::HdrImage;
use crate::shader_math::henyey_greenstein;
use glam::{DVec2, DVec3};

const STREAM: u64 = 0x60d_4a75;
const BEAMS_PER_ITEM: f64 = 1024.0;
/// The kernel's radius in beam spacings.
pub const KERNEL_SPACINGS: f64 = 3.0;

/// The underwater part [s0, s1] of a pixel's visible ray, with the water the ray crossed
/// before s0.
#[derive(Clone, Copy, Debug)]
struct Span {
    s0: f64,
    s1: f64,
    water_before: f64,
}

struct PixelRay {
    dir: DVec3,
    spans: Vec<Span>,
}

pub(super) fn render(
    ctx: &Context,
    sampler: &LightSampler,
    settings: &ReferenceSettings,
    threads: usize,
    progress: &Progress,
) -> HdrImage {
    let size = ctx.extents.godray;
    let pixels = (size[0] * size[1]) as usize;
    let rays: Vec<PixelRay> = (0..pixels as u32).map(|i| pixel_ray(ctx, i % size[0], i / size[0])).collect();
    let strata = Strata::new(sampler.rect_lo, sampler.rect_hi, settings.godray_beams);
    let radius = KERNEL_SPACINGS * (strata.area() / strata.n as f64).sqrt();
    let splatter = Splatter::new(ctx, &rays, radius);
    let buffers = trace_strata(
        ctx,
        sampler,
        &strata,
        settings.seed,
        STREAM,
        BEAMS_PER_ITEM,
        threads,
        progress,
        || (vec![[0.0f64; 4]; pixels], vec![u64::MAX; pixels]),
        |(buffer, stamps), path, index| splatter.splat(path, index, buffer, stamps),
    );
    sum_buffers(size, buffers.into_iter().map(|(b, _)| b).collect())
}

/// Pixel (x, y)'s centre ray and its underwater spans up to what it sees.
fn pixel_ray(ctx: &Context, x: u32, y: u32) -> PixelRay {
    let cam = &ctx.camera;
    let c = cam.position;
    let dir = cam.pixel_ray(x, y, ctx.extents.godray);
    let rate = cam.depth_rate(dir);
    let mut end = if rate > 0.0 { (cam.z_far - cam.clip(c).w) / rate } else { f64::INFINITY };
    end = end.min(ctx.box_exit(c, dir));
    if let Some(hit) = ctx.bvh.closest(c, dir, 0.0, end) {
        end = hit.t;
    }
    if let Some(t) = ctx.view_surface_hit(c, dir, 0.0, end) {
        end = t;
    }
    // Walk the crossings of the surface (inside the extent or not: the medium's boundary).
    let s = &ctx.surface;
    let mut spans = Vec::new();
    let mut inside = s.above(c) < 0.0;
    let (mut t, mut water) = (0.0, 0.0);
    for _ in 0..1000 {
        let crossing = s.crossing(c, dir, t, end, !inside);
        let stop = crossing.unwrap_or(end);
        if inside && stop > t {
            spans.push(Span { s0: t, s1: stop, water_before: water });
            water += stop - t;
        }
        match crossing {
            Some(c) if c < end => {
                inside = !inside;
                t = c + 1e-7;
            }
            _ => break,
        }
    }
    PixelRay { dir, spans }
}

struct Splatter<'a> {
    ctx: &'a Context<'a>,
    rays: &'a [PixelRay],
    radius: f64,
    planes: [(DVec3, f64); 4],
    /// Depth below which a beam's pixels are found by brute force (see `splat`).
    near_depth: f64,
    /// Every view-ray point shallower than `near_depth` lies within this of the camera.
    near_reach: f64,
    /// σs · Φ-independent factor of every contribution: σs / (π r²).
    scale: f64,
    hg_g: f32,
}

impl<'a> Splatter<'a> {
    fn new(ctx: &'a Context<'a>, rays: &'a [PixelRay], radius: f64) -> Self {
        let cam = &ctx.camera;
        let near_depth = cam.z_near.max(4.0 * radius);
        // The view frustum's corner rays are the least aligned with its axis.
        let min_cos = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(x, y)| cam.depth_rate(cam.ray(DVec2::new(x, y))))
            .into_iter()
            .fold(1.0f64, f64::min)
            .max(1e-6);
        let m = &ctx.scene.medium;
        Self {
            ctx,
            rays,
            radius,
            planes: cam.side_planes(),
            near_depth,
            near_reach: radius + near_depth / min_cos,
            scale: m.scattering as f64 / (std::f64::consts::PI * radius * radius),
            hg_g: m.hg_g,
        }
    }

    /// Adds beam `id`'s radiance to every pixel whose ray passes within the kernel radius.
    /// Candidate pixels come from the beam's projection (its pieces' bounding boxes widened by
    /// the radius); `stamps` makes each pixel count once per beam.
    fn splat(&self, beam: &LightPath, id: u64, buffer: &mut [[f64; 4]], stamps: &mut [u64]) {
        let cam = &self.ctx.camera;
        let r = self.radius;
        let (o, d) = (beam.surface, beam.direction);
        // The part of the beam that can be within r of a visible view-ray point: inside the
        // frustum widened by r, and between depth −r and the far plane + r.
        let (mut t0, mut t1) = (0.0, beam.length);
        for (n, offset) in self.planes {
            clip_half(n.dot(o) + offset + r, n.dot(d), &mut t0, &mut t1);
        }
        let (depth0, rate) = (cam.clip(o).w, cam.depth_rate(d));
        clip_half(cam.z_far + r - depth0, -rate, &mut t0, &mut t1);
        clip_half(depth0 + r, rate, &mut t0, &mut t1);
        if !(t0 < t1) {
            return;
        }
        let mut visit = |x: u32, y: u32| {
            let i = (y * self.ctx.extents.godray[0] + x) as usize;
            if stamps[i] == id {
                return;
            }
            stamps[i] = id;
            if let Some(l) = self.contribution(&self.rays[i], beam) {
                let p = &mut buffer[i];
                p[0] += l.x;
                p[1] += l.y;
                p[2] += l.z;
                p[3] += 1.0;
            }
        };
        // Split at the depth `near_depth`: the shallow part (close to the camera, where the
        // kernel's image is large) is rare and checked against every pixel, when it comes near
        // enough to the camera to matter at all.
        let (mut f0, mut f1) = (t0, t1);
        clip_half(depth0 - self.near_depth, rate, &mut f0, &mut f1);
        let (mut n0, mut n1) = (t0, t1);
        clip_half(self.near_depth - depth0, -rate, &mut n0, &mut n1);
        if n0 < n1 && segment_distance(cam.position, o + n0 * d, o + n1 * d) < self.near_reach {
            self.all_pixels(&mut visit);
        }
        if f0 < f1 {
            self.piece(o, d, f0, f1, 0, &mut visit);
        }
    }

    /// Visits the pixels whose centres fall in the image of beam piece [ta, tb] widened by r,
    /// subdividing until a piece is short on screen and short against its depth.
    fn piece(&self, o: DVec3, d: DVec3, ta: f64, tb: f64, level: u32, visit: &mut impl FnMut(u32, u32)) {
        let cam = &self.ctx.camera;
        let size = self.ctx.extents.godray;
        let to_pixels =
            |c: glam::DVec4| (DVec2::new(c.x, c.y) / c.w + 1.0) * 0.5 * DVec2::new(size[0] as f64, size[1] as f64);
        let (pa, pb) = (o + ta * d, o + tb * d);
        let (ca, cb) = (cam.clip(pa), cam.clip(pb));
        let long_on_screen = (to_pixels(cb) - to_pixels(ca)).length() > 4.0;
        let long_for_depth = tb - ta > 0.25 * ca.w.min(cb.w);
        if level < 40 && (long_on_screen || long_for_depth) {
            let mid = 0.5 * (ta + tb);
            self.piece(o, d, ta, mid, level + 1, visit);
            self.piece(o, d, mid, tb, level + 1, visit);
            return;
        }
        // The image of a box in front of the camera lies within its corners' images.
        let (lo, hi) = (pa.min(pb) - self.radius, pa.max(pb) + self.radius);
        let (mut min, mut max) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
        for k in 0..8 {
            let p = DVec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let c = cam.clip(p);
            if !(c.w > 1e-9) {
                self.all_pixels(visit);
                return;
            }
            let s = to_pixels(c);
            min = min.min(s);
            max = max.max(s);
        }
        // Pixel centres (i + 0.5) inside [min, max].
        let first = |v: f64| (v - 0.5).ceil().max(0.0);
        let last = |v: f64, n: u32| (v - 0.5).floor().min(n as f64 - 1.0);
        let (x0, x1) = (first(min.x), last(max.x, size[0]));
        let (y0, y1) = (first(min.y), last(max.y, size[1]));
        if x0 > x1 || y0 > y1 {
            return;
        }
        for y in y0 as u32..=y1 as u32 {
            for x in x0 as u32..=x1 as u32 {
                visit(x, y);
            }
        }
    }

    fn all_pixels(&self, visit: &mut impl FnMut(u32, u32)) {
        let size = self.ctx.extents.godray;
        for y in 0..size[1] {
            for x in 0..size[0] {
                visit(x, y);
            }
        }
    }

    /// The beam's in-scattered radiance along the pixel's ray, W/(m²·sr) per channel.
    fn contribution(&self, ray: &PixelRay, beam: &LightPath) -> Option<DVec3> {
        let (v, rt) = (ray.dir, beam.direction);
        let w0 = self.ctx.camera.position - beam.surface;
        // Along the view ray, the beam parameter of the nearest beam point is t(s) = a + b·s
        // and the squared distance to the beam |q + s·u|².
        let (a, b) = (w0.dot(rt), v.dot(rt));
        let (q, u) = (w0 - a * rt, v - b * rt);
        let (uu, qu, qq, r2) = (u.dot(u), q.dot(u), q.dot(q), self.radius * self.radius);
        let (mut lo, mut hi) = if uu < 1e-14 {
            if qq >= r2 {
                return None;
            }
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            let disc = qu * qu - uu * (qq - r2);
            if disc <= 0.0 {
                return None;
            }
            let sq = disc.sqrt();
            ((-qu - sq) / uu, (-qu + sq) / uu)
        };
        // Only the beam's extent [0, length] carries light.
        if b.abs() < 1e-15 {
            if a < 0.0 || a > beam.length {
                return None;
            }
        } else {
            let (sa, sb) = (-a / b, (beam.length - a) / b);
            lo = lo.max(sa.min(sb));
            hi = hi.min(sa.max(sb));
        }
        if !(lo < hi) {
            return None;
        }
        let gamma = self.ctx.gamma;
        let mut sum = DVec3::ZERO;
        for span in &ray.spans {
            let (l, h) = (lo.max(span.s0), hi.min(span.s1));
            if !(l < h) {
                continue;
            }
            // −γ·(t(s) + w(s)) with w(s) = water_before + (s − s0): linear in s.
            let alpha = -gamma * (a + span.water_before - span.s0);
            let beta = -gamma * (1.0 + b);
            for c in 0..3 {
                sum[c] += exp_integral(alpha[c], beta[c], l, h);
            }
        }
        if sum == DVec3::ZERO {
            return None;
        }
        // θ between the beam and the direction towards the camera (−v).
        let phase = henyey_greenstein((-b) as f32, self.hg_g) as f64;
        Some(sum * (self.scale * phase * beam.flux))
    }
}

/// ∫_l^h e^(α + β·s) ds, stable for β → 0.
fn exp_integral(alpha: f64, beta: f64, l: f64, h: f64) -> f64 {
    let x = beta * (h - l);
    let ratio = if x.abs() < 1e-12 { 1.0 } else { x.exp_m1() / x };
    (alpha + beta * l).exp() * (h - l) * ratio
}

/// Narrows [t0, t1] to where a + b·t ≥ 0.
fn clip_half(a: f64, b: f64, t0: &mut f64, t1: &mut f64) {
    if b.abs() < 1e-300 {
        if a < 0.0 {
            *t1 = f64::NEG_INFINITY;
        }
    } else if b > 0.0 {
        *t0 = t0.max(-a / b);
    } else {
        *t1 = t1.min(-a / b);
    }
}

/// Distance from `p` to the segment [a, b].
fn segment_distance(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - p).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exp_integral_is_exact() {
        let (a, b, l, h): (f64, f64, f64, f64) = (-0.3, -0.7, 1.0, 4.0);
        let exact = ((a + b * h).exp() - (a + b * l).exp()) / b;
        assert!((exp_integral(a, b, l, h) - exact).abs() < 1e-14);
        assert!((exp_integral(-0.3, 0.0, 1.0, 4.0) - 3.0 * (-0.3f64).exp()).abs() < 1e-14);
    }
}
