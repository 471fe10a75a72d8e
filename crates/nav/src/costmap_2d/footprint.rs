//! The robot's footprint in its base frame: a circle of `robot_radius` or a polygon
//! (`footprint`), padded by `footprint_padding`, with its inscribed and circumscribed radii.
//!
//! The ROS `footprint` parameter is accepted both as a YAML list `[[x, y], ...]` and as the
//! string form `"[[x, y], ...]"` that dynamic_reconfigure uses.

use serde::{Deserialize, Serialize};
use xhab_types::{Point2, Pose2};

/// The `footprint` parameter: polygon vertices in the base frame (m, x forward, y left);
/// empty means "round, use `robot_radius`".
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(try_from = "FootprintRepr", into = "Vec<[f64; 2]>")]
pub struct FootprintSpec(pub Vec<[f64; 2]>);

#[derive(Deserialize)]
#[serde(untagged)]
enum FootprintRepr {
    List(Vec<[f64; 2]>),
    Text(String),
}

impl TryFrom<FootprintRepr> for FootprintSpec {
    type Error = String;
    fn try_from(r: FootprintRepr) -> Result<Self, String> {
        match r {
            FootprintRepr::List(v) => Ok(Self(v)),
            FootprintRepr::Text(s) => serde_yaml::from_str::<Vec<[f64; 2]>>(&s)
                .map(Self)
                .map_err(|_| format!("footprint must be a list of [x, y] points, got {s:?}")),
        }
    }
}

impl From<FootprintSpec> for Vec<[f64; 2]> {
    fn from(s: FootprintSpec) -> Self {
        s.0
    }
}

/// A footprint ready for collision checks, in the base frame (m).
#[derive(Debug, Clone, PartialEq)]
pub struct Footprint {
    /// Polygon vertices (padded); empty for a circle.
    polygon: Vec<Point2>,
    /// Radius of a round footprint (padded) (m); 0 for a polygon.
    radius: f64,
    inscribed: f64,
    circumscribed: f64,
}

impl Footprint {
    /// A round footprint of `radius` (m).
    pub fn circle(radius: f64) -> Self {
        Self {
            polygon: Vec::new(),
            radius,
            inscribed: radius,
            circumscribed: radius,
        }
    }

    /// A polygonal footprint, each vertex pushed `padding` (m) away from the axes as ROS's
    /// `padFootprint`; fewer than 3 vertices give a circle of radius `padding`.
    pub fn polygon(vertices: &[[f64; 2]], padding: f64) -> Self {
        if vertices.len() < 3 {
            return Self::circle(padding.max(0.0));
        }
        let sign = |v: f64| {
            if v > 0.0 {
                1.0
            } else if v < 0.0 {
                -1.0
            } else {
                0.0
            }
        };
        let polygon: Vec<Point2> = vertices
            .iter()
            .map(|v| Point2::new(v[0] + sign(v[0]) * padding, v[1] + sign(v[1]) * padding))
            .collect();
        let n = polygon.len();
        let inscribed = (0..n)
            .map(|i| point_segment_distance(Point2::default(), polygon[i], polygon[(i + 1) % n]))
            .fold(f64::INFINITY, f64::min);
        let circumscribed = polygon.iter().map(|p| p.x.hypot(p.y)).fold(0.0, f64::max);
        Self {
            polygon,
            radius: 0.0,
            inscribed,
            circumscribed,
        }
    }

    /// The footprint the costmap parameters describe: the polygon when it has at least three
    /// vertices, else a circle of `robot_radius + padding` (m).
    pub fn from_params(robot_radius: f64, spec: &FootprintSpec, padding: f64) -> Self {
        if spec.0.len() >= 3 {
            Self::polygon(&spec.0, padding)
        } else {
            Self::circle(robot_radius + padding)
        }
    }

    /// Whether the footprint is a circle.
    pub fn is_circle(&self) -> bool {
        self.polygon.is_empty()
    }
    /// Radius of a round footprint (m; 0 for a polygon).
    pub fn radius(&self) -> f64 {
        self.radius
    }
    /// Polygon vertices in the base frame (m; empty for a circle).
    pub fn vertices(&self) -> &[Point2] {
        &self.polygon
    }
    /// Distance from the base origin to the nearest point of the outline (m).
    pub fn inscribed_radius(&self) -> f64 {
        self.inscribed
    }
    /// Distance from the base origin to the farthest point of the outline (m).
    pub fn circumscribed_radius(&self) -> f64 {
        self.circumscribed
    }

    /// Whether point `p` of the base frame (m) lies inside the footprint.
    pub fn contains_local(&self, p: Point2) -> bool {
        if self.is_circle() {
            return p.x.hypot(p.y) <= self.radius;
        }
        let n = self.polygon.len();
        let mut inside = false;
        let mut j = n - 1;
        for i in 0..n {
            let (a, b) = (self.polygon[i], self.polygon[j]);
            if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
                inside = !inside;
            }
            j = i;
        }
        inside
    }

    /// The outline placed at `pose` (world frame, m): the polygon, or 16 points on the circle
    /// (as ROS's `makeFootprintFromRadius`).
    pub fn outline_at(&self, pose: Pose2) -> Vec<Point2> {
        let local: Vec<Point2> = if self.is_circle() {
            (0..16)
                .map(|i| {
                    let a = i as f64 * std::f64::consts::TAU / 16.0;
                    Point2::new(self.radius * a.cos(), self.radius * a.sin())
                })
                .collect()
        } else {
            self.polygon.clone()
        };
        local
            .into_iter()
            .map(|p| pose.compose(Pose2::new(p.x, p.y, 0.0)).position())
            .collect()
    }
}

/// Distance (m) from point `p` to segment `ab`.
pub fn point_segment_distance(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let l2 = dx * dx + dy * dy;
    let t = if l2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a.x + t * dx - p.x).hypot(a.y + t * dy - p.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_of_a_rectangle_and_a_circle() {
        let r = Footprint::polygon(
            &[[-0.2, -0.15], [0.2, -0.15], [0.2, 0.15], [-0.2, 0.15]],
            0.0,
        );
        assert!((r.inscribed_radius() - 0.15).abs() < 1e-12);
        assert!((r.circumscribed_radius() - 0.25).abs() < 1e-12);
        assert!(
            r.contains_local(Point2::new(0.19, 0.14)) && !r.contains_local(Point2::new(0.21, 0.0))
        );
        let padded = Footprint::polygon(
            &[[-0.2, -0.15], [0.2, -0.15], [0.2, 0.15], [-0.2, 0.15]],
            0.01,
        );
        assert!((padded.inscribed_radius() - 0.16).abs() < 1e-12);
        let c = Footprint::from_params(0.46, &FootprintSpec::default(), 0.01);
        assert!(c.is_circle() && (c.inscribed_radius() - 0.47).abs() < 1e-12);
    }

    #[test]
    fn footprint_parses_from_a_list_or_a_string() {
        let a: FootprintSpec =
            serde_yaml::from_str("[[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]").unwrap();
        let b: FootprintSpec =
            serde_yaml::from_str("\"[[0.1, 0.1], [-0.1, 0.1], [-0.1, -0.1]]\"").unwrap();
        assert_eq!(a, b);
        assert_eq!(a.0.len(), 3);
        assert!(serde_yaml::from_str::<FootprintSpec>("\"[[0.1], x]\"").is_err());
    }
}
