//! Global localisation trials: AMCL starts from particles spread uniformly over the map's free
//! space while the robot drives (under physics, steered by ground truth so that its motion does
//! not depend on the filter) from an episode's start to random goals; a trial converges when
//! the estimate comes within `tolerance` of the truth before `max_travel` metres of travel.

use crate::benchmark::{nav_params, ParamError, ParamFile};
use crate::nav_agent::{episode_time, Localization, NavStack, NavInputs, NavReply, NavSetup};
use crate::runner::PhysicsSetup;
use crate::scan_source::ScanSource;
use crate::setup::{self, PhysicsOptions, SceneOptions, SetupError};
use rand::SeedableRng;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use xhab_nav::amcl::{Amcl, AmclParams};
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

impl Default for GlobalLocConfig {
    fn default() -> Self {
        Self { tolerance: 0.2, max_travel: 10.0, seed: 0 }
    }
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

/// What `xhab localize` runs, as its flags give it.
#[derive(Debug, Clone)]
pub struct LocalizeOptions {
    /// The SCENE argument: a file or `procedural[:SEED]`.
    pub scene: String,
    /// How to read it; the grids are built for the robot's radius unless one is given.
    pub scene_options: SceneOptions,
    /// Episodes whose starts the trials use (Habitat PointNav `.json.gz` or `.json`).
    pub episodes: PathBuf,
    /// Number of trials.
    pub trials: usize,
    /// Tolerance, travel budget and seed of the trials.
    pub config: GlobalLocConfig,
    /// The map AMCL localises on (map_server YAML); `None`: the scene cut at the lidar's height.
    pub map: Option<PathBuf>,
    /// ROS parameter files, layered in order (`FILE[@NAMESPACE]`).
    pub nav_params: Vec<ParamFile>,
    /// Particles spread over the free space at the start (AMCL's max_particles; at least 1).
    pub particles: usize,
    /// The robot (its radius, lidar and costmap shape) and its physics.
    pub physics: PhysicsOptions,
}

/// The trials' results; serialized, the JSON `xhab localize --out` writes.
#[derive(Debug, Clone, Serialize)]
pub struct LocalizeReport {
    /// The SCENE argument.
    pub scene: String,
    /// Trials that ran.
    pub trials: usize,
    /// Convergence tolerance (m).
    pub tolerance_m: f64,
    /// Particles spread at the start.
    pub particles: usize,
    /// The AMCL parameters in effect.
    pub amcl: AmclParams,
    /// Travel budget (m).
    pub max_travel_m: f64,
    /// Fraction of the trials that converged.
    pub converged_fraction: f64,
    /// Mean travel at convergence over the converged trials (m; 0 without any).
    pub mean_travel_at_convergence_m: f64,
    /// Fraction of the trials within tolerance at their end.
    pub within_tolerance_at_end_fraction: f64,
    /// Wall time of the trials (s).
    pub wall_s: f64,
    /// Each trial.
    pub per_trial: Vec<GlobalLocTrial>,
    /// Warnings for the user (unknown nav parameters), in order (not in the JSON).
    #[serde(skip)]
    pub warnings: Vec<String>,
}

impl LocalizeReport {
    /// Trials that converged.
    pub fn converged(&self) -> usize {
        self.per_trial.iter().filter(|t| t.converged).count()
    }

    /// Trials within tolerance at their end.
    pub fn within_tolerance_at_end(&self) -> usize {
        self.per_trial.iter().filter(|t| t.final_error_m < self.tolerance_m).count()
    }
}

/// Why the trials could not run. Messages name the flag or file, as the CLI spells them.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LocalizeError {
    /// The scene, robot, physics, episodes or map could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The nav parameter files could not be loaded.
    #[error(transparent)]
    NavParams(#[from] ParamError),
    /// No particle to spread.
    #[error("--particles must be at least 1")]
    NoParticles,
}

/// Runs the global localisation trials `o` describes: the robot (profile, radius, lidar,
/// physics) on the scene, AMCL with the nav parameters sized to it, one trial per episode
/// start (cycling) until `o.trials`.
pub fn run_localize(o: &LocalizeOptions) -> Result<LocalizeReport, LocalizeError> {
    if o.particles == 0 {
        return Err(LocalizeError::NoParticles);
    }
    let profile = setup::robot_profile(&o.physics.robot)?;
    let mut scene_options = o.scene_options.clone();
    scene_options.agent_radius.get_or_insert(profile.radius);
    let world = setup::load_geometry(&o.scene, &scene_options)?;
    let ds = setup::read_episodes(&o.episodes)?;
    let physics = setup::physics_setup(&world, &o.physics)?;
    let (mut params, warnings) = nav_params(&o.nav_params, Some(&profile))?;
    params.amcl.max_particles = o.particles;
    let rays = setup::ray_scene(&world.scene)?;
    let nav = NavSetup { params, map: None, localization: Localization::Amcl, scan: Some(ScanSource::lidar(Arc::new(rays), profile.laser.lidar())), scan_period: 0.1 };
    let map = o.map.as_deref().map(setup::load_static_map).transpose()?;
    let t = Instant::now();
    let trials = run_trials(&world, &ds.episodes, o.trials, &physics, &nav, map.as_ref(), &o.config);
    let wall_s = t.elapsed().as_secs_f64();
    let n = trials.len().max(1) as f64;
    let conv = trials.iter().filter(|t| t.converged).count();
    let mean_travel = trials.iter().filter_map(|t| t.travel_at_convergence_m).sum::<f64>() / conv.max(1) as f64;
    let still = trials.iter().filter(|t| t.final_error_m < o.config.tolerance).count();
    Ok(LocalizeReport {
        scene: o.scene.clone(),
        trials: trials.len(),
        tolerance_m: o.config.tolerance,
        particles: o.particles,
        amcl: nav.params.amcl,
        max_travel_m: o.config.max_travel,
        converged_fraction: conv as f64 / n,
        mean_travel_at_convergence_m: mean_travel,
        within_tolerance_at_end_fraction: still as f64 / n,
        wall_s,
        per_trial: trials,
        warnings,
    })
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
    let mut brain = NavStack::new(&drive, &map, &map, new_goal(&mut rng, env.pose().position())?, env.pose(), None, seed);
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
                brain = NavStack::new(&drive, &map, &map, new_goal(&mut rng, env.pose().position())?, env.pose(), None, seed);
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

#[cfg(test)]
mod tests {
    use super::*;

    fn options(dir: &std::path::Path) -> LocalizeOptions {
        let world = setup::load_world("procedural:1", &SceneOptions::default()).unwrap();
        let ds = setup::generate(&world, "procedural:1", "auto", 2, 1, "procedural:1").unwrap();
        std::fs::create_dir_all(dir).unwrap();
        let episodes = dir.join("eps.json.gz");
        xhab_sim::episode::write_dataset(&ds, &episodes).unwrap();
        LocalizeOptions {
            scene: "procedural:1".into(),
            scene_options: SceneOptions::default(),
            episodes,
            trials: 3,
            config: GlobalLocConfig { max_travel: 2.0, ..Default::default() },
            map: None,
            nav_params: Vec::new(),
            particles: 500,
            physics: PhysicsOptions { robot: "turtlebot3_burger".into(), ..Default::default() },
        }
    }

    #[test]
    fn trials_run_and_the_report_counts_them() {
        let dir = std::env::temp_dir().join(format!("xhab-localize-{}", std::process::id()));
        let o = options(&dir);
        let r = run_localize(&o).unwrap();
        assert_eq!((r.scene.as_str(), r.trials, r.per_trial.len()), ("procedural:1", 3, 3));
        assert_eq!((r.particles, r.amcl.max_particles), (500, 500));
        assert_eq!((r.tolerance_m, r.max_travel_m), (0.2, 2.0));
        assert!((r.converged_fraction - r.converged() as f64 / 3.0).abs() < 1e-12);
        assert!((r.within_tolerance_at_end_fraction - r.within_tolerance_at_end() as f64 / 3.0).abs() < 1e-12);
        for t in &r.per_trial {
            assert!(t.travel_m >= 0.0 && t.final_error_m >= 0.0, "{t:?}");
            assert_eq!(t.converged, t.travel_at_convergence_m.is_some());
        }
        assert!(r.wall_s > 0.0 && r.warnings.is_empty());
        let json = serde_json::to_value(&r).unwrap();
        let keys: Vec<&String> = json.as_object().unwrap().keys().collect();
        assert_eq!(
            keys,
            ["amcl", "converged_fraction", "max_travel_m", "mean_travel_at_convergence_m", "particles", "per_trial", "scene", "tolerance_m", "trials", "wall_s", "within_tolerance_at_end_fraction"]
        );
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn bad_options_are_errors_naming_the_flag_or_file() {
        let dir = std::env::temp_dir().join(format!("xhab-localize-bad-{}", std::process::id()));
        let o = options(&dir);
        let e = |o: LocalizeOptions| run_localize(&o).expect_err("should fail").to_string();
        assert_eq!(e(LocalizeOptions { particles: 0, ..o.clone() }), "--particles must be at least 1");
        assert!(e(LocalizeOptions { physics: PhysicsOptions { robot: "no_such_robot".into(), ..Default::default() }, ..o.clone() }).starts_with("--robot no_such_robot"));
        assert!(e(LocalizeOptions { episodes: dir.join("none.json.gz"), ..o.clone() }).contains("none.json.gz"));
        assert!(e(LocalizeOptions { map: Some(dir.join("none.yaml")), ..o.clone() }).starts_with("loading map"));
        let y = dir.join("nav.yaml");
        std::fs::write(&y, "amcl:\n  min_particles: many\n").unwrap();
        let files = vec![y.to_str().unwrap().parse().unwrap()];
        assert!(e(LocalizeOptions { nav_params: files, ..o.clone() }).contains("nav.yaml"));
        std::fs::remove_dir_all(&dir).ok();
    }
}
