//! Points and planar poses in the world frame (REP-103, metres and radians).

use serde::{Deserialize, Serialize};

/// A point in the plane (m).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Point2 {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
}

impl Point2 {
    /// A point from its coordinates (m).
    pub const fn new(x: f64, y: f64) -> Self {
        Self { x, y }
    }
    /// Euclidean distance to `o` (m).
    pub fn dist(self, o: Point2) -> f64 {
        (self.x - o.x).hypot(self.y - o.y)
    }
}

/// A point in space (m), world frame: x forward, y left, z up.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Point3 {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// z, up (m).
    pub z: f64,
}

impl Point3 {
    /// A point from its coordinates (m).
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }
    /// The planar part (x, y).
    pub fn xy(self) -> Point2 {
        Point2::new(self.x, self.y)
    }
    /// Converts a point from Habitat/glTF's y-up frame `(x, y, z)` to ours `(x, -z, y)`.
    pub fn from_habitat(p: [f64; 3]) -> Self {
        Self::new(p[0], -p[2], p[1])
    }
    /// Converts a point of ours to Habitat/glTF's y-up frame: `(x, y, z) -> (x, z, -y)`.
    pub fn to_habitat(self) -> [f64; 3] {
        [self.x, self.z, -self.y]
    }
}

/// A planar pose: position (m) and heading `yaw` (rad, counter-clockwise from +x).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Pose2 {
    /// x (m).
    pub x: f64,
    /// y (m).
    pub y: f64,
    /// Heading (rad, CCW from +x, in (-pi, pi]).
    pub yaw: f64,
}

impl Pose2 {
    /// A pose from position (m) and yaw (rad).
    pub const fn new(x: f64, y: f64, yaw: f64) -> Self {
        Self { x, y, yaw }
    }
    /// The position part.
    pub fn position(self) -> Point2 {
        Point2::new(self.x, self.y)
    }
    /// `self * other`: `other` expressed in `self`'s frame, brought to the parent frame.
    pub fn compose(self, o: Pose2) -> Pose2 {
        let (s, c) = self.yaw.sin_cos();
        Pose2::new(
            self.x + c * o.x - s * o.y,
            self.y + s * o.x + c * o.y,
            normalize_angle(self.yaw + o.yaw),
        )
    }
    /// The inverse transform.
    pub fn inverse(self) -> Pose2 {
        let (s, c) = self.yaw.sin_cos();
        Pose2::new(-c * self.x - s * self.y, s * self.x - c * self.y, normalize_angle(-self.yaw))
    }
}

/// Wraps an angle into (-pi, pi] (rad).
pub fn normalize_angle(a: f64) -> f64 {
    use std::f64::consts::TAU;
    // Within one turn of zero `rem_euclid` is exact without its division: the same value.
    let mut r = if (0.0..TAU).contains(&a) {
        a
    } else if a < 0.0 && a > -TAU {
        a + TAU
    } else {
        a.rem_euclid(TAU)
    };
    if r > std::f64::consts::PI {
        r -= std::f64::consts::TAU;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn habitat_round_trip() {
        let p = Point3::from_habitat([1.0, 2.0, 3.0]);
        assert_eq!(p, Point3::new(1.0, -3.0, 2.0));
        assert_eq!(p.to_habitat(), [1.0, 2.0, 3.0]);
    }

    #[test]
    fn compose_inverse_is_identity() {
        let a = Pose2::new(1.0, -2.0, 0.7);
        let i = a.compose(a.inverse());
        assert!(i.x.abs() < 1e-12 && i.y.abs() < 1e-12 && i.yaw.abs() < 1e-12);
    }

    #[test]
    fn the_fast_wrap_equals_rem_euclid() {
        let slow = |a: f64| {
            let mut r = a.rem_euclid(std::f64::consts::TAU);
            if r > std::f64::consts::PI {
                r -= std::f64::consts::TAU;
            }
            r
        };
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        for k in 0..200_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let a = (x >> 11) as f64 / (1u64 << 53) as f64 * 30.0 - 15.0;
            let a = if k % 7 == 0 { a * 1e-12 } else { a };
            assert_eq!(normalize_angle(a).to_bits(), slow(a).to_bits(), "{a}");
        }
        for a in [0.0, -0.0, std::f64::consts::TAU, -std::f64::consts::TAU, std::f64::consts::PI, -std::f64::consts::PI, 1e300, -1e-320] {
            assert_eq!(normalize_angle(a).to_bits(), slow(a).to_bits(), "{a}");
        }
        assert!(normalize_angle(f64::NAN).is_nan());
    }

    #[test]
    fn angles_wrap_into_half_open_interval() {
        use std::f64::consts::PI;
        for (a, e) in [(3.0 * PI, PI), (-PI, PI), (0.5, 0.5), (-0.5, -0.5), (2.0 * PI, 0.0)] {
            assert!((normalize_angle(a) - e).abs() < 1e-12, "{a} -> {}", normalize_angle(a));
        }
    }
}
