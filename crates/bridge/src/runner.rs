//! Runs episodes in-process: an agent against the simulator, one episode per task, in
//! parallel with results independent of the thread count.

use crate::agents::AgentKind;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use xhab_sim::env::{DiscreteEnv, Env, TaskConfig};
use xhab_sim::episode::{Dataset, Episode};
use xhab_sim::metrics::EpisodeMetrics;
use xhab_sim::world::World;
use xhab_types::Pose2;

/// How to run a benchmark.
#[derive(Debug, Clone)]
pub struct RunConfig {
    /// The agent.
    pub agent: AgentKind,
    /// The task settings.
    pub task: TaskConfig,
    /// Worker threads (1 = sequential).
    pub threads: usize,
    /// Keep each episode's trajectory (poses after each step).
    pub record_trajectories: bool,
}

/// The outcome of one episode that ran.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EpisodeRun {
    /// The episode's id.
    pub episode_id: String,
    /// Its metrics.
    pub metrics: EpisodeMetrics,
    /// Wall time of the episode, reset included (s).
    pub wall_s: f64,
    /// Poses from the start, one per step (when recorded).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub trajectory: Option<Vec<Pose2>>,
}

/// An episode that could not run, and why.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct InvalidRun {
    /// The episode's id.
    pub episode_id: String,
    /// Why, in words.
    pub reason: String,
}

/// What happened to one episode.
#[derive(Debug, Clone)]
pub enum Outcome {
    /// It ran.
    Ran(EpisodeRun),
    /// It was invalid for the agent.
    Invalid(InvalidRun),
}

/// Runs one episode with a fresh agent.
pub fn run_episode(world: &World, ep: &Episode, cfg: &RunConfig) -> Outcome {
    let t0 = Instant::now();
    let invalid = |reason: String| Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason });
    let grid = match world.grid_at(ep.start_position.z) {
        Ok(g) => g,
        Err(e) => return invalid(e.to_string()),
    };
    for g in &ep.goals {
        if (g.position.z - ep.start_position.z).abs() > xhab_sim::world::FLOOR_MATCH {
            return invalid(format!("goal at height {:.3} m is not on the start's floor", g.position.z));
        }
    }
    let mut env = match Env::new(grid, ep, cfg.task.clone()) {
        Ok(e) => e,
        Err(e) => return invalid(e.to_string()),
    };
    let mut agent = cfg.agent.build();
    agent.reset();
    let mut traj = cfg.record_trajectories.then(|| vec![env.pose()]);
    while !env.is_done() {
        let a = agent.act(&env);
        env.step(a);
        if let Some(t) = traj.as_mut() {
            t.push(env.pose());
        }
    }
    Outcome::Ran(EpisodeRun {
        episode_id: ep.episode_id.clone(),
        metrics: env.metrics(),
        wall_s: t0.elapsed().as_secs_f64(),
        trajectory: traj,
    })
}

/// Runs every episode of `ds`; results come back in the dataset's order whatever the thread
/// count. `progress` is called once per finished episode (from any thread).
pub fn run_dataset(world: &World, ds: &Dataset, cfg: &RunConfig, progress: &(dyn Fn() + Sync)) -> Vec<Outcome> {
    let run = |ep: &Episode| {
        let o = run_episode(world, ep, cfg);
        progress();
        o
    };
    if cfg.threads <= 1 {
        return ds.episodes.iter().map(run).collect();
    }
    // Grids are built once, before the workers start, so that no worker waits on another.
    for ep in &ds.episodes {
        let _ = world.grid_at(ep.start_position.z);
    }
    match rayon::ThreadPoolBuilder::new().num_threads(cfg.threads).build() {
        Ok(pool) => pool.install(|| ds.episodes.par_iter().map(run).collect()),
        Err(_) => ds.episodes.iter().map(run).collect(),
    }
}

/// Means over the episodes that ran, and totals.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Aggregate {
    /// Episodes that ran.
    pub episodes: usize,
    /// Mean success.
    pub success: f64,
    /// Mean SPL.
    pub spl: f64,
    /// Mean soft SPL.
    pub soft_spl: f64,
    /// Mean final distance to goal (m).
    pub distance_to_goal: f64,
    /// Mean actions per episode.
    pub steps: f64,
    /// Mean collisions per episode.
    pub collisions: f64,
    /// Wall time of the whole run (s).
    pub wall_s: f64,
    /// Actions per second of wall time over the whole run.
    pub steps_per_s: f64,
}

/// Aggregates episode runs; `wall_s` is the run's elapsed time (s).
pub fn aggregate(runs: &[&EpisodeRun], wall_s: f64) -> Aggregate {
    let n = runs.len().max(1) as f64;
    let mean = |f: &dyn Fn(&EpisodeMetrics) -> f64| runs.iter().map(|r| f(&r.metrics)).sum::<f64>() / n;
    let total_steps: f64 = runs.iter().map(|r| r.metrics.steps as f64).sum();
    Aggregate {
        episodes: runs.len(),
        success: mean(&|m| m.success),
        spl: mean(&|m| m.spl),
        soft_spl: mean(&|m| m.soft_spl),
        distance_to_goal: mean(&|m| m.distance_to_goal),
        steps: mean(&|m| m.steps as f64),
        collisions: mean(&|m| m.collisions as f64),
        wall_s,
        steps_per_s: if wall_s > 0.0 { total_steps / wall_s } else { 0.0 },
    }
}
