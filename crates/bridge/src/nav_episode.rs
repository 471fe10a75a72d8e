//! One episode of the native navigation stack in-process: the navigator's brain fed through
//! the ROS message conversions, driving the physics environment at its controller rate.

use crate::camera_capture::{capture, RenderStats};
use crate::nav_agent::{episode_time, localization_map, NavStack, NavInputs, NavReply, NavSetup, INITIAL_STD_XY, INITIAL_STD_YAW};
use crate::outcome::{EpisodeRun, InvalidRun, Outcome};
use crate::run_config::RunConfig;
use std::time::Instant;
use xhab_nav::navigator::AbortReason;
use xhab_sim::env::{DiscreteEnv, EnvView};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::physics_env::PhysicsEnv;
use xhab_types::Pose2;

/// Runs one episode with the navigator on `env` (already reset), returning its outcome.
pub(crate) fn run_nav(env: &mut PhysicsEnv, grid: &NavGrid, scene: &xhab_sim::scene::Scene, index: usize, ep_id: &str, goal: xhab_types::Point2, setup: &NavSetup, cfg: &RunConfig, t0: Instant) -> Outcome {
    // The navigator gets its inputs through the same message conversions as the ROS nav node
    // (f32 map resolution and scan angles, yaw through a quaternion), so that a run over ROS
    // is identical to this one.
    use crate::ros::convert as cv;
    let scored = setup.scored(cfg.task.success_distance);
    let setup = &scored;
    let map = setup.map.as_deref().cloned().unwrap_or_else(|| grid.occupancy_grid());
    let map = cv::grid_from_msg(&cv::occupancy_grid(0.0, &map)).expect("a map converts to its own message");
    let amcl_map = match localization_map(setup, grid, scene) {
        Some(m) => cv::grid_from_msg(&cv::occupancy_grid(0.0, &m)).expect("a map converts to its own message"),
        None => map.clone(),
    };
    let via = |p: Pose2| cv::pose2(&cv::pose(p, 0.0));
    let spread = cv::pose_with_covariance(0.0, Pose2::default(), INITIAL_STD_XY, INITIAL_STD_YAW).pose.covariance;
    let mut brain = NavStack::new(setup, &map, &amcl_map, goal, via(env.odometry()), Some((spread[0].sqrt(), spread[35].sqrt())), cfg.seed);
    let period = setup.params.dwa.controller_period.max(1e-3);
    let mut traj = cfg.record_trajectories.then(|| vec![env.pose()]);
    let mut sensor = setup.scan.as_ref().map(|s| s.sensor(cfg.seed));
    let mut aborted = false;
    let mut stats = RenderStats::default();
    let mut step = 0u64;
    // The laser's mount as the static transform carries it over ROS.
    let scan_mount = setup.scan.as_ref().map_or(Pose2::default(), |s| cv::pose2_of_transform(&cv::transform(s.mount(), 0.0)));
    while !env.is_done() {
        let t = episode_time(env.sim_s());
        // The observation's camera frame (`--sensors`): rendered at each controller step; the
        // navigator reads scans only (a depth scan source flattens this frame when it comes
        // from the same camera, else renders its own).
        let mut seen = None;
        if let Some(rig) = cfg.sensors.as_deref() {
            match capture(rig, env.pose(), grid.floor_z, cfg.seed, index, step, &mut stats) {
                Ok(frame) => seen = Some((rig, frame)),
                Err(reason) => return Outcome::Invalid(InvalidRun { episode_id: ep_id.to_string(), reason }),
            }
        }
        step += 1;
        let scan = match sensor.as_mut() {
            Some(s) if brain.scan_due(t) => match s.scan_seen(env.pose(), grid.floor_z, seen.as_ref().map(|(r, f)| (*r, f))) {
                Ok(scan) => Some(cv::scan_from_msg(&cv::laser_scan(t, "laser", &scan, setup.scan_period))),
                Err(e) => return Outcome::Invalid(InvalidRun { episode_id: ep_id.to_string(), reason: format!("scan at {t:.2} s: {e}") }),
            },
            _ => None,
        };
        let inp = NavInputs { t, odom: via(env.odometry()), twist: env.robot().twist(), truth: Some(via(env.pose())), scan: scan.as_ref(), scan_mount };
        match brain.step(inp) {
            NavReply::Stop => env.call_stop(),
            NavReply::Abort => {
                aborted = true;
                break;
            }
            NavReply::Drive(tw) => env.drive(tw, period),
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
        stuck: Some(env.stuck()),
        stuck_cause: env.stuck_cause().map(str::to_string),
        abort_reason: aborted.then(|| brain.abort_reason().map_or("unknown", AbortReason::as_str).to_string()),
        final_localization: brain.last_fix(),
        localization_error: brain.localization_error(),
        render: cfg.sensors.is_some().then_some((stats.frames, stats.seconds)),
        ros: None,
    })
}
