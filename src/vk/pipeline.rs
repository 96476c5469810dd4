//! Shader modules, graphics pipelines and compute pipelines.
//!
//! Pipelines are described by a small struct rather than a builder chain, so a pass states
//! in one place what its pipeline does (topology, blending, depth, specialization). Stages are
//! named; the caller says where a name's SPIR-V is (`shaders::graphics_pipeline` passes the
//! embedded table), so the backend knows no shader of its own.

use super::device::Device;
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// How a pipeline writes its colour attachments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Blend {
    /// Replace.
    Opaque,
    /// dst += src, for photon splats: every photon adds its energy.
    Additive,
    /// Writes no colour: a draw that only writes depth into a pass with colour attachments.
    NoColor,
}

/// Everything a pass decides about its graphics pipeline.
pub struct GraphicsPipelineDesc<'a> {
    pub name: &'a str,
    /// Program names, e.g. `grid_splat.vert`, found by the caller's lookup; geometry is optional.
    pub vertex: &'a str,
    pub geometry: Option<&'a str>,
    pub fragment: &'a str,
    pub topology: vk::PrimitiveTopology,
    pub blend: Blend,
    pub color_attachments: u32,
    pub depth_test: bool,
    pub depth_write: bool,
    /// Specialization constants (id, value), applied to every stage.
    pub specialization: &'a [(u32, u32)],
    pub push_constant_bytes: u32,
    pub set_layouts: &'a [vk::DescriptorSetLayout],
    pub render_pass: vk::RenderPass,
    /// Lines drawn wider than 1 px set the width dynamically (vkCmdSetLineWidth).
    pub dynamic_line_width: bool,
    /// Per-vertex input from binding 0: stride and (location, format, offset); empty when
    /// the vertex shader builds its input from gl_VertexIndex.
    pub vertex_stride: u32,
    pub vertex_attributes: &'a [(u32, vk::Format, u32)],
}

impl<'a> GraphicsPipelineDesc<'a> {
    /// The common case, which a pass's description changes with `..` where it differs:
    /// triangles, opaque into one colour attachment, no depth, no geometry shader, no
    /// specialization, push constants, descriptor sets or vertex buffers.
    pub fn new(name: &'a str, vertex: &'a str, fragment: &'a str, render_pass: vk::RenderPass) -> Self {
        Self {
            name,
            vertex,
            geometry: None,
            fragment,
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            blend: Blend::Opaque,
            color_attachments: 1,
            depth_test: false,
            depth_write: false,
            specialization: &[],
            push_constant_bytes: 0,
            set_layouts: &[],
            render_pass,
            dynamic_line_width: false,
            vertex_stride: 0,
            vertex_attributes: &[],
        }
    }
}

/// Everything a pass decides about a compute pipeline.
pub struct ComputePipelineDesc<'a> {
    pub name: &'a str,
    /// Program name, e.g. `caustics.comp`, found by the caller's lookup.
    pub shader: &'a str,
    pub specialization: &'a [(u32, u32)],
    pub push_constant_bytes: u32,
    pub set_layouts: &'a [vk::DescriptorSetLayout],
}

pub struct Pipeline {
    pub raw: vk::Pipeline,
    pub layout: vk::PipelineLayout,
    bind_point: vk::PipelineBindPoint,
    /// The stages of the layout's push-constant range (pushes must name exactly these).
    push_stages: vk::ShaderStageFlags,
    device: Arc<Device>,
}

/// A pipeline layout with one push-constant range (if any bytes) visible to `stages`.
fn pipeline_layout(
    device: &Device,
    name: &str,
    set_layouts: &[vk::DescriptorSetLayout],
    push_constant_bytes: u32,
    stages: vk::ShaderStageFlags,
) -> Result<vk::PipelineLayout> {
    let push_ranges = [vk::PushConstantRange::default().stage_flags(stages).size(push_constant_bytes)];
    let layout_info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(set_layouts)
        .push_constant_ranges(if push_constant_bytes > 0 { &push_ranges[..] } else { &[] });
    let layout = unsafe { device.raw.create_pipeline_layout(&layout_info, None) }.call("vkCreatePipelineLayout")?;
    device.set_name(layout, &format!("{name} layout"));
    Ok(layout)
}

/// Specialization map entries and data for (id, value) pairs of 32-bit constants.
fn specialization_data(constants: &[(u32, u32)]) -> (Vec<vk::SpecializationMapEntry>, Vec<u8>) {
    let entries = constants
        .iter()
        .enumerate()
        .map(|(i, (id, _))| vk::SpecializationMapEntry { constant_id: *id, offset: 4 * i as u32, size: 4 })
        .collect();
    (entries, constants.iter().flat_map(|(_, v)| v.to_ne_bytes()).collect())
}

/// The SPIR-V of a program by name, or `None` where there is no such program.
pub type ShaderLookup<'a> = &'a dyn Fn(&str) -> Option<&'static [u8]>;

/// SPIR-V bytes as 32-bit words (copied: `include_bytes!` gives no 4-byte alignment), or
/// `None` where they are not SPIR-V.
pub fn spirv_words(bytes: &[u8]) -> Option<Vec<u32>> {
    if !bytes.len().is_multiple_of(4) || bytes.len() < 20 {
        return None;
    }
    let words: Vec<u32> = bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
    (words[0] == 0x0723_0203).then_some(words)
}

/// Creates a shader module from the SPIR-V `lookup` has for `name`.
fn shader_module(device: &Device, lookup: ShaderLookup<'_>, name: &str) -> Result<vk::ShaderModule> {
    let bytes = lookup(name).ok_or_else(|| Error::MissingShader(name.to_string()))?;
    let words = spirv_words(bytes)
        .ok_or_else(|| Error::InvalidParameter { name: "spirv", message: format!("{name} is not SPIR-V") })?;
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    let module = unsafe { device.raw.create_shader_module(&info, None) }.call("vkCreateShaderModule")?;
    device.set_name(module, name);
    Ok(module)
}

impl Pipeline {
    /// A pipeline with its layout and no pipeline yet: it owns the layout from here, so an
    /// early return while creating the pipeline destroys it.
    fn with_layout(
        device: &Arc<Device>,
        name: &str,
        set_layouts: &[vk::DescriptorSetLayout],
        push_constant_bytes: u32,
        bind_point: vk::PipelineBindPoint,
    ) -> Result<Self> {
        let push_stages = if bind_point == vk::PipelineBindPoint::COMPUTE {
            vk::ShaderStageFlags::COMPUTE
        } else {
            vk::ShaderStageFlags::ALL_GRAPHICS
        };
        let layout = pipeline_layout(device, name, set_layouts, push_constant_bytes, push_stages)?;
        Ok(Self { raw: vk::Pipeline::null(), layout, bind_point, push_stages, device: device.clone() })
    }

    pub fn graphics(device: &Arc<Device>, lookup: ShaderLookup<'_>, desc: &GraphicsPipelineDesc<'_>) -> Result<Self> {
        let raw_dev = &device.raw;
        let mut pipeline = Self::with_layout(
            device,
            desc.name,
            desc.set_layouts,
            desc.push_constant_bytes,
            vk::PipelineBindPoint::GRAPHICS,
        )?;

        let mut stages_named = vec![(vk::ShaderStageFlags::VERTEX, desc.vertex)];
        if let Some(g) = desc.geometry {
            stages_named.push((vk::ShaderStageFlags::GEOMETRY, g));
        }
        stages_named.push((vk::ShaderStageFlags::FRAGMENT, desc.fragment));
        let mut modules = Vec::new();
        for (_, name) in &stages_named {
            match shader_module(device, lookup, name) {
                Ok(m) => modules.push(m),
                Err(e) => {
                    for m in modules {
                        unsafe { raw_dev.destroy_shader_module(m, None) };
                    }
                    return Err(e);
                }
            }
        }

        let (spec_entries, spec_data) = specialization_data(desc.specialization);
        let spec = vk::SpecializationInfo::default().map_entries(&spec_entries).data(&spec_data);
        let stages: Vec<vk::PipelineShaderStageCreateInfo> = stages_named
            .iter()
            .zip(&modules)
            .map(|((stage, _), module)| {
                vk::PipelineShaderStageCreateInfo::default()
                    .stage(*stage)
                    .module(*module)
                    .name(c"main")
                    .specialization_info(&spec)
            })
            .collect();

        let vertex_bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: desc.vertex_stride,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let vertex_attributes: Vec<vk::VertexInputAttributeDescription> = desc
            .vertex_attributes
            .iter()
            .map(|&(location, format, offset)| vk::VertexInputAttributeDescription {
                location,
                binding: 0,
                format,
                offset,
            })
            .collect();
        let vertex_input = if desc.vertex_attributes.is_empty() {
            vk::PipelineVertexInputStateCreateInfo::default()
        } else {
            vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&vertex_bindings)
                .vertex_attribute_descriptions(&vertex_attributes)
        };
        let input_assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth_test)
            .depth_write_enable(desc.depth_write)
            .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL);
        let attachment = match desc.blend {
            Blend::Opaque => {
                vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA)
            }
            Blend::Additive => vk::PipelineColorBlendAttachmentState::default()
                .blend_enable(true)
                .src_color_blend_factor(vk::BlendFactor::ONE)
                .dst_color_blend_factor(vk::BlendFactor::ONE)
                .color_blend_op(vk::BlendOp::ADD)
                .src_alpha_blend_factor(vk::BlendFactor::ONE)
                .dst_alpha_blend_factor(vk::BlendFactor::ONE)
                .alpha_blend_op(vk::BlendOp::ADD)
                .color_write_mask(vk::ColorComponentFlags::RGBA),
            Blend::NoColor => {
                vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::empty())
            }
        };
        let attachments = vec![attachment; desc.color_attachments as usize];
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if desc.dynamic_line_width {
            dynamic_states.push(vk::DynamicState::LINE_WIDTH);
        }
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(pipeline.layout)
            .render_pass(desc.render_pass)
            .subpass(0);
        let created = unsafe { raw_dev.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) };
        for m in modules {
            unsafe { raw_dev.destroy_shader_module(m, None) };
        }
        pipeline.raw = created.map_err(|(_, e)| e).call("vkCreateGraphicsPipelines")?[0];
        device.set_name(pipeline.raw, desc.name);
        Ok(pipeline)
    }

    pub fn compute(device: &Arc<Device>, lookup: ShaderLookup<'_>, desc: &ComputePipelineDesc<'_>) -> Result<Self> {
        let mut pipeline = Self::with_layout(
            device,
            desc.name,
            desc.set_layouts,
            desc.push_constant_bytes,
            vk::PipelineBindPoint::COMPUTE,
        )?;
        let layout = pipeline.layout;
        let module = shader_module(device, lookup, desc.shader)?;
        let (spec_entries, spec_data) = specialization_data(desc.specialization);
        let spec = vk::SpecializationInfo::default().map_entries(&spec_entries).data(&spec_data);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(module)
            .name(c"main")
            .specialization_info(&spec);
        let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout);
        let created = unsafe { device.raw.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) };
        unsafe { device.raw.destroy_shader_module(module, None) };
        pipeline.raw = created.map_err(|(_, e)| e).call("vkCreateComputePipelines")?[0];
        device.set_name(pipeline.raw, desc.name);
        Ok(pipeline)
    }
}

impl Pipeline {
    /// Binds the pipeline and, if given, its descriptor set 0.
    pub fn bind(&self, cmd: vk::CommandBuffer, set: Option<vk::DescriptorSet>) {
        let dev = &self.device.raw;
        unsafe {
            dev.cmd_bind_pipeline(cmd, self.bind_point, self.raw);
            if let Some(set) = set {
                dev.cmd_bind_descriptor_sets(cmd, self.bind_point, self.layout, 0, &[set], &[]);
            }
        }
    }

    /// Pushes `bytes` at offset 0 (every stage sees the push-constant block).
    pub fn push(&self, cmd: vk::CommandBuffer, bytes: &[u8]) {
        unsafe { self.device.raw.cmd_push_constants(cmd, self.layout, self.push_stages, 0, bytes) };
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        unsafe {
            self.device.raw.destroy_pipeline(self.raw, None);
            self.device.raw.destroy_pipeline_layout(self.layout, None);
        }
    }
}

/// Sets a full-target viewport and scissor (both are dynamic state in every pipeline).
pub fn set_viewport(device: &Device, cmd: vk::CommandBuffer, extent: vk::Extent2D) {
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    unsafe {
        device.raw.cmd_set_viewport(cmd, 0, &[viewport]);
        device.raw.cmd_set_scissor(cmd, 0, &[vk::Rect2D { offset: vk::Offset2D::default(), extent }]);
    }
}
