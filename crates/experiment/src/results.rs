//! A study's results: one bench report per run (`runs/RUN/bench.json`, as `xhab bench --out`
//! writes it), and `results.json` / `results.csv` with one row per run × episode. Built by
//! merging the parts that runs or shards left, so a sharded study merges into the same
//! results as one run (timing figures aside).

use crate::part::{Part, PartError, Trajectory};
use crate::plan::{Plan, RunPlan, SkippedRun};
use crate::spec::ExperimentSpec;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use xhab_bridge::report::{aggregate, episodes_csv, BenchReport, EpisodeReport, InvalidReport};
use xhab_bridge::runner::Aggregate;

/// Version of the results layout.
pub const RESULTS_VERSION: u32 = 1;

/// What an experiment folder holds about its study: `DIR/experiment.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ExperimentRecord {
    /// The spec, as read (paths expanded).
    pub spec: ExperimentSpec,
    /// Its runs.
    pub plan: Plan,
}

impl ExperimentRecord {
    /// The record's file in `dir`.
    pub fn path(dir: &Path) -> PathBuf {
        dir.join("experiment.json")
    }

    /// Reads `dir`'s record.
    pub fn read(dir: &Path) -> Result<Self, ResultsError> {
        let path = Self::path(dir);
        let text = std::fs::read_to_string(&path).map_err(|source| ResultsError::Io { path: path.clone(), source })?;
        serde_json::from_str(&text).map_err(|e| ResultsError::Format { path, message: e.to_string() })
    }

    /// Whether `other` describes the same study (same spec, runs and episode counts; the
    /// folders generated episode sets live in may differ).
    pub fn same_study(&self, other: &Self) -> bool {
        let key = |r: &ExperimentRecord| (r.spec.clone(), r.plan.runs.iter().map(|x| (x.id.clone(), x.episodes_label.clone(), x.episodes)).collect::<Vec<_>>());
        key(self) == key(other)
    }
}

/// `results.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Results {
    /// Layout version.
    pub schema_version: u32,
    /// The study's name.
    pub experiment: String,
    /// What it asks.
    pub description: String,
    /// One summary per run, in plan order.
    pub runs: Vec<RunResult>,
    /// Combinations the study leaves out, and why.
    pub skipped: Vec<SkippedRun>,
    /// One row per run × valid episode, in plan and episode order.
    pub episodes: Vec<ResultRow>,
}

/// A run's summary.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunResult {
    /// The run's id (its folder under `runs/`).
    pub id: String,
    /// The scene's name.
    pub scene: String,
    /// The agent's name.
    pub agent: String,
    /// The configuration's name.
    pub configuration: String,
    /// Whether it ran under physics.
    pub physics: bool,
    /// Whether agent and simulator ran as ROS nodes.
    pub ros: bool,
    /// Whether agent and simulator ran as ROS 2 nodes.
    #[serde(default)]
    pub ros2: bool,
    /// The seed.
    pub seed: u64,
    /// The episodes file.
    pub episodes_file: String,
    /// Means over valid episodes (wall time: the parts' sum).
    pub aggregate: Aggregate,
    /// Episodes left out as invalid.
    pub invalid: usize,
    /// The run's bench report, relative to the folder.
    pub report: String,
}

/// One episode of one run.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ResultRow {
    /// The run's id.
    pub run: String,
    /// The scene's name.
    pub scene: String,
    /// The agent's name.
    pub agent: String,
    /// The configuration's name.
    pub configuration: String,
    /// Whether it ran under physics.
    pub physics: bool,
    /// Whether agent and simulator ran as ROS nodes.
    pub ros: bool,
    /// Whether agent and simulator ran as ROS 2 nodes.
    #[serde(default)]
    pub ros2: bool,
    /// The seed.
    pub seed: u64,
    /// The episode's index in its set.
    pub episode_index: usize,
    /// Its metrics, as `xhab bench` reports them.
    #[serde(flatten)]
    pub metrics: EpisodeReport,
}

/// Why results could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// Reading or writing failed.
    #[error("{path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// A file is not what it should be.
    #[error("{path}: {message}")]
    Format {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A part could not be read.
    #[error(transparent)]
    Part(#[from] PartError),
    /// The folders hold different studies.
    #[error("{a} and {b} hold different experiments (their experiment.json differ): merge shards of one study only")]
    OtherStudy {
        /// One folder.
        a: PathBuf,
        /// The other.
        b: PathBuf,
    },
    /// Some episodes of a run have no part yet.
    #[error("run {run} is incomplete: episodes {missing} have not run (run the missing shards, or `xhab experiment` without --shard, first)")]
    Incomplete {
        /// The run.
        run: String,
        /// The missing episode ranges, `a..b, c..d`.
        missing: String,
    },
    /// Two parts of a run overlap without covering the same episodes.
    #[error("run {run}: parts {a} and {b} overlap")]
    Overlap {
        /// The run.
        run: String,
        /// One part.
        a: String,
        /// The other.
        b: String,
    },
}

/// A run whose parts are all present, merged.
#[derive(Debug, Clone)]
pub struct MergedRun {
    /// The run's report, as `xhab bench --out` writes it.
    pub report: BenchReport,
    /// Each reported episode's index in the set.
    pub indices: Vec<usize>,
    /// The episodes' trajectories.
    pub trajectories: Vec<Trajectory>,
}

/// Merges the parts of `run` found in `dirs`: they must tile its episodes (the same part in
/// several folders counts once).
pub fn merge_run(run: &RunPlan, dirs: &[PathBuf]) -> Result<MergedRun, ResultsError> {
    let mut found: Vec<(usize, usize, PathBuf)> = Vec::new();
    for d in dirs {
        for p in Part::find(d, &run.id)? {
            if !found.iter().any(|f| (f.0, f.1) == (p.0, p.1)) {
                found.push(p);
            }
        }
    }
    found.sort();
    let mut missing = Vec::new();
    let mut at = 0;
    let mut chosen: Vec<&(usize, usize, PathBuf)> = Vec::new();
    for f in &found {
        if f.0 < at {
            let prev = chosen.last().map_or_else(String::new, |c| c.2.display().to_string());
            return Err(ResultsError::Overlap { run: run.id.clone(), a: prev, b: f.2.display().to_string() });
        }
        if f.0 > at {
            missing.push(format!("{at}..{}", f.0));
        }
        at = f.1;
        chosen.push(f);
    }
    if at < run.episodes {
        missing.push(format!("{at}..{}", run.episodes));
    }
    if !missing.is_empty() {
        return Err(ResultsError::Incomplete { run: run.id.clone(), missing: missing.join(", ") });
    }
    let parts: Vec<Part> = chosen.iter().map(|c| Part::read(&c.2)).collect::<Result<_, _>>()?;
    let mut episodes = Vec::new();
    let mut indices = Vec::new();
    let mut invalid = Vec::new();
    let mut trajectories = Vec::new();
    let mut wall_s = 0.0;
    for p in &parts {
        episodes.extend(p.report.episodes.iter().cloned());
        indices.extend(&p.indices);
        invalid.extend(p.report.invalid.reasons.iter().cloned());
        trajectories.extend(p.trajectories.iter().cloned());
        wall_s += p.report.aggregate.wall_s;
    }
    let mut report = parts[0].report.clone();
    report.episodes_file = run.episodes_label.clone();
    report.aggregate = aggregate(&episodes, wall_s);
    if parts.len() > 1 {
        // A comparison with an in-process run holds for one part only.
        report.ros_check = None;
        report.aggregate.ros_overhead = None;
    } else {
        report.aggregate.ros_overhead = parts[0].report.aggregate.ros_overhead;
    }
    report.episodes = episodes;
    report.invalid = InvalidReport::new(invalid);
    Ok(MergedRun { report, indices, trajectories })
}

/// Merges every run of the study in `dirs` into `out`: `runs/RUN/bench.json`, `bench.csv`
/// and `trajectories.json`, then `results.json` and `results.csv`. Fails, naming the run and
/// episodes, when a part is missing.
pub fn merge(dirs: &[PathBuf], out: &Path) -> Result<Results, ResultsError> {
    let first = dirs.first().ok_or_else(|| ResultsError::Format { path: out.to_path_buf(), message: "no folder to merge".into() })?;
    let record = ExperimentRecord::read(first)?;
    for d in &dirs[1..] {
        if !record.same_study(&ExperimentRecord::read(d)?) {
            return Err(ResultsError::OtherStudy { a: first.clone(), b: d.clone() });
        }
    }
    let write = |path: PathBuf, text: String| -> Result<(), ResultsError> {
        if let Some(p) = path.parent() {
            std::fs::create_dir_all(p).map_err(|source| ResultsError::Io { path: p.to_path_buf(), source })?;
        }
        std::fs::write(&path, text).map_err(|source| ResultsError::Io { path, source })
    };
    if !ExperimentRecord::path(out).exists() {
        write(ExperimentRecord::path(out), serde_json::to_string_pretty(&record).unwrap_or_default() + "\n")?;
    }
    // Floor maps the trajectories are drawn on travel with the results.
    for d in dirs.iter().filter(|d| d.as_path() != out) {
        copy_missing(&d.join("maps"), &out.join("maps"))?;
    }
    let spec = &record.spec;
    let mut results = Results {
        schema_version: RESULTS_VERSION,
        experiment: spec.name.clone(),
        description: spec.description.clone(),
        runs: Vec::new(),
        skipped: record.plan.skipped.clone(),
        episodes: Vec::new(),
    };
    for run in &record.plan.runs {
        let m = merge_run(run, dirs)?;
        let c = &spec.configurations[run.configuration];
        let (scene, agent, configuration) = (spec.scenes[run.scene].label(), spec.agents[run.agent].label(), c.label());
        let dir = out.join("runs").join(&run.id);
        write(dir.join("bench.json"), m.report.to_json().map_err(|e| ResultsError::Format { path: dir.join("bench.json"), message: e.to_string() })?)?;
        write(dir.join("bench.csv"), episodes_csv(&m.report.episodes))?;
        write(dir.join("trajectories.json"), serde_json::to_string(&m.trajectories).unwrap_or_default() + "\n")?;
        for (e, &i) in m.report.episodes.iter().zip(&m.indices) {
            results.episodes.push(ResultRow {
                run: run.id.clone(),
                scene: scene.clone(),
                agent: agent.clone(),
                configuration: configuration.clone(),
                physics: c.physics,
                ros: c.ros,
                ros2: c.ros2,
                seed: run.seed,
                episode_index: i,
                metrics: e.clone(),
            });
        }
        results.runs.push(RunResult {
            id: run.id.clone(),
            scene,
            agent,
            configuration,
            physics: c.physics,
            ros: c.ros,
            ros2: c.ros2,
            seed: run.seed,
            episodes_file: run.episodes_label.clone(),
            aggregate: m.report.aggregate.clone(),
            invalid: m.report.invalid.count,
            report: format!("runs/{}/bench.json", run.id),
        });
    }
    write(out.join("results.json"), serde_json::to_string_pretty(&results).unwrap_or_default() + "\n")?;
    write(out.join("results.csv"), results_csv(&results))?;
    Ok(results)
}

/// Reads `DIR/results.json`.
pub fn read_results(dir: &Path) -> Result<Results, ResultsError> {
    let path = dir.join("results.json");
    let text = std::fs::read_to_string(&path).map_err(|source| ResultsError::Io { path: path.clone(), source })?;
    serde_json::from_str(&text).map_err(|e| ResultsError::Format { path, message: e.to_string() })
}

/// `results.csv`: one line per run × valid episode (`ros2` last: columns are only added at
/// the end).
pub fn results_csv(r: &Results) -> String {
    let mut s = String::from("run,scene,agent,configuration,physics,ros,seed,episode_index,episode_id,success,spl,soft_spl,distance_to_goal,steps,collisions,path_length,start_distance,called_stop,failure,sim_s,wall_s,ros2\n");
    let q = |t: &str| if t.contains([',', '"', '\n']) { format!("\"{}\"", t.replace('"', "\"\"")) } else { t.to_string() };
    for row in &r.episodes {
        let e = &row.metrics;
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            q(&row.run), q(&row.scene), q(&row.agent), q(&row.configuration), row.physics, row.ros, row.seed, row.episode_index, q(&e.episode_id),
            e.success, e.spl, e.soft_spl, e.distance_to_goal, e.steps, e.collisions, e.path_length, e.start_distance, e.called_stop,
            e.failure.as_deref().unwrap_or(""), e.sim_s.map_or_else(String::new, |x| x.to_string()), e.wall_s, row.ros2
        ));
    }
    s
}

/// Copies the files of `from` that `to` lacks (flat folders).
fn copy_missing(from: &Path, to: &Path) -> Result<(), ResultsError> {
    let Ok(entries) = std::fs::read_dir(from) else { return Ok(()) };
    std::fs::create_dir_all(to).map_err(|source| ResultsError::Io { path: to.to_path_buf(), source })?;
    for e in entries.flatten() {
        let dest = to.join(e.file_name());
        if !dest.exists() {
            std::fs::copy(e.path(), &dest).map_err(|source| ResultsError::Io { path: dest.clone(), source })?;
        }
    }
    Ok(())
}

/// Whether two results agree in everything but timing (wall and render times, real-time
/// factors, rates, ROS overheads and waits): what a sharded study merged must share with
/// the same study run whole.
pub fn same_results(a: &Results, b: &Results) -> bool {
    strip_timing(serde_json::to_value(a).unwrap_or_default()) == strip_timing(serde_json::to_value(b).unwrap_or_default())
}

/// `v` without timing fields (any depth).
pub fn strip_timing(v: serde_json::Value) -> serde_json::Value {
    const TIMING: [&str; 7] = ["wall_s", "steps_per_s", "real_time_factor", "render_s", "render_frames_per_s", "ros_overhead", "stack_wait_s"];
    match v {
        serde_json::Value::Object(m) => serde_json::Value::Object(m.into_iter().filter(|(k, _)| !TIMING.contains(&k.as_str())).map(|(k, v)| (k, strip_timing(v))).collect()),
        serde_json::Value::Array(a) => serde_json::Value::Array(a.into_iter().map(strip_timing).collect()),
        x => x,
    }
}
