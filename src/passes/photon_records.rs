//! Photon recording, shared by the caustic and godray passes (`FrameOptions::record_photons`):
//! the geometry shaders' PHOTON_DEBUG variants write two vec4 records per photon into a
//! host-visible storage buffer, which the host reads once the frame's fence has signalled
//! (`src/flux_budget.rs`, the twin tests).

use crate::error::{Error, Result};
use crate::passes::PhotonPath;
use crate::vk::buffer::Buffer;
use crate::vk::descriptors::Resource;
use crate::vk::device::Device;
use ash::vk;
use std::sync::Arc;

/// Bytes per photon: two vec4 records.
const BYTES_PER_PHOTON: u64 = 32;

pub struct PhotonRecords {
    buffer: Buffer,
}

impl PhotonRecords {
    /// A buffer for `photons` photons' records, named `name`. Recording is a feature of the
    /// geometry-shader path and needs stores from the vertex pipeline.
    pub fn new(device: &Arc<Device>, name: &str, photons: u64, path: PhotonPath) -> Result<Self> {
        if path != PhotonPath::GeometryShader {
            return Err(Error::InvalidParameter {
                name: "record_photons",
                message: "photon recording is a feature of the geometry-shader path".into(),
            });
        }
        if !device.has_pipeline_stores() {
            return Err(Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["vertexPipelineStoresAndAtomics (photon recording)"],
            });
        }
        let buffer = Buffer::new(
            device,
            name,
            photons * BYTES_PER_PHOTON,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        Ok(Self { buffer })
    }

    /// The buffer as the shaders' PHOTON_DEBUG binding.
    pub fn resource(&self) -> Resource {
        Resource::Storage { buffer: self.buffer.raw, range: self.buffer.size }
    }

    /// After the draw that records: the geometry shader's writes made visible to the host,
    /// which reads them once the frame's fence signals.
    pub fn record_host_barrier(&self, device: &Device, cmd: vk::CommandBuffer) {
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::GEOMETRY_SHADER)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        unsafe { device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host)) };
    }

    /// The records, two per photon in grid order. Only meaningful after the frame that
    /// recorded them has finished.
    pub fn read(&self) -> Option<Vec<[f32; 4]>> {
        let bytes = self.buffer.mapped()?;
        let floats: Vec<f32> = bytes.chunks_exact(4).map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        Some(floats.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]]).collect())
    }
}
