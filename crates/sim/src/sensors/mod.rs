//! Sensors by CPU ray casting (parry3d BVH): the depth camera and a planar lidar.

pub mod camera;
pub mod lidar;
pub mod raycast;

pub use camera::{render_depth, render_rgb, CameraParams};
pub use lidar::{Lidar, LidarParams};
pub use raycast::RayScene;
