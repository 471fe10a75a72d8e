//! AMCL's odometry motion models for a differential-drive base (Probabilistic Robotics,
//! sample_motion_model_odometry): a motion is split into a turn, a straight move and a second
//! turn, and each part is perturbed with noise drawn from alpha1..alpha4.

use rand::Rng;
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, Pose2};

/// Which form of the differential-drive model (ROS `odom_model_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum OdomModelType {
    /// ROS's original model: the alpha expressions (variances) are used as standard deviations.
    #[default]
    #[serde(rename = "diff")]
    Diff,
    /// The corrected model: standard deviations are the square roots of those variances.
    #[serde(rename = "diff-corrected")]
    DiffCorrected,
}

/// One odometry motion, decomposed once and applied to every particle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct OdomMotion {
    rot1: f64,
    trans: f64,
    rot2: f64,
    /// Standard deviations of the noise on rot1 (rad), trans (m) and rot2 (rad).
    std: [f64; 3],
}

impl OdomMotion {
    /// The motion from odometry pose `a` to `b` (odom frame) under `model` with noise
    /// parameters `alpha` (alpha1..alpha4).
    pub(crate) fn new(a: Pose2, b: Pose2, model: OdomModelType, alpha: [f64; 4]) -> Self {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let trans = dx.hypot(dy);
        // Below 1 cm the direction of travel is noise itself: all of the turn goes to rot2.
        let rot1 = if trans < 0.01 { 0.0 } else { normalize_angle(dy.atan2(dx) - a.yaw) };
        let rot2 = normalize_angle(b.yaw - a.yaw - rot1);
        // Noise on the smaller of a turn and its reverse, so driving backwards is not a half turn.
        let r1n = rot1.abs().min(std::f64::consts::PI - rot1.abs());
        let r2n = rot2.abs().min(std::f64::consts::PI - rot2.abs());
        let [a1, a2, a3, a4] = alpha;
        let var = [a1 * r1n * r1n + a2 * trans * trans, a3 * trans * trans + a4 * (r1n * r1n + r2n * r2n), a1 * r2n * r2n + a2 * trans * trans];
        let std = match model {
            OdomModelType::Diff => var,
            OdomModelType::DiffCorrected => var.map(f64::sqrt),
        };
        Self { rot1, trans, rot2, std }
    }

    /// Moves particle pose `p` by this motion with freshly drawn noise.
    pub(crate) fn sample(&self, p: Pose2, rng: &mut impl Rng) -> Pose2 {
        let r1 = normalize_angle(self.rot1 - self.std[0] * gaussian(rng));
        let t = self.trans - self.std[1] * gaussian(rng);
        let r2 = normalize_angle(self.rot2 - self.std[2] * gaussian(rng));
        let (s, c) = (p.yaw + r1).sin_cos();
        Pose2::new(p.x + t * c, p.y + t * s, normalize_angle(p.yaw + r1 + r2))
    }
}

pub(crate) use xhab_types::gaussian;

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    /// Mean and standard deviation of the x reached by driving 1 m straight ahead.
    fn spread(model: OdomModelType, alpha3: f64) -> (f64, f64) {
        let m = OdomMotion::new(Pose2::default(), Pose2::new(1.0, 0.0, 0.0), model, [0.0, 0.0, alpha3, 0.0]);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        let xs: Vec<f64> = (0..20_000).map(|_| m.sample(Pose2::default(), &mut rng).x).collect();
        let mean = xs.iter().sum::<f64>() / xs.len() as f64;
        (mean, (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / xs.len() as f64).sqrt())
    }

    #[test]
    fn diff_takes_the_variance_as_the_deviation_and_corrected_its_root() {
        // 1 m with alpha3 = 0.04: variance 0.04 m^2; "diff" draws with sigma 0.04, the
        // corrected model with sigma 0.2.
        let (m, s) = spread(OdomModelType::Diff, 0.04);
        assert!((m - 1.0).abs() < 0.002 && (s - 0.04).abs() < 0.002, "{m} {s}");
        let (m, s) = spread(OdomModelType::DiffCorrected, 0.04);
        assert!((m - 1.0).abs() < 0.01 && (s - 0.2).abs() < 0.006, "{m} {s}");
    }

    #[test]
    fn without_noise_a_particle_follows_the_odometry_in_its_own_frame() {
        let a = Pose2::new(1.0, 2.0, 0.3);
        let b = a.compose(Pose2::new(0.5, 0.1, 0.4));
        let m = OdomMotion::new(a, b, OdomModelType::Diff, [0.0; 4]);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        // A particle elsewhere, facing elsewhere, makes the same relative move.
        let p = Pose2::new(-3.0, 0.5, -1.2);
        let q = m.sample(p, &mut rng);
        let want = p.compose(Pose2::new(0.5, 0.1, 0.4));
        assert!((q.x - want.x).abs() < 1e-9 && (q.y - want.y).abs() < 1e-9 && normalize_angle(q.yaw - want.yaw).abs() < 1e-9);
        // Driving backwards is a reverse move, not two half turns with their noise.
        let back = OdomMotion::new(Pose2::default(), Pose2::new(-0.5, 0.0, 0.0), OdomModelType::Diff, [1.0, 0.0, 0.0, 0.0]);
        assert!(back.std[0] < 1e-9, "{:?}", back.std);
    }
}
