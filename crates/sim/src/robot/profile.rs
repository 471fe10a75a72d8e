//! Robot profiles: body size, mass, drive limits and camera mount, as small YAML data files.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A ground robot's body and differential drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotProfile {
    /// Profile name.
    pub name: String,
    /// Body radius (m): the collision cylinder (circumscribed radius for a polygon footprint).
    pub radius: f64,
    /// Body height (m).
    pub height: f64,
    /// Mass (kg).
    pub mass: f64,
    /// Distance between the drive wheels (m).
    pub wheel_base: f64,
    /// Largest forward/backward speed (m/s).
    pub max_linear: f64,
    /// Largest turn rate (rad/s).
    pub max_angular: f64,
    /// Largest linear acceleration (m/s^2).
    pub max_linear_accel: f64,
    /// Largest angular acceleration (rad/s^2).
    pub max_angular_accel: f64,
    /// Camera height above the floor (m).
    pub camera_height: f64,
    /// Footprint polygon in the base frame (m), when not round.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub footprint: Option<Vec<[f64; 2]>>,
    /// The planar laser's mount: its tf frame and where it sits on the base.
    #[serde(default)]
    pub laser: LaserMount,
    /// Highest step the base climbs up or down (m, default 0: none; Habitat's agent and the
    /// LoCoBot profile climb Habitat's 0.2).
    #[serde(default)]
    pub step_height: f64,
}

/// Where the planar laser sits on the base (REP-105: a static base_link -> `frame` transform).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LaserMount {
    /// Its tf frame id (default `laser`).
    pub frame: String,
    /// Offset forward of the base's centre (m, default 0).
    pub x: f64,
    /// Offset to the left of the base's centre (m, default 0).
    pub y: f64,
    /// Height of the scan plane above the floor (m, default 0.2).
    pub z: f64,
}

impl LaserMount {
    /// The simulated lidar (LDS-01 beams and ranges) at this mount.
    pub fn lidar(&self) -> crate::sensors::LidarParams {
        crate::sensors::LidarParams { mount_height: self.z, mount_xy: [self.x, self.y], ..Default::default() }
    }
}

impl Default for LaserMount {
    fn default() -> Self {
        Self { frame: "laser".into(), x: 0.0, y: 0.0, z: 0.2 }
    }
}

/// Why a profile could not be loaded.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ProfileError {
    /// No built-in profile has that name.
    #[error("unknown robot profile '{0}' (built in: habitat, locobot, turtlebot3_burger, turtlebot3_waffle; or a path to a .yaml file)")]
    Unknown(String),
    /// The file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A field is missing or wrong.
    #[error("{path}: {field}: {reason}")]
    Field {
        /// The file (or the built-in name).
        path: PathBuf,
        /// The field.
        field: String,
        /// What is wrong.
        reason: String,
    },
}

const BUILTIN: [(&str, &str); 4] = [
    ("habitat", include_str!("../../profiles/habitat.yaml")),
    ("locobot", include_str!("../../profiles/locobot.yaml")),
    ("turtlebot3_burger", include_str!("../../profiles/turtlebot3_burger.yaml")),
    ("turtlebot3_waffle", include_str!("../../profiles/turtlebot3_waffle.yaml")),
];

impl RobotProfile {
    /// Names of the built-in profiles.
    pub fn builtin_names() -> Vec<&'static str> {
        BUILTIN.iter().map(|b| b.0).collect()
    }

    /// A built-in profile by name.
    pub fn builtin(name: &str) -> Result<RobotProfile, ProfileError> {
        let (_, text) = BUILTIN.iter().find(|b| b.0 == name).ok_or_else(|| ProfileError::Unknown(name.to_string()))?;
        Self::parse(text, Path::new(name))
    }

    /// A built-in name or a path to a profile YAML file.
    pub fn named_or_file(s: &str) -> Result<RobotProfile, ProfileError> {
        if BUILTIN.iter().any(|b| b.0 == s) {
            return Self::builtin(s);
        }
        if s.ends_with(".yaml") || s.ends_with(".yml") {
            return Self::from_file(Path::new(s));
        }
        Err(ProfileError::Unknown(s.to_string()))
    }

    /// Reads a profile from a YAML file.
    pub fn from_file(path: &Path) -> Result<RobotProfile, ProfileError> {
        let bytes = std::fs::read(path).map_err(|source| ProfileError::Io { path: path.to_path_buf(), source })?;
        let text = String::from_utf8(bytes).map_err(|e| ProfileError::Field {
            path: path.to_path_buf(),
            field: "(file)".into(),
            reason: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
        })?;
        Self::parse(&text, path)
    }

    /// Parses a profile's YAML text and checks its ranges; `path` names the file in errors.
    pub fn parse(text: &str, path: &Path) -> Result<RobotProfile, ProfileError> {
        let de = serde_yaml::Deserializer::from_str(text);
        let p: RobotProfile = serde_path_to_error::deserialize(de).map_err(|e| ProfileError::Field {
            path: path.to_path_buf(),
            field: e.path().to_string(),
            reason: e.inner().to_string(),
        })?;
        p.validate().map_err(|(field, reason)| ProfileError::Field { path: path.to_path_buf(), field: field.into(), reason })?;
        Ok(p)
    }

    /// Checks ranges: every size, mass and limit positive and finite; a footprint of at least 3
    /// finite points.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        for (f, v) in [
            ("radius", self.radius),
            ("height", self.height),
            ("mass", self.mass),
            ("wheel_base", self.wheel_base),
            ("max_linear", self.max_linear),
            ("max_angular", self.max_angular),
            ("max_linear_accel", self.max_linear_accel),
            ("max_angular_accel", self.max_angular_accel),
            ("camera_height", self.camera_height),
            ("laser.z", self.laser.z),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err((f, format!("must be a positive number, got {v}")));
            }
        }
        if !(self.step_height.is_finite() && self.step_height >= 0.0 && self.step_height < self.height) {
            return Err(("step_height", format!("must be at least 0 and below the body's height, got {}", self.step_height)));
        }
        if !(self.laser.x.is_finite() && self.laser.y.is_finite()) {
            return Err(("laser", format!("x and y must be finite, got {} and {}", self.laser.x, self.laser.y)));
        }
        if self.laser.frame.is_empty() || self.laser.frame.contains(char::is_whitespace) {
            return Err(("laser.frame", format!("must be a tf frame id, got '{}'", self.laser.frame)));
        }
        if let Some(fp) = &self.footprint {
            if fp.len() < 3 {
                return Err(("footprint", format!("a polygon needs at least 3 points, got {}", fp.len())));
            }
            if let Some(i) = fp.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
                return Err(("footprint", format!("point {i} is not finite: [{}, {}]", fp[i][0], fp[i][1])));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtins_load_and_bad_fields_are_named() {
        for n in RobotProfile::builtin_names() {
            let p = RobotProfile::builtin(n).unwrap();
            assert_eq!(p.name, n);
        }
        let dir = std::env::temp_dir().join(format!("xhab-prof-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("bad.yaml");
        std::fs::write(&f, "name: x\nradius: -1\nheight: 1\nmass: 1\nwheel_base: 0.2\nmax_linear: 1\nmax_angular: 1\nmax_linear_accel: 1\nmax_angular_accel: 1\ncamera_height: 0.5\n").unwrap();
        let e = RobotProfile::from_file(&f).unwrap_err().to_string();
        assert!(e.contains("bad.yaml") && e.contains("radius"), "{e}");
        std::fs::write(&f, "name: x\nradius: 0.1\nheigth: 1\n").unwrap();
        let e = RobotProfile::from_file(&f).unwrap_err().to_string();
        assert!(e.contains("heigth"), "{e}");
    }
}
