//! The native navigation stack as an agent: the move_base-like navigator drives the physics
//! simulator with velocity commands (controller at 1 / controller_period Hz), localised by
//! ground truth or by wheel odometry alone.

use crate::runner::{EpisodeRun, Outcome, RunConfig};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use std::time::Instant;
use xhab_nav::amcl::Amcl;
use xhab_nav::navigator::{NavParams, NavStatus, Navigator};
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::physics_env::PhysicsEnv;
use xhab_sim::sensors::{Lidar, LidarParams, RayScene};
use xhab_types::{OccupancyGrid, Pose2};

/// Where the navigator believes the robot is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Localization {
    /// The simulator's ground truth.
    GroundTruth,
    /// Integrated wheel odometry with noise (drifts).
    Odom,
    /// AMCL on the static map, from the start pose with ROS's initial covariance
    /// (0.5 m, pi/12 rad standard deviations), fed by odometry and the lidar.
    Amcl,
}

/// What the nav agent needs beyond the run config.
#[derive(Debug, Clone)]
pub struct NavSetup {
    /// Navigator parameters.
    pub params: NavParams,
    /// The static map (`None`: the map of the episode's floor, as `xhab map` makes it).
    pub map: Option<Arc<OccupancyGrid>>,
    /// Localisation source.
    pub localization: Localization,
    /// The planar lidar feeding the obstacle layer (scene for ray casting, parameters), if any.
    pub lidar: Option<(Arc<RayScene>, LidarParams)>,
    /// Scan period (s, default 0.1 = 10 Hz).
    pub scan_period: f64,
}

/// Runs one episode with the navigator on `env` (already reset), returning its outcome.
pub(crate) fn run_nav(env: &mut PhysicsEnv, grid: &NavGrid, ep_id: &str, goal: xhab_types::Point2, setup: &NavSetup, cfg: &RunConfig, t0: Instant) -> Outcome {
    let mut nav = Navigator::new(setup.params.clone());
    match &setup.map {
        Some(m) => nav.set_map(m),
        None => nav.set_map(&grid.occupancy_grid()),
    }
    nav.set_goal(goal, 0.0);
    let period = setup.params.dwa.controller_period.max(1e-3);
    let mut traj = cfg.record_trajectories.then(|| vec![env.pose()]);
    let mut lidar = setup.lidar.as_ref().map(|(rs, p)| (rs.clone(), Lidar::new(p.clone(), cfg.seed)));
    let mut next_scan = 0.0;
    let mut amcl = (setup.localization == Localization::Amcl).then(|| {
        let map = setup.map.as_deref().cloned().unwrap_or_else(|| grid.occupancy_grid());
        let mut a = Amcl::new(&map, setup.params.amcl.clone(), cfg.seed);
        a.init(env.odometry(), 0.5, std::f64::consts::PI / 12.0);
        a
    });
    // map -> odom: identity until AMCL corrects it (odometry starts at the true start pose).
    let mut map_to_odom = Pose2::default();
    let (mut err_sum, mut err_n) = ([0.0f64; 2], 0usize);
    while !env.is_done() {
        let mut pose: Pose2 = match setup.localization {
            Localization::GroundTruth => env.pose(),
            Localization::Odom | Localization::Amcl => map_to_odom.compose(env.odometry()),
        };
        if let Some((rs, l)) = lidar.as_mut() {
            if env.sim_s() + 1e-9 >= next_scan {
                // Taken where the robot is, placed where it believes it is.
                let scan = l.scan(rs, env.pose(), grid.floor_z);
                if let Some(a) = amcl.as_mut() {
                    if a.update(env.odometry(), &scan, Pose2::default()) {
                        map_to_odom = a.map_to_odom(env.odometry());
                        pose = map_to_odom.compose(env.odometry());
                        let truth = env.pose();
                        err_sum[0] += pose.position().dist(truth.position());
                        err_sum[1] += xhab_types::normalize_angle(pose.yaw - truth.yaw).abs();
                        err_n += 1;
                    }
                }
                nav.add_scan(&scan, pose);
                next_scan += setup.scan_period;
            }
        }
        let cmd = nav.tick(env.sim_s(), pose, env.robot().twist());
        match cmd.status {
            NavStatus::Succeeded => env.call_stop(),
            NavStatus::Aborted => break,
            _ => env.drive(cmd.twist, period),
        }
        if let Some(t) = traj.as_mut() {
            t.push(env.pose());
        }
    }
    Outcome::Ran(EpisodeRun {
        episode_id: ep_id.to_string(),
        metrics: env.metrics(),
        wall_s: t0.elapsed().as_secs_f64(),
        trajectory: traj,
        sim_s: Some(env.sim_s()),
        stuck: Some(env.stuck() || nav.status() == NavStatus::Aborted),
        localization_error: (err_n > 0).then(|| [err_sum[0] / err_n as f64, err_sum[1] / err_n as f64]),
    })
}
