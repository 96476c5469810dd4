//! The interactive viewer: the method live in a window, on any Vulkan driver.
//!
//! The frame renders off screen exactly as the headless renderer does; the present pass
//! (`passes::present`) blits its output into the acquired swapchain image. Resizing
//! recreates the swapchain and the frame (effect targets keep their fraction of the window);
//! a 0×0 window draws nothing until it has an area again. Toggling an effect rebuilds the
//! frame, since the scene decides which passes and targets exist.
//!
//! This file holds the event loop and the window's, swapchain's and frame's lifecycle; keys
//! and mouse are in `input`, the title's timings and the memory report in `timings`, and
//! scripted sessions in `script`.

pub mod camera;
mod input;
pub mod script;
mod timings;

use crate::frame::FrameRing;
use crate::frame::{Frame, FrameOptions};
use crate::image_io;
use crate::passes::present::{PresentPass, ACQUIRE_WAIT_STAGE};
use crate::passes::PassId;
use crate::scene::Scene;
use crate::vk::swapchain::{PresentMode, Surface, Swapchain};
use crate::vk::{Context, ContextDesc, ShutdownReport};
use anyhow::{anyhow, Context as _, Result};
use ash::vk;
use camera::FlyCamera;
use input::Input;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use script::{Script, Step};
use std::path::PathBuf;
use std::time::{Duration, Instant};
use timings::Timings;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, EventLoop};
use winit::keyboard::PhysicalKey;
use winit::window::{Window, WindowId};

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
    /// A sweep's rows (`underlight sweep`'s sweep.json): the window title shows the error it
    /// measured for the setting nearest to the current one. Empty: no estimate.
    pub sweep: Vec<crate::accuracy::SweepRow>,
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
    crate::headless::check_clock(options.time, 0.0, 1)?;
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
            counts = live.timings.pass_frames;
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

/// Everything that exists while the window is open. Field order is drop order: the GPU state
/// before the window it presents to.
struct Live {
    gpu: Gpu,
    window: Window,
    view: View,
    input: Input,
    script: Script,
    timings: Timings,
    /// Frames presented so far.
    frames_rendered: u64,
    /// Saved from the next frame presented (F12, a script step, the last of `--frames`).
    pending_screenshot: Option<PathBuf>,
}

/// The device and what draws into the window. Field order is drop order: GPU objects before
/// the surface, the surface before the device.
struct Gpu {
    frame: Option<Frame>,
    ring: FrameRing,
    /// None while the window has no area (minimised).
    swapchain: Option<Swapchain>,
    present: PresentPass,
    present_mode: PresentMode,
    /// The device clamps last printed (`Frame::clamped`).
    reported_clamps: Vec<String>,
    surface: Surface,
    ctx: Context,
}

/// What the window shows: the scene with its current settings, seen from the fly camera, at
/// the animation's time.
struct View {
    /// The scene as loaded (camera reset, default preset) and as currently shown.
    loaded: Scene,
    scene: Scene,
    camera: FlyCamera,
    time: f32,
    paused: bool,
    /// Advance the paused animation by one frame (N).
    step_once: bool,
    /// When the last redraw began: the time since moves the camera, and the animation when
    /// it runs in real time.
    last_instant: Instant,
    /// The sweep whose measured errors the title shows (`ViewerOptions::sweep`).
    sweep: Vec<crate::accuracy::SweepRow>,
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
                live.input.look(state == ElementState::Pressed);
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                live.input.cursor_moved(position.x, position.y, &mut live.view.camera);
                Ok(())
            }
            WindowEvent::RedrawRequested => match live.redraw(&self.options) {
                Ok(presented) => {
                    self.presented += presented.unwrap_or(false) as u64;
                    // Checked after a skipped frame too: a script that ends while the window
                    // has no area (minimised, or resized to a zero side) counts its frames
                    // there, and waited for ever when only presented frames could end it.
                    if live.finished(&self.options) {
                        event_loop.exit();
                    }
                    Ok(())
                }
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
        // SAFETY: the window outlives the surface (`Live` drops the GPU state first).
        let surface = unsafe { Surface::new(&ctx.device, display, handle)? };
        let ring = FrameRing::new(&ctx.device, false)?;
        let present = PresentPass::new(&ctx.device);
        println!("device: {}", ctx.device.info.describe());
        println!("{}", input::KEYS_HELP);
        let gpu = Gpu {
            frame: None,
            ring,
            swapchain: None,
            present,
            present_mode: options.present_mode,
            reported_clamps: Vec::new(),
            surface,
            ctx,
        };
        let view = View {
            camera: FlyCamera::from_camera(&scene.camera),
            loaded: scene.clone(),
            scene,
            time: options.time,
            paused: options.paused,
            step_once: false,
            last_instant: Instant::now(),
            sweep: options.sweep.clone(),
        };
        let mut live = Self {
            gpu,
            window,
            view,
            input: Input::new(),
            script: Script::new(&options.script),
            timings: Timings::new(),
            frames_rendered: 0,
            pending_screenshot: None,
        };
        let size = live.window.inner_size();
        live.resize(size)?;
        Ok(live)
    }

    fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        self.gpu.resize(size, &self.view.scene)
    }

    fn finished(&self, options: &ViewerOptions) -> bool {
        if !options.script.is_empty() {
            return self.script.ended() && self.pending_screenshot.is_none();
        }
        options.frames.is_some_and(|n| self.frames_rendered >= n as u64)
    }

    /// Draws one frame if the window has an area. Returns whether a frame was presented
    /// (`None` when nothing was attempted).
    fn redraw(&mut self, options: &ViewerOptions) -> Result<Option<bool>> {
        self.advance_script()?;
        let now = Instant::now();
        let dt = (now - self.view.last_instant).as_secs_f32().min(0.1);
        self.view.last_instant = now;
        self.input.fly(&mut self.view.camera, dt);
        let gpu = &mut self.gpu;
        if gpu.frame.is_none() {
            if let Some(extent) = gpu.swapchain.as_ref().map(|s| s.extent) {
                gpu.rebuild_frame(extent, &self.view.scene)?;
            }
        }
        let (Some(frame), Some(swapchain)) = (gpu.frame.as_mut(), gpu.swapchain.as_ref()) else {
            // Minimised: count scripted frames anyway so a script cannot hang on a hidden window.
            self.script.frame_done();
            std::thread::sleep(Duration::from_millis(10));
            return Ok(None);
        };
        // The last frame of `--frames` with `--screenshot` is saved.
        if options.frames.is_some_and(|n| self.frames_rendered + 1 == n as u64) && options.screenshot.is_some() {
            self.pending_screenshot = options.screenshot.clone();
        }
        let view = &mut self.view;
        if !view.paused || view.step_once {
            view.time += if options.script.is_empty() && options.frames.is_none() { dt } else { 1.0 / 60.0 };
            view.step_once = false;
        }
        {
            let s = frame.scene_mut();
            view.camera.apply(&mut s.camera);
            s.water = view.scene.water;
        }

        let slot = gpu.ring.begin()?;
        let slot_index = slot.index;
        let acquired = swapchain.acquire(slot_index)?;
        let Some(image_index) = acquired else {
            // Out of date: drop this frame's recording and rebuild for the window's size.
            gpu.ring.abandon()?;
            let size = self.window.inner_size();
            self.resize(size)?;
            return Ok(Some(false));
        };
        let image = swapchain.images[image_index as usize];
        frame.record(slot, view.time);
        let cmd = slot.cmd;
        let output = &frame.compose.output.image;
        let screenshot = self.pending_screenshot.take();
        if screenshot.is_some() {
            gpu.present.prepare_screenshot(swapchain.extent)?;
        }
        let present = &gpu.present;
        slot.timer.pass(cmd, PassId::Present, |cmd| {
            present.record(cmd, output, image, swapchain.extent, screenshot.is_some());
        });
        let waits = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.acquired[slot_index])
            .stage_mask(ACQUIRE_WAIT_STAGE)];
        let signals = [vk::SemaphoreSubmitInfo::default()
            .semaphore(swapchain.rendered[image_index as usize])
            .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)];
        gpu.ring.submit(&waits, &signals)?;
        if let Some((_, t)) = gpu.ring.take_fresh_timings() {
            self.timings.record(t);
        }
        let ok = swapchain.present(image_index)?;
        self.frames_rendered += 1;
        self.timings.presented(&gpu.ctx.device, self.frames_rendered);
        self.script.frame_done();
        if let Some(path) = screenshot {
            // A screenshot is an explicit request: waiting for its frame is what it asks for.
            gpu.ring.finish(|_, _| {})?;
            gpu.save_screenshot(&path)?;
        }
        let v = &self.view;
        self.timings.report(&self.window, &v.scene, &v.sweep, self.frames_rendered);
        if !ok {
            let size = self.window.inner_size();
            self.resize(size)?;
        }
        Ok(Some(true))
    }

    fn shutdown(self) -> ShutdownReport {
        self.timings.print_memory(&self.gpu.ctx.device, self.frames_rendered);
        let Live { gpu, window, .. } = self;
        let report = gpu.shutdown();
        drop(window);
        report
    }
}

impl Gpu {
    /// Recreates the swapchain for the window's size, and the frame if the size changed.
    fn resize(&mut self, size: PhysicalSize<u32>, scene: &Scene) -> Result<()> {
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
                self.rebuild_frame(sc.extent, scene)?;
            }
        }
        Ok(())
    }

    /// A new frame for `scene`: passes and targets follow its effects.
    fn rebuild_frame(&mut self, extent: vk::Extent2D, scene: &Scene) -> Result<()> {
        self.ctx.device.wait_idle()?;
        self.frame = None;
        let options = FrameOptions { camera_moves: true, ..FrameOptions::default() };
        let frame = Frame::new(&self.ctx.device, scene, extent, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, options)?;
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

    /// A new frame for `scene` after a change of its settings.
    fn rebuild_current(&mut self, scene: &Scene) -> Result<()> {
        match self.swapchain.as_ref().map(|s| s.extent) {
            Some(extent) => self.rebuild_frame(extent, scene),
            // Minimised: rebuild when the window comes back.
            None => {
                self.frame = None;
                Ok(())
            }
        }
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

    fn shutdown(self) -> ShutdownReport {
        let Gpu { frame, ring, swapchain, present, surface, ctx, .. } = self;
        let _ = ctx.device.wait_idle();
        drop((frame, ring, swapchain, present, surface));
        ctx.shutdown()
    }
}
