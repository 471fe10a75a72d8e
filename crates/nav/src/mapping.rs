//! Occupancy-grid mapping from laser scans with known poses: log-odds updates, free space
//! ray-traced to each return, written as a map_server-style grid.

use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, OccupancyGrid, Point2, Pose2, GRID_FREE, GRID_OCCUPIED, GRID_UNKNOWN};

/// Mapper parameters (gmapping/slam_toolbox-like names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MapperParams {
    /// Cell size (m, default 0.05).
    pub resolution: f64,
    /// Probability that a cell holding a return is occupied (default 0.7).
    pub prob_hit: f64,
    /// Probability that a cell a beam passed through is occupied (default 0.4).
    pub prob_miss: f64,
    /// Log-odds are clamped to +- this (default 5).
    pub clamp: f64,
    /// Occupancy probability above which a cell is written occupied (default 0.65).
    pub occupied_thresh: f64,
    /// Occupancy probability below which a cell is written free (default 0.196).
    pub free_thresh: f64,
    /// Beams with no return clear up to this range (m, default 3; 0 = never).
    pub max_clear_range: f64,
}

impl Default for MapperParams {
    fn default() -> Self {
        Self { resolution: 0.05, prob_hit: 0.7, prob_miss: 0.4, clamp: 5.0, occupied_thresh: 0.65, free_thresh: 0.196, max_clear_range: 3.0 }
    }
}

fn logit(p: f64) -> f64 {
    (p / (1.0 - p)).ln()
}

/// A log-odds occupancy grid over a fixed area.
#[derive(Debug, Clone)]
pub struct Mapper {
    /// Parameters.
    pub params: MapperParams,
    origin: Point2,
    width: usize,
    height: usize,
    log_odds: Vec<f32>,
    /// Cells touched by any beam (the rest stays unknown).
    seen: Vec<bool>,
}

impl Mapper {
    /// A map covering `min`..`max` (m), all unknown.
    pub fn new(min: Point2, max: Point2, params: MapperParams) -> Self {
        let r = params.resolution;
        let width = ((max.x - min.x) / r).ceil().max(1.0) as usize;
        let height = ((max.y - min.y) / r).ceil().max(1.0) as usize;
        Self { params, origin: min, width, height, log_odds: vec![0.0; width * height], seen: vec![false; width * height] }
    }

    fn cell(&self, p: Point2) -> Option<usize> {
        let c = ((p.x - self.origin.x) / self.params.resolution).floor();
        let r = ((p.y - self.origin.y) / self.params.resolution).floor();
        (c >= 0.0 && r >= 0.0 && c < self.width as f64 && r < self.height as f64).then(|| r as usize * self.width + c as usize)
    }

    /// Integrates a scan taken at `sensor` (world frame).
    pub fn integrate(&mut self, scan: &LaserScan, sensor: Pose2) {
        let (hit, miss, clamp) = (logit(self.params.prob_hit) as f32, logit(self.params.prob_miss) as f32, self.params.clamp as f32);
        let res = self.params.resolution;
        let o = sensor.position();
        for (i, &r) in scan.ranges.iter().enumerate() {
            let a = sensor.yaw + scan.angle(i);
            let valid = r.is_finite() && (r as f64) >= scan.range_min && (r as f64) <= scan.range_max;
            let len = if valid { r as f64 } else if self.params.max_clear_range > 0.0 { self.params.max_clear_range.min(scan.range_max) } else { continue };
            let end = Point2::new(o.x + len * a.cos(), o.y + len * a.sin());
            let end_cell = if valid { self.cell(end) } else { None };
            // Each cell the beam crosses once, the return's cell excluded.
            let n = (len / (res * 0.5)).ceil() as usize;
            let mut last = None;
            for k in 0..n {
                let d = k as f64 * res * 0.5;
                let Some(c) = self.cell(Point2::new(o.x + d * a.cos(), o.y + d * a.sin())) else { break };
                if Some(c) == last || Some(c) == end_cell {
                    continue;
                }
                last = Some(c);
                self.log_odds[c] = (self.log_odds[c] + miss).max(-clamp);
                self.seen[c] = true;
            }
            if let Some(c) = end_cell {
                self.log_odds[c] = (self.log_odds[c] + hit).min(clamp);
                self.seen[c] = true;
            }
        }
    }

    /// The map: occupied above `occupied_thresh`, free below `free_thresh`, unknown otherwise
    /// or where no beam went.
    pub fn to_grid(&self) -> OccupancyGrid {
        let mut g = OccupancyGrid::new(self.width, self.height, self.params.resolution, Pose2::new(self.origin.x, self.origin.y, 0.0), GRID_UNKNOWN);
        let (occ, free) = (logit(self.params.occupied_thresh) as f32, logit(self.params.free_thresh) as f32);
        for i in 0..self.log_odds.len() {
            if !self.seen[i] {
                continue;
            }
            let l = self.log_odds[i];
            g.data[i] = if l > occ { GRID_OCCUPIED } else if l < free { GRID_FREE } else { GRID_UNKNOWN };
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scan(ranges: Vec<f32>) -> LaserScan {
        let n = ranges.len();
        let inc = std::f64::consts::TAU / n as f64;
        LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges }
    }

    #[test]
    fn a_circle_of_returns_maps_a_free_disc_inside_a_ring() {
        let mut m = Mapper::new(Point2::new(-2.0, -2.0), Point2::new(2.0, 2.0), MapperParams::default());
        for _ in 0..5 {
            m.integrate(&scan(vec![1.0; 720]), Pose2::new(0.0, 0.0, 0.0));
        }
        let g = m.to_grid();
        let at = |x: f64, y: f64| {
            let (c, r) = g.world_to_cell(Point2::new(x, y)).unwrap();
            g.get(c, r)
        };
        assert_eq!(at(0.5, 0.0), GRID_FREE);
        assert_eq!(at(-0.3, 0.6), GRID_FREE);
        assert_eq!(at(0.975, 0.0), GRID_OCCUPIED);
        assert_eq!(at(0.0, -0.975), GRID_OCCUPIED);
        assert_eq!(at(1.8, 1.8), GRID_UNKNOWN);
        // A later scan with nothing there clears the ring (no return: clear to 3 m).
        for _ in 0..20 {
            m.integrate(&scan(vec![f32::NAN; 720]), Pose2::new(0.0, 0.0, 0.0));
        }
        let g = m.to_grid();
        let (c, r) = g.world_to_cell(Point2::new(0.975, 0.0)).unwrap();
        assert_eq!(g.get(c, r), GRID_FREE);
    }
}
