//! The Vulkan instance: loader, optional Khronos validation with synchronization validation,
//! and a debug-utils messenger that records every warning and error.

use super::validation::{messenger_callback, ValidationLog};
use crate::error::{Error, Result, VkResultExt};
use ash::vk;
use std::ffi::{c_char, CStr};

pub const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Environment variable that turns validation on for any command (`1`/`true`/`on`).
pub const VALIDATION_ENV: &str = "UNDERLIGHT_VALIDATION";

/// Whether `UNDERLIGHT_VALIDATION` asks for validation.
pub fn validation_requested_by_env() -> bool {
    std::env::var(VALIDATION_ENV)
        .map(|v| matches!(v.to_ascii_lowercase().as_str(), "1" | "true" | "on" | "yes"))
        .unwrap_or(false)
}

pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    /// Present when VK_EXT_debug_utils is enabled (always with validation; otherwise when the
    /// loader offers it), for object names and pass labels.
    pub debug_utils: Option<ash::ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    pub validation: ValidationLog,
    pub validation_enabled: bool,
}

impl Instance {
    /// Creates the instance. `extra_extensions` are instance extensions the caller needs
    /// (e.g. surface extensions for a window).
    pub fn new(validation: bool, extra_extensions: &[*const c_char]) -> Result<Self> {
        // SAFETY: loading the system Vulkan loader; no other Vulkan state exists yet.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))?;

        let available_layers =
            unsafe { entry.enumerate_instance_layer_properties() }.call("vkEnumerateInstanceLayerProperties")?;
        if validation
            && !available_layers.iter().any(|l| l.layer_name_as_c_str().map(|n| n == VALIDATION_LAYER).unwrap_or(false))
        {
            return Err(Error::ValidationLayerMissing { layer: "VK_LAYER_KHRONOS_validation" });
        }
        let available_exts = unsafe { entry.enumerate_instance_extension_properties(None) }
            .call("vkEnumerateInstanceExtensionProperties")?;
        let has_debug_utils = available_exts
            .iter()
            .any(|e| e.extension_name_as_c_str().map(|n| n == ash::ext::debug_utils::NAME).unwrap_or(false));
        // The validation layer itself provides debug_utils, so with validation it is always there.
        let use_debug_utils = validation || has_debug_utils;

        let mut extensions: Vec<*const c_char> = extra_extensions.to_vec();
        if use_debug_utils {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        let layers: Vec<*const c_char> = if validation { vec![VALIDATION_LAYER.as_ptr()] } else { vec![] };

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"underlight")
            .application_version(vk::make_api_version(0, 0, 1, 0))
            .engine_name(c"underlight")
            .api_version(vk::API_VERSION_1_3);

        let log = ValidationLog::new();
        let mut messenger_info = messenger_create_info(&log);
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);

        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if use_debug_utils {
            // Chained so that instance creation and destruction are covered too.
            create_info = create_info.push_next(&mut messenger_info);
        }
        if validation {
            create_info = create_info.push_next(&mut validation_features);
        }

        // SAFETY: every pointer in create_info refers to locals alive for this call.
        let raw = unsafe { entry.create_instance(&create_info, None) }.call("vkCreateInstance")?;

        let (debug_utils, messenger) = if use_debug_utils {
            let du = ash::ext::debug_utils::Instance::new(&entry, &raw);
            let info = messenger_create_info(&log);
            match unsafe { du.create_debug_utils_messenger(&info, None) } {
                Ok(m) => (Some(du), m),
                Err(e) => {
                    unsafe { raw.destroy_instance(None) };
                    return Err(Error::Vk { call: "vkCreateDebugUtilsMessengerEXT", result: e });
                }
            }
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };

        Ok(Self { entry, raw, debug_utils, messenger, validation: log, validation_enabled: validation })
    }
}

fn messenger_create_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(messenger_callback))
        .user_data(log.as_user_data())
}

impl Drop for Instance {
    fn drop(&mut self) {
        self.validation.set_phase("instance destruction");
        // SAFETY: the device (and everything made from it) is destroyed before the instance:
        // `Context` drops its `Device` first.
        unsafe {
            if let Some(du) = &self.debug_utils {
                du.destroy_debug_utils_messenger(self.messenger, None);
            }
            self.raw.destroy_instance(None);
        }
    }
}
