//! The interactive viewer: the method live in a window, on any Vulkan driver.
//!
//! The frame renders off screen exactly as the headless renderer does; the present pass
//! (`passes::present`) blits its output into the acquired swapchain image. Resizing recreates the swapchain and
//! the frame (effect targets keep their fraction of the window); a 0×0 window draws nothing
//! until it has an area again. Toggling an effect rebuilds the frame, since the scene decides
//! which passes and targets exist.

pub mod camera;
pub mod script;

use crate::frame::FrameRing;
use crate::frame::PassTimings;
use crate::frame::{Frame, FrameOptions};
use crate::headless::median_timings;
use crate::image_io;
use crate::memory::MemorySample;
use crate::passes::present::{PresentPass, ACQUIRE_WAIT_STAGE};
use crate::passes::PassId;
use crate::scene::{Scene, WaterModel};
use crate::vk::swapchain::{PresentMode, Surface, Swapchain};
use crate::vk::{Context, ContextDesc, ShutdownReport};
use anyhow::{anyhow, Context as _, Result};
use ash::vk;
use camera::FlyCamera;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use script::{Effect, Preset, Step};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::time::{Duration, Instant};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

/// Frames whose timings the title's medians are taken over.
const TIMING_WINDOW: usize = 60;

pub struct ViewerOptions {
    pub scene: Scene,
    pub context: ContextDesc,
    pub present_mode: PresentMode,
    /// Initial inner size; the scene's output size when absent.
    pub size: Option<(u32, u32)>,
    /// Scripted steps; the viewer exits after the last.
    pub script: Vec<Step>,
    /// Exit after this many frames (with `screenshot`, the last one is saved).
    pub frames: Option<u32>,
    pub screenshot: Option<PathBuf>,
    /// Animation time at start, and whether time starts paused.
    pub time: f32,
    pub paused: bool,
}

/// What a viewer session ended with.
pub struct ViewerReport {
    pub frames_presented: u64,
    /// Frames in which each pass was recorded (passes that never ran are left out), in
    /// `PassId::ALL` order: the water's refraction and reflection only in frames whose camera
    /// was above the water.
    pub pass_frames: Vec<(PassId, u64)>,
    pub shutdown: ShutdownReport,
}

/// Opens the window and runs until it is closed, Esc is pressed, or the script or frame
/// count ends.
pub fn run(options: ViewerOptions) -> Result<ViewerReport> {
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!("cannot open a window: {e}. Is there a display? (set DISPLAY, or run under `xvfb-run -a`)")
    })?;
    let mut app = App { options, live: None, error: None, presented: 0, report: None };
    event_loop.run_app(&mut app).context("running the window's event loop")?;
    if let Some(e) = app.error {
        // Tear down what exists even on error, so validation still reports.
        if let Some(live) = app.live.take() {
            let _ = live.shutdown();
        }
        return Err(e);
    }
    let mut counts = [0u64; PassId::ALL.len()];
    let shutdown = match app.live.take() {
        Some(live) => {
            counts = live.pass_frames;
            live.shutdown()
        }
        None => app.report.take().unwrap_or_default(),
    };
    let pass_frames = PassId::ALL.into_iter().zip(counts).filter(|(_, n)| *n > 0).collect();
    Ok(ViewerReport { frames_presented: app.presented, pass_frames, shutdown })
}

struct App {
    options: ViewerOptions,
    live: Option<Live>,
    error: Option<anyhow::Error>,
    presented: u64,
    report: Option<ShutdownReport>,
}

/// Everything that exists while the window is open. Field order is drop order: GPU objects
/// before the surface, the surface before the device, the window last.
struct Live {
    frame: Option<Frame>,
    ring: FrameRing,
    swapchain: Option<Swapchain>,
    present: PresentPass,
    /// The device clamps last printed (`Frame::clamped`).
    reported_clamps: Vec<String>,
    surface: Surface,
    ctx: Context,
    window: Window,
    /// The scene as loaded (camera reset, default preset) and as currently shown.
    loaded: Scene,
    scene: Scene,
    camera: FlyCamera,
    present_mode: PresentMode,
    time: f32,
    paused: bool,
    step_once: bool,
    last_instant: Instant,
    keys_down: Vec<KeyCode>,
    looking: bool,
    cursor: Option<(f64, f64)>,
    script: VecDeque<Step>,
    frames_left_in_step: u32,
    frames_rendered: u64,
    pending_screenshot: Option<PathBuf>,
    timings: VecDeque<PassTimings>,
    /// Frames each pass was recorded in, indexed as `PassId::ALL`.
    pass_frames: [u64; PassId::ALL.len()],
    last_report: Instant,
    frames_since_report: u32,
    /// Memory after frame `MEMORY_SAMPLE_FRAME`, printed beside the memory at exit: a window
    /// left open must not grow.
    memory_early: Option<MemorySample>,
}

/// The frame whose memory the viewer compares with its memory at exit (after warm-up).
const MEMORY_SAMPLE_FRAME: u64 = 100;

fn print_memory(sample: &MemorySample) {
    println!(
        "memory at frame {}: resident {} bytes, device {} bytes in {} allocations",
        sample.frame,
        sample.resident_bytes.map_or("unknown".to_string(), |b| b.to_string()),
        sample.device.allocated_bytes,
        sample.device.allocations
    );
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.live.is_some() {
            return;
        }
        match Live::new(event_loop, &self.options) {
            Ok(live) => {
                live.window.request_redraw();
                self.live = Some(live);
            }
            Err(e) => {
                self.error = Some(e);
                event_loop.exit();
            }
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(live) = self.live.as_mut() else { return };
        let result = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::Resized(size) => live.resize(size),
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    live.key(code, event.state == ElementState::Pressed, event_loop)
                } else {
                    Ok(())
                }
            }
            WindowEvent::MouseInput { button: MouseButton::Right, state, .. } => {
                live.looking = state == ElementState::Pressed;
                live.cursor = None;
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                if live.looking {
                    if let Some((x, y)) = live.cursor {
                        let k = 0.004;
                        live.camera.turn((position.x - x) as f32 * k, -(position.y - y) as f32 * k);
                    }
                    live.cursor = Some((position.x, position.y));
                }
                Ok(())
            }
            WindowEvent::RedrawRequested => match live.redraw(&self.options) {
                Ok(Some(presented)) => {
                    self.presented += presented as u64;
                    if live.finished(&self.options) {
                        event_loop.exit();
                    }
                    Ok(())
                }
                Ok(None) => Ok(()),
                Err(e) => Err(e),
            },
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.error = Some(e);
            event_loop.exit();
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(live) = &self.live {
            live.window.request_redraw();
        }
    }
}

impl Live {
    fn new(event_loop: &ActiveEventLoop, options: &ViewerOptions) -> Result<Self> {
        let scene = options.scene.clone();
        let (w, h) = options.size.unwrap_or((scene.output[0], scene.output[1]));
        let attributes = Window::default_attributes()
            .with_title(format!("underlight — {}", scene.name))
            .with_inner_size(PhysicalSize::new(w, h));
        let window = event_loop.create_window(attributes).context("creating the window")?;
        let display = window.display_handle().context("window display handle")?.as_raw();
        let handle = window.window_handle().context("window handle")?.as_raw();
        let mut desc = options.context.clone();
        desc.instance_extensions = ash_window::enumerate_required_extensions(display)
            .context("surface extensions for this window system")?
            .to_vec();
        let ctx = Context::new(&desc)?;
        // SAFETY: the window outlives the surface (`Live` drops the surface first).
        let surface = unsafe { Surface::new(&ctx.device, display, handle)? };
        let ring = FrameRing::new(&ctx.device)?;
        let present = PresentPass::new(&ctx.device);
        println!("device: {}", ctx.device.info.describe());
        println!(
            "keys: WASD/QE move (Shift faster), right-drag or arrows look, 1/2/3 caustics/godrays/filter, \
             4 caustic estimator, \
             M water model, +/- amplitude, P pause, N step, H/L high/default preset, R reset camera, \
             I settings, F12 screenshot, Esc quit"
        );
        let mut live = Self {
            frame: None,
            ring,
            swapchain: None,
            present,
            reported_clamps: Vec::new(),
            surface,
            ctx,
            window,
            camera: FlyCamera::from_camera(&scene.camera),
            loaded: scene.clone(),
            scene,
            present_mode: options.present_mode,
            time: options.time,
            paused: options.paused,
            step_once: false,
            last_instant: Instant::now(),
            keys_down: Vec::new(),
            looking: false,
            cursor: None,
            script: options.script.iter().cloned().collect(),
            frames_left_in_step: 0,
            frames_rendered: 0,
            pending_screenshot: None,
            timings: VecDeque::with_capacity(TIMING_WINDOW),
            pass_frames: [0; PassId::ALL.len()],
            last_report: Instant::now(),
            frames_since_report: 0,
            memory_early: None,
        };
        let size = live.window.inner_size();
        live.resize(size)?;
        Ok(live)
    }

    /// Recreates the swapchain for the window's size, and the frame if the size changed.
    fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        let extent = vk::Extent2D { width: size.width, height: size.height };
        let dev = self.ctx.device.clone();
        dev.wait_idle()?;
        if extent.width == 0 || extent.height == 0 {
            // Minimised: nothing to present to. Keep the frame for when the window returns.
            self.swapchain = None;
            return Ok(());
        }
        let old = self.swapchain.take();
        self.swapchain = Swapchain::new(&dev, &self.surface, extent, self.present_mode, old.as_ref())?;
        drop(old);
        if let Some(sc) = &self.swapchain {
            let same = self.frame.as_ref().map(|f| f.extents.output == [sc.extent.width, sc.extent.height]);
            if same != Some(true) {
                self.rebuild_frame(sc.extent)?;
            }
        }
        Ok(())
    }

    /// A new frame for the current scene: passes and targets follow its effects.
    fn rebuild_frame(&mut self, extent: vk::Extent2D) -> Result<()> {
        self.ctx.device.wait_idle()?;
        self.frame = None;
        let options = FrameOptions { camera_moves: true, ..FrameOptions::default() };
        let frame = Frame::new(&self.ctx.device, &self.scene, extent, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, options)?;
        // Settings beyond what the device can draw (point sizes, line width) are clamped;
        // say so once per change, not on every resize.
        if frame.clamped != self.reported_clamps {
            for note in &frame.clamped {
                eprintln!("warning: {note}");
            }
            self.reported_clamps = frame.clamped.clone();
        }
        self.frame = Some(frame);
        self.present.release_screenshot_buffer();
        Ok(())
    }

    fn rebuild_current(&mut self) -> Result<()> {
        match self.swapchain.as_ref().map(|s| s.extent) {
            Some(extent) => self.rebuild_frame(extent),
            // Minimised: rebuild when the window comes back.
            None => {
                self.frame = None;
                Ok(())
            }
        }
    }

    fn toggle(&mut self, effect: Effect) -> Result<()> {
        let e = &mut self.scene.effects;
        let flag = match effect {
            Effect::Caustics => &mut e.caustics,
            Effect::Godrays => &mut e.godrays,
            Effect::Filter => &mut e.filter,
        };
        *flag = !*flag;
        println!("{effect:?}: {}", if *flag { "on" } else { "off" });
        self.rebuild_current()
    }

    /// The next caustic estimator (paper's points, triangles). The triangles' geometry shader
    /// takes at most TRIANGLE_MAX_SUBDIVISION; a finer subdivision is lowered to it.
    fn next_estimator(&mut self) -> Result<()> {
        use crate::scene::CausticEstimator;
        let e = &mut self.scene.effects;
        e.caustic_estimator = match e.caustic_estimator {
            CausticEstimator::Paper => CausticEstimator::Triangles,
            CausticEstimator::Triangles => CausticEstimator::Paper,
        };
        let max = crate::shader_math::TRIANGLE_MAX_SUBDIVISION;
        if e.caustic_estimator == CausticEstimator::Triangles && e.caustic_subdivision > max {
            println!("caustic subdivision {} lowered to {max} for the triangle estimator", e.caustic_subdivision);
            e.caustic_subdivision = max;
        }
        println!("caustic estimator: {}", e.caustic_estimator.name());
        self.rebuild_current()
    }

    fn preset(&mut self, preset: Preset) -> Result<()> {
        let e = &mut self.scene.effects;
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
                let d = &self.loaded.effects;
                e.caustic_grid = d.caustic_grid;
                e.caustic_subdivision = d.caustic_subdivision;
                e.caustic_estimator = d.caustic_estimator;
                e.godray_grid = d.godray_grid;
                e.godray_subdivision = d.godray_subdivision;
                e.point_size_min = d.point_size_min;
                e.point_size_max = d.point_size_max;
            }
        }
        println!("preset {preset:?}");
        self.rebuild_current()
    }

    fn next_water(&mut self) {
        let w = &mut self.scene.water;
        w.model = match w.model {
            WaterModel::CircularCosine => WaterModel::AxisCosineNoise,
            WaterModel::AxisCosineNoise => WaterModel::CircularCosine,
        };
        println!("water model: {:?}", w.model);
    }

    fn scale_amplitude(&mut self, factor: f32) {
        let w = &mut self.scene.water;
        w.amplitude = (w.amplitude * factor).clamp(0.0, w.wavelength);
        println!("wave amplitude: {:.4} m", w.amplitude);
    }

    fn key(&mut self, code: KeyCode, pressed: bool, event_loop: &ActiveEventLoop) -> Result<()> {
        if !pressed {
            self.keys_down.retain(|k| *k != code);
            return Ok(());
        }
        if !self.keys_down.contains(&code) {
            self.keys_down.push(code);
        }
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::Digit1 => self.toggle(Effect::Caustics)?,
            KeyCode::Digit2 => self.toggle(Effect::Godrays)?,
            KeyCode::Digit3 => self.toggle(Effect::Filter)?,
            KeyCode::Digit4 => self.next_estimator()?,
            KeyCode::KeyM => self.next_water(),
            KeyCode::Equal | KeyCode::NumpadAdd => self.scale_amplitude(1.25),
            KeyCode::Minus | KeyCode::NumpadSubtract => self.scale_amplitude(0.8),
            KeyCode::KeyP => self.paused = !self.paused,
            KeyCode::KeyN => self.step_once = true,
            KeyCode::KeyH => self.preset(Preset::High)?,
            KeyCode::KeyL => self.preset(Preset::Default)?,
            KeyCode::KeyR => self.camera = FlyCamera::from_camera(&self.loaded.camera),
            KeyCode::KeyI => self.print_settings(),
            KeyCode::F12 => {
                self.pending_screenshot = Some(PathBuf::from(format!("out/screenshot-{}.png", self.frames_rendered)))
            }
            _ => {}
        }
        Ok(())
    }

    fn print_settings(&self) {
        let s = &self.scene;
        let e = &s.effects;
        println!(
            "scene {:?}: camera {:.2} yaw {:.1}° pitch {:.1}°; water {:?} amplitude {} m; caustics {} ({}²×{}², {}), \
             godrays {} ({}²×{}²), filter {}; points {}–{} px; time {:.2} s{}",
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
            e.godrays,
            e.godray_grid,
            e.godray_subdivision,
            e.filter,
            e.point_size_min,
            e.point_size_max,
            self.time,
            if self.paused { " (paused)" } else { "" }
        );
    }

    /// Moves the camera by the keys held, scaled by the time since the last frame.
    fn fly(&mut self, dt: f32) {
        let fast = self.keys_down.iter().any(|k| matches!(k, KeyCode::ShiftLeft | KeyCode::ShiftRight));
        let speed = if fast { 4.0 } else { 1.0 } * dt;
        let turn = 1.2 * dt;
        for i in 0..self.keys_down.len() {
            match self.keys_down[i] {
                KeyCode::KeyW => self.camera.translate(0.0, 0.0, speed),
                KeyCode::KeyS => self.camera.translate(0.0, 0.0, -speed),
                KeyCode::KeyD => self.camera.translate(speed, 0.0, 0.0),
                KeyCode::KeyA => self.camera.translate(-speed, 0.0, 0.0),
                KeyCode::KeyE => self.camera.translate(0.0, speed, 0.0),
                KeyCode::KeyQ => self.camera.translate(0.0, -speed, 0.0),
                KeyCode::ArrowLeft => self.camera.turn(-turn, 0.0),
                KeyCode::ArrowRight => self.camera.turn(turn, 0.0),
                KeyCode::ArrowUp => self.camera.turn(0.0, turn),
                KeyCode::ArrowDown => self.camera.turn(0.0, -turn),
                _ => {}
            }
        }
    }

    /// Runs script steps until one asks for frames (or the script ends).
    fn advance_script(&mut self) -> Result<()> {
        while self.frames_left_in_step == 0 {
            let Some(step) = self.script.pop_front() else { return Ok(()) };
            match step {
                Step::Frames(n) => self.frames_left_in_step = n,
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
                Step::NextWater => self.next_water(),
                Step::Amplitude(f) => self.scale_amplitude(f),
                Step::Move(r, u, f) => self.camera.translate(r, u, f),
                Step::Look(yaw, pitch) => self.camera.turn(yaw.to_radians(), pitch.to_radians()),
                Step::Preset(p) => self.preset(p)?,
                Step::Screenshot(path) => self.pending_screenshot = Some(PathBuf::from(path)),
            }
        }
        Ok(())
    }

    fn finished(&self, options: &ViewerOptions) -> bool {
        if !options.script.is_empty() {
            return self.script.is_empty() && self.frames_left_in_step == 0 && self.pending_screenshot.is_none();
        }
        options.frames.is_some_and(|n| self.frames_rendered >= n as u64)
    }

    /// Draws one frame if the window has an area. Returns whether a frame was presented
    /// (`None` when nothing was attempted).
    fn redraw(&mut self, options: &ViewerOptions) -> Result<Option<bool>> {
        self.advance_script()?;
        let now = Instant::now();
        let dt = (now - self.last_instant).as_secs_f32().min(0.1);
        self.last_instant = now;
        self.fly(dt);
        if self.frame.is_none() {
            if let Some(extent) = self.swapchain.as_ref().map(|s| s.extent) {
                self.rebuild_frame(extent)?;
            }
        }
        let (Some(frame), Some(swapchain)) = (self.frame.as_mut(), self.swapchain.as_ref()) else {
            // Minimised: count scripted frames anyway so a script cannot hang on a hidden window.
            self.frames_left_in_step = self.frames_left_in_step.saturating_sub(1);
            std::thread::sleep(Duration::from_millis(10));
            return Ok(None);
        };
        // The last frame of `--frames` with `--screenshot` is saved.
        if options.frames.is_some_and(|n| self.frames_rendered + 1 == n as u64) && options.screenshot.is_some() {
            self.pending_screenshot = options.screenshot.clone();
        }
        if !self.paused || self.step_once {
            self.time += if options.script.is_empty() && options.frames.is_none() { dt } else { 1.0 / 60.0 };
            self.step_once = false;
        }
        {
            let s = frame.scene_mut();
            self.camera.apply(&mut s.camera);
            s.water = self.scene.water;
        }

        let slot = self.ring.begin()?;
        let slot_index = slot.index;
        let acquired = swapchain.acquire(slot_index)?;
        let Some(image_index) = acquired else {
            // Out of date: drop this frame's recording and rebuild for the window's size.
            self.ring.abandon()?;
            let size = self.window.inner_size();
            self.resize(size)?;
            return Ok(Some(false));
        };
        let image = swapchain.images[image_index as usize];
        frame.record(slot, self.time);
        let cmd = slot.cmd;
        let output = &frame.compose.output.image;
        let screenshot = self.pending_screenshot.take();
        if screenshot.is_some() {
            self.present.prepare_screenshot(swapchain.extent)?;
        }
        let present = &self.present;
        slot.timer.pass(cmd, PassId::Present, |cmd| {
            present.record(cmd, output, image, swapchain.extent, screenshot.is_some());
        });
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.acquired[slot_index])
            .stage_mask(ACQUIRE_WAIT_STAGE)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.rendered[image_index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        self.ring.submit(&waits, &signals)?;
        // Keep the last 60 frames' timings, reusing the oldest entry's storage once full.
        if let Some((_, t)) = self.ring.take_fresh_timings() {
            let mut entry = if self.timings.len() == TIMING_WINDOW {
                self.timings.pop_front().unwrap_or_default()
            } else {
                PassTimings::default()
            };
            entry.passes.clone_from(&t.passes);
            for (id, _) in &entry.passes {
                if let Some(i) = PassId::ALL.iter().position(|p| p == id) {
                    self.pass_frames[i] += 1;
                }
            }
            self.timings.push_back(entry);
        }
        let ok = swapchain.present(image_index)?;
        self.frames_rendered += 1;
        if self.frames_rendered == MEMORY_SAMPLE_FRAME {
            self.memory_early = Some(MemorySample::now(&self.ctx.device, self.frames_rendered));
        }
        self.frames_left_in_step = self.frames_left_in_step.saturating_sub(1);
        if let Some(path) = screenshot {
            // A screenshot is an explicit request: waiting for its frame is what it asks for.
            self.ring.finish(|_, _| {})?;
            self.save_screenshot(&path)?;
        }
        self.report_timings();
        if !ok {
            let size = self.window.inner_size();
            self.resize(size)?;
        }
        Ok(Some(true))
    }

    fn save_screenshot(&self, path: &std::path::Path) -> Result<()> {
        let (Some(buffer), Some(sc)) = (self.present.screenshot_buffer(), &self.swapchain) else { return Ok(()) };
        let bytes = buffer.mapped().context("screenshot buffer is not mapped")?;
        let mut rgba = bytes.to_vec();
        if sc.format == vk::Format::B8G8R8A8_SRGB {
            for px in rgba.chunks_exact_mut(4) {
                px.swap(0, 2);
            }
        }
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        image_io::write_png(path, sc.extent.width, sc.extent.height, &rgba)?;
        println!("wrote {}", path.display());
        Ok(())
    }

    /// Puts the per-pass GPU times in the title twice a second and on the terminal every 2 s.
    fn report_timings(&mut self) {
        self.frames_since_report += 1;
        let elapsed = self.last_report.elapsed();
        if elapsed < Duration::from_millis(500) || self.timings.is_empty() {
            return;
        }
        // Twice a second, not per frame: the copy for the median is fine here.
        let frames: Vec<PassTimings> = self.timings.iter().cloned().collect();
        let median = median_timings(&frames);
        let fps = self.frames_since_report as f64 / elapsed.as_secs_f64();
        let passes: Vec<String> = median.passes.iter().map(|(id, ms)| format!("{} {:.1}", id.name(), ms)).collect();
        let line = format!("{:.1} fps | GPU ms: {} | total {:.1}", fps, passes.join(" "), median.total_ms());
        self.window.set_title(&format!("underlight — {} — {line}", self.scene.name));
        if self.frames_rendered.is_multiple_of(4) || elapsed > Duration::from_secs(2) {
            println!("{line}");
        }
        self.last_report = Instant::now();
        self.frames_since_report = 0;
    }

    fn shutdown(self) -> ShutdownReport {
        if let Some(early) = &self.memory_early {
            print_memory(early);
            print_memory(&MemorySample::now(&self.ctx.device, self.frames_rendered));
        }
        let Live { frame, ring, swapchain, present, surface, ctx, window, .. } = self;
        let _ = ctx.device.wait_idle();
        drop((frame, ring, swapchain, present, surface));
        let report = ctx.shutdown();
        drop(window);
        report
    }
}
