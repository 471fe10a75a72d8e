//! How to run an external stack, and how its episodes went.

use crate::ros::names::Names;
use crate::scan_source::ScanSource;
use serde::{Deserialize, Serialize};
use std::time::Duration;
use xhab_types::OccupancyGrid;

/// How the simulated clock relates to the stack's answers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pace {
    /// After each tick, wait for the stack's `cmd_vel` (up to `grace` of wall time, then go
    /// on with the last command and count a miss).
    Lockstep {
        /// Wall time to wait for `cmd_vel` after a tick.
        grace: Duration,
    },
    /// Run at `rate` times real time, taking whatever `cmd_vel` came last.
    Realtime {
        /// Simulated seconds per wall second.
        rate: f64,
    },
}

/// Where map -> odom comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapOdom {
    /// The stack publishes it (its own amcl).
    Stack,
    /// The simulator publishes it from ground truth (as ROS's fake_localization).
    GroundTruth,
}

/// How goals reach the stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GoalInterface {
    /// The stack's action (ROS 1: `move_base`; ROS 2: `navigate_to_pose`).
    Action,
    /// A goal topic (ROS 1: `move_base_simple/goal`; ROS 2: `goal_pose`); the action's status
    /// topic still tells how the goal ended.
    Simple,
}

/// How to run an external stack.
#[derive(Debug, Clone)]
pub struct ExternalOptions {
    /// ROS 1: `http://host:port` of a running master; `None` starts `rosmaster` for the run.
    /// Not used over ROS 2.
    pub master: Option<String>,
    /// How long to wait for the stack before failing (wall time).
    pub timeout: Duration,
    /// The simulator node's name, namespace and remappings.
    pub names: Names,
    /// How goals reach the stack.
    pub goal_interface: GoalInterface,
    /// Simulated seconds after which an episode's goal is cancelled.
    pub episode_timeout: f64,
    /// Who publishes map -> odom.
    pub map_odom: MapOdom,
    /// How the clock advances.
    pub pace: Pace,
    /// Ticks per simulated second (the stack's controller frequency, Hz).
    pub controller_frequency: f64,
    /// The map to latch on `map`, if any.
    pub map: Option<OccupancyGrid>,
    /// A command that starts the stack (run with `sh -c`, stopped at the end), if any.
    pub launch: Option<String>,
    /// The laser scans published on `scan`.
    pub scan: Option<ScanSource>,
    /// Period between scans (s).
    pub scan_period: f64,
}

/// How an external stack's episode went.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct RosEpisode {
    /// The goal's terminal action state (SUCCEEDED, ABORTED, PREEMPTED, CANCELED, ...), or
    /// `NONE` when the stack never acknowledged the goal.
    pub ros_status: String,
    /// Why the episode ended: `terminal_state`, `timeout`, `stuck` or `step_limit`.
    pub end: String,
    /// Ticks after which the stack's `cmd_vel` did not come within the grace (lock-step).
    pub cmd_vel_missed: u64,
    /// Wall time spent waiting for the stack (s).
    pub stack_wait_s: f64,
    /// Simulated time from sending the goal to its acknowledgement by the stack (s).
    pub goal_ack_s: Option<f64>,
}
