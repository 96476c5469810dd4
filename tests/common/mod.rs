//! Shared test harness: every GPU test runs on a real driver (lavapipe here) with the
//! Khronos validation layer and synchronization validation on, and fails on any validation
//! message, leaked Vulkan object or leaked allocation.
#![allow(dead_code)]

use underlight::vk::{Context, ContextDesc, ShutdownReport};

/// A context with validation on. `UNDERLIGHT_DEVICE` still picks the device.
pub fn validated_context() -> Context {
    let mut desc = ContextDesc::from_env();
    desc.validation = true;
    match Context::new(&desc) {
        Ok(c) => c,
        Err(e) => panic!("creating a validated Vulkan context failed: {e}"),
    }
}

/// Tears the context down and fails the test on any validation message (with its pass),
/// leaked object or leaked allocation.
pub fn assert_clean_shutdown(ctx: Context) {
    let report = ctx.shutdown();
    assert_clean(&report);
}

pub fn assert_clean(report: &ShutdownReport) {
    assert!(
        report.is_clean(),
        "Vulkan teardown is not clean ({} validation message(s), {} leaked allocation(s)):\n{report}",
        report.validation.len(),
        report.leaked_allocations.len()
    );
}
