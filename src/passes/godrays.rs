//! Godrays pass (method step 6): photons cast on their own, coarser grid; each one that
//! lands becomes a line from the water surface to its hit, whose fragments add the beam's
//! in-scattered radiance (Henyey–Greenstein phase, attenuation along both legs) into a
//! low-resolution RGBA32F target. Units: docs/units.md.

use crate::error::{Error, Result};
use crate::frame::bindings as b;
use crate::shader_math::GODRAY_MAX_SUBDIVISION;
use crate::vk::commands::FRAMES_IN_FLIGHT;
use crate::vk::descriptors::{Binding, DescriptorSets};
use crate::vk::device::Device;
use crate::vk::pipeline::{Blend, GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use std::sync::Arc;

/// What the godray shaders read: the water's noise, the light's position map, scene depth.
pub const BINDINGS: &[(u32, Binding)] = &[
    (b::UNIFORMS, Binding::Uniform),
    (b::NOISE, Binding::Texture),
    (b::LIGHT_POSITION, Binding::Texture),
    (b::SCENE_DEPTH, Binding::Texture),
];

/// Godray accumulation format. Hundreds of beam fragments land on one pixel of the small
/// target, each a tiny fraction of the sum; half floats (11-bit mantissa) lose a measurable
/// share of that (−13 % in tests/godrays.rs on lavapipe), single floats do not, and the
/// target is small enough (the paper's 128²) that the extra bandwidth is negligible.
pub const TARGET_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

pub struct GodraysPass {
    pub grid: u32,
    /// Line width actually drawn, px (the scene's, clamped to the device's range).
    pub line_width: f32,
    pipeline: Pipeline,
    pub target: ColorTarget,
    pub sets: DescriptorSets,
    device: Arc<Device>,
}

impl GodraysPass {
    pub fn new(device: &Arc<Device>, extent: vk::Extent2D, grid: u32, subdivision: u32, line_width: f32) -> Result<Self> {
        if subdivision == 0 || subdivision > GODRAY_MAX_SUBDIVISION {
            return Err(Error::InvalidParameter {
                name: "godray_subdivision",
                message: format!("{subdivision} is outside 1..={GODRAY_MAX_SUBDIVISION}"),
            });
        }
        let [lo, hi] = device.limits().line_width_range;
        let line_width = line_width.clamp(lo.max(1.0), hi);
        let features = unsafe {
            device.instance.raw.get_physical_device_format_properties(device.info.handle, TARGET_FORMAT)
        }
        .optimal_tiling_features;
        let needed = vk::FormatFeatureFlags::COLOR_ATTACHMENT_BLEND | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR;
        if !features.contains(needed) {
            return Err(Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["R32G32B32A32_SFLOAT with blending and linear filtering (godray target)"],
            });
        }
        let sets = DescriptorSets::new(device, "godrays", BINDINGS, FRAMES_IN_FLIGHT as u32)?;
        let target = ColorTarget::new(device, "godrays", extent, TARGET_FORMAT, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)?;
        let pipeline = Pipeline::graphics(
            device,
            &GraphicsPipelineDesc {
                geometry: Some("godrays.geom"),
                topology: vk::PrimitiveTopology::POINT_LIST,
                blend: Blend::Additive,
                specialization: &[(0, subdivision)],
                push_constant_bytes: 4,
                set_layouts: &[sets.layout],
                dynamic_line_width: true,
                ..GraphicsPipelineDesc::new("godrays", "photon_grid.vert", "godrays.frag", target.render_pass.raw)
            },
        )?;
        Ok(Self { grid, line_width, pipeline, target, sets, device: device.clone() })
    }

    pub fn record(&self, cmd: vk::CommandBuffer, frame_index: usize) {
        let dev = &self.device;
        self.target.render_pass.begin(cmd);
        self.pipeline.bind(cmd, Some(self.sets.sets[frame_index]));
        self.pipeline.push(cmd, &self.grid.to_ne_bytes());
        unsafe {
            dev.raw.cmd_set_line_width(cmd, self.line_width);
            dev.raw.cmd_draw(cmd, self.grid * self.grid, 1, 0, 0);
        }
        self.target.render_pass.end(cmd);
    }
}
