//! Sensor data: depth images and planar laser scans (sensor_msgs semantics).

use serde::{Deserialize, Serialize};

/// A depth image: `width * height` depths in metres along the optical axis (z), row-major,
/// row 0 at the top; 0 where nothing was hit within range (as Habitat's depth sensor).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DepthImage {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Depths (m).
    pub data: Vec<f32>,
}

/// Pinhole intrinsics (pixels), optical frame: z forward, x right, y down.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Intrinsics {
    /// Focal length along x (px).
    pub fx: f64,
    /// Focal length along y (px).
    pub fy: f64,
    /// Principal point x (px).
    pub cx: f64,
    /// Principal point y (px).
    pub cy: f64,
}

impl Intrinsics {
    /// Intrinsics of a `width x height` image with horizontal field of view `hfov` (rad) and
    /// square pixels, in ROS's convention (pixel centres at whole coordinates, so the image
    /// centre is at ((width - 1) / 2, (height - 1) / 2)).
    pub fn from_hfov(width: usize, height: usize, hfov: f64) -> Self {
        let fx = width as f64 / 2.0 / (hfov / 2.0).tan();
        Self { fx, fy: fx, cx: (width as f64 - 1.0) / 2.0, cy: (height as f64 - 1.0) / 2.0 }
    }
}

/// A planar laser scan as sensor_msgs/LaserScan: beam i points at
/// `angle_min + i * angle_increment` (rad, CCW, 0 ahead); ranges in metres, NaN where the
/// return is invalid or out of [range_min, range_max].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LaserScan {
    /// Angle of the first beam (rad).
    pub angle_min: f64,
    /// Angle of the last beam (rad).
    pub angle_max: f64,
    /// Angle between beams (rad).
    pub angle_increment: f64,
    /// Shortest valid range (m).
    pub range_min: f64,
    /// Longest valid range (m).
    pub range_max: f64,
    /// Ranges (m).
    pub ranges: Vec<f32>,
}

impl LaserScan {
    /// Angle of beam `i` (rad).
    pub fn angle(&self, i: usize) -> f64 {
        self.angle_min + i as f64 * self.angle_increment
    }

    /// Whether beam `i` is a return: finite and in [range_min, range_max) (a reading at
    /// range_max, like NaN, means nothing was hit, as amcl reads it).
    pub fn is_return(&self, i: usize) -> bool {
        let r = self.ranges[i] as f64;
        r.is_finite() && r >= self.range_min && r < self.range_max
    }

    /// Whether beam `i` saw nothing within range_max: NaN (xhab's sensors, no hit), +inf
    /// (REP 117) or at least range_max. A reading below range_min is neither this nor a return:
    /// it says nothing.
    pub fn is_clear(&self, i: usize) -> bool {
        let r = self.ranges[i] as f64;
        r.is_nan() || r >= self.range_max
    }

    /// How many beams are returns ([`Self::is_return`]).
    pub fn returns(&self) -> usize {
        (0..self.ranges.len()).filter(|&i| self.is_return(i)).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_beam_is_a_return_clear_or_says_nothing() {
        let ranges = vec![1.0, f32::NAN, f32::INFINITY, 3.5, 9.0, 0.05, 0.0, f32::NEG_INFINITY];
        let scan = LaserScan { angle_min: 0.0, angle_max: 0.7, angle_increment: 0.1, range_min: 0.1, range_max: 3.5, ranges };
        let kind = |i| match (scan.is_return(i), scan.is_clear(i)) {
            (true, false) => 'r',
            (false, true) => 'c',
            (false, false) => '-',
            (true, true) => panic!("beam {i} both"),
        };
        assert_eq!((0..8).map(kind).collect::<String>(), "rcccc---");
    }
}
