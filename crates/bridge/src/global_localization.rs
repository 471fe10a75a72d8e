//! Global localisation trials: AMCL starts from particles spread uniformly over the map's free
//! space while the robot drives (under physics, steered by ground truth so that its motion does
//! not depend on the filter) from an episode's start to random goals; a trial converges when
//! the estimate comes within `tolerance` of the truth before `max_travel` metres of travel.

use crate::nav_agent::{episode_time, Localization, NavBrain, NavInputs, NavReply, NavSetup};
use crate::runner::PhysicsSetup;
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use xhab_nav::amcl::Amcl;
use xhab_sim::env::{EnvView, TaskConfig};
use xhab_sim::episode::Episode;
use xhab_sim::physics_env::PhysicsEnv;
use xhab_sim::world::World;
use xhab_types::OccupancyGrid;

/// How the trials run.
#[derive(Debug, Clone)]
pub struct GlobalLocConfig {
    /// Position error under which the filter counts as converged (m, default 0.2).
    pub tolerance: f64,
    /// Travel within which it must converge (m, default 10).
    pub max_travel: f64,
    /// Seed of trial i is `seed + i` (AMCL, odometry noise, goals).
    pub seed: u64,
}

/// One trial's outcome.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct GlobalLocTrial {
    /// The episode whose start it used.
    pub episode_id: String,
    /// Whether the error fell under the tolerance within the travel budget.
    pub converged: bool,
    /// Travel when it first did (m), if it did.
    pub travel_at_convergence_m: Option<f64>,
    /// Position error at the end of the trial (m).
    pub final_error_m: f64,
    /// Heading error at the end of the trial (degrees).
    pub final_error_deg: f64,
    /// Travel of the trial (m).
    pub travel_m: f64,
    /// Filter updates.
    pub updates: usize,
}

/// Runs one trial per episode of `episodes` (cycling until `trials`).
pub fn run_trials(world: &World, episodes: &[Episode], trials: usize, physics: &PhysicsSetup, setup: &NavSetup, map: Option<&OccupancyGrid>, cfg: &GlobalLocConfig) -> Vec<GlobalLocTrial> {
    let mut out = Vec::new();
    // Episodes whose start or goal the robot cannot use are passed over.
    for (i, ep) in episodes.iter().cycle().take(trials * 3).enumerate() {
        if out.len() == trials {
            break;
        }
        if let Some(t) = trial(world, ep, physics, setup, map, cfg, cfg.seed.wrapping_add(i as u64)) {
            out.push(t);
        }
    }
    out
}

fn trial(world: &World, ep: &Episode, physics: &PhysicsSetup, setup: &NavSetup, map: Option<&OccupancyGrid>, cfg: &GlobalLocConfig, seed: u64) -> Option<GlobalLocTrial> {
    let grid = world.grid_at(ep.start_position.z).ok()?;
    // A given map serves both; else the robot plans on the body-band map and AMCL localises
    // on the scan-plane map.
    let (map, amcl_map) = match map {
        Some(m) => (m.clone(), m.clone()),
        None => (grid.occupancy_grid(), crate::nav_agent::localization_map(setup, &grid, &world.scene).unwrap_or_else(|| grid.occupancy_grid())),
    };
    let task = TaskConfig { max_episode_steps: u32::MAX, ..Default::default() };
    let mut env = PhysicsEnv::new(grid.clone(), &physics.scene, ep, task, &physics.profile, physics.config.clone(), seed).ok()?;
    let mut sensor = setup.scan.as_ref()?.sensor(seed);
    let mount = setup.scan.as_ref()?.mount();
    let mut amcl = Amcl::new(&amcl_map, setup.params.amcl.clone(), seed);
    amcl.global_init();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed ^ 0x9e37_79b9_7f4a_7c15);
    let island = grid.island_at(ep.start_position.xy());
    let cells = grid.cells_on_islands(1.0);
    let drive = NavSetup { localization: Localization::GroundTruth, ..setup.clone() };
    // A random goal on the start's island, at least 1 m away.
    let new_goal = |rng: &mut rand_chacha::ChaCha8Rng, from: xhab_types::Point2| {
        (0..200).filter_map(|_| grid.sample_navigable_point(&cells, rng).map(|p| p.xy())).find(|p| grid.island_at(*p) == island && p.dist(from) > 1.0)
    };
    let mut brain = NavBrain::new(&drive, &map, &map, new_goal(&mut rng, env.pose().position())?, env.pose(), None, seed);
    let period = setup.params.dwa.controller_period.max(1e-3);
    let (mut travel, mut last) = (0.0, env.pose().position());
    let mut t0 = 0.0;
    let (mut converged_at, mut updates, mut err) = (None, 0usize, [f64::INFINITY, 180.0]);
    let mut sched = crate::nav_agent::ScanSchedule::new(setup.scan_period);
    let mut goals = 0;
    while travel < cfg.max_travel && env.sim_s() < 600.0 {
        let t = episode_time(env.sim_s());
        let scan = if sched.due(t) {
            sched.taken += 1;
            Some(sensor.scan(env.pose(), grid.floor_z).ok()?)
        } else {
            None
        };
        if let Some(s) = &scan {
            if amcl.update(env.odometry(), s, mount) {
                updates += 1;
                let est = amcl.estimate().pose;
                let truth = env.pose();
                err = [est.position().dist(truth.position()), xhab_types::normalize_angle(est.yaw - truth.yaw).abs().to_degrees()];
                if converged_at.is_none() && err[0] < cfg.tolerance {
                    converged_at = Some(travel);
                }
            }
        }
        let inp = NavInputs { t: t - t0, odom: env.odometry(), twist: env.robot().twist(), truth: Some(env.pose()), scan: scan.as_ref(), scan_mount: mount };
        match brain.step(inp) {
            NavReply::Drive(tw) => env.step_twist(tw, period),
            NavReply::Stop | NavReply::Abort => {
                goals += 1;
                if goals > 50 {
                    break;
                }
                brain = NavBrain::new(&drive, &map, &map, new_goal(&mut rng, env.pose().position())?, env.pose(), None, seed);
                t0 = t;
            }
        }
        let p = env.pose().position();
        travel += p.dist(last);
        last = p;
    }
    Some(GlobalLocTrial {
        episode_id: ep.episode_id.clone(),
        converged: converged_at.is_some(),
        travel_at_convergence_m: converged_at,
        final_error_m: err[0],
        final_error_deg: err[1],
        travel_m: travel,
        updates,
    })
}

