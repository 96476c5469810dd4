//! The speed–accuracy trade (`underlight reference`, `underlight sweep`): the reference
//! buffers, cached by scene and settings; a sweep over the method's settings measuring each
//! one's GPU time and its error against the reference; the Pareto front; CSV and plot.
//!
//! - `reference_cache`: the reference buffers, cached by scene and settings.
//! - `configs`: the settings a sweep varies and the sweep's own.
//! - `measure`: each setting's GPU time and error against the reference.
//! - `report`: the Pareto front, CSV, table and plot.
//! - `tune`: the setting a user asks for (`underlight tune`): the cheapest under an error
//!   bound, or the most accurate within a time budget.

mod configs;
mod measure;
mod reference_cache;
mod report;
mod tune;

pub use configs::{SweepAxes, SweepSpec};
pub use measure::{run_sweep, SweepRow};
pub use reference_cache::{cached_reference, default_cache_dir, Progress};
pub use report::{csv, mark_pareto, plot, ranked_error, table};
pub use tune::{effects_block, nearest_setting, pick, tune_error, TuneGoal, TuneMiss};
