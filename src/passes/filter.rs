//! Filter pass (method step 7): a rotating-kernel low-pass over one sparse photon buffer,
//! into a filtered copy of the same size. The frame runs one instance per effect buffer,
//! both inside the one timed "filter" pass; each instance has its own descriptor set, so the
//! shader's single input binding points at that instance's buffer.

use crate::error::Result;
use crate::frame::bindings as b;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{set_viewport, Blend, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, Load, RenderPass};
use ash::vk;
use std::sync::Arc;

pub const BINDINGS: &[(u32, Binding)] = &[(b::FILTER_INPUT, Binding::Texture)];

/// Taps of the rotating kernel besides the centre.
pub const TAPS: u32 = 8;

pub struct FilterPass {
    /// Kernel radius in pixels of the buffer.
    pub radius_px: f32,
    pipeline: Pipeline,
    render_pass: RenderPass,
    pub output: Image,
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl FilterPass {
    pub fn new(device: &Arc<Device>, name: &str, input: &Image, radius_px: f32) -> Result<Self> {
        let sets = DescriptorSets::new(device, name, BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let output = Image::new(
            device,
            &format!("{name} output"),
            input.extent,
            input.format,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let render_pass = RenderPass::new(
            device,
            name,
            &[Attachment { image: &output, load: Load::Clear([0.0; 4]), final_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL }],
            None,
        )?;
        let pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                name,
                vertex: "fullscreen.vert",
                geometry: None,
                fragment: "filter.frag",
                topology: vk::PrimitiveTopology::TRIANGLE_LIST,
                blend: Blend::Opaque,
                color_attachments: 1,
                depth_test: false,
                depth_write: false,
                specialization: &[(0, TAPS)],
                push_constant_bytes: 4,
                set_layouts: &[sets.layout],
                render_pass: render_pass.raw,
                dynamic_line_width: false,
                vertex_stride: 0,
                vertex_attributes: &[],
            },
        )?;
        Ok(Self { radius_px, pipeline, render_pass, output, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        self.render_pass.begin(cmd);
        set_viewport(dev, cmd, self.output.extent);
        unsafe {
            dev.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.raw);
            dev.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline.layout, 0, &[set], &[]);
            dev.raw.cmd_push_constants(cmd, self.pipeline.layout, vk::ShaderStageFlags::ALL_GRAPHICS, 0, &self.radius_px.to_ne_bytes());
            dev.raw.cmd_draw(cmd, 3, 1, 0, 0);
        }
        self.render_pass.end(cmd);
    }
}
