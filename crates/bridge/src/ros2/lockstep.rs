//! xhab's lock-step protocol over ROS 2 (`xhab bench --ros2`): the simulator's side
//! ([`LockstepSim2`]: `xhab/episode`, `xhab/step` out, `xhab/step_reply` in, over the
//! simulator node), the QoS that loses no step, and the agent side's [`Inbox`], which takes a
//! step's messages on the standard topics by their stamp.
//!
//! QoS: the lock-step topics and, in lock-step, the state and sensor topics are reliable with
//! [`LOCKSTEP_DEPTH`] samples of history (at most one step is in flight); `xhab/episode` is
//! transient local, so an agent that joins late still reads the episode it is asked about.

use super::convert as cv;
use super::msgs::{builtin_interfaces::Time, geometry_msgs as gm, nav_msgs, sensor_msgs, RosType};
use super::node::{latched_qos, reliable_qos, Ros2Config, Ros2Node};
use super::sim_node::SimNode2;
use super::xhab_msgs;
use crate::robot_io::{Command, EpisodeStart, LockstepTransport, Mounts, RobotState, SimTransport, StepAnswer};
use crate::ros::names::Names;
use crate::ros::node::RosError;
use crate::ros::sim_node::{EPISODE_TOPIC, STEP_REPLY_TOPIC, STEP_TOPIC};
use ros2_client::{Publisher, QosProfile, Subscription};
use std::collections::VecDeque;
use std::time::Duration;
use xhab_sim::sensors::{CameraFrame, CameraParams};
use xhab_types::OccupancyGrid;

/// Samples of history every lock-step reader and writer keeps: far more than the one step in
/// flight, so that none is overwritten before it is read.
pub const LOCKSTEP_DEPTH: usize = 100;

/// The QoS of the lock-step topics and, in lock-step, of the state and sensor topics:
/// reliable, volatile, [`LOCKSTEP_DEPTH`] samples.
pub fn lockstep_qos() -> QosProfile {
    reliable_qos(LOCKSTEP_DEPTH)
}

/// How often a step is published again while the agent has never answered: DDS delivers
/// nothing to a reader before discovery has matched it with the writer, so the first step of
/// a run is repeated (same stamp; receivers take one per stamp) until the answer comes.
const RESEND: Duration = Duration::from_millis(20);

/// ROS 2 time as a comparable (seconds, nanoseconds) pair.
pub fn stamp_key(t: &Time) -> (i32, u32) {
    (t.sec, t.nanosec)
}

/// The simulator node in lock-step: [`SimNode2`] (its state and sensor topics reliable) with
/// xhab's lock-step topics.
pub struct LockstepSim2 {
    /// The simulator node.
    pub sim: SimNode2,
    episode: Publisher<xhab_msgs::Episode>,
    step: Publisher<xhab_msgs::Step>,
    replies: Subscription<xhab_msgs::StepReply>,
    reply_topic: String,
    answered: bool,
    /// Where the steps' wall time went: publishing (state, frame, step) and waiting for the
    /// answer (s), and the steps answered.
    pub timing: StepTiming,
}

/// Wall time of the lock-step exchange, summed over a run's steps (s).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepTiming {
    /// Publishing each step's state, frame and `xhab/step`.
    pub publish_s: f64,
    /// Waiting for `xhab/step_reply` (the round trip and the agent's own work).
    pub wait_s: f64,
    /// Steps answered.
    pub steps: u64,
}

impl LockstepSim2 {
    /// Joins the domain of `config` as the simulator node `names`; scans are stamped with
    /// `laser_frame`; `timeout` bounds every wait for the agent.
    pub fn new(names: Names, config: Ros2Config, laser_frame: &str, timeout: Duration) -> Result<LockstepSim2, RosError> {
        let mut sim = SimNode2::with_sensor_qos(names, config, laser_frame, timeout, lockstep_qos())?;
        let n = &mut sim.node;
        let episode = n.publisher(EPISODE_TOPIC, latched_qos())?;
        let step = n.publisher(STEP_TOPIC, lockstep_qos())?;
        let replies = n.subscription(STEP_REPLY_TOPIC, lockstep_qos())?;
        let reply_topic = n.names.resolve(STEP_REPLY_TOPIC);
        Ok(LockstepSim2 { sim, episode, step, replies, reply_topic, answered: false, timing: StepTiming::default() })
    }
}

/// The announcement as xhab_msgs/Episode.
fn episode_msg(e: &EpisodeStart) -> xhab_msgs::Episode {
    xhab_msgs::Episode {
        index: e.index,
        episode_id: e.episode_id.clone(),
        start: cv::time(e.start),
        goal: gm::PoseStamped { header: cv::header(e.start, "map"), pose: cv::pose(e.goal, e.goal_z) },
        initial_pose: cv::pose_with_covariance(e.start, e.initial_pose, e.initial_std.0, e.initial_std.1),
        map_stamp: e.map_stamp.map_or(Time::default(), cv::time),
        amcl_map_stamp: e.amcl_map_stamp.map_or(Time::default(), cv::time),
    }
}

/// The answer a reply carries; an unknown kind is an error naming it.
fn answer(r: xhab_msgs::StepReply) -> Result<StepAnswer, RosError> {
    match r.kind {
        xhab_msgs::StepReply::DRIVE => Ok(StepAnswer::Drive(cv::twist2(&r.twist))),
        xhab_msgs::StepReply::ACTION => Ok(StepAnswer::Action(r.action)),
        xhab_msgs::StepReply::STOP => Ok(StepAnswer::Stop),
        xhab_msgs::StepReply::ABORT => Ok(StepAnswer::Abort(r.abort_reason)),
        k => Err(RosError::Protocol(format!("{STEP_REPLY_TOPIC}: unknown reply kind {k} (DRIVE, ACTION, STOP or ABORT expected)"))),
    }
}

fn perr(topic: &str, e: impl std::fmt::Display) -> RosError {
    RosError::Node(format!("publishing on {topic}: {e}"))
}

impl SimTransport for LockstepSim2 {
    async fn publish_static_tf(&mut self, m: &Mounts) -> Result<(), RosError> {
        self.sim.publish_static_tf(m).await
    }
    async fn publish_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.sim.publish_map(stamp, map).await
    }
    async fn publish_amcl_map(&mut self, stamp: f64, map: &OccupancyGrid) -> Result<(), RosError> {
        self.sim.publish_amcl_map(stamp, map).await
    }
    async fn publish_state(&self, s: &RobotState<'_>) -> Result<(), RosError> {
        self.sim.publish_state(s).await
    }
    async fn publish_frame(&self, stamp: f64, cam: &CameraParams, frame: &CameraFrame) -> Result<(), RosError> {
        self.sim.publish_frame(stamp, cam, frame).await
    }
    async fn next_command(&mut self) -> Result<Command, RosError> {
        self.sim.next_command().await
    }
    fn latest_command(&mut self) -> Option<Command> {
        self.sim.latest_command()
    }
}

impl LockstepTransport for LockstepSim2 {
    async fn publish_episode(&mut self, e: &EpisodeStart) -> Result<(), RosError> {
        self.episode.async_publish(episode_msg(e)).await.map_err(|x| perr(EPISODE_TOPIC, x))
    }

    async fn lockstep(&mut self, st: &RobotState<'_>, frame: Option<(&CameraParams, &CameraFrame)>, episode: u32, step: u32) -> Result<StepAnswer, RosError> {
        let msg = xhab_msgs::Step { episode, step, stamp: cv::time(st.stamp), scan: st.scan.is_some() };
        let timeout = self.sim.timeout;
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            let t0 = std::time::Instant::now();
            self.sim.publish_state(st).await?;
            if let Some((cam, f)) = frame {
                self.sim.publish_frame(st.stamp, cam, f).await?;
            }
            self.step.async_publish(msg).await.map_err(|e| perr(STEP_TOPIC, e))?;
            let t1 = std::time::Instant::now();
            self.timing.publish_s += (t1 - t0).as_secs_f64();
            let wait_until = if self.answered { deadline } else { deadline.min(tokio::time::Instant::now() + RESEND) };
            loop {
                match tokio::time::timeout_at(wait_until, self.replies.async_take()).await {
                    Ok(Ok((r, _))) if r.episode == episode && r.step == step => {
                        if !self.answered {
                            tracing::debug!("sim: first lock-step answer");
                        }
                        self.answered = true;
                        self.timing.wait_s += t1.elapsed().as_secs_f64();
                        self.timing.steps += 1;
                        return answer(r);
                    }
                    Ok(Ok(_)) => {} // an answer to a resent earlier step
                    Ok(Err(e)) => tracing::warn!("{}: a reply that does not decode was dropped: {e}", self.reply_topic),
                    Err(_) => break,
                }
            }
            if tokio::time::Instant::now() >= deadline {
                return Err(RosError::Timeout(format!(
                    "no answer on {} to step {step} of episode {episode} within {:.0} s (lock-step over ROS 2): is the agent node running in DDS domain {}?",
                    self.reply_topic,
                    timeout.as_secs_f64(),
                    self.sim.node.config.domain_id
                )));
            }
        }
    }
}

/// Messages with a header stamp.
pub trait Stamped2 {
    /// `header.stamp`.
    fn stamp(&self) -> Time;
}

macro_rules! stamped {
    ($($t:ty),*) => {$(impl Stamped2 for $t { fn stamp(&self) -> Time { self.header.stamp } })*};
}
stamped!(gm::PoseStamped, nav_msgs::Odometry, nav_msgs::OccupancyGrid, sensor_msgs::LaserScan);

/// A subscription whose messages are taken by their stamp: lock-step pairs a step's messages
/// on separate topics by `header.stamp`, never by arrival order (DDS orders nothing across
/// topics).
pub struct Inbox<T: RosType> {
    sub: Subscription<T>,
    topic: String,
    pending: VecDeque<T>,
}

impl<T: RosType + Stamped2> Inbox<T> {
    /// Wraps the subscription `sub` to `topic` (its resolved name, for errors).
    pub fn new(sub: Subscription<T>, topic: String) -> Self {
        Self { sub, topic, pending: VecDeque::new() }
    }

    /// A subscription of `node` to `topic` with `qos`, wrapped.
    pub fn subscribe(node: &mut Ros2Node, topic: &str, qos: QosProfile) -> Result<Self, RosError> {
        Ok(Self::new(node.subscription(topic, qos)?, node.names.resolve(topic)))
    }

    /// Moves what has arrived into the queue, without waiting.
    fn absorb(&mut self) {
        for _ in 0..10_000 {
            match self.sub.take() {
                Ok(Some((m, _))) => self.pending.push_back(m),
                Ok(None) => break,
                Err(e) => tracing::warn!("{}: a message that does not decode was dropped: {e}", self.topic),
            }
        }
    }

    /// The message stamped `stamp`, waiting up to `timeout`; messages stamped earlier are
    /// dropped (a step's messages come once, or again with the same stamp when resent), later
    /// ones kept for their own step. `what` names it in the timeout error.
    pub async fn take(&mut self, stamp: Time, timeout: Duration, what: &str) -> Result<T, RosError> {
        let key = stamp_key(&stamp);
        self.absorb();
        self.pending.retain(|m| stamp_key(&m.stamp()) >= key);
        if let Some(i) = self.pending.iter().position(|m| stamp_key(&m.stamp()) == key) {
            return Ok(self.pending.remove(i).expect("found at i"));
        }
        let deadline = tokio::time::Instant::now() + timeout;
        loop {
            match tokio::time::timeout_at(deadline, self.sub.async_take()).await {
                Ok(Ok((m, _))) => match stamp_key(&m.stamp()).cmp(&key) {
                    std::cmp::Ordering::Less => {}
                    std::cmp::Ordering::Equal => return Ok(m),
                    std::cmp::Ordering::Greater => self.pending.push_back(m),
                },
                Ok(Err(e)) => tracing::warn!("{}: a message that does not decode was dropped: {e}", self.topic),
                Err(_) => return Err(RosError::Timeout(format!("no {what} on {} stamped {}.{:09} within {:.0} s", self.topic, stamp.sec, stamp.nanosec, timeout.as_secs_f64()))),
            }
        }
    }

    /// The newest message that has arrived, if any (older ones are dropped).
    pub fn latest(&mut self) -> Option<T> {
        self.absorb();
        let last = self.pending.pop_back();
        self.pending.clear();
        last
    }
}

/// Waits for the announcement of episode `index` on `episodes` (older ones are skipped).
pub async fn episode_announcement(episodes: &Subscription<xhab_msgs::Episode>, index: u32, timeout: Duration) -> Result<xhab_msgs::Episode, RosError> {
    let deadline = tokio::time::Instant::now() + timeout;
    loop {
        match tokio::time::timeout_at(deadline, episodes.async_take()).await {
            Ok(Ok((e, _))) if e.index == index => return Ok(e),
            Ok(Ok(_)) => {}
            Ok(Err(e)) => tracing::warn!("{EPISODE_TOPIC}: an announcement that does not decode was dropped: {e}"),
            Err(_) => return Err(RosError::Timeout(format!("no announcement of episode {index} on {EPISODE_TOPIC} within {:.0} s", timeout.as_secs_f64()))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::Pose2;

    /// With no agent in its domain, a step ends in a timeout that names the reply topic and
    /// the domain, after the timeout and not much later.
    #[test]
    fn a_missing_agent_is_a_timeout_naming_the_reply_topic() {
        let config = Ros2Config { domain_id: 199, localhost_only: true };
        let rt = tokio::runtime::Builder::new_current_thread().enable_all().build().unwrap();
        let t0 = std::time::Instant::now();
        let e = rt
            .block_on(async {
                let mut sim = LockstepSim2::new(Names::plain("xhab_sim_lonely"), config, "laser", Duration::from_millis(600))?;
                let st = RobotState { stamp: 1.0, truth: Pose2::default(), floor_z: 0.0, odom: Pose2::default(), twist: Default::default(), scan: None, map_to_odom: None };
                sim.lockstep(&st, None, 0, 0).await
            })
            .unwrap_err();
        let s = e.to_string();
        assert!(matches!(e, RosError::Timeout(_)), "{s}");
        assert!(s.contains("/xhab/step_reply") && s.contains("DDS domain 199"), "{s}");
        let dt = t0.elapsed().as_secs_f64();
        assert!((0.6..10.0).contains(&dt), "{dt}");
    }
}
