//! The simulator as a ROS 1 node: publishes what a robot driver and its sensors would (clock,
//! odom with covariance, tf per REP-105, scan, camera images, the map, ground truth) and takes
//! `cmd_vel` or `action`. Lock-step between xhab's own nodes adds `xhab/episode`, `xhab/step`
//! and `xhab/step_reply` (xhab_msgs): standard topics carry only their standard content.

use super::convert as cv;
use super::msgs::{geometry_msgs as gm, nav_msgs, rosgraph_msgs, sensor_msgs, std_msgs, tf2_msgs, xhab_msgs};
use super::names::Names;
use super::node::{RosError, RosNode};
use roslibrust::ros1::Publisher;
use std::time::Duration;
use tokio::sync::mpsc;
use xhab_sim::sensors::{CameraFrame, CameraParams, DepthNoise, Renderer};
use xhab_types::{OccupancyGrid, Pose2, Twist};

pub use crate::robot_io::{Command, Mounts, RobotState, DEPTH_OPTICAL_FRAME, RGB_OPTICAL_FRAME};
use crate::robot_io::{render_frame, EpisodeStart, LockstepTransport, SimTransport, StepAnswer, OPTICAL_ROTATION};

/// The topic of the map AMCL localises on when it differs from `map` (the scene cut at the
/// laser's height, while `map` holds the body-band map for the costmap), as amcl's `map`
/// remapped into its namespace.
pub const AMCL_MAP_TOPIC: &str = "amcl/map";
/// xhab's lock-step topics (xhab_msgs/Episode, Step, StepReply).
pub const EPISODE_TOPIC: &str = "xhab/episode";
/// See [`EPISODE_TOPIC`].
pub const STEP_TOPIC: &str = "xhab/step";
/// See [`EPISODE_TOPIC`].
pub const STEP_REPLY_TOPIC: &str = "xhab/step_reply";

/// How often a lock-step step is published again while no reply has ever come: roslibrust
/// drops what is published before a subscriber's connection is up, so the first step of a
/// run is repeated (same stamp; receivers take one per stamp) until the agent answers.
const RESEND: Duration = Duration::from_millis(5);

/// The simulator node's publishers and command subscriptions.
pub struct SimNode {
    /// The node (kept alive with it).
    pub node: RosNode,
    clock: Publisher<rosgraph_msgs::Clock>,
    tf: Publisher<tf2_msgs::TFMessage>,
    tf_static: Publisher<tf2_msgs::TFMessage>,
    odom: Publisher<nav_msgs::Odometry>,
    truth: Publisher<gm::PoseStamped>,
    scan: Publisher<sensor_msgs::LaserScan>,
    map: Publisher<nav_msgs::OccupancyGrid>,
    amcl_map: Publisher<nav_msgs::OccupancyGrid>,
    initialpose: Publisher<gm::PoseWithCovarianceStamped>,
    depth: Publisher<sensor_msgs::Image>,
    depth_info: Publisher<sensor_msgs::CameraInfo>,
    rgb: Publisher<sensor_msgs::Image>,
    rgb_info: Publisher<sensor_msgs::CameraInfo>,
    episode: Publisher<xhab_msgs::Episode>,
    step: Publisher<xhab_msgs::Step>,
    replies: mpsc::UnboundedReceiver<xhab_msgs::StepReply>,
    cmd_vel: mpsc::UnboundedReceiver<gm::Twist>,
    action: mpsc::UnboundedReceiver<std_msgs::Int16>,
    laser_frame: String,
    answered: bool,
    /// The latched messages published so far (static tf, map, localisation map, episode),
    /// published again with the first step until the agent answers: roslibrust's latching
    /// misses a message published while a subscriber's connection is being accepted.
    latched: Latched,
    /// How long to wait for a peer before failing (s).
    pub timeout: Duration,
}

/// See [`SimNode::latched`].
#[derive(Default)]
struct Latched {
    tf_static: Option<tf2_msgs::TFMessage>,
    map: Option<nav_msgs::OccupancyGrid>,
    amcl_map: Option<nav_msgs::OccupancyGrid>,
    episode: Option<xhab_msgs::Episode>,
}

fn perr(topic: &str, e: impl std::fmt::Display) -> RosError {
    RosError::Node(format!("publishing on {topic}: {e}"))
}

impl SimNode {
    /// Registers the node `names` and its topics with the master at `uri`; scans are stamped
    /// with `laser_frame`.
    pub async fn new(uri: &str, names: Names, laser_frame: &str, timeout: Duration) -> Result<SimNode, RosError> {
        let t0 = std::time::Instant::now();
        let node = RosNode::new(uri, names).await?;
        tracing::debug!("sim: node registered in {:.3} s", t0.elapsed().as_secs_f64());
        // Registrations are round trips to the master: made together, not one after another.
        let n = &node;
        let (clock, tf, tf_static, odom, truth, scan, map, amcl_map, initialpose) = tokio::try_join!(
            n.advertise("/clock", false),
            n.advertise("/tf", false),
            n.advertise("/tf_static", true),
            n.advertise("odom", false),
            n.advertise("ground_truth/pose", false),
            n.advertise("scan", false),
            n.advertise("map", true),
            n.advertise(AMCL_MAP_TOPIC, true),
            n.advertise("initialpose", false),
        )?;
        let (depth, depth_info, rgb, rgb_info, episode, step) = tokio::try_join!(
            n.advertise("camera/depth/image_raw", false),
            n.advertise("camera/depth/camera_info", false),
            n.advertise("camera/rgb/image_raw", false),
            n.advertise("camera/rgb/camera_info", false),
            n.advertise(EPISODE_TOPIC, true),
            n.advertise(STEP_TOPIC, false),
        )?;
        let (replies, cmd_vel, action) = tokio::try_join!(n.subscribe(STEP_REPLY_TOPIC), n.subscribe("cmd_vel"), n.subscribe("action"))?;
        Ok(SimNode {
            clock,
            tf,
            tf_static,
            odom,
            truth,
            scan,
            map,
            amcl_map,
            initialpose,
            depth,
            depth_info,
            rgb,
            rgb_info,
            episode,
            step,
            replies,
            cmd_vel,
            action,
            node,
            laser_frame: laser_frame.to_string(),
            answered: false,
            latched: Latched::default(),
            timeout,
        })
    }

    /// Publishes the static transforms (latched): base_link -> the laser frame, base_link ->
    /// camera_link -> the depth and RGB optical frames.
    pub async fn publish_static_tf(&mut self, m: &Mounts) -> Result<(), RosError> {
        let [x, y, z, w] = OPTICAL_ROTATION;
        let optical = gm::Transform { translation: gm::Vector3 { x: 0.0, y: 0.0, z: 0.0 }, rotation: gm::Quaternion { x, y, z, w } };
        let msg = tf2_msgs::TFMessage {
            transforms: vec![
                cv::tf(0.0, "base_link", &m.laser_frame, cv::transform(m.laser, m.laser_z)),
                cv::tf(0.0, "base_link", "camera_link", cv::transform(Pose2::default(), m.camera_z)),
                cv::tf(0.0, "camera_link", DEPTH_OPTICAL_FRAME, optical.clone()),
                cv::tf(0.0, "camera_link", RGB_OPTICAL_FRAME, optical),
            ],
        };
        self.tf_static.publish(&msg).await.map_err(|e| perr("/tf_static", e))?;
        self.latched.tf_static = Some(msg);
        Ok(())
    }

    /// Publishes the localisation map (latched) on [`AMCL_MAP_TOPIC`].
    pub async fn publish_amcl_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        let m = cv::occupancy_grid(stamp, map);
        self.amcl_map.publish(&m).await.map_err(|e| perr(AMCL_MAP_TOPIC, e))?;
        self.latched.amcl_map = Some(m);
        Ok(())
    }

    /// Publishes the map (latched).
    pub async fn publish_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        let m = cv::occupancy_grid(stamp, map);
        self.map.publish(&m).await.map_err(|e| perr("map", e))?;
        self.latched.map = Some(m);
        Ok(())
    }

    /// Publishes an initial pose estimate on `initialpose` with standard deviations (m, rad).
    pub async fn publish_initialpose(&self, stamp: f64, p: Pose2, xy_std: f64, yaw_std: f64) -> Result<(), RosError> {
        self.initialpose.publish(&cv::pose_with_covariance(stamp, p, xy_std, yaw_std)).await.map_err(|e| perr("initialpose", e))
    }

    /// Publishes the clock alone (between episodes, so that sim-time timers run).
    pub async fn publish_clock(&self, stamp: f64) -> Result<(), RosError> {
        self.clock.publish(&rosgraph_msgs::Clock { clock: cv::time(stamp) }).await.map_err(|e| perr("/clock", e))
    }

    /// Publishes the robot's state: clock, tf odom -> base_link (and map -> odom when given),
    /// scan (if any), odom and ground truth, every one stamped `s.stamp`.
    pub async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError> {
        self.publish_clock(s.stamp).await?;
        let mut transforms = vec![cv::tf(s.stamp, "odom", "base_link", cv::transform(s.odom, 0.0))];
        if let Some(m2o) = s.map_to_odom {
            transforms.push(cv::tf(s.stamp, "map", "odom", cv::transform(m2o, 0.0)));
        }
        self.tf.publish(&tf2_msgs::TFMessage { transforms }).await.map_err(|e| perr("/tf", e))?;
        if let Some((scan, period)) = s.scan {
            self.scan.publish(&cv::laser_scan(s.stamp, &self.laser_frame, scan, period)).await.map_err(|e| perr("scan", e))?;
        }
        self.odom.publish(&cv::odometry(s.stamp, s.odom, s.twist)).await.map_err(|e| perr("odom", e))?;
        let gt = gm::PoseStamped { header: cv::header(s.stamp, "map"), pose: cv::pose(s.truth, s.floor_z) };
        self.truth.publish(&gt).await.map_err(|e| perr("ground_truth/pose", e))
    }

    /// Publishes a rendered camera frame: depth, and RGB when it has one, each with its
    /// camera_info in its own optical frame.
    pub async fn publish_frame(&self, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError> {
        let k = cam.intrinsics();
        self.depth_info.publish(&cv::camera_info(stamp, DEPTH_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera/depth/camera_info", e))?;
        self.depth.publish(&cv::depth_image(stamp, DEPTH_OPTICAL_FRAME, &frame.depth)).await.map_err(|e| perr("camera/depth/image_raw", e))?;
        if let Some(rgb) = &frame.rgb {
            self.rgb_info.publish(&cv::camera_info(stamp, RGB_OPTICAL_FRAME, cam.width, cam.height, &k)).await.map_err(|e| perr("camera/rgb/camera_info", e))?;
            self.rgb.publish(&cv::rgb_image(stamp, RGB_OPTICAL_FRAME, cam.width, cam.height, rgb.clone())).await.map_err(|e| perr("camera/rgb/image_raw", e))?;
        }
        Ok(())
    }

    /// Renders depth (with `noise`, seeded by `seed` and `n`; and RGB when `want_rgb`) from
    /// `base` and publishes it.
    pub async fn publish_camera(&self, n: u64, stamp: f64, renderer: &Renderer, base: Pose2, floor_z: f64, cam: &CameraParams, want_rgb: bool, noise: &DepthNoise, seed: u64) -> Result<(), RosError> {
        let f = render_frame(n, renderer, base, floor_z, cam, want_rgb, noise, seed)?;
        self.publish_frame(stamp, cam, &f).await
    }

    /// Announces a lock-step episode on [`EPISODE_TOPIC`] (latched).
    pub async fn publish_episode(&mut self, e: &xhab_msgs::Episode) -> Result<(), RosError> {
        self.episode.publish(e).await.map_err(|x| perr(EPISODE_TOPIC, x))?;
        self.latched.episode = Some(e.clone());
        Ok(())
    }

    /// Publishes the latched messages again (see [`SimNode::latched`]).
    pub async fn republish_latched(&self) -> Result<(), RosError> {
        let l = &self.latched;
        if let Some(m) = &l.tf_static {
            self.tf_static.publish(m).await.map_err(|e| perr("/tf_static", e))?;
        }
        if let Some(m) = &l.map {
            self.map.publish(m).await.map_err(|e| perr("map", e))?;
        }
        if let Some(m) = &l.amcl_map {
            self.amcl_map.publish(m).await.map_err(|e| perr(AMCL_MAP_TOPIC, e))?;
        }
        if let Some(m) = &l.episode {
            self.episode.publish(m).await.map_err(|e| perr(EPISODE_TOPIC, e))?;
        }
        Ok(())
    }

    /// One lock-step step: publishes the state (and camera frame), then `xhab/step`, and
    /// waits for the agent's reply to this very step. Until the agent has answered once, the
    /// step is published again every 5 ms (the first messages of a run may reach no one),
    /// after the latched messages.
    pub async fn lockstep(&mut self, st: &RobotState<'_>, frame: Option<(&CameraParams, &CameraFrame)>, episode: u32, step: u32) -> Result<xhab_msgs::StepReply, RosError> {
        let msg = xhab_msgs::Step { episode, step, stamp: cv::time(st.stamp), scan: st.scan.is_some() };
        let deadline = tokio::time::Instant::now() + self.timeout;
        let mut resend = false;
        loop {
            if resend {
                self.republish_latched().await?;
            }
            resend = true;
            self.publish_state(st).await?;
            if let Some((cam, f)) = frame {
                self.publish_frame(st.stamp, cam, f).await?;
            }
            self.step.publish(&msg).await.map_err(|e| perr(STEP_TOPIC, e))?;
            let wait_until = if self.answered { deadline } else { deadline.min(tokio::time::Instant::now() + RESEND) };
            loop {
                match tokio::time::timeout_at(wait_until, self.replies.recv()).await {
                    Ok(Some(r)) if r.episode == episode && r.step == step => {
                        if !self.answered {
                            tracing::debug!("sim: first lock-step answer");
                        }
                        self.answered = true;
                        return Ok(r);
                    }
                    Ok(Some(_)) => {} // an answer to a resent earlier step
                    Ok(None) => return Err(RosError::Protocol(format!("{STEP_REPLY_TOPIC}: the subscription closed"))),
                    Err(_) => break,
                }
            }
            if tokio::time::Instant::now() >= deadline {
                return Err(RosError::Timeout(format!(
                    "no answer on {} to step {step} of episode {episode} within {:.0} s (lock-step): is the agent node running on this master?",
                    self.node.names.resolve(STEP_REPLY_TOPIC),
                    self.timeout.as_secs_f64()
                )));
            }
        }
    }

    /// The next command (`xhab ros sim --lockstep`): waits up to the timeout for `cmd_vel`
    /// or `action`.
    pub async fn next_command(&mut self) -> Result<Command, RosError> {
        tokio::select! {
            m = self.cmd_vel.recv() => match m {
                Some(m) => Ok(Command::Twist(cv::twist2(&m))),
                None => Err(RosError::Protocol("cmd_vel subscription closed".into())),
            },
            m = self.action.recv() => match m {
                Some(m) => Ok(Command::Action(m.data)),
                None => Err(RosError::Protocol("action subscription closed".into())),
            },
            _ = tokio::time::sleep(self.timeout) => Err(RosError::Timeout(format!("no cmd_vel or action within {:.0} s (lock-step)", self.timeout.as_secs_f64()))),
        }
    }

    /// The next `cmd_vel` within `grace` (wall time), if one comes.
    pub async fn cmd_vel_within(&mut self, grace: Duration) -> Option<Twist> {
        match tokio::time::timeout(grace, self.cmd_vel.recv()).await {
            Ok(Some(m)) => Some(cv::twist2(&m)),
            _ => None,
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

impl SimTransport for SimNode {
    async fn publish_static_tf(&mut self, m: &Mounts) -> Result<(), RosError> {
        SimNode::publish_static_tf(self, m).await
    }
    async fn publish_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        SimNode::publish_map(self, stamp, map).await
    }
    async fn publish_amcl_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        SimNode::publish_amcl_map(self, stamp, map).await
    }
    async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError> {
        SimNode::publish_state(self, s).await
    }
    async fn publish_frame(&self, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError> {
        SimNode::publish_frame(self, stamp, cam, frame).await
    }
    async fn next_command(&mut self) -> Result<Command, RosError> {
        SimNode::next_command(self).await
    }
    fn latest_command(&mut self) -> Option<Command> {
        SimNode::latest_command(self)
    }
}

/// The announcement of a lock-step episode as xhab_msgs/Episode.
fn episode_msg(e: &EpisodeStart) -> xhab_msgs::Episode {
    let zero = cv::time(0.0);
    xhab_msgs::Episode {
        index: e.index,
        episode_id: e.episode_id.clone(),
        start: cv::time(e.start),
        goal: gm::PoseStamped { header: cv::header(e.start, "map"), pose: cv::pose(e.goal, e.goal_z) },
        initial_pose: cv::pose_with_covariance(e.start, e.initial_pose, e.initial_std.0, e.initial_std.1),
        map_stamp: e.map_stamp.map_or(zero.clone(), cv::time),
        amcl_map_stamp: e.amcl_map_stamp.map_or(zero, cv::time),
    }
}

impl LockstepTransport for SimNode {
    async fn publish_episode(&mut self, e: &EpisodeStart) -> Result<(), RosError> {
        SimNode::publish_episode(self, &episode_msg(e)).await
    }
    async fn lockstep(&mut self, st: &RobotState<'_>, frame: Option<(&CameraParams, &CameraFrame)>, episode: u32, step: u32) -> Result<StepAnswer, RosError> {
        let r = SimNode::lockstep(self, st, frame, episode, step).await?;
        match r.kind {
            xhab_msgs::StepReply::DRIVE => Ok(StepAnswer::Drive(cv::twist2(&r.twist))),
            xhab_msgs::StepReply::ACTION => Ok(StepAnswer::Action(r.action)),
            xhab_msgs::StepReply::STOP => Ok(StepAnswer::Stop),
            xhab_msgs::StepReply::ABORT => Ok(StepAnswer::Abort(r.abort_reason)),
            k => Err(RosError::Protocol(format!("{STEP_REPLY_TOPIC}: unknown reply kind {k} (DRIVE, ACTION, STOP or ABORT expected)"))),
        }
    }
}
