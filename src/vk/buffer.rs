//! Buffers backed by gpu-allocator that free themselves.

use super::device::Device;
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;
use std::mem::ManuallyDrop;
use std::sync::Arc;

pub struct Buffer {
    pub raw: vk::Buffer,
    pub size: vk::DeviceSize,
    allocation: ManuallyDrop<Allocation>,
    device: Arc<Device>,
}

impl Buffer {
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self> {
        let info = vk::BufferCreateInfo::default().size(size).usage(usage);
        let raw = unsafe { device.raw.create_buffer(&info, None) }.call("vkCreateBuffer")?;
        let requirements = unsafe { device.raw.get_buffer_memory_requirements(raw) };
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                unsafe { device.raw.destroy_buffer(raw, None) };
                return Err(Error::Alloc { name: name.into(), source });
            }
        };
        let bound = unsafe { device.raw.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) };
        let buffer = Self { raw, size, allocation: ManuallyDrop::new(allocation), device: device.clone() };
        bound.call("vkBindBufferMemory")?;
        device.set_name(raw, name);
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer (`CpuToGpu` / `GpuToCpu`).
    pub fn mapped(&self) -> Option<&[u8]> {
        self.allocation.mapped_slice().map(|s| &s[..self.size as usize])
    }

    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        let size = self.size as usize;
        self.allocation.mapped_slice_mut().map(|s| &mut s[..size])
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the buffer (frames are waited
        // on before their resources drop). The allocation is taken exactly once, here.
        unsafe {
            self.device.raw.destroy_buffer(self.raw, None);
            let allocation = ManuallyDrop::take(&mut self.allocation);
            let _ = self.device.allocator().free(allocation);
        }
    }
}
