//! The validation canary: proves that validation messages, leaked objects and leaked
//! allocations are caught and attributed, so a green suite means something.

mod common;

use common::{assert_clean_shutdown, validated_context};
use gpu_allocator::vulkan::{AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;
use underlight::frame::FrameRing;
use underlight::passes::PassId;
use underlight::vk::buffer::Buffer;
use underlight::vk::image::Image;
use underlight::vk::{vk, Context, ContextDesc};

#[test]
fn clean_context_reports_nothing() {
    let ctx = validated_context();
    assert!(ctx.device.instance.validation_enabled);
    assert_clean_shutdown(ctx);
}

#[test]
fn invalid_call_is_caught_with_its_vuid() {
    let ctx = validated_context();
    // A buffer of size 0 violates VUID-VkBufferCreateInfo-size-00912.
    let info = vk::BufferCreateInfo::default().size(0).usage(vk::BufferUsageFlags::TRANSFER_DST);
    if let Ok(buffer) = unsafe { ctx.device.raw.create_buffer(&info, None) } {
        unsafe { ctx.device.raw.destroy_buffer(buffer, None) };
    }
    let messages = ctx.take_validation_messages();
    assert!(
        messages.iter().any(|m| m.id.contains("VUID-VkBufferCreateInfo-size-00912")),
        "the invalid call was not reported: {messages:?}"
    );
    assert_clean_shutdown(ctx);
}

#[test]
fn sync_hazard_is_caught_and_names_its_pass() {
    let ctx = validated_context();
    let dev = &ctx.device;
    let image = Image::new(
        dev,
        "hazard target",
        vk::Extent2D { width: 8, height: 8 },
        vk::Format::R16G16B16A16_SFLOAT,
        vk::ImageUsageFlags::TRANSFER_DST,
    )
    .unwrap();
    let mut ring = FrameRing::new(dev, false).unwrap();
    let slot = ring.begin().unwrap();
    let cmd = slot.cmd;
    slot.timer.pass(cmd, PassId::Filter, |cmd| unsafe {
        let to_general = [vk::ImageMemoryBarrier2::default()
            .dst_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .dst_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .old_layout(vk::ImageLayout::UNDEFINED)
            .new_layout(vk::ImageLayout::GENERAL)
            .image(image.raw)
            .subresource_range(image.full_range())];
        dev.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_general));
        let color = vk::ClearColorValue { float32: [1.0; 4] };
        // Two writes with no barrier between them: a write-after-write hazard.
        dev.raw.cmd_clear_color_image(cmd, image.raw, vk::ImageLayout::GENERAL, &color, &[image.full_range()]);
        dev.raw.cmd_clear_color_image(cmd, image.raw, vk::ImageLayout::GENERAL, &color, &[image.full_range()]);
    });
    ring.submit(&[], &[]).unwrap();
    ring.finish(|_, _| {}).unwrap();
    let messages = ctx.take_validation_messages();
    let hazard = messages
        .iter()
        .find(|m| m.id.contains("SYNC-HAZARD-WRITE-AFTER-WRITE"))
        .unwrap_or_else(|| panic!("synchronization validation missed the hazard: {messages:?}"));
    assert_eq!(hazard.pass, "filter", "the message must name the pass it was raised in");
    drop((ring, image));
    assert_clean_shutdown(ctx);
}

#[test]
fn leaked_vulkan_object_is_reported_at_device_destruction() {
    let ctx = validated_context();
    let info = vk::SamplerCreateInfo::default();
    let _leaked = unsafe { ctx.device.raw.create_sampler(&info, None) }.unwrap();
    let report = ctx.shutdown();
    assert!(
        report.validation.iter().any(|m| m.text.contains("VkSampler") && m.pass == "device destruction"),
        "the leaked sampler was not reported: {report}"
    );
}

#[test]
fn leaked_allocation_is_reported() {
    let ctx = validated_context();
    let requirements = vk::MemoryRequirements { size: 4096, alignment: 256, memory_type_bits: !0 };
    let allocation = ctx
        .device
        .allocator()
        .allocate(&AllocationCreateDesc {
            name: "deliberately leaked",
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })
        .unwrap();
    std::mem::forget(allocation);
    let report = ctx.shutdown();
    assert_eq!(report.leaked_allocations.len(), 1, "{report}");
    assert!(report.leaked_allocations[0].contains("deliberately leaked"));
}

#[test]
fn resource_alive_at_shutdown_is_reported() {
    let ctx = validated_context();
    let buffer = Buffer::new(
        &ctx.device,
        "outlives its context",
        256,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuOnly,
    )
    .unwrap();
    let report = ctx.shutdown();
    assert_eq!(report.device_still_referenced, 1, "{report}");
    // The buffer still frees itself, and the device goes with it.
    drop(buffer);
}

#[test]
fn unknown_device_name_lists_the_available_ones() {
    let desc = ContextDesc { validation: true, device_name: Some("no-such-gpu-anywhere".into()), ..Default::default() };
    let err = Context::new(&desc).err().expect("an unknown device must be an error");
    let text = err.to_string();
    assert!(text.contains("no-such-gpu-anywhere") && text.contains("available:"), "{text}");
}
