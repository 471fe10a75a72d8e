//! Plain data shared by `xhab-sim` and `xhab-nav`: points, poses, velocities and grids.
//!
//! Everything here is IO-free and follows ROS REP-103: metres, seconds, radians,
//! x forward, y left, z up, yaw counter-clockwise from +x.
#![warn(missing_docs)]

pub mod distance_field;
mod gaussian;
mod geometry;
mod grid;
mod sensor;
mod twist;

pub use gaussian::gaussian;
pub use geometry::{normalize_angle, Point2, Point3, Pose2};
pub use grid::{axis_cell, OccupancyGrid, GRID_FREE, GRID_OCCUPIED, GRID_UNKNOWN};
pub use sensor::{DepthImage, Intrinsics, LaserScan};
pub use twist::Twist;
