//! Rust twin of `glsl/common.glsl`: the same formulas, for CPU tests and (later) the
//! reference renderer. Change both together.

use glam::{UVec2, Vec2};
use std::f32::consts::PI;

/// Largest per-axis photon subdivision one geometry-shader invocation emits (GLSL
/// `MAX_SUBDIVISION`; the geometry shader's `max_vertices` is its square).
pub const MAX_SUBDIVISION: u32 = 8;

/// See `photon_grid_uv` in common.glsl.
pub fn photon_grid_uv(cell: UVec2, sub: UVec2, subdiv: u32, grid: UVec2) -> Vec2 {
    (cell.as_vec2() + (sub.as_vec2() + 0.5) / subdiv as f32) / grid.as_vec2()
}

/// See `demo_wave_gradient` in common.glsl.
pub fn demo_wave_gradient(uv: Vec2, t: f32) -> Vec2 {
    let k1 = Vec2::new(7.0, 3.0) * 2.0 * PI;
    let k2 = Vec2::new(-4.0, 9.0) * 2.0 * PI;
    k1 * (k1.dot(uv) + 1.3 * t).cos() / k1.dot(k1) + k2 * (k2.dot(uv) + 0.9 * t).cos() / k2.dot(k2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_uv_tiles_unit_square_evenly() {
        // 3 cells × 2 sub-cells per axis = 6 photons per axis at (k + 0.5)/6.
        let grid = UVec2::splat(3);
        let mut xs: Vec<f32> = (0..3)
            .flat_map(|c| (0..2).map(move |s| photon_grid_uv(UVec2::new(c, 0), UVec2::new(s, 0), 2, grid).x))
            .collect();
        xs.sort_by(f32::total_cmp);
        for (k, x) in xs.iter().enumerate() {
            assert!((x - (k as f32 + 0.5) / 6.0).abs() < 1e-6, "{k}: {x}");
        }
    }

    #[test]
    fn wave_gradient_is_gradient_of_its_potential() {
        // Potential h = sin(k1·uv + a)/|k1|² + sin(k2·uv + b)/|k2|²; compare with finite differences.
        let h = |uv: Vec2, t: f32| {
            let k1 = Vec2::new(7.0, 3.0) * 2.0 * PI;
            let k2 = Vec2::new(-4.0, 9.0) * 2.0 * PI;
            (k1.dot(uv) + 1.3 * t).sin() / k1.dot(k1) + (k2.dot(uv) + 0.9 * t).sin() / k2.dot(k2)
        };
        let e = 1e-3;
        for &(x, y, t) in &[(0.1, 0.2, 0.0), (0.7, 0.4, 2.0), (0.33, 0.9, 5.5)] {
            let uv = Vec2::new(x, y);
            let fd = Vec2::new(
                (h(uv + Vec2::X * e, t) - h(uv - Vec2::X * e, t)) / (2.0 * e),
                (h(uv + Vec2::Y * e, t) - h(uv - Vec2::Y * e, t)) / (2.0 * e),
            );
            assert!((fd - demo_wave_gradient(uv, t)).length() < 1e-3, "{fd} vs {}", demo_wave_gradient(uv, t));
        }
    }
}
