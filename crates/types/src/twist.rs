//! Planar velocity command, as geometry_msgs/Twist restricted to a ground robot.

use serde::{Deserialize, Serialize};

/// A velocity in the robot's base frame: `linear` along +x (m/s), `angular` about +z (rad/s).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Twist {
    /// Forward speed (m/s).
    pub linear: f64,
    /// Turn rate (rad/s, counter-clockwise positive).
    pub angular: f64,
}
