//! How far a GPU frame is from the reference (`reference`): per-buffer errors on the HDR
//! values, FLIP on the tonemapped image, and frame-to-frame flicker. `underlight sweep`
//! reports these against GPU time; `docs/accuracy.md` explains the choices.

use crate::image_io::{tonemap_srgb8, HdrImage};
use anyhow::{bail, Result};

/// Errors of one photon buffer (caustic irradiance or godray radiance) against the reference,
/// over the RGB channels of every pixel. Relative figures are normalised by the reference's
/// mean, not per pixel: most pixels of a caustic buffer are near zero somewhere, and a
/// per-pixel ratio would be dominated by them.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BufferError {
    /// √(mean (test − ref)²) / mean ref.
    pub relative_rmse: f64,
    /// mean |test − ref| / mean ref.
    pub mean_relative_error: f64,
    /// (Σ test − Σ ref) / Σ ref: energy made or lost (signed).
    pub flux_error: f64,
}

fn same_size(a: &HdrImage, b: &HdrImage, what: &str) -> Result<()> {
    if (a.width, a.height) != (b.width, b.height) {
        bail!("{what}: {}×{} against a {}×{} reference", a.width, a.height, b.width, b.height);
    }
    Ok(())
}

/// `test` against `reference` (same size).
pub fn buffer_error(test: &HdrImage, reference: &HdrImage) -> Result<BufferError> {
    same_size(test, reference, "buffer error")?;
    let (mut sq, mut abs, mut sum_t, mut sum_r) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for (t, r) in test.pixels.iter().zip(&reference.pixels) {
        for c in 0..3 {
            let (t, r) = (t[c] as f64, r[c] as f64);
            sq += (t - r) * (t - r);
            abs += (t - r).abs();
            sum_t += t;
            sum_r += r;
        }
    }
    if !(sum_r > 0.0) {
        bail!("the reference buffer is black: no relative error can be measured");
    }
    let n = (reference.pixels.len() * 3) as f64;
    let mean_r = sum_r / n;
    Ok(BufferError {
        relative_rmse: (sq / n).sqrt() / mean_r,
        mean_relative_error: abs / n / mean_r,
        flux_error: (sum_t - sum_r) / sum_r,
    })
}

/// Half the side of the neighbourhood `gap_fraction` judges "lit" by: 15×15 pixels.
const GAP_NEIGHBOURHOOD_RADIUS: i64 = 7;

/// The share of a caustic buffer's lit region that holds exactly nothing: holes between
/// splats that spread too little. A pixel is in the lit region when the mean of its 15×15
/// neighbourhood exceeds a tenth of the mean over the pixels that hold anything (channel
/// sums). An estimator that covers the receivers it lights scores 0; the paper's
/// distance-sized points score 0.2–0.4 on the built-in scenes at their own sizes. A hard
/// shadow's border counts too (about 7 px of it lie in the lit region), so compare on
/// scenes without, or against the reference's own figure.
pub fn gap_fraction(image: &HdrImage) -> f64 {
    let (w, h) = (image.width as i64, image.height as i64);
    let value: Vec<f64> = image.pixels.iter().map(|p| (p[0] + p[1] + p[2]) as f64).collect();
    let lit: Vec<f64> = value.iter().copied().filter(|v| *v > 0.0).collect();
    if lit.is_empty() {
        return 0.0;
    }
    let lit_mean = lit.iter().sum::<f64>() / lit.len() as f64;
    // Summed-area table, one row and column of zeros in front.
    let mut table = vec![0.0f64; ((w + 1) * (h + 1)) as usize];
    for y in 0..h {
        let mut row = 0.0;
        for x in 0..w {
            row += value[(y * w + x) as usize];
            table[((y + 1) * (w + 1) + x + 1) as usize] = table[(y * (w + 1) + x + 1) as usize] + row;
        }
    }
    let at = |x: i64, y: i64| table[(y * (w + 1) + x) as usize];
    let (mut region, mut empty) = (0u64, 0u64);
    for y in 0..h {
        for x in 0..w {
            let (x0, x1) = ((x - GAP_NEIGHBOURHOOD_RADIUS).max(0), (x + GAP_NEIGHBOURHOOD_RADIUS + 1).min(w));
            let (y0, y1) = ((y - GAP_NEIGHBOURHOOD_RADIUS).max(0), (y + GAP_NEIGHBOURHOOD_RADIUS + 1).min(h));
            let mean = (at(x1, y1) - at(x0, y1) - at(x1, y0) + at(x0, y0)) / ((x1 - x0) * (y1 - y0)) as f64;
            if mean > 0.1 * lit_mean {
                region += 1;
                empty += (value[(y * w + x) as usize] == 0.0) as u64;
            }
        }
    }
    if region == 0 {
        0.0
    } else {
        empty as f64 / region as f64
    }
}

/// Holes against the reference: among the pixels the reference lights together with all
/// eight neighbours (channel 0 above a tenth of its mean over the pixels it lights, as
/// `gap_fraction` judges a region lit), the share the GPU's buffer leaves at exactly zero.
/// Unlike `gap_fraction` it does not count a shadow's border, which the reference leaves dark
/// too (the tank at 800×800: gap fraction 0.092 for the reference itself).
pub fn lit_holes(gpu: &HdrImage, reference: &HdrImage) -> Result<f64> {
    if (gpu.width, gpu.height) != (reference.width, reference.height) {
        bail!("size mismatch: {}×{} vs {}×{}", gpu.width, gpu.height, reference.width, reference.height);
    }
    let (w, h) = (gpu.width as i64, gpu.height as i64);
    let lit_values: Vec<f64> = reference.pixels.iter().map(|p| p[0] as f64).filter(|v| *v > 0.0).collect();
    if lit_values.is_empty() {
        return Ok(0.0);
    }
    let threshold = 0.1 * lit_values.iter().sum::<f64>() / lit_values.len() as f64;
    let lit = |x: i64, y: i64| {
        (0..w).contains(&x) && (0..h).contains(&y) && reference.at(x as u32, y as u32)[0] as f64 > threshold
    };
    let (mut region, mut holes) = (0u64, 0u64);
    for y in 0..h {
        for x in 0..w {
            if (-1..=1).all(|dy| (-1..=1).all(|dx| lit(x + dx, y + dy))) {
                region += 1;
                holes += (gpu.at(x as u32, y as u32)[0] == 0.0) as u64;
            }
        }
    }
    Ok(if region == 0 { 0.0 } else { holes as f64 / region as f64 })
}

/// Half the side of the neighbourhood `light_in_shadow` judges dark by: 5×5 pixels.
pub const SHADOW_RADIUS: i64 = 2;

/// Light in the reference's shadows: the share of the GPU buffer's light (channel 0) that
/// lies where the reference holds nothing in the pixel and in all its 5×5 neighbourhood. A
/// shadow's interior, not its border (the pixels beside the edge may hold some of the lit
/// side's light in either), nor a lone empty pixel of a noisy reference. The footprint points'
/// hats, a photon's span wide, ran into the shadows of receivers nearer the light before
/// they were held to where a photon could land (docs/accuracy.md, "Hats held out of the
/// shadows").
pub fn light_in_shadow(gpu: &HdrImage, reference: &HdrImage) -> Result<f64> {
    if (gpu.width, gpu.height) != (reference.width, reference.height) {
        bail!("size mismatch: {}×{} vs {}×{}", gpu.width, gpu.height, reference.width, reference.height);
    }
    let (w, h) = (gpu.width as i64, gpu.height as i64);
    let dark =
        |x: i64, y: i64| !(0..w).contains(&x) || !(0..h).contains(&y) || reference.at(x as u32, y as u32)[0] <= 0.0;
    let r = SHADOW_RADIUS;
    let (mut total, mut in_shadow) = (0.0f64, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            let light = gpu.at(x as u32, y as u32)[0] as f64;
            total += light;
            if light != 0.0 && (-r..=r).all(|dy| (-r..=r).all(|dx| dark(x + dx, y + dy))) {
                in_shadow += light;
            }
        }
    }
    Ok(if total > 0.0 { in_shadow / total } else { 0.0 })
}

/// The radiance (W/(m²·sr), RGB) behind the compose pass's 8-bit sRGB output: the sRGB
/// encoding and the tonemap `1 − e^(−exposure·L)` undone. A channel at 255 is read as 254.5,
/// the brightest value the byte can stand for without being clipped.
pub fn output_radiance(rgba8: &[u8], exposure: f32) -> Vec<[f32; 3]> {
    let decode = |byte: u8| {
        let v = (byte as f32).min(254.5) / 255.0;
        let mapped = if v <= 0.04045 { v / 12.92 } else { ((v + 0.055) / 1.055).powf(2.4) };
        -(1.0 - mapped).ln() / exposure
    };
    rgba8.chunks_exact(4).map(|p| [decode(p[0]), decode(p[1]), decode(p[2])]).collect()
}

/// How far a composed image is from the same frame composed from full-resolution effect
/// buffers, near edges and overall. Low-resolution effect buffers upsampled across a depth
/// edge bleed one side's light onto the other (a halo); the error near the strongest edges
/// shows it, the whole-image figure shows what it costs elsewhere.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct EdgeError {
    /// √(mean (test − ref)²) / mean ref over the pixels within `EDGE_BAND` px of an edge.
    pub near_edges: f64,
    /// The same over every pixel.
    pub whole: f64,
    /// How many pixels the edge band holds.
    pub edge_pixels: usize,
}

/// The edge band's half width, px: pixels within this Chebyshev distance of an edge pixel.
pub const EDGE_BAND: i64 = 3;
/// The edges: the pixels whose gradient of the reference's luminance is in its top 5 %.
pub const EDGE_QUANTILE: f64 = 0.95;

/// `test` against `reference` (linear RGB, `width`×`height`, rows from the top). Edges are the
/// reference's: where its luminance's Sobel gradient is in the top `1 − EDGE_QUANTILE`.
pub fn edge_error(test: &[[f32; 3]], reference: &[[f32; 3]], width: usize, height: usize) -> Result<EdgeError> {
    if test.len() != width * height || reference.len() != width * height {
        bail!("edge error: {} and {} pixels for a {width}×{height} image", test.len(), reference.len());
    }
    if width < 3 || height < 3 {
        bail!("edge error: a {width}×{height} image has no interior to find edges in");
    }
    let luminance: Vec<f64> =
        reference.iter().map(|p| 0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64).collect();
    let at = |x: usize, y: usize| luminance[y * width + x];
    let mut gradient = vec![0.0f64; width * height];
    for y in 1..height - 1 {
        for x in 1..width - 1 {
            let gx = at(x + 1, y - 1) + 2.0 * at(x + 1, y) + at(x + 1, y + 1)
                - at(x - 1, y - 1)
                - 2.0 * at(x - 1, y)
                - at(x - 1, y + 1);
            let gy = at(x - 1, y + 1) + 2.0 * at(x, y + 1) + at(x + 1, y + 1)
                - at(x - 1, y - 1)
                - 2.0 * at(x, y - 1)
                - at(x + 1, y - 1);
            gradient[y * width + x] = gx.hypot(gy);
        }
    }
    let mut sorted = gradient.clone();
    sorted.sort_by(f64::total_cmp);
    let threshold = sorted[((sorted.len() - 1) as f64 * EDGE_QUANTILE) as usize];
    let mut band = vec![false; width * height];
    for y in 0..height as i64 {
        for x in 0..width as i64 {
            let g = gradient[y as usize * width + x as usize];
            if g <= threshold || g == 0.0 {
                continue;
            }
            for by in (y - EDGE_BAND).max(0)..=(y + EDGE_BAND).min(height as i64 - 1) {
                for bx in (x - EDGE_BAND).max(0)..=(x + EDGE_BAND).min(width as i64 - 1) {
                    band[by as usize * width + bx as usize] = true;
                }
            }
        }
    }
    let error = |inside: &dyn Fn(usize) -> bool| -> Result<(f64, usize)> {
        let (mut sq, mut sum, mut n) = (0.0f64, 0.0f64, 0usize);
        for (t, r) in test.iter().zip(reference).enumerate().filter(|(i, _)| inside(*i)).map(|(_, p)| p) {
            for c in 0..3 {
                sq += (t[c] as f64 - r[c] as f64).powi(2);
                sum += r[c] as f64;
            }
            n += 1;
        }
        if n == 0 || !(sum > 0.0) {
            bail!("edge error: the reference is black where it is measured ({n} pixels)");
        }
        let samples = (3 * n) as f64;
        Ok(((sq / samples).sqrt() / (sum / samples), n))
    };
    let (near_edges, edge_pixels) = error(&|i| band[i])?;
    let (whole, _) = error(&|_| true)?;
    Ok(EdgeError { near_edges, whole, edge_pixels })
}

/// Frame-to-frame change of one buffer: √(mean (b − a)²) / mean of both. Measured for the
/// GPU and for the reference at the same two times, the GPU's excess over the reference's is
/// flicker the method adds (photons jumping between pixels, splats popping at map texels).
pub fn frame_change(a: &HdrImage, b: &HdrImage) -> Result<f64> {
    same_size(a, b, "frame change")?;
    let (mut sq, mut sum) = (0.0f64, 0.0f64);
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        for c in 0..3 {
            let (p, q) = (p[c] as f64, q[c] as f64);
            sq += (q - p) * (q - p);
            sum += 0.5 * (p + q);
        }
    }
    if !(sum > 0.0) {
        return Ok(0.0);
    }
    let n = (a.pixels.len() * 3) as f64;
    Ok((sq / n).sqrt() / (sum / n))
}

/// Bilinear sample at normalised `uv`, clamped to the edge: the compose pass's linear sampler.
pub fn sample_bilinear(image: &HdrImage, u: f32, v: f32) -> [f32; 4] {
    let x = (u * image.width as f32 - 0.5).clamp(0.0, (image.width - 1) as f32);
    let y = (v * image.height as f32 - 0.5).clamp(0.0, (image.height - 1) as f32);
    let (x0, y0) = (x.floor() as u32, y.floor() as u32);
    let (x1, y1) = ((x0 + 1).min(image.width - 1), (y0 + 1).min(image.height - 1));
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let (a, b, c, d) = (image.at(x0, y0), image.at(x1, y0), image.at(x0, y1), image.at(x1, y1));
    std::array::from_fn(|i| (a[i] * (1.0 - fx) + b[i] * fx) * (1.0 - fy) + (c[i] * (1.0 - fx) + d[i] * fx) * fy)
}

/// `image` resampled to width × height as compose reads an effect buffer: bilinearly between
/// texel centres, clamped at the border (`sample_bilinear`). Used to measure a buffer smaller
/// than the output against a reference traced at the output's size.
pub fn upsampled(image: &HdrImage, width: u32, height: u32) -> HdrImage {
    let mut pixels = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let (u, v) = ((x as f32 + 0.5) / width as f32, (y as f32 + 0.5) / height as f32);
            pixels.push(sample_bilinear(image, u, v));
        }
    }
    HdrImage { width, height, pixels }
}

/// The final image, 8-bit sRGB RGB, as compose.frag makes it: scene colour + caustic
/// irradiance × albedo/π × transmittance + godray radiance (both upsampled bilinearly), then
/// `1 − e^(−exposure·L)`. FLIP compares two images composed here, one with the GPU's photon
/// buffers and one with the reference's, so it measures the photon buffers' error and not
/// the rounding of the GPU's own compose.
pub fn compose_srgb8(
    scene_color: &HdrImage,
    albedo_transmittance: &HdrImage,
    caustics: Option<&HdrImage>,
    godrays: Option<&HdrImage>,
    exposure: f32,
) -> Vec<u8> {
    let (w, h) = (scene_color.width, scene_color.height);
    let mut radiance = scene_color.clone();
    for y in 0..h {
        for x in 0..w {
            let (u, v) = ((x as f32 + 0.5) / w as f32, (y as f32 + 0.5) / h as f32);
            let l = &mut radiance.pixels[(y * w + x) as usize];
            if let Some(c) = caustics {
                let (e, a) = (sample_bilinear(c, u, v), albedo_transmittance.at(x, y));
                (0..3).for_each(|i| l[i] += a[i] * e[i]);
            }
            if let Some(g) = godrays {
                let r = sample_bilinear(g, u, v);
                (0..3).for_each(|i| l[i] += r[i]);
            }
        }
    }
    // The same tonemap as the render command's PNGs; FLIP takes RGB, so alpha is dropped.
    tonemap_srgb8(&radiance, exposure).chunks_exact(4).flat_map(|p| [p[0], p[1], p[2]]).collect()
}

/// Mean FLIP (NVIDIA's perceptual difference, 0 = identical, 1 = maximal) between two 8-bit
/// sRGB RGB images, at the default viewing condition (67 pixels per degree).
pub fn flip(reference_rgb: &[u8], test_rgb: &[u8], width: u32, height: u32) -> Result<f64> {
    let n = (width * height * 3) as usize;
    if reference_rgb.len() != n || test_rgb.len() != n {
        bail!("FLIP: images of {} and {} bytes for {width}×{height} RGB", reference_rgb.len(), test_rgb.len());
    }
    let reference = nv_flip::FlipImageRgb8::with_data(width, height, reference_rgb);
    let test = nv_flip::FlipImageRgb8::with_data(width, height, test_rgb);
    let error_map = nv_flip::flip(reference, test, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    Ok(nv_flip::FlipPool::from_image(&error_map).mean() as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn upsampling_reads_between_texel_centres_as_compose_does() {
        let image = HdrImage { width: 2, height: 1, pixels: vec![[0.0; 4], [1.0; 4]] };
        let wide = upsampled(&image, 4, 1);
        let red: Vec<f32> = wide.pixels.iter().map(|p| p[0]).collect();
        // Output centres at 1/8, 3/8, 5/8, 7/8 fall at texel coordinates −¼ (clamped), ¼, ¾
        // and 1¼ (clamped).
        assert_eq!(red, [0.0, 0.25, 0.75, 1.0]);
    }

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> f32) -> HdrImage {
        let pixels = (0..h).flat_map(|y| (0..w).map(move |x| (x, y))).map(|(x, y)| [f(x, y); 4]).collect();
        HdrImage { width: w, height: h, pixels }
    }

    #[test]
    fn edge_error_sees_a_halo_at_the_edge_and_not_elsewhere() {
        // A bright pillar (x < 20) against a dim wall, and the same with the pillar's light
        // bled 2 px onto the wall: all the error is in the edge band.
        let (w, h) = (48usize, 32usize);
        let sharp: Vec<[f32; 3]> = (0..w * h).map(|i| if i % w < 20 { [1.0; 3] } else { [0.1; 3] }).collect();
        let mut haloed = sharp.clone();
        for y in 0..h {
            for x in 20..22 {
                haloed[y * w + x] = [0.5; 3];
            }
        }
        let same = edge_error(&sharp, &sharp, w, h).unwrap();
        assert_eq!((same.near_edges, same.whole), (0.0, 0.0));
        let e = edge_error(&haloed, &sharp, w, h).unwrap();
        // The band: 2 edge columns (19, 20) widened by 3 px each way, all rows.
        assert_eq!(e.edge_pixels, 8 * h, "{e:?}");
        assert!(e.near_edges > 2.0 * e.whole && e.whole > 0.0, "{e:?}");
        assert!(edge_error(&sharp, &sharp[1..], w, h).is_err());
    }

    #[test]
    fn output_radiance_undoes_the_tonemap() {
        let exposure = 0.7;
        let hdr = image(4, 1, |x, _| 0.3 * x as f32 + 0.05);
        let back = output_radiance(&tonemap_srgb8(&hdr, exposure), exposure);
        for (p, l) in hdr.pixels.iter().zip(&back) {
            // 8-bit steps: within 2 % here.
            assert!((l[0] - p[0]).abs() <= 0.02 * p[0] + 1e-3, "{} against {}", l[0], p[0]);
        }
    }

    /// A `w`×`h` image whose pixel (x, y) holds f(x, y) in every channel.
    fn grey_image(w: u32, h: u32, f: &dyn Fn(u32, u32) -> f32) -> HdrImage {
        HdrImage {
            width: w,
            height: h,
            pixels: (0..w * h)
                .map(|i| {
                    let v = f(i % w, i / w);
                    [v, v, v, 1.0]
                })
                .collect(),
        }
    }

    #[test]
    fn light_in_shadow_counts_the_light_inside_what_the_reference_leaves_dark() {
        let image = grey_image;
        // The reference lights the left half (x < 6) but for one empty pixel inside it; the GPU
        // lights every pixel with 1.
        let reference = image(12, 8, &|x, y| if x < 6 && (x, y) != (2, 4) { 1.0 } else { 0.0 });
        let gpu = image(12, 8, &|_, _| 1.0);
        // Dark with all of its 5×5 neighbourhood: x in 8..=11 (x = 6 and 7 see the lit half),
        // every row; the lone empty pixel is not.
        let share = light_in_shadow(&gpu, &reference).unwrap();
        assert!((share - 4.0 * 8.0 / 96.0).abs() < 1e-12, "{share}");
        // Light only where the reference is lit reads zero.
        let lit_only = image(12, 8, &|x, _| if x < 6 { 3.0 } else { 0.0 });
        assert_eq!(light_in_shadow(&lit_only, &reference).unwrap(), 0.0);
        assert!(light_in_shadow(&image(4, 4, &|_, _| 1.0), &reference).is_err());
    }

    #[test]
    fn lit_holes_count_zero_pixels_inside_what_the_reference_lights() {
        let lit = grey_image;
        // The reference lights the left half; the GPU the same but for one pixel inside it and
        // all of the right half.
        let reference = lit(10, 10, &|x, _| if x < 5 { 1.0 } else { 0.0 });
        let gpu = lit(10, 10, &|x, y| if (x, y) == (2, 5) { 0.0 } else { 1.0 });
        // Lit with all neighbours: x in 0..=3 (x = 0 has no left neighbour: 1..=3), y in 1..=8.
        let holes = lit_holes(&gpu, &reference).unwrap();
        assert!((holes - 1.0 / 24.0).abs() < 1e-12, "{holes}");
        assert_eq!(lit_holes(&reference, &reference).unwrap(), 0.0);
    }

    #[test]
    fn gap_fraction_counts_holes_in_lit_regions_only() {
        let image = |f: &dyn Fn(u32, u32) -> f32| HdrImage {
            width: 64,
            height: 64,
            pixels: (0..64 * 64).map(|i| [f(i % 64, i / 64), 0.0, 0.0, 1.0]).collect(),
        };
        assert_eq!(gap_fraction(&image(&|_, _| 1.0)), 0.0);
        // Dots every 2 px in each axis: 3 of every 4 pixels of the lit region are empty.
        let dots = gap_fraction(&image(&|x, y| if x % 2 == 0 && y % 2 == 0 { 4.0 } else { 0.0 }));
        assert!((dots - 0.75).abs() < 0.01, "{dots}");
        // Dots 4 px apart are a mean of a sixteenth of their value: too faint to be lit.
        assert_eq!(gap_fraction(&image(&|x, y| if x % 4 == 1 && y % 4 == 1 { 16.0 } else { 0.0 })), 0.0);
        // Half lit, half dark: only the dark strip next to the border is in the lit region.
        let half = gap_fraction(&image(&|x, _| if x < 32 { 1.0 } else { 0.0 }));
        assert!(half > 0.0 && half < 7.0 / 39.0 + 1e-9, "{half}");
        assert_eq!(gap_fraction(&image(&|_, _| 0.0)), 0.0);
    }

    #[test]
    fn buffer_error_figures() {
        let r = image(8, 8, |x, _| 1.0 + x as f32);
        assert_eq!(buffer_error(&r, &r).unwrap(), BufferError::default());
        // 10 % too bright everywhere: every figure reads 0.1 (rmse: 0.1·rms/mean of r).
        let t = image(8, 8, |x, _| 1.1 * (1.0 + x as f32));
        let e = buffer_error(&t, &r).unwrap();
        assert!((e.flux_error - 0.1).abs() < 1e-6 && (e.mean_relative_error - 0.1).abs() < 1e-6, "{e:?}");
        let rms = ((1..=8).map(|v| (v * v) as f64).sum::<f64>() / 8.0).sqrt();
        assert!((e.relative_rmse - 0.1 * rms / 4.5).abs() < 1e-6, "{e:?}");
        // Energy moved, not lost: flux error 0, the others not.
        let moved = image(8, 8, |x, _| 1.0 + (7 - x) as f32);
        let e = buffer_error(&moved, &r).unwrap();
        assert!(e.flux_error.abs() < 1e-9 && e.relative_rmse > 0.5, "{e:?}");
        assert!(buffer_error(&image(4, 4, |_, _| 1.0), &r).is_err());
        assert!(buffer_error(&r, &image(8, 8, |_, _| 0.0)).is_err());
    }

    #[test]
    fn frame_change_is_zero_for_a_still_frame() {
        let a = image(8, 8, |x, y| (x * y) as f32);
        assert_eq!(frame_change(&a, &a).unwrap(), 0.0);
        let b = image(8, 8, |x, y| (x * y) as f32 * 1.2);
        assert!(frame_change(&a, &b).unwrap() > 0.1);
    }

    #[test]
    fn compose_and_flip() {
        let black = image(16, 16, |_, _| 0.0);
        let lit = image(16, 16, |_, _| 1.0);
        let caustic = image(8, 8, |x, _| x as f32 * 0.2);
        let a = compose_srgb8(&black, &lit, Some(&caustic), None, 1.0);
        assert_eq!(a.len(), 16 * 16 * 3);
        // Bilinear upsampling: a ramp stays monotone along x.
        assert!(a[3 * 15] > a[3 * 8] && a[3 * 8] > a[0]);
        assert_eq!(flip(&a, &a, 16, 16).unwrap(), 0.0);
        let b = compose_srgb8(&black, &lit, None, None, 1.0);
        assert!(flip(&a, &b, 16, 16).unwrap() > 0.05);
        assert!(flip(&a, &b[..10], 16, 16).is_err());
    }
}
