//! The simulator as a ROS 1 node: publishes what a robot driver and its sensors would (clock,
//! odom, tf, scan, ground truth, camera images, the map) and takes `cmd_vel` or `action`.

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, rosgraph_msgs, sensor_msgs, std_msgs, tf2_msgs};
use super::node::{self, Connected, RosError};
use roslibrust::ros1::{NodeHandle, Publisher};
use std::time::Duration;
use tokio::sync::mpsc;
use xhab_sim::sensors::{render_depth, render_rgb, CameraParams, RayScene};
use xhab_types::{LaserScan, OccupancyGrid, Pose2, Twist};

/// The camera's optical frame (z forward, x right, y down).
pub const CAMERA_OPTICAL_FRAME: &str = "camera_depth_optical_frame";

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

    /// Waits until the named topics have subscribers (`ground_truth/pose`, `odom`, `scan`, `goal`, `initialpose`).
    pub async fn wait_for(&self, topics: &[&str]) -> Result<(), RosError> {
        let mut pubs: Vec<(&str, &dyn Connected)> = Vec::new();
        for t in topics {
            let p: &dyn Connected = match *t {
                "ground_truth/pose" => &self.truth,
                "odom" => &self.odom,
                "scan" => &self.scan,
                "clock" => &self.clock,
                "move_base_simple/goal" => &self.goal,
                "initialpose" => &self.initialpose,
                other => return Err(RosError::Protocol(format!("unknown topic {other}"))),
            };
            pubs.push((t, p));
        }
        node::wait_for_subscribers(&pubs, self.timeout).await
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
        if self.tf.connected() {
            let m = tf2_msgs::TFMessage { transforms: vec![cv::tf(s.stamp, "odom", "base_link", cv::transform(s.odom, 0.0))] };
            self.tf.publish(&m).await.map_err(|e| perr("tf", e))?;
        }
        if let Some((scan, period, _)) = s.scan {
            self.scan.publish(&cv::laser_scan(s.seq, s.stamp, "laser", scan, period)).await.map_err(|e| perr("scan", e))?;
        }
        self.odom.publish(&cv::odometry(s.seq, s.stamp, s.odom, s.twist)).await.map_err(|e| perr("odom", e))?;
        let gt = gm::PoseStamped { header: cv::header(s.seq, s.stamp, "map"), pose: cv::pose(s.truth, s.floor_z) };
        self.truth.publish(&gt).await.map_err(|e| perr("ground_truth/pose", e))
    }

    /// Whether anyone listens to the camera topics: (depth, rgb).
    pub fn camera_wanted(&self) -> (bool, bool) {
        (self.depth.connected() || self.depth_info.connected(), self.rgb.connected() || self.rgb_info.connected())
    }

    /// Renders and publishes the camera images someone subscribes to (ray-cast renderer).
    pub async fn publish_camera(&self, seq: u32, stamp: f64, scene: &RayScene, base: Pose2, floor_z: f64, cam: &CameraParams) -> Result<(), RosError> {
        let (want_depth, want_rgb) = self.camera_wanted();
        let k = cam.intrinsics();
        if want_depth {
            let d = render_depth(scene, base, floor_z, cam);
            self.depth_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
            self.depth.publish(&cv::depth_image(seq, stamp, CAMERA_OPTICAL_FRAME, &d)).await.map_err(|e| perr("depth", e))?;
        }
        if want_rgb {
            let rgb = render_rgb(scene, base, floor_z, cam);
            self.rgb_info.publish(&cv::camera_info(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera_info", e))?;
            self.rgb.publish(&cv::rgb_image(seq, stamp, CAMERA_OPTICAL_FRAME, cam.width, cam.height, rgb)).await.map_err(|e| perr("rgb", e))?;
        }
        Ok(())
    }

    /// The next command (lock-step): waits up to `timeout` for `cmd_vel` or `action`.
    pub async fn next_command(&mut self) -> Result<Command, RosError> {
        let t = self.timeout;
        tokio::select! {
            m = self.cmd_vel.recv() => m.map(|m| Command::Twist(cv::twist2(&m))).ok_or_else(|| RosError::Protocol("cmd_vel subscription closed".into())),
            m = self.action.recv() => m.map(|m| Command::Action(m.data)).ok_or_else(|| RosError::Protocol("action subscription closed".into())),
            _ = tokio::time::sleep(t) => Err(RosError::Timeout(format!("no cmd_vel or action from the agent within {:.0} s (lock-step)", t.as_secs_f64()))),
        }
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
