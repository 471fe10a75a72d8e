//! Local control: the [`Controller`] interface (ROS nav_core's BaseLocalPlanner in Rust
//! shape) and [`DwaController`], the DWA local planner with ROS's parameters and fixes for
//! its known failure modes.
//!
//! [`DwaController`] samples velocities in the dynamic window, rolls each out
//! ([`trajectory`]), scores it on distance maps of the local path and goal ([`map_grid`]) and
//! obstacle cost, and refuses oscillations ([`oscillation`]); [`goal_checker`] decides arrival.

mod dwa;
mod dwa_params;
pub mod goal_checker;
pub mod map_grid;
pub mod oscillation;
#[cfg(test)]
mod tests;
pub mod trajectory;

pub use dwa::DwaController;
pub use dwa_params::DwaParams;

use crate::costmap_2d::Costmap2D;
use xhab_types::{Pose2, Twist};

/// Why the controller gave no command.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ControlError {
    /// No plan has been set: call `set_plan` first.
    #[error("no plan to follow")]
    NoPlan,
    /// The robot is outside the costmap handed to the controller (check the rolling window's
    /// size and the localisation).
    #[error("the robot is outside the local costmap")]
    RobotOffCostmap,
    /// No part of the plan ahead lies in the local costmap: the robot is far off its plan;
    /// replan.
    #[error("the plan ahead is outside the local costmap")]
    PlanOffCostmap,
    /// Every sampled velocity collides or leads nowhere; replan or recover.
    #[error("no valid trajectory")]
    NoValidTrajectory,
}

/// A local controller following a global plan.
pub trait Controller {
    /// Follows a new plan (world frame, poses from the robot to the goal).
    fn set_plan(&mut self, plan: &[Pose2]);

    /// The velocity command for the robot at `pose` moving at `vel` (base frame), given the
    /// local `costmap` (world frame).
    fn compute_velocity(
        &mut self,
        pose: Pose2,
        vel: Twist,
        costmap: &Costmap2D,
    ) -> Result<Twist, ControlError>;

    /// Whether the robot at `pose` moving at `vel` has arrived at the plan's goal.
    fn is_goal_reached(&mut self, pose: Pose2, vel: Twist) -> bool;

    /// Caps the translational speed (m/s); the default ignores it.
    fn set_speed_limit(&mut self, _max_vel_trans: f64) {}

    /// Forgets the plan and any state kept between calls.
    fn reset(&mut self) {}
}
