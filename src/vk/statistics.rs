//! Per-pass pipeline-statistics queries: how much work each pass handed each shader stage.
//!
//! Timestamps say how long a pass took on one device; these counts say what it asked of the
//! device, and they mean the same on any driver: how many geometry-shader invocations ran and
//! how many primitives they emitted, how many fragments were shaded. So a pass's cost can be
//! read as work × price per unit, and a change that moves the time can be told apart from one
//! that moves the work (the footprint hats drawn as quads shaded a sixth of the sprites'
//! fragments: docs/performance.md). Only where a mode asks for them (`bench` and `render
//! --pipeline-statistics`): the queries are cheap, but on some GPUs they serialise work
//! between passes, so timed runs without them stay as they were.
//!
//! [`PassTimer`](super::timing::PassTimer) owns one [`StatisticsPool`] per frame in flight
//! when asked, and brackets each pass with one query, as it does with its timestamps.

use super::device::Device;
use super::timing::read_available;
use crate::error::{Result, VkResultExt};
use ash::vk;
use serde::Serialize;
use std::sync::Arc;

/// The counters each query takes, in the order Vulkan writes them (by flag bit).
const COUNTED: vk::QueryPipelineStatisticFlags = vk::QueryPipelineStatisticFlags::from_raw(
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::GEOMETRY_SHADER_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
        | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw()
        | vk::QueryPipelineStatisticFlags::COMPUTE_SHADER_INVOCATIONS.as_raw(),
);
/// Values per query: the counters above, then the availability word.
const VALUES: usize = 7;

/// One pass's work, per shader stage, in one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct StageCounts {
    pub vertex_invocations: u64,
    pub geometry_invocations: u64,
    /// Primitives the geometry shader emitted (a strip of 4 vertices is 2 triangles).
    pub geometry_primitives: u64,
    /// Primitives that left clipping towards the rasteriser.
    pub clipped_primitives: u64,
    pub fragment_invocations: u64,
    pub compute_invocations: u64,
}

impl StageCounts {
    /// The column headings of `row`, in its order.
    pub const HEADINGS: [&'static str; 6] = ["VS", "GS", "GS prims", "clip prims", "FS", "CS"];

    pub fn row(&self) -> [u64; 6] {
        [
            self.vertex_invocations,
            self.geometry_invocations,
            self.geometry_primitives,
            self.clipped_primitives,
            self.fragment_invocations,
            self.compute_invocations,
        ]
    }

    fn from_values(v: &[u64; VALUES]) -> Self {
        Self {
            vertex_invocations: v[0],
            geometry_invocations: v[1],
            geometry_primitives: v[2],
            clipped_primitives: v[3],
            fragment_invocations: v[4],
            compute_invocations: v[5],
        }
    }
}

/// A table of passes' counts: one row per (name, counts), one column per stage.
pub fn counts_table<'a>(rows: impl IntoIterator<Item = (&'a str, StageCounts)>) -> String {
    use std::fmt::Write as _;
    let mut out = format!("{:<12}", "pass");
    for h in StageCounts::HEADINGS {
        let _ = write!(out, " {h:>12}");
    }
    for (name, counts) in rows {
        let _ = write!(out, "\n{name:<12}");
        for v in counts.row() {
            let _ = write!(out, " {v:>12}");
        }
    }
    out
}

/// The pipeline-statistics query pool of one frame in flight: query i counts pass i.
pub struct StatisticsPool {
    pool: vk::QueryPool,
    capacity: u32,
    /// Reused read-back storage: the counters and availability per query.
    results: Vec<[u64; VALUES]>,
    device: Arc<Device>,
}

impl StatisticsPool {
    /// `None` where the device offers no pipeline-statistics queries.
    pub fn new(device: &Arc<Device>, name: &str, capacity: u32) -> Result<Option<Self>> {
        if !device.has_pipeline_statistics() {
            return Ok(None);
        }
        let info = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .query_count(capacity)
            .pipeline_statistics(COUNTED);
        let pool = unsafe { device.raw.create_query_pool(&info, None) }.call("vkCreateQueryPool")?;
        device.set_name(pool, name);
        Ok(Some(Self { pool, capacity, results: vec![[0; VALUES]; capacity as usize], device: device.clone() }))
    }

    /// Resets every query (in the command buffer, before the frame's first pass).
    pub fn reset(&self, cmd: vk::CommandBuffer) {
        unsafe { self.device.raw.cmd_reset_query_pool(cmd, self.pool, 0, self.capacity) };
    }

    /// Opens query `index` (outside any render pass: each pass begins and ends its own).
    pub fn begin(&self, cmd: vk::CommandBuffer, index: u32) {
        unsafe { self.device.raw.cmd_begin_query(cmd, self.pool, index, vk::QueryControlFlags::empty()) };
    }

    pub fn end(&self, cmd: vk::CommandBuffer, index: u32) {
        unsafe { self.device.raw.cmd_end_query(cmd, self.pool, index) };
    }

    /// The first `n` queries' counts into `out` (cleared first); false, leaving `out` untouched,
    /// while one is not available. Call only after the frame's fence signalled.
    pub fn read(&mut self, n: usize, out: &mut Vec<StageCounts>) -> Result<bool> {
        let results = &mut self.results[..n];
        if !read_available(&self.device, self.pool, results)? {
            return Ok(false);
        }
        out.clear();
        out.extend(results.iter().map(StageCounts::from_values));
        Ok(true)
    }
}

impl Drop for StatisticsPool {
    fn drop(&mut self) {
        unsafe { self.device.raw.destroy_query_pool(self.pool, None) };
    }
}
