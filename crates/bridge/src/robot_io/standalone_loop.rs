//! The simulator node's main loop (`xhab ros sim`, `xhab ros2 sim`), written once against
//! [`SimTransport`]: publish the static transforms and the maps, then per cycle the state
//! (clock, tf, odom, scan) and camera frames, and step the robot under the newest command.

use super::state::{Command, Mounts, RobotState};
use crate::ros::standalone_sim::StandaloneOptions;
use crate::ros::node::RosError;
use std::sync::Arc;
use std::time::{Duration, Instant};
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::navgrid::NavGrid;
use xhab_sim::physics_env::PhysicsEnv;
use xhab_sim::sensors::{CameraFrame, CameraParams, DepthNoise, Lidar, Renderer};
use xhab_types::{OccupancyGrid, Point3, Pose2, Twist};

/// What a simulator node does on its transport: publish the robot's state, its sensors and
/// its maps, and take commands. ROS 1's `ros::sim_node::SimNode` and ROS 2's
/// `ros2::sim_node::SimNode2` implement it; [`run_sim`] drives either.
// Static dispatch only, and the loop runs on `block_on`: the futures need not be `Send`.
#[allow(async_fn_in_trait)]
pub trait SimTransport {
    /// Publishes the static transforms (latched): base_link -> the laser frame, base_link ->
    /// camera_link -> the depth and RGB optical frames.
    async fn publish_static_tf(&mut self, m: &Mounts) -> Result<(), RosError>;
    /// Publishes the map (latched) with stamp `stamp` (s).
    async fn publish_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError>;
    /// Publishes the localisation map (latched) on `amcl/map`.
    async fn publish_amcl_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError>;
    /// Publishes the robot's state: clock, tf odom -> base_link (and map -> odom when given),
    /// scan (if any), odom and ground truth, every one stamped `s.stamp`.
    async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError>;
    /// Publishes a rendered camera frame: depth, and RGB when it has one, each with its
    /// camera_info in its own optical frame.
    async fn publish_frame(&self, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError>;
    /// The next command, waiting up to the node's timeout.
    async fn next_command(&mut self) -> Result<Command, RosError>;
    /// The newest command that has arrived, if any, without waiting.
    fn latest_command(&mut self) -> Option<Command>;
}

/// Renders depth (with `noise`, seeded by `seed` and the frame number `n`; and RGB when
/// `want_rgb`) from `base` on the floor at `floor_z` (m).
pub fn render_frame(n: u64, renderer: &Renderer, base: Pose2, floor_z: f64, cam: &CameraParams, want_rgb: bool, noise: &DepthNoise, seed: u64) -> Result<CameraFrame, RosError> {
    let (mut depth, rgb) = if want_rgb {
        let (d, c) = renderer.depth_rgb(base, floor_z, cam).map_err(|e| RosError::Node(format!("rendering depth and rgb: {e}")))?;
        (d, Some(c))
    } else {
        (renderer.depth(base, floor_z, cam).map_err(|e| RosError::Node(format!("rendering depth: {e}")))?, None)
    };
    noise.apply(&mut depth, seed ^ n.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    Ok(CameraFrame { depth, rgb })
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

/// Runs the simulator on `sim` until `o.duration` passes (forever without one): under
/// physics, one control interval of `o.period` per cycle under the newest `cmd_vel` (zero
/// after `o.cmd_vel_timeout` without one; in lock-step, exactly one command per cycle);
/// without physics, one discrete action per command.
pub async fn run_sim<T: SimTransport>(sim: &mut T, grid: Arc<NavGrid>, o: &StandaloneOptions) -> Result<(), RosError> {
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
                        let f = render_frame(seq, rs, env.pose(), grid.floor_z, cam, *rgb, &o.depth_noise, o.seed)?;
                        sim.publish_frame(t, cam, &f).await?;
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
            let mut env = KinematicEnv::new(grid.clone(), &ep, task).map_err(|e| RosError::Protocol(format!("start pose: {e}")))?;
            let mut t = 0.0;
            loop {
                let p = env.pose();
                let scan = lidar.as_mut().map(|(rs, l)| l.scan(rs, p, grid.floor_z));
                let st = RobotState { stamp: t, truth: p, floor_z: o.start_z, odom: p, twist: Twist::default(), scan: scan.as_ref().map(|s| (s, o.scan_period)), map_to_odom: o.map_odom_ground_truth.then(Pose2::default) };
                sim.publish_state(&st).await?;
                if let Some((rs, cam, rgb)) = &o.camera {
                    let f = render_frame(seq, rs, p, grid.floor_z, cam, *rgb, &o.depth_noise, o.seed)?;
                    sim.publish_frame(t, cam, &f).await?;
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
