//! Running a study: every part a shard (or the whole study) owns, skipping parts already in
//! the folder, then (unsharded) merging them into results and the report.

use crate::part::{Part, Trajectory};
use crate::plan::{bench_options, plan, Plan, PlanError, RunPlan};
use crate::results::{merge, ExperimentRecord, Results, ResultsError};
use crate::shard::{parts, Shard};
use crate::spec::ExperimentSpec;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use xhab_bridge::benchmark::{run_bench_until, BenchError, BenchRun};
use xhab_bridge::runner::Outcome;

/// How to run a study.
#[derive(Debug, Clone)]
pub struct ExperimentOptions {
    /// The folder results go to (parts, runs, results, report).
    pub out: PathBuf,
    /// Run only this slice; `None`: everything, then merge and report.
    pub shard: Option<Shard>,
    /// Write the HTML report after merging (unsharded runs).
    pub report: bool,
}

/// What a study run reports as it goes.
#[derive(Debug, Clone)]
pub enum Progress<'a> {
    /// The plan: runs, episodes this invocation owns, and parts already done.
    Planned {
        /// The study's runs.
        plan: &'a Plan,
        /// Parts this invocation owns.
        parts: usize,
        /// Episodes in them.
        episodes: usize,
    },
    /// A part starts (or is found finished, `reused`).
    PartStarted {
        /// Its run.
        run: &'a RunPlan,
        /// First episode.
        first: usize,
        /// One past the last.
        end: usize,
        /// Already in the folder: skipped.
        reused: bool,
    },
    /// An episode of the current part finished: `(done, total)` in the part.
    Episode {
        /// Episodes of the part finished.
        done: usize,
        /// Episodes in the part (twice for compare runs).
        total: usize,
    },
    /// Warnings of a part's run (invalid episodes, unknown parameters).
    Warning(&'a str),
}

/// A finished study run.
#[derive(Debug)]
pub struct ExperimentRun {
    /// The runs.
    pub plan: Plan,
    /// Parts run now.
    pub ran: usize,
    /// Parts found finished and skipped.
    pub reused: usize,
    /// The merged results (unsharded runs).
    pub results: Option<Results>,
    /// The report's page (unsharded runs with `report`).
    pub report: Option<PathBuf>,
}

/// Why a study could not run.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// The runs could not be planned.
    #[error(transparent)]
    Plan(Box<PlanError>),
    /// The folder holds another study.
    #[error("{dir} holds results of another experiment (its experiment.json differs from this spec): choose another --out")]
    OtherStudy {
        /// The folder.
        dir: PathBuf,
    },
    /// A run's options are wrong.
    #[error("run {run}: {message}")]
    Options {
        /// The run.
        run: String,
        /// What is wrong.
        message: String,
    },
    /// A run failed.
    #[error("run {run}")]
    Bench {
        /// The run.
        run: String,
        /// Why.
        #[source]
        source: Box<BenchError>,
    },
    /// Writing parts, maps or results failed.
    #[error(transparent)]
    Results(Box<ResultsError>),
    /// The report could not be made.
    #[error(transparent)]
    Report(Box<crate::report::ReportError>),
    /// The SLURM submission failed.
    #[error(transparent)]
    Slurm(Box<crate::slurm::SlurmError>),
}

/// Errors are boxed in [`ExperimentError`] (they are large); `?` boxes them.
macro_rules! boxed_from {
    ($($t:ty => $v:ident),*) => {$(
        impl From<$t> for ExperimentError {
            fn from(e: $t) -> Self {
                ExperimentError::$v(Box::new(e))
            }
        }
    )*};
}
boxed_from!(PlanError => Plan, ResultsError => Results, crate::report::ReportError => Report, crate::slurm::SlurmError => Slurm);

/// Runs `spec` into `o.out`: its parts (all, or a shard's), skipping those already there;
/// unsharded, then merges them into `results.json`/`.csv` and the report.
pub fn run_experiment(spec: &ExperimentSpec, o: &ExperimentOptions, progress: &(dyn Fn(Progress<'_>) + Sync)) -> Result<ExperimentRun, ExperimentError> {
    run_experiment_until(spec, o, &AtomicBool::new(false), progress)
}

/// [`run_experiment`] that stops with a `Cancelled` bench error once `cancel` is set (e.g. on
/// Ctrl-C); the parts finished so far stay in the folder, so a rerun resumes after them.
pub fn run_experiment_until(spec: &ExperimentSpec, o: &ExperimentOptions, cancel: &AtomicBool, progress: &(dyn Fn(Progress<'_>) + Sync)) -> Result<ExperimentRun, ExperimentError> {
    let plan = prepare(spec, &o.out)?;
    let mine = parts(&plan, o.shard);
    progress(Progress::Planned { plan: &plan, parts: mine.len(), episodes: mine.iter().map(|p| p.end - p.first).sum() });
    let (mut ran, mut reused) = (0, 0);
    for p in &mine {
        let run = &plan.runs[p.run];
        let done = Part::path(&o.out, &run.id, p.first, p.end).exists();
        progress(Progress::PartStarted { run, first: p.first, end: p.end, reused: done });
        if done {
            reused += 1;
            continue;
        }
        let mut bo = bench_options(spec, run, p.first, p.end).map_err(|message| ExperimentError::Options { run: run.id.clone(), message })?;
        bo.record_trajectories = true;
        let b = run_bench_until(&bo, cancel, &|done, total| progress(Progress::Episode { done, total })).map_err(|source| ExperimentError::Bench { run: run.id.clone(), source: Box::new(source) })?;
        for w in &b.warnings {
            progress(Progress::Warning(w));
        }
        let part = to_part(spec, run, p.first, p.end, &b, &o.out)?;
        part.write(&o.out).map_err(ResultsError::from)?;
        ran += 1;
    }
    if o.shard.is_some() {
        return Ok(ExperimentRun { plan, ran, reused, results: None, report: None });
    }
    let (results, report) = merge_and_report(std::slice::from_ref(&o.out), &o.out, o.report)?;
    Ok(ExperimentRun { plan, ran, reused, results: Some(results), report })
}

/// Plans `spec` into the folder `out`: generates its episode sets and writes
/// `experiment.json`, or checks that the one there describes the same study.
pub fn prepare(spec: &ExperimentSpec, out: &Path) -> Result<Plan, ExperimentError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| ExperimentError::Results(Box::new(ResultsError::Io { path, source }))
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let plan = plan(spec, out)?;
    let record = ExperimentRecord { spec: spec.clone(), plan: plan.clone() };
    let record_path = ExperimentRecord::path(out);
    if record_path.exists() {
        if !ExperimentRecord::read(out)?.same_study(&record) {
            return Err(ExperimentError::OtherStudy { dir: out.to_path_buf() });
        }
    } else {
        let tmp = record_path.with_extension(format!("tmp{}", std::process::id()));
        std::fs::write(&tmp, serde_json::to_string_pretty(&record).unwrap_or_default() + "\n").map_err(io(&tmp))?;
        std::fs::rename(&tmp, &record_path).map_err(io(&record_path))?;
    }
    Ok(plan)
}

/// `xhab merge`: the parts in `dirs` (shards of one study) merged into `out`, then the
/// report when `report`; the results and the report's page.
pub fn merge_and_report(dirs: &[PathBuf], out: &Path, report: bool) -> Result<(Results, Option<PathBuf>), ExperimentError> {
    std::fs::create_dir_all(out).map_err(|source| ExperimentError::Results(Box::new(ResultsError::Io { path: out.to_path_buf(), source })))?;
    let results = merge(dirs, out)?;
    let page = if report { Some(crate::report::write_report(out)?) } else { None };
    Ok((results, page))
}

/// The part a bench run of episodes `first..end` makes; draws each floor's map once.
fn to_part(spec: &ExperimentSpec, run: &RunPlan, first: usize, end: usize, b: &BenchRun, dir: &Path) -> Result<Part, ExperimentError> {
    let mut indices = Vec::new();
    let mut invalid_indices = Vec::new();
    let mut trajectories = Vec::new();
    let scene = crate::plan::slug(&spec.scenes[run.scene].label());
    for (k, (ep, outcome)) in b.dataset.episodes.iter().zip(&b.outcomes).enumerate() {
        let index = first + k;
        let r = match outcome {
            Outcome::Invalid(_) => {
                invalid_indices.push(index);
                continue;
            }
            Outcome::Ran(r) => r,
        };
        indices.push(index);
        let z = ep.start_position.z;
        let (Ok(grid), Some(floor)) = (b.world.grid_at(z), b.world.floor_at(z)) else { continue };
        let map = format!("{scene}_floor{floor}");
        if !dir.join("maps").join(format!("{map}.yaml")).exists() {
            write_floor_map(&grid.occupancy_grid(), dir, &map).map_err(|message| ExperimentError::Options { run: run.id.clone(), message })?;
        }
        let goals: Vec<xhab_types::Point2> = ep.goals.iter().map(|g| g.position.xy()).collect();
        let mm = |x: f64| (x * 1000.0).round() / 1000.0;
        let pt = |p: xhab_types::Point2| [mm(p.x), mm(p.y)];
        let shortest = grid.field(&goals).path(&grid, ep.start_position.xy());
        trajectories.push(Trajectory {
            episode_id: ep.episode_id.clone(),
            index,
            map: format!("maps/{map}.yaml"),
            path: r.trajectory.as_deref().unwrap_or_default().iter().map(|p| pt(p.position())).collect(),
            shortest_path: shortest.into_iter().map(pt).collect(),
            start: pt(ep.start_position.xy()),
            goals: goals.into_iter().map(pt).collect(),
        });
    }
    let mut report = b.report.clone();
    report.episodes_file = run.episodes_label.clone();
    Ok(Part { run: run.id.clone(), first, end, report, indices, invalid_indices, trajectories })
}

/// Writes `DIR/maps/NAME.yaml` (+ image and picture): into a folder of this process first,
/// then moved in, YAML last, so that shards drawing the same map at once never leave half
/// of one.
fn write_floor_map(map: &xhab_types::OccupancyGrid, dir: &Path, name: &str) -> Result<(), String> {
    let tmp = dir.join("maps").join(format!(".tmp{}", std::process::id()));
    let (yaml, png) = xhab_bridge::setup::write_map(map, &tmp.join(name)).map_err(|e| format!("writing the floor map {}: {e}", tmp.display()))?;
    let mut files: Vec<PathBuf> = std::fs::read_dir(&tmp).map_err(|e| format!("{}: {e}", tmp.display()))?.flatten().map(|e| e.path()).filter(|p| *p != yaml && *p != png).collect();
    files.push(png);
    files.push(yaml);
    for f in files {
        let to = dir.join("maps").join(f.file_name().unwrap_or_default());
        std::fs::rename(&f, &to).map_err(|e| format!("{}: {e}", to.display()))?;
    }
    std::fs::remove_dir(&tmp).ok();
    Ok(())
}
