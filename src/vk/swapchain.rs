//! The window surface and its swapchain: creation, recreation on resize, acquire and
//! present. The frame renders off screen and its output is blitted into the acquired image,
//! so the frame's targets do not depend on the swapchain's format or image count.

use super::device::Device;
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// What a failed `vkCreateSwapchainKHR` for a window of `extent` means. A window the device
/// cannot hold a swapchain for (an X server grants windows far larger than its screen) is the
/// window's fault, not the renderer's: the error says its size and to shrink it.
fn swapchain_error(extent: vk::Extent2D, result: vk::Result) -> Error {
    match result {
        vk::Result::ERROR_OUT_OF_DEVICE_MEMORY | vk::Result::ERROR_OUT_OF_HOST_MEMORY => {
            Error::WindowTooLarge { width: extent.width, height: extent.height, result }
        }
        result => Error::Vk { call: "vkCreateSwapchainKHR", result },
    }
}

/// How images are presented (`--present-mode`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresentMode {
    /// Wait for vertical blank: no tearing, the default every driver must offer.
    Fifo,
    /// Replace the queued image: low latency without tearing, where offered.
    Mailbox,
    /// Present at once: lowest latency, may tear.
    Immediate,
}

impl PresentMode {
    fn vk(self) -> vk::PresentModeKHR {
        match self {
            PresentMode::Fifo => vk::PresentModeKHR::FIFO,
            PresentMode::Mailbox => vk::PresentModeKHR::MAILBOX,
            PresentMode::Immediate => vk::PresentModeKHR::IMMEDIATE,
        }
    }
}

pub struct Swapchain {
    pub raw: vk::SwapchainKHR,
    pub images: Vec<vk::Image>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    /// Signalled by acquire, one per frame in flight.
    pub acquired: Vec<vk::Semaphore>,
    /// Signalled by the frame's submission, waited on by present; one per swapchain image
    /// (a semaphore may be reused only once the image it was presented with comes back).
    pub rendered: Vec<vk::Semaphore>,
    loader: ash::khr::swapchain::Device,
    device: Arc<Device>,
}

/// The surface of a window. Destroyed after every swapchain made from it.
pub struct Surface {
    pub raw: vk::SurfaceKHR,
    pub loader: ash::khr::surface::Instance,
    /// Keeps the instance (through the device) alive until the surface is destroyed.
    _device: Arc<Device>,
}

impl Surface {
    /// # Safety
    /// The display and window handles must stay valid for the surface's lifetime.
    pub unsafe fn new(
        device: &Arc<Device>,
        display: raw_window_handle::RawDisplayHandle,
        window: raw_window_handle::RawWindowHandle,
    ) -> Result<Self> {
        let inst = &device.instance;
        let raw = unsafe { ash_window::create_surface(&inst.entry, &inst.raw, display, window, None) }
            .call("vkCreate*SurfaceKHR")?;
        let loader = ash::khr::surface::Instance::new(&inst.entry, &inst.raw);
        let supported =
            unsafe { loader.get_physical_device_surface_support(device.info.handle, device.queue_family, raw) }
                .unwrap_or(false);
        let surface = Self { raw, loader, _device: device.clone() };
        if !supported {
            return Err(Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["presentation to this window from the graphics queue"],
            });
        }
        Ok(surface)
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

impl Swapchain {
    /// Creates (or recreates, retiring `old`) a swapchain for a window of `size` pixels.
    /// Returns `None` when the surface currently has no area (a minimised window).
    pub fn new(
        device: &Arc<Device>,
        surface: &Surface,
        size: vk::Extent2D,
        mode: PresentMode,
        old: Option<&Swapchain>,
    ) -> Result<Option<Self>> {
        let pd = device.info.handle;
        let caps = unsafe { surface.loader.get_physical_device_surface_capabilities(pd, surface.raw) }
            .call("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size.width.clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size.height.clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let formats = unsafe { surface.loader.get_physical_device_surface_formats(pd, surface.raw) }
            .call("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        // An sRGB format: the frame's output is already tonemapped and sRGB-encoded, and a
        // blit between sRGB formats copies the encoded values unchanged.
        let format = formats
            .iter()
            .find(|f| matches!(f.format, vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB))
            .ok_or_else(|| Error::MissingFeatures {
                device: device.info.name.clone(),
                missing: vec!["an sRGB 8-bit swapchain format"],
            })?;
        let modes = unsafe { surface.loader.get_physical_device_surface_present_modes(pd, surface.raw) }
            .call("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        if !modes.contains(&mode.vk()) {
            return Err(Error::InvalidParameter {
                name: "present-mode",
                message: format!("{mode:?} is not offered by this surface (offered: {modes:?})"),
            });
        }
        let mut image_count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            image_count = image_count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            // Written by a blit, read back for screenshots.
            .image_usage(vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(mode.vk())
            .clipped(true)
            .old_swapchain(old.map(|s| s.raw).unwrap_or_default());
        let loader = ash::khr::swapchain::Device::new(&device.instance.raw, &device.raw);
        let raw = unsafe { loader.create_swapchain(&info, None) }.map_err(|result| swapchain_error(extent, result))?;
        let mut swapchain = Self {
            raw,
            images: Vec::new(),
            format: format.format,
            extent,
            acquired: Vec::new(),
            rendered: Vec::new(),
            loader,
            device: device.clone(),
        };
        swapchain.images = unsafe { swapchain.loader.get_swapchain_images(raw) }.call("vkGetSwapchainImagesKHR")?;
        for (i, image) in swapchain.images.iter().enumerate() {
            device.set_name(*image, &format!("swapchain image {i}"));
        }
        let sem = || unsafe { device.raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) };
        for _ in 0..super::commands::FRAMES_IN_FLIGHT {
            swapchain.acquired.push(sem().call("vkCreateSemaphore")?);
        }
        for _ in 0..swapchain.images.len() {
            swapchain.rendered.push(sem().call("vkCreateSemaphore")?);
        }
        Ok(Some(swapchain))
    }

    /// Acquires the next image, signalling `acquired[slot]`. `None`: out of date, recreate.
    pub fn acquire(&self, slot: usize) -> Result<Option<u32>> {
        match unsafe { self.loader.acquire_next_image(self.raw, u64::MAX, self.acquired[slot], vk::Fence::null()) } {
            Ok((index, _suboptimal)) => Ok(Some(index)),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(None),
            Err(e) => Err(Error::Vk { call: "vkAcquireNextImageKHR", result: e }),
        }
    }

    /// Presents image `index` once `rendered[index]` signals. `false`: out of date or
    /// suboptimal, recreate.
    pub fn present(&self, index: u32) -> Result<bool> {
        let waits = [self.rendered[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
        match unsafe { self.loader.queue_present(self.device.queue, &info) } {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(e) => Err(Error::Vk { call: "vkQueuePresentKHR", result: e }),
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        unsafe {
            // Presentation engine use of the semaphores ends only when the device is idle.
            let _ = self.device.raw.device_wait_idle();
            for s in self.acquired.iter().chain(&self.rendered) {
                self.device.raw.destroy_semaphore(*s, None);
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_swapchain_the_device_cannot_allocate_names_the_window_s_size() {
        let extent = vk::Extent2D { width: 34464, height: 34464 };
        for result in [vk::Result::ERROR_OUT_OF_DEVICE_MEMORY, vk::Result::ERROR_OUT_OF_HOST_MEMORY] {
            let message = swapchain_error(extent, result).to_string();
            assert!(message.contains("34464×34464") && message.contains("smaller"), "{message}");
        }
        // Other failures stay the driver's, named by the call.
        let message = swapchain_error(extent, vk::Result::ERROR_SURFACE_LOST_KHR).to_string();
        assert!(message.contains("vkCreateSwapchainKHR") && !message.contains("smaller"), "{message}");
    }
}
