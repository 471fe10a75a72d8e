//! Obstacle layer: marks from laser scans and ray-traced clearing, on the global map's grid,
//! and the rolling local costmap built from it (costmap_2d's obstacle layer and
//! rolling_window, with the same parameter names).

use crate::cell_bounds::DirtyBounds;
use crate::costmap::{axis_cell, edt, inflation_cost, Costmap, CostmapParams, LETHAL};
use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, Point2, Pose2};

/// Obstacle layer parameters (ROS names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObstacleParams {
    /// Readings farther than this do not mark (m, default 2.5).
    pub obstacle_range: f64,
    /// Rays clear free space up to this distance (m, default 3.0).
    pub raytrace_range: f64,
    /// Invalid (NaN / out of range) readings clear along the whole ray (default true; ROS's
    /// `inf_is_valid`, false by default in an observation source, for a lidar that reports
    /// max range as no return).
    pub clear_on_max_range: bool,
    /// Side of the rolling local costmap (m, default 4).
    pub local_window: f64,
    /// Readings mark obstacles (default true).
    pub marking: bool,
    /// Rays clear the cells they cross (default true; an observation source in a ROS file
    /// defaults to false, as costmap_2d's).
    pub clearing: bool,
}

impl Default for ObstacleParams {
    fn default() -> Self {
        Self { obstacle_range: 2.5, raytrace_range: 3.0, clear_on_max_range: true, local_window: 4.0, marking: true, clearing: true }
    }
}

/// Marks on a grid aligned with a costmap: true where a scan saw an obstacle.
#[derive(Debug, Clone, PartialEq)]
pub struct ObstacleLayer {
    /// Parameters.
    pub params: ObstacleParams,
    width: usize,
    height: usize,
    resolution: f64,
    origin: Point2,
    marked: Vec<bool>,
    /// Cells whose mark flipped since the last [`ObstacleLayer::take_changes`].
    changed: DirtyBounds,
    /// Number of mark flips so far.
    flips: u64,
}

impl ObstacleLayer {
    /// An empty layer on the grid of `cm`.
    pub fn new(cm: &Costmap, params: ObstacleParams) -> Self {
        Self { params, width: cm.width, height: cm.height, resolution: cm.resolution, origin: cm.origin, marked: vec![false; cm.width * cm.height], changed: DirtyBounds::default(), flips: 0 }
    }

    /// Forgets every mark (the "clear costmaps" recovery).
    pub fn reset(&mut self) {
        for i in 0..self.marked.len() {
            if self.marked[i] {
                self.set(i, false);
            }
        }
    }

    /// Sets the mark of cell `i`, recording a flip.
    #[inline]
    fn set(&mut self, i: usize, v: bool) {
        if self.marked[i] != v {
            self.marked[i] = v;
            self.changed.touch(i % self.width, i / self.width);
            self.flips += 1;
        }
    }

    /// The bounds of the cells whose mark flipped since the last call (costmap_2d's
    /// `updateBounds`), `None` when none did.
    pub fn take_changes(&mut self) -> Option<crate::cell_bounds::CellBounds> {
        self.changed.take()
    }

    /// How many times a mark flipped since the layer was made (changes between two readings
    /// mean the marks changed).
    pub fn flips(&self) -> u64 {
        self.flips
    }

    /// The marks, row-major on the costmap's grid.
    pub fn marks(&self) -> &[bool] {
        &self.marked
    }

    /// Whether cell `i` (index in the costmap's grid) is marked.
    pub fn is_marked(&self, i: usize) -> bool {
        self.marked.get(i).copied().unwrap_or(false)
    }

    /// Number of marked cells.
    pub fn marked_cells(&self) -> usize {
        self.marked.iter().filter(|&&m| m).count()
    }

    #[inline]
    fn cell(&self, p: Point2) -> Option<usize> {
        let c = axis_cell((p.x - self.origin.x) / self.resolution, self.width)?;
        let r = axis_cell((p.y - self.origin.y) / self.resolution, self.height)?;
        Some(r * self.width + c)
    }

    /// Clears along each ray and marks its end, for a scan taken at `sensor` (world frame).
    pub fn update(&mut self, scan: &LaserScan, sensor: Pose2) {
        let p = self.params.clone();
        let o = sensor.position();
        for (i, &r) in scan.ranges.iter().enumerate() {
            let a = sensor.yaw + scan.angle(i);
            let (sa, ca) = a.sin_cos();
            let valid = r.is_finite() && (r as f64) >= scan.range_min && (r as f64) <= scan.range_max;
            let clear_to = if !p.clearing {
                0.0
            } else if valid {
                (r as f64).min(p.raytrace_range)
            } else if p.clear_on_max_range {
                p.raytrace_range.min(scan.range_max)
            } else {
                continue;
            };
            // Clear up to (not including) the hit's cell.
            let hit_cell = valid.then(|| self.cell(Point2::new(o.x + r as f64 * ca, o.y + r as f64 * sa))).flatten();
            let n = (clear_to / (self.resolution * 0.5)).ceil() as usize;
            let mut last = usize::MAX;
            for k in 0..n {
                let d = k as f64 * self.resolution * 0.5;
                if let Some(c) = self.cell(Point2::new(o.x + d * ca, o.y + d * sa)) {
                    if c != last && Some(c) != hit_cell {
                        self.set(c, false);
                    }
                    last = c;
                }
            }
            if p.marking && valid && (r as f64) <= p.obstacle_range {
                if let Some(c) = hit_cell {
                    self.set(c, true);
                }
            }
        }
    }

    /// The rolling local costmap around `center`: the static map's lethal cells and the
    /// marks, inflated, over a `local_window`-sided square; built from scratch (the reference
    /// that [`crate::layered_costmap::LayeredCostmap::local`] keeps up incrementally).
    pub fn local_costmap(&self, global: &Costmap, center: Point2, params: &CostmapParams) -> Costmap {
        let res = global.resolution;
        let half = (self.params.local_window / 2.0 / res).ceil() as isize;
        let margin = (params.inflation_radius / res).ceil() as isize + 1;
        let (cc, cr) = (((center.x - global.origin.x) / res).floor() as isize, ((center.y - global.origin.y) / res).floor() as isize);
        let (c0, r0) = (cc - half - margin, cr - half - margin);
        let n = (2 * (half + margin)) as usize;
        let mut lethal = vec![false; n * n];
        for r in 0..n {
            for c in 0..n {
                let (gc, gr) = (c0 + c as isize, r0 + r as isize);
                let inside = gc >= 0 && gr >= 0 && (gc as usize) < global.width && (gr as usize) < global.height;
                lethal[r * n + c] = !inside || {
                    let gi = gr as usize * global.width + gc as usize;
                    global.cost[gi] == LETHAL || self.marked[gi]
                };
            }
        }
        let d = edt(&lethal, n, n);
        let m = margin as usize;
        let w = n - 2 * m;
        let mut cost = vec![0u8; w * w];
        for r in 0..w {
            for c in 0..w {
                let i = (r + m) * n + (c + m);
                cost[r * w + c] = if lethal[i] { LETHAL } else { inflation_cost(d[i] * res, params) };
            }
        }
        let origin = Point2::new(global.origin.x + (c0 + margin) as f64 * res, global.origin.y + (r0 + margin) as f64 * res);
        Costmap { width: w, height: w, resolution: res, origin, cost }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap::INSCRIBED;
    use xhab_types::OccupancyGrid;

    fn empty() -> Costmap {
        Costmap::from_map(&OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0), &CostmapParams::default())
    }

    fn scan(ranges: Vec<f32>) -> LaserScan {
        let n = ranges.len();
        LaserScan { angle_min: -0.1, angle_max: 0.1, angle_increment: 0.2 / (n - 1) as f64, range_min: 0.1, range_max: 3.5, ranges }
    }

    #[test]
    fn marks_hits_clears_rays_and_inflates_locally() {
        let cm = empty();
        let mut layer = ObstacleLayer::new(&cm, ObstacleParams::default());
        layer.update(&scan(vec![1.0; 5]), Pose2::new(1.0, 2.5, 0.0));
        assert!(layer.marked_cells() >= 1 && layer.marked_cells() <= 5);
        let local = layer.local_costmap(&cm, Point2::new(1.0, 2.5), &CostmapParams::default());
        assert_eq!(local.cost_at(Point2::new(2.01, 2.5)), LETHAL);
        assert!(local.cost_at(Point2::new(1.93, 2.5)) >= INSCRIBED);
        assert_eq!(local.cost_at(Point2::new(1.2, 2.5)), 0);
        // The obstacle moved away: a longer reading through the old mark clears it.
        layer.update(&scan(vec![2.0; 5]), Pose2::new(1.0, 2.5, 0.0));
        let local = layer.local_costmap(&cm, Point2::new(1.0, 2.5), &CostmapParams::default());
        assert!(local.cost_at(Point2::new(2.01, 2.5)) < INSCRIBED);
        // No return at all clears up to the raytrace range.
        layer.update(&scan(vec![f32::NAN; 5]), Pose2::new(1.0, 2.5, 0.0));
        assert_eq!(layer.marked_cells(), 0);
        // Readings beyond obstacle_range do not mark.
        layer.update(&scan(vec![3.0; 5]), Pose2::new(0.2, 2.5, 0.0));
        assert_eq!(layer.marked_cells(), 0);
    }
}
