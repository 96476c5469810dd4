//! The scene's meshes on the GPU: one vertex buffer (position, normal, albedo) and one index
//! buffer for all of them, drawn with a single call by the shadow and scene passes.

use crate::error::Result;
use crate::scene::Scene;
use crate::vk::buffer::Buffer;
use crate::vk::device::Device;
use crate::vk::upload::buffer_with_data;
use ash::vk;
use std::sync::Arc;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MeshVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub albedo: [f32; 3],
}

/// Vertex attributes of `MeshVertex` for `glsl/scene/mesh.vert`: (location, format, offset).
pub const MESH_ATTRIBUTES: [(u32, vk::Format, u32); 3] = [
    (0, vk::Format::R32G32B32_SFLOAT, 0),
    (1, vk::Format::R32G32B32_SFLOAT, 12),
    (2, vk::Format::R32G32B32_SFLOAT, 24),
];

pub struct GpuMeshes {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
}

impl GpuMeshes {
    pub fn new(device: &Arc<Device>, scene: &Scene) -> Result<Self> {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as u32;
            for (p, n) in m.positions.iter().zip(&m.normals) {
                vertices.push(MeshVertex { position: p.to_array(), normal: n.to_array(), albedo: m.albedo.to_array() });
            }
            indices.extend(m.indices.iter().map(|i| base + i));
        }
        let vb = buffer_with_data(
            device,
            "scene vertices",
            bytemuck::cast_slice(&vertices),
            vk::BufferUsageFlags::VERTEX_BUFFER,
        )?;
        let ib = buffer_with_data(
            device,
            "scene indices",
            bytemuck::cast_slice(&indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
        )?;
        Ok(Self { vertices: vb, indices: ib, index_count: indices.len() as u32 })
    }

    pub fn draw(&self, device: &Device, cmd: vk::CommandBuffer) {
        unsafe {
            device.raw.cmd_bind_vertex_buffers(cmd, 0, &[self.vertices.raw], &[0]);
            device.raw.cmd_bind_index_buffer(cmd, self.indices.raw, 0, vk::IndexType::UINT32);
            device.raw.cmd_draw_indexed(cmd, self.index_count, 1, 0, 0, 0);
        }
    }
}
