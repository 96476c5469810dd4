//! Fly camera: position plus yaw/pitch, applied to the scene's look-at camera.

use crate::scene::Camera;
use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct FlyCamera {
    pub position: Vec3,
    /// Radians; 0 looks along +x, positive turns towards +z.
    pub yaw: f32,
    /// Radians, clamped short of straight up/down.
    pub pitch: f32,
}

const PITCH_LIMIT: f32 = 1.55;

impl FlyCamera {
    pub fn from_camera(c: &Camera) -> Self {
        let d = (c.look_at - c.position).normalize_or(Vec3::X);
        Self { position: c.position, yaw: d.z.atan2(d.x), pitch: d.y.clamp(-1.0, 1.0).asin() }
    }

    pub fn forward(&self) -> Vec3 {
        Vec3::new(self.pitch.cos() * self.yaw.cos(), self.pitch.sin(), self.pitch.cos() * self.yaw.sin())
    }

    /// Moves by metres along the view's right, world up, and forward.
    pub fn translate(&mut self, right: f32, up: f32, forward: f32) {
        let f = self.forward();
        let r = f.cross(Vec3::Y).normalize_or(Vec3::X);
        self.position += r * right + Vec3::Y * up + f * forward;
    }

    /// Turns by radians.
    pub fn turn(&mut self, yaw: f32, pitch: f32) {
        self.yaw += yaw;
        self.pitch = (self.pitch + pitch).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Writes position and look-at into the scene's camera (field of view and planes stay).
    pub fn apply(&self, c: &mut Camera) {
        c.position = self.position;
        c.look_at = self.position + self.forward();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_a_camera_and_moves_along_its_view() {
        let c = Camera {
            position: Vec3::new(1.0, -1.0, 2.0),
            look_at: Vec3::new(2.0, -1.5, 1.0),
            fov_y_degrees: 60.0,
            z_near: 0.1,
            z_far: 50.0,
        };
        let mut fly = FlyCamera::from_camera(&c);
        let mut out = c;
        fly.apply(&mut out);
        let want = (c.look_at - c.position).normalize();
        assert!(((out.look_at - out.position) - want).length() < 1e-5);
        fly.translate(0.0, 0.0, 2.0);
        assert!((fly.position - (c.position + 2.0 * want)).length() < 1e-5);
        fly.turn(0.0, 10.0);
        assert!(fly.pitch <= PITCH_LIMIT);
    }
}
