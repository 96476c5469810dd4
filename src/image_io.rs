//! Images on disk: float dumps (PFM) of HDR targets for scripts and tests, and tonemapped
//! sRGB PNGs for people.

use anyhow::{bail, Context as _, Result};
use std::io::{BufRead, BufReader, Read, Write};
use std::path::Path;

/// Linear RGBA floats, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct HdrImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl HdrImage {
    pub fn at(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Sum of each channel over the image (f64, so large targets sum exactly enough).
    pub fn channel_sums(&self) -> [f64; 4] {
        let mut s = [0.0f64; 4];
        for p in &self.pixels {
            for c in 0..4 {
                s[c] += p[c] as f64;
            }
        }
        s
    }

    /// Whether any channel of any texel is NaN or infinite.
    pub fn has_non_finite(&self) -> bool {
        self.pixels.iter().any(|p| p.iter().any(|v| !v.is_finite()))
    }
}

/// Writes RGB as a little-endian PFM (rows bottom to top, as the format requires).
pub fn write_pfm(path: &Path, image: &HdrImage) -> Result<()> {
    let mut out = Vec::with_capacity(image.pixels.len() * 12 + 32);
    write!(out, "PF\n{} {}\n-1.0\n", image.width, image.height)?;
    for y in (0..image.height).rev() {
        for x in 0..image.width {
            for c in &image.at(x, y)[..3] {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    std::fs::write(path, out).with_context(|| format!("writing {}", path.display()))
}

/// Writes RGB as an OpenEXR file of 32-bit float channels R, G and B (no compression, one
/// layer), which every EXR reader opens.
pub fn write_exr(path: &Path, image: &HdrImage) -> Result<()> {
    use exr::prelude::*;
    let (w, h) = (image.width as usize, image.height as usize);
    let channels = SpecificChannels::rgb(|position: Vec2<usize>| {
        let p = image.pixels[position.y() * w + position.x()];
        (p[0], p[1], p[2])
    });
    let layer = Layer::new((w, h), LayerAttributes::default(), Encoding::UNCOMPRESSED, channels);
    Image::from_layer(layer).write().to_file(path).with_context(|| format!("writing {}", path.display()))
}

/// Reads the first RGB(A) layer of an OpenEXR file (any sample type, as f32); alpha is 1
/// where the file has none.
pub fn read_exr(path: &Path) -> Result<HdrImage> {
    use exr::prelude::*;
    let image = read_first_rgba_layer_from_file(
        path,
        |resolution, _| HdrImage {
            width: resolution.width() as u32,
            height: resolution.height() as u32,
            pixels: vec![[0.0; 4]; resolution.width() * resolution.height()],
        },
        |image: &mut HdrImage, position, (r, g, b, a): (f32, f32, f32, f32)| {
            let i = position.y() * image.width as usize + position.x();
            image.pixels[i] = [r, g, b, a];
        },
    )
    .with_context(|| format!("reading {}", path.display()))?;
    Ok(image.layer_data.channel_data.pixels)
}

/// Reads a colour (`PF`) or greyscale (`Pf`) PFM of either endianness; alpha is set to 1.
pub fn read_pfm(path: &Path) -> Result<HdrImage> {
    let file = std::fs::File::open(path).with_context(|| format!("opening {}", path.display()))?;
    let mut r = BufReader::new(file);
    let mut header = Vec::new();
    // Three whitespace-separated header lines: kind, "w h", scale.
    for _ in 0..3 {
        let mut line = String::new();
        r.read_line(&mut line)?;
        header.push(line.trim().to_string());
    }
    let channels = match header[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => bail!("{}: not a PFM (header {other:?})", path.display()),
    };
    let dims: Vec<u32> = header[1].split_whitespace().filter_map(|s| s.parse().ok()).collect();
    let [width, height] = dims[..] else { bail!("{}: bad PFM size line {:?}", path.display(), header[1]) };
    let scale: f32 = header[2].parse().with_context(|| format!("{}: bad PFM scale", path.display()))?;
    let little = scale < 0.0;
    let mut data = Vec::new();
    r.read_to_end(&mut data)?;
    let expected = width as usize * height as usize * channels * 4;
    if data.len() != expected {
        bail!("{}: PFM has {} data bytes, expected {expected}", path.display(), data.len());
    }
    let mut pixels = vec![[0.0, 0.0, 0.0, 1.0]; (width * height) as usize];
    for (i, v) in data.chunks_exact(4).enumerate() {
        let b = [v[0], v[1], v[2], v[3]];
        let value = if little { f32::from_le_bytes(b) } else { f32::from_be_bytes(b) };
        let texel = i / channels;
        let (x, y_from_bottom) = (texel as u32 % width, texel as u32 / width);
        let p = &mut pixels[((height - 1 - y_from_bottom) * width + x) as usize];
        if channels == 1 {
            p[0] = value;
            p[1] = value;
            p[2] = value;
        } else {
            p[i % 3] = value;
        }
    }
    Ok(HdrImage { width, height, pixels })
}

/// Linear → sRGB transfer function (IEC 61966-2-1).
pub fn linear_to_srgb(c: f32) -> f32 {
    let c = c.clamp(0.0, 1.0);
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// Tonemaps linear radiance to 8-bit sRGB RGBA: `1 − exp(−exposure·c)` per channel, which
/// keeps dark values linear and rolls highlights off instead of clipping them.
pub fn tonemap_srgb8(image: &HdrImage, exposure: f32) -> Vec<u8> {
    let mut out = Vec::with_capacity(image.pixels.len() * 4);
    for p in &image.pixels {
        for c in &p[..3] {
            let mapped = if c.is_finite() { 1.0 - (-exposure * c.max(0.0)).exp() } else { 0.0 };
            out.push((linear_to_srgb(mapped) * 255.0 + 0.5) as u8);
        }
        out.push(255);
    }
    out
}

/// Writes 8-bit RGBA as PNG.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<()> {
    let file = std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgba);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header().with_context(|| format!("writing {}", path.display()))?;
    writer.write_image_data(rgba).with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pfm_round_trip_keeps_orientation_and_values() {
        let image = HdrImage {
            width: 3,
            height: 2,
            pixels: (0..6).map(|i| [i as f32, 0.5 * i as f32, -1.0e-3 * i as f32, 1.0]).collect(),
        };
        let path = std::env::temp_dir().join(format!("underlight-pfm-{}.pfm", std::process::id()));
        write_pfm(&path, &image).unwrap();
        let back = read_pfm(&path).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(back, image);
    }

    #[test]
    fn tonemap_is_monotone_and_srgb_encoded() {
        let image = HdrImage { width: 4, height: 1, pixels: vec![[0.0; 4], [0.1; 4], [1.0; 4], [100.0; 4]] };
        let px = tonemap_srgb8(&image, 1.0);
        assert_eq!(px[0], 0);
        assert!(px[4] < px[8] && px[8] < px[12]);
        // 1 − e^−1 = 0.632 linear → 0.8165 sRGB → 208.7 → 208.
        assert_eq!(px[8], 208);
        assert_eq!(px[12], 255);
    }
}
