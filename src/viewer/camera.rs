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
    /// The scene's own position and look-at, applied as they are until the camera first moves
    /// or turns: yaw and pitch give the same view direction only to within rounding, and a
    /// photon survey ray that the rounding moves across a silhouette or a shadow's edge moves
    /// the warp's knots, and with them every photon. Before the survey's side test and its
    /// shared deposit (`frame::photon_density`) any rounding could: the viewer drew a caustic
    /// sampled anew, 4.1 % of its channels off by more than 8 from `render`'s frame (mean
    /// 1.07 / 255, `tests/viewer.rs`). Since, without this, 0.23 % of them are (mean 0.07): the
    /// survey is continuous but for such rays, so the first frame still needs the scene's own
    /// camera to be `render`'s.
    unmoved: Option<(Vec3, Vec3)>,
}

const PITCH_LIMIT: f32 = 1.55;

impl FlyCamera {
    pub fn from_camera(c: &Camera) -> Self {
        let d = (c.look_at - c.position).normalize_or(Vec3::X);
        Self {
            position: c.position,
            yaw: d.z.atan2(d.x),
            pitch: d.y.clamp(-1.0, 1.0).asin(),
            unmoved: Some((c.position, c.look_at)),
        }
    }

    pub fn forward(&self) -> Vec3 {
        Vec3::new(self.pitch.cos() * self.yaw.cos(), self.pitch.sin(), self.pitch.cos() * self.yaw.sin())
    }

    /// Moves by metres along the view's right, world up, and forward.
    pub fn translate(&mut self, right: f32, up: f32, forward: f32) {
        let f = self.forward();
        let r = f.cross(Vec3::Y).normalize_or(Vec3::X);
        if right != 0.0 || up != 0.0 || forward != 0.0 {
            self.unmoved = None;
        }
        self.position += r * right + Vec3::Y * up + f * forward;
    }

    /// Turns by radians.
    pub fn turn(&mut self, yaw: f32, pitch: f32) {
        if yaw != 0.0 || pitch != 0.0 {
            self.unmoved = None;
        }
        self.yaw += yaw;
        self.pitch = (self.pitch + pitch).clamp(-PITCH_LIMIT, PITCH_LIMIT);
    }

    /// Writes position and look-at into the scene's camera (field of view and planes stay).
    pub fn apply(&self, c: &mut Camera) {
        (c.position, c.look_at) = self.unmoved.unwrap_or((self.position, self.position + self.forward()));
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
        // Unmoved, the scene's camera exactly, however yaw and pitch round.
        fly.translate(0.0, 0.0, 0.0);
        fly.turn(0.0, 0.0);
        fly.apply(&mut out);
        assert_eq!((out.position, out.look_at), (c.position, c.look_at));
        let want = (c.look_at - c.position).normalize();
        assert!((fly.forward() - want).length() < 1e-5);
        fly.translate(0.0, 0.0, 2.0);
        assert!((fly.position - (c.position + 2.0 * want)).length() < 1e-5);
        fly.apply(&mut out);
        assert!(((out.look_at - out.position) - want).length() < 1e-5);
        fly.turn(0.0, 10.0);
        assert!(fly.pitch <= PITCH_LIMIT);
    }
}
