//! The xhab navigation stack: knows nothing of the simulator or of ROS.
//!
//! [`map_server`]: maps in ROS's format; [`costmap`]: static and inflation layers with ROS
//! cost values; [`planner`]: A*/Dijkstra global planner; [`dwa`]: the DWA local planner;
//! [`navigator`]: a move_base-like state machine over them; [`ros_params`]: ROS parameter
//! files (move_base, costmap_2d, DWA, global_planner, amcl) read into its parameters.
#![warn(missing_docs)]

pub mod amcl;
pub mod cell_bounds;
pub mod costmap;
pub mod depth_projection;
pub mod depth_to_scan;
/// The exact distance transform, shared with the simulator's navigation grid.
pub use xhab_types::distance_field;
pub mod dwa;
pub mod frontier;
pub mod goal_approach;
pub mod inflation_table;
pub mod layered_costmap;
pub mod map_agreement;
pub mod map_server;
pub mod mapping;
pub mod navigator;
pub mod obstacle_layer;
pub mod planner;
pub mod ros_params;
