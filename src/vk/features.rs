//! What a device must offer for the method, checked before anything is created, so a user with
//! an unsuitable device gets the name of the missing feature instead of a crash later.

use ash::vk;

/// The facts about a physical device that decide whether underlight can run on it.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeviceCapabilities {
    pub features: vk::PhysicalDeviceFeatures,
    pub synchronization2: bool,
    /// `timestampValidBits` of the graphics queue family; `None` when there is no graphics queue.
    pub graphics_timestamp_valid_bits: Option<u32>,
    pub timestamp_period: f32,
    /// VK_EXT_shader_atomic_float's `shaderBufferFloat32AtomicAdd`: optional, used only by the
    /// compute photon path (splats added with float atomics), measured against the others.
    pub buffer_float_atomic_add: bool,
}

/// Names of the required features the device lacks, in a fixed order; empty when suitable.
///
/// - `geometryShader`: the photon grid is subdivided by a geometry shader (the method's core).
/// - `shaderTessellationAndGeometryPointSize`: that shader writes `gl_PointSize` per photon.
/// - `largePoints`: caustic splats are 2–20 px points.
/// - `wideLines`: godrays are lines up to 12 px wide.
/// - `synchronization2`: all barriers are recorded with `vkCmdPipelineBarrier2`.
/// - `graphicsQueue` / `timestamps`: every pass is timed with timestamp queries.
pub fn missing_features(caps: &DeviceCapabilities) -> Vec<&'static str> {
    let f = &caps.features;
    let mut missing = Vec::new();
    let checks = [
        (f.geometry_shader, "geometryShader"),
        (f.shader_tessellation_and_geometry_point_size, "shaderTessellationAndGeometryPointSize"),
        (f.large_points, "largePoints"),
        (f.wide_lines, "wideLines"),
        // The refraction and reflection passes cut the scene at the water with a clip plane.
        (f.shader_clip_distance, "shaderClipDistance"),
        (caps.synchronization2 as vk::Bool32, "synchronization2"),
    ];
    for (have, name) in checks {
        if have == vk::FALSE {
            missing.push(name);
        }
    }
    match caps.graphics_timestamp_valid_bits {
        None => missing.push("graphicsQueue"),
        Some(0) => missing.push("timestamps (timestampValidBits = 0 on the graphics queue)"),
        Some(_) if caps.timestamp_period <= 0.0 => missing.push("timestamps (timestampPeriod = 0)"),
        Some(_) => {}
    }
    missing
}

#[cfg(test)]
mod tests {
    use super::*;

    fn complete() -> DeviceCapabilities {
        DeviceCapabilities {
            features: vk::PhysicalDeviceFeatures {
                geometry_shader: vk::TRUE,
                shader_tessellation_and_geometry_point_size: vk::TRUE,
                large_points: vk::TRUE,
                wide_lines: vk::TRUE,
                shader_clip_distance: vk::TRUE,
                ..Default::default()
            },
            synchronization2: true,
            graphics_timestamp_valid_bits: Some(64),
            timestamp_period: 1.0,
            buffer_float_atomic_add: false,
        }
    }

    #[test]
    fn complete_device_passes() {
        assert!(missing_features(&complete()).is_empty());
    }

    #[test]
    fn each_missing_feature_is_named() {
        let mut c = complete();
        c.features.geometry_shader = vk::FALSE;
        assert_eq!(missing_features(&c), vec!["geometryShader"]);

        let mut c = complete();
        c.features.wide_lines = vk::FALSE;
        c.features.large_points = vk::FALSE;
        assert_eq!(missing_features(&c), vec!["largePoints", "wideLines"]);

        let mut c = complete();
        c.features.shader_tessellation_and_geometry_point_size = vk::FALSE;
        assert_eq!(missing_features(&c), vec!["shaderTessellationAndGeometryPointSize"]);

        let mut c = complete();
        c.graphics_timestamp_valid_bits = Some(0);
        assert!(missing_features(&c)[0].starts_with("timestamps"));

        let mut c = complete();
        c.timestamp_period = 0.0;
        assert!(missing_features(&c)[0].starts_with("timestamps"));

        let mut c = complete();
        c.graphics_timestamp_valid_bits = None;
        assert_eq!(missing_features(&c), vec!["graphicsQueue"]);
    }
}
