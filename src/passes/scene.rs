//! Scene pass (method step 3): the scene from the camera into off-screen colour (ambient and
//! above-water sun, attenuated by the water on the way to the camera), the factor caustics
//! are multiplied by in compose (albedo/π × transmittance), and depth, which caustics and
//! godrays are tested against. The water surface is drawn here too, as a displaced grid.

use crate::error::Result;
use crate::frame::mesh::{GpuMeshes, MeshVertex, MESH_ATTRIBUTES};
use crate::frame::bindings as b;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, Load, RenderPass};
use ash::vk;
use std::sync::Arc;

/// What the scene pass's shaders read: the water surface's vertex shader samples the noise.
pub const BINDINGS: &[(u32, Binding)] = &[(b::UNIFORMS, Binding::Uniform), (b::NOISE, Binding::Texture)];

/// Cells per axis of the water-surface grid.
pub const WATER_GRID_CELLS: u32 = 128;

pub struct ScenePass {
    mesh_pipeline: Pipeline,
    water_pipeline: Pipeline,
    render_pass: RenderPass,
    pub color: Image,
    pub albedo_transmittance: Image,
    pub depth: Image,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl ScenePass {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let sets = DescriptorSets::new(device, "scene", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
        let color = Image::new(device, "scene colour", extent, vk::Format::R16G16B16A16_SFLOAT, usage)?;
        let albedo_transmittance =
            Image::new(device, "scene albedo×transmittance", extent, vk::Format::R16G16B16A16_SFLOAT, usage)?;
        let depth = Image::new(
            device,
            "scene depth",
            extent,
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
        )?;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let render_pass = RenderPass::new(
            device,
            "scene",
            &[
                Attachment { image: &color, load: Load::Clear([0.0, 0.0, 0.0, 1.0]), final_layout: read },
                Attachment { image: &albedo_transmittance, load: Load::Clear([0.0; 4]), final_layout: read },
            ],
            Some(&Attachment { image: &depth, load: Load::Clear([1.0; 4]), final_layout: read }),
        )?;
        // Both draw into colour + albedo×transmittance with depth test and write.
        let layouts = [sets.layout];
        let opaque_with_depth = |name, vertex, fragment| GraphicsPipelineDesc {
            color_attachments: 2,
            depth_test: true,
            depth_write: true,
            set_layouts: &layouts,
            ..GraphicsPipelineDesc::new(name, vertex, fragment, render_pass.raw)
        };
        let mesh_pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                vertex_stride: std::mem::size_of::<MeshVertex>() as u32,
                vertex_attributes: &MESH_ATTRIBUTES,
                ..opaque_with_depth("scene meshes", "mesh.vert", "scene.frag")
            },
        )?;
        let water_pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                specialization: &[(0, WATER_GRID_CELLS)],
                ..opaque_with_depth("water surface", "water.vert", "water.frag")
            },
        )?;
        Ok(Self { mesh_pipeline, water_pipeline, render_pass, color, albedo_transmittance, depth, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        self.render_pass.begin(cmd);
        self.mesh_pipeline.bind(cmd, Some(set));
        meshes.draw(dev, cmd);
        // Same set layout: set 0 stays bound across the pipeline change.
        self.water_pipeline.bind(cmd, None);
        unsafe { dev.raw.cmd_draw(cmd, 6 * WATER_GRID_CELLS * WATER_GRID_CELLS, 1, 0, 0) };
        self.render_pass.end(cmd);
    }
}
