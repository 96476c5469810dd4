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
//!
//! Each map is one image array with a layer per pair (first, steeper), which the photon
//! passes sample as one `sampler2DArray`: the pair a search reads is the fetch's layer index,
//! where two images would need `steep ? fetch(a) : fetch(b)`, and llvmpipe fetches both sides
//! of that select (docs/performance.md, "One fetch per map read").

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

/// The pairs of maps: the first, along flat water's refracted light, and where the maps bend
/// the second, steeper one; each is a layer of the map arrays, in this order.
pub const FIRST_MAPS: u32 = 0;
pub const STEEP_MAPS: u32 = 1;

pub struct ShadowPass {
    pipeline: Pipeline,
    /// One render pass per pair of maps (layer), in layer order. Before the images: their
    /// framebuffers refer to the images' layer views.
    render_passes: Vec<RenderPass>,
    /// Receiver positions (w = 1 where a receiver is stored), one layer per pair of maps.
    pub position: Image,
    /// Receiver normals, one layer per pair of maps.
    pub normal: Image,
    /// Only attached (each render pass's own depth test, cleared when it begins, so the pairs
    /// share it); kept alive here for the framebuffers.
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
    /// `steep`: also render the second maps (where the light's maps bend; a point light's do
    /// not, and its photons have nothing else to search).
    pub fn new(device: &Arc<Device>, size: u32, steep: bool) -> Result<Self> {
        let sets = DescriptorSets::new(device, "shadow", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let pairs = if steep { 2 } else { 1 };
        let extent = vk::Extent2D { width: size, height: size };
        let sampled =
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_SRC;
        let position =
            Image::array(device, "light position maps", extent, vk::Format::R32G32B32A32_SFLOAT, sampled, pairs)?;
        let normal = Image::array(device, "light normal maps", extent, normal_format(device), sampled, pairs)?;
        let depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        let depth = Image::new(device, "light map depth", extent, vk::Format::D32_SFLOAT, depth_usage)?;
        let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let render_passes = (0..pairs)
            .map(|layer| {
                let map = |image| Attachment {
                    image,
                    layer,
                    load: Load::Clear([0.0; 4]),
                    store: Store::Keep,
                    final_layout: read,
                };
                RenderPass::new(
                    device,
                    if layer == STEEP_MAPS { "shadow (steep maps)" } else { "shadow" },
                    &[map(&position), map(&normal)],
                    Some(&Attachment::new(
                        &depth,
                        Load::Clear([1.0; 4]),
                        Store::Discard, // its own depth test only; the maps hold the positions
                        vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                    )),
                )
            })
            .collect::<Result<Vec<_>>>()?;
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
                ..GraphicsPipelineDesc::new("shadow", "shadow.vert", "shadow.frag", render_passes[0].raw)
            },
        )?;
        Ok(Self { pipeline, render_passes, position, normal, _depth: depth, sets, device: device.clone() })
    }

    /// How many pairs of maps the pass renders (the map arrays' layers): 1 or 2.
    pub fn pairs(&self) -> u32 {
        self.position.layers
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        let dev = &self.device;
        let set = self.sets.sets[frame_index];
        for (layer, render_pass) in (0u32..).zip(&self.render_passes) {
            render_pass.begin(cmd);
            self.pipeline.bind(cmd, Some(set));
            self.pipeline.push(cmd, &layer.to_ne_bytes());
            meshes.draw(dev, cmd);
            render_pass.end(cmd);
        }
    }
}
