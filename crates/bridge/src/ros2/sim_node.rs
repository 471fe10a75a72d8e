//! The simulator as a ROS 2 node: what a robot driver and its sensors publish (clock, odom,
//! tf, scan, camera images with camera_info, the map, ground truth) with Nav2's QoS, and
//! `cmd_vel` or `action` in.
//!
//! QoS: `scan` and the camera topics sensor data (best effort, volatile); `map`, `amcl/map`
//! and `/tf_static` latched (reliable, transient local); `odom`, `/tf`, `/clock`,
//! `ground_truth/pose` reliable and volatile (matched by best-effort subscribers too).

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, rosgraph_msgs, sensor_msgs, std_msgs, tf2_msgs, RosType};
use super::node::{command_qos, latched_qos, reliable_qos, sensor_data_qos, Ros2Config, Ros2Node};
use crate::robot_io::{Command, Mounts, RobotState, SimTransport, DEPTH_OPTICAL_FRAME, OPTICAL_ROTATION, RGB_OPTICAL_FRAME};
use crate::ros::names::Names;
use crate::ros::node::RosError;
use crate::ros::sim_node::AMCL_MAP_TOPIC;
use ros2_client::{Publisher, Subscription};
use std::time::Duration;
use xhab_sim::sensors::{CameraFrame, CameraParams};
use xhab_types::{OccupancyGrid, Pose2};

/// A publisher with the resolved name of its topic, for errors.
struct Pub<T: RosType> {
    topic: String,
    p: Publisher<T>,
}

impl<T: RosType> Pub<T> {
    fn new(node: &mut Ros2Node, topic: &str, qos: ros2_client::QosProfile) -> Result<Self, RosError> {
        Ok(Pub { topic: node.names.resolve(topic), p: node.publisher(topic, qos)? })
    }

    async fn publish(&self, m: T) -> Result<(), RosError> {
        self.p.async_publish(m).await.map_err(|e| RosError::Node(format!("publishing on {}: {e}", self.topic)))
    }
}

/// The ROS 2 simulator node's publishers and command subscriptions.
pub struct SimNode2 {
    clock: Pub<rosgraph_msgs::Clock>,
    tf: Pub<tf2_msgs::TFMessage>,
    tf_static: Pub<tf2_msgs::TFMessage>,
    odom: Pub<nav_msgs::Odometry>,
    truth: Pub<gm::PoseStamped>,
    scan: Pub<sensor_msgs::LaserScan>,
    map: Pub<nav_msgs::OccupancyGrid>,
    amcl_map: Pub<nav_msgs::OccupancyGrid>,
    depth: Pub<sensor_msgs::Image>,
    depth_info: Pub<sensor_msgs::CameraInfo>,
    rgb: Pub<sensor_msgs::Image>,
    rgb_info: Pub<sensor_msgs::CameraInfo>,
    cmd_vel: Subscription<gm::Twist>,
    action: Subscription<std_msgs::Int16>,
    initialpose: Pub<gm::PoseWithCovarianceStamped>,
    laser_frame: String,
    /// How long to wait for a command in lock-step before failing.
    pub timeout: Duration,
    /// The node (kept alive with its endpoints; dropped last).
    pub node: Ros2Node,
}

impl SimNode2 {
    /// Joins the domain of `config` as the node `names` with its topics; scans are stamped
    /// with `laser_frame`.
    pub fn new(names: Names, config: Ros2Config, laser_frame: &str, timeout: Duration) -> Result<SimNode2, RosError> {
        Self::with_sensor_qos(names, config, laser_frame, timeout, sensor_data_qos())
    }

    /// [`SimNode2::new`] with `sensor` as the QoS of the scan and camera topics (reliable in
    /// lock-step, where no step's scan may be lost; best-effort subscribers still match).
    pub fn with_sensor_qos(names: Names, config: Ros2Config, laser_frame: &str, timeout: Duration, sensor: ros2_client::QosProfile) -> Result<SimNode2, RosError> {
        let mut node = Ros2Node::new(names, config)?;
        let n = &mut node;
        Ok(SimNode2 {
            clock: Pub::new(n, "/clock", reliable_qos(1))?,
            tf: Pub::new(n, "/tf", reliable_qos(100))?,
            tf_static: Pub::new(n, "/tf_static", latched_qos())?,
            odom: Pub::new(n, "odom", reliable_qos(10))?,
            truth: Pub::new(n, "ground_truth/pose", reliable_qos(10))?,
            scan: Pub::new(n, "scan", sensor.clone())?,
            map: Pub::new(n, "map", latched_qos())?,
            amcl_map: Pub::new(n, AMCL_MAP_TOPIC, latched_qos())?,
            depth: Pub::new(n, "camera/depth/image_raw", sensor.clone())?,
            depth_info: Pub::new(n, "camera/depth/camera_info", sensor.clone())?,
            rgb: Pub::new(n, "camera/rgb/image_raw", sensor.clone())?,
            rgb_info: Pub::new(n, "camera/rgb/camera_info", sensor.clone())?,
            cmd_vel: n.subscription("cmd_vel", command_qos())?,
            action: n.subscription("action", command_qos())?,
            initialpose: Pub::new(n, "initialpose", reliable_qos(10))?,
            laser_frame: laser_frame.to_string(),
            timeout,
            node,
        })
    }

    /// Publishes the clock alone at `stamp` (s).
    pub async fn publish_clock(&self, stamp: f64) -> Result<(), RosError> {
        self.clock.publish(rosgraph_msgs::Clock { clock: cv::time(stamp) }).await
    }

    /// The next command waiting on `cmd_vel` (first) or `action`, if any; samples that fail
    /// to decode are logged and skipped.
    fn take_one(&self) -> Option<Command> {
        for _ in 0..MAX_BAD_SAMPLES {
            match self.cmd_vel.take() {
                Ok(Some((m, _))) => return Some(Command::Twist(cv::twist2(&m))),
                Ok(None) => break,
                Err(e) => tracing::warn!("cmd_vel: a message that does not decode was dropped: {e}"),
            }
        }
        for _ in 0..MAX_BAD_SAMPLES {
            match self.action.take() {
                Ok(Some((m, _))) => return Some(Command::Action(m.data)),
                Ok(None) => break,
                Err(e) => tracing::warn!("action: a message that does not decode was dropped: {e}"),
            }
        }
        None
    }
}

/// How many undecodable samples one look at a subscription skips at most.
const MAX_BAD_SAMPLES: usize = 64;

impl SimTransport for SimNode2 {
    async fn publish_static_tf(&mut self, m: &Mounts) -> Result<(), RosError> {
        let [x, y, z, w] = OPTICAL_ROTATION;
        let optical = gm::Transform { translation: gm::Vector3::default(), rotation: gm::Quaternion { x, y, z, w } };
        let msg = tf2_msgs::TFMessage {
            transforms: vec![
                cv::tf(0.0, "base_link", &m.laser_frame, cv::transform(m.laser, m.laser_z)),
                cv::tf(0.0, "base_link", "camera_link", cv::transform(Pose2::default(), m.camera_z)),
                cv::tf(0.0, "camera_link", DEPTH_OPTICAL_FRAME, optical),
                cv::tf(0.0, "camera_link", RGB_OPTICAL_FRAME, optical),
            ],
        };
        self.tf_static.publish(msg).await
    }

    async fn publish_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.map.publish(cv::occupancy_grid(stamp, map)).await
    }

    async fn publish_amcl_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.amcl_map.publish(cv::occupancy_grid(stamp, map)).await
    }

    async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError> {
        self.publish_clock(s.stamp).await?;
        let mut transforms = vec![cv::tf(s.stamp, "odom", "base_link", cv::transform(s.odom, 0.0))];
        if let Some(m2o) = s.map_to_odom {
            transforms.push(cv::tf(s.stamp, "map", "odom", cv::transform(m2o, 0.0)));
        }
        self.tf.publish(tf2_msgs::TFMessage { transforms }).await?;
        if let Some((scan, period)) = s.scan {
            self.scan.publish(cv::laser_scan(s.stamp, &self.laser_frame, scan, period)).await?;
        }
        self.odom.publish(cv::odometry(s.stamp, s.odom, s.twist)).await?;
        self.truth.publish(gm::PoseStamped { header: cv::header(s.stamp, "map"), pose: cv::pose(s.truth, s.floor_z) }).await
    }

    async fn publish_frame(&self, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError> {
        let k = cam.intrinsics();
        self.depth_info.publish(cv::camera_info(stamp, DEPTH_OPTICAL_FRAME, cam.width, cam.height, &k)).await?;
        self.depth.publish(cv::depth_image(stamp, DEPTH_OPTICAL_FRAME, &frame.depth)).await?;
        if let Some(rgb) = &frame.rgb {
            self.rgb_info.publish(cv::camera_info(stamp, RGB_OPTICAL_FRAME, cam.width, cam.height, &k)).await?;
            self.rgb.publish(cv::rgb_image(stamp, RGB_OPTICAL_FRAME, cam.width, cam.height, rgb.clone())).await?;
        }
        Ok(())
    }

    async fn next_command(&mut self) -> Result<Command, RosError> {
        let deadline = tokio::time::Instant::now() + self.timeout;
        // Both subscriptions are polled every millisecond: a command costs at most that in
        // latency, and neither subscription's stream is held across the other's.
        loop {
            if let Some(c) = self.take_one() {
                return Ok(c);
            }
            if tokio::time::Instant::now() >= deadline {
                return Err(RosError::Timeout(format!("no cmd_vel or action within {:.0} s (lock-step)", self.timeout.as_secs_f64())));
            }
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    }

    fn latest_command(&mut self) -> Option<Command> {
        let mut last = None;
        // Bounded: commands arriving while this drains wait for the next cycle.
        for _ in 0..10_000 {
            match self.take_one() {
                Some(c) => last = Some(c),
                None => break,
            }
        }
        last
    }
}

/// What benchmarking an external stack needs beyond the simulator's loop (`xhab bench --agent
/// ros2`): the clock alone, `initialpose`, and waiting for `cmd_vel`.
impl crate::external_stack::StackSim for SimNode2 {
    async fn publish_clock(&self, stamp: f64) -> Result<(), RosError> {
        SimNode2::publish_clock(self, stamp).await
    }

    async fn publish_initialpose(&self, stamp: f64, p: Pose2, xy_std: f64, yaw_std: f64) -> Result<(), RosError> {
        self.initialpose.publish(cv::pose_with_covariance(stamp, p, xy_std, yaw_std)).await
    }

    async fn cmd_vel_within(&mut self, grace: Duration) -> Option<xhab_types::Twist> {
        let deadline = tokio::time::Instant::now() + grace;
        loop {
            for _ in 0..MAX_BAD_SAMPLES {
                match self.cmd_vel.take() {
                    Ok(Some((m, _))) => return Some(cv::twist2(&m)),
                    Ok(None) => break,
                    Err(e) => tracing::warn!("cmd_vel: a message that does not decode was dropped: {e}"),
                }
            }
            if tokio::time::Instant::now() >= deadline {
                return None;
            }
            tokio::time::sleep(Duration::from_millis(1)).await;
        }
    }
}
