//! Filter pass (method step 7): a rotating-kernel low-pass over one sparse photon buffer,
//! into a filtered copy of the same size. The frame runs one instance per effect buffer,
//! both inside the one timed "filter" pass; each instance has its own descriptor sets, so the
//! shader's single input binding points at that instance's buffer. Taps on another surface
//! than the centre's are left out (glsl/shared/depth_aware.glsl), so the filter reads the depth
//! the photon passes tested against: one set per photon set (`photon_set_index`).

use crate::error::Result;
use crate::passes::PHOTON_SETS;
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

pub const BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Storage),
    (b::FRAME_VALUES, Binding::Uniform),
    (b::SCENE_DEPTH, Binding::Texture),
    (b::FILTER_INPUT, Binding::Texture),
];

/// Taps of the rotating kernel besides the centre.
pub const TAPS: u32 = 8;

pub struct FilterPass {
    /// Kernel radius in pixels of the buffer.
    pub radius_px: f32,
    /// How far off the centre's surface a tap may lie (frame::CAUSTIC_SAME_SURFACE).
    pub same_surface: f32,
    pipeline: Pipeline,
    pub output: ColorTarget,
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl FilterPass {
    pub fn new(device: &Arc<Device>, name: &str, input: &Image, radius_px: f32, same_surface: f32) -> Result<Self> {
        let sets = DescriptorSets::new(device, name, BINDINGS, PHOTON_SETS as u32)?;
        let output =
            ColorTarget::new(device, name, input.extent, input.format, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                specialization: &[(0, TAPS)],
                push_constant_bytes: 8,
                set_layouts: &[sets.layout],
                ..GraphicsPipelineDesc::new(name, "fullscreen.vert", "filter.frag", output.render_pass.raw)
            },
        )?;
        Ok(Self { radius_px, same_surface, pipeline, output, sets, device: device.clone() })
    }

    /// `photon_set`: the set of the photon passes that filled the input this frame.
    pub fn record(&self, cmd: vk::CommandBuffer, photon_set: usize) {
        self.output.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[photon_set]));
        self.pipeline.push(cmd, bytemuck::bytes_of(&[self.radius_px, self.same_surface]));
        unsafe { self.device.raw.cmd_draw(cmd, 3, 1, 0, 0) };
        self.output.render_pass.end(cmd);
    }
}
