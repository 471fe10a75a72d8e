//! The inflation layer (ROS `costmap_2d::InflationLayer`): costs that fall off with the
//! distance `d` to the nearest lethal cell, with ROS's cost function
//!
//! ```text
//! d = 0                          -> LETHAL (254)
//! 0 < d <= inscribed_radius      -> INSCRIBED (253)
//! inscribed_radius < d <= r_infl -> floor(252 * exp(-cost_scaling_factor * (d - inscribed_radius)))
//! d > r_infl                     -> FREE (0)
//! ```
//!
//! where `d` runs between cell centres. Distances come from an exact Euclidean distance
//! transform over the updated window (grown by the inflation radius) rather than ROS's
//! cell-by-cell priority-queue propagation; the values are the same wherever ROS's propagation
//! is exact. Inflation only raises costs (it takes the maximum with what is there), and it
//! overwrites an unknown cell only with a cost of at least INSCRIBED (any cost above FREE with
//! `inflate_unknown`).

use super::cost_values::{FREE, INSCRIBED, LETHAL, MAX_NON_OBSTACLE, UNKNOWN};
use super::costmap::{Bounds, CellRange, Costmap2D};
use super::distance_transform::squared_distance_transform;
use super::layer::CostmapLayer;
use crate::param_error::{check_range, ParamError};
use serde::{Deserialize, Serialize};
use xhab_types::Pose2;

/// Inflation layer parameters (ROS names and noetic defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct InflationLayerParams {
    /// Whether the layer is applied (default true).
    pub enabled: bool,
    /// Distance from obstacles up to which costs are inflated (m, default 0.55, range [0, 50]);
    /// never less than the inscribed radius in effect.
    pub inflation_radius: f64,
    /// Exponential decay of the cost beyond the inscribed radius (1/m, default 10, range
    /// [0, 100]); larger values let paths run closer to obstacles.
    pub cost_scaling_factor: f64,
    /// Inflated costs above FREE overwrite unknown cells (default false).
    pub inflate_unknown: bool,
}

impl Default for InflationLayerParams {
    fn default() -> Self {
        Self {
            enabled: true,
            inflation_radius: 0.55,
            cost_scaling_factor: 10.0,
            inflate_unknown: false,
        }
    }
}

impl InflationLayerParams {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("inflation_radius", self.inflation_radius, 0.0, 50.0)?;
        check_range("cost_scaling_factor", self.cost_scaling_factor, 0.0, 100.0)
    }
}

/// ROS's inflation cost at distance `d` (m) from the nearest obstacle for a robot of
/// `inscribed_radius` (m).
pub fn inflation_cost(d: f64, inscribed_radius: f64, p: &InflationLayerParams) -> u8 {
    if d <= 0.0 {
        LETHAL
    } else if d <= inscribed_radius + 1e-9 {
        INSCRIBED
    } else if d > p.inflation_radius.max(inscribed_radius) + 1e-9 {
        FREE
    } else {
        let c = (INSCRIBED - 1) as f64 * (-p.cost_scaling_factor * (d - inscribed_radius)).exp();
        (c as u8).min(MAX_NON_OBSTACLE)
    }
}

/// The inflation layer.
#[derive(Debug, Clone)]
pub struct InflationLayer {
    name: String,
    params: InflationLayerParams,
    inscribed_radius: f64,
    need_full: bool,
    /// Cost by squared distance in cells, for `table_resolution`.
    table: Vec<u8>,
    table_resolution: f64,
}

impl InflationLayer {
    /// A layer named `name` for a robot of `inscribed_radius` (m).
    pub fn new(name: &str, params: InflationLayerParams, inscribed_radius: f64) -> Self {
        Self {
            name: name.to_string(),
            params,
            inscribed_radius,
            need_full: true,
            table: Vec::new(),
            table_resolution: 0.0,
        }
    }

    /// Parameters.
    pub fn params(&self) -> &InflationLayerParams {
        &self.params
    }

    /// The inscribed radius in use (m).
    pub fn inscribed_radius(&self) -> f64 {
        self.inscribed_radius
    }

    /// The distance up to which costs are raised (m).
    pub fn effective_radius(&self) -> f64 {
        self.params.inflation_radius.max(self.inscribed_radius)
    }

    /// Changes the robot's inscribed radius (m); the next update re-inflates everything.
    pub fn set_inscribed_radius(&mut self, r: f64) {
        self.inscribed_radius = r;
        self.need_full = true;
        self.table.clear();
    }

    fn cell_radius(&self, resolution: f64) -> usize {
        (self.effective_radius() / resolution).ceil() as usize
    }

    fn ensure_table(&mut self, resolution: f64) {
        if self.table_resolution == resolution && !self.table.is_empty() {
            return;
        }
        let k = self.cell_radius(resolution) + 1;
        self.table = (0..=2 * k * k)
            .map(|sq| {
                inflation_cost(
                    (sq as f64).sqrt() * resolution,
                    self.inscribed_radius,
                    &self.params,
                )
            })
            .collect();
        self.table_resolution = resolution;
    }
}

impl CostmapLayer for InflationLayer {
    fn name(&self) -> &str {
        &self.name
    }

    fn update_bounds(&mut self, _robot: Pose2, master: &Costmap2D, bounds: &mut Bounds) {
        if self.need_full {
            bounds.union(&master.world_bounds());
            self.need_full = false;
        } else {
            bounds.expand(self.effective_radius());
        }
    }

    fn update_costs(&mut self, _robot: Pose2, master: &mut Costmap2D, cells: CellRange) {
        if cells.is_empty() {
            return;
        }
        let res = master.resolution();
        self.ensure_table(res);
        let region = cells.grown(self.cell_radius(res) + 1, master.size_x(), master.size_y());
        let (w, h) = (region.xn - region.x0, region.yn - region.y0);
        let mut seeds = vec![false; w * h];
        let mut any = false;
        for y in 0..h {
            for x in 0..w {
                let lethal = master.cost(region.x0 + x, region.y0 + y) == LETHAL;
                seeds[y * w + x] = lethal;
                any |= lethal;
            }
        }
        if !any {
            return;
        }
        let sq = squared_distance_transform(&seeds, w, h);
        let inflate_unknown = self.params.inflate_unknown;
        for my in cells.y0..cells.yn {
            for mx in cells.x0..cells.xn {
                let d2 = sq[(my - region.y0) * w + (mx - region.x0)];
                let c = if d2.is_finite() {
                    self.table.get(d2 as usize).copied().unwrap_or(FREE)
                } else {
                    FREE
                };
                if c == FREE {
                    continue;
                }
                let old = master.cost(mx, my);
                if old == UNKNOWN {
                    if (inflate_unknown && c > FREE) || c >= INSCRIBED {
                        master.set_cost(mx, my, c);
                    }
                } else if c > old {
                    master.set_cost(mx, my, c);
                }
            }
        }
    }

    fn reset(&mut self) {
        self.need_full = true;
    }

    fn match_size(&mut self, _master: &Costmap2D) {
        self.need_full = true;
    }

    fn is_enabled(&self) -> bool {
        self.params.enabled
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::Point2;

    #[test]
    fn cost_function_matches_hand_computed_values() {
        let p = InflationLayerParams::default();
        let r = 0.1;
        for (d, want) in [
            (0.0, LETHAL),
            (0.05, INSCRIBED),
            (0.1, INSCRIBED),
            (0.15, 152), // 252 * exp(-0.5) = 152.8
            (0.2, 92),   // 252 * exp(-1) = 92.7
            (0.3, 34),   // 252 * exp(-2) = 34.1
            (0.55, 2),   // 252 * exp(-4.5) = 2.8
            (0.5501, FREE),
        ] {
            assert_eq!(inflation_cost(d, r, &p), want, "d = {d}");
        }
        // Never rises with distance.
        let mut last = LETHAL;
        for k in 0..700 {
            let c = inflation_cost(k as f64 * 0.001, r, &p);
            assert!(c <= last, "rose at {k} mm");
            last = c;
        }
    }

    #[test]
    fn inflates_a_single_obstacle_by_cell_distance() {
        let mut m = Costmap2D::new(41, 41, 0.05, Point2::default(), FREE);
        m.set_cost(20, 20, LETHAL);
        m.set_cost(0, 40, UNKNOWN);
        m.set_cost(20, 19, UNKNOWN);
        let mut l = InflationLayer::new("inflation_layer", InflationLayerParams::default(), 0.1);
        let mut b = Bounds::empty();
        l.update_bounds(Pose2::default(), &m, &mut b);
        let r = m.cell_range(&b);
        l.update_costs(Pose2::default(), &mut m, r);
        assert_eq!(m.cost(20, 20), LETHAL);
        assert_eq!(m.cost(22, 20), INSCRIBED); // 0.1 m
        assert_eq!(m.cost(23, 20), 152); // 0.15 m
        assert_eq!(m.cost(24, 20), 92); // 0.2 m
        assert_eq!(m.cost(23, 24), 56); // hypot(3, 4) * 0.05 = 0.25 m: 252 * exp(-1.5) = 56.2
        assert_eq!(m.cost(20, 31), 2); // 0.55 m
        assert_eq!(m.cost(20, 32), FREE); // 0.6 m
        assert_eq!(
            m.cost(20, 19),
            INSCRIBED,
            "unknown overwritten by an inscribed cost"
        );
        assert_eq!(m.cost(0, 40), UNKNOWN, "far unknown stays unknown");
    }
}
