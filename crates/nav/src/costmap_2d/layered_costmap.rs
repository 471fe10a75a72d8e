//! [`LayeredCostmap`]: a master [`Costmap2D`] built from layers in the configured order (ROS
//! `costmap_2d::LayeredCostmap` with the parts of `Costmap2DROS` that are not ROS plumbing),
//! either fixed to the static map (global costmap) or a rolling window that follows the robot
//! (local costmap); and [`CostmapParams`], its parameters by ROS names.

use super::cost_values::{FREE, UNKNOWN};
use super::costmap::{Bounds, Costmap2D};
use super::footprint::{Footprint, FootprintSpec};
use super::inflation_layer::{InflationLayer, InflationLayerParams};
use super::layer::CostmapLayer;
use super::obstacle_layer::{ObstacleLayer, ObstacleLayerParams};
use super::static_layer::{StaticLayer, StaticLayerParams};
use crate::param_error::{check_positive, check_range, ParamError};
use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, OccupancyGrid, Point2, Pose2};

/// ROS plugin type of the static layer.
pub const STATIC_LAYER_TYPE: &str = "costmap_2d::StaticLayer";
/// ROS plugin type of the obstacle layer.
pub const OBSTACLE_LAYER_TYPE: &str = "costmap_2d::ObstacleLayer";
/// ROS plugin type of the voxel layer (run as a planar obstacle layer).
pub const VOXEL_LAYER_TYPE: &str = "costmap_2d::VoxelLayer";
/// ROS plugin type of the inflation layer.
pub const INFLATION_LAYER_TYPE: &str = "costmap_2d::InflationLayer";

/// One entry of the ROS `plugins` list: the layer's name and its plugin type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PluginSpec {
    /// Name; a ROS YAML keeps the layer's parameters under it (here they are read into
    /// `static_layer`, `obstacle_layer` or `inflation_layer` by type).
    pub name: String,
    /// Plugin type, e.g. `costmap_2d::InflationLayer`.
    #[serde(rename = "type")]
    pub kind: String,
}

impl PluginSpec {
    /// An entry of `name` and `kind`.
    pub fn new(name: &str, kind: &str) -> Self {
        Self {
            name: name.to_string(),
            kind: kind.to_string(),
        }
    }
}

/// Costmap parameters (ROS `costmap_2d` names and noetic code defaults), one set per costmap
/// (`global_costmap`, `local_costmap`), with the parameters of its layers nested by layer.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CostmapParams {
    /// Frame of the costmap (default `map`; informational, poses are given in it).
    pub global_frame: String,
    /// Frame of the robot base (default `base_link`; informational).
    pub robot_base_frame: String,
    /// Rate of costmap updates (Hz, default 5, range [0, 100]; 0 updates on every tick).
    pub update_frequency: f64,
    /// Whether the costmap is a window centred on the robot (default false).
    pub rolling_window: bool,
    /// Width of the costmap when not given by the static map (m, default 10).
    pub width: f64,
    /// Height of the costmap when not given by the static map (m, default 10).
    pub height: f64,
    /// Cell size when not given by the static map (m, default 0.05, range (0, 50]).
    pub resolution: f64,
    /// x of the lower-left corner when not given by the static map (m, default 0).
    pub origin_x: f64,
    /// y of the lower-left corner when not given by the static map (m, default 0).
    pub origin_y: f64,
    /// Radius of a round robot (m, default 0.46, range [0, 10]); used when `footprint` is empty.
    pub robot_radius: f64,
    /// Footprint polygon in the base frame (m, default empty: round robot).
    pub footprint: FootprintSpec,
    /// Padding added around the footprint (m, default 0.01, range [0, 1]).
    pub footprint_padding: f64,
    /// Cells without information are UNKNOWN (true) or FREE (false, default).
    pub track_unknown_space: bool,
    /// Layers in update order (default static, obstacle, inflation layer).
    pub plugins: Vec<PluginSpec>,
    /// Static layer parameters.
    pub static_layer: StaticLayerParams,
    /// Obstacle layer parameters.
    pub obstacle_layer: ObstacleLayerParams,
    /// Inflation layer parameters.
    pub inflation_layer: InflationLayerParams,
}

impl Default for CostmapParams {
    fn default() -> Self {
        Self {
            global_frame: "map".into(),
            robot_base_frame: "base_link".into(),
            update_frequency: 5.0,
            rolling_window: false,
            width: 10.0,
            height: 10.0,
            resolution: 0.05,
            origin_x: 0.0,
            origin_y: 0.0,
            robot_radius: 0.46,
            footprint: FootprintSpec::default(),
            footprint_padding: 0.01,
            track_unknown_space: false,
            plugins: vec![
                PluginSpec::new("static_layer", STATIC_LAYER_TYPE),
                PluginSpec::new("obstacle_layer", OBSTACLE_LAYER_TYPE),
                PluginSpec::new("inflation_layer", INFLATION_LAYER_TYPE),
            ],
            static_layer: StaticLayerParams::default(),
            obstacle_layer: ObstacleLayerParams::default(),
            inflation_layer: InflationLayerParams::default(),
        }
    }
}

impl CostmapParams {
    /// Checks ranges, the footprint and the plugin types.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_range("update_frequency", self.update_frequency, 0.0, 100.0)?;
        check_positive("width", self.width)?;
        check_positive("height", self.height)?;
        check_positive("resolution", self.resolution)?;
        check_range("resolution", self.resolution, 0.0, 50.0)?;
        check_range("robot_radius", self.robot_radius, 0.0, 10.0)?;
        check_range("footprint_padding", self.footprint_padding, 0.0, 1.0)?;
        if !self.footprint.0.is_empty() && self.footprint.0.len() < 3 {
            return Err(ParamError::invalid(
                "footprint",
                format!("needs at least 3 points, got {}", self.footprint.0.len()),
            ));
        }
        if self.footprint.0.iter().flatten().any(|v| !v.is_finite()) {
            return Err(ParamError::invalid("footprint", "points must be finite"));
        }
        for (i, p) in self.plugins.iter().enumerate() {
            if ![
                STATIC_LAYER_TYPE,
                OBSTACLE_LAYER_TYPE,
                VOXEL_LAYER_TYPE,
                INFLATION_LAYER_TYPE,
            ]
            .contains(&p.kind.as_str())
            {
                return Err(ParamError::invalid(
                    &format!("plugins[{i}].type"),
                    format!("unsupported layer type {:?}", p.kind),
                ));
            }
        }
        self.static_layer
            .validate()
            .map_err(|e| e.within("static_layer"))?;
        self.obstacle_layer
            .validate()
            .map_err(|e| e.within("obstacle_layer"))?;
        self.inflation_layer
            .validate()
            .map_err(|e| e.within("inflation_layer"))
    }

    /// The footprint these parameters describe.
    pub fn robot_footprint(&self) -> Footprint {
        Footprint::from_params(self.robot_radius, &self.footprint, self.footprint_padding)
    }
}

/// One layer of a [`LayeredCostmap`].
#[derive(Debug, Clone)]
pub enum Layer {
    /// A static map layer.
    Static(StaticLayer),
    /// An obstacle layer fed by laser scans.
    Obstacle(ObstacleLayer),
    /// An inflation layer.
    Inflation(InflationLayer),
}

impl Layer {
    fn as_dyn(&mut self) -> &mut dyn CostmapLayer {
        match self {
            Layer::Static(l) => l,
            Layer::Obstacle(l) => l,
            Layer::Inflation(l) => l,
        }
    }
}

/// A costmap made of layers.
#[derive(Debug, Clone)]
pub struct LayeredCostmap {
    params: CostmapParams,
    footprint: Footprint,
    master: Costmap2D,
    layers: Vec<Layer>,
}

impl LayeredCostmap {
    /// A costmap with `params` (checked); its window is `width` x `height` at `origin_x/y`
    /// until a static map (for a non-rolling costmap) gives it the map's geometry.
    pub fn new(params: CostmapParams) -> Result<Self, ParamError> {
        params.validate()?;
        let footprint = params.robot_footprint();
        let default = if params.track_unknown_space {
            UNKNOWN
        } else {
            FREE
        };
        let (nx, ny) = (
            (params.width / params.resolution).round().max(1.0) as usize,
            (params.height / params.resolution).round().max(1.0) as usize,
        );
        let master = Costmap2D::new(
            nx,
            ny,
            params.resolution,
            Point2::new(params.origin_x, params.origin_y),
            default,
        );
        let layers = params
            .plugins
            .iter()
            .map(|p| match p.kind.as_str() {
                STATIC_LAYER_TYPE => Layer::Static(StaticLayer::new(
                    &p.name,
                    params.static_layer.clone(),
                    params.rolling_window,
                )),
                INFLATION_LAYER_TYPE => Layer::Inflation(InflationLayer::new(
                    &p.name,
                    params.inflation_layer.clone(),
                    footprint.inscribed_radius(),
                )),
                _ => Layer::Obstacle(ObstacleLayer::new(
                    &p.name,
                    params.obstacle_layer.clone(),
                    footprint.clone(),
                )),
            })
            .collect();
        let mut cm = Self {
            params,
            footprint,
            master,
            layers,
        };
        cm.match_layers();
        Ok(cm)
    }

    fn match_layers(&mut self) {
        for l in &mut self.layers {
            l.as_dyn().match_size(&self.master);
        }
    }

    /// Gives the static layers a new map; a non-rolling costmap takes the map's geometry.
    pub fn set_map(&mut self, map: &OccupancyGrid) {
        if !self.params.rolling_window {
            self.master
                .resize(map.width, map.height, map.resolution, map.origin.position());
            self.match_layers();
        }
        for l in &mut self.layers {
            if let Layer::Static(s) = l {
                s.set_map(map);
            }
        }
    }

    /// Queues a scan from a sensor at `sensor` (world frame) for every obstacle layer.
    pub fn add_scan(&mut self, scan: &LaserScan, sensor: Pose2) {
        for l in &mut self.layers {
            if let Layer::Obstacle(o) = l {
                o.add_scan(scan, sensor);
            }
        }
    }

    /// Replaces the robot's footprint (inflation and footprint clearing follow it).
    pub fn set_footprint(&mut self, footprint: Footprint) {
        for l in &mut self.layers {
            match l {
                Layer::Inflation(i) => i.set_inscribed_radius(footprint.inscribed_radius()),
                Layer::Obstacle(o) => o.set_footprint(footprint.clone()),
                Layer::Static(_) => {}
            }
        }
        self.footprint = footprint;
    }

    /// Brings the master grid up to date with the robot at `robot` (world frame): moves a
    /// rolling window, then runs the layers' two update phases.
    pub fn update(&mut self, robot: Pose2) {
        if self.params.rolling_window {
            let o = Point2::new(
                robot.x - self.master.size_in_meters_x() / 2.0,
                robot.y - self.master.size_in_meters_y() / 2.0,
            );
            self.master.update_origin(o);
            self.match_layers();
        }
        let mut bounds = Bounds::empty();
        for l in &mut self.layers {
            let l = l.as_dyn();
            if l.is_enabled() {
                l.update_bounds(robot, &self.master, &mut bounds);
            }
        }
        let cells = self.master.cell_range(&bounds);
        if cells.is_empty() {
            return;
        }
        self.master.reset_range(cells);
        for l in &mut self.layers {
            let l = l.as_dyn();
            if l.is_enabled() {
                l.update_costs(robot, &mut self.master, cells);
            }
        }
    }

    /// Forgets what every layer learnt from sensors and rebuilds the master at the next update
    /// (ROS `resetLayers`).
    pub fn reset_layers(&mut self) {
        self.master.reset();
        for l in &mut self.layers {
            l.as_dyn().reset();
        }
    }

    /// Clears the obstacle layers outside the square of side `reset_distance` (m) centred on
    /// `center` (ROS ClearCostmapRecovery); the master follows at the next update.
    pub fn clear_obstacles_outside(&mut self, center: Point2, reset_distance: f64) {
        for l in &mut self.layers {
            if let Layer::Obstacle(o) = l {
                o.clear_outside(center, reset_distance);
            }
        }
    }

    /// The master grid.
    pub fn costmap(&self) -> &Costmap2D {
        &self.master
    }
    /// The robot's footprint.
    pub fn footprint(&self) -> &Footprint {
        &self.footprint
    }
    /// Parameters.
    pub fn params(&self) -> &CostmapParams {
        &self.params
    }
    /// The layers in update order.
    pub fn layers(&self) -> &[Layer] {
        &self.layers
    }
    /// Whether a static layer holds a map.
    pub fn has_map(&self) -> bool {
        self.layers
            .iter()
            .any(|l| matches!(l, Layer::Static(s) if s.map_costs().is_some()))
    }
}
