//! A 2D occupancy grid with nav_msgs/OccupancyGrid semantics.

use crate::{Point2, Pose2};
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

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
        Some((axis_cell(l.x / self.resolution, self.width)?, axis_cell(l.y / self.resolution, self.height)?))
    }

    /// The grid in the world's axes: itself when its origin is not rotated (yaw 0), else a
    /// grid of the same resolution over the rotated grid's bounding box whose cells take the
    /// value under their centre (unknown outside it). The costmaps and AMCL index cells by
    /// plain arithmetic, so a rotated map (map_server's origin yaw) goes through this first.
    pub fn axis_aligned(&self) -> Cow<'_, OccupancyGrid> {
        if self.origin.yaw == 0.0 || self.width == 0 || self.height == 0 {
            return Cow::Borrowed(self);
        }
        let (w, h) = (self.width as f64 * self.resolution, self.height as f64 * self.resolution);
        let corners = [(0.0, 0.0), (w, 0.0), (0.0, h), (w, h)].map(|(x, y)| self.origin.compose(Pose2::new(x, y, 0.0)).position());
        let lo = Point2::new(corners.iter().map(|p| p.x).fold(f64::INFINITY, f64::min), corners.iter().map(|p| p.y).fold(f64::INFINITY, f64::min));
        let hi = Point2::new(corners.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max), corners.iter().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max));
        // Cells whose centres lie within the box (a hair's slack for multiples of 90 degrees).
        let cells = |span: f64| ((span / self.resolution) - 1e-9).ceil().max(1.0) as usize;
        let (nw, nh) = (cells(hi.x - lo.x), cells(hi.y - lo.y));
        let mut out = OccupancyGrid::new(nw, nh, self.resolution, Pose2::new(lo.x, lo.y, 0.0), GRID_UNKNOWN);
        for r in 0..nh {
            for c in 0..nw {
                let p = out.cell_center(c, r);
                if let Some((sc, sr)) = self.world_to_cell(p) {
                    out.data[r * nw + c] = self.get(sc, sr);
                }
            }
        }
        Cow::Owned(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_to_cell_is_floor_inside_and_none_outside_or_for_nan() {
        let g = OccupancyGrid::new(4, 3, 0.5, Pose2::new(-1.0, 2.0, 0.0), 0);
        assert_eq!(g.world_to_cell(Point2::new(-1.0, 2.0)), Some((0, 0)));
        assert_eq!(g.world_to_cell(Point2::new(0.99, 3.49)), Some((3, 2)));
        assert_eq!(g.world_to_cell(Point2::new(-1.01, 2.0)), None);
        assert_eq!(g.world_to_cell(Point2::new(1.0, 2.0)), None);
        assert_eq!(g.world_to_cell(Point2::new(f64::NAN, 2.5)), None, "NaN used to land in cell 0");
        assert_eq!(g.world_to_cell(Point2::new(0.0, f64::INFINITY)), None);
    }

    #[test]
    fn a_rotated_grid_keeps_its_values_where_they_are_in_the_world() {
        // 40 x 20 cells, an occupied column at col 30 and a free rest, turned by 90 and by 30
        // degrees about an origin off zero.
        for yaw in [std::f64::consts::FRAC_PI_2, 30f64.to_radians(), -2.0] {
            let mut g = OccupancyGrid::new(40, 20, 0.05, Pose2::new(1.0, -2.0, yaw), GRID_FREE);
            for r in 0..20 {
                g.set(30, r, GRID_OCCUPIED);
            }
            let a = g.axis_aligned();
            assert_eq!(a.origin.yaw, 0.0);
            // Every cell of the original, seen at its centre, has its value in the new grid.
            let mut same = 0;
            for r in 0..20 {
                for c in 0..40 {
                    let p = g.cell_center(c, r);
                    let (ac, ar) = a.world_to_cell(p).expect("inside the box");
                    same += usize::from(a.get(ac, ar) == g.get(c, r));
                }
            }
            // Nearest-cell resampling of a turned grid: all but a few cells on the column's edges.
            assert!(same >= 800 - 40, "yaw {yaw}: {same} of 800");
            // Outside the turned grid, inside the box: unknown.
            assert!(a.data.contains(&GRID_UNKNOWN) || yaw == std::f64::consts::FRAC_PI_2);
        }
        let flat = OccupancyGrid::new(3, 2, 0.1, Pose2::new(1.0, 1.0, 0.0), GRID_FREE);
        assert!(matches!(flat.axis_aligned(), Cow::Borrowed(_)));
    }

    #[test]
    fn a_quarter_turn_is_exact() {
        let mut g = OccupancyGrid::new(4, 2, 1.0, Pose2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2), GRID_FREE);
        g.set(3, 0, GRID_OCCUPIED);
        let a = g.axis_aligned();
        assert_eq!((a.width, a.height), (2, 4));
        // Cell (3, 0) spans x 3..4 along the grid's x, which is the world's y; its y 0..1 runs
        // along the world's -x: world x -1..0, y 3..4.
        let (c, r) = a.world_to_cell(Point2::new(-0.5, 3.5)).unwrap();
        assert_eq!(a.get(c, r), GRID_OCCUPIED);
        assert_eq!(a.data.iter().filter(|&&v| v == GRID_OCCUPIED).count(), 1);
        assert!(!a.data.contains(&GRID_UNKNOWN));
    }
}

/// The cell index `floor(x)` along an axis of `n` cells, if in `0..n` (`x` in cells; NaN is
/// outside): the one world-to-cell rule of every grid (occupancy grids, costmaps, navigation
/// grids). Truncation equals `floor` for the non-negative values kept, without a libm call.
#[inline]
pub fn axis_cell(x: f64, n: usize) -> Option<usize> {
    (x >= 0.0 && x < n as f64).then_some(x as usize)
}
