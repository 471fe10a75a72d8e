//! A simulated planar lidar: horizontal rays at a height above the floor, seeded noise.

use super::raycast::RayScene;
use xhab_types::gaussian;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, Pose2};

/// Lidar parameters (TurtleBot3 LDS-01 defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LidarParams {
    /// Number of beams (default 360).
    pub beams: usize,
    /// Angle of the first beam (rad, default -pi).
    pub angle_min: f64,
    /// Angle of the last beam (rad, default pi - 2 pi / beams).
    pub angle_max: f64,
    /// Shortest valid range (m, default 0.12).
    pub range_min: f64,
    /// Longest valid range (m, default 3.5).
    pub range_max: f64,
    /// Height of the scan plane above the floor (m, default 0.2).
    pub mount_height: f64,
    /// Where the laser sits forward of and left of the base's centre (m, default 0, 0).
    pub mount_xy: [f64; 2],
    /// Standard deviation of Gaussian range noise (m, default 0: off).
    pub noise_std: f64,
}

impl Default for LidarParams {
    fn default() -> Self {
        let beams = 360;
        Self {
            beams,
            angle_min: -std::f64::consts::PI,
            angle_max: std::f64::consts::PI - std::f64::consts::TAU / beams as f64,
            range_min: 0.12,
            range_max: 3.5,
            mount_height: 0.2,
            mount_xy: [0.0, 0.0],
            noise_std: 0.0,
        }
    }
}

/// A planar lidar with its own seeded noise stream.
#[derive(Debug, Clone)]
pub struct Lidar {
    /// Parameters.
    pub params: LidarParams,
    rng: ChaCha8Rng,
}

impl Lidar {
    /// A lidar; `seed` drives the noise.
    pub fn new(params: LidarParams, seed: u64) -> Self {
        Self { params, rng: ChaCha8Rng::seed_from_u64(seed) }
    }

    /// The scan from the robot at `base` on the floor at `floor_z` (m); ranges outside
    /// [range_min, range_max] are NaN.
    pub fn scan(&mut self, scene: &RayScene, base: Pose2, floor_z: f64) -> LaserScan {
        let p = &self.params;
        let n = p.beams.max(1);
        let inc = if n > 1 { (p.angle_max - p.angle_min) / (n - 1) as f64 } else { 0.0 };
        let at = base.compose(Pose2::new(p.mount_xy[0], p.mount_xy[1], 0.0));
        // Horizontal rays: the scene's cut at the scan plane gives the same hits, faster.
        let slice = scene.slice(floor_z + p.mount_height);
        let origin = [at.x, at.y];
        let mut ranges = Vec::with_capacity(n);
        for i in 0..n {
            let a = base.yaw + p.angle_min + i as f64 * inc;
            let hit = slice.cast(origin, [a.cos(), a.sin()], p.range_max);
            let r = hit.map(|r| if p.noise_std > 0.0 { r + p.noise_std * gaussian(&mut self.rng) } else { r });
            ranges.push(match r {
                Some(r) if r >= p.range_min && r <= p.range_max => r as f32,
                _ => f32::NAN,
            });
        }
        LaserScan { angle_min: p.angle_min, angle_max: p.angle_min + inc * (n - 1) as f64, angle_increment: inc, range_min: p.range_min, range_max: p.range_max, ranges }
    }
}
