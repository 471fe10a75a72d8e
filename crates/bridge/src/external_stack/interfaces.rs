//! What [`super::run_episodes`] needs of a transport: the simulator node's topics beyond
//! [`SimTransport`]'s, and a client of the stack's goal interface.

use crate::robot_io::SimTransport;
use crate::ros::node::RosError;
use std::time::Duration;
use xhab_types::{Point3, Twist};

/// A goal's state as the stack reports it, transport-neutral.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GoalState {
    /// The state's name as the transport spells it (`ACTIVE`, `SUCCEEDED`, `EXECUTING`, ...).
    pub name: &'static str,
    /// Whether the goal is over.
    pub terminal: bool,
    /// Whether it ended reached (Habitat's stop).
    pub succeeded: bool,
}

/// The simulator node of a benchmark of an external stack.
// Static dispatch only, and the loop runs on `block_on`: the futures need not be `Send`.
#[allow(async_fn_in_trait)]
pub trait StackSim: SimTransport {
    /// Publishes `/clock` alone at `stamp` (s), between episodes.
    async fn publish_clock(&self, stamp: f64) -> Result<(), RosError>;
    /// Publishes `initialpose` in `map` at `stamp` (s): pose `p` with standard deviations
    /// `xy_std` (m) and `yaw_std` (rad).
    async fn publish_initialpose(&self, stamp: f64, p: xhab_types::Pose2, xy_std: f64, yaw_std: f64) -> Result<(), RosError>;
    /// The next `cmd_vel`, waiting up to `grace` (wall time).
    async fn cmd_vel_within(&mut self, grace: Duration) -> Option<Twist>;
    /// Publishes the latched messages (static tf, maps) again: ROS 1's latching can miss a
    /// connection accepted as they were first published. DDS's transient local durability
    /// delivers them to late subscribers by itself, hence the default does nothing.
    async fn republish_latched(&mut self) -> Result<(), RosError> {
        Ok(())
    }
}

/// The client of a stack's goal interface: sends a goal, follows its state, cancels it.
#[allow(async_fn_in_trait)]
pub trait GoalClient {
    /// Sends a new goal named `id` at `position` (map frame, m) stamped `stamp` (s).
    async fn send(&mut self, id: &str, stamp: f64, position: Point3) -> Result<(), RosError>;
    /// Sends the goal again (the stack's connection may not have been up the first time).
    async fn resend(&mut self) -> Result<(), RosError>;
    /// Takes in what the stack reported; returns our goal's state, if known.
    fn absorb(&mut self) -> Option<GoalState>;
    /// Our goal's last known state.
    fn state(&self) -> Option<GoalState>;
    /// Whether the stack has shown itself (a status, a matched endpoint).
    fn server_seen(&self) -> bool;
    /// Cancels our goal.
    async fn cancel(&mut self) -> Result<(), RosError>;
    /// Forgets the goal (between episodes).
    fn clear(&mut self);
    /// Before each episode: what the stack offers to start afresh (ROS 1: move_base's
    /// `clear_costmaps`).
    async fn before_episode(&mut self) {}
    /// Whether the stack takes a goal at once, without its clock moving (a ROS 2 action's
    /// goal response): in lock-step the clock then waits for it (up to the grace), so that
    /// the tick at which the stack starts on the goal does not depend on timing.
    fn acknowledges_at_once(&self) -> bool {
        false
    }
    /// The resolved name the stack reports goal states on, for messages.
    fn status_topic(&self) -> String;
}
