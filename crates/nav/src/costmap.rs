//! A 2D costmap with ROS cost values: a static layer from a map_server map and an inflation
//! layer with costmap_2d's cost function, computed with an exact distance transform.

use serde::{Deserialize, Serialize};
use xhab_types::{OccupancyGrid, Point2, GRID_UNKNOWN};

/// A free cell.
pub const FREE: u8 = 0;
/// A cell within the robot's inscribed radius of an obstacle.
pub const INSCRIBED: u8 = 253;
/// An obstacle.
pub const LETHAL: u8 = 254;
/// Unknown space.
pub const UNKNOWN: u8 = 255;

/// Costmap parameters (ROS costmap_2d names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CostmapParams {
    /// Robot radius (m, default 0.1): the inscribed radius of a round footprint.
    pub robot_radius: f64,
    /// Distance to which costs are inflated around obstacles (m, default 0.55).
    pub inflation_radius: f64,
    /// Decay of the inflated cost with distance (1/m, default 10).
    pub cost_scaling_factor: f64,
    /// Map occupancy (0..100) from which a cell is lethal (default 65, as map_saver).
    pub lethal_cost_threshold: i8,
    /// Treat unknown cells as unknown (true) or as free (false, default), as ROS track_unknown_space.
    pub track_unknown_space: bool,
    /// Footprint polygon in the base frame (m); empty for a round robot of `robot_radius`.
    pub footprint: Vec<[f64; 2]>,
    /// Padding added around the footprint (m, default 0).
    pub footprint_padding: f64,
}

impl CostmapParams {
    /// Inscribed radius (m): `robot_radius`, or the distance from the base origin to the
    /// nearest edge of the (padded) footprint polygon.
    pub fn inscribed_radius(&self) -> f64 {
        if self.footprint.len() < 3 {
            return self.robot_radius + self.footprint_padding;
        }
        let n = self.footprint.len();
        (0..n)
            .map(|i| {
                let (a, b) = (self.footprint[i], self.footprint[(i + 1) % n]);
                let d = [b[0] - a[0], b[1] - a[1]];
                let l2 = d[0] * d[0] + d[1] * d[1];
                let t = if l2 > 0.0 { (-(a[0] * d[0] + a[1] * d[1]) / l2).clamp(0.0, 1.0) } else { 0.0 };
                (a[0] + t * d[0]).hypot(a[1] + t * d[1])
            })
            .fold(f64::INFINITY, f64::min)
            + self.footprint_padding
    }

    /// Circumscribed radius (m): the farthest footprint vertex (or `robot_radius`).
    pub fn circumscribed_radius(&self) -> f64 {
        if self.footprint.len() < 3 {
            return self.robot_radius + self.footprint_padding;
        }
        self.footprint.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max) + self.footprint_padding
    }
}

impl Default for CostmapParams {
    fn default() -> Self {
        Self {
            robot_radius: 0.1,
            inflation_radius: 0.55,
            cost_scaling_factor: 10.0,
            lethal_cost_threshold: 65,
            track_unknown_space: false,
            footprint: Vec::new(),
            footprint_padding: 0.0,
        }
    }
}

/// A costmap: row-major u8 costs, row 0 at the bottom, like the map it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Costmap {
    /// Cells along x.
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// Cell size (m).
    pub resolution: f64,
    /// World position of the lower-left corner of cell (0, 0) (m).
    pub origin: Point2,
    /// Costs.
    pub cost: Vec<u8>,
}

/// ROS inflation cost at distance `d` (m) from an obstacle.
pub fn inflation_cost(d: f64, p: &CostmapParams) -> u8 {
    let inscribed = p.inscribed_radius();
    if d <= 0.0 {
        LETHAL
    } else if d <= inscribed {
        INSCRIBED
    } else if d > p.inflation_radius {
        FREE
    } else {
        (252.0 * (-p.cost_scaling_factor * (d - inscribed)).exp()).floor() as u8
    }
}

impl Costmap {
    /// The static layer of `map` inflated (a rotated map is first turned into the world's
    /// axes: [`OccupancyGrid::axis_aligned`]).
    pub fn from_map(map: &OccupancyGrid, p: &CostmapParams) -> Costmap {
        let map = &*map.axis_aligned();
        let (w, h) = (map.width, map.height);
        let lethal: Vec<bool> = map.data.iter().map(|&v| v >= p.lethal_cost_threshold).collect();
        let mut d = edt(&lethal, w, h);
        // The map's outside is an obstacle: distances reach at most across the nearest edge.
        for (i, di) in d.iter_mut().enumerate() {
            let (c, r) = (i % w, i / w);
            *di = di.min(border_cells(c, r, w, h) as f64);
        }
        let mut cost = vec![FREE; w * h];
        for i in 0..w * h {
            cost[i] = if lethal[i] {
                LETHAL
            } else {
                let c = inflation_cost(d[i] * map.resolution, p);
                if p.track_unknown_space && map.data[i] == GRID_UNKNOWN && c < INSCRIBED {
                    UNKNOWN
                } else {
                    c
                }
            };
        }
        Costmap { width: w, height: h, resolution: map.resolution, origin: Point2::new(map.origin.x, map.origin.y), cost }
    }

    /// Cell (col, row) of world point `p`, if inside.
    #[inline]
    pub fn cell(&self, p: Point2) -> Option<(usize, usize)> {
        let c = axis_cell((p.x - self.origin.x) / self.resolution, self.width)?;
        let r = axis_cell((p.y - self.origin.y) / self.resolution, self.height)?;
        Some((c, r))
    }

    /// World centre of cell (col, row) (m).
    pub fn center(&self, c: usize, r: usize) -> Point2 {
        Point2::new(self.origin.x + (c as f64 + 0.5) * self.resolution, self.origin.y + (r as f64 + 0.5) * self.resolution)
    }

    /// Cost at world point `p`; LETHAL outside the map.
    #[inline]
    pub fn cost_at(&self, p: Point2) -> u8 {
        self.cell(p).map_or(LETHAL, |(c, r)| self.cost[r * self.width + c])
    }
}

/// Cells from cell (`c`, `r`) to the nearest cell off a `w` x `h` map: straight across the
/// nearest edge (the map's outside counts as an obstacle to both costmaps).
pub(crate) fn border_cells(c: usize, r: usize, w: usize, h: usize) -> usize {
    (c + 1).min(r + 1).min(w - c).min(h - r)
}

pub use xhab_types::axis_cell;

/// Distance (in cells) from each cell centre to the nearest `true` cell centre (exact EDT).
pub fn edt(blocked: &[bool], w: usize, h: usize) -> Vec<f64> {
    xhab_types::distance_field::edt(blocked, w, h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::Pose2;

    #[test]
    fn a_rotated_map_puts_its_walls_where_the_map_has_them() {
        // Issue 20: the origin's yaw used to be dropped, so a turned map's walls landed where
        // the unturned map has them. A wall along the map's column 30, the map turned by 90
        // degrees about (1, -2): the wall runs along the world's x at y = -2 + 30.5 * 0.05.
        let mut m = OccupancyGrid::new(40, 40, 0.05, Pose2::new(1.0, -2.0, std::f64::consts::FRAC_PI_2), 0);
        for r in 0..40 {
            m.set(30, r, 100);
        }
        let (both, layered) = (CostmapParams::default(), crate::layered_costmap::LayeredCostmap::new(&m, &CostmapParams::default(), &CostmapParams::default(), Default::default()));
        for cm in [Costmap::from_map(&m, &both), layered.global().clone()] {
            for k in 0..40 {
                let wall = m.cell_center(30, k);
                assert_eq!(cm.cost_at(wall), LETHAL, "{wall:?}");
                // The wall is a line along x at y = -0.475 (the map's x is the world's y).
                assert!((wall.y - -0.475).abs() < 1e-9, "{wall:?}");
                // 0.5 m to its side, inside the map and away from its edges: free.
                let beside = Point2::new(wall.x, wall.y - 0.5);
                assert!((8..32).contains(&k) || cm.cost_at(beside) < LETHAL, "{beside:?}");
                assert!(!(8..32).contains(&k) || cm.cost_at(beside) < INSCRIBED, "{beside:?}");
            }
        }
    }

    #[test]
    fn inflation_follows_the_ros_formula() {
        let p = CostmapParams::default();
        assert_eq!(inflation_cost(0.0, &p), LETHAL);
        assert_eq!(inflation_cost(0.05, &p), INSCRIBED);
        assert_eq!(inflation_cost(0.1, &p), INSCRIBED);
        // 252 * exp(-10 * 0.1) = 92.7
        assert_eq!(inflation_cost(0.2, &p), 92);
        assert_eq!(inflation_cost(0.56, &p), FREE);
        // A 0.4 x 0.3 m rectangle: inscribed 0.15, circumscribed 0.25.
        let rect = CostmapParams { footprint: vec![[-0.2, -0.15], [0.2, -0.15], [0.2, 0.15], [-0.2, 0.15]], ..Default::default() };
        assert!((rect.inscribed_radius() - 0.15).abs() < 1e-12 && (rect.circumscribed_radius() - 0.25).abs() < 1e-12);
        assert_eq!(inflation_cost(0.14, &rect), INSCRIBED);
        let mut last = 255;
        for k in 0..60 {
            let c = inflation_cost(k as f64 * 0.01, &p);
            assert!(c <= last);
            last = c;
        }
    }

    #[test]
    fn costmap_of_a_wall() {
        let mut m = OccupancyGrid::new(20, 10, 0.05, Pose2::new(0.0, 0.0, 0.0), 0);
        for r in 0..10 {
            m.set(10, r, 100);
        }
        let cm = Costmap::from_map(&m, &CostmapParams::default());
        assert_eq!(cm.cost[5 * 20 + 10], LETHAL);
        assert_eq!(cm.cost[5 * 20 + 8], INSCRIBED); // 0.1 m away
        assert_eq!(cm.cost[5 * 20 + 6], 92); // 0.2 m away
        assert_eq!(cm.cost_at(Point2::new(-1.0, 0.0)), LETHAL);
    }
}
