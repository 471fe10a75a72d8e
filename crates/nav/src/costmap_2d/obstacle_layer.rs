//! The obstacle layer (ROS `costmap_2d::ObstacleLayer`) for planar laser scans: each scan
//! clears the cells its rays cross (ray-trace clearing up to `raytrace_range`) and marks the
//! cells its returns hit (up to `obstacle_range`).
//!
//! Readings follow sensor_msgs/LaserScan: a range below `range_min` or negative infinity is
//! dropped; +inf (and a reading at or beyond `range_max`) means "no return within range" and
//! clears the whole ray when `inf_is_valid`; NaN is dropped unless `nan_is_inf` (for sources
//! such as depthimage_to_laserscan that report "nothing within range" as NaN). A "no return"
//! never marks (ROS marks at `range_max` when `range_max < obstacle_range`; we do not).
//! As in ROS, every ray of a batch of scans clears before any of them marks.

use super::cost_values::{FREE, LETHAL, UNKNOWN};
use super::costmap::{Bounds, CellRange, Costmap2D};
use super::footprint::Footprint;
use super::layer::CostmapLayer;
use super::raytrace::traverse_segment;
use crate::param_error::{check_range, ParamError};
use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, Point2, Pose2};

/// Obstacle layer parameters (ROS names; the observation source's keys `obstacle_range`,
/// `raytrace_range`, `inf_is_valid`, `marking`, `clearing` live here, since scans arrive by
/// function call rather than by topic).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObstacleLayerParams {
    /// Whether the layer is applied (default true).
    pub enabled: bool,
    /// Accepted for compatibility (default unset, inheriting the costmap's). Cells no scan has
    /// seen never change the layers below, which is ROS's behaviour with `true`; with `false`
    /// ROS writes them as free and so erases the static map's unknown space wherever the
    /// update reaches, a quirk not reproduced.
    pub track_unknown_space: Option<bool>,
    /// Clears the cells under the robot's footprint on every update (default true).
    pub footprint_clearing_enabled: bool,
    /// How the layer meets the layers below: 0 overwrite, 1 maximum (default 1).
    pub combination_method: i32,
    /// Returns farther than this do not mark (m, default 2.5, range [0, 50]).
    pub obstacle_range: f64,
    /// Rays clear free space up to this distance (m, default 3.0, range [0, 50]).
    pub raytrace_range: f64,
    /// +inf readings (no return) clear along the whole ray (default false, as ROS).
    pub inf_is_valid: bool,
    /// NaN readings count as +inf (xhab extension, default false).
    pub nan_is_inf: bool,
    /// Scans mark obstacles (default true).
    pub marking: bool,
    /// Scans clear free space (default true; ROS's per-source default is false, but a scan
    /// source that never clears leaves every transient obstacle in the map for good).
    pub clearing: bool,
}

impl Default for ObstacleLayerParams {
    fn default() -> Self {
        Self {
            enabled: true,
            track_unknown_space: None,
            footprint_clearing_enabled: true,
            combination_method: 1,
            obstacle_range: 2.5,
            raytrace_range: 3.0,
            inf_is_valid: false,
            nan_is_inf: false,
            marking: true,
            clearing: true,
        }
    }
}

impl ObstacleLayerParams {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("obstacle_range", self.obstacle_range, 0.0, 50.0)?;
        check_range("raytrace_range", self.raytrace_range, 0.0, 50.0)?;
        if !(0..=1).contains(&self.combination_method) {
            return Err(ParamError::invalid(
                "combination_method",
                format!(
                    "must be 0 (overwrite) or 1 (maximum), got {}",
                    self.combination_method
                ),
            ));
        }
        Ok(())
    }
}

/// The obstacle layer: marks and clears on its own grid, aligned with the master's.
#[derive(Debug, Clone)]
pub struct ObstacleLayer {
    name: String,
    params: ObstacleLayerParams,
    grid: Costmap2D,
    footprint: Footprint,
    pending: Vec<(LaserScan, Pose2)>,
    extra_bounds: Bounds,
}

/// Scans kept between two updates; older ones are dropped.
const MAX_PENDING_SCANS: usize = 16;

impl ObstacleLayer {
    /// A layer named `name` with the robot's `footprint` (for footprint clearing); it takes its
    /// grid geometry from the master at the first [`match_size`](CostmapLayer::match_size).
    pub fn new(name: &str, params: ObstacleLayerParams, footprint: Footprint) -> Self {
        Self {
            name: name.to_string(),
            params,
            grid: Costmap2D::new(0, 0, 1.0, Point2::default(), UNKNOWN),
            footprint,
            pending: Vec::new(),
            extra_bounds: Bounds::empty(),
        }
    }

    /// Queues a scan taken by a sensor at `sensor` (world frame: position m, yaw rad) for the
    /// next update.
    pub fn add_scan(&mut self, scan: &LaserScan, sensor: Pose2) {
        if self.pending.len() >= MAX_PENDING_SCANS {
            self.pending.remove(0);
        }
        self.pending.push((scan.clone(), sensor));
    }

    /// The layer's own grid: [`LETHAL`] where marked, [`FREE`] where cleared, [`UNKNOWN`] where
    /// no scan reached.
    pub fn grid(&self) -> &Costmap2D {
        &self.grid
    }

    /// Replaces the footprint used for footprint clearing.
    pub fn set_footprint(&mut self, footprint: Footprint) {
        self.footprint = footprint;
    }

    /// Parameters.
    pub fn params(&self) -> &ObstacleLayerParams {
        &self.params
    }

    /// Number of marked cells.
    pub fn marked_cells(&self) -> usize {
        self.grid.costs().iter().filter(|&&c| c == LETHAL).count()
    }

    /// Forgets the cells outside the square of side `reset_distance` (m) centred on `center`
    /// (ROS ClearCostmapRecovery with `invert_area_to_clear` false).
    pub fn clear_outside(&mut self, center: Point2, reset_distance: f64) {
        let h = reset_distance / 2.0;
        let (x0, y0) = self
            .grid
            .world_to_map_continuous(Point2::new(center.x - h, center.y - h));
        let (x1, y1) = self
            .grid
            .world_to_map_continuous(Point2::new(center.x + h, center.y + h));
        let (sx, sy) = (self.grid.size_x(), self.grid.size_y());
        for my in 0..sy {
            for mx in 0..sx {
                let inside = (mx as f64) > x0.floor()
                    && (mx as f64) < x1.floor()
                    && (my as f64) > y0.floor()
                    && (my as f64) < y1.floor();
                if !inside {
                    self.grid.set_cost(mx, my, UNKNOWN);
                }
            }
        }
        self.extra_bounds.union(&self.grid.world_bounds());
    }

    fn process_scans(&mut self, bounds: &mut Bounds) {
        let pending = std::mem::take(&mut self.pending);
        let p = self.params.clone();
        let mut marks: Vec<Point2> = Vec::new();
        for (scan, sensor) in &pending {
            let o = sensor.position();
            bounds.touch(o);
            let sensor_in_map = self.grid.contains(o);
            for (i, &r) in scan.ranges.iter().enumerate() {
                let r = r as f64;
                let no_return = r == f64::INFINITY
                    || (r.is_finite() && r >= scan.range_max)
                    || (r.is_nan() && p.nan_is_inf);
                let (a_s, a_c) = (sensor.yaw + scan.angle(i)).sin_cos();
                let at = |d: f64| Point2::new(o.x + d * a_c, o.y + d * a_s);
                if no_return {
                    if p.inf_is_valid && p.clearing && sensor_in_map {
                        let end = at(p.raytrace_range.min(scan.range_max));
                        self.clear_ray(o, end, false, bounds);
                    }
                    continue;
                }
                if !r.is_finite() || r < scan.range_min {
                    continue;
                }
                if p.clearing && sensor_in_map {
                    let hit_inside = r <= p.raytrace_range;
                    self.clear_ray(o, at(r.min(p.raytrace_range)), hit_inside, bounds);
                }
                if p.marking && r < p.obstacle_range {
                    marks.push(at(r));
                }
            }
        }
        for m in marks {
            if let Some((mx, my)) = self.grid.world_to_map(m) {
                self.grid.set_cost(mx, my, LETHAL);
                bounds.touch(m);
            }
        }
    }

    /// Frees the cells from `from` to `to` (m), the last one excepted when `keep_end`.
    fn clear_ray(&mut self, from: Point2, to: Point2, keep_end: bool, bounds: &mut Bounds) {
        let (x0, y0) = self.grid.world_to_map_continuous(from);
        let (x1, y1) = self.grid.world_to_map_continuous(to);
        let end = (x1.floor() as i64, y1.floor() as i64);
        let (sx, sy) = (self.grid.size_x() as i64, self.grid.size_y() as i64);
        let grid = &mut self.grid;
        traverse_segment(x0, y0, x1, y1, |cx, cy| {
            if cx < 0 || cy < 0 || cx >= sx || cy >= sy {
                return false;
            }
            if keep_end && (cx, cy) == end {
                return false;
            }
            grid.set_cost(cx as usize, cy as usize, FREE);
            true
        });
        bounds.touch(to);
    }

    fn clear_footprint(&mut self, robot: Pose2, bounds: &mut Bounds) {
        let r = self.footprint.circumscribed_radius();
        let b = Bounds {
            min_x: robot.x - r,
            min_y: robot.y - r,
            max_x: robot.x + r,
            max_y: robot.y + r,
        };
        let cells = self.grid.cell_range(&b);
        let to_base = robot.inverse();
        for my in cells.y0..cells.yn {
            for mx in cells.x0..cells.xn {
                let w = self.grid.map_to_world(mx, my);
                if self
                    .footprint
                    .contains_local(to_base.compose(Pose2::new(w.x, w.y, 0.0)).position())
                {
                    self.grid.set_cost(mx, my, FREE);
                }
            }
        }
        bounds.union(&b);
    }
}

impl CostmapLayer for ObstacleLayer {
    fn name(&self) -> &str {
        &self.name
    }

    fn update_bounds(&mut self, robot: Pose2, _master: &Costmap2D, bounds: &mut Bounds) {
        self.process_scans(bounds);
        if self.params.footprint_clearing_enabled {
            self.clear_footprint(robot, bounds);
        }
        bounds.union(&self.extra_bounds);
        self.extra_bounds = Bounds::empty();
    }

    fn update_costs(&mut self, _robot: Pose2, master: &mut Costmap2D, cells: CellRange) {
        if self.grid.size_x() != master.size_x() || self.grid.size_y() != master.size_y() {
            return;
        }
        let overwrite = self.params.combination_method == 0;
        for my in cells.y0..cells.yn {
            for mx in cells.x0..cells.xn {
                let own = self.grid.cost(mx, my);
                if own == UNKNOWN {
                    continue;
                }
                let old = master.cost(mx, my);
                if overwrite || old == UNKNOWN || old < own {
                    master.set_cost(mx, my, own);
                }
            }
        }
    }

    fn reset(&mut self) {
        self.grid.reset();
        self.pending.clear();
        self.extra_bounds.union(&self.grid.world_bounds());
    }

    fn match_size(&mut self, master: &Costmap2D) {
        let same_shape = self.grid.size_x() == master.size_x()
            && self.grid.size_y() == master.size_y()
            && self.grid.resolution() == master.resolution();
        if same_shape {
            self.grid.update_origin(master.origin());
        } else {
            self.grid.resize(
                master.size_x(),
                master.size_y(),
                master.resolution(),
                master.origin(),
            );
        }
    }

    fn is_enabled(&self) -> bool {
        self.params.enabled
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(params: ObstacleLayerParams) -> ObstacleLayer {
        let mut l = ObstacleLayer::new("obstacle_layer", params, Footprint::circle(0.1));
        l.match_size(&Costmap2D::new(100, 100, 0.05, Point2::default(), FREE));
        l
    }

    /// Five beams spread over +-0.1 rad.
    fn scan(ranges: Vec<f32>) -> LaserScan {
        let n = ranges.len();
        LaserScan {
            angle_min: -0.1,
            angle_max: 0.1,
            angle_increment: 0.2 / (n - 1) as f64,
            range_min: 0.1,
            range_max: 3.5,
            ranges,
        }
    }

    fn update(l: &mut ObstacleLayer, robot: Pose2) -> Bounds {
        let mut b = Bounds::empty();
        l.update_bounds(
            robot,
            &Costmap2D::new(100, 100, 0.05, Point2::default(), FREE),
            &mut b,
        );
        b
    }

    #[test]
    fn marks_hits_and_clears_them_when_the_obstacle_moves_away() {
        let mut l = layer(ObstacleLayerParams::default());
        let robot = Pose2::new(1.0, 2.5, 0.0);
        l.add_scan(&scan(vec![1.0; 5]), robot);
        let b = update(&mut l, robot);
        assert!(b.min_x <= 1.0 && b.max_x >= 1.99);
        assert!((1..=5).contains(&l.marked_cells()), "{}", l.marked_cells());
        assert_eq!(l.grid().cost_at(Point2::new(2.01, 2.5)), Some(LETHAL));
        assert_eq!(l.grid().cost_at(Point2::new(1.5, 2.5)), Some(FREE));
        // The obstacle moved away: a longer reading along the same rays clears the old marks.
        l.add_scan(&scan(vec![2.0; 5]), robot);
        update(&mut l, robot);
        assert_eq!(l.grid().cost_at(Point2::new(2.01, 2.5)), Some(FREE));
        assert_eq!(l.grid().cost_at(Point2::new(3.01, 2.5)), Some(LETHAL));
        // Beyond obstacle_range (2.5 m): no mark, but the ray still clears.
        l.add_scan(&scan(vec![2.8; 5]), robot);
        update(&mut l, robot);
        assert_eq!(l.marked_cells(), 0);
    }

    #[test]
    fn no_return_clears_only_when_inf_is_valid() {
        let robot = Pose2::new(1.0, 2.5, 0.0);
        for (params, ranges, cleared) in [
            (
                ObstacleLayerParams::default(),
                vec![f32::INFINITY; 5],
                false,
            ),
            (
                ObstacleLayerParams {
                    inf_is_valid: true,
                    ..Default::default()
                },
                vec![f32::INFINITY; 5],
                true,
            ),
            (
                ObstacleLayerParams {
                    inf_is_valid: true,
                    ..Default::default()
                },
                vec![f32::NAN; 5],
                false,
            ),
            (
                ObstacleLayerParams {
                    inf_is_valid: true,
                    nan_is_inf: true,
                    ..Default::default()
                },
                vec![f32::NAN; 5],
                true,
            ),
            (
                ObstacleLayerParams {
                    inf_is_valid: true,
                    ..Default::default()
                },
                vec![3.5; 5],
                true,
            ),
        ] {
            let mut l = layer(params);
            l.add_scan(&scan(vec![1.0; 5]), robot);
            update(&mut l, robot);
            assert!(l.marked_cells() > 0);
            l.add_scan(&scan(ranges.clone()), robot);
            update(&mut l, robot);
            assert_eq!(l.marked_cells() == 0, cleared, "{ranges:?}");
            // A no-return never marks.
            assert_ne!(l.grid().cost_at(Point2::new(4.01, 2.5)), Some(LETHAL));
        }
    }

    #[test]
    fn combines_by_maximum_and_clears_its_footprint() {
        let mut l = layer(ObstacleLayerParams::default());
        let robot = Pose2::new(1.0, 2.5, 0.0);
        l.add_scan(
            &scan(vec![0.3, 0.3, 0.05, 0.3, 0.3]),
            Pose2::new(0.75, 2.5, 0.0),
        );
        update(&mut l, robot);
        // The hits at 1.05 m fall inside the robot's 0.1 m footprint: cleared at once.
        assert_eq!(l.marked_cells(), 0);
        let mut master = Costmap2D::new(100, 100, 0.05, Point2::default(), FREE);
        master.set_cost(60, 50, LETHAL);
        l.add_scan(&scan(vec![1.0; 5]), robot);
        update(&mut l, robot);
        l.update_costs(
            robot,
            &mut master,
            CellRange {
                x0: 0,
                y0: 0,
                xn: 100,
                yn: 100,
            },
        );
        assert_eq!(
            master.cost(60, 50),
            LETHAL,
            "a cleared cell of this layer does not erase the static map"
        );
        assert_eq!(master.cost_at(Point2::new(2.01, 2.5)), Some(LETHAL));
    }
}
