//! ROS 2 message types as serde structs, field for field in the order of their `.msg`
//! definitions (ROS 2 Kilted), so that RustDDS's CDR encoding is the wire format rclpy and
//! rclcpp read. Fixed-size arrays are CDR arrays (no length), `Vec`s are sequences (a u32
//! length, then the elements), byte sequences go through [`bytes`] to be copied whole.
//!
//! Each type has its ROS 2 type name ([`RosType::PACKAGE`], [`RosType::NAME`]).

use serde::{Deserialize, Serialize};

/// A ROS 2 message type: its package and name (`sensor_msgs`, `LaserScan`).
pub trait RosType: Serialize + for<'de> Deserialize<'de> + Send + 'static {
    /// The package, e.g. `sensor_msgs`.
    const PACKAGE: &'static str;
    /// The message's name in its package, e.g. `LaserScan`.
    const NAME: &'static str;
}

macro_rules! ros_type {
    ($pkg:literal, $($t:ident),+) => {$(
        impl RosType for $t {
            const PACKAGE: &'static str = $pkg;
            const NAME: &'static str = stringify!($t);
        }
    )+};
}

/// `uint8[]` as one byte string (CDR: a u32 length, then the bytes), not byte by byte.
pub mod bytes {
    use serde::{Deserializer, Serializer};

    /// Serializes `v` as a byte sequence.
    pub fn serialize<S: Serializer>(v: &[u8], s: S) -> Result<S::Ok, S::Error> {
        s.serialize_bytes(v)
    }

    struct V;
    impl<'de> serde::de::Visitor<'de> for V {
        type Value = Vec<u8>;
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("a byte sequence")
        }
        fn visit_bytes<E: serde::de::Error>(self, v: &[u8]) -> Result<Vec<u8>, E> {
            Ok(v.to_vec())
        }
        fn visit_byte_buf<E: serde::de::Error>(self, v: Vec<u8>) -> Result<Vec<u8>, E> {
            Ok(v)
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<Vec<u8>, A::Error> {
            let mut out = Vec::with_capacity(a.size_hint().unwrap_or(0).min(1 << 20));
            while let Some(b) = a.next_element()? {
                out.push(b);
            }
            Ok(out)
        }
    }

    /// Deserializes a byte sequence.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u8>, D::Error> {
        d.deserialize_byte_buf(V)
    }
}

/// `float64[N]` for N above serde's 32 (covariances: 36), as a CDR array (no length).
pub mod array {
    use serde::ser::SerializeTuple;
    use serde::{Deserializer, Serializer};

    /// Serializes the array as a tuple (CDR: the elements alone).
    pub fn serialize<S: Serializer, const N: usize>(v: &[f64; N], s: S) -> Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple(N)?;
        for x in v {
            t.serialize_element(x)?;
        }
        t.end()
    }

    struct V<const N: usize>;
    impl<'de, const N: usize> serde::de::Visitor<'de> for V<N> {
        type Value = [f64; N];
        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "{N} float64 values")
        }
        fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut a: A) -> Result<[f64; N], A::Error> {
            let mut out = [0.0; N];
            for (i, o) in out.iter_mut().enumerate() {
                *o = a.next_element()?.ok_or_else(|| serde::de::Error::invalid_length(i, &self))?;
            }
            Ok(out)
        }
    }

    /// Deserializes the array from a tuple.
    pub fn deserialize<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<[f64; N], D::Error> {
        d.deserialize_tuple(N, V::<N>)
    }
}

/// builtin_interfaces: time.
pub mod builtin_interfaces {
    use super::*;

    /// builtin_interfaces/Time: seconds and nanoseconds (in [0, 1e9)) since the clock's epoch.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct Time {
        /// Whole seconds (s).
        pub sec: i32,
        /// Nanoseconds past `sec` (ns, < 1e9).
        pub nanosec: u32,
    }
    /// builtin_interfaces/Duration: a span of seconds and nanoseconds (in [0, 1e9)).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct Duration {
        /// Whole seconds (s).
        pub sec: i32,
        /// Nanoseconds past `sec` (ns, < 1e9).
        pub nanosec: u32,
    }
    ros_type!("builtin_interfaces", Time, Duration);
}

/// std_msgs: the header and the plain values xhab uses.
pub mod std_msgs {
    use super::*;

    /// std_msgs/Header (ROS 2: no `seq`).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct Header {
        /// When the data was taken.
        pub stamp: builtin_interfaces::Time,
        /// The frame the data is in.
        pub frame_id: String,
    }

    /// std_msgs/Int16.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct Int16 {
        /// The value.
        pub data: i16,
    }
    ros_type!("std_msgs", Header, Int16);
}

/// rosgraph_msgs: the clock.
pub mod rosgraph_msgs {
    use super::*;

    /// rosgraph_msgs/Clock: the simulated time, on `/clock`.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct Clock {
        /// The current time.
        pub clock: builtin_interfaces::Time,
    }
    ros_type!("rosgraph_msgs", Clock);
}

/// geometry_msgs: points, poses, transforms, velocities.
pub mod geometry_msgs {
    use super::*;

    /// geometry_msgs/Vector3 (m, m/s or rad/s as the field says).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
    pub struct Vector3 {
        /// x.
        pub x: f64,
        /// y.
        pub y: f64,
        /// z.
        pub z: f64,
    }

    /// geometry_msgs/Point (m).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
    pub struct Point {
        /// x (m).
        pub x: f64,
        /// y (m).
        pub y: f64,
        /// z (m).
        pub z: f64,
    }

    /// geometry_msgs/Quaternion (x, y, z, w; unit length for a rotation).
    #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
    pub struct Quaternion {
        /// x.
        pub x: f64,
        /// y.
        pub y: f64,
        /// z.
        pub z: f64,
        /// w.
        pub w: f64,
    }

    impl Default for Quaternion {
        fn default() -> Self {
            Quaternion { x: 0.0, y: 0.0, z: 0.0, w: 1.0 }
        }
    }

    /// geometry_msgs/Pose.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
    pub struct Pose {
        /// Position (m).
        pub position: Point,
        /// Orientation.
        pub orientation: Quaternion,
    }

    /// geometry_msgs/PoseStamped (`goal_pose`, ground truth).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct PoseStamped {
        /// Stamp and frame.
        pub header: std_msgs::Header,
        /// The pose in the header's frame.
        pub pose: Pose,
    }

    /// geometry_msgs/PoseWithCovariance: row-major 6x6 covariance over (x, y, z, roll,
    /// pitch, yaw).
    #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
    pub struct PoseWithCovariance {
        /// The pose.
        pub pose: Pose,
        /// Covariance (m^2, rad^2, row-major 6x6).
        #[serde(with = "array")]
        pub covariance: [f64; 36],
    }

    impl Default for PoseWithCovariance {
        fn default() -> Self {
            PoseWithCovariance { pose: Pose::default(), covariance: [0.0; 36] }
        }
    }

    /// geometry_msgs/PoseWithCovarianceStamped (`initialpose`, `amcl_pose`).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct PoseWithCovarianceStamped {
        /// Stamp and frame.
        pub header: std_msgs::Header,
        /// The pose with its covariance.
        pub pose: PoseWithCovariance,
    }

    /// geometry_msgs/Twist: linear (m/s) and angular (rad/s) velocity.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
    pub struct Twist {
        /// Linear velocity (m/s).
        pub linear: Vector3,
        /// Angular velocity (rad/s).
        pub angular: Vector3,
    }

    /// geometry_msgs/TwistWithCovariance.
    #[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
    pub struct TwistWithCovariance {
        /// The velocity.
        pub twist: Twist,
        /// Covariance ((m/s)^2, (rad/s)^2, row-major 6x6).
        #[serde(with = "array")]
        pub covariance: [f64; 36],
    }

    impl Default for TwistWithCovariance {
        fn default() -> Self {
            TwistWithCovariance { twist: Twist::default(), covariance: [0.0; 36] }
        }
    }

    /// geometry_msgs/Transform.
    #[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
    pub struct Transform {
        /// Translation (m).
        pub translation: Vector3,
        /// Rotation.
        pub rotation: Quaternion,
    }

    /// geometry_msgs/TransformStamped: `header.frame_id` -> `child_frame_id`.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct TransformStamped {
        /// Stamp and parent frame.
        pub header: std_msgs::Header,
        /// The child frame.
        pub child_frame_id: String,
        /// The child's pose in the parent frame.
        pub transform: Transform,
    }
    ros_type!("geometry_msgs", Vector3, Point, Quaternion, Pose, PoseStamped, PoseWithCovariance, PoseWithCovarianceStamped, Twist, TwistWithCovariance, Transform, TransformStamped);
}

/// sensor_msgs: scans, images, camera calibration.
pub mod sensor_msgs {
    use super::*;

    /// sensor_msgs/LaserScan (angles in rad, counter-clockwise; ranges in m).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct LaserScan {
        /// Stamp (of the first ray) and the laser's frame.
        pub header: std_msgs::Header,
        /// Angle of the first ray (rad).
        pub angle_min: f32,
        /// Angle of the last ray (rad).
        pub angle_max: f32,
        /// Angle between rays (rad).
        pub angle_increment: f32,
        /// Time between rays (s).
        pub time_increment: f32,
        /// Time between scans (s).
        pub scan_time: f32,
        /// Smallest valid range (m).
        pub range_min: f32,
        /// Largest valid range (m).
        pub range_max: f32,
        /// Ranges (m); out of [range_min, range_max] means no valid return.
        pub ranges: Vec<f32>,
        /// Intensities (device units; may be empty).
        pub intensities: Vec<f32>,
    }

    /// sensor_msgs/Image.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct Image {
        /// Stamp and optical frame.
        pub header: std_msgs::Header,
        /// Rows (pixels).
        pub height: u32,
        /// Columns (pixels).
        pub width: u32,
        /// Pixel encoding (`rgb8`, `32FC1`, ...).
        pub encoding: String,
        /// 1 if the data is big-endian.
        pub is_bigendian: u8,
        /// Bytes per row.
        pub step: u32,
        /// The pixels, row by row.
        #[serde(with = "bytes")]
        pub data: Vec<u8>,
    }

    /// sensor_msgs/RegionOfInterest (pixels).
    #[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
    pub struct RegionOfInterest {
        /// Leftmost pixel.
        pub x_offset: u32,
        /// Topmost pixel.
        pub y_offset: u32,
        /// Rows.
        pub height: u32,
        /// Columns.
        pub width: u32,
        /// Whether to rectify.
        pub do_rectify: bool,
    }

    /// sensor_msgs/CameraInfo (ROS 2 field names: `d`, `k`, `r`, `p`).
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct CameraInfo {
        /// Stamp and optical frame.
        pub header: std_msgs::Header,
        /// Rows (pixels).
        pub height: u32,
        /// Columns (pixels).
        pub width: u32,
        /// Distortion model (`plumb_bob`).
        pub distortion_model: String,
        /// Distortion coefficients.
        pub d: Vec<f64>,
        /// Intrinsic matrix (pixels, row-major 3x3).
        pub k: [f64; 9],
        /// Rectification matrix (row-major 3x3).
        pub r: [f64; 9],
        /// Projection matrix (pixels, row-major 3x4).
        pub p: [f64; 12],
        /// Horizontal binning.
        pub binning_x: u32,
        /// Vertical binning.
        pub binning_y: u32,
        /// Region of interest (all zeros: the full image).
        pub roi: RegionOfInterest,
    }
    ros_type!("sensor_msgs", LaserScan, Image, RegionOfInterest, CameraInfo);
}

/// nav_msgs: odometry and maps.
pub mod nav_msgs {
    use super::*;

    /// nav_msgs/Odometry: the pose in `header.frame_id`, the velocity in `child_frame_id`.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct Odometry {
        /// Stamp and the odometry frame.
        pub header: std_msgs::Header,
        /// The base's frame.
        pub child_frame_id: String,
        /// The base's pose.
        pub pose: geometry_msgs::PoseWithCovariance,
        /// The base's velocity.
        pub twist: geometry_msgs::TwistWithCovariance,
    }

    /// nav_msgs/MapMetaData.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct MapMetaData {
        /// When the map was loaded.
        pub map_load_time: builtin_interfaces::Time,
        /// Cell size (m).
        pub resolution: f32,
        /// Columns (cells).
        pub width: u32,
        /// Rows (cells).
        pub height: u32,
        /// Pose of cell (0, 0)'s corner in the map frame.
        pub origin: geometry_msgs::Pose,
    }

    /// nav_msgs/OccupancyGrid: row-major from the origin, -1 unknown, 0 free .. 100 occupied.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct OccupancyGrid {
        /// Stamp and the map frame.
        pub header: std_msgs::Header,
        /// Size, resolution, origin.
        pub info: MapMetaData,
        /// Occupancy per cell.
        pub data: Vec<i8>,
    }
    ros_type!("nav_msgs", Odometry, MapMetaData, OccupancyGrid);
}

// Actions: unique_identifier_msgs, action_msgs, nav2_msgs (NavigateToPose).
mod actions;
pub use actions::{action_msgs, nav2_msgs, unique_identifier_msgs};

/// tf2_msgs: transforms.
pub mod tf2_msgs {
    use super::*;

    /// tf2_msgs/TFMessage, on `/tf` and `/tf_static`.
    #[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
    pub struct TFMessage {
        /// The transforms.
        pub transforms: Vec<geometry_msgs::TransformStamped>,
    }
    ros_type!("tf2_msgs", TFMessage);
}

#[cfg(test)]
mod tests {
    //! Wire-format checks against bytes rclpy (ROS 2 Kilted, Fast CDR) serialized
    //! (`rclpy.serialization.serialize_message`, the 4-byte encapsulation header first). Fast
    //! CDR leaves padding bytes unset, so the checks decode rclpy's bytes into our types and
    //! ours back, and compare lengths, not raw bytes.
    use super::*;
    use byteorder::LittleEndian;
    use ros2_client::dds::rustdds::cdr_encoding;

    fn hex(s: &str) -> Vec<u8> {
        (0..s.len()).step_by(2).map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap()).collect()
    }

    /// Decodes rclpy's bytes as `T`, checks the value, and that ours encode to the same length
    /// and decode to the same value.
    fn check<T: RosType + PartialEq + std::fmt::Debug>(recorded: &str, want: T) {
        let b = hex(recorded);
        assert_eq!(&b[..4], &[0, 1, 0, 0], "CDR little-endian encapsulation");
        let (got, n) = cdr_encoding::from_bytes::<T, LittleEndian>(&b[4..]).unwrap();
        assert_eq!(got, want, "{}", T::NAME);
        assert_eq!(n, b.len() - 4, "{}: all bytes read", T::NAME);
        let ours = cdr_encoding::to_vec::<T, LittleEndian>(&want).unwrap();
        assert_eq!(ours.len(), b.len() - 4, "{}: same length as rclpy's", T::NAME);
        assert_eq!(cdr_encoding::from_bytes::<T, LittleEndian>(&ours).unwrap().0, want);
    }

    fn header(sec: i32, nanosec: u32, frame: &str) -> std_msgs::Header {
        std_msgs::Header { stamp: builtin_interfaces::Time { sec, nanosec }, frame_id: frame.into() }
    }

    #[test]
    fn laser_scan_and_clock_match_rclpy() {
        check(
            "000100000300000080b2e60e0a000000626173655f7363616e00b50d0000c0bf0000c03f0000c03f00000000cdcccc3d8fc2f53d00006040030000000000803f0000807f0000204000000000",
            sensor_msgs::LaserScan {
                header: header(3, 250_000_000, "base_scan"),
                angle_min: -1.5,
                angle_max: 1.5,
                angle_increment: 1.5,
                time_increment: 0.0,
                scan_time: 0.1,
                range_min: 0.12,
                range_max: 3.5,
                ranges: vec![1.0, f32::INFINITY, 2.5],
                intensities: vec![],
            },
        );
        check("000100000700000005000000", rosgraph_msgs::Clock { clock: builtin_interfaces::Time { sec: 7, nanosec: 5 } });
    }

    #[test]
    fn camera_info_and_image_match_rclpy() {
        check(
            "0001000000000000000000000400000063616d0002000000030000000a000000706c756d625f626f620035120500000070e8b91200000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000604000000000000000000000000000e05f40000000000000000000000000000060400000000000e05f4000000000000000000000000000000000000000000000f03f000000000000f03f000000000000000000000000000000000000000000000000000000000000f03f000000000000000000000000000000000000000000000000000000000000f03f000000000000604000000000000000000000000000e05f400000000000000000000000000000000000000000000060400000000000e05f40000000000000000000000000000000000000000000000000000000000000f03f000000000000000000000000000000000000000000000000000000000000000000",
            sensor_msgs::CameraInfo {
                header: header(0, 0, "cam"),
                height: 2,
                width: 3,
                distortion_model: "plumb_bob".into(),
                d: vec![0.0; 5],
                k: [128.0, 0.0, 127.5, 0.0, 128.0, 127.5, 0.0, 0.0, 1.0],
                r: [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                p: [128.0, 0.0, 127.5, 0.0, 0.0, 128.0, 127.5, 0.0, 0.0, 0.0, 1.0, 0.0],
                ..Default::default()
            },
        );
        check(
            "000100000000000000000000040000007267620001000000010000000500000072676238000074720300000003000000010203",
            sensor_msgs::Image { header: header(0, 0, "rgb"), height: 1, width: 1, encoding: "rgb8".into(), is_bigendian: 0, step: 3, data: vec![1, 2, 3] },
        );
    }

    #[test]
    fn odometry_and_occupancy_grid_match_rclpy() {
        let mut pose_cov = [0.0; 36];
        pose_cov[0] = 1e-3;
        let mut twist_cov = [0.0; 36];
        twist_cov[35] = 1e-3;
        let odom = "000100000000000000000000050000006f646f6d004964af0a000000626173655f6c696e6b0064b364488401000000000000f03f0000000000000000000000000000000000000000000000000000000000000000000000000000e03f000000000000e83ffca9f1d24d62503f"
            .to_string()
            + &"0".repeat(2 * 8 * 35)
            + "9a9999999999c93f"
            + &"0".repeat(2 * 8 * 5)
            + &"0".repeat(2 * 8 * 35)
            + "fca9f1d24d62503f";
        check(
            &odom,
            nav_msgs::Odometry {
                header: header(0, 0, "odom"),
                child_frame_id: "base_link".into(),
                pose: geometry_msgs::PoseWithCovariance {
                    pose: geometry_msgs::Pose { position: geometry_msgs::Point { x: 1.0, y: 0.0, z: 0.0 }, orientation: geometry_msgs::Quaternion { x: 0.0, y: 0.0, z: 0.5, w: 0.75 } },
                    covariance: pose_cov,
                },
                twist: geometry_msgs::TwistWithCovariance { twist: geometry_msgs::Twist { linear: geometry_msgs::Vector3 { x: 0.2, y: 0.0, z: 0.0 }, ..Default::default() }, covariance: twist_cov },
            },
        );
        check(
            "000100000000000000000000040000006d6170000000000000000000cdcc4c3d020000000100000000000000000000000000f0bf00000000000000000000000000000000000000000000000000000000000000000000000000000000000000000000f03f02000000ff64",
            nav_msgs::OccupancyGrid {
                header: header(0, 0, "map"),
                info: nav_msgs::MapMetaData {
                    map_load_time: builtin_interfaces::Time::default(),
                    resolution: 0.05,
                    width: 2,
                    height: 1,
                    origin: geometry_msgs::Pose { position: geometry_msgs::Point { x: -1.0, y: 0.0, z: 0.0 }, orientation: geometry_msgs::Quaternion::default() },
                },
                data: vec![-1, 100],
            },
        );
    }
}
