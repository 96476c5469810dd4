//! `underlight bench`: per-pass GPU times of the frame for the paper's configurations,
//! from timestamp queries, with validation off. Warm-up frames are discarded; each pass's
//! median, 5th and 95th percentile over the measured frames are reported, beside the frame
//! rates the paper measured on its GTX 260 (2009).
//!
//! - `configs`: the named configurations and how one is applied to a scene.
//! - `measure`: running the frames, per-pass statistics, `--compare-paths`, `--scaling`.
//! - `report`: the table, the CSV and the scaling table.

mod configs;
mod measure;
mod report;

pub use configs::{configs, move_camera_above_water, BenchConfig};
pub use measure::{
    buffer_difference, compare_paths, run_config, scaling, BenchResult, BufferDifference, PassCounts, PassStats, Series,
};
pub use report::{scaling_table, BenchReport};
