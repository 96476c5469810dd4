//! One-shot uploads of static data (meshes, the noise texture) through a staging buffer.
//! Set-up only: each call waits for the GPU.

use super::buffer::Buffer;
use super::commands::one_shot;
use super::device::Device;
use super::image::Image;
use crate::error::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// A device-local buffer filled with `bytes`.
pub fn buffer_with_data(
    device: &Arc<Device>,
    name: &str,
    bytes: &[u8],
    usage: vk::BufferUsageFlags,
) -> Result<Buffer> {
    let size = bytes.len().max(4) as vk::DeviceSize;
    let mut staging = Buffer::new(device, &format!("{name} staging"), size, vk::BufferUsageFlags::TRANSFER_SRC, MemoryLocation::CpuToGpu)?;
    staging.mapped_mut().expect("host-visible staging")[..bytes.len()].copy_from_slice(bytes);
    let buffer = Buffer::new(device, name, size, usage | vk::BufferUsageFlags::TRANSFER_DST, MemoryLocation::GpuOnly)?;
    one_shot(device, &format!("upload {name}"), |cmd| unsafe {
        device.raw.cmd_copy_buffer(cmd, staging.raw, buffer.raw, &[vk::BufferCopy { src_offset: 0, dst_offset: 0, size }]);
        // Make the copy visible to every later reader (vertex input, shaders).
        let barrier = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::MEMORY_READ)];
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
    let image = Image::new(device, name, extent, format, vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST)?;
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
        device.raw.cmd_copy_buffer_to_image(cmd, staging.raw, image.raw, vk::ImageLayout::TRANSFER_DST_OPTIMAL, &[region]);
        let to_read = [vk::ImageMemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            .dst_access_mask(vk::AccessFlags2::SHADER_SAMPLED_READ)
            .old_layout(vk::ImageLayout::TRANSFER_DST_OPTIMAL)
            .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
            .image(image.raw)
            .subresource_range(image.full_range())];
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_read));
    })?;
    Ok(image)
}

/// Moves freshly created images from UNDEFINED to SHADER_READ_ONLY_OPTIMAL, for images a
/// pipeline binds before any pass has written them (their contents stay undefined: the
/// shaders that bind them read them only in frames whose passes wrote them first).
pub fn make_sampleable(device: &Device, name: &str, images: &[&Image]) -> Result<()> {
    if images.is_empty() {
        return Ok(());
    }
    let barriers: Vec<vk::ImageMemoryBarrier2> = images
        .iter()
        .map(|image| {
            vk::ImageMemoryBarrier2::default()
                .dst_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
                .dst_access_mask(vk::AccessFlags2::SHADER_SAMPLED_READ)
                .old_layout(vk::ImageLayout::UNDEFINED)
                .new_layout(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .image(image.raw)
                .subresource_range(image.full_range())
        })
        .collect();
    one_shot(device, name, |cmd| unsafe {
        device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&barriers));
    })
}
