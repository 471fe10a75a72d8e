//! Wheel odometry with the diff-drive noise model that AMCL assumes (Probabilistic Robotics,
//! sample_motion_model_odometry): each motion is split into rotation, translation, rotation,
//! and each part is perturbed with a standard deviation drawn from alpha1..alpha4.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use xhab_types::gaussian;
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, Pose2};

/// Noise parameters (ROS amcl's odom_alpha1..4, "corrected" standard-deviation form).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OdometryNoise {
    /// Rotation noise from rotation (default 0.005).
    pub alpha1: f64,
    /// Rotation noise from translation (default 0.005).
    pub alpha2: f64,
    /// Translation noise from translation (default 0.01).
    pub alpha3: f64,
    /// Translation noise from rotation (default 0.005).
    pub alpha4: f64,
}

impl Default for OdometryNoise {
    fn default() -> Self {
        // Small, as for a well-calibrated indoor base; ROS amcl's defaults (0.2) describe the
        // filter's belief about a bad odometry, not the odometry itself.
        Self { alpha1: 0.005, alpha2: 0.005, alpha3: 0.01, alpha4: 0.005 }
    }
}

/// Integrates noisy odometry from successive ground-truth poses; seeded.
#[derive(Debug, Clone)]
pub struct WheelOdometry {
    noise: OdometryNoise,
    rng: ChaCha8Rng,
    last_truth: Pose2,
    estimate: Pose2,
}

impl WheelOdometry {
    /// Starts at `start` (odometry and ground truth agree at the start).
    pub fn new(start: Pose2, noise: OdometryNoise, seed: u64) -> Self {
        Self { noise, rng: ChaCha8Rng::seed_from_u64(seed), last_truth: start, estimate: start }
    }

    /// Feeds the new ground-truth pose; returns the odometry pose.
    pub fn update(&mut self, truth: Pose2) -> Pose2 {
        let a = self.last_truth;
        let (dx, dy) = (truth.x - a.x, truth.y - a.y);
        let trans = dx.hypot(dy);
        // As ROS amcl: below 1 cm the direction of travel is noise itself, so take none.
        let rot1 = if trans < 0.01 { 0.0 } else { normalize_angle(dy.atan2(dx) - a.yaw) };
        let rot2 = normalize_angle(truth.yaw - a.yaw - rot1);
        let n = &self.noise;
        let s_rot1 = (n.alpha1 * rot1 * rot1 + n.alpha2 * trans * trans).sqrt();
        let s_trans = (n.alpha3 * trans * trans + n.alpha4 * (rot1 * rot1 + rot2 * rot2)).sqrt();
        let s_rot2 = (n.alpha1 * rot2 * rot2 + n.alpha2 * trans * trans).sqrt();
        let r1 = rot1 - s_rot1 * gaussian(&mut self.rng);
        let t = trans - s_trans * gaussian(&mut self.rng);
        let r2 = rot2 - s_rot2 * gaussian(&mut self.rng);
        let e = self.estimate;
        self.estimate = Pose2::new(e.x + t * (e.yaw + r1).cos(), e.y + t * (e.yaw + r1).sin(), normalize_angle(e.yaw + r1 + r2));
        self.last_truth = truth;
        self.estimate
    }

    /// The current odometry pose.
    pub fn pose(&self) -> Pose2 {
        self.estimate
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_noise_is_exact_and_noise_is_seeded() {
        let zero = OdometryNoise { alpha1: 0.0, alpha2: 0.0, alpha3: 0.0, alpha4: 0.0 };
        let mut o = WheelOdometry::new(Pose2::new(1.0, 2.0, 0.3), zero, 1);
        let mut truth = Pose2::new(1.0, 2.0, 0.3);
        for k in 0..100 {
            truth = truth.compose(Pose2::new(0.05, 0.0, if k % 3 == 0 { 0.1 } else { -0.02 }));
            let e = o.update(truth);
            assert!((e.x - truth.x).abs() < 1e-9 && (e.y - truth.y).abs() < 1e-9 && (e.yaw - truth.yaw).abs() < 1e-9);
        }
        let run = |seed| {
            let mut o = WheelOdometry::new(Pose2::default(), OdometryNoise::default(), seed);
            let mut t = Pose2::default();
            for _ in 0..50 {
                t = t.compose(Pose2::new(0.1, 0.0, 0.05));
                o.update(t);
            }
            o.pose()
        };
        assert_eq!(run(3), run(3));
        assert_ne!(run(3), run(4));
    }
}
