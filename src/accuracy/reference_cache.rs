//! The reference buffers a sweep measures against, cached on disk by scene and settings
//! (`underlight reference`), and the progress bar shown while one is traced.

use crate::frame::uniforms::FrameExtents;
use crate::image_io::{read_pfm, write_pfm};
use crate::passes::PassId;
use crate::reference::{ReferenceImages, ReferenceSettings};
use crate::scene::Scene;
use crate::shader_math::NoiseTexture;
use anyhow::{Context as _, Result};
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// FNV-1a over bytes: a cache key stable across runs and toolchains (std's hasher is not).
fn fnv1a(bytes: &[u8], mut h: u64) -> u64 {
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    h
}

/// What the reference depends on: geometry, camera, light, water (its parameters and the
/// noise texture's texels, which are code, not scene: a change to the texture must not hand
/// back buffers traced over the old water), medium, which effects exist, the target sizes,
/// the time and the reference's own settings. Not the method's settings (grids, iterations,
/// point sizes, filter): a sweep over those reuses one reference.
fn reference_key(
    scene: &Scene,
    extents: &FrameExtents,
    time: f32,
    settings: &ReferenceSettings,
    noise: &NoiseTexture,
) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    let e = &scene.effects;
    let text = format!(
        "{:?}|{:?}|{:?}|{:?}|{}|{}|{:?}|{:?}|{}|{}|{}",
        scene.camera,
        scene.light,
        scene.water,
        scene.medium,
        e.caustics,
        e.godrays,
        extents.caustic,
        extents.godray,
        time.to_bits(),
        settings.caustic_photons,
        settings.godray_beams
    );
    h = fnv1a(text.as_bytes(), h);
    h = fnv1a(&settings.seed.to_le_bytes(), h);
    h = fnv1a(&noise.size.to_le_bytes(), h);
    h = fnv1a(bytemuck::cast_slice(&noise.texels), h);
    for m in &scene.meshes {
        h = fnv1a(bytemuck::cast_slice(&m.positions), h);
        h = fnv1a(bytemuck::cast_slice(&m.indices), h);
    }
    format!("{}-{h:016x}", scene.name.replace(|c: char| !c.is_ascii_alphanumeric(), "_"))
}

/// The default cache folder: `$XDG_CACHE_HOME/underlight/reference`, else
/// `~/.cache/underlight/reference`, else `target/underlight-reference`.
pub fn default_cache_dir() -> PathBuf {
    let base = std::env::var_os("XDG_CACHE_HOME")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".cache")))
        .unwrap_or_else(|| PathBuf::from("target"));
    base.join("underlight").join("reference")
}

/// A progress bar on stderr: `label [#####.....]  45 %`, redrawn at most every 1 %.
pub struct Progress {
    label: String,
    last: std::sync::atomic::AtomicU32,
}

impl Progress {
    pub fn new(label: impl Into<String>) -> Self {
        Self { label: label.into(), last: std::sync::atomic::AtomicU32::new(u32::MAX) }
    }

    pub fn update(&self, fraction: f64) {
        use std::io::IsTerminal as _;
        let percent = (fraction.clamp(0.0, 1.0) * 100.0) as u32;
        // Into a log (not a terminal) every 25 %, so redraws do not flood it.
        let step = if std::io::stderr().is_terminal() { 1 } else { 25 };
        let percent = percent / step * step;
        if self.last.swap(percent, std::sync::atomic::Ordering::Relaxed) == percent {
            return;
        }
        let filled = (percent / 4) as usize;
        let bar = format!("{} [{}{}] {percent:>3} %", self.label, "#".repeat(filled), ".".repeat(25 - filled));
        if step == 1 {
            eprint!("\r{bar}{}", if percent == 100 { "\n" } else { "" });
            std::io::stderr().flush().ok();
        } else {
            eprintln!("{bar}");
        }
    }
}

/// The reference buffers for `scene` at `time` and `extents`: read from `cache_dir` when a
/// run with the same inputs wrote them, otherwise traced (with a progress bar) and stored.
pub fn cached_reference(
    scene: &Scene,
    time: f32,
    extents: &FrameExtents,
    settings: &ReferenceSettings,
    cache_dir: &Path,
) -> Result<ReferenceImages> {
    let dir = cache_dir.join(reference_key(scene, extents, time, settings, &NoiseTexture::generate()));
    let (caustics, caustics_half, godrays) =
        (dir.join("caustics.pfm"), dir.join("caustics_half.pfm"), dir.join("godrays.pfm"));
    let want = |on: bool, p: &Path| !on || p.exists();
    let plan = crate::frame::FramePlan::for_scene(scene);
    let (has_c, has_g) = (plan.runs(PassId::Caustics), plan.runs(PassId::Godrays));
    // A cache from before the half buffer existed lacks it, and is traced again.
    if dir.join("done").exists() && want(has_c, &caustics) && want(has_c, &caustics_half) && want(has_g, &godrays) {
        let load = |on: bool, p: &Path| if on { read_pfm(p).map(Some) } else { Ok(None) };
        return Ok(ReferenceImages {
            caustics: load(has_c, &caustics)?,
            caustics_half: load(has_c, &caustics_half)?,
            godrays: load(has_g, &godrays)?,
        });
    }
    let progress = Progress::new(format!("reference {} t={time}", scene.name));
    let images = crate::reference::render(scene, time, extents, settings, &|f| progress.update(f))?;
    progress.update(1.0);
    std::fs::create_dir_all(&dir).with_context(|| format!("creating the reference cache {}", dir.display()))?;
    if let (Some(c), Some(h)) = (&images.caustics, &images.caustics_half) {
        write_pfm(&caustics, c)?;
        write_pfm(&caustics_half, h)?;
    }
    if let Some(g) = &images.godrays {
        write_pfm(&godrays, g)?;
    }
    std::fs::write(dir.join("done"), b"")?;
    Ok(images)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_key_follows_the_water_s_noise_texels() {
        let scene = crate::scene::load("tank").unwrap();
        let extents = crate::frame::target_extents(&scene, [64, 40], 64.0, 8.0);
        let settings = ReferenceSettings { caustic_photons: 1000, godray_beams: 100, threads: 1, seed: 1 };
        let noise = NoiseTexture::generate();
        let key = reference_key(&scene, &extents, 1.0, &settings, &noise);
        assert_eq!(key, reference_key(&scene, &extents, 1.0, &settings, &noise.clone()));
        let mut changed = noise.clone();
        changed.texels[77][1] += 1e-3;
        assert_ne!(key, reference_key(&scene, &extents, 1.0, &settings, &changed), "one texel's gradient changed");
        assert_ne!(key, reference_key(&scene, &extents, 2.0, &settings, &noise), "another time");
    }
}
