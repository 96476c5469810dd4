//! Per-pass GPU timing with timestamp queries.
//!
//! Every pass is recorded through [`PassTimer::pass`], which opens a debug label and writes a
//! timestamp before and after the pass, so the names in the timing table, in validation
//! messages and in GPU debuggers are the same. Each frame in flight owns its own query pool;
//! results are read only after that frame's fence has signalled, so reading never stalls.
//!
//! Asked for, the timer also counts each pass's work per shader stage with a
//! pipeline-statistics query (`statistics.rs`), read with the times.
//!
//! The backend knows no pass of the method: a timed pass is anything with a label
//! ([`TimedPass`]); the method's `passes::PassId` is one, and `frame::PassTimings` the table
//! of its times.

use super::device::Device;
use super::statistics::{StageCounts, StatisticsPool};
use crate::error::{Result, VkResultExt};
use ash::vk;
use std::ffi::CStr;
use std::fmt;
use std::sync::Arc;

/// What a timed pass is called: its debug label, which is also its name in the timing table
/// and in validation messages.
pub trait TimedPass: Copy + Eq + Ord + fmt::Debug + 'static {
    fn label(self) -> &'static CStr;
    fn name(self) -> &'static str {
        self.label().to_str().unwrap_or("?")
    }
}

/// GPU milliseconds per pass of one frame, in recording order, and where the timer counts
/// them, each pass's work per shader stage (`counts[i]` is `passes[i]`'s; empty otherwise).
#[derive(Clone, Debug)]
pub struct PassTimings<P> {
    pub passes: Vec<(P, f64)>,
    pub counts: Vec<StageCounts>,
}

impl<P> Default for PassTimings<P> {
    fn default() -> Self {
        Self { passes: Vec::new(), counts: Vec::new() }
    }
}

impl<P: TimedPass> PassTimings<P> {
    pub fn get(&self, id: P) -> Option<f64> {
        self.passes.iter().find(|(p, _)| *p == id).map(|(_, ms)| *ms)
    }

    /// Each counted pass with its work per shader stage, in recording order (none where the
    /// timer did not count).
    pub fn counted(&self) -> impl Iterator<Item = (P, StageCounts)> + '_ {
        self.passes.iter().zip(&self.counts).map(|((p, _), c)| (*p, *c))
    }

    /// The pass's work per shader stage, where the timer counted it.
    pub fn counts(&self, id: P) -> Option<StageCounts> {
        self.counted().find(|(p, _)| *p == id).map(|(_, c)| c)
    }

    /// Sum of the passes (not the frame's wall time: gaps between passes are excluded).
    pub fn total_ms(&self) -> f64 {
        self.passes.iter().map(|(_, ms)| ms).sum()
    }
}

impl<P: TimedPass> fmt::Display for PassTimings<P> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{:<12} {:>10}", "pass", "GPU ms")?;
        for (id, ms) in &self.passes {
            writeln!(f, "{:<12} {:>10.3}", id.name(), ms)?;
        }
        write!(f, "{:<12} {:>10.3}", "total", self.total_ms())
    }
}

/// The timestamp query pool of one frame in flight.
pub struct PassTimer<P> {
    pool: vk::QueryPool,
    capacity_passes: u32,
    /// Passes recorded into the current frame, in order; query 2i / 2i+1 are pass i's ends.
    recorded: Vec<P>,
    /// Reused read-back storage: (value, availability) per query.
    results: Vec<[u64; 2]>,
    valid_mask: u64,
    ns_per_tick: f64,
    /// With `statistics` asked for on a device that has them: query i counts pass i.
    statistics: Option<StatisticsPool>,
    device: Arc<Device>,
}

impl<P: TimedPass> PassTimer<P> {
    /// `statistics`: also count each pass's work per stage (where the device can).
    pub fn new(device: &Arc<Device>, name: &str, capacity_passes: u32, statistics: bool) -> Result<Self> {
        let info =
            vk::QueryPoolCreateInfo::default().query_type(vk::QueryType::TIMESTAMP).query_count(capacity_passes * 2);
        let pool = unsafe { device.raw.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        device.set_name(pool, name);
        let statistics = if statistics {
            match StatisticsPool::new(device, &format!("{name}, statistics"), capacity_passes) {
                Ok(s) => s,
                Err(e) => {
                    unsafe { device.raw.destroy_query_pool(pool, None) };
                    return Err(e);
                }
            }
        } else {
            None
        };
        let bits = device.info.capabilities.graphics_timestamp_valid_bits.unwrap_or(64);
        Ok(Self {
            pool,
            capacity_passes,
            recorded: Vec::with_capacity(capacity_passes as usize),
            results: vec![[0; 2]; capacity_passes as usize * 2],
            valid_mask: timestamp_mask(bits),
            ns_per_tick: device.limits().timestamp_period as f64,
            statistics,
            device: device.clone(),
        })
    }

    /// Starts a frame: resets the pool (in the command buffer, before any pass).
    pub fn begin_frame(&mut self, cmd: vk::CommandBuffer) {
        self.recorded.clear();
        unsafe { self.device.raw.cmd_reset_query_pool(cmd, self.pool, 0, self.capacity_passes * 2) };
        if let Some(statistics) = &self.statistics {
            statistics.reset(cmd);
        }
    }

    /// Records one pass: label, begin timestamp, the pass itself, end timestamp.
    ///
    /// Panics if more passes are recorded in one frame than the pool was made for: a
    /// programming error, not an input error.
    pub fn pass<R>(&mut self, cmd: vk::CommandBuffer, id: P, record: impl FnOnce(vk::CommandBuffer) -> R) -> R {
        let index = self.recorded.len() as u32;
        assert!(index < self.capacity_passes, "more than {} timed passes in one frame", self.capacity_passes);
        self.recorded.push(id);
        let dev = &self.device;
        dev.begin_label(cmd, id.label());
        // Not every layer version reports command-buffer labels with its messages (1.3.239's
        // synchronization validation does not), so the pass is also declared as the phase.
        dev.set_phase(id.name());
        unsafe { dev.raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::TOP_OF_PIPE, self.pool, 2 * index) };
        if let Some(statistics) = &self.statistics {
            statistics.begin(cmd, index);
        }
        let r = record(cmd);
        if let Some(statistics) = &self.statistics {
            statistics.end(cmd, index);
        }
        unsafe { dev.raw.cmd_write_timestamp2(cmd, vk::PipelineStageFlags2::BOTTOM_OF_PIPE, self.pool, 2 * index + 1) };
        dev.end_label(cmd);
        dev.set_phase("recording, between passes");
        r
    }

    /// Reads the frame's timings (and counts) into `out`. Call only after the frame's fence
    /// signalled. Returns false when the frame recorded no pass or a result is not available
    /// (`out`'s times then untouched).
    pub fn read(&mut self, out: &mut PassTimings<P>) -> Result<bool> {
        let n = self.recorded.len();
        if n == 0 {
            return Ok(false);
        }
        let results = &mut self.results[..2 * n];
        if !read_available(&self.device, self.pool, results)? {
            return Ok(false);
        }
        match &mut self.statistics {
            Some(statistics) => {
                if !statistics.read(n, &mut out.counts)? {
                    return Ok(false);
                }
            }
            None => out.counts.clear(),
        }
        out.passes.clear();
        for (i, id) in self.recorded.iter().enumerate() {
            let ticks = ticks_between(results[2 * i][0], results[2 * i + 1][0], self.valid_mask);
            out.passes.push((*id, ticks as f64 * self.ns_per_tick * 1e-6));
        }
        Ok(true)
    }
}

impl<P> Drop for PassTimer<P> {
    fn drop(&mut self) {
        unsafe { self.device.raw.destroy_query_pool(self.pool, None) };
    }
}

/// Reads the first `results.len()` queries of `pool`, each as its values followed by its
/// availability word (64-bit); true when every one was available. Never waits: call after
/// the fence of the frame that wrote them.
pub(super) fn read_available<const N: usize>(
    device: &Device,
    pool: vk::QueryPool,
    results: &mut [[u64; N]],
) -> Result<bool> {
    unsafe {
        device.raw.get_query_pool_results(
            pool,
            0,
            results,
            vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WITH_AVAILABILITY,
        )
    }
    .or_else(|e| if e == vk::Result::NOT_READY { Ok(()) } else { Err(e) })
    .call("vkGetQueryPoolResults")?;
    Ok(results.iter().all(|r| r[N - 1] != 0))
}

/// The mask of the bits a timestamp actually holds (`timestampValidBits`).
pub fn timestamp_mask(valid_bits: u32) -> u64 {
    if valid_bits >= 64 {
        u64::MAX
    } else {
        (1u64 << valid_bits) - 1
    }
}

/// Ticks from `begin` to `end`, correct across a wrap of a counter of fewer than 64 bits.
pub fn ticks_between(begin: u64, end: u64, mask: u64) -> u64 {
    (end & mask).wrapping_sub(begin & mask) & mask
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_wrap_within_valid_bits() {
        let m = timestamp_mask(36);
        assert_eq!(m, (1 << 36) - 1);
        // A counter that wrapped between the two writes.
        assert_eq!(ticks_between(m - 9, 5, m), 15);
        // Garbage above the valid bits is ignored.
        assert_eq!(ticks_between(0xF000_0000_0000_0000 | 7, 0xA000_0000_0000_0000 | 12, m), 5);
        assert_eq!(ticks_between(100, 250, timestamp_mask(64)), 150);
    }
}
