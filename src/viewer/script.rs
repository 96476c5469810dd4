//! Scripted viewer sessions (`underlight view --script ...`), so tests and demos can drive
//! the window the way a person would: resize, minimise, toggle effects, move the camera.
//! `parse` reads a script; the viewer runs it a step at a time (`Script`).

use super::Live;
use crate::scene::file::MAX_OUTPUT_SIDE;
use anyhow::{bail, Context as _, Result};
use std::collections::VecDeque;
use std::path::PathBuf;
use winit::dpi::PhysicalSize;

/// One step of a script. Steps run in order; `Frames` renders before the next step.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Render this many frames.
    Frames(u32),
    /// Ask the window system for a new inner size.
    Resize(u32, u32),
    /// Minimise: the window reports a 0×0 surface, so no frame is drawn until restored.
    Minimize,
    Restore,
    /// Switch an effect on or off (rebuilds the frame: passes and targets follow the scene).
    Toggle(Effect),
    /// Switch to the next caustic estimator (the paper's points, footprint points, triangles).
    NextEstimator,
    /// Switch to the next godray method (lines, footprint ribbons, ray march).
    NextGodrayMethod,
    /// Switch the caustic photons (false) or the godray beams (true) between the even grid
    /// and the view's density.
    NextPhotonDensity(bool),
    /// Switch to the other water model.
    NextWater,
    /// Scale the wave amplitude by this factor.
    Amplitude(f32),
    /// Move the camera by metres along (right, up, forward) of its view.
    Move(f32, f32, f32),
    /// Turn the camera by degrees (yaw right, pitch up).
    Look(f32, f32),
    /// The paper's high setting (grids 500²×4 / 300²×4, points 2–10) or its default.
    Preset(Preset),
    /// Write the presented image to this PNG.
    Screenshot(String),
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    Caustics,
    Godrays,
    Filter,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Preset {
    Default,
    High,
}

/// Parses `step,step,...`, e.g. `frames:3,resize:320x240,minimize,frames:2,restore`.
pub fn parse(text: &str) -> Result<Vec<Step>> {
    let mut steps = Vec::new();
    for (i, item) in text.split(',').map(str::trim).filter(|s| !s.is_empty()).enumerate() {
        let (name, arg) = item.split_once(':').unwrap_or((item, ""));
        let bad = || format!("script step {} ({item:?})", i + 1);
        let floats = |n: usize| -> Result<Vec<f32>> {
            let v: Vec<f32> =
                arg.split('/').map(|x| x.trim().parse::<f32>()).collect::<Result<_, _>>().with_context(bad)?;
            if v.len() != n || v.iter().any(|x| !x.is_finite()) {
                bail!("{}: expected {n} finite number(s) separated by '/'", bad());
            }
            Ok(v)
        };
        steps.push(match name {
            "frames" => Step::Frames(arg.parse().with_context(bad)?),
            "resize" => {
                let (w, h) = arg.split_once('x').with_context(|| format!("{}: expected WxH", bad()))?;
                let (w, h): (u32, u32) = (w.parse().with_context(bad)?, h.parse().with_context(bad)?);
                // As --width and --height: X11 keeps a window's side in 16 bits, so 100000
                // became a 34464-pixel window whose swapchain no device could allocate. Zero is
                // allowed: a window with no area is what the viewer must survive.
                if w.max(h) > MAX_OUTPUT_SIDE {
                    bail!("{}: a window's side is at most {MAX_OUTPUT_SIDE} pixels", bad());
                }
                Step::Resize(w, h)
            }
            "minimize" => Step::Minimize,
            "restore" => Step::Restore,
            "toggle" => Step::Toggle(match arg {
                "caustics" => Effect::Caustics,
                "godrays" => Effect::Godrays,
                "filter" => Effect::Filter,
                _ => bail!("{}: toggle caustics, godrays or filter", bad()),
            }),
            "water" => Step::NextWater,
            "estimator" => Step::NextEstimator,
            "godray-method" => Step::NextGodrayMethod,
            "density" => Step::NextPhotonDensity(match arg {
                "" | "caustics" => false,
                "godrays" => true,
                _ => bail!("{}: density, density:caustics or density:godrays", bad()),
            }),
            "amplitude" => Step::Amplitude(floats(1)?[0]),
            "move" => {
                let v = floats(3)?;
                Step::Move(v[0], v[1], v[2])
            }
            "look" => {
                let v = floats(2)?;
                Step::Look(v[0], v[1])
            }
            "preset" => Step::Preset(match arg {
                "default" => Preset::Default,
                "high" => Preset::High,
                _ => bail!("{}: preset default or high", bad()),
            }),
            "screenshot" if !arg.is_empty() => Step::Screenshot(arg.to_string()),
            _ => bail!(
                "{}: unknown step; steps are frames:N, resize:WxH, minimize, restore, toggle:EFFECT, estimator, godray-method, density[:caustics|godrays], water, \
                 amplitude:F, move:R/U/F, look:YAW/PITCH, preset:default|high, screenshot:PATH",
                bad()
            ),
        });
    }
    Ok(steps)
}

/// A script as the viewer runs it: the steps left, and the frames the current `Frames` step
/// has still to draw.
pub(super) struct Script {
    steps: VecDeque<Step>,
    frames_left_in_step: u32,
}

impl Script {
    pub(super) fn new(steps: &[Step]) -> Self {
        Self { steps: steps.iter().cloned().collect(), frames_left_in_step: 0 }
    }

    /// A frame was presented, or skipped because the window has no area.
    pub(super) fn frame_done(&mut self) {
        self.frames_left_in_step = self.frames_left_in_step.saturating_sub(1);
    }

    /// Every step has run and drawn its frames.
    pub(super) fn ended(&self) -> bool {
        self.steps.is_empty() && self.frames_left_in_step == 0
    }
}

impl Live {
    /// Runs script steps until one asks for frames (or the script ends).
    pub(super) fn advance_script(&mut self) -> Result<()> {
        while self.script.frames_left_in_step == 0 {
            let Some(step) = self.script.steps.pop_front() else { return Ok(()) };
            match step {
                Step::Frames(n) => self.script.frames_left_in_step = n,
                Step::Resize(w, h) => {
                    let size = PhysicalSize::new(w, h);
                    // The window system applies it when it can; apply it here too, so the
                    // script does not depend on a window manager being present.
                    let _ = self.window.request_inner_size(size);
                    self.resize(size)?;
                }
                Step::Minimize => {
                    self.window.set_minimized(true);
                    // Without a window manager (Xvfb) nothing iconifies; take the 0×0 path a
                    // minimised window reports, which is what this step tests.
                    self.resize(PhysicalSize::new(0, 0))?;
                }
                Step::Restore => {
                    self.window.set_minimized(false);
                    let size = self.window.inner_size();
                    self.resize(size)?;
                }
                Step::Toggle(effect) => self.toggle(effect)?,
                Step::NextEstimator => self.next_estimator()?,
                Step::NextGodrayMethod => self.next_godray_method()?,
                Step::NextPhotonDensity(beams) => self.next_photon_density(beams)?,
                Step::NextWater => self.next_water()?,
                Step::Amplitude(f) => self.scale_amplitude(f)?,
                Step::Move(r, u, f) => self.view.camera.translate(r, u, f),
                Step::Look(yaw, pitch) => self.view.camera.turn(yaw.to_radians(), pitch.to_radians()),
                Step::Preset(p) => self.preset(p)?,
                Step::Screenshot(path) => self.pending_screenshot = Some(PathBuf::from(path)),
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_step_and_rejects_bad_ones() {
        let s = parse("frames:2, resize:320x240,minimize,restore,toggle:godrays,water,amplitude:1.5,move:0/0/1,look:10/-5,preset:high,screenshot:a.png").unwrap();
        assert_eq!(s.len(), 11);
        assert_eq!(s[1], Step::Resize(320, 240));
        assert_eq!(s[7], Step::Move(0.0, 0.0, 1.0));
        let s = parse("estimator,godray-method,density:godrays").unwrap();
        assert_eq!(s, [Step::NextEstimator, Step::NextGodrayMethod, Step::NextPhotonDensity(true)]);
        for bad in ["frames:x", "resize:10", "resize:100000x100000", "toggle:fog", "move:1/2", "amplitude:nan", "jump"]
        {
            let e = parse(bad).unwrap_err().to_string();
            assert!(e.contains("script step 1"), "{bad}: {e}");
        }
    }
}
