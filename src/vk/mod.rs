//! The hand-written Vulkan backend, one file per concept.

pub mod barrier;
pub mod buffer;
pub mod commands;
pub mod descriptors;
pub mod device;
pub mod features;
pub mod image;
pub mod instance;
pub mod pipeline;
pub mod readback;
pub mod render_pass;
pub mod sampler;
pub mod statistics;
pub mod swapchain;
pub mod timing;
pub mod upload;
pub mod validation;

pub use ash::vk;
use std::sync::Arc;

use crate::error::Result;
use device::Device;
use instance::Instance;
use validation::ValidationMessage;

/// How to set up Vulkan.
#[derive(Clone, Debug, Default)]
pub struct ContextDesc {
    /// Enable the Khronos validation layer with synchronization validation.
    pub validation: bool,
    /// Pick the device whose name contains this (case-insensitive); else the best suitable.
    pub device_name: Option<String>,
    /// Instance extensions a window needs (surface extensions); empty when headless.
    pub instance_extensions: Vec<*const std::ffi::c_char>,
}

impl ContextDesc {
    /// Settings from the environment: `UNDERLIGHT_VALIDATION`, `UNDERLIGHT_DEVICE`.
    pub fn from_env() -> Self {
        Self {
            validation: instance::validation_requested_by_env(),
            device_name: std::env::var(device::DEVICE_ENV).ok().filter(|s| !s.is_empty()),
            instance_extensions: Vec::new(),
        }
    }
}

/// Instance plus device. Everything the renderer creates holds the `Arc<Device>`.
pub struct Context {
    pub device: Arc<Device>,
}

/// What tearing down a context found: every validation message of its lifetime not yet
/// taken, allocations never freed, and whether some object still held the device.
#[derive(Debug, Default)]
pub struct ShutdownReport {
    pub validation: Vec<ValidationMessage>,
    pub leaked_allocations: Vec<String>,
    /// Number of other owners of the device at shutdown (live buffers, images, passes…).
    pub device_still_referenced: usize,
}

impl ShutdownReport {
    pub fn is_clean(&self) -> bool {
        self.validation.is_empty() && self.leaked_allocations.is_empty() && self.device_still_referenced == 0
    }
}

impl std::fmt::Display for ShutdownReport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        for m in &self.validation {
            writeln!(f, "{m}")?;
        }
        for l in &self.leaked_allocations {
            writeln!(f, "leak: {l}")?;
        }
        if self.device_still_referenced > 0 {
            writeln!(f, "{} object(s) still held the device at shutdown", self.device_still_referenced)?;
        }
        Ok(())
    }
}

impl Context {
    pub fn new(desc: &ContextDesc) -> Result<Self> {
        let instance = Arc::new(Instance::new(desc.validation, &desc.instance_extensions)?);
        let devices = device::enumerate(&instance)?;
        let chosen = device::choose(&devices, desc.device_name.as_deref())?;
        // A window brings surface extensions; only then is the swapchain extension wanted.
        let swapchain = !desc.instance_extensions.is_empty();
        let device = Arc::new(Device::new(instance, chosen, swapchain)?);
        Ok(Self { device })
    }

    /// Validation messages recorded so far (removed from the log).
    pub fn take_validation_messages(&self) -> Vec<ValidationMessage> {
        self.device.instance.validation.take()
    }

    /// Destroys the device and instance and reports what the layers and the allocator found.
    /// Every object made from the device must have been dropped first.
    pub fn shutdown(self) -> ShutdownReport {
        let log = self.device.instance.validation.clone();
        let mut report = ShutdownReport::default();
        match Arc::try_unwrap(self.device) {
            // Dropping the device destroys it (the layer reports leaked objects, the
            // allocator reports leaked allocations), then the instance.
            Ok(device) => drop(device),
            Err(shared) => report.device_still_referenced = Arc::strong_count(&shared) - 1,
        }
        report.validation = log.take();
        report.leaked_allocations = log.take_leaks();
        report
    }
}
