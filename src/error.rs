//! The renderer's error type. Small and typed inside the library; the CLI adds context with
//! `anyhow` at the edges.

use ash::vk;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("could not load the Vulkan loader (libvulkan.so.1): {0}. Install it with: apt-get install libvulkan1 mesa-vulkan-drivers")]
    Loader(String),

    #[error("validation was requested but the layer {layer} is not installed. Install it with: apt-get install vulkan-validationlayers")]
    ValidationLayerMissing { layer: &'static str },

    #[error("no Vulkan device found. Install a driver, e.g. apt-get install mesa-vulkan-drivers (lavapipe)")]
    NoDevice,

    #[error("no Vulkan device named like {wanted:?}; available: {available}")]
    DeviceNotFound { wanted: String, available: String },

    #[error("device {device:?} lacks required feature(s): {}", missing.join(", "))]
    MissingFeatures { device: String, missing: Vec<&'static str> },

    #[error("no suitable Vulkan device: {}", reasons.join("; "))]
    NoSuitableDevice { reasons: Vec<String> },

    #[error("{call} failed: {result}")]
    Vk { call: &'static str, result: vk::Result },

    #[error("GPU memory allocation for {name:?} failed: {source}")]
    Alloc { name: String, source: gpu_allocator::AllocationError },

    #[error("no embedded SPIR-V named {0:?}: run `underlight shaders` and rebuild")]
    MissingShader(String),

    #[error("the window is {width}×{height} pixels, and the device could not allocate a swapchain that size ({result}): make the window smaller")]
    WindowTooLarge { width: u32, height: u32, result: vk::Result },

    #[error("invalid parameter {name}: {message}")]
    InvalidParameter { name: &'static str, message: String },
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Adds the name of the Vulkan call to a `vk::Result`, so an error says what failed.
pub trait VkResultExt<T> {
    fn call(self, call: &'static str) -> Result<T>;
}

impl<T> VkResultExt<T> for std::result::Result<T, vk::Result> {
    fn call(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vk { call, result })
    }
}
