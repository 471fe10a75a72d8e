//! `xhab experiment`: a study from a YAML file, run whole, as one shard, or submitted to
//! SLURM. Parses the flags, calls the library, shows progress and prints the runs' table.

use crate::cli::ExperimentArgs;
use anyhow::{Context, Result};
use indicatif::MultiProgress;
use std::path::Path;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use xhab_experiment::execute::{run_experiment, ExperimentOptions, Progress};
use xhab_experiment::slurm::{submit_experiment, SlurmOptions};
use xhab_experiment::{ExperimentSpec, Results};

pub fn run(a: &ExperimentArgs, quiet: bool) -> Result<ExitCode> {
    let spec = ExperimentSpec::read(&a.spec)?;
    let out = a.out.clone().unwrap_or_else(|| Path::new("results").join(xhab_experiment::plan::slug(&spec.name)));
    if a.slurm {
        let abs = |p: &Path| std::path::absolute(p).with_context(|| format!("resolving {}", p.display()));
        let o = SlurmOptions {
            xhab: std::env::current_exe().context("finding the xhab binary")?,
            spec: abs(&a.spec)?,
            out: abs(&out)?,
            workdir: std::env::current_dir().context("the current folder")?,
            shards: a.shards,
            cpus_per_task: spec.threads,
            partition: a.partition.clone(),
            time: a.time.clone(),
            name: spec.name.clone(),
        };
        let s = submit_experiment(&spec, &o)?;
        println!("slurm: array job {} ({} shards, {}), merge job {} after it; results in {}", s.array_job, a.shards, s.array_script.display(), s.merge_job, out.display());
        return Ok(ExitCode::SUCCESS);
    }
    let bars = if quiet { MultiProgress::with_draw_target(indicatif::ProgressDrawTarget::hidden()) } else { MultiProgress::new() };
    let overall = bars.add(super::progress(0, quiet, "experiment"));
    let part = bars.add(super::progress(0, quiet, "run"));
    let base = AtomicUsize::new(0);
    let in_part = AtomicUsize::new(0);
    let o = ExperimentOptions { out: out.clone(), shard: a.shard, report: !a.no_report };
    let r = run_experiment(&spec, &o, &|p| match p {
        Progress::Planned { plan, parts, episodes } => {
            overall.set_length(episodes as u64);
            if !quiet {
                let _ = bars.println(format!("xhab: {} runs ({} skipped as not applicable), {parts} parts here, {episodes} episodes", plan.runs.len(), plan.skipped.len()));
            }
        }
        Progress::PartStarted { run, first, end, reused } => {
            let n = end - first;
            base.fetch_add(in_part.swap(if reused { 0 } else { n }, Ordering::Relaxed), Ordering::Relaxed);
            if reused {
                base.fetch_add(n, Ordering::Relaxed);
                overall.set_position(base.load(Ordering::Relaxed) as u64);
            }
            part.set_prefix(run.id.clone());
            part.set_length(n as u64);
            part.set_position(if reused { n as u64 } else { 0 });
        }
        Progress::Episode { done, total } => {
            part.set_length(total as u64);
            part.set_position(done as u64);
            // Compare runs count each episode twice; the overall bar counts episodes.
            let n = in_part.load(Ordering::Relaxed);
            let k = if total > n && n > 0 { done * n / total } else { done };
            overall.set_position((base.load(Ordering::Relaxed) + k) as u64);
        }
        Progress::Warning(w) => {
            let _ = bars.println(format!("xhab: warning: {w}"));
        }
    })?;
    part.finish_and_clear();
    overall.finish_and_clear();
    eprintln!("xhab: {} parts run, {} already finished (skipped)", r.ran, r.reused);
    match &r.results {
        Some(res) => print_results(res, &out),
        None => println!("shard {} done in {}; when every shard has run: xhab merge {}", a.shard.map_or_else(String::new, |s| s.to_string()), out.display(), out.display()),
    }
    if let Some(p) = &r.report {
        println!("report: {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// One line per run: the configuration's metrics.
pub fn print_results(r: &Results, dir: &Path) {
    println!("{:<44} {:>8} {:>8} {:>8} {:>8} {:>8}", "run", "episodes", "success", "spl", "soft_spl", "wall_s");
    for run in &r.runs {
        let a = &run.aggregate;
        println!("{:<44} {:>8} {:>8.3} {:>8.3} {:>8.3} {:>8.2}", run.id, a.episodes, a.success, a.spl, a.soft_spl, a.wall_s);
    }
    for s in &r.skipped {
        println!("skipped {} / {} / {}: {}", s.scene, s.agent, s.configuration, s.reason);
    }
    println!("results: {} and {}", dir.join("results.json").display(), dir.join("results.csv").display());
}
