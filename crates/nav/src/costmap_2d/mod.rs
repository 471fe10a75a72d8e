//! Layered costmaps with ROS costmap_2d's cost values, layers and parameter names.
//!
//! - [`Costmap2D`]: the grid of u8 costs and its world <-> map conversions;
//!   [`cost_values`]: FREE 0 .. LETHAL 254, UNKNOWN 255.
//! - [`CostmapLayer`]: the two-phase layer interface; [`StaticLayer`] (map_server map),
//!   [`ObstacleLayer`] (laser scans: marking and ray-trace clearing), [`InflationLayer`]
//!   (ROS cost function over an exact distance transform).
//! - [`Footprint`]: round or polygonal robot with inscribed/circumscribed radii.
//! - [`LayeredCostmap`]: layers in order over a fixed (global) or rolling (local) window,
//!   configured by [`CostmapParams`].

pub mod cost_values;
mod costmap;
mod distance_transform;
mod footprint;
mod inflation_layer;
mod layer;
mod layered_costmap;
mod obstacle_layer;
mod raytrace;
mod static_layer;
#[cfg(test)]
mod tests;

pub use cost_values::{FREE, INSCRIBED, LETHAL, MAX_NON_OBSTACLE, UNKNOWN};
pub use costmap::{Bounds, CellRange, Costmap2D};
pub use distance_transform::squared_distance_transform;
pub use footprint::{point_segment_distance, Footprint, FootprintSpec};
pub use inflation_layer::{inflation_cost, InflationLayer, InflationLayerParams};
pub use layer::CostmapLayer;
pub use layered_costmap::{
    CostmapParams, Layer, LayeredCostmap, PluginSpec, INFLATION_LAYER_TYPE, OBSTACLE_LAYER_TYPE,
    STATIC_LAYER_TYPE, VOXEL_LAYER_TYPE,
};
pub use obstacle_layer::{ObstacleLayer, ObstacleLayerParams};
pub use raytrace::traverse_segment;
pub use static_layer::{StaticLayer, StaticLayerParams};
