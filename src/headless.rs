//! Headless rendering: frames into an off-screen target, the last one read back.

use crate::error::Result;
use crate::frame::FrameRing;
use crate::frame::PassTimings;
use crate::frame::{Frame, FrameOptions};
use crate::image_io::HdrImage;
use crate::passes::shadow::{FIRST_MAPS, STEEP_MAPS};
use crate::passes::PassId;
use crate::scene::Scene;
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::readback::Readback;
use crate::vk::timing::TimedPass;
use ash::vk;
use std::sync::Arc;

/// Median GPU milliseconds of each pass over several frames, in pass order.
pub fn median_timings<P: TimedPass>(frames: &[crate::vk::timing::PassTimings<P>]) -> crate::vk::timing::PassTimings<P> {
    let mut ids: Vec<P> = frames.iter().flat_map(|t| t.passes.iter().map(|(id, _)| *id)).collect();
    ids.sort();
    ids.dedup();
    let mut out = crate::vk::timing::PassTimings::default();
    for id in ids {
        let mut v: Vec<f64> = frames.iter().filter_map(|t| t.get(id)).collect();
        v.sort_by(f64::total_cmp);
        out.passes.push((id, v[v.len() / 2]));
    }
    out
}

/// What a headless render of a scene reads back from its last frame.
pub struct SceneImages {
    /// The tonemapped output, 8-bit sRGB RGBA, rows from the top.
    pub output: Vec<u8>,
    pub width: u32,
    pub height: u32,
    /// HDR scene colour (radiance, W/(m²·sr)).
    pub scene_color: HdrImage,
    /// albedo/π × water transmittance to the camera, per output pixel.
    pub albedo_transmittance: HdrImage,
    /// Caustic irradiance (W/m²) at the caustic target's size, when the frame has caustics,
    /// before and after the filter.
    pub caustics: Option<HdrImage>,
    pub caustics_filtered: Option<HdrImage>,
    /// Godray radiance (W/(m²·sr)) at the godray target's size, before and after the filter.
    pub godrays: Option<HdrImage>,
    pub godrays_filtered: Option<HdrImage>,
    /// With photon recording: the light's receiver maps, world positions (RGBA32F) and
    /// normals.
    pub light_positions: Option<HdrImage>,
    pub light_normals: Option<HdrImage>,
    /// With photon recording, where the frame has them: the second, steeper maps alike
    /// (`frame::uniforms::steep_light_axis`).
    pub steep_light_positions: Option<HdrImage>,
    pub steep_light_normals: Option<HdrImage>,
    /// With photon recording: per caustic photon, (hit, landed) and (surface, flux).
    pub photon_records: Option<Vec<[f32; 4]>>,
    /// With photon recording and godray beams: per beam, (hit, fate) and (surface, flux).
    pub beam_records: Option<Vec<[f32; 4]>>,
}

impl SceneImages {
    /// The photon effects that ran in this frame and deposited nothing (their buffer is zero
    /// everywhere), each with what a user can check. A planned effect that lands no photon is
    /// a fault to report, never a silent black buffer.
    pub fn silent_effects(&self, scene: &Scene) -> Vec<String> {
        let empty = |img: &Option<HdrImage>| img.as_ref().is_some_and(|i| i.pixels.iter().all(|p| p[..3] == [0.0; 3]));
        let w = &scene.water;
        let water = format!(
            "the water covers x ∈ [{}, {}], z ∈ [{}, {}] at y = {} m",
            w.extent_min.x, w.extent_max.x, w.extent_min.y, w.extent_max.y, w.level
        );
        let mut notes = Vec::new();
        if empty(&self.caustics) {
            notes.push(format!(
                "caustics ran but no photon landed in the view (the caustic buffer is zero): no photon that enters the water reaches a receiver the camera sees ({water}; the light travels along {}). Check water.extent_min/extent_max, light.direction and the camera",
                scene.light.direction
            ));
        }
        if empty(&self.godrays) {
            notes.push(format!(
                "godrays ran but no beam reached the view (the godray buffer is zero): no photon that enters the water ends on a receiver in front of the camera ({water}). Check water.extent_min/extent_max, light.direction and the camera"
            ));
        }
        notes
    }
}

/// A scene's frame with its ring of frames in flight and read-backs, kept alive across
/// renders so benchmarks time frames, not set-up.
pub struct SceneRenderer {
    pub frame: Frame,
    ring: FrameRing,
    output: Readback,
    scene_color: Readback,
    albedo_transmittance: Readback,
    /// Photon buffers in order: caustics, filtered caustics, godrays, filtered godrays.
    effects: [Option<Readback>; 4],
    /// With photon recording: the light's position and normal maps.
    light_maps: Option<[Readback; 2]>,
    /// And the second, steeper ones where the frame has them.
    steep_light_maps: Option<[Readback; 2]>,
}

impl SceneRenderer {
    pub fn new(device: &Arc<Device>, scene: &Scene, output: vk::Extent2D) -> Result<Self> {
        Self::with_options(device, scene, output, FrameOptions::default())
    }

    pub fn with_options(
        device: &Arc<Device>,
        scene: &Scene,
        output: vk::Extent2D,
        options: FrameOptions,
    ) -> Result<Self> {
        let frame = Frame::new(device, scene, output, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, options)?;
        let ring = FrameRing::new(device, options.pipeline_statistics)?;
        let output = Readback::new(device, &frame.compose.output.image)?;
        let scene_color = Readback::new(device, &frame.scene_pass.color)?;
        let albedo_transmittance = Readback::new(device, &frame.scene_pass.albedo_transmittance)?;
        let mut effects: [Option<Readback>; 4] = Default::default();
        for (slot, image) in effects.iter_mut().zip(effect_images(&frame)) {
            *slot = image.map(|i| Readback::new(device, i)).transpose()?;
        }
        // With photon recording, each pair of light maps the frame has (positions, normals):
        // the layers of the shadow pass's map arrays.
        let maps = |layer: u32| -> Result<Option<[Readback; 2]>> {
            let Some(shadow) = frame.shadow.as_ref().filter(|s| options.record_photons && layer < s.pairs()) else {
                return Ok(None);
            };
            Ok(Some([
                Readback::of_layer(device, &shadow.position, layer)?,
                Readback::of_layer(device, &shadow.normal, layer)?,
            ]))
        };
        let (light_maps, steep_light_maps) = (maps(FIRST_MAPS)?, maps(STEEP_MAPS)?);
        Ok(Self { frame, ring, output, scene_color, albedo_transmittance, effects, light_maps, steep_light_maps })
    }

    /// Renders `frames` frames at times `t0 + k·dt`; with `read_back`, the last frame's
    /// targets are copied to the host and returned.
    pub fn render(
        &mut self,
        frames: u32,
        t0: f32,
        dt: f32,
        read_back: bool,
    ) -> Result<(Vec<PassTimings>, Option<SceneImages>)> {
        let (out, sc, at, fx) = (&self.output, &self.scene_color, &self.albedo_transmittance, &self.effects);
        let lm = &self.light_maps;
        let steep_lm = &self.steep_light_maps;
        let frame = &mut self.frame;
        let timings = run_frames(&mut self.ring, frames, t0, dt, |slot, time, last| {
            frame.record(slot, time);
            if read_back && last {
                let cmd = slot.cmd;
                let frame = &*frame;
                slot.timer.pass(cmd, PassId::Readback, |cmd| {
                    let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
                    out.record(cmd, &frame.compose.output.image);
                    sc.record_from(cmd, &frame.scene_pass.color, read);
                    at.record_from(cmd, &frame.scene_pass.albedo_transmittance, read);
                    for (rb, image) in fx.iter().zip(effect_images(frame)) {
                        if let (Some(rb), Some(image)) = (rb, image) {
                            rb.record_from(cmd, image, read);
                        }
                    }
                    for [positions, normals] in [lm, steep_lm].into_iter().flatten() {
                        let shadow = frame.shadow.as_ref().expect("light map read-backs without a shadow pass");
                        positions.record_from(cmd, &shadow.position, read);
                        normals.record_from(cmd, &shadow.normal, read);
                    }
                });
            }
        })?;
        if !(read_back && frames > 0) {
            return Ok((timings, None));
        }
        let e = self.frame.compose.output.image.extent;
        // Photon buffers store values relative to E_surface (half-float precision); report
        // them in physical units.
        let e_surface = crate::frame::uniforms::surface_irradiance(self.frame.scene());
        let effect = |i: usize| -> Result<Option<HdrImage>> {
            let Some(rb) = &self.effects[i] else { return Ok(None) };
            let mut img = rb.read()?;
            for p in &mut img.pixels {
                for c in &mut p[..3] {
                    *c *= e_surface;
                }
            }
            Ok(Some(img))
        };
        let images = SceneImages {
            output: self.output.bytes().to_vec(),
            width: e.width,
            height: e.height,
            scene_color: self.scene_color.read()?,
            albedo_transmittance: self.albedo_transmittance.read()?,
            caustics: effect(0)?,
            caustics_filtered: effect(1)?,
            godrays: effect(2)?,
            godrays_filtered: effect(3)?,
            light_positions: self.light_maps.as_ref().map(|[p, _]| p.read()).transpose()?,
            light_normals: self.light_maps.as_ref().map(|[_, n]| n.read()).transpose()?,
            steep_light_positions: self.steep_light_maps.as_ref().map(|[p, _]| p.read()).transpose()?,
            steep_light_normals: self.steep_light_maps.as_ref().map(|[_, n]| n.read()).transpose()?,
            photon_records: self.frame.caustics.as_ref().and_then(|c| c.read_photon_records()),
            beam_records: self.frame.godrays.as_ref().and_then(|g| g.read_photon_records()),
        };
        Ok((timings, Some(images)))
    }
}

/// Every wave phase follows the clock: a NaN or infinite time would make every photon NaN and
/// leave the effect buffers empty for a reason no diagnostic names. Checks the times of
/// `frames` frames from `t0` in steps of `dt` (the viewer's, from its start time).
pub(crate) fn check_clock(t0: f32, dt: f32, frames: u32) -> Result<()> {
    let last = t0 + dt * frames.saturating_sub(1) as f32;
    if !(t0.is_finite() && dt.is_finite() && last.is_finite()) {
        return Err(crate::error::Error::InvalidParameter {
            name: "time",
            message: format!("the frames' times must be finite (first {t0} s, step {dt} s, last {last} s)"),
        });
    }
    Ok(())
}

/// Renders `frames` frames (time `t0 + k·dt`) through the ring of frames in flight; `record`
/// records one into its slot (the bool: it is the last). Returns each frame's per-pass GPU
/// times, in frame order. Headless measurement collects every frame's table, so this
/// allocates per frame; the viewer's loop does not.
pub(crate) fn run_frames<P: TimedPass>(
    ring: &mut crate::vk::commands::FrameRing<P>,
    frames: u32,
    t0: f32,
    dt: f32,
    mut record: impl FnMut(&mut crate::vk::commands::FrameSlot<P>, f32, bool),
) -> Result<Vec<crate::vk::timing::PassTimings<P>>> {
    check_clock(t0, dt, frames)?;
    let mut timings = Vec::with_capacity(frames as usize);
    for f in 0..frames {
        let slot = ring.begin()?;
        record(slot, t0 + dt * f as f32, f + 1 == frames);
        ring.submit(&[], &[])?;
        // `begin` retired the frame recorded FRAMES_IN_FLIGHT ago; keep its timings.
        if let Some((_, t)) = ring.take_fresh_timings() {
            timings.push(t.clone());
        }
    }
    // The last frames in flight finish here, oldest first.
    ring.finish(|_, t| timings.push(t.clone()))?;
    Ok(timings)
}

/// The frame's photon buffers in `SceneRenderer::effects` order.
fn effect_images(frame: &Frame) -> [Option<&Image>; 4] {
    [
        frame.caustics.as_ref().map(|c| &c.target.image),
        frame.caustic_filter.as_ref().map(|f| &f.output.image),
        frame.godrays.as_ref().map(|g| &g.target.image),
        frame.godray_filter.as_ref().map(|f| &f.output.image),
    ]
}
