//! [`Costmap2D`]: a grid of u8 costs over an axis-aligned window of the world, with the
//! world <-> map conversions of ROS costmap_2d; [`Bounds`] and [`CellRange`] describe the part
//! of it an update touches.

use super::cost_values::{cost_to_occupancy, FREE};
use xhab_types::{OccupancyGrid, Point2, Pose2};

/// An axis-aligned region of the world frame (m) that layers grow as they change cells;
/// starts empty (min > max).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    /// Smallest x (m).
    pub min_x: f64,
    /// Smallest y (m).
    pub min_y: f64,
    /// Largest x (m).
    pub max_x: f64,
    /// Largest y (m).
    pub max_y: f64,
}

impl Default for Bounds {
    fn default() -> Self {
        Self::empty()
    }
}

impl Bounds {
    /// The empty region.
    pub const fn empty() -> Self {
        Self {
            min_x: f64::INFINITY,
            min_y: f64::INFINITY,
            max_x: f64::NEG_INFINITY,
            max_y: f64::NEG_INFINITY,
        }
    }
    /// Whether nothing has been touched.
    pub fn is_empty(&self) -> bool {
        self.min_x > self.max_x || self.min_y > self.max_y
    }
    /// Grows the region to contain point `p` (m).
    pub fn touch(&mut self, p: Point2) {
        self.min_x = self.min_x.min(p.x);
        self.min_y = self.min_y.min(p.y);
        self.max_x = self.max_x.max(p.x);
        self.max_y = self.max_y.max(p.y);
    }
    /// Grows a non-empty region by `margin` (m) on every side.
    pub fn expand(&mut self, margin: f64) {
        if !self.is_empty() {
            self.min_x -= margin;
            self.min_y -= margin;
            self.max_x += margin;
            self.max_y += margin;
        }
    }
    /// Grows the region to contain `o`.
    pub fn union(&mut self, o: &Bounds) {
        if !o.is_empty() {
            self.touch(Point2::new(o.min_x, o.min_y));
            self.touch(Point2::new(o.max_x, o.max_y));
        }
    }
}

/// A half-open range of cells `[x0, xn) x [y0, yn)` of a costmap.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct CellRange {
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// One past the last column.
    pub xn: usize,
    /// One past the last row.
    pub yn: usize,
}

impl CellRange {
    /// Whether the range holds no cell.
    pub fn is_empty(&self) -> bool {
        self.x0 >= self.xn || self.y0 >= self.yn
    }
    /// The range grown by `k` cells on every side, clipped to a `size_x` x `size_y` grid.
    pub fn grown(&self, k: usize, size_x: usize, size_y: usize) -> CellRange {
        CellRange {
            x0: self.x0.saturating_sub(k),
            y0: self.y0.saturating_sub(k),
            xn: (self.xn + k).min(size_x),
            yn: (self.yn + k).min(size_y),
        }
    }
}

/// A costmap: `size_x * size_y` u8 costs (see [`cost_values`](super::cost_values)), row-major,
/// row 0 at the bottom (lowest y), cell (0, 0)'s lower-left corner at `origin` (world frame, m);
/// the grid is axis-aligned with the world frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Costmap2D {
    size_x: usize,
    size_y: usize,
    resolution: f64,
    origin: Point2,
    default_value: u8,
    costs: Vec<u8>,
}

impl Costmap2D {
    /// A costmap of `size_x` x `size_y` cells of `resolution` (m), cell (0, 0)'s corner at
    /// `origin` (m), every cell `default_value`.
    pub fn new(
        size_x: usize,
        size_y: usize,
        resolution: f64,
        origin: Point2,
        default_value: u8,
    ) -> Self {
        Self {
            size_x,
            size_y,
            resolution,
            origin,
            default_value,
            costs: vec![default_value; size_x * size_y],
        }
    }

    /// A costmap over the same cells as `grid`, every cell `default_value` (the grid's yaw is
    /// ignored, as ROS costmap_2d does).
    pub fn like_grid(grid: &OccupancyGrid, default_value: u8) -> Self {
        Self::new(
            grid.width,
            grid.height,
            grid.resolution,
            grid.origin.position(),
            default_value,
        )
    }

    /// Columns.
    pub fn size_x(&self) -> usize {
        self.size_x
    }
    /// Rows.
    pub fn size_y(&self) -> usize {
        self.size_y
    }
    /// Cell edge length (m).
    pub fn resolution(&self) -> f64 {
        self.resolution
    }
    /// World position of the lower-left corner of cell (0, 0) (m).
    pub fn origin(&self) -> Point2 {
        self.origin
    }
    /// Width of the window (m).
    pub fn size_in_meters_x(&self) -> f64 {
        self.size_x as f64 * self.resolution
    }
    /// Height of the window (m).
    pub fn size_in_meters_y(&self) -> f64 {
        self.size_y as f64 * self.resolution
    }
    /// The value cells are reset to.
    pub fn default_value(&self) -> u8 {
        self.default_value
    }
    /// Sets the value cells are reset to.
    pub fn set_default_value(&mut self, v: u8) {
        self.default_value = v;
    }
    /// All costs, index `my * size_x + mx`.
    pub fn costs(&self) -> &[u8] {
        &self.costs
    }
    /// All costs, mutable.
    pub fn costs_mut(&mut self) -> &mut [u8] {
        &mut self.costs
    }
    /// Index of cell (mx, my).
    pub fn index(&self, mx: usize, my: usize) -> usize {
        my * self.size_x + mx
    }
    /// Cell (mx, my) of index `i`.
    pub fn cell_of(&self, i: usize) -> (usize, usize) {
        (i % self.size_x, i / self.size_x)
    }
    /// Cost of cell (mx, my); the cell must be inside.
    pub fn cost(&self, mx: usize, my: usize) -> u8 {
        self.costs[self.index(mx, my)]
    }
    /// Sets the cost of cell (mx, my); the cell must be inside.
    pub fn set_cost(&mut self, mx: usize, my: usize, c: u8) {
        let i = self.index(mx, my);
        self.costs[i] = c;
    }

    /// Continuous map coordinates (cells, may lie outside) of world point `p` (m).
    pub fn world_to_map_continuous(&self, p: Point2) -> (f64, f64) {
        (
            (p.x - self.origin.x) / self.resolution,
            (p.y - self.origin.y) / self.resolution,
        )
    }
    /// Cell containing world point `p` (m), or `None` outside the window.
    pub fn world_to_map(&self, p: Point2) -> Option<(usize, usize)> {
        let (fx, fy) = self.world_to_map_continuous(p);
        (fx >= 0.0 && fy >= 0.0 && fx < self.size_x as f64 && fy < self.size_y as f64)
            .then_some((fx as usize, fy as usize))
    }
    /// Cell (possibly outside the window) containing world point `p` (m), as signed indices.
    pub fn world_to_map_unbounded(&self, p: Point2) -> (i64, i64) {
        let (fx, fy) = self.world_to_map_continuous(p);
        (fx.floor() as i64, fy.floor() as i64)
    }
    /// World position of the centre of cell (mx, my) (m).
    pub fn map_to_world(&self, mx: usize, my: usize) -> Point2 {
        Point2::new(
            self.origin.x + (mx as f64 + 0.5) * self.resolution,
            self.origin.y + (my as f64 + 0.5) * self.resolution,
        )
    }
    /// Cost at world point `p` (m), `None` outside the window.
    pub fn cost_at(&self, p: Point2) -> Option<u8> {
        self.world_to_map(p).map(|(x, y)| self.cost(x, y))
    }
    /// Whether the window contains world point `p` (m).
    pub fn contains(&self, p: Point2) -> bool {
        self.world_to_map(p).is_some()
    }

    /// The cells a world region covers, clipped to the window (empty when disjoint).
    pub fn cell_range(&self, b: &Bounds) -> CellRange {
        if b.is_empty() {
            return CellRange::default();
        }
        let clip = |v: f64, n: usize| v.clamp(0.0, n as f64) as usize;
        let (x0, y0) = self.world_to_map_continuous(Point2::new(b.min_x, b.min_y));
        let (x1, y1) = self.world_to_map_continuous(Point2::new(b.max_x, b.max_y));
        CellRange {
            x0: clip(x0.floor(), self.size_x),
            y0: clip(y0.floor(), self.size_y),
            xn: clip(x1.floor() + 1.0, self.size_x),
            yn: clip(y1.floor() + 1.0, self.size_y),
        }
    }
    /// The whole window as a cell range.
    pub fn full_range(&self) -> CellRange {
        CellRange {
            x0: 0,
            y0: 0,
            xn: self.size_x,
            yn: self.size_y,
        }
    }
    /// The whole window as a world region (m).
    pub fn world_bounds(&self) -> Bounds {
        Bounds {
            min_x: self.origin.x,
            min_y: self.origin.y,
            max_x: self.origin.x + self.size_in_meters_x(),
            max_y: self.origin.y + self.size_in_meters_y(),
        }
    }

    /// Sets every cell to the default value.
    pub fn reset(&mut self) {
        let d = self.default_value;
        self.costs.iter_mut().for_each(|c| *c = d);
    }
    /// Sets the cells of `r` to the default value.
    pub fn reset_range(&mut self, r: CellRange) {
        let d = self.default_value;
        for my in r.y0..r.yn {
            let row = my * self.size_x;
            self.costs[row + r.x0..row + r.xn]
                .iter_mut()
                .for_each(|c| *c = d);
        }
    }
    /// Reallocates the grid with a new geometry, every cell the default value.
    pub fn resize(&mut self, size_x: usize, size_y: usize, resolution: f64, origin: Point2) {
        *self = Self::new(size_x, size_y, resolution, origin, self.default_value);
    }

    /// Moves the window so that its origin is `new_origin` snapped down to whole cells (m),
    /// keeping the costs of the cells both windows cover and resetting the others (ROS
    /// `Costmap2D::updateOrigin`, used by rolling windows).
    pub fn update_origin(&mut self, new_origin: Point2) {
        let dx = ((new_origin.x - self.origin.x) / self.resolution).floor() as i64;
        let dy = ((new_origin.y - self.origin.y) / self.resolution).floor() as i64;
        if dx == 0 && dy == 0 {
            return;
        }
        let (sx, sy) = (self.size_x as i64, self.size_y as i64);
        let mut moved = vec![self.default_value; self.costs.len()];
        for ny in 0..sy {
            let oy = ny + dy;
            if oy < 0 || oy >= sy {
                continue;
            }
            let (x_lo, x_hi) = ((-dx).max(0), (sx - dx).min(sx));
            if x_lo >= x_hi {
                continue;
            }
            let src = (oy * sx + x_lo + dx) as usize;
            let dst = (ny * sx + x_lo) as usize;
            let n = (x_hi - x_lo) as usize;
            moved[dst..dst + n].copy_from_slice(&self.costs[src..src + n]);
        }
        self.costs = moved;
        self.origin = Point2::new(
            self.origin.x + dx as f64 * self.resolution,
            self.origin.y + dy as f64 * self.resolution,
        );
    }

    /// The costmap as a nav_msgs/OccupancyGrid with ROS's publisher translation (see
    /// [`cost_to_occupancy`]).
    pub fn to_occupancy_grid(&self) -> OccupancyGrid {
        OccupancyGrid {
            width: self.size_x,
            height: self.size_y,
            resolution: self.resolution,
            origin: Pose2::new(self.origin.x, self.origin.y, 0.0),
            data: self.costs.iter().map(|&c| cost_to_occupancy(c)).collect(),
        }
    }

    /// Whether every cell is `FREE`.
    pub fn is_all_free(&self) -> bool {
        self.costs.iter().all(|&c| c == FREE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_map_round_trip_and_edges() {
        let m = Costmap2D::new(10, 5, 0.1, Point2::new(-0.5, 1.0), 0);
        assert_eq!(m.world_to_map(Point2::new(-0.5, 1.0)), Some((0, 0)));
        assert_eq!(m.world_to_map(Point2::new(0.449, 1.42)), Some((9, 4)));
        assert_eq!(m.world_to_map(Point2::new(0.5, 1.2)), None);
        assert_eq!(m.world_to_map(Point2::new(-0.51, 1.2)), None);
        let c = m.map_to_world(3, 2);
        assert!((c.x + 0.15).abs() < 1e-12 && (c.y - 1.25).abs() < 1e-12);
        assert_eq!(m.world_to_map(c), Some((3, 2)));
        let r = m.cell_range(&Bounds {
            min_x: -0.45,
            min_y: 0.0,
            max_x: 0.0,
            max_y: 1.15,
        });
        assert_eq!(
            r,
            CellRange {
                x0: 0,
                y0: 0,
                xn: 6,
                yn: 2
            }
        );
    }

    #[test]
    fn update_origin_keeps_the_overlap() {
        let mut m = Costmap2D::new(4, 4, 1.0, Point2::new(0.0, 0.0), 0);
        m.set_cost(2, 3, 7);
        m.set_cost(0, 0, 9);
        m.update_origin(Point2::new(1.5, 1.2));
        assert_eq!(m.origin(), Point2::new(1.0, 1.0));
        assert_eq!(m.cost(1, 2), 7);
        assert_eq!(
            m.costs().iter().filter(|&&c| c != 0).count(),
            1,
            "the cell at (0, 0) left the window"
        );
        m.update_origin(Point2::new(-3.0, -3.0));
        assert!(m.is_all_free());
    }
}
