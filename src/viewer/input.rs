//! Keys and mouse: held keys fly the camera, right-drag turns it, and single keys change the
//! scene's settings (the same changes script steps make).

use super::camera::FlyCamera;
use super::script::{Effect, Preset};
use super::{Live, View};
use crate::scene::WaterModel;
use anyhow::Result;
use std::path::PathBuf;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::KeyCode;

/// Printed when the window opens.
pub(super) const KEYS_HELP: &str =
    "keys: WASD/QE move (Shift faster), right-drag or arrows look, 1/2/3 caustics/godrays/filter, \
     4 caustic estimator, 5/6 caustic photon / godray beam density, 7 godray method, \
     M water model, +/- amplitude, P pause, N step, H/L high/default preset, R reset camera, \
     I settings, F12 screenshot, Esc quit";

/// Radians the camera turns per pixel the cursor moves while looking.
const LOOK_PER_PIXEL: f32 = 0.004;

/// What the keyboard and mouse hold between events.
pub(super) struct Input {
    /// Keys held down, in the order they were pressed; `fly` moves by each.
    keys_down: Vec<KeyCode>,
    /// The right button is held: cursor motion turns the camera.
    looking: bool,
    /// Where the cursor was at its last motion while looking.
    cursor: Option<(f64, f64)>,
}

impl Input {
    pub(super) fn new() -> Self {
        Self { keys_down: Vec::new(), looking: false, cursor: None }
    }

    /// The right button went down (start looking) or up (stop).
    pub(super) fn look(&mut self, pressed: bool) {
        self.looking = pressed;
        self.cursor = None;
    }

    /// Turns the camera by the cursor's motion since its last position, while looking.
    pub(super) fn cursor_moved(&mut self, x: f64, y: f64, camera: &mut FlyCamera) {
        if self.looking {
            if let Some((last_x, last_y)) = self.cursor {
                let k = LOOK_PER_PIXEL;
                camera.turn((x - last_x) as f32 * k, -(y - last_y) as f32 * k);
            }
            self.cursor = Some((x, y));
        }
    }

    /// Moves the camera by the keys held, scaled by the time since the last frame.
    pub(super) fn fly(&self, camera: &mut FlyCamera, dt: f32) {
        let fast = self.keys_down.iter().any(|k| matches!(k, KeyCode::ShiftLeft | KeyCode::ShiftRight));
        let speed = if fast { 4.0 } else { 1.0 } * dt;
        let turn = 1.2 * dt;
        for key in &self.keys_down {
            match key {
                KeyCode::KeyW => camera.translate(0.0, 0.0, speed),
                KeyCode::KeyS => camera.translate(0.0, 0.0, -speed),
                KeyCode::KeyD => camera.translate(speed, 0.0, 0.0),
                KeyCode::KeyA => camera.translate(-speed, 0.0, 0.0),
                KeyCode::KeyE => camera.translate(0.0, speed, 0.0),
                KeyCode::KeyQ => camera.translate(0.0, -speed, 0.0),
                KeyCode::ArrowLeft => camera.turn(-turn, 0.0),
                KeyCode::ArrowRight => camera.turn(turn, 0.0),
                KeyCode::ArrowUp => camera.turn(0.0, turn),
                KeyCode::ArrowDown => camera.turn(0.0, -turn),
                _ => {}
            }
        }
    }
}

impl Live {
    /// A key went down or up. Keys that change something act on every press, the window
    /// system's repeats of a held key included.
    pub(super) fn key(&mut self, code: KeyCode, pressed: bool, event_loop: &ActiveEventLoop) -> Result<()> {
        let keys_down = &mut self.input.keys_down;
        if !pressed {
            keys_down.retain(|k| *k != code);
            return Ok(());
        }
        if !keys_down.contains(&code) {
            keys_down.push(code);
        }
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::Digit1 => self.toggle(Effect::Caustics)?,
            KeyCode::Digit2 => self.toggle(Effect::Godrays)?,
            KeyCode::Digit3 => self.toggle(Effect::Filter)?,
            KeyCode::Digit4 => self.next_estimator()?,
            KeyCode::Digit5 => self.next_photon_density(false)?,
            KeyCode::Digit6 => self.next_photon_density(true)?,
            KeyCode::Digit7 => self.next_godray_method()?,
            KeyCode::KeyM => self.next_water()?,
            KeyCode::Equal | KeyCode::NumpadAdd => self.scale_amplitude(1.25)?,
            KeyCode::Minus | KeyCode::NumpadSubtract => self.scale_amplitude(0.8)?,
            KeyCode::KeyP => self.view.paused = !self.view.paused,
            KeyCode::KeyN => self.view.step_once = true,
            KeyCode::KeyH => self.preset(Preset::High)?,
            KeyCode::KeyL => self.preset(Preset::Default)?,
            KeyCode::KeyR => self.view.camera = FlyCamera::from_camera(&self.view.loaded.camera),
            KeyCode::KeyI => self.view.print_settings(),
            KeyCode::F12 => {
                self.pending_screenshot = Some(PathBuf::from(format!("out/screenshot-{}.png", self.frames_rendered)))
            }
            _ => {}
        }
        Ok(())
    }

    pub(super) fn toggle(&mut self, effect: Effect) -> Result<()> {
        let e = &mut self.view.scene.effects;
        let flag = match effect {
            Effect::Caustics => &mut e.caustics,
            Effect::Godrays => &mut e.godrays,
            Effect::Filter => &mut e.filter,
        };
        *flag = !*flag;
        println!("{effect:?}: {}", if *flag { "on" } else { "off" });
        self.gpu.rebuild_current(&self.view.scene)
    }

    /// The next caustic estimator (paper's points, footprint points, triangles). A subdivision
    /// finer than the estimator's geometry shader takes (`CausticEstimator::max_subdivision`)
    /// is lowered to it, and one coarser than it needs (`min_subdivision`) raised.
    pub(super) fn next_estimator(&mut self) -> Result<()> {
        use crate::scene::CausticEstimator;
        let e = &mut self.view.scene.effects;
        e.caustic_estimator = match e.caustic_estimator {
            CausticEstimator::Paper => CausticEstimator::Footprint,
            CausticEstimator::Footprint => CausticEstimator::Triangles,
            CausticEstimator::Triangles => CausticEstimator::Paper,
        };
        let what = format!("the {} estimator", e.caustic_estimator.name());
        let bounds = e.caustic_estimator.min_subdivision()..=e.caustic_estimator.max_subdivision();
        fit_subdivision("caustic", &mut e.caustic_subdivision, bounds, &what);
        println!("caustic estimator: {}", e.caustic_estimator.name());
        self.gpu.rebuild_current(&self.view.scene)
    }

    /// The next godray method (the paper's lines, footprint ribbons, the ray march). The march
    /// needs a directional light, so a point light's scene skips it. A subdivision finer than
    /// the method's geometry shader takes (`GodrayMethod::max_subdivision`) is lowered to it.
    pub(super) fn next_godray_method(&mut self) -> Result<()> {
        use crate::scene::{GodrayMethod, LightKind};
        let point_light = self.view.scene.light.kind == LightKind::Point;
        let e = &mut self.view.scene.effects;
        e.godray_method = match e.godray_method {
            GodrayMethod::Beams => GodrayMethod::Footprint,
            GodrayMethod::Footprint if point_light => GodrayMethod::Beams,
            GodrayMethod::Footprint => GodrayMethod::Marched,
            GodrayMethod::Marched => GodrayMethod::Beams,
        };
        let what = format!("the {} godrays", e.godray_method.name());
        fit_subdivision("godray", &mut e.godray_subdivision, 1..=e.godray_method.max_subdivision(), &what);
        println!("godray method: {}", e.godray_method.name());
        self.gpu.rebuild_current(&self.view.scene)
    }

    /// The caustic photons (or, `beams`, the godray beams) on the even grid or spread as the
    /// view needs them (rebuilt: the frame surveys the scene's triangles only for the second).
    pub(super) fn next_photon_density(&mut self, beams: bool) -> Result<()> {
        use crate::scene::PhotonSpread;
        let e = &mut self.view.scene.effects;
        let density = if beams { &mut e.godray_photon_density } else { &mut e.caustic_photon_density };
        *density = match *density {
            PhotonSpread::Even => PhotonSpread::View,
            PhotonSpread::View => PhotonSpread::Even,
        };
        println!("{} density: {}", if beams { "godray beam" } else { "caustic photon" }, density.name());
        self.gpu.rebuild_current(&self.view.scene)
    }

    pub(super) fn preset(&mut self, preset: Preset) -> Result<()> {
        let e = &mut self.view.scene.effects;
        match preset {
            // The paper's high setting: 1M caustic photons, 360k godray photons, small points.
            Preset::High => {
                e.caustic_grid = 500;
                e.caustic_subdivision = 2;
                e.godray_grid = 300;
                e.godray_subdivision = 2;
                e.point_size_min = 2.0;
                e.point_size_max = 10.0;
            }
            Preset::Default => {
                let d = &self.view.loaded.effects;
                e.caustic_grid = d.caustic_grid;
                e.caustic_subdivision = d.caustic_subdivision;
                e.caustic_estimator = d.caustic_estimator;
                e.caustic_photon_density = d.caustic_photon_density;
                e.godray_photon_density = d.godray_photon_density;
                e.godray_method = d.godray_method;
                e.godray_grid = d.godray_grid;
                e.godray_subdivision = d.godray_subdivision;
                e.point_size_min = d.point_size_min;
                e.point_size_max = d.point_size_max;
            }
        }
        println!("preset {preset:?}");
        self.gpu.rebuild_current(&self.view.scene)
    }

    /// The other water model. The frame reads the water from the scene every frame, so
    /// nothing is rebuilt (as for the amplitude), unless the change decides anew how the
    /// photons find the water (`water_changed`).
    pub(super) fn next_water(&mut self) -> Result<()> {
        let newton = crate::frame::newton_crossing(&self.view.scene);
        let w = &mut self.view.scene.water;
        w.model = match w.model {
            WaterModel::CircularCosine => WaterModel::AxisCosineNoise,
            WaterModel::AxisCosineNoise => WaterModel::CircularCosine,
        };
        println!("water model: {:?}", w.model);
        self.water_changed(newton)
    }

    pub(super) fn scale_amplitude(&mut self, factor: f32) -> Result<()> {
        let newton = crate::frame::newton_crossing(&self.view.scene);
        let w = &mut self.view.scene.water;
        w.amplitude = (w.amplitude * factor).clamp(0.0, w.wavelength);
        println!("wave amplitude: {:.4} m", w.amplitude);
        self.water_changed(newton)
    }

    /// Rebuilds the frame where steeper or gentler waves change whether Newton's search alone
    /// finds every photon's water crossing (`newton_before`: it did before the change): the
    /// photon passes compile that choice in (`frame::newton_crossing`).
    fn water_changed(&mut self, newton_before: bool) -> Result<()> {
        if crate::frame::newton_crossing(&self.view.scene) == newton_before {
            return Ok(());
        }
        self.gpu.rebuild_current(&self.view.scene)
    }
}

impl View {
    fn print_settings(&self) {
        let s = &self.scene;
        let e = &s.effects;
        println!(
            "scene {:?}: camera {:.2} yaw {:.1}° pitch {:.1}°; water {:?} amplitude {} m; caustics {} ({}²×{}², {}, {} photons), \
             godrays {} ({}, {}²×{}²), filter {}; points {}–{} px; time {:.2} s{}",
            s.name,
            self.camera.position,
            self.camera.yaw.to_degrees(),
            self.camera.pitch.to_degrees(),
            s.water.model,
            s.water.amplitude,
            e.caustics,
            e.caustic_grid,
            e.caustic_subdivision,
            e.caustic_estimator.name(),
            e.caustic_photon_density.name(),
            e.godrays,
            e.godray_method.name(),
            e.godray_grid,
            e.godray_subdivision,
            e.filter,
            e.point_size_min,
            e.point_size_max,
            self.time,
            if self.paused { " (paused)" } else { "" }
        );
    }
}

/// Brings a `kind` (caustic, godray) subdivision into `bounds`, those of `what` (its geometry
/// shader's output limit above, the neighbours the footprint points need below), saying so.
fn fit_subdivision(kind: &str, subdivision: &mut u32, bounds: std::ops::RangeInclusive<u32>, what: &str) {
    let fitted = (*subdivision).clamp(*bounds.start(), *bounds.end());
    if fitted != *subdivision {
        let how = if fitted < *subdivision { "lowered" } else { "raised" };
        println!("{kind} subdivision {subdivision} {how} to {fitted} for {what}");
        *subdivision = fitted;
    }
}
