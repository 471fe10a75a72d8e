//! A 2D occupancy grid with nav_msgs/OccupancyGrid semantics.

use crate::{Point2, Pose2};
use serde::{Deserialize, Serialize};

/// Cell value of a free cell (nav_msgs/OccupancyGrid).
pub const GRID_FREE: i8 = 0;
/// Cell value of an occupied cell.
pub const GRID_OCCUPIED: i8 = 100;
/// Cell value of an unknown cell.
pub const GRID_UNKNOWN: i8 = -1;

/// An occupancy grid as nav_msgs/OccupancyGrid: row-major, row 0 at the bottom (lowest y),
/// values 0..=100 (probability of occupancy in percent) or -1 for unknown.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OccupancyGrid {
    /// Cells along x.
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// Edge length of a cell (m).
    pub resolution: f64,
    /// Pose of the lower-left corner of cell (0, 0) in the world frame (m, rad).
    pub origin: Pose2,
    /// `width * height` values, index `row * width + col`.
    pub data: Vec<i8>,
}

impl OccupancyGrid {
    /// A grid filled with `value`.
    pub fn new(width: usize, height: usize, resolution: f64, origin: Pose2, value: i8) -> Self {
        Self { width, height, resolution, origin, data: vec![value; width * height] }
    }
    /// Value at column `col`, row `row` (row 0 at the bottom).
    pub fn get(&self, col: usize, row: usize) -> i8 {
        self.data[row * self.width + col]
    }
    /// Sets the value at column `col`, row `row`.
    pub fn set(&mut self, col: usize, row: usize, v: i8) {
        self.data[row * self.width + col] = v;
    }
    /// World position of a cell's centre (m); assumes an unrotated origin (yaw is applied).
    pub fn cell_center(&self, col: usize, row: usize) -> Point2 {
        let local = Pose2::new((col as f64 + 0.5) * self.resolution, (row as f64 + 0.5) * self.resolution, 0.0);
        self.origin.compose(local).position()
    }
    /// Cell containing world point `p`, or `None` outside the grid.
    pub fn world_to_cell(&self, p: Point2) -> Option<(usize, usize)> {
        let l = self.origin.inverse().compose(Pose2::new(p.x, p.y, 0.0));
        let c = (l.x / self.resolution).floor();
        let r = (l.y / self.resolution).floor();
        if c < 0.0 || r < 0.0 || c >= self.width as f64 || r >= self.height as f64 {
            return None;
        }
        Some((c as usize, r as usize))
    }
}
