//! Occupancy-grid mapping with known poses: log-odds updates from laser scans (free space
//! ray-traced to each return) and, in a second layer, from obstacle and floor points of a
//! depth camera (see [`crate::depth_projection`]); written as a map_server-style grid.

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
    /// Log-odds of the depth-camera layer (obstacle points in the body band, floor points).
    band_log_odds: Vec<f32>,
    /// Cells with any depth-camera point.
    band_seen: Vec<bool>,
    /// Per-cell stamp of the last update that touched it (dedupes cells within one update).
    mark: Vec<u32>,
    /// The current update's stamp.
    stamp: u32,
}

impl Mapper {
    /// A map covering `min`..`max` (m), all unknown.
    pub fn new(min: Point2, max: Point2, params: MapperParams) -> Self {
        let r = params.resolution;
        let width = ((max.x - min.x) / r).ceil().max(1.0) as usize;
        let height = ((max.y - min.y) / r).ceil().max(1.0) as usize;
        let n = width * height;
        Self { params, origin: min, width, height, log_odds: vec![0.0; n], seen: vec![false; n], band_log_odds: vec![0.0; n], band_seen: vec![false; n], mark: vec![0; n], stamp: 0 }
    }

    fn cell(&self, p: Point2) -> Option<usize> {
        let c = ((p.x - self.origin.x) / self.params.resolution).floor();
        let r = ((p.y - self.origin.y) / self.params.resolution).floor();
        (c >= 0.0 && r >= 0.0 && c < self.width as f64 && r < self.height as f64).then(|| r as usize * self.width + c as usize)
    }

    /// A fresh stamp for one update (all marks cleared when it wraps).
    fn next_stamp(&mut self) -> u32 {
        if self.stamp >= u32::MAX - 2 {
            self.mark.iter_mut().for_each(|m| *m = 0);
            self.stamp = 0;
        }
        self.stamp += 1;
        self.stamp
    }

    /// Calls `f` on each cell a ray from `o` at angle `a` crosses within `len` (m), in order,
    /// stopping where it leaves the map (exact grid traversal, Amanatides and Woo).
    fn trace(&self, o: Point2, a: f64, len: f64, mut f: impl FnMut(usize)) {
        let res = self.params.resolution;
        let (x0, y0) = ((o.x - self.origin.x) / res, (o.y - self.origin.y) / res);
        let (dx, dy) = (a.cos(), a.sin());
        let l = len / res;
        let (mut c, mut r) = (x0.floor() as i64, y0.floor() as i64);
        let (sc, sr) = (if dx > 0.0 { 1 } else { -1 }, if dy > 0.0 { 1 } else { -1 });
        let axis = |p0: f64, cell: i64, d: f64| -> (f64, f64) {
            if d > 0.0 {
                ((cell as f64 + 1.0 - p0) / d, 1.0 / d)
            } else if d < 0.0 {
                ((p0 - cell as f64) / -d, -1.0 / d)
            } else {
                (f64::INFINITY, f64::INFINITY)
            }
        };
        let (mut tx, ddx) = axis(x0, c, dx);
        let (mut ty, ddy) = axis(y0, r, dy);
        let (w, h) = (self.width as i64, self.height as i64);
        loop {
            if c < 0 || r < 0 || c >= w || r >= h {
                return;
            }
            f((r * w + c) as usize);
            let t = if tx < ty {
                c += sc;
                tx += ddx;
                tx - ddx
            } else {
                r += sr;
                ty += ddy;
                ty - ddy
            };
            if t >= l {
                return;
            }
        }
    }

    /// Integrates a scan taken at `sensor` (world frame). Cells holding a return of this scan
    /// get no miss from it: a beam grazing a wall passes through the wall's cells just before
    /// its own return, and without this rule such beams would wear walls into dashed lines.
    pub fn integrate(&mut self, scan: &LaserScan, sensor: Pose2) {
        let (hit, miss, clamp) = (logit(self.params.prob_hit) as f32, logit(self.params.prob_miss) as f32, self.params.clamp as f32);
        let o = sensor.position();
        let hits_stamp = self.next_stamp();
        let mut beams = Vec::with_capacity(scan.ranges.len());
        let mut hits = Vec::new();
        for (i, &r) in scan.ranges.iter().enumerate() {
            let a = sensor.yaw + scan.angle(i);
            let valid = r.is_finite() && (r as f64) >= scan.range_min && (r as f64) <= scan.range_max;
            let len = if valid { r as f64 } else if self.params.max_clear_range > 0.0 { self.params.max_clear_range.min(scan.range_max) } else { continue };
            if valid {
                if let Some(c) = self.cell(Point2::new(o.x + len * a.cos(), o.y + len * a.sin())) {
                    if self.mark[c] != hits_stamp {
                        self.mark[c] = hits_stamp;
                        hits.push(c);
                    }
                }
            }
            beams.push((a, len));
        }
        // Each beam: one miss for each cell it crosses, cells with a return excluded.
        let mut crossed = Vec::new();
        for &(a, len) in &beams {
            self.trace(o, a, len, |c| crossed.push(c));
            for c in crossed.drain(..) {
                if self.mark[c] != hits_stamp {
                    self.log_odds[c] = (self.log_odds[c] + miss).max(-clamp);
                    self.seen[c] = true;
                }
            }
        }
        for c in hits {
            self.log_odds[c] = (self.log_odds[c] + hit).min(clamp);
            self.seen[c] = true;
        }
    }

    /// Integrates one depth image's points (world frame, m) into the camera layer: a hit for
    /// each cell holding an obstacle point, a miss for each other cell holding a floor point
    /// unless the cell has had more hits than misses. Seeing the floor under a table does not
    /// say that the table is gone: obstacles in the body band stand.
    pub fn integrate_points(&mut self, obstacles: &[Point2], floor: &[Point2]) {
        let (hit, miss, clamp) = (logit(self.params.prob_hit) as f32, logit(self.params.prob_miss) as f32, self.params.clamp as f32);
        let hits_stamp = self.next_stamp();
        for &p in obstacles {
            if let Some(c) = self.cell(p) {
                if self.mark[c] != hits_stamp {
                    self.mark[c] = hits_stamp;
                    self.band_log_odds[c] = (self.band_log_odds[c] + hit).min(clamp);
                    self.band_seen[c] = true;
                }
            }
        }
        let free_stamp = self.next_stamp();
        for &p in floor {
            if let Some(c) = self.cell(p) {
                if self.mark[c] != hits_stamp && self.mark[c] != free_stamp {
                    self.mark[c] = free_stamp;
                    if self.band_log_odds[c] <= 0.0 {
                        self.band_log_odds[c] = (self.band_log_odds[c] + miss).max(-clamp);
                    }
                    self.band_seen[c] = true;
                }
            }
        }
    }

    /// The map: occupied where either layer is above `occupied_thresh`, else free where either
    /// is below `free_thresh`, unknown otherwise or where nothing was seen.
    pub fn to_grid(&self) -> OccupancyGrid {
        let mut g = OccupancyGrid::new(self.width, self.height, self.params.resolution, Pose2::new(self.origin.x, self.origin.y, 0.0), GRID_UNKNOWN);
        let (occ, free) = (logit(self.params.occupied_thresh) as f32, logit(self.params.free_thresh) as f32);
        for i in 0..self.log_odds.len() {
            let laser = self.seen[i].then_some(self.log_odds[i]);
            let band = self.band_seen[i].then_some(self.band_log_odds[i]);
            g.data[i] = if laser.is_some_and(|l| l > occ) || band.is_some_and(|l| l > occ) {
                GRID_OCCUPIED
            } else if laser.is_some_and(|l| l < free) || band.is_some_and(|l| l < free) {
                GRID_FREE
            } else {
                GRID_UNKNOWN
            };
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

    #[test]
    fn camera_obstacles_stand_however_often_the_laser_passes_under_them() {
        let mut m = Mapper::new(Point2::new(-2.0, -2.0), Point2::new(2.0, 2.0), MapperParams::default());
        // A table top at x = 0.5..0.6 seen by the camera, floor in front of it.
        let top: Vec<Point2> = (0..10).map(|i| Point2::new(0.525 + 0.05 * (i % 2) as f64, -0.2 + 0.05 * (i / 2) as f64)).collect();
        let floor: Vec<Point2> = (0..8).map(|i| Point2::new(0.125 + 0.05 * i as f64, 0.0)).collect();
        for _ in 0..3 {
            m.integrate_points(&top, &floor);
        }
        // The laser sees under it all the way to 1 m, many times.
        for _ in 0..50 {
            m.integrate(&scan(vec![1.0; 720]), Pose2::new(0.0, 0.0, 0.0));
        }
        let g = m.to_grid();
        let at = |x: f64, y: f64| {
            let (c, r) = g.world_to_cell(Point2::new(x, y)).unwrap();
            g.get(c, r)
        };
        assert_eq!(at(0.525, 0.025), GRID_OCCUPIED);
        assert_eq!(at(0.3, 0.025), GRID_FREE);
        assert_eq!(at(-0.5, 0.0), GRID_FREE);
    }
}
