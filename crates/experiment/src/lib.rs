//! Experiments as files: a study ([`ExperimentSpec`], read from YAML) expanded into runs
//! ([`plan`]), run whole or as shards ([`run_experiment`]), merged into results
//! ([`merge`]) and shown as an HTML report ([`report::write_report`]); [`slurm`] submits a
//! sharded study as a SLURM array job.

pub mod execute;
pub mod part;
pub mod plan;
pub mod report;
pub mod results;
pub mod shard;
pub mod slurm;
pub mod spec;

pub use execute::{merge_and_report, run_experiment, run_experiment_until, ExperimentError, ExperimentOptions, ExperimentRun, Progress};
pub use plan::{plan, Plan, RunPlan};
pub use results::{merge, Results};
pub use shard::Shard;
pub use spec::ExperimentSpec;
