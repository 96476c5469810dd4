//! Present pass (viewer only): the frame's output into the window. It reads the compose
//! pass's output (left in TRANSFER_SRC_OPTIMAL by the frame the viewer builds) and blits it
//! into the acquired swapchain image, which it leaves in PRESENT_SRC_KHR. For a screenshot
//! it also copies the presented image into its own host-visible buffer, made visible to the
//! host once the frame's fence has signalled.

use crate::error::Result;
use crate::vk::buffer::Buffer;
use crate::vk::device::Device;
use crate::vk::image::Image;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// The stage the submission waits for the acquire semaphore at: the pass's first barrier
/// starts its layout transition after it.
pub const ACQUIRE_WAIT_STAGE: vk::PipelineStageFlags2 = vk::PipelineStageFlags2::ALL_TRANSFER;

pub struct PresentPass {
    /// The copy of the presented image, made on the first screenshot and kept until
    /// `release_screenshot_buffer` (it is sized for the swapchain's extent).
    screenshot: Option<Buffer>,
    device: Arc<Device>,
}

impl PresentPass {
    pub fn new(device: &Arc<Device>) -> Self {
        Self { screenshot: None, device: device.clone() }
    }

    /// Makes the screenshot buffer for an `extent` swapchain image, unless it exists.
    pub fn prepare_screenshot(&mut self, extent: vk::Extent2D) -> Result<()> {
        if self.screenshot.is_none() {
            self.screenshot = Some(Buffer::new(
                &self.device,
                "screenshot",
                (extent.width * extent.height * 4) as u64,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        Ok(())
    }

    /// The screenshot buffer, once `prepare_screenshot` made it.
    pub fn screenshot_buffer(&self) -> Option<&Buffer> {
        self.screenshot.as_ref()
    }

    /// Frees the screenshot buffer; the next screenshot makes one for the swapchain then.
    pub fn release_screenshot_buffer(&mut self) {
        self.screenshot = None;
    }

    /// Blits `output` into the swapchain image `target` and leaves it ready to present; with
    /// `screenshot`, also copies the presented image into the screenshot buffer (when
    /// `prepare_screenshot` made one).
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        output: &Image,
        target: vk::Image,
        extent: vk::Extent2D,
        screenshot: bool,
    ) {
        let dev = &self.device;
        let screenshot = self.screenshot.as_ref().filter(|_| screenshot);
        let range =
            vk::ImageSubresourceRange::default().aspect_mask(vk::ImageAspectFlags::COLOR).level_count(1).layer_count(1);
        let layers = vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::COLOR).layer_count(1);
        let barrier = |old, new, src_stage, src_access, dst_stage, dst_access| {
            vk::ImageMemoryBarrier2::default()
                .src_stage_mask(src_stage)
                .src_access_mask(src_access)
                .dst_stage_mask(dst_stage)
                .dst_access_mask(dst_access)
                .old_layout(old)
                .new_layout(new)
                .image(target)
                .subresource_range(range)
        };
        let corner = vk::Offset3D { x: extent.width as i32, y: extent.height as i32, z: 1 };
        let blit = vk::ImageBlit::default()
            .src_subresource(layers)
            .src_offsets([vk::Offset3D::default(), corner])
            .dst_subresource(layers)
            .dst_offsets([vk::Offset3D::default(), corner]);
        unsafe {
            // After the acquire semaphore (waited at the transfer stage), before the blit.
            let to_dst = [barrier(
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                ACQUIRE_WAIT_STAGE,
                vk::AccessFlags2::NONE,
                vk::PipelineStageFlags2::BLIT,
                vk::AccessFlags2::TRANSFER_WRITE,
            )];
            dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_dst));
            dev.raw.cmd_blit_image(
                cmd,
                output.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                target,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &[blit],
                vk::Filter::NEAREST,
            );
            let mut last = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
            if let Some(buffer) = screenshot {
                let to_src = [barrier(
                    last,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::PipelineStageFlags2::BLIT,
                    vk::AccessFlags2::TRANSFER_WRITE,
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_READ,
                )];
                dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_src));
                let region = vk::BufferImageCopy::default().image_subresource(layers).image_extent(vk::Extent3D {
                    width: extent.width,
                    height: extent.height,
                    depth: 1,
                });
                dev.raw.cmd_copy_image_to_buffer(
                    cmd,
                    target,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buffer.raw,
                    &[region],
                );
                let to_host = [vk::MemoryBarrier2::default()
                    .src_stage_mask(vk::PipelineStageFlags2::COPY)
                    .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                    .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                    .dst_access_mask(vk::AccessFlags2::HOST_READ)];
                dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
                last = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            }
            // Presentation is ordered by the semaphore the submission signals.
            // The last access matches the layout it leaves (best practices checks the pairing).
            let last_access = if last == vk::ImageLayout::TRANSFER_DST_OPTIMAL {
                vk::AccessFlags2::TRANSFER_WRITE
            } else {
                vk::AccessFlags2::TRANSFER_READ
            };
            let to_present = [barrier(
                last,
                vk::ImageLayout::PRESENT_SRC_KHR,
                vk::PipelineStageFlags2::ALL_TRANSFER,
                last_access,
                vk::PipelineStageFlags2::NONE,
                vk::AccessFlags2::NONE,
            )];
            dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_present));
        }
    }
}
