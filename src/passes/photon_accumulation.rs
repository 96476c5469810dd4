//! What the compute photon paths share: photons dispatched one invocation each, splats added
//! into a float storage buffer with atomics (VK_EXT_shader_atomic_float), and a resolve that
//! copies the buffer into the pass's effect target, so the filter and compose passes read a
//! compute path's buffer exactly as they read a rasterised one.

use crate::error::{Error, Result};
use crate::shader_abi::bindings as b;
use crate::shaders;
use crate::vk::buffer::Buffer;
use crate::vk::descriptors::{Binding, DescriptorSets, Resource};
use crate::vk::device::Device;
use crate::vk::pipeline::{GraphicsPipelineDesc, Pipeline};
use crate::vk::render_pass::ColorTarget;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// Invocations per workgroup of the photon compute shaders (their `local_size_x`).
pub const PHOTONS_PER_GROUP: u64 = 64;

/// Dispatches one invocation per photon. Counts beyond the device's group-count limit are
/// laid out in rows (`photon_invocation_index` in glsl/photons/photon_accumulation.glsl).
pub fn dispatch_per_photon(device: &Device, cmd: vk::CommandBuffer, photons: u64) {
    let groups = photons.div_ceil(PHOTONS_PER_GROUP).max(1);
    let max_x = device.limits().max_compute_work_group_count[0] as u64;
    let (x, y) = if groups <= max_x { (groups, 1) } else { (max_x, groups.div_ceil(max_x)) };
    unsafe { device.raw.cmd_dispatch(cmd, x as u32, y as u32, 1) };
}

/// The device must add floats atomically into storage buffers (the compute photon path).
pub fn require_float_atomics(device: &Device) -> Result<()> {
    if device.has_float_atomics() {
        return Ok(());
    }
    Err(Error::MissingFeatures {
        device: device.info.name.clone(),
        missing: vec!["shaderBufferFloat32AtomicAdd (VK_EXT_shader_atomic_float), for the compute photon path"],
    })
}

/// An RGBA float per pixel of an effect target, and the pass that resolves it into it.
pub struct AtomicAccumulation {
    pub buffer: Buffer,
    extent: vk::Extent2D,
    resolve: Pipeline,
    resolve_sets: DescriptorSets,
    device: Arc<Device>,
}

impl AtomicAccumulation {
    pub fn new(device: &Arc<Device>, name: &str, target: &ColorTarget) -> Result<Self> {
        let extent = target.image.extent;
        let buffer = Buffer::new(
            device,
            &format!("{name} accumulation"),
            extent.width as u64 * extent.height as u64 * 16,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        // One set: the buffer is shared by the frames in flight, like the target it fills
        // (the barriers in `record_clear` order one frame's use after the previous one's).
        let resolve_sets =
            DescriptorSets::new(device, &format!("{name} resolve"), &[(b::PHOTON_ACCUMULATION, Binding::Storage)], 1)?;
        resolve_sets.write_at(0, vec![(b::PHOTON_ACCUMULATION as usize, Self::resource_of(&buffer))]);
        let resolve = shaders::graphics_pipeline(
            device,
            &GraphicsPipelineDesc {
                push_constant_bytes: 8,
                set_layouts: &[resolve_sets.layout],
                ..GraphicsPipelineDesc::new(
                    &format!("{name} resolve"),
                    "fullscreen.vert",
                    "photon_resolve.frag",
                    target.render_pass.raw,
                )
            },
        )?;
        Ok(Self { buffer, extent, resolve, resolve_sets, device: device.clone() })
    }

    fn resource_of(buffer: &Buffer) -> Resource {
        Resource::Storage { buffer: buffer.raw, range: buffer.size }
    }

    /// The buffer as the photon compute shader's binding.
    pub fn resource(&self) -> Resource {
        Self::resource_of(&self.buffer)
    }

    /// Zeroes the buffer once the previous frame's compute and resolve are done with it, and
    /// makes the zeros visible to the photon compute shader.
    pub fn record_clear(&self, cmd: vk::CommandBuffer) {
        let dev = &self.device.raw;
        let storage = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        let before = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::FRAGMENT_SHADER)
            .src_access_mask(storage)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)];
        let after = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_TRANSFER)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .dst_access_mask(storage)];
        unsafe {
            dev.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&before));
            dev.cmd_fill_buffer(cmd, self.buffer.raw, 0, vk::WHOLE_SIZE, 0);
            dev.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&after));
        }
    }

    /// Copies the accumulated splats into `target` (after the photon dispatch).
    pub fn record_resolve(&self, cmd: vk::CommandBuffer, target: &ColorTarget) {
        let to_fragment = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COMPUTE_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::SHADER_STORAGE_READ)
            .dst_stage_mask(vk::PipelineStageFlags2::FRAGMENT_SHADER)
            .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ)];
        unsafe {
            self.device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_fragment));
        }
        target.render_pass.begin(cmd);
        self.resolve.bind(cmd, Some(self.resolve_sets.sets[0]));
        let size = [self.extent.width, self.extent.height];
        self.resolve.push(cmd, bytemuck::cast_slice(&size));
        unsafe { self.device.raw.cmd_draw(cmd, 3, 1, 0, 0) };
        target.render_pass.end(cmd);
    }
}
