//! Reflection pass (water seen from above): the part of the scene above the water mirrored in
//! its mean plane, from the camera, cut below the lowest trough by a clip plane (Mihálik's
//! thesis, ch. 7). Colour alpha marks where a mesh was drawn; the water surface shows the sky
//! elsewhere. Half the output's resolution: the waves blur the reflection anyway, and this
//! pass draws every mesh above the water again. Recorded only in frames where the camera can
//! see the surface from above.

use super::scene::{mesh_pipeline, View, COLOR_FORMAT};
use crate::error::Result;
use crate::passes::mesh::GpuMeshes;
use crate::shader_abi::bindings as b;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::Pipeline;
use crate::vk::render_pass::{Attachment, Load, RenderPass, Store};
use ash::vk;
use std::sync::Arc;

/// What the pass's shaders read.
pub const BINDINGS: &[(u32, Binding)] = &[(b::UNIFORMS, Binding::Storage), (b::FRAME_VALUES, Binding::Uniform)];

/// The reflection's size for an output size.
pub fn reflection_extent(output: vk::Extent2D) -> vk::Extent2D {
    vk::Extent2D { width: output.width.div_ceil(2), height: output.height.div_ceil(2) }
}

pub struct ReflectionPass {
    pipeline: Pipeline,
    render_pass: RenderPass,
    pub color: Image,
    _depth: Image,
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl ReflectionPass {
    pub fn new(device: &Arc<Device>, output: vk::Extent2D) -> Result<Self> {
        let extent = reflection_extent(output);
        let sets = DescriptorSets::new(device, "reflection", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        // TRANSFER_DST: the frame clears it before its first pass (upload::clear_to_sampled).
        let usage =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        let color = Image::new(device, "reflection colour", extent, COLOR_FORMAT, usage)?;
        let depth = Image::new(
            device,
            "reflection depth",
            extent,
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        )?;
        let render_pass = RenderPass::new(
            device,
            "reflection",
            &[Attachment::new(&color, Load::Clear([0.0; 4]), Store::Keep, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)],
            Some(&Attachment::new(
                &depth,
                Load::Clear([1.0; 4]),
                Store::Discard, // its own depth test only
                vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            )),
        )?;
        let pipeline = mesh_pipeline(device, "reflection meshes", View::Reflection, 1, sets.layout, render_pass.raw)?;
        Ok(Self { pipeline, render_pass, color, _depth: depth, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        self.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[frame_index]));
        meshes.draw(&self.device, cmd);
        self.render_pass.end(cmd);
    }
}
