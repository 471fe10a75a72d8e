//! The speed of the native navigation loop (`xhab perf SCENE --nav`): the nav agent under
//! physics with the lidar and AMCL, on one thread, over a fixed set of episodes (generated
//! with Habitat's rules from a fixed seed on the scene's lowest floor).

use crate::agents::AgentKind;
use crate::nav_agent::{Localization, NavSetup};
use crate::runner::{run_dataset, EpisodeRun, Outcome, RunConfig};
use crate::scan_source::ScanSource;
use crate::setup::{generate, physics_setup, PhysicsOptions, SetupError};
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;
use xhab_sim::env::TaskConfig;
use xhab_sim::world::World;

/// Episodes in the fixed set.
pub const NAV_PERF_EPISODES: usize = 10;
/// Seed the fixed set is generated with.
pub const NAV_PERF_SEED: u64 = 1;

/// Figures of one timed run of the navigation loop.
#[derive(Debug, Clone, Serialize)]
pub struct NavPerf {
    /// Simulated seconds per wall-clock second, whole episodes (setup included), one thread.
    pub nav_real_time_factor: f64,
    /// Simulated time over the set (s).
    pub nav_sim_s: f64,
    /// Wall time over the set (s).
    pub nav_wall_s: f64,
    /// Episodes that ran.
    pub nav_episodes: usize,
    /// Mean success over them.
    pub nav_success: f64,
    /// Mean SPL over them.
    pub nav_spl: f64,
}

/// Why the navigation loop could not be timed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum NavPerfError {
    /// The episodes, the robot or the physics world could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The default navigation parameters did not load.
    #[error(transparent)]
    Params(#[from] xhab_nav::ros_params::ParamError),
}

/// Times the nav agent (default parameters sized to `robot`, a built-in profile name or
/// YAML file; the robot's lidar; AMCL) on the fixed episode set of `world` (`scene_id` names
/// the scene in the episodes), on one thread.
pub fn nav_perf(world: &World, scene_id: &str, robot: &str) -> Result<NavPerf, NavPerfError> {
    let ds = generate(world, scene_id, "auto", NAV_PERF_EPISODES, NAV_PERF_SEED, scene_id)?;
    let physics = physics_setup(world, &PhysicsOptions { robot: robot.to_string(), ..Default::default() })?;
    let (params, _no_files_no_warnings) = crate::benchmark::nav_params(&[], Some(&physics.profile))?;
    let rays = crate::setup::ray_scene(&world.scene)?;
    let scan = ScanSource::lidar(Arc::new(rays), physics.profile.laser.lidar());
    let nav = NavSetup { params, map: None, localization: Localization::Amcl, scan: Some(scan), scan_period: 0.1 };
    let cfg = RunConfig { agent: AgentKind::Nav, task: TaskConfig::default(), threads: 1, record_trajectories: false, physics: Some(physics), seed: 0, nav: Some(nav), sensors: None, episode_indices: None };
    let t = Instant::now();
    let outcomes = run_dataset(world, &ds, &cfg, &|| {});
    let wall_s = t.elapsed().as_secs_f64();
    let runs: Vec<&EpisodeRun> = outcomes.iter().filter_map(|o| if let Outcome::Ran(r) = o { Some(r) } else { None }).collect();
    let eps: Vec<crate::report::EpisodeReport> = runs.iter().map(|r| crate::report::EpisodeReport::from(*r)).collect();
    let agg = crate::report::aggregate(&eps, wall_s);
    let sim_s = agg.sim_s.unwrap_or(0.0);
    Ok(NavPerf { nav_real_time_factor: if wall_s > 0.0 { sim_s / wall_s } else { 0.0 }, nav_sim_s: sim_s, nav_wall_s: wall_s, nav_episodes: runs.len(), nav_success: agg.success, nav_spl: agg.spl })
}
