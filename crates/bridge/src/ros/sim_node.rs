//! The simulator as a ROS 1 node: publishes what a robot driver and its sensors would (clock,
//! odom, tf, scan, ground truth, camera images, the map) and takes `cmd_vel` or `action`.

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, rosgraph_msgs, sensor_msgs, std_msgs, tf2_msgs};
use super::node::{self, RosError};
use roslibrust::ros1::{NodeHandle, Publisher};
use std::time::Duration;
use tokio::sync::mpsc;
use xhab_sim::sensors::{CameraFrame, CameraParams, DepthNoise, Renderer};
use xhab_types::{LaserScan, OccupancyGrid, Pose2, Twist};

/// The camera's optical frame (z forward, x right, y down).
pub const CAMERA_OPTICAL_FRAME: &str = "camera_depth_optical_frame";

/// The topic of the map AMCL localises on when it differs from `map` (the scene cut at the
/// laser's height, while `map` holds the body-band map for the costmap), as amcl's `map`
/// remapped into its namespace.
pub const AMCL_MAP_TOPIC: &str = "amcl/map";

/// `header.seq` of a handshake probe (never a real step).
pub const PROBE_SEQ: u32 = u32::MAX;
/// `action` value an agent answers a probe with (never a real action).
pub const READY_ACTION: i16 = -1000;

/// Whether a message on `action` or `cmd_vel` answers a handshake probe: `action` of
/// [`READY_ACTION`] or a Twist with `linear.z` set (a planar base never commands it).
pub fn is_ready_reply(c: &Command) -> bool {
    match c {
        Command::Action(a) => *a == READY_ACTION,
        Command::Twist(_) => false,
    }
}

/// A command from the agent side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// A velocity (geometry_msgs/Twist on `cmd_vel`).
    Twist(Twist),
    /// A discrete action (std_msgs/Int16 on `action`): Habitat's 0..=3; -1 = give up.
    Action(i16),
}

/// The simulator node's publishers and command subscriptions.
pub struct SimNode {
    /// The node handle (kept alive with the node).
    pub nh: NodeHandle,
    clock: Publisher<rosgraph_msgs::Clock>,
    tf: Publisher<tf2_msgs::TFMessage>,
    tf_static: Publisher<tf2_msgs::TFMessage>,
    odom: Publisher<nav_msgs::Odometry>,
    truth: Publisher<gm::PoseStamped>,
    scan: Publisher<sensor_msgs::LaserScan>,
    map: Publisher<nav_msgs::OccupancyGrid>,
    amcl_map: Publisher<nav_msgs::OccupancyGrid>,
    goal: Publisher<gm::PoseStamped>,
    initialpose: Publisher<gm::PoseWithCovarianceStamped>,
    depth: Publisher<sensor_msgs::Image>,
    depth_info: Publisher<sensor_msgs::CameraInfo>,
    rgb: Publisher<sensor_msgs::Image>,
    rgb_info: Publisher<sensor_msgs::CameraInfo>,
    cmd_vel: mpsc::UnboundedReceiver<gm::Twist>,
    action: mpsc::UnboundedReceiver<std_msgs::Int16>,
    /// How long to wait for a peer before failing (s).
    pub timeout: Duration,
}

/// One instant of the simulated robot, as the node publishes it.
#[derive(Debug, Clone, Copy)]
pub struct RobotState<'a> {
    /// Sequence number of the step within the episode (0 = the episode's first).
    pub seq: u32,
    /// ROS time (s) of the instant.
    pub stamp: f64,
    /// Ground-truth pose of the base in the world (= map) frame.
    pub truth: Pose2,
    /// Height of the floor the robot stands on (m).
    pub floor_z: f64,
    /// Odometry pose of the base in the odom frame.
    pub odom: Pose2,
    /// Base velocity.
    pub twist: Twist,
    /// A scan taken now, if any, with its period (s) and the laser's height above the base (m).
    pub scan: Option<(&'a LaserScan, f64, f64)>,
}

impl SimNode {
    /// Registers the node `name` and its topics with the master at `uri`.
    pub async fn new(uri: &str, name: &str, timeout: Duration) -> Result<SimNode, RosError> {
        let nh = node::node(uri, name).await?;
        Ok(SimNode {
            clock: node::advertise(&nh, "clock", false).await?,
            tf: node::advertise(&nh, "tf", false).await?,
            tf_static: node::advertise(&nh, "tf_static", true).await?,
            odom: node::advertise(&nh, "odom", false).await?,
            truth: node::advertise(&nh, "ground_truth/pose", false).await?,
            scan: node::advertise(&nh, "scan", false).await?,
            map: node::advertise(&nh, "map", true).await?,
            amcl_map: node::advertise(&nh, AMCL_MAP_TOPIC, true).await?,
            goal: node::advertise(&nh, "move_base_simple/goal", false).await?,
            initialpose: node::advertise(&nh, "initialpose", false).await?,
            depth: node::advertise(&nh, "camera/depth/image_raw", false).await?,
            depth_info: node::advertise(&nh, "camera/depth/camera_info", false).await?,
            rgb: node::advertise(&nh, "camera/rgb/image_raw", false).await?,
            rgb_info: node::advertise(&nh, "camera/rgb/camera_info", false).await?,
            cmd_vel: node::subscribe(&nh, "cmd_vel").await?,
            action: node::subscribe(&nh, "action").await?,
            nh,
            timeout,
        })
    }

    /// Publishes the static transforms base_link -> laser (at `laser_z`) and base_link ->
    /// camera_link -> optical frame (camera at `camera_z`), latched.
    pub async fn publish_static_tf(&self, laser_z: f64, camera_z: f64) -> Result<(), RosError> {
        let optical = gm::Transform { translation: gm::Vector3 { x: 0.0, y: 0.0, z: 0.0 }, rotation: gm::Quaternion { x: -0.5, y: 0.5, z: -0.5, w: 0.5 } };
        let m = tf2_msgs::TFMessage {
            transforms: vec![
                cv::tf(0.0, "base_link", "laser", cv::transform(Pose2::default(), laser_z)),
                cv::tf(0.0, "base_link", "camera_link", cv::transform(Pose2::default(), camera_z)),
                cv::tf(0.0, "camera_link", CAMERA_OPTICAL_FRAME, optical),
            ],
        };
        self.tf_static.publish(&m).await.map_err(|e| RosError::Node(format!("tf_static: {e}")))
    }

    /// Publishes the localisation map (latched) on [`AMCL_MAP_TOPIC`].
    pub async fn publish_amcl_map(&self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.amcl_map.publish(&cv::occupancy_grid(stamp, map)).await.map_err(|e| RosError::Node(format!("{AMCL_MAP_TOPIC}: {e}")))
    }

    /// Publishes the map (latched).
    pub async fn publish_map(&self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.map.publish(&cv::occupancy_grid(stamp, map)).await.map_err(|e| RosError::Node(format!("map: {e}")))
    }

    /// Publishes an episode's goal (`header.seq` = the episode's index) at height `z`.
    pub async fn publish_goal(&self, index: u32, stamp: f64, goal: Pose2, z: f64) -> Result<(), RosError> {
        let m = gm::PoseStamped { header: cv::header(index, stamp, "map"), pose: cv::pose(goal, z) };
        self.goal.publish(&m).await.map_err(|e| RosError::Node(format!("goal: {e}")))
    }

    /// Publishes an initial pose with standard deviations (m, rad).
    pub async fn publish_initialpose(&self, index: u32, stamp: f64, p: Pose2, xy_std: f64, yaw_std: f64) -> Result<(), RosError> {
        self.initialpose.publish(&cv::pose_with_covariance(index, stamp, p, xy_std, yaw_std)).await.map_err(|e| RosError::Node(format!("initialpose: {e}")))
    }

    /// Publishes the robot's state: clock, tf odom -> base_link, scan (if any), odom and
    /// ground truth, in that order.
    pub async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError> {
        self.clock.publish(&rosgraph_msgs::Clock { clock: cv::time(s.stamp) }).await.map_err(|e| perr("clock", e))?;
        let m = tf2_msgs::TFMessage { transforms: vec![cv::tf(s.stamp, "odom", "base_link", cv::transform(s.odom, 0.0))] };
        self.tf.publish(&m).await.map_err(|e| perr("tf", e))?;
        if let Some((scan, period, _)) = s.scan {
            self.scan.publish(&cv::laser_scan(s.seq, s.stamp, "laser", scan, period)).await.map_err(|e| perr("scan", e))?;
        }
        self.odom.publish(&cv::odometry(s.seq, s.stamp, s.odom, s.twist)).await.map_err(|e| perr("odom", e))?;
        let gt = gm::PoseStamped { header: cv::header(s.seq, s.stamp, "map"), pose: cv::pose(s.truth, s.floor_z) };
        self.truth.publish(&gt).await.map_err(|e| perr("ground_truth/pose", e))
    }

    /// Publishes a rendered camera frame: depth, and RGB when it has one, each with its
    /// camera_info.
    pub async fn publish_frame(&self, seq: u32, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError> {
        let k = cam.intrinsics();
        self.depth_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
        self.depth.publish(&cv::depth_image(seq, stamp, CAMERA_OPTICAL_FRAME, &frame.depth)).await.map_err(|e| perr("depth", e))?;
        if let Some(rgb) = &frame.rgb {
            self.rgb_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
            self.rgb.publish(&cv::rgb_image(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, rgb.clone())).await.map_err(|e| perr("rgb", e))?;
        }
        Ok(())
    }

    /// Renders and publishes depth (with `noise`, seeded by `seed` and `seq`; and RGB when
    /// `want_rgb`) with their camera_info.
    pub async fn publish_camera(&self, seq: u32, stamp: f64, renderer: &Renderer, base: Pose2, floor_z: f64, cam: &CameraParams, want_rgb: bool, noise: &DepthNoise, seed: u64) -> Result<(), RosError> {
        let k = cam.intrinsics();
        let (mut d, rgb) = if want_rgb {
            let (d, c) = renderer.depth_rgb(base, floor_z, cam).map_err(|e| RosError::Node(format!("rendering depth and rgb: {e}")))?;
            (d, Some(c))
        } else {
            (renderer.depth(base, floor_z, cam).map_err(|e| RosError::Node(format!("rendering depth: {e}")))?, None)
        };
        noise.apply(&mut d, seed ^ (seq as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
        self.depth_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
        self.depth.publish(&cv::depth_image(seq, stamp, CAMERA_OPTICAL_FRAME, &d)).await.map_err(|e| perr("depth", e))?;
        if let Some(rgb) = rgb {
            self.rgb_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
            self.rgb.publish(&cv::rgb_image(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, rgb)).await.map_err(|e| perr("rgb", e))?;
        }
        Ok(())
    }

    /// The next command (lock-step): waits up to `timeout` for `cmd_vel` or `action`,
    /// skipping late answers to handshake probes.
    pub async fn next_command(&mut self) -> Result<Command, RosError> {
        let deadline = tokio::time::Instant::now() + self.timeout;
        loop {
            let c = tokio::select! {
                m = self.cmd_vel.recv() => match m {
                    Some(m) if m.linear.z != 0.0 => continue,
                    Some(m) => Command::Twist(cv::twist2(&m)),
                    None => return Err(RosError::Protocol("cmd_vel subscription closed".into())),
                },
                m = self.action.recv() => match m {
                    Some(m) => Command::Action(m.data),
                    None => return Err(RosError::Protocol("action subscription closed".into())),
                },
                _ = tokio::time::sleep_until(deadline) => return Err(RosError::Timeout(format!("no cmd_vel or action from the agent within {:.0} s (lock-step)", self.timeout.as_secs_f64()))),
            };
            if !is_ready_reply(&c) {
                return Ok(c);
            }
        }
    }

    /// Lock-step handshake: publishes probes (`header.seq` = [`PROBE_SEQ`]) on `topics` every
    /// 50 ms until the agent has answered on `action` (and on `cmd_vel` when `twist`), which
    /// proves every connection both ways is up: roslibrust drops messages published before a
    /// subscriber's connection exists, so lock-step cannot start earlier.
    pub async fn handshake(&mut self, topics: &[&str], twist: bool) -> Result<(), RosError> {
        let deadline = tokio::time::Instant::now() + self.timeout;
        let (mut got_action, mut got_twist) = (false, !twist);
        while !(got_action && got_twist) {
            tracing::debug!("sim: probing {topics:?}");
            for t in topics {
                self.probe(t).await?;
            }
            let tick = tokio::time::Instant::now() + Duration::from_millis(50);
            loop {
                tokio::select! {
                    m = self.cmd_vel.recv() => if m.is_some_and(|m| m.linear.z != 0.0) { got_twist = true },
                    m = self.action.recv() => if m.is_some_and(|m| m.data == READY_ACTION) { got_action = true },
                    _ = tokio::time::sleep_until(tick) => break,
                }
            }
            if tokio::time::Instant::now() > deadline {
                return Err(RosError::Timeout(format!("the agent did not answer the handshake on {} within {:.0} s", topics.join(", "), self.timeout.as_secs_f64())));
            }
        }
        Ok(())
    }

    /// Publishes one probe on `topic`.
    async fn probe(&self, topic: &str) -> Result<(), RosError> {
        let h = cv::header(PROBE_SEQ, 0.0, "probe");
        let r = match topic {
            "ground_truth/pose" => self.truth.publish(&gm::PoseStamped { header: h, ..Default::default() }).await,
            "move_base_simple/goal" => self.goal.publish(&gm::PoseStamped { header: h, ..Default::default() }).await,
            "initialpose" => self.initialpose.publish(&gm::PoseWithCovarianceStamped { header: h, ..Default::default() }).await,
            "odom" => self.odom.publish(&nav_msgs::Odometry { header: h, ..Default::default() }).await,
            "scan" => self.scan.publish(&sensor_msgs::LaserScan { header: h, ..Default::default() }).await,
            "map" => self.map.publish(&nav_msgs::OccupancyGrid { header: h, ..Default::default() }).await,
            AMCL_MAP_TOPIC => self.amcl_map.publish(&nav_msgs::OccupancyGrid { header: h, ..Default::default() }).await,
            other => return Err(RosError::Protocol(format!("no probe for topic {other}"))),
        };
        r.map_err(|e| perr(topic, e))
    }

    /// The newest command that has arrived, if any (free-running mode), without waiting.
    pub fn latest_command(&mut self) -> Option<Command> {
        let mut last = None;
        while let Ok(m) = self.cmd_vel.try_recv() {
            last = Some(Command::Twist(cv::twist2(&m)));
        }
        while let Ok(m) = self.action.try_recv() {
            last = Some(Command::Action(m.data));
        }
        last
    }
}

/// A publishing error naming the topic.
fn perr(topic: &str, e: impl std::fmt::Display) -> RosError {
    RosError::Node(format!("publishing on {topic}: {e}"))
}
