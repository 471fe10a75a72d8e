//! [`GridPlanner`]: Dijkstra or A* on the costmap's cells (see [`grid_search`](super::grid_search)
//! for the cost), then shortcut, smoothed and oriented.
//!
//! Start and goal rules: a start in a lethal cell fails ([`PlanError::StartOccupied`]); a start
//! in the inscribed zone (a robot pressed against a wall) may cross inscribed cells within the
//! escape radius around it to get out, where ROS would fail. An impassable goal is replaced by
//! the nearest passable cell within `default_tolerance`; an unreachable goal by the nearest
//! reachable cell within it, as navfn does.

use super::grid_search::{search, CostModel};
use super::orientation::orient;
use super::planner_params::GlobalPlannerParams;
use super::smoother::{densify, shortcut, smooth};
use super::{GlobalPlanner, Path, PlanError};
use crate::costmap_2d::{Costmap2D, LETHAL, UNKNOWN};
use crate::param_error::ParamError;
use xhab_types::{Point2, Pose2};

/// A grid planner with ROS global_planner's parameters.
#[derive(Debug, Clone)]
pub struct GridPlanner {
    params: GlobalPlannerParams,
    escape_radius: f64,
    expanded: usize,
}

impl GridPlanner {
    /// A planner with `params` (checked).
    pub fn new(params: GlobalPlannerParams) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self {
            params,
            escape_radius: 0.0,
            expanded: 0,
        })
    }

    /// Parameters.
    pub fn params(&self) -> &GlobalPlannerParams {
        &self.params
    }

    /// Sets how far (m, default 0) from a start inside the inscribed zone the path may cross
    /// inscribed cells; the robot's inscribed radius is the natural value.
    pub fn set_escape_radius(&mut self, r: f64) {
        self.escape_radius = r.max(0.0);
    }

    /// Cells the last search expanded.
    pub fn last_expanded(&self) -> usize {
        self.expanded
    }

    /// Passable cells within `radius` (m) of `p`, nearest first.
    fn cells_near(costmap: &Costmap2D, weights: &[f64], p: Point2, radius: f64) -> Vec<usize> {
        let (cx, cy) = costmap.world_to_map_unbounded(p);
        let k = (radius / costmap.resolution()).ceil() as i64 + 1;
        let mut out: Vec<(f64, usize)> = Vec::new();
        for y in (cy - k).max(0)..=(cy + k).min(costmap.size_y() as i64 - 1) {
            for x in (cx - k).max(0)..=(cx + k).min(costmap.size_x() as i64 - 1) {
                let (x, y) = (x as usize, y as usize);
                let d = costmap.map_to_world(x, y).dist(p);
                let i = costmap.index(x, y);
                if d <= radius && weights[i].is_finite() {
                    out.push((d, i));
                }
            }
        }
        out.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out.into_iter().map(|(_, i)| i).collect()
    }
}

impl GlobalPlanner for GridPlanner {
    fn plan(&mut self, costmap: &Costmap2D, start: Pose2, goal: Pose2) -> Result<Path, PlanError> {
        let p = &self.params;
        let model = CostModel::from_params(p);
        let mut weights = model.weights(costmap);
        let (sx, sy) = costmap
            .world_to_map(start.position())
            .ok_or(PlanError::StartOutsideMap)?;
        let (gx, gy) = costmap
            .world_to_map(goal.position())
            .ok_or(PlanError::GoalOutsideMap)?;
        let (s, g) = (costmap.index(sx, sy), costmap.index(gx, gy));
        let start_cost = costmap.cost(sx, sy);
        if start_cost == LETHAL || (start_cost == UNKNOWN && !p.allow_unknown) {
            return Err(PlanError::StartOccupied);
        }
        if !weights[s].is_finite() {
            // Inside the inscribed zone: let the path cross it near the start, at the highest cost.
            let w = model.weight_of_cost(p.lethal_cost as f64);
            let r = self.escape_radius + 0.5 * costmap.resolution();
            let k = (r / costmap.resolution()).ceil() as i64;
            for y in (sy as i64 - k).max(0)..=(sy as i64 + k).min(costmap.size_y() as i64 - 1) {
                for x in (sx as i64 - k).max(0)..=(sx as i64 + k).min(costmap.size_x() as i64 - 1) {
                    let (x, y) = (x as usize, y as usize);
                    let c = costmap.cost(x, y);
                    if c < LETHAL && costmap.map_to_world(x, y).dist(start.position()) <= r {
                        let i = costmap.index(x, y);
                        weights[i] = weights[i].min(w);
                    }
                }
            }
            weights[s] = w;
        }
        let tolerance = p.default_tolerance;
        let candidates = if tolerance > 0.0 {
            Self::cells_near(costmap, &weights, goal.position(), tolerance)
        } else {
            Vec::new()
        };
        let target = if weights[g].is_finite() {
            g
        } else {
            *candidates.first().ok_or(PlanError::GoalOccupied)?
        };
        let res = costmap.resolution();
        let result = search(
            &weights,
            costmap.size_x(),
            costmap.size_y(),
            res,
            s,
            target,
            !p.use_dijkstra,
        );
        self.expanded = result.expanded;
        let target = if result.found {
            target
        } else {
            *candidates
                .iter()
                .find(|&&c| result.cost[c].is_finite())
                .ok_or(PlanError::NoPath)?
        };
        let cells = result.cells_to(target).ok_or(PlanError::NoPath)?;
        let end = if target == g {
            goal.position()
        } else {
            costmap.map_to_world(target % costmap.size_x(), target / costmap.size_x())
        };
        let mut pts: Vec<Point2> = cells
            .iter()
            .map(|&i| costmap.map_to_world(i % costmap.size_x(), i / costmap.size_x()))
            .collect();
        let cum: Vec<f64> = cells.iter().map(|&i| result.cost[i]).collect();
        pts[0] = start.position();
        if pts.len() == 1 {
            pts.push(end);
        } else if let Some(last) = pts.last_mut() {
            *last = end;
        }
        let mut pts = if p.smooth_path && pts.len() > 2 {
            let short = shortcut(costmap, &weights, &pts, &cum);
            let mut dense = densify(&short, res);
            smooth(costmap, &weights, &mut dense);
            dense
        } else {
            pts
        };
        pts.dedup_by(|a, b| a.dist(*b) < 1e-9);
        Ok(orient(
            &pts,
            start.yaw,
            goal.yaw,
            p.orientation_mode,
            p.orientation_window_size.max(1) as usize,
        ))
    }
}
