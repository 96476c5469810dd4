//! Shadow pass (method step 2): the scene from the light. Besides depth it stores, per
//! texel, the world position of the nearest receiver (Shah's position texture, for the
//! image-space intersection) and its normal (for the iteration's convergence test and the
//! caustic splat's footprint). The water
//! mask the paper makes optional is derived from the position map instead (see photon_cast.glsl).
//! Under a directional light the maps see underwater receivers along the light's refracted
//! direction, where the photons travel (`shader_math::light_map_point`); a geometry shader
//! cuts the triangles that cross the water level so that each piece projects exactly. There
//! it also renders a second pair of maps bent more steeply (`steep`), which the photons
//! search where the first cannot place them (`frame::uniforms::steep_light_axis`).

use crate::error::Result;
use crate::passes::mesh::{GpuMeshes, MESH_ATTRIBUTES};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::{Attachment, Load, RenderPass, Store};
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
    /// The second maps, bent along `FrameUniforms::steep_light_axis`; None where the maps do
    /// not bend (a point light), whose photons have nothing else to search.
    pub steep: Option<SteepMaps>,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

/// The second pair of light maps and their render pass (the first's formats, so the pass's
/// one pipeline draws into either).
pub struct SteepMaps {
    render_pass: RenderPass,
    pub position: Image,
    pub normal: Image,
    _depth: Image,
}

/// A pair of receiver maps (positions, normals) and the depth they are tested with, named
/// `what` ("light", "steep light").
fn map_images(device: &Arc<Device>, what: &str, size: u32) -> Result<[Image; 3]> {
    let extent = vk::Extent2D { width: size, height: size };
    let sampled =
        vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
    let position =
        Image::new(device, &format!("{what} position map"), extent, vk::Format::R32G32B32A32_SFLOAT, sampled)?;
    let normal = Image::new(device, &format!("{what} normal map"), extent, normal_format(device), sampled)?;
    let depth = Image::new(
        device,
        &format!("{what} depth"),
        extent,
        vk::Format::D32_SFLOAT,
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
    )?;
    Ok([position, normal, depth])
}

/// The render pass that clears and fills one pair of maps, leaving them for the photon passes.
fn map_render_pass(
    device: &Arc<Device>,
    name: &str,
    position: &Image,
    normal: &Image,
    depth: &Image,
) -> Result<RenderPass> {
    let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    RenderPass::new(
        device,
        name,
        &[
            Attachment { image: position, load: Load::Clear([0.0; 4]), store: Store::Keep, final_layout: read },
            Attachment { image: normal, load: Load::Clear([0.0; 4]), store: Store::Keep, final_layout: read },
        ],
        Some(&Attachment {
            image: depth,
            load: Load::Clear([1.0; 4]),
            store: Store::Discard, // its own depth test only; the maps hold the positions
            final_layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        }),
    )
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
    /// `steep`: also render the second maps (where the light's maps bend).
    pub fn new(device: &Arc<Device>, size: u32, steep: bool) -> Result<Self> {
        let sets = DescriptorSets::new(device, "shadow", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let [position, normal, depth] = map_images(device, "light", size)?;
        let render_pass = map_render_pass(device, "shadow", &position, &normal, &depth)?;
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
                // Which maps (shadow.geom's `steep`).
                push_constant_bytes: 4,
                ..GraphicsPipelineDesc::new("shadow", "shadow.vert", "shadow.frag", render_pass.raw)
            },
        )?;
        let steep = if steep {
            let [position, normal, depth] = map_images(device, "steep light", size)?;
            let render_pass = map_render_pass(device, "shadow (steep maps)", &position, &normal, &depth)?;
            Some(SteepMaps { render_pass, position, normal, _depth: depth })
        } else {
            None
        };
        Ok(Self { pipeline, render_pass, position, normal, _depth: depth, steep, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        let passes =
            std::iter::once((&self.render_pass, 0u32)).chain(self.steep.as_ref().map(|s| (&s.render_pass, 1u32)));
        for (render_pass, steep) in passes {
            render_pass.begin(cmd);
            self.pipeline.bind(cmd, Some(set));
            self.pipeline.push(cmd, &steep.to_ne_bytes());
            meshes.draw(dev, cmd);
            render_pass.end(cmd);
        }
    }
}
