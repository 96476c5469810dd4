//! One-shot uploads of static data (meshes, the noise texture) through a staging buffer.
//! Set-up only: each call waits for the GPU.

use super::barrier::{SHADER_STAGES, VERTEX_INPUT_STAGES};
use super::buffer::Buffer;
use super::commands::one_shot;
use super::device::Device;
use super::image::Image;
use crate::error::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// A device-local buffer filled with `bytes`.
pub fn buffer_with_data(device: &Arc<Device>, name: &str, bytes: &[u8], usage: vk::BufferUsageFlags) -> Result<Buffer> {
    let size = bytes.len().max(4) as vk::DeviceSize;
    let mut staging = Buffer::new(
        device,
        &format!("{name} staging"),
        size,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.mapped_mut().expect("host-visible staging")[..bytes.len()].copy_from_slice(bytes);
    let buffer = Buffer::new(device, name, size, usage | vk::BufferUsageFlags::TRANSFER_DST, MemoryLocation::GpuOnly)?;
    one_shot(device, &format!("upload {name}"), |cmd| unsafe {
        device.raw.cmd_copy_buffer(
            cmd,
            staging.raw,
            buffer.raw,
            &[vk::BufferCopy { src_offset: 0, dst_offset: 0, size }],
        );
        // Make the copy visible to every later reader (vertex input, shaders).
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(VERTEX_INPUT_STAGES | SHADER_STAGES)
            .dst_access_mask(
                vk::AccessFlags2::VERTEX_ATTRIBUTE_READ | vk::AccessFlags2::INDEX_READ | vk::AccessFlags2::SHADER_READ,
            )];
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier));
    })?;
    Ok(buffer)
}

/// A sampled image filled with `bytes` (tightly packed texels), left in SHADER_READ_ONLY_OPTIMAL.
pub fn image_with_data(
    device: &Arc<Device>,
    name: &str,
    extent: vk::Extent2D,
    format: vk::Format,
    bytes: &[u8],
) -> Result<Image> {
    let mut staging = Buffer::new(
        device,
        &format!("{name} staging"),
        bytes.len() as vk::DeviceSize,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.mapped_mut().expect("host-visible staging").copy_from_slice(bytes);
    let image =
        Image::new(device, name, extent, format, vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST)?;
    one_shot(device, &format!("upload {name}"), |cmd| unsafe {
        let to_dst = [vk::ImageMemoryBarrier2::default()
            .dst_stage_mask(vk::PipelineStageFlags2::COPY)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .image(image.raw)
            .subresource_range(image.full_range())];
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_dst));
        let region = vk::BufferImageCopy::default()
            .image_subresource(vk::ImageSubresourceLayers::default().aspect_mask(image.aspect).layer_count(1))
            .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 });
        device.raw.cmd_copy_buffer_to_image(
            cmd,
            staging.raw,
            image.raw,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
        );
        let to_read = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(SHADER_STAGES)
            .dst_access_mask(vk::AccessFlags2::SHADER_READ)
            .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
            .image(image.raw)
            .subresource_range(image.full_range())];
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_read));
    })?;
    Ok(image)
}

/// Clears freshly created images to zero and leaves them in SHADER_READ_ONLY_OPTIMAL, for
/// images a pipeline binds before any pass has written them (the shaders that bind them read
/// them only in frames whose passes wrote them first, but a defined zero is what a debugger
/// shows, and a transition straight from UNDEFINED to a read-only layout is a pattern the
/// best-practices layer rightly flags). The images need TRANSFER_DST usage.
pub fn clear_to_sampled(device: &Device, name: &str, images: &[&Image]) -> Result<()> {
    if images.is_empty() {
        return Ok(());
    }
    let barriers = |to_clear: bool| -> Vec<vk::ImageMemoryBarrier2> {
        images
            .iter()
            .map(|image| {
                let b = vk::ImageMemoryBarrier2::default().image(image.raw).subresource_range(image.full_range());
                if to_clear {
                    b.dst_stage_mask(vk::PipelineStageFlags2::CLEAR)
                        .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                        .old_layout(vk::ImageLayout::UNDEFINED)
                        .new_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                } else {
                    b.src_stage_mask(vk::PipelineStageFlags2::CLEAR)
                        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                        .dst_stage_mask(SHADER_STAGES)
                        .dst_access_mask(vk::AccessFlags2::SHADER_READ)
                        .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
                        .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                }
            })
            .collect()
    };
    let (to_clear, to_read) = (barriers(true), barriers(false));
    one_shot(device, name, |cmd| unsafe {
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_clear));
        for image in images {
            let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            if image.aspect.contains(vk::ImageAspectFlags::DEPTH) {
                let value = vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 };
                device.raw.cmd_clear_depth_stencil_image(cmd, image.raw, dst, &value, &[image.full_range()]);
            } else {
                let value = vk::ClearColorValue { float32: [0.0; 4] };
                device.raw.cmd_clear_color_image(cmd, image.raw, dst, &value, &[image.full_range()]);
            }
        }
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_read));
    })
}
