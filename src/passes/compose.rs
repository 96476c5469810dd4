//! Compose pass (method step 8): scene colour + caustics × albedo/π × transmittance +
//! godrays + the glow of the water's highlights (when the surface can be seen from above),
//! tonemapped into an sRGB target. The shader variant is chosen by which effects the
//! frame has, so a missing effect's target is never bound.

use crate::error::Result;
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

pub const OUTPUT_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;

pub struct ComposePass {
    pipeline: Pipeline,
    pub output: ColorTarget,
    /// This pass's descriptor sets (one per frame in flight), written by the frame.
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl ComposePass {
    /// What the chosen compose variant reads: only the targets the frame has.
    pub fn bindings(caustics: bool, godrays: bool) -> Vec<(u32, Binding)> {
        let mut v = vec![
            (b::UNIFORMS, Binding::Storage),
            (b::FRAME_VALUES, Binding::Uniform),
            (b::SCENE_COLOR, Binding::Texture),
        ];
        if caustics || godrays {
            // Effect targets are upsampled along the scene's depth (glsl/shared/depth_aware.glsl).
            v.push((b::SCENE_DEPTH, Binding::Texture));
        }
        if caustics {
            v.push((b::ALBEDO_TRANSMITTANCE, Binding::Texture));
            v.push((b::CAUSTICS, Binding::Texture));
        }
        if godrays {
            v.push((b::GODRAYS, Binding::Texture));
        }
        v
    }

    pub fn new(
        device: &Arc<Device>,
        extent: vk::Extent2D,
        caustics: bool,
        godrays: bool,
        glow: bool,
        final_layout: vk::ImageLayout,
    ) -> Result<Self> {
        let sets = DescriptorSets::new(device, "compose", &Self::bindings(caustics, godrays), FRAMES_IN_FLIGHT as u32)?;
        let output = ColorTarget::new(device, "output", extent, OUTPUT_FORMAT, final_layout)?;
        let fragment = match (caustics, godrays) {
            (false, false) => "compose.frag",
            (true, false) => "compose_caustics.frag",
            (false, true) => "compose_godrays.frag",
            (true, true) => "compose_caustics_godrays.frag",
        };
        let pipeline = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                set_layouts: &[sets.layout],
                specialization: &[
                    (0, glow as u32),
                    (1, crate::frame::CAUSTIC_SAME_SURFACE.to_bits()),
                    (2, crate::frame::GODRAY_SAME_SURFACE.to_bits()),
                ],
                ..GraphicsPipelineDesc::new("compose", "fullscreen.vert", fragment, output.render_pass.raw)
            },
        )?;
        Ok(Self { pipeline, output, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize) {
        self.output.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[frame_index]));
        unsafe { self.device.raw.cmd_draw(cmd, 3, 1, 0, 0) };
        self.output.render_pass.end(cmd);
    }
}
