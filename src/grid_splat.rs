//! Grid splat: the foundation's proof that the whole stack works end to end (`underlight
//! grid-splat`), kept as a demo outside the method's passes: it has its own timed passes
//! ([`DemoPass`]), frame ring and read-back, and shares only the backend with the method.
//!
//! A coarse grid of points is drawn with no vertex buffer; a geometry shader subdivides each
//! into SUBDIVISION×SUBDIVISION photons (a specialization constant, so the loop unrolls) and
//! emits each as a point with `gl_PointSize`; the points are added into an RGBA16F target.
//! It is the skeleton the caustics pass grows from: same grid, same amplification, same
//! blending, without the water and scene intersection.

use crate::error::{Error, Result};
use crate::image_io::HdrImage;
use crate::shader_math::MAX_SUBDIVISION;
use crate::shaders;
use crate::vk::commands::FrameRing;
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, GraphicsPipelineDesc, Pipeline};
use crate::vk::readback::Readback;
use crate::vk::render_pass::ColorTarget;
use crate::vk::timing::{PassTimings, TimedPass};
use ash::vk;
use std::ffi::CStr;
use std::sync::Arc;

/// Format of the accumulation target: half floats add photon energies without clamping.
pub const TARGET_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSplatSettings {
    /// Coarse cells per axis.
    pub grid: u32,
    /// Photons per cell per axis (geometry-shader amplification).
    pub subdivision: u32,
    pub point_size: f32,
    /// Energy each photon adds to R, G and B.
    pub energy: f32,
    /// Demo displacement of the photons (0 puts them at sub-cell centres).
    pub wave_amplitude: f32,
}

impl Default for GridSplatSettings {
    fn default() -> Self {
        // The paper's caustic grid: 200×200 cells, 2×2 photons each.
        Self { grid: 200, subdivision: 2, point_size: 2.0, energy: 0.08, wave_amplitude: 1.3 }
    }
}

impl GridSplatSettings {
    pub fn photon_count(&self) -> u64 {
        (self.grid as u64 * self.subdivision as u64).pow(2)
    }

    /// Checks the settings against the method's bounds and the device's limits.
    pub fn validate(&self, device: &Device) -> Result<()> {
        let limits = device.limits();
        if self.grid == 0 || self.grid > 8192 {
            return Err(Error::InvalidParameter {
                name: "grid",
                message: format!("{} is outside 1..=8192", self.grid),
            });
        }
        // Each photon emits gl_Position (4), gl_PointSize (1) and the energy (4).
        const COMPONENTS_PER_PHOTON: u32 = 9;
        let by_components = (limits.max_geometry_total_output_components / COMPONENTS_PER_PHOTON)
            .min(limits.max_geometry_output_vertices);
        let max_sub = MAX_SUBDIVISION.min((by_components as f64).sqrt() as u32);
        if self.subdivision == 0 || self.subdivision > max_sub {
            return Err(Error::InvalidParameter {
                name: "subdivision",
                message: format!(
                    "{} is outside 1..={max_sub} (shader bound {MAX_SUBDIVISION}; device: {} output vertices, {} output components)",
                    self.subdivision, limits.max_geometry_output_vertices, limits.max_geometry_total_output_components
                ),
            });
        }
        let [lo, hi] = limits.point_size_range;
        if !(self.point_size >= lo && self.point_size <= hi) {
            return Err(Error::InvalidParameter {
                name: "point_size",
                message: format!("{} is outside the device's range {lo}..={hi}", self.point_size),
            });
        }
        if !self.energy.is_finite() || !self.wave_amplitude.is_finite() {
            return Err(Error::InvalidParameter { name: "energy/wave_amplitude", message: "must be finite".into() });
        }
        Ok(())
    }
}

/// Push constants; layout matches `glsl/grid_splat/grid_splat_params.glsl`.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GridSplatPush {
    pub grid: [u32; 2],
    pub point_size: f32,
    pub energy: f32,
    pub wave_amplitude: f32,
    pub time: f32,
}
const _: () = assert!(std::mem::size_of::<GridSplatPush>() == 24);

pub struct GridSplatPass {
    pub settings: GridSplatSettings,
    pipeline: Pipeline,
    pub target: ColorTarget,
    device: Arc<Device>,
}

impl GridSplatPass {
    /// `final_layout` is the layout the target is left in for its reader
    /// (TRANSFER_SRC_OPTIMAL for a read-back, SHADER_READ_ONLY_OPTIMAL for a later pass).
    pub fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        settings: GridSplatSettings,
        final_layout: vk::ImageLayout,
    ) -> Result<Self> {
        settings.validate(device)?;
        let target = ColorTarget::new(device, "grid_splat", extent, TARGET_FORMAT, final_layout)?;
        let pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                geometry: Some("grid_splat.geom"),
                topology: vk::PrimitiveTopology::POINT_LIST,
                blend: Blend::Additive,
                specialization: &[(0, settings.subdivision)],
                push_constant_bytes: std::mem::size_of::<GridSplatPush>() as u32,
                ..GraphicsPipelineDesc::new("grid_splat", "grid_splat.vert", "grid_splat.frag", target.render_pass.raw)
            },
        )?;
        Ok(Self { settings, pipeline, target, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, time: f32) {
        let s = &self.settings;
        let push = GridSplatPush {
            grid: [s.grid, s.grid],
            point_size: s.point_size,
            energy: s.energy,
            wave_amplitude: s.wave_amplitude,
            time,
        };
        self.target.render_pass.begin(cmd);
        self.pipeline.bind(cmd, None);
        self.pipeline.push(cmd, bytemuck::bytes_of(&push));
        unsafe { self.device.raw.cmd_draw(cmd, s.grid * s.grid, 1, 0, 0) };
        self.target.render_pass.end(cmd);
    }
}

/// The demo's timed passes (the method's are `passes::PassId`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum DemoPass {
    /// The photon grid subdivided by the geometry shader and splatted.
    GridSplat,
    /// Copy of the target into host memory.
    Readback,
}

impl TimedPass for DemoPass {
    fn label(self) -> &'static CStr {
        match self {
            DemoPass::GridSplat => c"grid_splat",
            DemoPass::Readback => c"readback",
        }
    }
}

/// The grid-splat pass with its frame ring and read-back, kept alive across renders so
/// benchmarks time frames, not set-up.
pub struct GridSplatRenderer {
    pass: GridSplatPass,
    readback: Readback,
    ring: FrameRing<DemoPass>,
}

impl GridSplatRenderer {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D, settings: GridSplatSettings) -> Result<Self> {
        let pass = GridSplatPass::new(device, extent, settings, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
        let readback = Readback::new(device, &pass.target.image)?;
        let ring = FrameRing::new(device, false)?;
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
    ) -> Result<(Vec<PassTimings<DemoPass>>, Option<HdrImage>)> {
        let (pass, readback) = (&self.pass, &self.readback);
        let timings = crate::headless::run_frames(&mut self.ring, frames, t0, dt, |slot, time, last| {
            let cmd = slot.cmd;
            slot.timer.pass(cmd, DemoPass::GridSplat, |cmd| pass.record(cmd, time));
            if read_back && last {
                slot.timer.pass(cmd, DemoPass::Readback, |cmd| readback.record(cmd, &pass.target.image));
            }
        })?;
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
) -> Result<(HdrImage, Vec<PassTimings<DemoPass>>)> {
    let mut renderer = GridSplatRenderer::new(device, extent, settings)?;
    let (timings, image) = renderer.render(frames.max(1), t0, dt, true)?;
    Ok((image.expect("read back requested"), timings))
}
