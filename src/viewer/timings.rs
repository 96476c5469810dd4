//! What the viewer reports as it runs: per-pass GPU times in the title and on the terminal,
//! the frames each pass ran in, and the memory early on and at exit.

use crate::frame::PassTimings;
use crate::headless::median_timings;
use crate::memory::MemorySample;
use crate::passes::PassId;
use crate::vk::device::Device;
use std::collections::VecDeque;
use std::time::{Duration, Instant};
use winit::window::Window;

/// Frames whose timings the title's medians are taken over.
const TIMING_WINDOW: usize = 60;

/// The frame whose memory the viewer compares with its memory at exit (after warm-up).
const MEMORY_SAMPLE_FRAME: u64 = 100;

pub(super) struct Timings {
    /// The last `TIMING_WINDOW` frames' pass timings, oldest first.
    recent: VecDeque<PassTimings>,
    /// Frames each pass was recorded in, indexed as `PassId::ALL`.
    pub(super) pass_frames: [u64; PassId::ALL.len()],
    last_report: Instant,
    frames_since_report: u32,
    /// Memory after frame `MEMORY_SAMPLE_FRAME`, printed beside the memory at exit: a window
    /// left open must not grow.
    memory_early: Option<MemorySample>,
}

impl Timings {
    pub(super) fn new() -> Self {
        Self {
            recent: VecDeque::with_capacity(TIMING_WINDOW),
            pass_frames: [0; PassId::ALL.len()],
            last_report: Instant::now(),
            frames_since_report: 0,
            memory_early: None,
        }
    }

    /// Keeps a retired frame's timings and counts the passes it recorded.
    pub(super) fn record(&mut self, timings: &PassTimings) {
        // Keep the last 60 frames' timings, reusing the oldest entry's storage once full.
        let mut entry = if self.recent.len() == TIMING_WINDOW {
            self.recent.pop_front().unwrap_or_default()
        } else {
            PassTimings::default()
        };
        entry.passes.clone_from(&timings.passes);
        for (id, _) in &entry.passes {
            if let Some(i) = PassId::ALL.iter().position(|p| p == id) {
                self.pass_frames[i] += 1;
            }
        }
        self.recent.push_back(entry);
    }

    /// Frame `frames_rendered` was presented: the memory is sampled after the warm-up.
    pub(super) fn presented(&mut self, device: &Device, frames_rendered: u64) {
        if frames_rendered == MEMORY_SAMPLE_FRAME {
            self.memory_early = Some(MemorySample::now(device, frames_rendered));
        }
    }

    /// Puts the per-pass GPU times in the title twice a second and on the terminal every 2 s.
    /// `sweep`: a sweep's rows; the error it measured for the setting nearest to the scene's
    /// current one is shown with the times.
    pub(super) fn report(
        &mut self,
        window: &Window,
        scene: &crate::scene::Scene,
        sweep: &[crate::accuracy::SweepRow],
        frames_rendered: u64,
    ) {
        self.frames_since_report += 1;
        let elapsed = self.last_report.elapsed();
        if elapsed < Duration::from_millis(500) || self.recent.is_empty() {
            return;
        }
        // Twice a second, not per frame: the copy for the median is fine here.
        let frames: Vec<PassTimings> = self.recent.iter().cloned().collect();
        let median = median_timings(&frames);
        let fps = self.frames_since_report as f64 / elapsed.as_secs_f64();
        let passes: Vec<String> = median.passes.iter().map(|(id, ms)| format!("{} {:.1}", id.name(), ms)).collect();
        let mut line = format!("{:.1} fps | GPU ms: {} | total {:.1}", fps, passes.join(" "), median.total_ms());
        if let Some(row) = crate::accuracy::nearest_setting(sweep, &scene.name, &scene.effects) {
            line += &format!(
                " | est. error {:.2} (sweep: {} {}² × {}²)",
                crate::accuracy::tune_error(row),
                row.estimator,
                row.caustic_grid,
                row.caustic_subdivision
            );
        }
        window.set_title(&format!("underlight — {} — {line}", scene.name));
        if frames_rendered.is_multiple_of(4) || elapsed > Duration::from_secs(2) {
            println!("{line}");
        }
        self.last_report = Instant::now();
        self.frames_since_report = 0;
    }

    /// At exit: the memory after the warm-up and now, if the viewer got past the warm-up.
    pub(super) fn print_memory(&self, device: &Device, frames_rendered: u64) {
        if let Some(early) = &self.memory_early {
            print_memory(early);
            print_memory(&MemorySample::now(device, frames_rendered));
        }
    }
}

fn print_memory(sample: &MemorySample) {
    println!(
        "memory at frame {}: resident {} bytes, device {} bytes in {} allocations",
        sample.frame,
        sample.resident_bytes.map_or("unknown".to_string(), |b| b.to_string()),
        sample.device.allocated_bytes,
        sample.device.allocations
    );
}
