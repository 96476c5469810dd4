//! Descriptor sets. Each pass declares its bindings once; a `DescriptorSets` owns the layout,
//! a pool sized for exactly its sets, and the sets (one per frame in flight where the pass
//! reads per-frame data).

use super::device::Device;
use crate::error::{Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// What one binding holds.
#[derive(Clone, Copy, Debug)]
pub enum Binding {
    /// A sampled image with its sampler.
    Texture,
    /// A storage buffer. The frame's parameter block is one too, read-only (glsl/shared/frame.glsl
    /// says why it is not a uniform buffer).
    Storage,
    /// A uniform buffer: only the frame's values, as the fragment shaders read them (the same
    /// buffer's start; glsl/shared/frame.glsl says why).
    Uniform,
}

impl Binding {
    fn vk_type(self) -> vk::DescriptorType {
        match self {
            Binding::Texture => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
            Binding::Storage => vk::DescriptorType::STORAGE_BUFFER,
            Binding::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
        }
    }
}

/// A resource written into a binding.
#[derive(Clone, Copy)]
pub enum Resource {
    Texture { view: vk::ImageView, sampler: vk::Sampler, layout: vk::ImageLayout },
    Storage { buffer: vk::Buffer, range: vk::DeviceSize },
    Uniform { buffer: vk::Buffer, range: vk::DeviceSize },
}

impl Resource {
    /// The kind of binding this resource fills.
    fn binding(&self) -> Binding {
        match self {
            Resource::Texture { .. } => Binding::Texture,
            Resource::Storage { .. } => Binding::Storage,
            Resource::Uniform { .. } => Binding::Uniform,
        }
    }
}

pub struct DescriptorSets {
    pub layout: vk::DescriptorSetLayout,
    pool: vk::DescriptorPool,
    pub sets: Vec<vk::DescriptorSet>,
    device: Arc<Device>,
}

impl DescriptorSets {
    /// One set layout with exactly `bindings` (binding number, kind), visible to every
    /// graphics stage and to compute, and `count` sets of it. Binding numbers may be sparse: passes share
    /// one numbering (glsl/shared/frame_textures.glsl) but each declares only what it reads.
    pub fn new(device: &Arc<Device>, name: &str, bindings: &[(u32, Binding)], count: u32) -> Result<Self> {
        let layout_bindings: Vec<vk::DescriptorSetLayoutBinding> = bindings
            .iter()
            .map(|&(i, b)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i)
                    .descriptor_type(b.vk_type())
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::ALL_GRAPHICS | vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        let layout =
            unsafe { device.raw.create_descriptor_set_layout(&info, None) }.call("vkCreateDescriptorSetLayout")?;
        device.set_name(layout, &format!("{name} set layout"));
        let mut this = Self { layout, pool: vk::DescriptorPool::null(), sets: Vec::new(), device: device.clone() };
        let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
        for (_, b) in bindings {
            match sizes.iter_mut().find(|s| s.ty == b.vk_type()) {
                Some(s) => s.descriptor_count += count,
                None => sizes.push(vk::DescriptorPoolSize { ty: b.vk_type(), descriptor_count: count }),
            }
        }
        let pool_info = vk::DescriptorPoolCreateInfo::default().max_sets(count).pool_sizes(&sizes);
        this.pool = unsafe { device.raw.create_descriptor_pool(&pool_info, None) }.call("vkCreateDescriptorPool")?;
        device.set_name(this.pool, &format!("{name} descriptor pool"));
        let layouts = vec![layout; count as usize];
        let alloc = vk::DescriptorSetAllocateInfo::default().descriptor_pool(this.pool).set_layouts(&layouts);
        this.sets = unsafe { device.raw.allocate_descriptor_sets(&alloc) }.call("vkAllocateDescriptorSets")?;
        Ok(this)
    }

    /// Writes each (binding, resource) into set `set`.
    pub fn write_at(&self, set: usize, resources: Vec<(usize, Resource)>) {
        for (binding, resource) in resources {
            self.write_one(set, binding as u32, &resource);
        }
    }

    fn write_one(&self, set: usize, binding: u32, resource: &Resource) {
        let buffer_info;
        let image_info;
        let w = vk::WriteDescriptorSet::default()
            .dst_set(self.sets[set])
            .dst_binding(binding)
            .descriptor_type(resource.binding().vk_type());
        let w = match resource {
            Resource::Texture { view, sampler, layout } => {
                image_info = [vk::DescriptorImageInfo { sampler: *sampler, image_view: *view, image_layout: *layout }];
                w.image_info(&image_info)
            }
            Resource::Storage { buffer, range } | Resource::Uniform { buffer, range } => {
                buffer_info = [vk::DescriptorBufferInfo { buffer: *buffer, offset: 0, range: *range }];
                w.buffer_info(&buffer_info)
            }
        };
        unsafe { self.device.raw.update_descriptor_sets(&[w], &[]) };
    }
}

impl Drop for DescriptorSets {
    fn drop(&mut self) {
        unsafe {
            self.device.raw.destroy_descriptor_pool(self.pool, None);
            self.device.raw.destroy_descriptor_set_layout(self.layout, None);
        }
    }
}
