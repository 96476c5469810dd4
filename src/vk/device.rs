//! Physical-device choice and the logical device: one graphics queue, the gpu-allocator
//! instance every resource draws from, and debug names/labels.

use super::features::{missing_features, DeviceCapabilities};
use super::instance::Instance;
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use std::ffi::{CStr, CString};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex, MutexGuard};

/// Environment variable that picks a device by (case-insensitive) substring of its name.
pub const DEVICE_ENV: &str = "UNDERLIGHT_DEVICE";

/// A physical device and what we learned about it while choosing.
#[derive(Clone)]
pub struct PhysicalDeviceInfo {
    pub handle: vk::PhysicalDevice,
    pub name: String,
    pub device_type: vk::PhysicalDeviceType,
    pub driver_name: String,
    pub driver_info: String,
    pub api_version: u32,
    pub properties: vk::PhysicalDeviceProperties,
    pub capabilities: DeviceCapabilities,
    pub graphics_queue_family: Option<u32>,
}

impl PhysicalDeviceInfo {
    /// Preference when no name is given: a discrete GPU first, a CPU rasterizer last.
    fn rank(&self) -> u32 {
        match self.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        }
    }

    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, Vulkan {}.{}.{}, driver {} {})",
            self.name,
            self.device_type,
            vk::api_version_major(self.api_version),
            vk::api_version_minor(self.api_version),
            vk::api_version_patch(self.api_version),
            self.driver_name,
            self.driver_info
        )
    }
}

/// Lists every physical device with its capabilities.
pub fn enumerate(instance: &Instance) -> Result<Vec<PhysicalDeviceInfo>> {
    let raw = &instance.raw;
    let handles = unsafe { raw.enumerate_physical_devices() }.call("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::with_capacity(handles.len());
    for handle in handles {
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
        unsafe { raw.get_physical_device_properties2(handle, &mut props2) };
        let properties = props2.properties;
        let extensions = unsafe { raw.enumerate_device_extension_properties(handle) }
            .call("vkEnumerateDeviceExtensionProperties")?;
        let has_atomic_float =
            extensions.iter().any(|e| e.extension_name_as_c_str() == Ok(ash::ext::shader_atomic_float::NAME));
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let mut atomic_float = vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default();
        let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
        // Chained only when the device has the extension (querying an unknown struct is invalid).
        if has_atomic_float {
            f2 = f2.push_next(&mut atomic_float);
        }
        unsafe { raw.get_physical_device_features2(handle, &mut f2) };
        let features = f2.features;
        let buffer_float_atomic_add = has_atomic_float && atomic_float.shader_buffer_float32_atomic_add == vk::TRUE;
        let queues = unsafe { raw.get_physical_device_queue_family_properties(handle) };
        let graphics = queues.iter().position(|q| q.queue_flags.contains(vk::QueueFlags::GRAPHICS));
        let cstr = |s: &[std::ffi::c_char]| {
            // SAFETY: Vulkan guarantees these fixed arrays are NUL-terminated.
            unsafe { CStr::from_ptr(s.as_ptr()) }.to_string_lossy().into_owned()
        };
        out.push(PhysicalDeviceInfo {
            handle,
            name: cstr(&properties.device_name),
            device_type: properties.device_type,
            driver_name: cstr(&driver.driver_name),
            driver_info: cstr(&driver.driver_info),
            api_version: properties.api_version,
            properties,
            capabilities: DeviceCapabilities {
                features,
                synchronization2: f13.synchronization2 == vk::TRUE && properties.api_version >= vk::API_VERSION_1_3,
                graphics_timestamp_valid_bits: graphics.map(|i| queues[i].timestamp_valid_bits),
                timestamp_period: properties.limits.timestamp_period,
                buffer_float_atomic_add,
            },
            graphics_queue_family: graphics.map(|i| i as u32),
        });
    }
    Ok(out)
}

/// Picks the device: the one whose name contains `wanted` (case-insensitive) if given, else
/// the best-ranked suitable one. A named device that lacks a feature is an error naming it.
pub fn choose(devices: &[PhysicalDeviceInfo], wanted: Option<&str>) -> Result<PhysicalDeviceInfo> {
    if devices.is_empty() {
        return Err(Error::NoDevice);
    }
    if let Some(wanted) = wanted {
        let w = wanted.to_lowercase();
        let dev = devices.iter().find(|d| d.name.to_lowercase().contains(&w)).ok_or_else(|| Error::DeviceNotFound {
            wanted: wanted.to_string(),
            available: devices.iter().map(|d| d.name.clone()).collect::<Vec<_>>().join(", "),
        })?;
        let missing = missing_features(&dev.capabilities);
        if !missing.is_empty() {
            return Err(Error::MissingFeatures { device: dev.name.clone(), missing });
        }
        return Ok(dev.clone());
    }
    let mut suitable: Vec<&PhysicalDeviceInfo> =
        devices.iter().filter(|d| missing_features(&d.capabilities).is_empty()).collect();
    suitable.sort_by_key(|d| d.rank());
    match suitable.first() {
        Some(d) => Ok((*d).clone()),
        None => Err(Error::NoSuitableDevice {
            reasons: devices
                .iter()
                .map(|d| format!("{} lacks {}", d.name, missing_features(&d.capabilities).join(", ")))
                .collect(),
        }),
    }
}

/// The logical device. Shared (`Arc`) by every resource made from it, so it is destroyed
/// only after the last of them; it in turn keeps the instance alive.
pub struct Device {
    pub raw: ash::Device,
    pub info: PhysicalDeviceInfo,
    pub queue: vk::Queue,
    pub queue_family: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    pub debug_utils: Option<ash::ext::debug_utils::Device>,
    /// Declared last: dropped after the device is destroyed.
    pub instance: Arc<Instance>,
}

impl Device {
    /// `swapchain`: enable VK_KHR_swapchain (only when the instance has surface extensions).
    pub fn new(instance: Arc<Instance>, info: PhysicalDeviceInfo, swapchain: bool) -> Result<Self> {
        let queue_family = info.graphics_queue_family.ok_or(Error::NoDevice)?;
        let priorities = [1.0f32];
        let queue_infos =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let features = vk::PhysicalDeviceFeatures {
            geometry_shader: vk::TRUE,
            shader_tessellation_and_geometry_point_size: vk::TRUE,
            large_points: vk::TRUE,
            wide_lines: vk::TRUE,
            shader_clip_distance: vk::TRUE,
            // Optional: lets the caustics pass record every photon for tests and debugging.
            vertex_pipeline_stores_and_atomics: info.capabilities.features.vertex_pipeline_stores_and_atomics,
            // Optional: per-pass counts of each stage's work, where a mode asks for them
            // (`bench` and `render --pipeline-statistics`).
            pipeline_statistics_query: info.capabilities.features.pipeline_statistics_query,
            ..Default::default()
        };
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true);
        let mut f2 = vk::PhysicalDeviceFeatures2::default().features(features).push_next(&mut f13);
        // Optional: float atomics for the compute photon path, enabled where offered.
        let mut atomic_float =
            vk::PhysicalDeviceShaderAtomicFloatFeaturesEXT::default().shader_buffer_float32_atomic_add(true);
        let mut enabled = Vec::new();
        if swapchain {
            enabled.push(ash::khr::swapchain::NAME.as_ptr());
        }
        if info.capabilities.buffer_float_atomic_add {
            enabled.push(ash::ext::shader_atomic_float::NAME.as_ptr());
            f2 = f2.push_next(&mut atomic_float);
        }
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_infos)
            .enabled_extension_names(&enabled)
            .push_next(&mut f2);
        instance.validation.set_phase("device creation");
        // SAFETY: the physical device comes from this instance; create_info points at locals.
        let raw = unsafe { instance.raw.create_device(info.handle, &create_info, None) }.call("vkCreateDevice")?;
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.raw.clone(),
            device: raw.clone(),
            physical_device: info.handle,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(source) => {
                unsafe { raw.destroy_device(None) };
                return Err(Error::Alloc { name: "allocator".into(), source });
            }
        };
        let debug_utils =
            instance.debug_utils.as_ref().map(|_| ash::ext::debug_utils::Device::new(&instance.raw, &raw));
        instance.validation.set_phase("setup");
        let device = Self {
            raw,
            info,
            queue,
            queue_family,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            debug_utils,
            instance,
        };
        device.set_name(device.queue, "graphics queue");
        Ok(device)
    }

    /// Whether geometry shaders may write storage buffers (the photon debug records).
    pub fn has_pipeline_stores(&self) -> bool {
        self.info.capabilities.features.vertex_pipeline_stores_and_atomics == vk::TRUE
    }

    /// Whether passes can count their stages' work with pipeline-statistics queries.
    pub fn has_pipeline_statistics(&self) -> bool {
        self.info.capabilities.features.pipeline_statistics_query == vk::TRUE
    }

    /// Whether shaders may add floats atomically into storage buffers (the compute photon path).
    pub fn has_float_atomics(&self) -> bool {
        self.info.capabilities.buffer_float_atomic_add
    }

    pub fn limits(&self) -> &vk::PhysicalDeviceLimits {
        &self.info.properties.limits
    }

    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Names a Vulkan object so validation messages and GPU debuggers say what it is.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if let Some(du) = &self.debug_utils {
            let Ok(name) = CString::new(name) else { return };
            let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
            // SAFETY: the handle belongs to this device. Naming is best-effort.
            let _ = unsafe { du.set_debug_utils_object_name(&info) };
        }
    }

    /// Opens a labelled region in a command buffer (shown by validation and debuggers).
    pub fn begin_label(&self, cmd: vk::CommandBuffer, label: &CStr) {
        if let Some(du) = &self.debug_utils {
            let info = vk::DebugUtilsLabelEXT::default().label_name(label);
            unsafe { du.cmd_begin_debug_utils_label(cmd, &info) };
        }
    }

    pub fn end_label(&self, cmd: vk::CommandBuffer) {
        if let Some(du) = &self.debug_utils {
            unsafe { du.cmd_end_debug_utils_label(cmd) };
        }
    }

    /// Declares the renderer's current phase, blamed for validation messages raised outside
    /// any command-buffer label.
    pub fn set_phase(&self, phase: &str) {
        self.instance.validation.set_phase(phase);
    }

    pub fn wait_idle(&self) -> Result<()> {
        unsafe { self.raw.device_wait_idle() }.call("vkDeviceWaitIdle")
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        let log = &self.instance.validation;
        log.set_phase("device destruction");
        // SAFETY: nothing else holds the device (this is its last Arc); waiting idle makes
        // sure no submitted work still uses it.
        unsafe {
            let _ = self.raw.device_wait_idle();
            let allocator = ManuallyDrop::take(&mut self.allocator);
            let report = allocator.lock().unwrap_or_else(|p| p.into_inner()).generate_report();
            for a in &report.allocations {
                log.record_leak(format!("GPU allocation {:?} ({} bytes) was never freed", a.name, a.size));
            }
            drop(allocator);
            // The validation layer reports every object of this device not yet destroyed.
            self.raw.destroy_device(None);
        }
    }
}
