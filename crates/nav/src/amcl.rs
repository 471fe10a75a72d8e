//! AMCL: Monte Carlo localisation with the diff-drive odometry motion model, the
//! likelihood-field laser model, KLD-adaptive sample size, low-variance resampling and
//! random-particle recovery (ROS amcl names and defaults).
//!
//! Departures from ROS amcl, on purpose: KLD uses the real normal quantile of `kld_z` (ROS
//! plugs the probability itself into the formula), resampling is the O(N) low-variance
//! sampler (ROS searches the cumulative weights, O(N^2) in the worst case).

use crate::costmap::edt;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use xhab_types::{normalize_angle, LaserScan, OccupancyGrid, Pose2, GRID_FREE, GRID_OCCUPIED};

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
    /// Rotation noise from rotation (default 0.2).
    pub odom_alpha1: f64,
    /// Rotation noise from translation (default 0.2).
    pub odom_alpha2: f64,
    /// Translation noise from translation (default 0.2).
    pub odom_alpha3: f64,
    /// Translation noise from rotation (default 0.2).
    pub odom_alpha4: f64,
    /// Beams used per update (default 30).
    pub laser_max_beams: usize,
    /// Weight of the hit component (default 0.95).
    pub laser_z_hit: f64,
    /// Weight of the random component (default 0.05).
    pub laser_z_rand: f64,
    /// Standard deviation of the hit component (m, default 0.2).
    pub laser_sigma_hit: f64,
    /// Distance beyond which the likelihood field is flat (m, default 2.0).
    pub laser_likelihood_max_dist: f64,
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
            odom_alpha1: 0.2,
            odom_alpha2: 0.2,
            odom_alpha3: 0.2,
            odom_alpha4: 0.2,
            laser_max_beams: 30,
            laser_z_hit: 0.95,
            laser_z_rand: 0.05,
            laser_sigma_hit: 0.2,
            laser_likelihood_max_dist: 2.0,
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
    /// Likelihood of a beam end in each cell: exp(-d^2 / 2 sigma^2), d capped at max_dist.
    field: Vec<f32>,
    free_cells: Vec<usize>,
    particles: Vec<(Pose2, f64)>,
    rng: ChaCha8Rng,
    last_odom: Option<Pose2>,
    moved: (f64, f64),
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

fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = rng.gen_range(f64::MIN_POSITIVE..1.0);
    let u2: f64 = rng.gen();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

impl Amcl {
    /// A filter on `map` (origin yaw 0), seeded; call [`Amcl::init`] or [`Amcl::global_init`].
    pub fn new(map: &OccupancyGrid, params: AmclParams, seed: u64) -> Self {
        let occ: Vec<bool> = map.data.iter().map(|&v| v == GRID_OCCUPIED).collect();
        let d = edt(&occ, map.width, map.height);
        let s2 = 2.0 * params.laser_sigma_hit * params.laser_sigma_hit;
        let field = d.iter().map(|&c| {
            let m = (c * map.resolution).min(params.laser_likelihood_max_dist);
            (-(m * m) / s2).exp() as f32
        }).collect();
        let free_cells = (0..map.data.len()).filter(|&i| map.data[i] == GRID_FREE).collect();
        Self { params, map: map.clone(), field, free_cells, particles: Vec::new(), rng: ChaCha8Rng::seed_from_u64(seed), last_odom: None, moved: (0.0, 0.0), updates: 0, w_slow: 0.0, w_fast: 0.0 }
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
    }

    /// Spreads `max_particles` particles uniformly over the map's free space.
    pub fn global_init(&mut self) {
        let n = self.params.max_particles.max(1);
        self.particles = (0..n).map(|_| (self.random_free_pose(), 1.0 / n as f64)).collect();
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

    /// One step: moves the particles by the odometry change since the last call, and when the
    /// robot has moved `update_min_d` or turned `update_min_a`, weighs them against `scan`
    /// (taken at `laser` in the base frame) and resamples every `resample_interval` updates.
    /// Returns whether a sensor update happened.
    pub fn update(&mut self, odom: Pose2, scan: &LaserScan, laser: Pose2) -> bool {
        let Some(last) = self.last_odom.replace(odom) else { return false };
        let delta = last.inverse().compose(odom);
        self.moved.0 += delta.x.hypot(delta.y);
        self.moved.1 += delta.yaw.abs();
        self.motion(last, odom);
        if self.moved.0 < self.params.update_min_d && self.moved.1 < self.params.update_min_a {
            return false;
        }
        self.moved = (0.0, 0.0);
        self.sense(scan, laser);
        self.updates += 1;
        if self.updates.is_multiple_of(self.params.resample_interval.max(1)) {
            self.resample();
        }
        true
    }

    /// Odometry motion model (Probabilistic Robotics, sample_motion_model_odometry).
    fn motion(&mut self, a: Pose2, b: Pose2) {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let trans = dx.hypot(dy);
        let rot1 = if trans < 0.01 { 0.0 } else { normalize_angle(dy.atan2(dx) - a.yaw) };
        let rot2 = normalize_angle(b.yaw - a.yaw - rot1);
        // As ROS: rotation noise on the smaller of the turn and its reverse (driving backwards).
        let r1n = rot1.abs().min((std::f64::consts::PI - rot1.abs()).abs());
        let r2n = rot2.abs().min((std::f64::consts::PI - rot2.abs()).abs());
        let p = self.params.clone();
        for k in 0..self.particles.len() {
            let sr1 = (p.odom_alpha1 * r1n * r1n + p.odom_alpha2 * trans * trans).sqrt();
            let st = (p.odom_alpha3 * trans * trans + p.odom_alpha4 * (r1n * r1n + r2n * r2n)).sqrt();
            let sr2 = (p.odom_alpha1 * r2n * r2n + p.odom_alpha2 * trans * trans).sqrt();
            let r1 = rot1 - sr1 * gaussian(&mut self.rng);
            let t = trans - st * gaussian(&mut self.rng);
            let r2 = rot2 - sr2 * gaussian(&mut self.rng);
            let q = &mut self.particles[k].0;
            *q = Pose2::new(q.x + t * (q.yaw + r1).cos(), q.y + t * (q.yaw + r1).sin(), normalize_angle(q.yaw + r1 + r2));
        }
    }

    /// Likelihood-field weights (ROS's sum of cubed beam likelihoods), and the recovery averages.
    fn sense(&mut self, scan: &LaserScan, laser: Pose2) {
        let p = &self.params;
        let n = scan.ranges.len();
        let step = (n / p.laser_max_beams.max(1)).max(1);
        let z_rand = p.laser_z_rand / scan.range_max.max(1e-6);
        // The used beams in the laser frame: end points (m) relative to the laser.
        let beams: Vec<(f64, f64)> = (0..n)
            .step_by(step)
            .filter_map(|i| {
                let r = scan.ranges[i] as f64;
                (r.is_finite() && r >= scan.range_min && r <= scan.range_max).then(|| (r * scan.angle(i).cos(), r * scan.angle(i).sin()))
            })
            .collect();
        // Maps are unrotated (origin yaw 0): cells by plain arithmetic, no trigonometry per beam.
        let (ox, oy, inv_res) = (self.map.origin.x, self.map.origin.y, 1.0 / self.map.resolution);
        let (mw, mh) = (self.map.width as i64, self.map.height as i64);
        let mut total = 0.0;
        for (pose, w) in self.particles.iter_mut() {
            let lp = pose.compose(laser);
            let (s, c) = lp.yaw.sin_cos();
            let mut sum = 0.0;
            for &(bx, by) in &beams {
                let (ex, ey) = (lp.x + c * bx - s * by, lp.y + s * bx + c * by);
                let (ci, ri) = (((ex - ox) * inv_res).floor() as i64, ((ey - oy) * inv_res).floor() as i64);
                let f = if ci >= 0 && ri >= 0 && ci < mw && ri < mh { self.field[(ri * mw + ci) as usize] as f64 } else { 0.0 };
                let pz = p.laser_z_hit * f + z_rand;
                sum += pz * pz * pz;
            }
            *w *= 1.0 + sum;
            total += *w;
        }
        if total > 0.0 {
            let n = self.particles.len() as f64;
            let avg = total / n;
            self.particles.iter_mut().for_each(|(_, w)| *w /= total);
            if self.params.recovery_alpha_slow > 0.0 {
                self.w_slow += self.params.recovery_alpha_slow * (avg - self.w_slow);
                self.w_fast += self.params.recovery_alpha_fast * (avg - self.w_fast);
            }
        } else {
            let n = self.particles.len() as f64;
            self.particles.iter_mut().for_each(|(_, w)| *w = 1.0 / n);
        }
    }

    /// Low-variance resampling with KLD-adaptive size and random-particle recovery.
    fn resample(&mut self) {
        let p = self.params.clone();
        let w_random = if p.recovery_alpha_slow > 0.0 && self.w_slow > 0.0 { (1.0 - self.w_fast / self.w_slow).max(0.0) } else { 0.0 };
        let z = normal_quantile(p.kld_z);
        let mut bins = std::collections::HashSet::new();
        let mut out: Vec<(Pose2, f64)> = Vec::with_capacity(p.max_particles);
        let n_old = self.particles.len();
        let mut cdf = Vec::with_capacity(n_old);
        let mut acc = 0.0;
        for (_, w) in &self.particles {
            acc += w;
            cdf.push(acc);
        }
        let start: f64 = self.rng.gen::<f64>() / n_old.max(1) as f64;
        let mut j = 0;
        let mut m = 0usize;
        loop {
            let q = if self.rng.gen::<f64>() < w_random {
                self.random_free_pose()
            } else {
                // Low variance: evenly spaced pointers through the cumulative weights.
                let u = (start + m as f64 / n_old.max(1) as f64).fract() * acc;
                if u < cdf.get(j.min(n_old - 1)).copied().unwrap_or(0.0) && j > 0 && u < cdf[j - 1] {
                    j = 0;
                }
                while j + 1 < n_old && cdf[j] < u {
                    j += 1;
                }
                self.particles[j].0
            };
            m += 1;
            out.push((q, 1.0));
            bins.insert(((q.x / 0.5).floor() as i64, (q.y / 0.5).floor() as i64, (q.yaw / 10f64.to_radians()).floor() as i64));
            let k = bins.len();
            let limit = if k <= 1 {
                p.max_particles
            } else {
                let k1 = (k - 1) as f64;
                let b = 2.0 / (9.0 * k1);
                ((k1 / (2.0 * p.kld_err)) * (1.0 - b + b.sqrt() * z).powi(3)).ceil() as usize
            };
            if out.len() >= p.max_particles || (out.len() >= p.min_particles && out.len() >= limit) {
                break;
            }
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

    /// The map -> odom correction for odometry pose `odom`: `estimate * odom^-1`.
    pub fn map_to_odom(&self, odom: Pose2) -> Pose2 {
        self.estimate().pose.compose(odom.inverse())
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

    #[test]
    fn tracks_a_robot_and_converges_from_an_offset_start() {
        let map = room();
        let mut amcl = Amcl::new(&map, AmclParams::default(), 3);
        // The filter starts 0.3 m and 0.2 rad off.
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
        let e = amcl.estimate();
        let err = e.pose.position().dist(truth.position());
        assert!(err < 0.1, "position error {err} ({:?} vs {truth:?})", e.pose);
        assert!(normalize_angle(e.pose.yaw - truth.yaw).abs() < 0.1);
        assert!(amcl.len() < AmclParams::default().max_particles, "KLD shrank the set: {}", amcl.len());
    }
}
