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
    /// Marks per tile of `TILE` x `TILE` cells, so that rays skip the stretches where there is
    /// nothing to clear.
    tile_marks: Vec<u8>,
    tiles_w: usize,
}

/// Side of the tiles whose marks are counted (cells).
const TILE: usize = 8;
/// Ray samples looked at together: their stretch is skipped when no mark lies near it.
const CHUNK: usize = 8;

impl ObstacleLayer {
    /// An empty layer on the grid of `cm`.
    pub fn new(cm: &Costmap, params: ObstacleParams) -> Self {
        Self { params, width: cm.width, height: cm.height, resolution: cm.resolution, origin: cm.origin, marked: vec![false; cm.width * cm.height], changed: DirtyBounds::default(), flips: 0, tile_marks: vec![0; cm.width.div_ceil(TILE) * cm.height.div_ceil(TILE)], tiles_w: cm.width.div_ceil(TILE) }
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
            let (c, r) = (i % self.width, i / self.width);
            self.changed.touch(c, r);
            self.flips += 1;
            let t = &mut self.tile_marks[(r / TILE) * self.tiles_w + c / TILE];
            *t = if v { *t + 1 } else { *t - 1 };
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

    /// Whether some mark may lie near the ray's stretch from `(x0, y0)` to `(x1, y1)` (in
    /// cells from the grid's origin): false only when every tile within a cell of the
    /// stretch's bounding box holds no mark, or the box misses the grid.
    #[inline]
    fn marks_near(&self, x0: f64, y0: f64, x1: f64, y1: f64) -> bool {
        let span = |p: f64, q: f64, n: usize| {
            let (lo, hi) = (p.min(q) - 1.0, p.max(q) + 1.0);
            if !(hi >= 0.0 && lo < n as f64) {
                return None;
            }
            // Truncation is floor here: both ends are clamped to be non-negative.
            Some((lo.max(0.0) as usize / TILE, hi.min(n as f64 - 1.0) as usize / TILE))
        };
        let (Some((tc0, tc1)), Some((tr0, tr1))) = (span(x0, x1, self.width), span(y0, y1, self.height)) else { return false };
        (tr0..=tr1).any(|tr| self.tile_marks[tr * self.tiles_w + tc0..=tr * self.tiles_w + tc1].iter().any(|&m| m > 0))
    }

    /// Clears along each ray and marks its end, for a scan taken at `sensor` (world frame).
    /// Each ray clears the cells under its samples every half cell, up to (not including) the
    /// hit's cell; stretches far from every mark are skipped, which changes nothing.
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
            let res = self.resolution;
            let at = |k: usize| {
                let d = k as f64 * res * 0.5;
                Point2::new(o.x + d * ca, o.y + d * sa)
            };
            // The samples in cells, to within a hair: where that cannot decide a sample's cell
            // (next to a cell edge) the exact position above does.
            let inv = 1.0 / res;
            let (ax, ay, bx, by) = ((o.x - self.origin.x) * inv, (o.y - self.origin.y) * inv, 0.5 * ca, 0.5 * sa);
            const HAIR: f64 = 1e-6;
            let (wf, hf) = (self.width as f64, self.height as f64);
            let mut last = usize::MAX;
            for k0 in (0..n).step_by(CHUNK) {
                let k1 = (k0 + CHUNK).min(n);
                let (kf0, kf1) = (k0 as f64, (k1 - 1) as f64);
                if !self.marks_near(ax + kf0 * bx, ay + kf0 * by, ax + kf1 * bx, ay + kf1 * by) {
                    continue;
                }
                for k in k0..k1 {
                    let (x, y) = (ax + k as f64 * bx, ay + k as f64 * by);
                    let inner = x >= HAIR && y >= HAIR && x < wf - HAIR && y < hf - HAIR;
                    // (Casts truncate, which is floor for these positive values.)
                    let (cx, cy) = (x as usize, y as usize);
                    let (fx, fy) = (x - cx as f64, y - cy as f64);
                    let cell = if inner && fx > HAIR && fx < 1.0 - HAIR && fy > HAIR && fy < 1.0 - HAIR {
                        Some(cy * self.width + cx)
                    } else if x > -1.0 && y > -1.0 && x < wf + 1.0 && y < hf + 1.0 {
                        self.cell(at(k))
                    } else {
                        None
                    };
                    if let Some(c) = cell {
                        if c != last && Some(c) != hit_cell {
                            self.set(c, false);
                        }
                        last = c;
                    }
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

    /// The update without skipping: every sample of every ray.
    fn naive_update(marked: &mut [bool], layer: &ObstacleLayer, scan: &LaserScan, sensor: Pose2) {
        let p = &layer.params;
        let o = sensor.position();
        for (i, &r) in scan.ranges.iter().enumerate() {
            let a = sensor.yaw + scan.angle(i);
            let valid = r.is_finite() && (r as f64) >= scan.range_min && (r as f64) <= scan.range_max;
            let clear_to = if valid { (r as f64).min(p.raytrace_range) } else { p.raytrace_range.min(scan.range_max) };
            let hit_cell = valid.then(|| layer.cell(Point2::new(o.x + r as f64 * a.cos(), o.y + r as f64 * a.sin()))).flatten();
            let n = (clear_to / (layer.resolution * 0.5)).ceil() as usize;
            for k in 0..n {
                let d = k as f64 * layer.resolution * 0.5;
                if let Some(c) = layer.cell(Point2::new(o.x + d * a.cos(), o.y + d * a.sin())) {
                    if Some(c) != hit_cell {
                        marked[c] = false;
                    }
                }
            }
            if valid && (r as f64) <= p.obstacle_range {
                if let Some(c) = hit_cell {
                    marked[c] = true;
                }
            }
        }
    }

    #[test]
    fn skipping_stretches_without_marks_changes_nothing() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        let cm = empty();
        let mut layer = ObstacleLayer::new(&cm, ObstacleParams::default());
        let mut reference = vec![false; 100 * 100];
        for _ in 0..200 {
            let n = 120;
            let inc = std::f64::consts::TAU / n as f64;
            let ranges = (0..n).map(|_| if rng.gen_bool(0.1) { f32::NAN } else { rng.gen_range(0.05..4.0) as f32 }).collect();
            let s = LaserScan { angle_min: -3.0, angle_max: -3.0 + inc * (n - 1) as f64, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges };
            // Sometimes from outside the map, looking in.
            let pose = Pose2::new(rng.gen_range(-1.0..6.0), rng.gen_range(-1.0..6.0), rng.gen_range(-3.2..3.2));
            // Sometimes on a cell corner, looking along the grid: samples fall on cell edges.
            let pose = if rng.gen_bool(0.3) { Pose2::new(0.05 * rng.gen_range(0..100) as f64, 0.05 * rng.gen_range(0..100) as f64, 3.0 + inc * rng.gen_range(0..4) as f64) } else { pose };
            naive_update(&mut reference, &layer, &s, pose);
            layer.update(&s, pose);
            assert_eq!(layer.marks(), &reference[..]);
        }
        assert!(layer.marked_cells() > 10);
        let counted: usize = layer.tile_marks.iter().map(|&t| t as usize).sum();
        assert_eq!(counted, layer.marked_cells());
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
