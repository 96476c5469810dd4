//! The rasterised photon splats' visibility test as the depth test. A caustic point or a
//! godray beam's fragment counts only where it is not behind what the scene shows at its
//! pixel (`behind_scene`, glsl/photons/photon_visibility.glsl). The photon targets are
//! smaller than the scene's depth buffer, so the splats cannot test against it directly.
//! Instead each pass draws one fullscreen triangle first (glsl/photons/photon_visibility.frag)
//! that writes, into a depth attachment of the target's size, the farthest depth a splat may
//! have at each pixel; the splats then test against it without writing it. The test runs
//! before their fragment shader, so fragments behind the scene cost no shading and no read of
//! the scene's depth. The compute path tests in its shader, and the caustic triangles, which
//! must lie on the surface their pixel shows (in front of it too), test in theirs. For the
//! footprint points the draw also writes the near plane where no photon could land (in a
//! shadow), which holds their hats, a whole photon span wide, to the lit side of its edge.

use crate::error::Result;
use crate::shaders;
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

/// Which target a visibility depth is for, which sets its tolerance in the shader
/// (specialization constant 0 of photon_visibility.frag).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VisibilityTarget {
    Caustics = 0,
    Godrays = 1,
    /// The footprint points' caustics: also held to where a photon could land, out of the
    /// shadows their hats would reach into (`light_could_land`, glsl/photons/photon_cast.glsl).
    LitCaustics = 2,
}

/// The draw that fills a photon target's depth attachment (`ColorTarget::with_optional_depth`).
pub struct VisibilityDepth {
    pipeline: Pipeline,
}

impl VisibilityDepth {
    /// `target` must have a depth attachment; `set_layouts`: the pass's own, which bind the
    /// frame's values and the scene's depth.
    pub fn new(
        device: &Arc<Device>,
        which: VisibilityTarget,
        target: &ColorTarget,
        set_layouts: &[vk::DescriptorSetLayout],
    ) -> Result<Self> {
        let name = match which {
            VisibilityTarget::Caustics => "caustics visibility",
            VisibilityTarget::Godrays => "godrays visibility",
            VisibilityTarget::LitCaustics => "footprint caustics visibility",
        };
        let desc = GraphicsPipelineDesc {
            blend: Blend::NoColor,
            depth_test: true,
            depth_write: true,
            specialization: &[(0, which as u32)],
            set_layouts,
            ..GraphicsPipelineDesc::new(name, "fullscreen.vert", "photon_visibility.frag", target.render_pass.raw)
        };
        Ok(Self { pipeline: shaders::graphics_pipeline(device, &desc)? })
    }

    /// Inside the target's render pass, before the splats: its depth, cleared to 1 when the
    /// pass began, becomes the farthest depth a splat may have at each pixel, and the depth
    /// test orders this draw before theirs.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, set: Option<vk::DescriptorSet>) {
        self.pipeline.bind(cmd, set);
        unsafe { device.raw.cmd_draw(cmd, 3, 1, 0, 0) };
    }
}
