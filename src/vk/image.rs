//! 2-D images (render targets) and 2-D image arrays, backed by gpu-allocator, that free
//! themselves. A plain image has one view; an array has one view of all its layers (what a
//! shader samples) and one per layer (what a render pass draws into).

use super::device::Device;
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;
use std::mem::ManuallyDrop;
use std::sync::Arc;

pub struct Image {
    pub raw: vk::Image,
    /// Null for images that are only copied to or from (no attachment or sampling usage).
    /// An array's view is a 2-D array view of all its layers (`sampler2DArray`).
    pub view: vk::ImageView,
    /// An attachable array's 2-D view of each layer (`attachment_view`); empty otherwise.
    layer_views: Vec<vk::ImageView>,
    /// 1 for a plain image.
    pub layers: u32,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    pub aspect: vk::ImageAspectFlags,
    /// The debug name, which its allocation carries too (memory reports list it).
    pub name: String,
    allocation: ManuallyDrop<Allocation>,
    device: Arc<Device>,
}

impl Image {
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
    ) -> Result<Self> {
        Self::create(device, name, extent, format, usage, None)
    }

    /// An array of `layers` images of one size and format, which a shader samples as one
    /// `sampler2DArray` (a layer index picks the image in the fetch itself, where two images
    /// would need a branch between two fetches) and render passes draw into layer by layer.
    pub fn array(
        device: &Arc<Device>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        layers: u32,
    ) -> Result<Self> {
        Self::create(device, name, extent, format, usage, Some(layers))
    }

    /// `array_layers`: None for a plain image (a 2-D view), Some for an array (array views).
    fn create(
        device: &Arc<Device>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        array_layers: Option<u32>,
    ) -> Result<Self> {
        let layers = array_layers.unwrap_or(1);
        if layers == 0 {
            return Err(Error::InvalidParameter { name: "image layers", message: format!("{name}: an array of none") });
        }
        let aspect = aspect_of(format);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })
            .mip_levels(1)
            .array_layers(layers)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let raw = unsafe { device.raw.create_image(&info, None) }.call("vkCreateImage")?;
        let requirements = unsafe { device.raw.get_image_memory_requirements(raw) };
        let allocation = device.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocation {
            Ok(a) => a,
            Err(source) => {
                unsafe { device.raw.destroy_image(raw, None) };
                return Err(Error::Alloc { name: name.into(), source });
            }
        };
        let mut image = Self {
            raw,
            view: vk::ImageView::null(),
            layer_views: Vec::new(),
            layers,
            format,
            extent,
            aspect,
            name: name.to_string(),
            allocation: ManuallyDrop::new(allocation),
            device: device.clone(),
        };
        unsafe { device.raw.bind_image_memory(raw, image.allocation.memory(), image.allocation.offset()) }
            .call("vkBindImageMemory")?;
        device.set_name(raw, name);
        // A view is only valid (and only needed) for images that are attached or sampled.
        let viewable = vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
            | vk::ImageUsageFlags::INPUT_ATTACHMENT;
        if usage.intersects(viewable) {
            let view_type =
                if array_layers.is_some() { vk::ImageViewType::TYPE_2D_ARRAY } else { vk::ImageViewType::TYPE_2D };
            image.view = image.create_view(view_type, image.full_range(), &format!("{name} view"))?;
        }
        let attachable = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        if array_layers.is_some() && usage.intersects(attachable) {
            for layer in 0..layers {
                let range = image.layer_range(layer);
                let view =
                    image.create_view(vk::ImageViewType::TYPE_2D, range, &format!("{name} layer {layer} view"))?;
                image.layer_views.push(view);
            }
        }
        Ok(image)
    }

    fn create_view(
        &self,
        view_type: vk::ImageViewType,
        range: vk::ImageSubresourceRange,
        name: &str,
    ) -> Result<vk::ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(view_type)
            .format(self.format)
            .subresource_range(range);
        let view = unsafe { self.device.raw.create_image_view(&info, None) }.call("vkCreateImageView")?;
        self.device.set_name(view, name);
        Ok(view)
    }

    /// The view a render pass attaches to draw into `layer` (0 for a plain image).
    pub fn attachment_view(&self, layer: u32) -> vk::ImageView {
        match self.layer_views.get(layer as usize) {
            Some(view) => *view,
            None => {
                assert_eq!(layer, 0, "{}: no layer {layer} to attach", self.name);
                self.view
            }
        }
    }

    /// Every layer of the image's one mip level.
    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange::default().aspect_mask(self.aspect).level_count(1).layer_count(self.layers)
    }

    /// One layer of the image's one mip level (0 for a plain image).
    pub fn layer_range(&self, layer: u32) -> vk::ImageSubresourceRange {
        self.full_range().base_array_layer(layer).layer_count(1)
    }

    pub fn texel_count(&self) -> usize {
        self.extent.width as usize * self.extent.height as usize
    }
}

/// Depth formats get the depth aspect, everything else colour.
pub fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D16_UNORM | vk::Format::D32_SFLOAT | vk::Format::X8_D24_UNORM_PACK32 => vk::ImageAspectFlags::DEPTH,
        vk::Format::D24_UNORM_S8_UINT | vk::Format::D32_SFLOAT_S8_UINT | vk::Format::D16_UNORM_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// Bytes per texel of the formats underlight reads back.
pub fn texel_size(format: vk::Format) -> Option<usize> {
    Some(match format {
        vk::Format::R16G16B16A16_SFLOAT => 8,
        vk::Format::R32G32B32A32_SFLOAT => 16,
        vk::Format::R8G8B8A8_UNORM
        | vk::Format::R8G8B8A8_SNORM
        | vk::Format::R8G8B8A8_SRGB
        | vk::Format::B8G8R8A8_UNORM
        | vk::Format::B8G8R8A8_SRGB
        | vk::Format::R32_SFLOAT
        | vk::Format::D32_SFLOAT => 4,
        vk::Format::R16_SFLOAT => 2,
        _ => return None,
    })
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the GPU no longer uses the image (see Buffer::drop); taken exactly once.
        unsafe {
            for view in self.layer_views.drain(..) {
                self.device.raw.destroy_image_view(view, None);
            }
            self.device.raw.destroy_image_view(self.view, None);
            self.device.raw.destroy_image(self.raw, None);
            let allocation = ManuallyDrop::take(&mut self.allocation);
            let _ = self.device.allocator().free(allocation);
        }
    }
}
