//! Shadow pass (method step 2): the scene from the light. Besides depth it stores, per
//! texel, the world position of the nearest receiver (Shah's position texture, for the
//! image-space intersection) and its normal (for the iteration's convergence test and the
//! caustic splat's footprint). The water
//! mask the paper makes optional is derived from the position map instead (see photon_cast.glsl).
//! Under a directional light the maps see underwater receivers along the light's refracted
//! direction, where the photons travel (`shader_math::light_map_point`); a geometry shader
//! cuts the triangles that cross the water level so that each piece projects exactly.

use crate::error::Result;
use crate::passes::mesh::{GpuMeshes, MESH_ATTRIBUTES};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, Load, RenderPass};
use ash::vk;
use std::sync::Arc;

/// What the shadow pass's shaders read (glsl/shared/frame_textures.glsl numbering).
pub const BINDINGS: &[(u32, Binding)] = &[(b::UNIFORMS, Binding::Storage)];

pub struct ShadowPass {
    pipeline: Pipeline,
    render_pass: RenderPass,
    pub position: Image,
    pub normal: Image,
    /// Only attached (depth testing); kept alive here for the framebuffer.
    _depth: Image,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

/// The light normal map's format: 8-bit signed normalised (4 MiB at 1024²), which the
/// photons' figures cannot tell from half floats (docs/accuracy.md, "The light's maps"), where
/// the device renders to and samples it; else half floats (8 MiB). The normals are unit
/// vectors and every reader normalises or tests their sign. The position map stays 32-bit
/// float: at half precision a receiver 30 m out is stored to 16 mm, and the port's caustic
/// error rose from 0.573 to 0.595.
pub fn normal_format(device: &Device) -> vk::Format {
    let compact = vk::Format::R8G8B8A8_SNORM;
    let features = unsafe { device.instance.raw.get_physical_device_format_properties(device.info.handle, compact) }
        .optimal_tiling_features;
    let needed = vk::FormatFeatureFlags::COLOR_ATTACHMENT
        | vk::FormatFeatureFlags::SAMPLED_IMAGE
        | vk::FormatFeatureFlags::TRANSFER_SRC;
    if features.contains(needed) {
        compact
    } else {
        vk::Format::R16G16B16A16_SFLOAT
    }
}

impl ShadowPass {
    pub fn new(device: &Arc<Device>, size: u32) -> Result<Self> {
        let sets = DescriptorSets::new(device, "shadow", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let extent = vk::Extent2D { width: size, height: size };
        let sampled =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
        let position = Image::new(device, "light position map", extent, vk::Format::R32G32B32A32_SFLOAT, sampled)?;
        let normal = Image::new(device, "light normal map", extent, normal_format(device), sampled)?;
        let depth = Image::new(
            device,
            "light depth",
            extent,
            vk::Format::D32_SFLOAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
        )?;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let render_pass = RenderPass::new(
            device,
            "shadow",
            &[
                Attachment { image: &position, load: Load::Clear([0.0; 4]), final_layout: read },
                Attachment { image: &normal, load: Load::Clear([0.0; 4]), final_layout: read },
            ],
            Some(&Attachment {
                image: &depth,
                load: Load::Clear([1.0; 4]),
                final_layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            }),
        )?;
        let pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                color_attachments: 2,
                depth_test: true,
                depth_write: true,
                set_layouts: &[sets.layout],
                vertex_stride: std::mem::size_of::<crate::passes::mesh::MeshVertex>() as u32,
                vertex_attributes: &MESH_ATTRIBUTES[..2],
                geometry: Some("shadow.geom"),
                ..GraphicsPipelineDesc::new("shadow", "shadow.vert", "shadow.frag", render_pass.raw)
            },
        )?;
        Ok(Self { pipeline, render_pass, position, normal, _depth: depth, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        self.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(set));
        meshes.draw(dev, cmd);
        self.render_pass.end(cmd);
    }
}
