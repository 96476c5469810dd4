//! Caustics: the irradiance on the underwater receivers each caustic-target pixel sees.
//!
//! The quantity, per pixel P of solid angle Ω_P (exact, from its corner rays), is the
//! irradiance averaged over the pixel's solid angle:
//!
//! ```text
//!     E_P = (1/Ω_P) ∫_P E(x(ω)) dω = (1/Ω_P) ∫_{visible footprint} E(x) · |cos θ_v| / d_v² dA
//! ```
//!
//! with x(ω) the receiver point the ray ω sees, d_v its distance and θ_v the angle between
//! the view ray and the receiver's geometric normal. Since E dA is the flux arriving on dA,
//! each photon of flux Φ (after Fresnel and e^(−γ·d)) landing at a point the pixel sees
//! adds `Φ · |cos θ_v| / (Ω_P · d_v²)`: an unbiased estimate with no kernel and no
//! clamp. It is the GPU's `ΔE = Φ / a_pix` with `a_pix = Ω_P · d_v² / |cos θ_v|` taken at the
//! photon's own point, summed over the pixel's exact area instead of an s × s splat (so the
//! GPU buffer ≈ this one blurred by its splat size). Written as a product, a receiver seen
//! edge-on needs no clamp: its photons simply add little each.
//!
//! Visibility is exact: the photon counts where the straight segment from the camera to its
//! receiver meets no triangle and no water surface inside the water's extent.

use super::light::{LightPath, LightSampler, Strata};
use super::{sum_buffers, trace_strata, Context, Progress, ReferenceSettings};
use crate::image_io::HdrImage;
use glam::DVec3;

/// Jitter stream of the caustic photons (the godray beams use another).
const STREAM: u64 = 0xc0ffee;
/// Photons per work item handed to a thread.
const PHOTONS_PER_ITEM: f64 = 8192.0;

/// The caustic buffer, and the same estimate from half of its photons
/// (`ReferenceImages::caustics_half`). The photons are two independent stratified sets of
/// half the count each (jitter streams `STREAM` and `STREAM + 1`), each a whole estimate of
/// the buffer; the buffer is their mean, weighted by their counts, and the second set is the
/// half. (Halves taken from one stratification, every other cell, are not independent:
/// each cell's neighbour lies in the other half, so their difference overstated the noise
/// 1.6× on a smooth wave.)
pub(super) fn render(
    ctx: &Context,
    sampler: &LightSampler,
    settings: &ReferenceSettings,
    threads: usize,
    progress: &Progress,
) -> (HdrImage, HdrImage) {
    let size = ctx.extents.caustic;
    let pixels = (size[0] * size[1]) as usize;
    let omega: Vec<f64> =
        (0..pixels as u32).map(|i| ctx.camera.pixel_solid_angle(i % size[0], i / size[0], size)).collect();
    let trace_set = |photons: u64, stream: u64| {
        let strata = Strata::new(sampler.rect_lo, sampler.rect_hi, photons);
        let buffers = trace_strata(
            ctx,
            sampler,
            &strata,
            settings.seed,
            stream,
            PHOTONS_PER_ITEM,
            threads,
            progress,
            || vec![[0.0f64; 4]; pixels],
            |buffer, path, _| deposit(ctx, path, &omega, buffer),
        );
        sum_buffers(size, buffers)
    };
    let second = settings.caustic_photons / 2;
    let first = settings.caustic_photons - second;
    let a = trace_set(first, STREAM);
    if second == 0 {
        return (a.clone(), a);
    }
    let b = trace_set(second, STREAM + 1);
    let (wa, wb) = (first as f32 / settings.caustic_photons as f32, second as f32 / settings.caustic_photons as f32);
    let mut all = a;
    for (p, q) in all.pixels.iter_mut().zip(&b.pixels) {
        for c in 0..3 {
            p[c] = wa * p[c] + wb * q[c];
        }
        p[3] += q[3];
    }
    (all, b)
}

/// Adds a photon that reached a receiver to the pixel that sees its landing point.
fn deposit(ctx: &Context, path: &LightPath, omega: &[f64], buffer: &mut [[f64; 4]]) {
    let Some(normal) = path.receiver else { return };
    let size = ctx.extents.caustic;
    let hit = path.end();
    let Some((x, y)) = ctx.camera.pixel_of(hit, size) else { return };
    let camera = ctx.camera.position;
    let to_hit = hit - camera;
    let d_view = to_hit.length();
    let dir = to_hit / d_view;
    // Stop just short of the receiver's own triangle.
    if ctx.bvh.occluded(camera, dir, 0.0, d_view * (1.0 - 1e-9) - 1e-9) {
        return;
    }
    if ctx.view_surface_hit(camera, dir, 0.0, d_view).is_some() {
        return;
    }
    let index = (y * size[0] + x) as usize;
    let geometry = normal.dot(dir).abs() / (omega[index] * d_view * d_view);
    let transmitted = (-ctx.gamma * path.length).exp() * path.flux;
    let e: DVec3 = transmitted * geometry;
    let p = &mut buffer[index];
    p[0] += e.x;
    p[1] += e.y;
    p[2] += e.z;
    p[3] += 1.0;
}
