//! The [`CostmapLayer`] interface: costmap_2d's two-phase layer update.
//!
//! Each update first lets every layer grow the [`Bounds`] of what changed (`update_bounds`);
//! the master grid is reset inside those bounds, then every layer writes its costs there
//! (`update_costs`), in the order the layers were configured.

use super::costmap::{Bounds, CellRange, Costmap2D};
use xhab_types::Pose2;

/// One layer of a layered costmap (static map, obstacles, inflation, ...).
pub trait CostmapLayer {
    /// The layer's name as configured (the ROS plugin `name`).
    fn name(&self) -> &str;

    /// Processes pending data and grows `bounds` (world frame, m) by the region whose costs
    /// this layer may change, with the robot at `robot`; `master` gives the grid geometry.
    fn update_bounds(&mut self, robot: Pose2, master: &Costmap2D, bounds: &mut Bounds);

    /// Writes this layer's costs into `master` within `cells` (already reset by the caller).
    fn update_costs(&mut self, robot: Pose2, master: &mut Costmap2D, cells: CellRange);

    /// Forgets everything the layer learnt from sensors (ROS `reset`).
    fn reset(&mut self) {}

    /// Follows a change of the master's geometry: a resize, or a rolling window's move.
    fn match_size(&mut self, _master: &Costmap2D) {}

    /// Whether the layer takes part in updates (ROS `enabled`).
    fn is_enabled(&self) -> bool {
        true
    }
}
