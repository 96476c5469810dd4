//! Samplers. The method reads most textures with texelFetch (exact texels), so only two
//! samplers exist: nearest for maps read at a position, linear for upsampling effect targets.

use super::device::Device;
use crate::error::{Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

pub struct Sampler {
    pub raw: vk::Sampler,
    device: Arc<Device>,
}

impl Sampler {
    pub fn new(device: &Arc<Device>, name: &str, filter: vk::Filter) -> Result<Self> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        let raw = unsafe { device.raw.create_sampler(&info, None) }.call("vkCreateSampler")?;
        device.set_name(raw, name);
        Ok(Self { raw, device: device.clone() })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        unsafe { self.device.raw.destroy_sampler(self.raw, None) };
    }
}
