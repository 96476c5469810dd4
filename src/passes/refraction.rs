//! Refraction pass (water seen from above): the part of the scene under the water, from the
//! camera, cut above the highest crest by a clip plane (Mihálik's thesis, ch. 7). It keeps
//! the radiance leaving each receiver, its albedo/π and its depth. The caustics and godrays
//! passes splat into this view (they test against its depth), and the water surface reads
//! all of them where its refracted ray meets this depth (`glsl/surface/water.frag`), then applies the
//! water along that ray. Recorded only in frames where the camera can see the surface from
//! above.

use super::scene::{mesh_pipeline, CameraTargets, View};
use crate::error::Result;
use crate::passes::mesh::GpuMeshes;
use crate::shader_abi::bindings as b;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::image::Image;
use crate::vk::pipeline::Pipeline;
use crate::vk::render_pass::RenderPass;
use ash::vk;
use std::sync::Arc;

/// What the pass's shaders read.
pub const BINDINGS: &[(u32, Binding)] = &[(b::UNIFORMS, Binding::Storage), (b::FRAME_VALUES, Binding::Uniform)];

pub struct RefractionPass {
    pipeline: Pipeline,
    render_pass: RenderPass,
    pub color: Image,
    pub albedo: Image,
    pub depth: Image,
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl RefractionPass {
    /// `extent`: the camera's (the caustic and godray buffers map onto this view as onto
    /// the scene pass's).
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D) -> Result<Self> {
        let sets = DescriptorSets::new(device, "refraction", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let CameraTargets { color, albedo, depth, render_pass } =
            CameraTargets::new(device, "refraction", "albedo", extent, vk::ImageUsageFlags::empty())?;
        let pipeline = mesh_pipeline(device, "refraction meshes", View::Refraction, 2, sets.layout, render_pass.raw)?;
        Ok(Self { pipeline, render_pass, color, albedo, depth, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize, meshes: &GpuMeshes) {
        self.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[frame_index]));
        meshes.draw(&self.device, cmd);
        self.render_pass.end(cmd);
    }
}
