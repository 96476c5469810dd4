//! Copying a render target into host memory, for headless output and tests.
//!
//! The staging buffer is made once per target; recording the copy adds no allocation and
//! no wait. Reading it is the caller's job once the frame's fence has signalled.

use super::barrier::SHADER_STAGES;
use super::buffer::Buffer;
use super::device::Device;
use super::image::{texel_size, Image};
use crate::error::{Error, Result};
use crate::image_io::HdrImage;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

pub struct Readback {
    buffer: Buffer,
    extent: vk::Extent2D,
    format: vk::Format,
    /// The layer copied (0 unless the image is an array).
    layer: u32,
    device: Arc<Device>,
}

impl Readback {
    pub fn new(device: &Arc<Device>, image: &Image) -> Result<Self> {
        Self::of_layer(device, image, 0)
    }

    /// A readback of one layer of an image array.
    pub fn of_layer(device: &Arc<Device>, image: &Image, layer: u32) -> Result<Self> {
        if layer >= image.layers {
            return Err(Error::InvalidParameter {
                name: "readback layer",
                message: format!("{} has {} layers, not a layer {layer}", image.name, image.layers),
            });
        }
        let texel = texel_size(image.format).ok_or_else(|| Error::InvalidParameter {
            name: "readback format",
            message: format!("{:?} cannot be read back", image.format),
        })?;
        let size = (image.texel_count() * texel) as vk::DeviceSize;
        let buffer = Buffer::new(
            device,
            &if image.layers > 1 {
                format!("{} layer {layer} read-back", image.name)
            } else {
                format!("{} read-back", image.name)
            },
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        Ok(Self { buffer, extent: image.extent, format: image.format, layer, device: device.clone() })
    }

    /// Records the copy of an image currently in `layout`: transitions it to
    /// TRANSFER_SRC_OPTIMAL first (after everything before) and back to `layout` after the
    /// copy, as a later frame may sample it before any pass rewrites it (the water surface
    /// binds the photon buffers in every frame).
    pub fn record_from(&self, cmd: vk::CommandBuffer, image: &Image, layout: vk::ImageLayout) {
        let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        // Out of `layout` after the passes that sampled it (their writes were made available
        // by their render pass), into the copy; and back for the shaders of later frames.
        let stage_access = |l: vk::ImageLayout| {
            if l == src {
                (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ)
            } else {
                (SHADER_STAGES, vk::AccessFlags2::SHADER_READ)
            }
        };
        let barrier = |from: vk::ImageLayout, to: vk::ImageLayout| {
            let (src_stage, src_access) = stage_access(from);
            let (dst_stage, dst_access) = stage_access(to);
            [vk::ImageMemoryBarrier2::default()
                .src_stage_mask(src_stage)
                .src_access_mask(src_access)
                .dst_stage_mask(dst_stage)
                .dst_access_mask(dst_access)
                .old_layout(from)
                .new_layout(to)
                .image(image.raw)
                .subresource_range(image.layer_range(self.layer))]
        };
        let dev = &self.device.raw;
        if layout != src {
            unsafe {
                dev.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().image_memory_barriers(&barrier(layout, src)),
                )
            };
        }
        self.record(cmd, image);
        if layout != src {
            unsafe {
                dev.cmd_pipeline_barrier2(
                    cmd,
                    &vk::DependencyInfo::default().image_memory_barriers(&barrier(src, layout)),
                )
            };
        }
    }

    /// The raw bytes copied (e.g. 8-bit sRGB texels). Call after the copy's fence signalled.
    pub fn bytes(&self) -> &[u8] {
        self.buffer.mapped().expect("readback buffers are host-visible")
    }

    /// Records the copy of `image` (in TRANSFER_SRC_OPTIMAL, after a pass whose outgoing
    /// dependency covers transfers) and makes it visible to the host.
    pub fn record(&self, cmd: vk::CommandBuffer, image: &Image) {
        let region = vk::BufferImageCopy::default()
            .image_subresource(
                vk::ImageSubresourceLayers::default()
                    .aspect_mask(image.aspect)
                    .base_array_layer(self.layer)
                    .layer_count(1),
            )
            .image_extent(vk::Extent3D { width: image.extent.width, height: image.extent.height, depth: 1 });
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::COPY)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        unsafe {
            self.device.raw.cmd_copy_image_to_buffer(
                cmd,
                image.raw,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                self.buffer.raw,
                &[region],
            );
            self.device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
        }
    }

    /// Decodes the copied texels to linear RGBA f32. Call after the copy's fence signalled.
    pub fn read(&self) -> Result<HdrImage> {
        let bytes = self.buffer.mapped().ok_or_else(|| Error::InvalidParameter {
            name: "readback",
            message: "staging buffer is not host-visible".into(),
        })?;
        let (w, h) = (self.extent.width, self.extent.height);
        let pixels: Vec<[f32; 4]> = match self.format {
            vk::Format::R16G16B16A16_SFLOAT => bytes
                .chunks_exact(8)
                .map(|t| {
                    let c = |i: usize| half::f16::from_le_bytes([t[2 * i], t[2 * i + 1]]).to_f32();
                    [c(0), c(1), c(2), c(3)]
                })
                .collect(),
            vk::Format::R32G32B32A32_SFLOAT => bytes
                .chunks_exact(16)
                .map(|t| {
                    let c = |i: usize| f32::from_le_bytes([t[4 * i], t[4 * i + 1], t[4 * i + 2], t[4 * i + 3]]);
                    [c(0), c(1), c(2), c(3)]
                })
                .collect(),
            // Signed normalised: −128 and −127 both read as −1 (the Vulkan rule).
            vk::Format::R8G8B8A8_SNORM => bytes
                .chunks_exact(4)
                .map(|t| {
                    let c = |i: usize| (t[i] as i8 as f32 / 127.0).max(-1.0);
                    [c(0), c(1), c(2), c(3)]
                })
                .collect(),
            vk::Format::R32_SFLOAT | vk::Format::D32_SFLOAT => bytes
                .chunks_exact(4)
                .map(|t| {
                    let v = f32::from_le_bytes([t[0], t[1], t[2], t[3]]);
                    [v, v, v, 1.0]
                })
                .collect(),
            other => return Err(Error::InvalidParameter { name: "readback format", message: format!("{other:?}") }),
        };
        Ok(HdrImage { width: w, height: h, pixels })
    }
}
