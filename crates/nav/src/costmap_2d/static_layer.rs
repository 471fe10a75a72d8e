//! The static layer (ROS `costmap_2d::StaticLayer`): costs from a map_server map.
//!
//! A map value at or above `lethal_cost_threshold` is [`LETHAL`], the unknown value
//! (`unknown_cost_value`, -1) is [`UNKNOWN`] when `track_unknown_space` and [`FREE`] otherwise,
//! and anything else is free (`trinary_costmap`) or scaled linearly towards lethal.

use super::cost_values::{FREE, LETHAL, UNKNOWN};
use super::costmap::{Bounds, CellRange, Costmap2D};
use super::layer::CostmapLayer;
use crate::param_error::{check_range, ParamError};
use serde::{Deserialize, Serialize};
use xhab_types::{OccupancyGrid, Pose2};

/// Static layer parameters (ROS names and noetic code defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StaticLayerParams {
    /// Whether the layer is applied (default true).
    pub enabled: bool,
    /// Unknown map cells stay [`UNKNOWN`] (true, the layer's ROS default) or become free.
    pub track_unknown_space: bool,
    /// Combine with the layers below by maximum (true) or overwrite them (false, default).
    pub use_maximum: bool,
    /// Map value (0..=100) from which a cell is lethal (default 100, range [0, 255]).
    pub lethal_cost_threshold: i32,
    /// Map value that means unknown (default -1).
    pub unknown_cost_value: i32,
    /// Map values below the threshold are free (true, default) or scaled towards lethal.
    pub trinary_costmap: bool,
}

impl Default for StaticLayerParams {
    fn default() -> Self {
        Self {
            enabled: true,
            track_unknown_space: true,
            use_maximum: false,
            lethal_cost_threshold: 100,
            unknown_cost_value: -1,
            trinary_costmap: true,
        }
    }
}

impl StaticLayerParams {
    /// Checks ranges.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range(
            "lethal_cost_threshold",
            self.lethal_cost_threshold as f64,
            0.0,
            255.0,
        )?;
        check_range(
            "unknown_cost_value",
            self.unknown_cost_value as f64,
            -128.0,
            255.0,
        )
    }

    /// The cost of map value `v` (read as an unsigned byte, as ROS does).
    pub fn interpret(&self, v: i8) -> u8 {
        let value = v as u8 as i32;
        let unknown = self.unknown_cost_value as i8 as u8 as i32;
        if value == unknown {
            return if self.track_unknown_space {
                UNKNOWN
            } else {
                FREE
            };
        }
        if value >= self.lethal_cost_threshold {
            LETHAL
        } else if self.trinary_costmap {
            FREE
        } else {
            ((value as f64 / self.lethal_cost_threshold.max(1) as f64) * LETHAL as f64) as u8
        }
    }
}

/// The static layer: the map's costs on the map's own grid.
#[derive(Debug, Clone)]
pub struct StaticLayer {
    name: String,
    params: StaticLayerParams,
    map: Option<Costmap2D>,
    rolling: bool,
    has_updated_data: bool,
}

impl StaticLayer {
    /// A layer named `name` without a map yet; `rolling` when its costmap is a rolling window.
    pub fn new(name: &str, params: StaticLayerParams, rolling: bool) -> Self {
        Self {
            name: name.to_string(),
            params,
            map: None,
            rolling,
            has_updated_data: false,
        }
    }

    /// Takes a new map (its yaw is ignored, as ROS costmap_2d does).
    pub fn set_map(&mut self, map: &OccupancyGrid) {
        let mut grid = Costmap2D::like_grid(map, FREE);
        for (c, &v) in grid.costs_mut().iter_mut().zip(&map.data) {
            *c = self.params.interpret(v);
        }
        self.map = Some(grid);
        self.has_updated_data = true;
    }

    /// The map's costs on the map's grid, once a map was set.
    pub fn map_costs(&self) -> Option<&Costmap2D> {
        self.map.as_ref()
    }

    /// Parameters.
    pub fn params(&self) -> &StaticLayerParams {
        &self.params
    }
}

impl CostmapLayer for StaticLayer {
    fn name(&self) -> &str {
        &self.name
    }

    fn update_bounds(&mut self, _robot: Pose2, master: &Costmap2D, bounds: &mut Bounds) {
        let Some(map) = &self.map else { return };
        if self.rolling {
            bounds.union(&master.world_bounds());
        } else if self.has_updated_data {
            bounds.union(&map.world_bounds());
        }
        self.has_updated_data = false;
    }

    fn update_costs(&mut self, _robot: Pose2, master: &mut Costmap2D, cells: CellRange) {
        let Some(map) = &self.map else { return };
        let same_grid = map.size_x() == master.size_x()
            && map.size_y() == master.size_y()
            && map.resolution() == master.resolution()
            && map.origin() == master.origin();
        let use_max = self.params.use_maximum;
        for my in cells.y0..cells.yn {
            for mx in cells.x0..cells.xn {
                let v = if same_grid {
                    map.cost(mx, my)
                } else {
                    match map.cost_at(master.map_to_world(mx, my)) {
                        Some(v) => v,
                        None => continue,
                    }
                };
                let old = master.cost(mx, my);
                let new = if !use_max {
                    v
                } else if v == UNKNOWN {
                    old
                } else if old == UNKNOWN {
                    v
                } else {
                    old.max(v)
                };
                master.set_cost(mx, my, new);
            }
        }
    }

    fn reset(&mut self) {
        self.has_updated_data = self.map.is_some();
    }

    fn is_enabled(&self) -> bool {
        self.params.enabled
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_values_follow_ros_interpretation() {
        let p = StaticLayerParams::default();
        assert_eq!(p.interpret(100), LETHAL);
        assert_eq!(p.interpret(99), FREE);
        assert_eq!(p.interpret(-1), UNKNOWN);
        let p = StaticLayerParams {
            track_unknown_space: false,
            lethal_cost_threshold: 65,
            trinary_costmap: false,
            ..Default::default()
        };
        assert_eq!(p.interpret(-1), FREE);
        assert_eq!(p.interpret(65), LETHAL);
        assert_eq!(p.interpret(0), FREE);
        assert_eq!(p.interpret(13), 50); // 13 / 65 * 254 = 50.8
    }
}
