//! [`GlobalPlannerParams`]: ROS global_planner's parameters (namespace `GlobalPlanner`).

use crate::param_error::{check_range, ParamError};
use serde::{Deserialize, Serialize};

/// Global planner parameters (ROS `global_planner` names and noetic defaults, plus
/// `smooth_path`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GlobalPlannerParams {
    /// Dijkstra (true, default) or A* (false); both return a cheapest path, A* explores less.
    pub use_dijkstra: bool,
    /// Cost of a free cell per cell length (default 50, range [1, 255]).
    pub neutral_cost: f64,
    /// Weight of the costmap's cost (default 3.0, range [0, 10]).
    pub cost_factor: f64,
    /// Cells of this cost and above are impassable (default 253 = INSCRIBED, range [1, 255]).
    pub lethal_cost: i32,
    /// Unknown cells are passable, at the highest non-lethal cost (default true).
    pub allow_unknown: bool,
    /// How far from an impassable or unreachable goal a reachable free cell may be taken
    /// instead (m, default 0, range [0, 100]).
    pub default_tolerance: f64,
    /// Headings along the path: 0 none, 1 forward (default), 2 interpolate, 3 forward then
    /// interpolate, 4 backward, 5 leftward, 6 rightward.
    pub orientation_mode: i32,
    /// Points on each side used for a forward heading (default 1, range [1, 255]).
    pub orientation_window_size: i32,
    /// Shortens and smooths the grid path (xhab, default true; false returns cell centres).
    pub smooth_path: bool,
}

impl Default for GlobalPlannerParams {
    fn default() -> Self {
        Self {
            use_dijkstra: true,
            neutral_cost: 50.0,
            cost_factor: 3.0,
            lethal_cost: 253,
            allow_unknown: true,
            default_tolerance: 0.0,
            orientation_mode: 1,
            orientation_window_size: 1,
            smooth_path: true,
        }
    }
}

impl GlobalPlannerParams {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("neutral_cost", self.neutral_cost, 1.0, 255.0)?;
        check_range("cost_factor", self.cost_factor, 0.0, 10.0)?;
        check_range("lethal_cost", self.lethal_cost as f64, 1.0, 255.0)?;
        check_range("default_tolerance", self.default_tolerance, 0.0, 100.0)?;
        check_range("orientation_mode", self.orientation_mode as f64, 0.0, 6.0)?;
        check_range(
            "orientation_window_size",
            self.orientation_window_size as f64,
            1.0,
            255.0,
        )
    }
}
