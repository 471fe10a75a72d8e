//! AMCL: Monte Carlo localisation with ROS amcl's names, defaults and models: the
//! differential-drive odometry motion model ([`motion`]), the laser models ([`laser`]),
//! KLD-adaptive sample size, random-particle recovery, update thresholds, and the estimate
//! of the heaviest particle cluster.
//!
//! As ROS, the motion model is applied once per filter update with the odometry change since
//! the last one (not at every odometry message), and the first scan after an initialisation
//! updates the filter whatever the motion.
//!
//! Departures from ROS amcl, on purpose: the default laser model is `likelihood_field_prob`
//! (ROS's is `likelihood_field`, whose `1 + sum(pz^3)` caps how much a scan can favour one
//! pose over another: on the shared scenes its tracking error is 1.7-2.7 times larger; set
//! `laser_model_type: likelihood_field` for ROS's behaviour); KLD uses the real normal quantile of `kld_z` (ROS
//! plugs the probability itself into the formula); resampling is O(N): a systematic
//! (low-variance) sample of `max_particles`, shuffled, taken in that order until the KLD
//! bound is met (ROS searches the cumulative weights per sample, O(N^2)); truncating a
//! shuffled systematic sample keeps it unbiased; `likelihood_field_prob` takes its
//! `laser_max_beams` beams evenly among the scan's returns (ROS strides over every beam and then
//! drops those without a return, so a robot far from the walls uses few or none of the returns
//! it has: on turtlebot3_world 10 of 30 beams returned, near open goals none);
//! `likelihood_field_prob` also weighs up to `laser_max_beams` beams without a return where
//! the returns leave a direction of the position open (one straight wall, a corridor): a ray
//! that would cross an occupied cell within range has likelihood `laser_no_return_likelihood`
//! (default 0.1; ROS's likelihood field skips them, so beside one straight wall it cannot
//! place the robot along it).

mod clear_rays;
mod laser;
mod motion;

pub use laser::LaserModelType;
pub use motion::OdomModelType;

use laser::LaserModel;
use motion::{gaussian, OdomMotion};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, LaserScan, OccupancyGrid, Pose2, GRID_FREE};

/// AMCL parameters (ROS names; noetic defaults unless noted).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct AmclParams {
    /// Fewest particles (default 100).
    pub min_particles: usize,
    /// Most particles (default 5000).
    pub max_particles: usize,
    /// KLD bound on the error of the sampled distribution (default 0.01).
    pub kld_err: f64,
    /// KLD confidence (default 0.99).
    pub kld_z: f64,
    /// Translation needed before a filter update (m, default 0.2).
    pub update_min_d: f64,
    /// Rotation needed before a filter update (rad, default pi/6).
    pub update_min_a: f64,
    /// Filter updates between resamplings (default 2).
    pub resample_interval: u32,
    /// Slow average decay for recovery (default 0: off).
    pub recovery_alpha_slow: f64,
    /// Fast average decay for recovery (default 0: off).
    pub recovery_alpha_fast: f64,
    /// Odometry model: `diff` (default) or `diff-corrected`.
    pub odom_model_type: OdomModelType,
    /// Rotation noise from rotation (default 0.2).
    pub odom_alpha1: f64,
    /// Rotation noise from translation (default 0.2).
    pub odom_alpha2: f64,
    /// Translation noise from translation (default 0.2).
    pub odom_alpha3: f64,
    /// Translation noise from rotation (default 0.2).
    pub odom_alpha4: f64,
    /// Laser model: `likelihood_field_prob` (default; ROS's default is `likelihood_field`),
    /// `likelihood_field` or `beam`.
    pub laser_model_type: LaserModelType,
    /// Beams used per update (default 30).
    pub laser_max_beams: usize,
    /// Weight of the hit component (default 0.95).
    pub laser_z_hit: f64,
    /// Weight of the short-reading component, beam model (default 0.1).
    pub laser_z_short: f64,
    /// Weight of the max-range component, beam model (default 0.05).
    pub laser_z_max: f64,
    /// Weight of the random component (default 0.05).
    pub laser_z_rand: f64,
    /// Standard deviation of the hit component (m, default 0.2).
    pub laser_sigma_hit: f64,
    /// Decay of the short-reading component, beam model (1/m, default 0.1).
    pub laser_lambda_short: f64,
    /// Distance beyond which the likelihood field is flat (m, default 2.0).
    pub laser_likelihood_max_dist: f64,
    /// `likelihood_field_prob`: the likelihood of a beam without a return whose ray crosses an
    /// occupied cell of the map within range (xhab's own, default 0.1; 1 ignores such beams,
    /// as ROS's likelihood field does).
    pub laser_no_return_likelihood: f64,
    /// Skip beams most particles cannot explain, `likelihood_field_prob` (default false).
    pub do_beamskip: bool,
    /// A beam end within this distance of an obstacle agrees with the map (m, default 0.5).
    pub beam_skip_distance: f64,
    /// Fraction of particles a beam must agree with to be used (default 0.3).
    pub beam_skip_threshold: f64,
    /// Fraction of skipped beams above which all are used after all (default 0.9).
    pub beam_skip_error_threshold: f64,
}

impl Default for AmclParams {
    fn default() -> Self {
        Self {
            min_particles: 100,
            max_particles: 5000,
            kld_err: 0.01,
            kld_z: 0.99,
            update_min_d: 0.2,
            update_min_a: std::f64::consts::PI / 6.0,
            resample_interval: 2,
            recovery_alpha_slow: 0.0,
            recovery_alpha_fast: 0.0,
            odom_model_type: OdomModelType::Diff,
            odom_alpha1: 0.2,
            odom_alpha2: 0.2,
            odom_alpha3: 0.2,
            odom_alpha4: 0.2,
            laser_model_type: LaserModelType::LikelihoodFieldProb,
            laser_max_beams: 30,
            laser_z_hit: 0.95,
            laser_z_short: 0.1,
            laser_z_max: 0.05,
            laser_z_rand: 0.05,
            laser_sigma_hit: 0.2,
            laser_lambda_short: 0.1,
            laser_likelihood_max_dist: 2.0,
            laser_no_return_likelihood: 0.1,
            do_beamskip: false,
            beam_skip_distance: 0.5,
            beam_skip_threshold: 0.3,
            beam_skip_error_threshold: 0.9,
        }
    }
}

/// The filter's estimate: mean pose and covariance of x, y, yaw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PoseEstimate {
    /// Mean pose (m, rad).
    pub pose: Pose2,
    /// Variances of x, y (m^2) and yaw (rad^2).
    pub variance: [f64; 3],
}

/// The particle filter on one map.
#[derive(Debug, Clone)]
pub struct Amcl {
    /// Parameters.
    pub params: AmclParams,
    map: OccupancyGrid,
    laser: LaserModel,
    free_cells: Vec<usize>,
    particles: Vec<(Pose2, f64)>,
    rng: ChaCha8Rng,
    /// Odometry pose at the last filter update (`None` until the first scan after init).
    last_odom: Option<Pose2>,
    updates: u32,
    w_slow: f64,
    w_fast: f64,
}

/// Normal quantile (inverse CDF) by Acklam's rational approximation (|error| < 1.2e-9).
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub fn normal_quantile(p: f64) -> f64 {
    let a = [-3.969683028665376e1, 2.209460984245205e2, -2.759285104469687e2, 1.383577518672690e2, -3.066479806614716e1, 2.506628277459239];
    let b = [-5.447609879822406e1, 1.615858368580409e2, -1.556989798598866e2, 6.680131188771972e1, -1.328068155288572e1];
    let c = [-7.784894002430293e-3, -3.223964580411365e-1, -2.400758277161838, -2.549732539343734, 4.374664141464968, 2.938163982698783];
    let d = [7.784695709041462e-3, 3.224671290700398e-1, 2.445134137142996, 3.754408661907416];
    let p = p.clamp(1e-12, 1.0 - 1e-12);
    let pl = 0.02425;
    if p < pl {
        let q = (-2.0 * p.ln()).sqrt();
        (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) / ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0)
    } else if p <= 1.0 - pl {
        let q = p - 0.5;
        let r = q * q;
        (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q / (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0)
    } else {
        -normal_quantile(1.0 - p)
    }
}

/// Particles needed so that, with `k` occupied bins, the sampled distribution is within
/// `kld_err` of the true one with confidence quantile `z` (Fox's KLD-sampling bound), at most
/// `max`.
fn kld_limit(k: usize, kld_err: f64, z: f64, max: usize) -> usize {
    if k <= 1 {
        return max;
    }
    let k1 = (k - 1) as f64;
    let b = 2.0 / (9.0 * k1);
    (((k1 / (2.0 * kld_err)) * (1.0 - b + b.sqrt() * z).powi(3)).ceil() as usize).min(max)
}

impl Amcl {
    /// A filter on `map` (a rotated map first turned into the world's axes:
    /// [`OccupancyGrid::axis_aligned`]), seeded; call [`Amcl::init`] or [`Amcl::global_init`].
    pub fn new(map: &OccupancyGrid, params: AmclParams, seed: u64) -> Self {
        let map = &*map.axis_aligned();
        let laser = LaserModel::new(map, &params);
        let free_cells = (0..map.data.len()).filter(|&i| map.data[i] == GRID_FREE).collect();
        Self { params, map: map.clone(), laser, free_cells, particles: Vec::new(), rng: ChaCha8Rng::seed_from_u64(seed), last_odom: None, updates: 0, w_slow: 0.0, w_fast: 0.0 }
    }

    /// Spreads `max_particles / 2` particles around `pose` with standard deviations
    /// (`std_xy` m, `std_yaw` rad).
    pub fn init(&mut self, pose: Pose2, std_xy: f64, std_yaw: f64) {
        let n = (self.params.max_particles / 2).max(self.params.min_particles).max(1);
        self.particles = (0..n)
            .map(|_| {
                let p = Pose2::new(pose.x + std_xy * gaussian(&mut self.rng), pose.y + std_xy * gaussian(&mut self.rng), normalize_angle(pose.yaw + std_yaw * gaussian(&mut self.rng)));
                (p, 1.0 / n as f64)
            })
            .collect();
        self.restart();
    }

    /// After an initialisation: the next scan updates the filter whatever the motion.
    fn restart(&mut self) {
        self.last_odom = None;
        self.updates = 0;
        self.w_slow = 0.0;
        self.w_fast = 0.0;
    }

    /// Spreads `max_particles` particles uniformly over the map's free space.
    pub fn global_init(&mut self) {
        let n = self.params.max_particles.max(1);
        self.particles = (0..n).map(|_| (self.random_free_pose(), 1.0 / n as f64)).collect();
        self.restart();
    }

    fn random_free_pose(&mut self) -> Pose2 {
        if self.free_cells.is_empty() {
            return Pose2::default();
        }
        let i = self.free_cells[self.rng.gen_range(0..self.free_cells.len())];
        let c = self.map.cell_center(i % self.map.width, i / self.map.width);
        let r = self.map.resolution;
        Pose2::new(c.x + (self.rng.gen::<f64>() - 0.5) * r, c.y + (self.rng.gen::<f64>() - 0.5) * r, self.rng.gen_range(-std::f64::consts::PI..std::f64::consts::PI))
    }

    /// Number of particles.
    pub fn len(&self) -> usize {
        self.particles.len()
    }
    /// Whether the filter has no particles yet.
    pub fn is_empty(&self) -> bool {
        self.particles.is_empty()
    }

    /// One step, fed every scan with the odometry pose at its time: when the robot has moved
    /// `update_min_d` or turned `update_min_a` since the last filter update (or this is the
    /// first scan after an initialisation), moves the particles by the odometry change, weighs
    /// them against `scan` (taken by a laser at `laser` in the base frame) and resamples every
    /// `resample_interval` updates. Returns whether the filter updated.
    pub fn update(&mut self, odom: Pose2, scan: &LaserScan, laser: Pose2) -> bool {
        if let Some(last) = self.last_odom {
            let delta = last.inverse().compose(odom);
            if delta.x.hypot(delta.y) < self.params.update_min_d && normalize_angle(delta.yaw).abs() < self.params.update_min_a {
                return false;
            }
            let p = &self.params;
            let m = OdomMotion::new(last, odom, p.odom_model_type, [p.odom_alpha1, p.odom_alpha2, p.odom_alpha3, p.odom_alpha4]);
            for k in 0..self.particles.len() {
                self.particles[k].0 = m.sample(self.particles[k].0, &mut self.rng);
            }
        }
        self.last_odom = Some(odom);
        self.sense(scan, laser);
        self.updates += 1;
        if self.updates.is_multiple_of(self.params.resample_interval.max(1)) {
            self.resample();
        }
        true
    }

    /// Whether every particle lies within 0.5 m (in x and in y) of the weighted mean, as
    /// ROS's `pf_update_converged`.
    pub fn converged(&self) -> bool {
        let (mut x, mut y, mut tw) = (0.0, 0.0, 0.0);
        for (p, w) in &self.particles {
            x += w * p.x;
            y += w * p.y;
            tw += w;
        }
        if tw <= 0.0 {
            return false;
        }
        let (x, y) = (x / tw, y / tw);
        self.particles.iter().all(|(p, _)| (p.x - x).abs() <= 0.5 && (p.y - y).abs() <= 0.5)
    }

    /// Weighs the particles by the laser model; updates the recovery averages.
    fn sense(&mut self, scan: &LaserScan, laser: Pose2) {
        let converged = self.params.do_beamskip && self.converged();
        let total = self.laser.weigh(&self.params, scan, laser, &mut self.particles, converged);
        let sum: f64 = self.particles.iter().map(|(_, w)| w).sum();
        let n = self.particles.len() as f64;
        if sum > 0.0 && sum.is_finite() {
            self.particles.iter_mut().for_each(|(_, w)| *w /= sum);
            if self.params.recovery_alpha_slow > 0.0 {
                let avg = total / n;
                self.w_slow += self.params.recovery_alpha_slow * (avg - self.w_slow);
                self.w_fast += self.params.recovery_alpha_fast * (avg - self.w_fast);
            }
        } else {
            self.particles.iter_mut().for_each(|(_, w)| *w = 1.0 / n);
        }
    }

    /// Resampling with KLD-adaptive size and random-particle recovery: a systematic sample of
    /// `max_particles` from the weights, shuffled, taken in order (or replaced by a random
    /// free pose with the recovery probability) until the KLD bound on the occupied bins
    /// (0.5 m x 0.5 m x 10 degrees, as ROS) is met.
    fn resample(&mut self) {
        let p = self.params.clone();
        let n_old = self.particles.len();
        if n_old == 0 {
            return;
        }
        let w_random = if p.recovery_alpha_slow > 0.0 && self.w_slow > 0.0 { (1.0 - self.w_fast / self.w_slow).max(0.0) } else { 0.0 };
        let m = p.max_particles.max(1);
        let total: f64 = self.particles.iter().map(|(_, w)| w).sum();
        let mut pool = Vec::with_capacity(m);
        let (mut j, mut acc) = (0, self.particles[0].1);
        let start = self.rng.gen::<f64>();
        for k in 0..m {
            let u = (start + k as f64) / m as f64 * total;
            while acc < u && j + 1 < n_old {
                j += 1;
                acc += self.particles[j].1;
            }
            pool.push(self.particles[j].0);
        }
        for k in (1..m).rev() {
            pool.swap(k, self.rng.gen_range(0..=k));
        }
        let z = normal_quantile(p.kld_z);
        let mut bins = std::collections::HashSet::new();
        let mut out: Vec<(Pose2, f64)> = Vec::with_capacity(m);
        for q in pool {
            let q = if w_random > 0.0 && self.rng.gen::<f64>() < w_random { self.random_free_pose() } else { q };
            out.push((q, 1.0));
            bins.insert(((q.x / 0.5).floor() as i64, (q.y / 0.5).floor() as i64, (q.yaw / 10f64.to_radians()).floor() as i64));
            if out.len() >= p.min_particles && out.len() >= kld_limit(bins.len(), p.kld_err, z, p.max_particles) {
                break;
            }
        }
        if w_random > 0.0 {
            // As ROS: the averages start over after random particles were injected.
            self.w_slow = 0.0;
            self.w_fast = 0.0;
        }
        let n = out.len() as f64;
        out.iter_mut().for_each(|(_, w)| *w = 1.0 / n);
        self.particles = out;
    }

    /// The estimate: weighted mean pose (circular mean for yaw) and variances of the heaviest
    /// cluster of particles, as ROS amcl reports its best cluster. Clusters are connected
    /// groups of occupied bins of 0.5 m x 0.5 m x 45 degrees (8-connected in x, y, yaw, with
    /// yaw wrapping), so a filter still split between places (global localisation) reports the
    /// likeliest place, not a point between them.
    pub fn estimate(&self) -> PoseEstimate {
        let cluster = self.best_cluster();
        let parts = || cluster.iter().map(|&i| &self.particles[i]);
        let (mut x, mut y, mut s, mut c, mut tw) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for (p, w) in parts() {
            x += w * p.x;
            y += w * p.y;
            s += w * p.yaw.sin();
            c += w * p.yaw.cos();
            tw += w;
        }
        let tw = f64::max(tw, 1e-300);
        let mean = Pose2::new(x / tw, y / tw, s.atan2(c));
        let mut v = [0.0; 3];
        for (p, w) in parts() {
            v[0] += w * (p.x - mean.x).powi(2);
            v[1] += w * (p.y - mean.y).powi(2);
            v[2] += w * normalize_angle(p.yaw - mean.yaw).powi(2);
        }
        PoseEstimate { pose: mean, variance: v.map(|a| a / tw) }
    }

    /// Indices of the particles in the heaviest cluster (all of them when there is one).
    fn best_cluster(&self) -> Vec<usize> {
        use std::collections::HashMap;
        const XY: f64 = 0.5;
        const YAW_BINS: i64 = 8;
        let key = |p: &Pose2| -> (i64, i64, i64) {
            let a = ((normalize_angle(p.yaw) + std::f64::consts::PI) / (2.0 * std::f64::consts::PI) * YAW_BINS as f64).floor() as i64;
            ((p.x / XY).floor() as i64, (p.y / XY).floor() as i64, a.rem_euclid(YAW_BINS))
        };
        let mut bins: HashMap<(i64, i64, i64), (usize, f64)> = HashMap::new();
        let mut order = Vec::new();
        for (p, w) in &self.particles {
            let k = key(p);
            let e = bins.entry(k).or_insert_with(|| {
                order.push(k);
                (usize::MAX, 0.0)
            });
            e.1 += w;
        }
        // Connected components by flood fill, in first-seen order (deterministic).
        let mut comp_weight = Vec::new();
        for &k in &order {
            if bins[&k].0 != usize::MAX {
                continue;
            }
            let id = comp_weight.len();
            let mut total = 0.0;
            let mut stack = vec![k];
            bins.get_mut(&k).unwrap().0 = id;
            while let Some((x, y, a)) = stack.pop() {
                total += bins[&(x, y, a)].1;
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for da in -1..=1 {
                            let n = (x + dx, y + dy, (a + da).rem_euclid(YAW_BINS));
                            if let Some(e) = bins.get_mut(&n) {
                                if e.0 == usize::MAX {
                                    e.0 = id;
                                    stack.push(n);
                                }
                            }
                        }
                    }
                }
            }
            comp_weight.push(total);
        }
        let best = comp_weight.iter().enumerate().fold((0, f64::MIN), |b, (i, &w)| if w > b.1 { (i, w) } else { b }).0;
        (0..self.particles.len()).filter(|&i| bins[&key(&self.particles[i].0)].0 == best).collect()
    }

    /// The estimate and the map -> odom correction it gives (as [`Amcl::estimate`] and
    /// [`Amcl::map_to_odom`], the clusters worked out once).
    pub fn estimate_and_map_to_odom(&self) -> (PoseEstimate, Pose2) {
        let e = self.estimate();
        (e, self.last_odom.map_or(Pose2::default(), |o| e.pose.compose(o.inverse())))
    }

    /// The map -> odom correction: the estimate composed with the inverse of the odometry pose
    /// of the last filter update (identity before the first).
    pub fn map_to_odom(&self) -> Pose2 {
        self.last_odom.map_or(Pose2::default(), |o| self.estimate().pose.compose(o.inverse()))
    }

    /// The robot's pose now (map frame): the last estimate carried forward by the odometry
    /// since that update, `map_to_odom * odom`.
    pub fn pose_at(&self, odom: Pose2) -> Pose2 {
        self.map_to_odom().compose(odom)
    }

    /// The particles (pose, weight).
    pub fn particles(&self) -> &[(Pose2, f64)] {
        &self.particles
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::Point2;

    #[test]
    fn normal_quantiles() {
        assert!((normal_quantile(0.99) - 2.326348).abs() < 1e-5);
        assert!((normal_quantile(0.5)).abs() < 1e-9);
        assert!((normal_quantile(0.01) + 2.326348).abs() < 1e-5);
    }

    /// A 6 x 4 m room with an off-centre pillar, and a ray-marched scan of it.
    fn room() -> OccupancyGrid {
        let mut m = OccupancyGrid::new(120, 80, 0.05, Pose2::default(), 0);
        for r in 0..80 {
            for c in 0..120 {
                if c == 0 || r == 0 || c == 119 || r == 79 || ((70..80).contains(&c) && (45..60).contains(&r)) {
                    m.set(c, r, 100);
                }
            }
        }
        m
    }

    fn scan(map: &OccupancyGrid, pose: Pose2) -> LaserScan {
        let n = 90;
        let inc = std::f64::consts::TAU / n as f64;
        let ranges = (0..n)
            .map(|i| {
                let a = pose.yaw - std::f64::consts::PI + i as f64 * inc;
                let mut d = 0.0;
                while d < 8.0 {
                    let p = Point2::new(pose.x + d * a.cos(), pose.y + d * a.sin());
                    if map.world_to_cell(p).is_none_or(|(c, r)| map.get(c, r) == 100) {
                        return d as f32;
                    }
                    d += 0.01;
                }
                f32::NAN
            })
            .collect();
        LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 8.0, ranges }
    }

    /// Drives a robot around the room with perfect odometry; the filter starts 0.3 m and
    /// 0.2 rad off. Returns the final position and heading errors and the particle count.
    fn track(params: AmclParams) -> (f64, f64, usize) {
        let map = room();
        let mut amcl = Amcl::new(&map, params, 3);
        amcl.init(Pose2::new(1.3, 1.2, 0.2), 0.3, 0.2);
        let mut truth = Pose2::new(1.0, 1.0, 0.0);
        amcl.update(truth, &scan(&map, truth), Pose2::default());
        for k in 0..60 {
            let step = if k % 20 < 15 { Pose2::new(0.1, 0.0, 0.0) } else { Pose2::new(0.0, 0.0, 0.3) };
            truth = truth.compose(step);
            if truth.x > 5.0 || truth.y > 3.5 || truth.y < 0.5 {
                truth = Pose2::new(truth.x.clamp(0.5, 5.0), truth.y.clamp(0.5, 3.5), truth.yaw + 1.0);
            }
            amcl.update(truth, &scan(&map, truth), Pose2::default());
        }
        // Odometry is the truth here: the pose now is the estimate carried forward by it.
        let p = amcl.pose_at(truth);
        (p.position().dist(truth.position()), normalize_angle(p.yaw - truth.yaw).abs(), amcl.len())
    }

    #[test]
    fn every_model_tracks_a_robot_and_converges_from_an_offset_start() {
        for (laser_model_type, odom_model_type) in [
            (LaserModelType::LikelihoodFieldProb, OdomModelType::Diff),
            (LaserModelType::LikelihoodField, OdomModelType::Diff),
            (LaserModelType::Beam, OdomModelType::Diff),
            (LaserModelType::LikelihoodFieldProb, OdomModelType::DiffCorrected),
        ] {
            let (err, yaw, n) = track(AmclParams { laser_model_type, odom_model_type, ..Default::default() });
            assert!(err < 0.1 && yaw < 0.1, "{laser_model_type:?} {odom_model_type:?}: position error {err}, heading error {yaw}");
            // (The product model can pack every particle into one KLD bin, where ROS's bound,
            // kept here, asks for max_particles.)
            if laser_model_type == LaserModelType::LikelihoodField {
                assert!(n < AmclParams::default().max_particles, "{laser_model_type:?}: KLD shrank the set: {n}");
            }
        }
        // Beam skipping changes nothing when every beam agrees with the map.
        let (err, _, _) = track(AmclParams { do_beamskip: true, ..Default::default() });
        assert!(err < 0.1, "{err}");
    }

    #[test]
    fn kld_bound_grows_with_the_occupied_bins() {
        let z = normal_quantile(0.99);
        assert_eq!(kld_limit(1, 0.01, z, 5000), 5000);
        let (a, b) = (kld_limit(10, 0.01, z, 100_000), kld_limit(100, 0.01, z, 100_000));
        // Fox 2003: about (k - 1) / (2 err) * (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3.
        assert!((1000..1150).contains(&a) && (6500..7000).contains(&b), "{a} {b}");
        assert_eq!(kld_limit(100, 0.01, z, 5000), 5000);
    }

    #[test]
    fn resampling_draws_in_proportion_to_the_weights() {
        let map = room();
        let params = AmclParams { min_particles: 4000, max_particles: 4000, ..Default::default() };
        let mut amcl = Amcl::new(&map, params, 9);
        // Four places with weights 0.1, 0.2, 0.3, 0.4, in many copies each, in random order
        // (a periodic order would alias with the systematic sampler's even spacing).
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        amcl.particles = (0..4000).map(|_| rng.gen_range(0..4)).map(|k| (Pose2::new(1.0 + k as f64, 2.0, 0.0), (1 + k) as f64)).collect();
        let copies: Vec<usize> = (0..4).map(|k| amcl.particles.iter().filter(|(p, _)| p.x == 1.0 + k as f64).count()).collect();
        let total: f64 = (0..4).map(|k| (k + 1) as f64 * copies[k] as f64).sum();
        amcl.resample();
        let mut counts = [0usize; 4];
        for (p, _) in amcl.particles() {
            counts[(p.x - 1.0).round() as usize] += 1;
        }
        for (k, &c) in counts.iter().enumerate() {
            let want = 4000.0 * (k + 1) as f64 * copies[k] as f64 / total;
            // Systematic sampling is exact to one draw per particle, not per place.
            assert!((c as f64 - want).abs() <= 2.0 * want.sqrt(), "{counts:?} {copies:?}");
        }
        // Fewer particles than the pool (KLD): a shuffled sample, still in proportion.
        let params = AmclParams { min_particles: 100, max_particles: 4000, kld_err: 0.5, ..Default::default() };
        let mut amcl = Amcl::new(&map, params, 9);
        amcl.particles = (0..4000).map(|i| (Pose2::new(1.0 + (i % 4) as f64, 2.0 + (i / 4 % 10) as f64 * 0.1, 0.0), if i % 4 == 3 { 3.0 } else { 1.0 })).collect();
        amcl.resample();
        let n = amcl.len();
        let heavy = amcl.particles().iter().filter(|(p, _)| (p.x - 4.0).abs() < 0.1).count();
        assert!(n < 4000 && (heavy as f64 / n as f64 - 0.5).abs() < 0.12, "{heavy} of {n}");
    }

    #[test]
    fn global_localization_finds_the_robot_in_an_asymmetric_room() {
        let map = room();
        let mut amcl = Amcl::new(&map, AmclParams { max_particles: 20_000, ..Default::default() }, 5);
        amcl.global_init();
        let mut truth = Pose2::new(4.2, 1.1, 2.5);
        amcl.update(truth, &scan(&map, truth), Pose2::default());
        for k in 0..30 {
            truth = truth.compose(if k % 10 < 7 { Pose2::new(0.1, 0.0, 0.0) } else { Pose2::new(0.0, 0.0, 0.35) });
            amcl.update(truth, &scan(&map, truth), Pose2::default());
        }
        let p = amcl.pose_at(truth);
        assert!(p.position().dist(truth.position()) < 0.1 && normalize_angle(p.yaw - truth.yaw).abs() < 0.1, "{p:?} vs {truth:?}");
        assert!(amcl.converged());
    }

    #[test]
    fn the_first_scan_after_init_updates_without_motion() {
        let map = room();
        let mut amcl = Amcl::new(&map, AmclParams::default(), 1);
        amcl.init(Pose2::new(1.0, 1.0, 0.0), 0.3, 0.2);
        let truth = Pose2::new(1.0, 1.0, 0.0);
        assert!(amcl.update(truth, &scan(&map, truth), Pose2::default()));
        assert!(!amcl.update(truth, &scan(&map, truth), Pose2::default()), "no motion: no update");
        let moved = truth.compose(Pose2::new(0.25, 0.0, 0.0));
        assert!(amcl.update(moved, &scan(&map, moved), Pose2::default()));
    }
}
