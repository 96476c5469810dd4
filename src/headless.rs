//! Headless rendering: frames into an off-screen target, the last one read back.

use crate::error::Result;
use crate::image_io::HdrImage;
use crate::passes::grid_splat::{GridSplatPass, GridSplatSettings};
use crate::passes::PassId;
use crate::vk::commands::FrameRing;
use crate::vk::device::Device;
use crate::vk::readback::Readback;
use crate::vk::timing::PassTimings;
use ash::vk;
use std::sync::Arc;

/// Median GPU milliseconds of each pass over several frames, in pass order.
pub fn median_timings(frames: &[PassTimings]) -> PassTimings {
    let mut ids: Vec<PassId> = frames.iter().flat_map(|t| t.passes.iter().map(|(id, _)| *id)).collect();
    ids.sort();
    ids.dedup();
    let mut out = PassTimings::default();
    for id in ids {
        let mut v: Vec<f64> = frames.iter().filter_map(|t| t.get(id)).collect();
        v.sort_by(f64::total_cmp);
        out.passes.push((id, v[v.len() / 2]));
    }
    out
}

/// The grid-splat pass with its frame ring and read-back, kept alive across renders so
/// benchmarks time frames, not set-up.
pub struct GridSplatRenderer {
    pass: GridSplatPass,
    readback: Readback,
    ring: FrameRing,
}

impl GridSplatRenderer {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D, settings: GridSplatSettings) -> Result<Self> {
        let pass = GridSplatPass::new(device, extent, settings, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
        let readback = Readback::new(device, &pass.target)?;
        let ring = FrameRing::new(device)?;
        Ok(Self { pass, readback, ring })
    }

    /// Renders `frames` frames (time `t0 + k·dt`), pipelined through the frames in flight,
    /// and returns each frame's per-pass GPU times. With `read_back`, the last frame also
    /// copies its target to the host, returned as an image.
    pub fn render(
        &mut self,
        frames: u32,
        t0: f32,
        dt: f32,
        read_back: bool,
    ) -> Result<(Vec<PassTimings>, Option<HdrImage>)> {
        let mut timings = Vec::with_capacity(frames as usize);
        for f in 0..frames {
            let time = t0 + dt * f as f32;
            let slot = self.ring.begin()?;
            let cmd = slot.cmd;
            let pass = &self.pass;
            slot.timer.pass(cmd, PassId::GridSplat, |cmd| pass.record(cmd, time));
            if read_back && f + 1 == frames {
                let readback = &self.readback;
                slot.timer.pass(cmd, PassId::Readback, |cmd| readback.record(cmd, &pass.target));
            }
            self.ring.submit(&[], &[])?;
            // `begin` retired the frame recorded FRAMES_IN_FLIGHT ago; keep its timings.
            if let Some((_, t)) = self.ring.take_fresh_timings() {
                timings.push(t.clone());
            }
        }
        // The last frames in flight finish here, oldest first.
        self.ring.finish(|_, t| timings.push(t.clone()))?;
        let image = if read_back && frames > 0 { Some(self.readback.read()?) } else { None };
        Ok((timings, image))
    }
}

/// Renders `frames` frames of the grid-splat pass and reads back the last.
pub fn render_grid_splat(
    device: &Arc<Device>,
    extent: vk::Extent2D,
    settings: GridSplatSettings,
    frames: u32,
    t0: f32,
    dt: f32,
) -> Result<(HdrImage, Vec<PassTimings>)> {
    let mut renderer = GridSplatRenderer::new(device, extent, settings)?;
    let (timings, image) = renderer.render(frames.max(1), t0, dt, true)?;
    Ok((image.expect("read back requested"), timings))
}
