//! Runs episodes in-process: an agent against the simulator, one episode per task, in
//! parallel with results independent of the thread count.

use crate::agents::{AgentKind, DiscreteAgent};
use std::sync::atomic::{AtomicBool, Ordering};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;
use std::sync::Arc;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView};
use xhab_sim::physics_env::PhysicsEnv;
use xhab_sim::episode::{Dataset, Episode};
use xhab_sim::world::World;
use xhab_nav::navigator::AbortReason;
use crate::camera_capture::{capture, RenderStats};
pub use crate::outcome::{EpisodeRun, InvalidRun, Outcome};
pub use crate::run_config::{PhysicsSetup, RunConfig};

/// An environment made for one episode (one per episode: the variants' size difference
/// costs nothing).
#[allow(clippy::large_enum_variant)]
pub(crate) enum EpisodeEnv {
    /// Teleport-and-slide.
    Plain(KinematicEnv),
    /// Under physics.
    Physics(PhysicsEnv),
}

impl EpisodeEnv {
    /// The environment as the runner steps it.
    pub(crate) fn as_dyn(&mut self) -> &mut dyn DiscreteEnv {
        match self {
            EpisodeEnv::Plain(e) => e,
            EpisodeEnv::Physics(e) => e,
        }
    }
}

/// Why episode `ep` cannot run over `transport` (a ROS interface that knows one storey's
/// map): a goal on another storey; `None` when all goals are on the start's storey.
pub(crate) fn across_storeys(ep: &Episode, transport: &str) -> Option<String> {
    let g = ep.goals.iter().find(|g| (g.position.z - ep.start_position.z).abs() > xhab_sim::world::FLOOR_MATCH)?;
    Some(format!("goal at height {:.3} m is on another storey: episodes across storeys do not run over {transport} yet", g.position.z))
}

/// Checks episode `ep` (number `index`) for the run and builds its environment and grid, or
/// says why it cannot run.
pub(crate) fn make_env(world: &World, ep: &Episode, index: usize, cfg: &RunConfig) -> Result<(EpisodeEnv, Arc<xhab_sim::navgrid::NavGrid>), String> {
    let grid = world.grid_at(ep.start_position.z).map_err(|e| e.to_string())?;
    let cross = ep.goals.iter().find(|g| (g.position.z - ep.start_position.z).abs() > xhab_sim::world::FLOOR_MATCH);
    if let Some(g) = cross {
        // Across storeys: the discrete simulator walks the flights between them.
        if cfg.agent == AgentKind::Nav {
            return Err(format!("goal at height {:.3} m is on another storey: the nav agent plans on one storey's map", g.position.z));
        }
        return match &cfg.physics {
            Some(ph) => {
                let seed = cfg.seed.wrapping_add(index as u64);
                let e = PhysicsEnv::in_world(world, &ph.scene, ep, cfg.task.clone(), &ph.profile, ph.config.clone(), seed).map_err(|e| e.to_string())?;
                let grid = e.grid().clone();
                Ok((EpisodeEnv::Physics(e), grid))
            }
            None => {
                let env = KinematicEnv::in_world(world, ep, cfg.task.clone()).map_err(|e| e.to_string())?;
                let grid = env.grid().clone();
                Ok((EpisodeEnv::Plain(env), grid))
            }
        };
    }
    match &cfg.physics {
        Some(ph) => {
            let seed = cfg.seed.wrapping_add(index as u64);
            let e = PhysicsEnv::new(grid.clone(), &ph.scene, ep, cfg.task.clone(), &ph.profile, ph.config.clone(), seed).map_err(|e| e.to_string())?;
            if cfg.agent == AgentKind::Nav && cfg.nav.is_none() {
                return Err("the nav agent needs its navigation setup".into());
            }
            Ok((EpisodeEnv::Physics(e), grid))
        }
        None if cfg.agent == AgentKind::Nav => Err("the nav agent drives with velocities: it needs --physics".into()),
        None => Ok((EpisodeEnv::Plain(KinematicEnv::new(grid.clone(), ep, cfg.task.clone()).map_err(|e| e.to_string())?), grid)),
    }
}

/// Runs one episode (number `index` in its dataset) with a fresh agent.
pub fn run_episode(world: &World, ep: &Episode, index: usize, cfg: &RunConfig) -> Outcome {
    let t0 = Instant::now();
    let invalid = |reason: String| Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason });
    let (mut made, grid) = match make_env(world, ep, index, cfg) {
        Ok(m) => m,
        Err(reason) => return invalid(reason),
    };
    if let (EpisodeEnv::Physics(e), AgentKind::Nav, Some(setup)) = (&mut made, cfg.agent, &cfg.nav) {
        let goal = ep.goals[0].position.xy();
        return crate::nav_episode::run_nav(e, &grid, &world.scene, index, &ep.episode_id, goal, setup, cfg, t0);
    }
    let Some(agent) = cfg.agent.build() else {
        return invalid(format!("agent {} needs --physics and its navigation setup", cfg.agent.name()));
    };
    drive_episode(made, ep, index, cfg, agent, &AtomicBool::new(false), t0).unwrap_or_else(|| invalid("cancelled".into()))
}

/// Runs one episode (number `index` in its dataset) with `agent`, a discrete agent of any
/// kind (`cfg.agent` and `cfg.nav` are not used). Returns `None` when `cancel` was set
/// before the episode ended (it is read before each action).
pub fn run_episode_with(world: &World, ep: &Episode, index: usize, cfg: &RunConfig, agent: Box<dyn DiscreteAgent>, cancel: &AtomicBool) -> Option<Outcome> {
    let t0 = Instant::now();
    let owned;
    let cfg = if cfg.agent == AgentKind::Nav {
        owned = RunConfig { agent: AgentKind::Oracle, nav: None, ..cfg.clone() };
        &owned
    } else {
        cfg
    };
    match make_env(world, ep, index, cfg) {
        Ok((made, _)) => drive_episode(made, ep, index, cfg, agent, cancel, t0),
        Err(reason) => Some(Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason })),
    }
}

/// Steps a discrete agent through an episode until it is done (or `cancel` is set: `None`).
fn drive_episode(mut made: EpisodeEnv, ep: &Episode, index: usize, cfg: &RunConfig, mut agent: Box<dyn DiscreteAgent>, cancel: &AtomicBool, t0: Instant) -> Option<Outcome> {
    let invalid = |reason: String| Some(Outcome::Invalid(InvalidRun { episode_id: ep.episode_id.clone(), reason }));
    agent.reset();
    let env = made.as_dyn();
    let mut traj = cfg.record_trajectories.then(|| vec![env.pose()]);
    let mut stats = RenderStats::default();
    let mut step = 0u64;
    while !env.is_done() {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let frame = match cfg.sensors.as_deref() {
            Some(rig) => match capture(rig, env.pose(), env.height(), cfg.seed, index, step, &mut stats) {
                Ok(f) => Some(f),
                Err(reason) => return invalid(reason),
            },
            None => None,
        };
        let obs = env.observe();
        let a = agent.act_observed(env, &obs, frame.as_ref());
        env.step(a);
        step += 1;
        if let Some(t) = traj.as_mut() {
            t.push(env.pose());
        }
    }
    if cancel.load(Ordering::Relaxed) {
        return None;
    }
    let (sim_s, stuck, stuck_cause) = match &made {
        EpisodeEnv::Physics(p) => (Some(p.sim_s()), Some(p.stuck()), p.stuck_cause().map(str::to_string)),
        EpisodeEnv::Plain(_) => (None, None, None),
    };
    let env = made.as_dyn();
    Some(Outcome::Ran(EpisodeRun {
        episode_id: ep.episode_id.clone(),
        metrics: env.metrics(),
        wall_s: t0.elapsed().as_secs_f64(),
        trajectory: traj,
        sim_s,
        stuck,
        stuck_cause,
        abort_reason: None,
        final_localization: None,
        localization_error: None,
        render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)),
        ros: None,
    }))
}

/// A run stopped by its cancel flag before every episode had run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("the run was cancelled")]
pub struct Cancelled;

/// Makes a fresh agent for episode `index`; called once per episode, from any worker thread.
pub type AgentFactory<'a> = dyn Fn(usize) -> Box<dyn DiscreteAgent> + Sync + 'a;

/// Runs every episode of `ds` with agents from `agents` (one per episode), as
/// [`run_dataset`] does with the built-in agents: results in the dataset's order whatever the
/// thread count. Setting `cancel` (e.g. from another thread on Ctrl-C) ends the run early
/// with [`Cancelled`]; episodes not yet started are skipped.
pub fn run_dataset_with(world: &World, ds: &Dataset, cfg: &RunConfig, agents: &AgentFactory<'_>, cancel: &AtomicBool, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, Cancelled> {
    let outcomes = run_each(world, ds, cfg.threads, cancel, progress, &|i, ep| run_episode_with(world, ep, cfg.episode_index(i), cfg, agents(cfg.episode_index(i)), cancel))?;
    if cancel.load(Ordering::Relaxed) {
        return Err(Cancelled);
    }
    Ok(outcomes)
}

/// Runs every episode of `ds`; results come back in the dataset's order whatever the thread
/// count. `progress` is called once per finished episode (from any thread).
pub fn run_dataset(world: &World, ds: &Dataset, cfg: &RunConfig, progress: &(dyn Fn() + Sync)) -> Vec<Outcome> {
    // Nothing sets the flag, so the run cannot end cancelled.
    run_dataset_until(world, ds, cfg, &AtomicBool::new(false), progress).unwrap_or_default()
}

/// [`run_dataset`] that ends early with [`Cancelled`] once `cancel` is set (checked before
/// each episode; episodes not yet started are skipped).
pub fn run_dataset_until(world: &World, ds: &Dataset, cfg: &RunConfig, cancel: &AtomicBool, progress: &(dyn Fn() + Sync)) -> Result<Vec<Outcome>, Cancelled> {
    run_each(world, ds, cfg.threads, cancel, progress, &|i, ep| Some(run_episode(world, ep, cfg.episode_index(i), cfg)))
}

/// Runs `run` on every episode, in order or on `threads` workers, results in the dataset's
/// order; skips what is left once `cancel` is set, and fails with [`Cancelled`] if any
/// episode went without an outcome.
fn run_each(world: &World, ds: &Dataset, threads: usize, cancel: &AtomicBool, progress: &(dyn Fn() + Sync), run: &(dyn Fn(usize, &Episode) -> Option<Outcome> + Sync)) -> Result<Vec<Outcome>, Cancelled> {
    let one = |(i, ep): (usize, &Episode)| {
        if cancel.load(Ordering::Relaxed) {
            return None;
        }
        let o = run(i, ep);
        progress();
        o
    };
    let outcomes: Vec<Option<Outcome>> = if threads <= 1 {
        ds.episodes.iter().enumerate().map(one).collect()
    } else {
        // Grids are built once, before the workers start, so that no worker waits on another.
        for ep in &ds.episodes {
            let _ = world.grid_at(ep.start_position.z);
        }
        match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
            Ok(pool) => pool.install(|| ds.episodes.par_iter().enumerate().map(one).collect()),
            Err(_) => ds.episodes.iter().enumerate().map(one).collect(),
        }
    };
    outcomes.into_iter().map(|o| o.ok_or(Cancelled)).collect()
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
    /// Total simulated time (s), physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sim_s: Option<f64>,
    /// Simulated seconds per wall-clock second (sim_s / wall_s), physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub real_time_factor: Option<f64>,
    /// Fraction of episodes in which the robot got stuck, physics runs only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stuck: Option<f64>,
    /// Failed episodes by cause.
    pub failures: Failures,
    /// Mean localisation error (m) over episodes that report one (AMCL runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub localization_error_m: Option<f64>,
    /// Mean heading error (degrees) over episodes that report one (AMCL runs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub localization_error_deg: Option<f64>,
    /// Wall time over ROS divided by wall time in-process (`--compare-ros` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ros_overhead: Option<f64>,
    /// Camera frames rendered over the run (`--sensors` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub frames: Option<u64>,
    /// Wall time spent rendering them, summed over threads (s) (`--sensors` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render_s: Option<f64>,
    /// Frames per second of rendering time (`--sensors` runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub render_frames_per_s: Option<f64>,
}

/// Why episodes failed (each failed episode counts once, in the first matching cause, in
/// the order of [`failure_cause`]).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct Failures {
    /// The robot got stuck (physics).
    pub stuck: usize,
    /// The agent called stop outside the success radius.
    pub stopped_outside: usize,
    /// The step limit ran out before stop.
    pub step_limit: usize,
    /// The navigator gave up because the goal is blocked or cut off in its costmap (nav runs).
    #[serde(default)]
    pub goal_unreachable_for_costmap: usize,
    /// The navigator gave up for another reason (nav runs; `abort_reason` says which).
    #[serde(default)]
    pub aborted: usize,
}

/// Why an episode failed, `None` when it succeeded: `stuck`, `goal_unreachable_for_costmap`,
/// `aborted` (the navigator gave up otherwise), `stopped_outside` or `step_limit`.
pub fn failure_cause(r: &EpisodeRun) -> Option<&'static str> {
    if r.metrics.success >= 1.0 {
        return None;
    }
    Some(if r.stuck == Some(true) {
        "stuck"
    } else if r.abort_reason.as_deref() == Some(AbortReason::GoalUnreachableForCostmap.as_str()) {
        "goal_unreachable_for_costmap"
    } else if r.abort_reason.is_some() {
        "aborted"
    } else if r.metrics.called_stop {
        "stopped_outside"
    } else {
        "step_limit"
    })
}

