//! Global planning on a costmap: the [`GlobalPlanner`] interface and [`GridPlanner`], a
//! Dijkstra / A* planner with ROS global_planner's parameters and a wall-avoiding cost, whose
//! paths are shortened where a straight line is no dearer ([`smoother`]) and given headings
//! ([`orientation`]).

mod grid_planner;
mod grid_search;
pub mod orientation;
mod planner_params;
pub mod smoother;
#[cfg(test)]
mod tests;

pub use grid_planner::GridPlanner;
pub use grid_search::{CostModel, SearchResult};
pub use planner_params::GlobalPlannerParams;

use crate::costmap_2d::Costmap2D;
use xhab_types::Pose2;

/// A path in the costmap's frame: poses from the start to the goal (m, rad), each heading
/// along the path (see [`orientation`]), the last one the goal's.
pub type Path = Vec<Pose2>;

/// Why no path was made (the variants of nav2's planner exceptions).
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// The start lies outside the costmap: localisation is off, or the map is too small.
    #[error("the start is outside the costmap")]
    StartOutsideMap,
    /// The goal lies outside the costmap: pick a goal on the map.
    #[error("the goal is outside the costmap")]
    GoalOutsideMap,
    /// The start cell is lethal (or unknown with `allow_unknown` off): the robot stands in an
    /// obstacle as far as the costmap knows; clearing the costmap may help.
    #[error("the start is in an obstacle")]
    StartOccupied,
    /// The goal cell is impassable and no free cell lies within `default_tolerance`.
    #[error("the goal is in an obstacle and no free cell is within tolerance")]
    GoalOccupied,
    /// No passable route joins start and goal (nor any free cell within tolerance of it).
    #[error("no path from start to goal")]
    NoPath,
}

/// A global planner: a path over `costmap` from `start` to `goal` (world frame).
pub trait GlobalPlanner {
    /// Plans a path; the first pose is at `start`, the last at `goal` (or at the free cell
    /// chosen within tolerance of it).
    fn plan(&mut self, costmap: &Costmap2D, start: Pose2, goal: Pose2) -> Result<Path, PlanError>;
}

/// Length of a path (m).
pub fn path_length(path: &[Pose2]) -> f64 {
    path.windows(2)
        .map(|w| w[0].position().dist(w[1].position()))
        .sum()
}
