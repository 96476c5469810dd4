//! The GPU frame's camera in f64: pixel (x, y) of a target W×H is the pinhole ray through
//! the pixel's centre of the frame's `camera_view_proj` (Vulkan clip space, y down), so the
//! reference's pixels are the GPU's pixels.

use crate::frame::uniforms::{FrameExtents, FrameUniforms};
use crate::scene::Scene;
use glam::{DMat4, DVec2, DVec3, DVec4, Mat4};

pub struct PixelCamera {
    pub position: DVec3,
    view_proj: DMat4,
    inverse: DMat4,
    pub z_near: f64,
    pub z_far: f64,
}

impl PixelCamera {
    pub fn new(scene: &Scene, extents: &FrameExtents, time: f32) -> Self {
        // The very matrix the GPU frame uploads (aspect from the output size).
        let u = FrameUniforms::new(scene, scene.bounds(), extents, time);
        let view_proj = Mat4::from_cols_array_2d(&u.camera_view_proj).as_dmat4();
        Self {
            position: scene.camera.position.as_dvec3(),
            view_proj,
            inverse: view_proj.inverse(),
            z_near: scene.camera.z_near as f64,
            z_far: scene.camera.z_far as f64,
        }
    }

    /// Unit direction of the ray through normalised device coordinates `ndc`.
    pub fn ray(&self, ndc: DVec2) -> DVec3 {
        let far = self.inverse * DVec4::new(ndc.x, ndc.y, 1.0, 1.0);
        (far.truncate() / far.w - self.position).normalize()
    }

    /// NDC of pixel corner or centre `(x, y)` (in pixels) of a `size` target.
    pub fn ndc(p: DVec2, size: [u32; 2]) -> DVec2 {
        p / DVec2::new(size[0] as f64, size[1] as f64) * 2.0 - 1.0
    }

    /// The ray through the centre of pixel (x, y).
    pub fn pixel_ray(&self, x: u32, y: u32, size: [u32; 2]) -> DVec3 {
        self.ray(Self::ndc(DVec2::new(x as f64 + 0.5, y as f64 + 0.5), size))
    }

    pub fn clip(&self, p: DVec3) -> DVec4 {
        self.view_proj * p.extend(1.0)
    }

    /// View depth (distance along the camera axis) per unit of travel along `d`.
    pub fn depth_rate(&self, d: DVec3) -> f64 {
        self.view_proj.row(3).truncate().dot(d)
    }

    /// The pixel `p` projects into, when it lies in the depth range (the GPU's splat culling).
    pub fn pixel_of(&self, p: DVec3, size: [u32; 2]) -> Option<(u32, u32)> {
        let c = self.clip(p);
        if !(c.w > 0.0) || c.z < 0.0 || c.z > c.w {
            return None;
        }
        let f = (DVec2::new(c.x, c.y) / c.w + 1.0) * 0.5 * DVec2::new(size[0] as f64, size[1] as f64);
        let (x, y) = (f.x.floor(), f.y.floor());
        (x >= 0.0 && y >= 0.0 && x < size[0] as f64 && y < size[1] as f64).then_some((x as u32, y as u32))
    }

    /// Exact solid angle of pixel (x, y), sr: the spherical quadrilateral of its corner rays,
    /// as two triangles (Van Oosterom & Strackee's formula).
    pub fn pixel_solid_angle(&self, x: u32, y: u32, size: [u32; 2]) -> f64 {
        let corner = |dx: u32, dy: u32| self.ray(Self::ndc(DVec2::new((x + dx) as f64, (y + dy) as f64), size));
        let (a, b, c, d) = (corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1));
        let tri =
            |a: DVec3, b: DVec3, c: DVec3| 2.0 * a.dot(b.cross(c)).abs().atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a));
        tri(a, b, c) + tri(a, c, d)
    }

    /// The view frustum's four side planes as (unit inward normal, offset): a point p is
    /// inside when `n·p + offset ≥ 0`, and `n·p + offset` is its signed distance.
    pub fn side_planes(&self) -> [(DVec3, f64); 4] {
        let m = &self.view_proj;
        let (r0, r1, r3) = (m.row(0), m.row(1), m.row(3));
        [r3 - r0, r3 + r0, r3 - r1, r3 + r1].map(|p| {
            let len = p.truncate().length();
            (p.truncate() / len, p.w / len)
        })
    }
}
