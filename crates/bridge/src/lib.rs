//! Wiring between agents and environments.
//!
//! [`agents`]: the agents `xhab bench --agent` can run; [`benchmark`]: a benchmark as data
//! and [`benchmark::run_bench`], the one entry point every front end calls; [`runner`]: in-process episode runs,
//! sequential or parallel with identical results; [`setup`]: environments built from the
//! options the CLI and the Python package share; [`report`]: the benchmark report;
//! [`gym`]: a Gymnasium-style PointNav environment (reset, step, reward), single or batched.
//! One entry point per command the CLI runs: [`scene_perf::measure_scene`] (`perf`),
//! [`navigate::navigate_once`], [`demo::run_demo`], [`global_localization::run_localize`]
//! (`localize`), and the ROS nodes' builders in [`ros`] (ROS 1) and `ros2` (ROS 2, feature
//! `ros2`), whose simulator nodes share [`robot_io`].
#![warn(missing_docs)]

pub mod agents;
pub mod benchmark;
mod camera_capture;
pub mod demo;
pub mod explore;
pub mod external_stack;
pub mod exploration_run;
pub mod global_localization;
pub mod gym;
pub mod map_picture;
pub mod nav_agent;
mod nav_episode;
pub mod outcome;
pub mod nav_perf;
pub mod navigate;
pub mod report;
pub mod run_config;
pub mod runner;
pub mod scan_source;
pub mod scene_perf;
pub mod setup;
pub mod ros;
pub mod robot_io;
#[cfg(feature = "ros2")]
pub mod ros2;
