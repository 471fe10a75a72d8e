//! `xhab ros sim`: the simulator as a long-running ROS node that real ROS tools (move_base,
//! amcl, rviz, rosbag, rostopic) drive and watch, free-running at a real-time factor or in
//! lock-step with one controller.

use super::master::Master;
use super::node::RosError;
use super::names::Names;
use super::sim_node::{Command, Mounts, RobotState, SimNode};
use crate::runner::PhysicsSetup;
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, Env, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::physics_env::PhysicsEnv;
use xhab_sim::sensors::{CameraParams, Lidar, LidarParams, RayScene, Renderer};
use xhab_types::{OccupancyGrid, Point3, Pose2, Twist};

/// How `xhab ros sim` runs.
#[derive(Debug, Clone)]
pub struct LiveOptions {
    /// Master URI; `None` starts one.
    pub master: Option<String>,
    /// The node's name, namespace and remappings.
    pub names: Names,
    /// The laser's and the camera's mounts (static tf).
    pub mounts: Mounts,
    /// Publish map -> odom from ground truth (as fake_localization), for stacks without a
    /// localiser.
    pub map_odom_ground_truth: bool,
    /// Physics (velocity commands on `cmd_vel`); `None`: discrete actions on `action`.
    pub physics: Option<PhysicsSetup>,
    /// Where the robot starts (world frame) and the height of its floor (m).
    pub start: Pose2,
    /// Height of the start's floor (m).
    pub start_z: f64,
    /// The map to publish (latched), if any.
    pub map: Option<OccupancyGrid>,
    /// The map to publish on `amcl/map` (latched), the one to localise on, if any.
    pub amcl_map: Option<OccupancyGrid>,
    /// The planar lidar, published on `scan` every `scan_period`.
    pub lidar: Option<(Arc<RayScene>, LidarParams)>,
    /// Period between scans (s).
    pub scan_period: f64,
    /// The camera (depth, and RGB when the flag is set), published every `camera_period`.
    pub camera: Option<(Arc<Renderer>, CameraParams, bool)>,
    /// Period between camera frames (s).
    pub camera_period: f64,
    /// Depth noise (off by default).
    pub depth_noise: xhab_sim::sensors::DepthNoise,
    /// Period of the state loop (s): odom, tf, clock and one physics interval per cycle.
    pub period: f64,
    /// Simulated seconds per wall second (0 = as fast as possible).
    pub rate: f64,
    /// Lock-step: each cycle waits for one `cmd_vel` before advancing.
    pub lockstep: bool,
    /// Stop after this much simulated time (s), if given.
    pub duration: Option<f64>,
    /// Seconds without `cmd_vel` after which the base stops (free-running).
    pub cmd_vel_timeout: f64,
    /// Seed of odometry and lidar noise.
    pub seed: u64,
    /// How long lock-step waits for a command (s).
    pub timeout: Duration,
}

/// A roaming "episode" for the live simulator: the start, with itself as the goal.
fn roaming(start: Pose2, z: f64) -> Episode {
    Episode {
        episode_id: "live".into(),
        scene_id: String::new(),
        start_position: Point3::new(start.x, start.y, z),
        start_yaw: start.yaw,
        goals: vec![Goal { position: Point3::new(start.x, start.y, z), radius: 0.2 }],
        geodesic_distance: None,
        info: serde_json::Value::Null,
    }
}

/// Runs the simulator node until `duration` passes or the process is interrupted.
pub fn run_live(grid: Arc<NavGrid>, o: &LiveOptions) -> Result<(), RosError> {
    let master = Master::connect_or_start(o.master.as_deref())?;
    eprintln!("xhab: ROS master {}{}", master.uri, if master.owned() { " (started for this run)" } else { "" });
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(async {
        tokio::select! {
            r = live(&master.uri, grid, o) => r,
            _ = tokio::signal::ctrl_c() => Ok(()),
        }
    })
}

async fn live(uri: &str, grid: Arc<NavGrid>, o: &LiveOptions) -> Result<(), RosError> {
    let mut sim = SimNode::new(uri, o.names.clone(), &o.mounts.laser_frame, o.timeout).await?;
    let task = TaskConfig { max_episode_steps: u32::MAX, ..Default::default() };
    let ep = roaming(o.start, o.start_z);
    sim.publish_static_tf(&o.mounts).await?;
    if let Some(m) = &o.map {
        sim.publish_map(0.0, m).await?;
    }
    if let Some(m) = &o.amcl_map {
        sim.publish_amcl_map(0.0, m).await?;
    }
    let mut lidar = o.lidar.as_ref().map(|(rs, p)| (rs.clone(), Lidar::new(p.clone(), o.seed)));
    let t0 = Instant::now();
    let (mut next_scan, mut next_frame) = (0.0, 0.0);
    let mut seq = 0u64;
    match &o.physics {
        Some(ph) => {
            let mut env = PhysicsEnv::new(grid.clone(), &ph.scene, &ep, task, &ph.profile, ph.config.clone(), o.seed).map_err(|e| RosError::Protocol(format!("start pose: {e}")))?;
            let (mut cmd, mut cmd_t) = (Twist::default(), f64::NEG_INFINITY);
            loop {
                let t = env.sim_s();
                let scan = match lidar.as_mut() {
                    Some((rs, l)) if t + 1e-9 >= next_scan => {
                        next_scan += o.scan_period;
                        Some(l.scan(rs, env.pose(), grid.floor_z))
                    }
                    _ => None,
                };
                let m2o = o.map_odom_ground_truth.then(|| env.pose().compose(env.odometry().inverse()));
                let st = RobotState { stamp: t, truth: env.pose(), floor_z: o.start_z, odom: env.odometry(), twist: env.robot().twist(), scan: scan.as_ref().map(|s| (s, o.scan_period)), map_to_odom: m2o };
                sim.publish_state(&st).await?;
                if let Some((rs, cam, rgb)) = &o.camera {
                    if t + 1e-9 >= next_frame {
                        next_frame += o.camera_period;
                        sim.publish_camera(seq, t, rs, env.pose(), grid.floor_z, cam, *rgb, &o.depth_noise, o.seed).await?;
                    }
                }
                if o.lockstep {
                    match sim.next_command().await? {
                        Command::Twist(tw) => cmd = tw,
                        Command::Action(a) => tracing::warn!("action {a} ignored: the physics simulator takes cmd_vel"),
                    }
                } else {
                    if let Some(Command::Twist(tw)) = sim.latest_command() {
                        (cmd, cmd_t) = (tw, t);
                    }
                    if t - cmd_t > o.cmd_vel_timeout {
                        cmd = Twist::default();
                    }
                }
                if !(cmd.linear.is_finite() && cmd.angular.is_finite()) {
                    tracing::warn!("cmd_vel with a non-finite value ignored (the base stops)");
                    cmd = Twist::default();
                }
                env.step_twist(cmd, o.period);
                seq = seq.wrapping_add(1);
                if o.duration.is_some_and(|d| env.sim_s() >= d - 1e-9) {
                    return Ok(());
                }
                pace(t0, env.sim_s(), o.rate).await;
            }
        }
        None => {
            let mut env = Env::new(grid.clone(), &ep, task).map_err(|e| RosError::Protocol(format!("start pose: {e}")))?;
            let mut t = 0.0;
            loop {
                let p = env.pose();
                let scan = lidar.as_mut().map(|(rs, l)| l.scan(rs, p, grid.floor_z));
                let st = RobotState { stamp: t, truth: p, floor_z: o.start_z, odom: p, twist: Twist::default(), scan: scan.as_ref().map(|s| (s, o.scan_period)), map_to_odom: o.map_odom_ground_truth.then(Pose2::default) };
                sim.publish_state(&st).await?;
                if let Some((rs, cam, rgb)) = &o.camera {
                    sim.publish_camera(seq, t, rs, p, grid.floor_z, cam, *rgb, &o.depth_noise, o.seed).await?;
                }
                // Wait for the next action; republish the state every period meanwhile.
                let a = loop {
                    match tokio::time::timeout(Duration::from_secs_f64(o.period.max(0.01) / o.rate.max(1e-3)), sim.next_command()).await {
                        Ok(Ok(Command::Action(a))) => break Some(a),
                        Ok(Ok(Command::Twist(_))) => tracing::warn!("cmd_vel ignored: the discrete simulator takes `action` (0 stop, 1 forward, 2 left, 3 right)"),
                        Ok(Err(e)) => return Err(e),
                        Err(_) if !o.lockstep => break None,
                        // Lock-step: the state again (same stamp), for a late subscriber.
                        Err(_) => sim.publish_state(&st).await?,
                    }
                };
                if let Some(a) = a {
                    match Action::from_index(a as i64) {
                        Some(a) => {
                            env.step(a);
                        }
                        None => tracing::warn!("action {a} ignored: 0 stop, 1 forward, 2 left, 3 right"),
                    }
                }
                seq = seq.wrapping_add(1);
                t += o.period;
                if o.duration.is_some_and(|d| t >= d - 1e-9) {
                    return Ok(());
                }
            }
        }
    }
}

/// Sleeps until `sim_s` simulated seconds correspond to wall time at `rate` (0: no pacing).
async fn pace(t0: Instant, sim_s: f64, rate: f64) {
    if rate > 0.0 {
        let due = t0 + Duration::from_secs_f64(sim_s / rate);
        let now = Instant::now();
        if due > now {
            tokio::time::sleep(due - now).await;
        }
    }
}
