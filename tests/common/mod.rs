//! Shared test harness: every GPU test runs on a real driver (lavapipe here) with the
//! Khronos validation layer and synchronization validation on, and fails on any validation
//! message, leaked Vulkan object or leaked allocation.
#![allow(dead_code)]

use glam::{Vec2, Vec3};
use underlight::scene::*;
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

pub const FLOOR_DEPTH: f32 = 2.0;

/// A square pool floor `FLOOR_DEPTH` below flat or wavy water, a camera under water looking
/// straight down at it, and a sun straight above.
pub fn pool(amplitude: f32) -> Scene {
    let half = 6.0;
    let floor = Mesh {
        name: "floor".into(),
        positions: vec![
            Vec3::new(-half, -FLOOR_DEPTH, -half),
            Vec3::new(half, -FLOOR_DEPTH, -half),
            Vec3::new(half, -FLOOR_DEPTH, half),
            Vec3::new(-half, -FLOOR_DEPTH, half),
        ],
        normals: vec![Vec3::Y; 4],
        indices: vec![0, 2, 1, 0, 3, 2],
        albedo: Vec3::splat(0.8),
    };
    Scene {
        name: "pool".into(),
        output: [96, 96],
        camera: Camera {
            position: Vec3::new(0.0, -0.5, 0.0),
            look_at: Vec3::new(0.0, -FLOOR_DEPTH, 0.0),
            fov_y_degrees: 60.0,
            z_near: 0.05,
            z_far: 10.0,
        },
        light: Light {
            kind: LightKind::Directional,
            direction: Vec3::NEG_Y,
            position: Vec3::ZERO,
            intensity: 9.2,
            distance: 100.0,
        },
        water: Water {
            model: WaterModel::AxisCosineNoise,
            level: 0.0,
            amplitude,
            wavelength: 0.8,
            speed: 0.5,
            noise_amplitude: 0.0,
            noise_scale: 4.0,
            center: Vec2::ZERO,
            extent_min: Vec2::splat(-half),
            extent_max: Vec2::splat(half),
            ior: 1.333,
        },
        medium: Medium { gamma: Vec3::splat(0.13), scattering: 0.05, hg_g: 0.5 },
        effects: Effects {
            caustic_grid: 160,
            caustic_subdivision: 2,
            caustic_target_scale: 1.0,
            point_size_min: 3.0,
            point_size_max: 12.0,
            shadow_map_size: 256,
            ..Effects::default()
        },
        meshes: vec![floor],
    }
}

/// An axis-aligned box mesh (outward normals) from `lo` to `hi`.
pub fn block(name: &str, lo: Vec3, hi: Vec3) -> Mesh {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut indices = Vec::new();
    for axis in 0..3 {
        for &side in &[0.0f32, 1.0] {
            let n = {
                let mut n = Vec3::ZERO;
                n[axis] = if side > 0.5 { 1.0 } else { -1.0 };
                n
            };
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let base = positions.len() as u32;
            for &(a, b) in &[(0.0f32, 0.0f32), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
                let mut p = Vec3::ZERO;
                p[axis] = if side > 0.5 { hi[axis] } else { lo[axis] };
                p[u] = if a > 0.5 { hi[u] } else { lo[u] };
                p[v] = if b > 0.5 { hi[v] } else { lo[v] };
                positions.push(p);
                normals.push(n);
            }
            // Counter-clockwise seen from outside.
            if side > 0.5 {
                indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
            } else {
                indices.extend([base, base + 2, base + 1, base, base + 3, base + 2]);
            }
        }
    }
    Mesh { name: name.into(), positions, normals, indices, albedo: Vec3::splat(0.5) }
}
