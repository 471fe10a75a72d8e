//! Conversions between xhab's types and ROS 1 messages (REP-103 frames, REP-105 names).

use super::msgs::{geometry_msgs as gm, nav_msgs, sensor_msgs, std_msgs};
use crate::robot_io::wire;
use roslibrust::codegen::integral_types::Time;
use xhab_types::{DepthImage, Intrinsics, LaserScan, OccupancyGrid, Pose2, Twist};

/// ROS time of `t` simulated seconds (rounded to the nanosecond).
pub fn time(t: f64) -> Time {
    let (secs, nsecs) = wire::split_time(t);
    Time { secs: secs as i32, nsecs: nsecs as i32 }
}

/// A header with stamp `t` (s) and frame `frame`; `seq` is left 0 (publishers number their
/// messages; nothing in xhab reads it).
pub fn header(t: f64, frame: &str) -> std_msgs::Header {
    std_msgs::Header { seq: 0, stamp: time(t), frame_id: frame.to_string() }
}

/// The seconds of a ROS time.
pub fn seconds(t: &Time) -> f64 {
    wire::join_time(t.secs as i64, t.nsecs as i64)
}

/// The quaternion of a rotation by `yaw` (rad) about z.
pub fn yaw_to_quaternion(yaw: f64) -> gm::Quaternion {
    let [x, y, z, w] = wire::yaw_quaternion(yaw);
    gm::Quaternion { x, y, z, w }
}

/// The yaw (rad, in (-pi, pi]) of a quaternion (its rotation about z; roll and pitch ignored).
pub fn quaternion_to_yaw(q: &gm::Quaternion) -> f64 {
    wire::quaternion_yaw([q.x, q.y, q.z, q.w])
}

/// A pose at height `z` (m).
pub fn pose(p: Pose2, z: f64) -> gm::Pose {
    gm::Pose { position: gm::Point { x: p.x, y: p.y, z }, orientation: yaw_to_quaternion(p.yaw) }
}

/// The planar pose of a ROS pose.
pub fn pose2(p: &gm::Pose) -> Pose2 {
    Pose2::new(p.position.x, p.position.y, quaternion_to_yaw(&p.orientation))
}

/// A transform for a planar pose at height `z`.
pub fn transform(p: Pose2, z: f64) -> gm::Transform {
    gm::Transform { translation: gm::Vector3 { x: p.x, y: p.y, z }, rotation: yaw_to_quaternion(p.yaw) }
}

/// The planar pose of a transform (its translation's x, y and its yaw).
pub fn pose2_of_transform(t: &gm::Transform) -> Pose2 {
    Pose2::new(t.translation.x, t.translation.y, quaternion_to_yaw(&t.rotation))
}

/// A stamped transform `parent -> child`.
pub fn tf(t: f64, parent: &str, child: &str, tr: gm::Transform) -> gm::TransformStamped {
    gm::TransformStamped { header: header(t, parent), child_frame_id: child.to_string(), transform: tr }
}

/// A base-frame velocity as a ROS Twist.
pub fn twist(t: Twist) -> gm::Twist {
    gm::Twist { linear: gm::Vector3 { x: t.linear, y: 0.0, z: 0.0 }, angular: gm::Vector3 { x: 0.0, y: 0.0, z: t.angular } }
}

/// The planar part of a ROS Twist (linear.x, angular.z).
pub fn twist2(t: &gm::Twist) -> Twist {
    Twist { linear: t.linear.x, angular: t.angular.z }
}

/// sensor_msgs/LaserScan of a scan taken at `t` (s) in `frame`; NaN ranges become +inf
/// (no return), as drivers report them; `scan_time` is the period between scans (s).
pub fn laser_scan(t: f64, frame: &str, s: &LaserScan, scan_time: f64) -> sensor_msgs::LaserScan {
    sensor_msgs::LaserScan {
        header: header(t, frame),
        angle_min: s.angle_min as f32,
        angle_max: s.angle_max as f32,
        angle_increment: s.angle_increment as f32,
        time_increment: 0.0,
        scan_time: scan_time as f32,
        range_min: s.range_min as f32,
        range_max: s.range_max as f32,
        ranges: wire::wire_ranges(&s.ranges),
        intensities: Vec::new(),
    }
}

/// Our scan of a sensor_msgs/LaserScan: ranges outside [range_min, range_max] become NaN.
pub fn scan_from_msg(m: &sensor_msgs::LaserScan) -> LaserScan {
    let (lo, hi) = (m.range_min, m.range_max);
    LaserScan {
        angle_min: m.angle_min as f64,
        angle_max: m.angle_max as f64,
        angle_increment: m.angle_increment as f64,
        range_min: lo as f64,
        range_max: hi as f64,
        ranges: wire::ranges_from_wire(&m.ranges, lo, hi),
    }
}

pub use wire::{ODOM_POSE_VARIANCE, ODOM_TWIST_VARIANCE};
use wire::diagonal;

/// nav_msgs/Odometry: the `odom` pose of `base_link` and its velocity in `base_link`, with
/// diagonal covariances.
pub fn odometry(t: f64, p: Pose2, v: Twist) -> nav_msgs::Odometry {
    nav_msgs::Odometry {
        header: header(t, "odom"),
        child_frame_id: "base_link".into(),
        pose: gm::PoseWithCovariance { pose: pose(p, 0.0), covariance: diagonal(ODOM_POSE_VARIANCE) },
        twist: gm::TwistWithCovariance { twist: twist(v), covariance: diagonal(ODOM_TWIST_VARIANCE) },
    }
}

/// nav_msgs/OccupancyGrid of a map (frame `map`); the resolution travels as f32, as in ROS.
pub fn occupancy_grid(t: f64, g: &OccupancyGrid) -> nav_msgs::OccupancyGrid {
    nav_msgs::OccupancyGrid {
        header: header(t, "map"),
        info: nav_msgs::MapMetaData {
            map_load_time: time(t),
            resolution: g.resolution as f32,
            width: g.width as u32,
            height: g.height as u32,
            origin: pose(g.origin, 0.0),
        },
        data: g.data.clone(),
    }
}

/// Our map of a nav_msgs/OccupancyGrid; an error when the data length does not match.
pub fn grid_from_msg(m: &nav_msgs::OccupancyGrid) -> Result<OccupancyGrid, String> {
    let o = &m.info.origin;
    wire::checked_grid(m.info.width, m.info.height, m.info.resolution, [o.position.x, o.position.y, o.position.z, o.orientation.x, o.orientation.y, o.orientation.z, o.orientation.w], &m.data)
}

/// A 32FC1 depth image (metres, little-endian) in `frame`; where nothing is hit within range
/// (0 in xhab's images) it holds NaN, as REP-118 asks.
pub fn depth_image(t: f64, frame: &str, d: &DepthImage) -> sensor_msgs::Image {
    sensor_msgs::Image { header: header(t, frame), height: d.height as u32, width: d.width as u32, encoding: "32FC1".into(), is_bigendian: 0, step: 4 * d.width as u32, data: wire::depth_bytes(d) }
}

/// An rgb8 image in `frame`.
pub fn rgb_image(t: f64, frame: &str, width: usize, height: usize, rgb: Vec<u8>) -> sensor_msgs::Image {
    sensor_msgs::Image { header: header(t, frame), height: height as u32, width: width as u32, encoding: "rgb8".into(), is_bigendian: 0, step: 3 * width as u32, data: rgb }
}

/// sensor_msgs/CameraInfo of a pinhole camera without distortion (plumb_bob, zeros).
pub fn camera_info(t: f64, frame: &str, width: usize, height: usize, k: &Intrinsics) -> sensor_msgs::CameraInfo {
    let (kk, r, p) = wire::camera_matrices(k);
    sensor_msgs::CameraInfo {
        header: header(t, frame),
        height: height as u32,
        width: width as u32,
        distortion_model: "plumb_bob".into(),
        D: vec![0.0; 5],
        K: kk,
        R: r,
        P: p,
        ..Default::default()
    }
}

/// A pose with covariance: standard deviations `xy_std` (m) and `yaw_std` (rad).
pub fn pose_with_covariance(t: f64, p: Pose2, xy_std: f64, yaw_std: f64) -> gm::PoseWithCovarianceStamped {
    gm::PoseWithCovarianceStamped { header: header(t, "map"), pose: gm::PoseWithCovariance { pose: pose(p, 0.0), covariance: wire::planar_covariance(xy_std, yaw_std) } }
}
