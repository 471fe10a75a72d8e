//! The robot's state and commands as a simulator node exchanges them.

use xhab_types::{LaserScan, Pose2, Twist};

/// The depth camera's optical frame (z forward, x right, y down).
pub const DEPTH_OPTICAL_FRAME: &str = "camera_depth_optical_frame";
/// The RGB camera's optical frame (at the same place as the depth camera's).
pub const RGB_OPTICAL_FRAME: &str = "camera_rgb_optical_frame";
/// The rotation from `camera_link` (x forward, z up) to an optical frame (z forward, x right,
/// y down), as a quaternion (x, y, z, w).
pub const OPTICAL_ROTATION: [f64; 4] = [-0.5, 0.5, -0.5, 0.5];

/// A command from the agent side.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// A velocity (geometry_msgs/Twist on `cmd_vel`).
    Twist(Twist),
    /// A discrete action (std_msgs/Int16 on `action`): Habitat's 0..=3.
    Action(i16),
}

/// The robot's sensor mounts, as static transforms from `base_link`.
#[derive(Debug, Clone)]
pub struct Mounts {
    /// The laser's frame id (`base_scan` on a TurtleBot3).
    pub laser_frame: String,
    /// Where the laser sits on the base (m, rad).
    pub laser: Pose2,
    /// The scan plane's height above the floor (m).
    pub laser_z: f64,
    /// The camera's height above the floor (m).
    pub camera_z: f64,
}

impl Default for Mounts {
    fn default() -> Self {
        Self { laser_frame: "laser".into(), laser: Pose2::default(), laser_z: 0.2, camera_z: 0.5 }
    }
}

/// One instant of the simulated robot, as the node publishes it.
#[derive(Debug, Clone, Copy)]
pub struct RobotState<'a> {
    /// ROS time (s) of the instant: the stamp of every message about it.
    pub stamp: f64,
    /// Ground-truth pose of the base in the world (= map) frame.
    pub truth: Pose2,
    /// Height of the floor the robot stands on (m).
    pub floor_z: f64,
    /// Odometry pose of the base in the odom frame.
    pub odom: Pose2,
    /// Base velocity.
    pub twist: Twist,
    /// A scan taken now, if any, with the period between scans (s).
    pub scan: Option<(&'a LaserScan, f64)>,
    /// map -> odom from ground truth, published on `/tf` when the simulator stands in for a
    /// localiser (`--map-odom ground-truth`, as ROS's fake_localization).
    pub map_to_odom: Option<Pose2>,
}
