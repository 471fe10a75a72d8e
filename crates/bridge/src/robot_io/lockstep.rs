//! The simulator's side of xhab's lock-step protocol, whatever the transport: what an
//! episode's announcement says ([`EpisodeStart`]), what the agent answers to a step
//! ([`StepAnswer`]), and the transport's part ([`LockstepTransport`]: announce, publish a step
//! and wait for its answer). ROS 1's and ROS 2's xhab_msgs carry these.

use super::standalone_loop::SimTransport;
use super::state::RobotState;
use crate::ros::node::RosError;
use xhab_sim::sensors::{CameraFrame, CameraParams};
use xhab_types::{Pose2, Twist};

/// The start of one lock-step episode (xhab_msgs/Episode).
#[derive(Debug, Clone, PartialEq)]
pub struct EpisodeStart {
    /// The episode's index in the run (0, 1, ...).
    pub index: u32,
    /// Its id in the dataset.
    pub episode_id: String,
    /// ROS time of the episode's first step (s).
    pub start: f64,
    /// The PointNav goal in the map frame, at height `goal_z` (m).
    pub goal: Pose2,
    /// The goal's height (m): the storey the agent plans on.
    pub goal_z: f64,
    /// The start pose the agent is told (map frame).
    pub initial_pose: Pose2,
    /// The initial pose's spread: standard deviations in x and y (m) and yaw (rad).
    pub initial_std: (f64, f64),
    /// The stamp of the episode's message on `map` (s), if one was published.
    pub map_stamp: Option<f64>,
    /// The stamp of the episode's message on `amcl/map` (s), if one was published.
    pub amcl_map_stamp: Option<f64>,
}

/// The agent's answer to one step (xhab_msgs/StepReply).
#[derive(Debug, Clone, PartialEq)]
pub enum StepAnswer {
    /// Drive with this velocity for one controller period.
    Drive(Twist),
    /// Take this discrete action (Habitat's numbering: 0 stop, 1 forward, 2 left, 3 right).
    Action(i16),
    /// The goal is reached: call Habitat's stop.
    Stop,
    /// The agent gave up, for this reason (empty when it did not say).
    Abort(String),
}

/// What a simulator node does in lock-step on top of [`SimTransport`]: announce each episode
/// on `xhab/episode`, and per step publish the state, the camera frame and `xhab/step`, then
/// wait for the answer on `xhab/step_reply`. ROS 1's `SimNode` and ROS 2's `LockstepSim2`
/// implement it; [`super::run_lockstep_dataset`] drives either.
#[allow(async_fn_in_trait)]
pub trait LockstepTransport: SimTransport {
    /// Announces an episode (latched / transient local).
    async fn publish_episode(&mut self, e: &EpisodeStart) -> Result<(), RosError>;
    /// One step: publishes `st` (and `frame`), then the step, and waits for the agent's
    /// answer to this very step; a timeout error names the reply topic.
    async fn lockstep(&mut self, st: &RobotState<'_>, frame: Option<(&CameraParams, &CameraFrame)>, episode: u32, step: u32) -> Result<StepAnswer, RosError>;
}
