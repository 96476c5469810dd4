//! Render passes with their framebuffer. Each pass of the frame owns one (the method is
//! described pass by pass, and a classic VkRenderPass states each pass's attachments, load
//! operations and layouts explicitly).

use super::device::Device;
use super::image::Image;
use super::pipeline::set_viewport;
use crate::error::{Result, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// What happens to an attachment's contents when the pass begins.
#[derive(Clone, Copy, Debug)]
pub enum Load {
    /// Cleared to this value (colour: RGBA; depth: the first component).
    Clear([f32; 4]),
    /// Kept; the image is in `layout` when the pass begins.
    Keep { layout: vk::ImageLayout },
}

/// What happens to an attachment's contents when the pass ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Store {
    /// Written back: something after the pass reads them.
    Keep,
    /// Left undefined: nothing reads them after the pass (a depth used only for this pass's
    /// own test), so a tiling GPU need not write them back.
    Discard,
}

pub struct Attachment<'a> {
    pub image: &'a Image,
    /// The layer drawn into (0 unless `image` is an array).
    pub layer: u32,
    pub load: Load,
    pub store: Store,
    /// Layout the pass leaves the image in, chosen for its next use.
    pub final_layout: vk::ImageLayout,
}

impl<'a> Attachment<'a> {
    /// A plain image's one layer (an array's layer: the struct with `layer` set).
    pub fn new(image: &'a Image, load: Load, store: Store, final_layout: vk::ImageLayout) -> Self {
        Self { image, layer: 0, load, store, final_layout }
    }
}

pub struct RenderPass {
    pub raw: vk::RenderPass,
    pub framebuffer: vk::Framebuffer,
    pub extent: vk::Extent2D,
    clear_values: Vec<vk::ClearValue>,
    device: Arc<Device>,
}

impl RenderPass {
    /// One subpass writing `colors` (and `depth`, if any). All attachments must share an extent.
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        colors: &[Attachment<'_>],
        depth: Option<&Attachment<'_>>,
    ) -> Result<Self> {
        let mut descs = Vec::new();
        let mut clear_values = Vec::new();
        let mut push = |a: &Attachment<'_>, is_depth: bool| {
            let (load_op, initial, clear) = match a.load {
                Load::Clear(c) => (vk::AttachmentLoadOp::CLEAR, vk::ImageLayout::UNDEFINED, c),
                Load::Keep { layout } => (vk::AttachmentLoadOp::LOAD, layout, [0.0; 4]),
            };
            let store_op = match a.store {
                Store::Keep => vk::AttachmentStoreOp::STORE,
                Store::Discard => vk::AttachmentStoreOp::DONT_CARE,
            };
            descs.push(
                vk::AttachmentDescription::default()
                    .format(a.image.format)
                    .samples(vk::SampleCountFlags::TYPE_1)
                    .load_op(load_op)
                    .store_op(store_op)
                    .stencil_load_op(vk::AttachmentLoadOp::DONT_CARE)
                    .stencil_store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .initial_layout(initial)
                    .final_layout(a.final_layout),
            );
            clear_values.push(if is_depth {
                vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: clear[0], stencil: 0 } }
            } else {
                vk::ClearValue { color: vk::ClearColorValue { float32: clear } }
            });
        };
        for c in colors {
            push(c, false);
        }
        if let Some(d) = depth {
            push(d, true);
        }
        let color_refs: Vec<vk::AttachmentReference> = (0..colors.len() as u32)
            .map(|i| vk::AttachmentReference { attachment: i, layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL })
            .collect();
        let depth_ref = vk::AttachmentReference {
            attachment: colors.len() as u32,
            layout: vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        };
        let mut subpass = vk::SubpassDescription::default()
            .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
            .color_attachments(&color_refs);
        if depth.is_some() {
            subpass = subpass.depth_stencil_attachment(&depth_ref);
        }
        // Dependencies with whatever comes before and after the pass, by the frame's shared
        // stage and access sets (vk::barrier): correct for any order of passes, and precise.
        use super::barrier::render_pass as rp;
        let dependencies = [
            vk::SubpassDependency {
                src_subpass: vk::SUBPASS_EXTERNAL,
                dst_subpass: 0,
                src_stage_mask: rp::OUTSIDE,
                dst_stage_mask: rp::INSIDE,
                src_access_mask: rp::WRITES,
                dst_access_mask: rp::USES,
                dependency_flags: vk::DependencyFlags::empty(),
            },
            vk::SubpassDependency {
                src_subpass: 0,
                dst_subpass: vk::SUBPASS_EXTERNAL,
                src_stage_mask: rp::ATTACHMENT_STAGES | rp::GRAPHICS_SHADERS,
                dst_stage_mask: rp::OUTSIDE,
                src_access_mask: rp::ATTACHMENT_WRITES | vk::AccessFlags::SHADER_WRITE,
                dst_access_mask: rp::AFTER_USES,
                dependency_flags: vk::DependencyFlags::empty(),
            },
        ];
        let subpasses = [subpass];
        let info =
            vk::RenderPassCreateInfo::default().attachments(&descs).subpasses(&subpasses).dependencies(&dependencies);
        let raw = unsafe { device.raw.create_render_pass(&info, None) }.call("vkCreateRenderPass")?;
        device.set_name(raw, name);
        let extent = colors.first().or(depth).map(|a| a.image.extent).unwrap_or_default();
        let mut pass = Self { raw, framebuffer: vk::Framebuffer::null(), extent, clear_values, device: device.clone() };
        let views: Vec<vk::ImageView> = colors.iter().chain(depth).map(|a| a.image.attachment_view(a.layer)).collect();
        let fb_info = vk::FramebufferCreateInfo::default()
            .render_pass(raw)
            .attachments(&views)
            .width(extent.width)
            .height(extent.height)
            .layers(1);
        pass.framebuffer = unsafe { device.raw.create_framebuffer(&fb_info, None) }.call("vkCreateFramebuffer")?;
        device.set_name(pass.framebuffer, &format!("{name} framebuffer"));
        Ok(pass)
    }

    /// Begins the pass and sets the viewport and scissor to its whole extent (every pipeline
    /// takes them as dynamic state).
    pub fn begin(&self, cmd: vk::CommandBuffer) {
        let info = vk::RenderPassBeginInfo::default()
            .render_pass(self.raw)
            .framebuffer(self.framebuffer)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent })
            .clear_values(&self.clear_values);
        unsafe { self.device.raw.cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE) };
        set_viewport(&self.device, cmd, self.extent);
    }

    /// `begin`, clearing the first colour attachment to `color` instead of its clear value
    /// (a clear that changes per frame; no allocation).
    pub fn begin_with_first_clear(&self, cmd: vk::CommandBuffer, color: [f32; 4]) {
        let mut values = [vk::ClearValue::default(); 4];
        let n = self.clear_values.len().min(values.len());
        values[..n].copy_from_slice(&self.clear_values[..n]);
        values[0] = vk::ClearValue { color: vk::ClearColorValue { float32: color } };
        let info = vk::RenderPassBeginInfo::default()
            .render_pass(self.raw)
            .framebuffer(self.framebuffer)
            .render_area(vk::Rect2D { offset: vk::Offset2D::default(), extent: self.extent })
            .clear_values(&values[..n]);
        unsafe { self.device.raw.cmd_begin_render_pass(cmd, &info, vk::SubpassContents::INLINE) };
        set_viewport(&self.device, cmd, self.extent);
    }

    pub fn end(&self, cmd: vk::CommandBuffer) {
        unsafe { self.device.raw.cmd_end_render_pass(cmd) };
    }
}

impl Drop for RenderPass {
    fn drop(&mut self) {
        unsafe {
            self.device.raw.destroy_framebuffer(self.framebuffer, None);
            self.device.raw.destroy_render_pass(self.raw, None);
        }
    }
}

/// One colour image a pass draws into, cleared to zero every frame and left in
/// `final_layout` for its reader: the shape of the photon, filter and compose passes.
pub struct ColorTarget {
    // The render pass first: its framebuffer refers to the images' views.
    pub render_pass: RenderPass,
    pub image: Image,
    /// A depth attachment of the same extent, for a pass that tests its draws against a
    /// depth of its own (`with_optional_depth`); the pass itself fills it, nothing else reads it.
    pub depth: Option<Image>,
}

impl ColorTarget {
    pub fn new(
        device: &Arc<Device>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        final_layout: vk::ImageLayout,
    ) -> Result<Self> {
        Self::with_optional_depth(device, name, extent, format, final_layout, false)
    }

    /// `new`, with a D32_SFLOAT depth attachment of the same extent where `with_depth`,
    /// cleared to 1 when the pass begins.
    pub fn with_optional_depth(
        device: &Arc<Device>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        final_layout: vk::ImageLayout,
        with_depth: bool,
    ) -> Result<Self> {
        // TRANSFER_SRC for read-backs; TRANSFER_DST for a clear before its first pass
        // (upload::clear_to_sampled).
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC
            | vk::ImageUsageFlags::TRANSFER_DST;
        let image = Image::new(device, name, extent, format, usage)?;
        let depth = with_depth
            .then(|| {
                let usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
                Image::new(device, &format!("{name} depth"), extent, vk::Format::D32_SFLOAT, usage)
            })
            .transpose()?;
        let depth_attachment = depth.as_ref().map(|image| {
            Attachment::new(
                image,
                Load::Clear([1.0; 4]),
                Store::Discard,
                vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
            )
        });
        let render_pass = RenderPass::new(
            device,
            name,
            &[Attachment::new(&image, Load::Clear([0.0; 4]), Store::Keep, final_layout)],
            depth_attachment.as_ref(),
        )?;
        Ok(Self { render_pass, image, depth })
    }
}
