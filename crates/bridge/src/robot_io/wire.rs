//! The numbers ROS messages carry, computed once for both transports: time as seconds and
//! nanoseconds, rotations about z as quaternions, odometry covariances, a pinhole camera's
//! matrices, depth pixels as bytes, scan ranges as drivers report them.

use xhab_types::{DepthImage, Intrinsics, OccupancyGrid, Pose2};

/// `t` simulated seconds as whole seconds and nanoseconds (rounded to the nanosecond;
/// negative times are 0).
pub fn split_time(t: f64) -> (i64, u32) {
    let ns = (t.max(0.0) * 1e9).round() as i64;
    (ns / 1_000_000_000, (ns % 1_000_000_000) as u32)
}

/// The seconds of a time given as seconds and nanoseconds.
pub fn join_time(sec: i64, nanosec: i64) -> f64 {
    sec as f64 + nanosec as f64 * 1e-9
}

/// The quaternion (x, y, z, w) of a rotation by `yaw` (rad) about z.
pub fn yaw_quaternion(yaw: f64) -> [f64; 4] {
    let (s, c) = (0.5 * yaw).sin_cos();
    [0.0, 0.0, s, c]
}

/// The yaw (rad, in (-pi, pi]) of a quaternion (x, y, z, w): its rotation about z, roll and
/// pitch ignored.
pub fn quaternion_yaw([x, y, z, w]: [f64; 4]) -> f64 {
    (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z))
}

/// Variances of wheel odometry's pose (x, y: m^2; yaw: rad^2) and velocity ((m/s)^2,
/// (rad/s)^2), as diff-drive drivers report them; the planar base's z, roll and pitch are
/// fixed, so theirs are tiny.
pub const ODOM_POSE_VARIANCE: [f64; 6] = [1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-3];
/// See [`ODOM_POSE_VARIANCE`].
pub const ODOM_TWIST_VARIANCE: [f64; 6] = [1e-3, 1e-6, 1e-6, 1e-6, 1e-6, 1e-3];

/// The row-major 6x6 matrix with `v` on its diagonal.
pub fn diagonal(v: [f64; 6]) -> [f64; 36] {
    let mut c = [0.0; 36];
    for i in 0..6 {
        c[i * 7] = v[i];
    }
    c
}

/// The covariance of a planar pose estimate with standard deviations `xy_std` (m) and
/// `yaw_std` (rad), row-major 6x6.
pub fn planar_covariance(xy_std: f64, yaw_std: f64) -> [f64; 36] {
    let mut cov = [0.0; 36];
    cov[0] = xy_std * xy_std;
    cov[7] = xy_std * xy_std;
    cov[35] = yaw_std * yaw_std;
    cov
}

/// A pinhole camera's matrices without distortion, row-major: K (3x3), R (identity) and
/// P (3x4), in pixels.
pub fn camera_matrices(k: &Intrinsics) -> ([f64; 9], [f64; 9], [f64; 12]) {
    (
        [k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
        [k.fx, 0.0, k.cx, 0.0, 0.0, k.fy, k.cy, 0.0, 0.0, 0.0, 1.0, 0.0],
    )
}

/// A depth image as 32FC1 bytes (metres, little-endian, row by row); where nothing is hit
/// within range (0 in xhab's images) the pixel is NaN, as REP-118 asks.
pub fn depth_bytes(d: &DepthImage) -> Vec<u8> {
    let mut data = Vec::with_capacity(d.data.len() * 4);
    for v in &d.data {
        let v = if *v > 0.0 { *v } else { f32::NAN };
        data.extend_from_slice(&v.to_le_bytes());
    }
    data
}

/// Scan ranges as drivers publish them: NaN (no return) becomes +inf.
pub fn wire_ranges(ranges: &[f32]) -> Vec<f32> {
    ranges.iter().map(|&r| if r.is_nan() { f32::INFINITY } else { r }).collect()
}

/// Scan ranges as xhab reads them: those outside [lo, hi] (m) become NaN.
pub fn ranges_from_wire(ranges: &[f32], lo: f32, hi: f32) -> Vec<f32> {
    ranges.iter().map(|&r| if r >= lo && r <= hi { r } else { f32::NAN }).collect()
}

/// A received map as xhab's grid: `width` x `height` cells of `resolution` (m) from `origin`
/// (position x, y, z and quaternion x, y, z, w); an error when the data length does not match,
/// the resolution is out of map_server's range or the origin is not finite.
pub fn checked_grid(width: u32, height: u32, resolution: f32, origin: [f64; 7], data: &[i8]) -> Result<OccupancyGrid, String> {
    let (w, h) = (width as usize, height as usize);
    if data.len() != w * h {
        return Err(format!("map: {} cells of data for {w} x {h}", data.len()));
    }
    use xhab_nav::map_server::{MAX_RESOLUTION, MIN_RESOLUTION};
    if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&(resolution as f64)) {
        return Err(format!("map: resolution {resolution} is not between {MIN_RESOLUTION} and {MAX_RESOLUTION} m per cell"));
    }
    if !origin.iter().all(|v| v.is_finite()) {
        return Err("map: origin is not finite".into());
    }
    let yaw = quaternion_yaw([origin[3], origin[4], origin[5], origin[6]]);
    Ok(OccupancyGrid { width: w, height: h, resolution: resolution as f64, origin: Pose2::new(origin[0], origin[1], yaw), data: data.to_vec() })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn time_splits_into_seconds_and_nanoseconds() {
        assert_eq!(split_time(0.0), (0, 0));
        assert_eq!(split_time(1.5), (1, 500_000_000));
        assert_eq!(split_time(-3.0), (0, 0));
        assert_eq!(split_time(2.000_000_000_4), (2, 0));
        assert!((join_time(3, 250_000_000) - 3.25).abs() < 1e-12);
    }

    #[test]
    fn yaw_round_trips_through_the_quaternion() {
        for yaw in [-3.0, -1.0, 0.0, 0.5, 3.1] {
            assert!((quaternion_yaw(yaw_quaternion(yaw)) - yaw).abs() < 1e-12);
        }
    }

    #[test]
    fn depth_bytes_are_little_endian_with_nan_for_no_return() {
        let d = DepthImage { width: 2, height: 1, data: vec![1.5, 0.0] };
        let b = depth_bytes(&d);
        assert_eq!(&b[..4], &1.5f32.to_le_bytes());
        assert!(f32::from_le_bytes([b[4], b[5], b[6], b[7]]).is_nan());
        assert_eq!(wire_ranges(&[f32::NAN, 2.0]), vec![f32::INFINITY, 2.0]);
        let r = ranges_from_wire(&[f32::INFINITY, 2.0, 0.01], 0.1, 10.0);
        assert!(r[0].is_nan() && r[1] == 2.0 && r[2].is_nan());
    }
}
