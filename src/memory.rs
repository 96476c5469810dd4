//! Memory over long runs: the process's resident memory and the GPU allocator's device
//! memory, sampled while a scene renders frame after frame (`underlight bench --soak N`).
//!
//! The frame path must keep both flat: no per-frame allocation of ours, and none of the
//! driver's that we provoke (docs/reliability.md: lavapipe kept a compiled shader variant per
//! draw while the frame's parameters were a uniform buffer, 24 MB a frame).

use crate::error::Result;
use crate::headless::SceneRenderer;
use crate::scene::Scene;
use crate::vk::device::Device;
use ash::vk;
use std::fmt;
use std::sync::Arc;

/// The process's resident set size in bytes (`VmRSS` of /proc/self/status), or None where
/// the platform has no such file.
pub fn resident_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

/// Device memory as gpu-allocator accounts it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct DeviceMemory {
    /// Live allocations and the bytes they use.
    pub allocations: usize,
    pub allocated_bytes: u64,
    /// Memory blocks taken from the driver and their capacity (allocations are carved from them).
    pub blocks: usize,
    pub capacity_bytes: u64,
}

impl DeviceMemory {
    pub fn of(device: &Device) -> Self {
        let report = device.allocator().generate_report();
        Self {
            allocations: report.allocations.len(),
            allocated_bytes: report.total_allocated_bytes,
            blocks: report.blocks.len(),
            capacity_bytes: report.total_capacity_bytes,
        }
    }
}

/// One live allocation of the device memory, by the name of the buffer or image it backs.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct NamedAllocation {
    pub name: String,
    pub bytes: u64,
}

/// Every live allocation, largest first (ties by name, so the order is stable).
pub fn allocations(device: &Device) -> Vec<NamedAllocation> {
    let report = device.allocator().generate_report();
    let mut out: Vec<NamedAllocation> =
        report.allocations.iter().map(|a| NamedAllocation { name: a.name.clone(), bytes: a.size }).collect();
    out.sort_by(|a, b| b.bytes.cmp(&a.bytes).then_with(|| a.name.cmp(&b.name)));
    out
}

/// What a renderer holds in device memory: each target and buffer it allocated, and the
/// most that was live at once while it rendered.
#[derive(Clone, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct FrameMemory {
    /// Allocations made since the renderer was created, largest first.
    pub allocations: Vec<NamedAllocation>,
    pub total_bytes: u64,
    /// The largest total seen at any sample (creation, after rendering, after read-back).
    pub peak_bytes: u64,
}

impl FrameMemory {
    /// The allocations live now that were not in `before` (by name and size), with the peak
    /// so far raised to their total.
    pub fn since(device: &Device, before: &[NamedAllocation], peak_bytes: u64) -> Self {
        let mut earlier = before.to_vec();
        let mut made = Vec::new();
        for a in allocations(device) {
            match earlier.iter().position(|e| *e == a) {
                Some(i) => {
                    earlier.swap_remove(i);
                }
                None => made.push(a),
            }
        }
        let total_bytes = made.iter().map(|a| a.bytes).sum();
        Self { allocations: made, total_bytes, peak_bytes: peak_bytes.max(total_bytes) }
    }
}

/// Memory after a number of frames.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct MemorySample {
    pub frame: u64,
    pub resident_bytes: Option<u64>,
    pub device: DeviceMemory,
}

impl MemorySample {
    pub fn now(device: &Device, frame: u64) -> Self {
        Self { frame, resident_bytes: resident_bytes(), device: DeviceMemory::of(device) }
    }
}

impl fmt::Display for MemorySample {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mib = |b: u64| b as f64 / (1024.0 * 1024.0);
        match self.resident_bytes {
            Some(r) => write!(f, "frame {:>6}: resident {:>8.1} MiB", self.frame, mib(r))?,
            None => write!(f, "frame {:>6}: resident (unknown on this platform)", self.frame)?,
        }
        let d = &self.device;
        write!(
            f,
            "; device {:.1} MiB in {} allocations, {} blocks of {:.1} MiB",
            mib(d.allocated_bytes),
            d.allocations,
            d.blocks,
            mib(d.capacity_bytes)
        )
    }
}

/// What a soak measured: a sample at each requested frame, in order.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SoakReport {
    pub scene: String,
    pub width: u32,
    pub height: u32,
    pub samples: Vec<MemorySample>,
}

impl SoakReport {
    /// Resident growth from the first sample to the last, bytes (negative: it shrank).
    pub fn resident_growth(&self) -> Option<i64> {
        let first = self.samples.first()?.resident_bytes? as i64;
        let last = self.samples.last()?.resident_bytes? as i64;
        Some(last - first)
    }

    /// Resident memory at the last sample relative to the first (1.0: flat).
    pub fn resident_ratio(&self) -> Option<f64> {
        let first = self.samples.first()?.resident_bytes? as f64;
        let last = self.samples.last()?.resident_bytes? as f64;
        Some(last / first)
    }
}

impl fmt::Display for SoakReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "soak of {:?} at {}×{}:", self.scene, self.width, self.height)?;
        for s in &self.samples {
            writeln!(f, "  {s}")?;
        }
        if let (Some(g), Some(r), [first, .., last]) =
            (self.resident_growth(), self.resident_ratio(), &self.samples[..])
        {
            let frames = (last.frame - first.frame).max(1);
            write!(
                f,
                "  resident change frame {} → {}: {:+.2} MiB ({:+.2} %), {:+.1} KiB per frame",
                first.frame,
                last.frame,
                g as f64 / (1024.0 * 1024.0),
                100.0 * (r - 1.0),
                g as f64 / 1024.0 / frames as f64
            )?;
        }
        Ok(())
    }
}

/// Renders `scene` for `frames` frames at `extent` (time advancing 1/60 s a frame, no
/// read-back) and samples memory after each frame number in `sample_at` (sorted; those
/// beyond `frames` are dropped).
pub fn soak(
    device: &Arc<Device>,
    scene: &Scene,
    extent: vk::Extent2D,
    frames: u64,
    sample_at: &[u64],
) -> Result<SoakReport> {
    let mut renderer = SceneRenderer::new(device, scene, extent)?;
    let mut samples = Vec::with_capacity(sample_at.len());
    let mut done = 0u64;
    // In chunks of at most 50 frames: the headless loop keeps every frame's timings until it
    // returns, and a soak must not grow memory of its own.
    for &at in sample_at.iter().filter(|&&f| f <= frames) {
        while done < at {
            let chunk = (at - done).min(50) as u32;
            renderer.render(chunk, done as f32 / 60.0, 1.0 / 60.0, false)?;
            done += chunk as u64;
        }
        samples.push(MemorySample::now(device, done));
    }
    Ok(SoakReport { scene: scene.name.clone(), width: extent.width, height: extent.height, samples })
}
