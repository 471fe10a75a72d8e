//! One file per command.

mod bench;
mod demo;
mod episodes;
mod experiment;
mod geodesic;
mod localize;
mod map;
mod merge;
mod navigate;
mod perf;
mod render;
mod report;
mod ros;
mod ros2;
mod scene;

use crate::cli::{Cli, Command};
use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use std::process::ExitCode;

/// Runs the parsed command.
pub fn run(cli: &Cli) -> Result<ExitCode> {
    match &cli.command {
        Command::Demo(a) => demo::run(a, cli.quiet),
        Command::Map(a) => map::run(a),
        Command::Episodes(a) => episodes::run(a),
        Command::Geodesic(a) => geodesic::run(a),
        Command::Bench(a) => bench::run(a, cli.quiet),
        Command::Perf(a) => perf::run(a),
        Command::Navigate(a) => navigate::run(a),
        Command::Render(a) => render::run(a),
        Command::Scene(c) => scene::run(c),
        Command::Ros(c) => ros::run(c),
        Command::Ros2(c) => ros2::run(c),
        Command::Localize(a) => localize::run(a),
        Command::Experiment(a) => experiment::run(a, cli.quiet),
        Command::Merge(a) => merge::run(a),
        Command::Report(a) => report::run(a),
    }
}

/// A progress bar on stderr that hides itself off a terminal or when quiet.
pub fn progress(len: usize, quiet: bool, what: &str) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let pb = ProgressBar::new(len as u64);
    pb.set_style(
        ProgressStyle::with_template("{prefix} [{bar:40}] {pos}/{len} {per_sec} eta {eta}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    pb.set_prefix(what.to_string());
    pb
}

/// Creates the parent folder of `path`.
pub fn ensure_parent(path: &std::path::Path) -> Result<()> {
    if let Some(p) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(p).map_err(|e| anyhow::anyhow!("creating folder {}: {e}", p.display()))?;
    }
    Ok(())
}
