//! AMCL's laser models (ROS `laser_model_type`): how likely a scan is from a particle's pose.
//!
//! - `likelihood_field`: each beam's end point is scored by its distance to the nearest
//!   occupied cell (a Gaussian of `laser_sigma_hit`, plus `laser_z_rand`); beams combine by
//!   ROS's ad-hoc `1 + sum(pz^3)`.
//! - `likelihood_field_prob`: the same beam scores multiplied (a true likelihood), with ROS's
//!   optional beam skipping: once the filter has converged, beams that most particles cannot
//!   explain (an obstacle missing from the map) are left out. Beams without a return count
//!   too (xhab's own) where the returns leave a direction of the position open: one whose ray
//!   would cross an occupied cell within range has likelihood `laser_no_return_likelihood`.
//!   Beside a single straight wall the returns fit every pose along it; where the wall ends,
//!   the beams that pass its end are what place the robot. Where the returns pin the position
//!   by themselves (the smaller eigenvalue of `sum n n^T` over their surface normals is 1 or
//!   more), they are left out: tracing a ray per particle and beam is costly.
//! - `beam`: each beam's range is compared with the range ray-cast in the map from the
//!   particle (hit, short, max and random parts), combined as `1 + sum(pz^3)`.
//!
//! Maps have origin yaw 0 ([`Amcl::new`](super::Amcl::new) turns a rotated one into the
//! world's axes), so cells come from plain arithmetic. Beams without a return (NaN,
//! +inf or at least `range_max`) are skipped by `likelihood_field`, weighed as clear rays by
//! `likelihood_field_prob`, and read as `range_max` by the beam model;
//! `likelihood_field` and `beam` take ROS's fixed stride over all beams, `likelihood_field_prob`
//! its `laser_max_beams` evenly among the returns (xhab's departure: see `valid_beams`).

use super::clear_rays::{weakest_constraint, ClearRays, CLEARANCE_CAP};
use super::AmclParams;
use crate::distance_field::{squared_edt, FAR};
use serde::{Deserialize, Serialize};
use xhab_types::{LaserScan, OccupancyGrid, Pose2, GRID_FREE, GRID_OCCUPIED};

/// Which laser model (ROS `laser_model_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum LaserModelType {
    /// Likelihood field, beams combined as `1 + sum(pz^3)` (ROS's default).
    #[serde(rename = "likelihood_field")]
    LikelihoodField,
    /// Likelihood field, beams multiplied, optional beam skipping (xhab's default).
    #[default]
    #[serde(rename = "likelihood_field_prob")]
    LikelihoodFieldProb,
    /// Beam model: measured against ray-cast ranges.
    #[serde(rename = "beam")]
    Beam,
}

/// One beam used in an update: range (m), and its end point relative to the laser (m).
#[derive(Debug, Clone, Copy)]
struct Beam {
    range: f64,
    bearing: f64,
    x: f64,
    y: f64,
}

/// The map as the laser models read it.
#[derive(Debug, Clone)]
pub(crate) struct LaserModel {
    /// Per cell: `exp(-d^2 / 2 sigma_hit^2)`, d the distance to the nearest occupied cell
    /// capped at `laser_likelihood_max_dist` (m).
    field: Vec<f32>,
    /// The field's value at the cap, used off the map.
    far: f32,
    /// `ln(z_hit * field + z_rand / range_max)` per cell and off the map, for the product
    /// model, with the `range_max` it was made for (scans rarely change it).
    log_pz: Option<(f64, Vec<f32>, f32)>,
    /// Per cell: whether a ray-cast beam stops there (occupied or unknown, as ROS's map_calc_range).
    stops: Vec<bool>,
    /// The map's clearance, for beams without a return.
    clear_rays: ClearRays,
    origin: (f64, f64),
    res: f64,
    size: (i64, i64),
}

/// Largest distance (m) between neighbouring returns that a surface normal is taken across.
const NORMAL_GAP: f64 = 0.3;

/// Indices of at most `max_beams` evenly spaced beams among the returns of `scan` within
/// its limits (all of them when fewer): the beams `likelihood_field_prob` uses (ROS strides
/// over every beam, returns or not, so a robot far from the walls of a large room uses few or
/// none of its returns).
fn valid_beams(scan: &LaserScan, max_beams: usize) -> Vec<usize> {
    evenly((0..scan.ranges.len()).filter(|&i| scan.is_return(i)).collect(), max_beams)
}

/// Indices of at most `max_beams` evenly spaced beams without a return
/// ([`LaserScan::is_clear`]).
fn clear_beams(scan: &LaserScan, max_beams: usize) -> Vec<usize> {
    evenly((0..scan.ranges.len()).filter(|&i| scan.is_clear(i)).collect(), max_beams)
}

/// At most `max` (at least 1) evenly spaced items of `valid`.
fn evenly(valid: Vec<usize>, max: usize) -> Vec<usize> {
    let m = max.max(1);
    if valid.len() <= m {
        return valid;
    }
    (0..m).map(|k| valid[k * valid.len() / m]).collect()
}

impl LaserModel {
    /// Precomputes the likelihood field and the ray-cast mask of `map`.
    pub(crate) fn new(map: &OccupancyGrid, p: &AmclParams) -> Self {
        let s2 = 2.0 * p.laser_sigma_hit * p.laser_sigma_hit;
        let max = p.laser_likelihood_max_dist;
        let value = |c: f64| (-((c * map.resolution).min(max)).powi(2) / s2).exp() as f32;
        // The field by squared cell distance, worked out once per distance: beyond a cell past
        // the cap every value is the cap's. (Exact distances, so the same values as per cell.)
        // (A cap too far for a table, or not a number: every distance exact, one by one.)
        let reach = max / map.resolution + 1.0;
        let reach = (reach.is_finite() && reach <= 1024.0).then(|| reach.max(1.0).ceil() as u32);
        let table: Vec<f32> = reach.map_or(Vec::new(), |r| (0..=r * r).map(|d2| value((d2 as f64).sqrt())).collect());
        let at_cap = value(f64::INFINITY);
        // One distance transform for the field and for the clear rays' clearance.
        let mut d2 = Vec::new();
        let cap = reach.map_or(FAR - 1, |r| (r * r).max(CLEARANCE_CAP * CLEARANCE_CAP));
        squared_edt(map.width, map.height, |c, r| map.data[r * map.width + c] == GRID_OCCUPIED, cap, &mut d2);
        let field = d2
            .iter()
            .map(|&k| match reach {
                Some(_) => table.get(k as usize).copied().unwrap_or(at_cap),
                None if k == FAR => at_cap,
                None => value((k as f64).sqrt()),
            })
            .collect();
        let stops = map.data.iter().map(|&v| v != GRID_FREE).collect();
        LaserModel {
            field,
            far: (-(max * max) / s2).exp() as f32,
            log_pz: None,
            stops,
            clear_rays: ClearRays::new(map, &d2),
            origin: (map.origin.x, map.origin.y),
            res: map.resolution,
            size: (map.width as i64, map.height as i64),
        }
    }

    fn cell(&self, x: f64, y: f64) -> Option<usize> {
        let (c, r) = (((x - self.origin.0) / self.res).floor() as i64, ((y - self.origin.1) / self.res).floor() as i64);
        (c >= 0 && r >= 0 && c < self.size.0 && r < self.size.1).then(|| (r * self.size.0 + c) as usize)
    }

    /// The likelihood field at world point (x, y) (m).
    fn field_at(&self, x: f64, y: f64) -> f64 {
        self.cell(x, y).map_or(self.far, |i| self.field[i]) as f64
    }

    /// Multiplies each particle's weight by the likelihood of `scan` taken by a laser at
    /// `laser` in the base frame; returns the sum of the new weights (before normalising,
    /// as ROS's recovery averages use it). `converged`: the filter's particles agree (for
    /// beam skipping).
    pub(crate) fn weigh(&mut self, p: &AmclParams, scan: &LaserScan, laser: Pose2, particles: &mut [(Pose2, f64)], converged: bool) -> f64 {
        let n = scan.ranges.len();
        let max_beams = p.laser_max_beams.max(2);
        // ROS's beam stride (likelihood_field, beam); likelihood_field_prob takes its beams
        // among the returns (valid_beams).
        let step = (n.saturating_sub(1) / (max_beams - 1)).max(1);
        let beam_model = p.laser_model_type == LaserModelType::Beam;
        let indices: Vec<usize> = match p.laser_model_type {
            LaserModelType::LikelihoodFieldProb => valid_beams(scan, max_beams),
            _ => (0..n).step_by(step).collect(),
        };
        let beams: Vec<Beam> = indices
            .into_iter()
            .filter_map(|i| {
                let r = match (scan.is_return(i), beam_model) {
                    (true, _) => scan.ranges[i] as f64,
                    // As ROS's node: readings outside the limits count as max-range readings.
                    (false, true) => scan.range_max,
                    (false, false) => return None,
                };
                let b = scan.angle(i);
                Some(Beam { range: r, bearing: b, x: r * b.cos(), y: r * b.sin() })
            })
            .collect();
        match p.laser_model_type {
            LaserModelType::LikelihoodField => self.weigh_cubed(p, scan, laser, &beams, particles),
            LaserModelType::LikelihoodFieldProb => {
                // Only where the returns leave a direction of the position open: elsewhere they
                // place the robot by themselves, and tracing rays for every particle is costly.
                let open = p.laser_no_return_likelihood < 1.0 && weakest_constraint(scan, NORMAL_GAP) < 1.0;
                let clear: Vec<f64> = if open { clear_beams(scan, max_beams).into_iter().map(|i| scan.angle(i)).collect() } else { Vec::new() };
                self.weigh_prob(p, scan, laser, &beams, &clear, particles, converged)
            }
            LaserModelType::Beam => self.weigh_beam(p, scan, laser, &beams, particles),
        }
    }

    /// Likelihood field, `1 + sum(pz^3)`.
    fn weigh_cubed(&self, p: &AmclParams, scan: &LaserScan, laser: Pose2, beams: &[Beam], particles: &mut [(Pose2, f64)]) -> f64 {
        let z_rand = p.laser_z_rand / scan.range_max.max(1e-6);
        let mut total = 0.0;
        for (pose, w) in particles.iter_mut() {
            let lp = pose.compose(laser);
            let (s, c) = lp.yaw.sin_cos();
            let mut sum = 0.0;
            for b in beams {
                let pz = p.laser_z_hit * self.field_at(lp.x + c * b.x - s * b.y, lp.y + s * b.x + c * b.y) + z_rand;
                sum += pz * pz * pz;
            }
            *w *= 1.0 + sum;
            total += *w;
        }
        total
    }

    /// Likelihood field, product of the beams' `pz`, with beam skipping once converged.
    /// Beams without a return (`clear`, their bearings) count too: one whose ray crosses an
    /// occupied cell short of `range_max` (less `2 laser_sigma_hit` for the range noise) has
    /// likelihood `laser_no_return_likelihood`, a clear one 1. [`Self::weigh`] passes them
    /// only when the returns leave a direction open ([`weakest_constraint`] below 1).
    #[allow(clippy::too_many_arguments)]
    fn weigh_prob(&mut self, p: &AmclParams, scan: &LaserScan, laser: Pose2, beams: &[Beam], clear: &[f64], particles: &mut [(Pose2, f64)], converged: bool) -> f64 {
        let z_rand = p.laser_z_rand / scan.range_max.max(1e-6);
        if self.log_pz.as_ref().is_none_or(|l| l.0 != scan.range_max) {
            let f = |v: f32| (p.laser_z_hit * v as f64 + z_rand).ln() as f32;
            self.log_pz = Some((scan.range_max, self.field.iter().map(|&v| f(v)).collect(), f(self.far)));
        }
        let Some((_, log_pz, log_far)) = self.log_pz.as_ref() else { return 0.0 };
        let skip = p.do_beamskip && converged;
        // A beam end within beam_skip_distance of an obstacle "agrees with the map".
        let s2 = 2.0 * p.laser_sigma_hit * p.laser_sigma_hit;
        let agree_above = (-(p.beam_skip_distance * p.beam_skip_distance) / s2).exp();
        let nb = beams.len();
        let mut log_all = if skip { vec![0f64; particles.len() * nb] } else { Vec::new() };
        let mut agree = vec![0usize; nb];
        let mut logp = vec![0f64; particles.len()];
        // Each particle's laser pose, for the returns and then for the beams without one.
        let lasers: Vec<Pose2> = particles.iter().map(|(pose, _)| pose.compose(laser)).collect();
        for (k, lp) in lasers.iter().enumerate() {
            let (s, c) = lp.yaw.sin_cos();
            for (j, b) in beams.iter().enumerate() {
                let cell = self.cell(lp.x + c * b.x - s * b.y, lp.y + s * b.x + c * b.y);
                let l = cell.map_or(*log_far, |i| log_pz[i]) as f64;
                if skip {
                    let f = cell.map_or(self.far, |i| self.field[i]) as f64;
                    agree[j] += (f > agree_above) as usize;
                    log_all[k * nb + j] = l;
                } else {
                    logp[k] += l;
                }
            }
        }
        if skip {
            let keep: Vec<bool> = agree.iter().map(|&a| a as f64 / particles.len().max(1) as f64 > p.beam_skip_threshold).collect();
            let skipped = keep.iter().filter(|k| !**k).count();
            // Most beams disagree: the filter has probably converged to a wrong pose; use all.
            let all = skipped as f64 >= nb as f64 * p.beam_skip_error_threshold;
            for (k, l) in logp.iter_mut().enumerate() {
                *l = (0..nb).filter(|&j| all || keep[j]).map(|j| log_all[k * nb + j]).sum();
            }
        }
        if !clear.is_empty() {
            let miss = p.laser_no_return_likelihood.max(1e-300).ln();
            let len = scan.range_max - 2.0 * p.laser_sigma_hit;
            for (l, blocked) in logp.iter_mut().zip(self.clear_rays.blocked_counts(&lasers, clear, len, true).0) {
                *l += blocked as f64 * miss;
            }
        }
        // Scaled by the largest likelihood so that many beams cannot underflow every weight.
        let top = logp.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let top = if top.is_finite() { top } else { 0.0 };
        let mut total = 0.0;
        for ((_, w), l) in particles.iter_mut().zip(&logp) {
            *w *= (l - top).exp();
            total += *w;
        }
        total * top.exp()
    }

    /// Beam model against ranges ray-cast in the map, `1 + sum(pz^3)`.
    fn weigh_beam(&self, p: &AmclParams, scan: &LaserScan, laser: Pose2, beams: &[Beam], particles: &mut [(Pose2, f64)]) -> f64 {
        let max = scan.range_max;
        let s2 = 2.0 * p.laser_sigma_hit * p.laser_sigma_hit;
        let mut total = 0.0;
        for (pose, w) in particles.iter_mut() {
            let lp = pose.compose(laser);
            let mut sum = 0.0;
            for b in beams {
                let expected = self.ray_range(lp.x, lp.y, lp.yaw + b.bearing, max);
                let z = b.range - expected;
                let mut pz = p.laser_z_hit * (-(z * z) / s2).exp();
                if z < 0.0 {
                    pz += p.laser_z_short * p.laser_lambda_short * (-p.laser_lambda_short * b.range).exp();
                }
                if b.range >= max {
                    pz += p.laser_z_max;
                } else {
                    pz += p.laser_z_rand / max;
                }
                sum += pz * pz * pz;
            }
            *w *= 1.0 + sum;
            total += *w;
        }
        total
    }

    /// Distance from (x, y) along heading `a` to the first cell a beam stops in (occupied,
    /// unknown or off the map), capped at `max` (m); exact grid traversal.
    fn ray_range(&self, x: f64, y: f64, a: f64, max: f64) -> f64 {
        self.march(x, y, a, max, &self.stops).0.min(max)
    }

    /// Walks the cells the ray from (x, y) along heading `a` crosses (exact grid traversal)
    /// up to `max` (m): the distance where it stopped and whether a cell of `mask` stopped it
    /// (false: it left the map, distance then where it left, or reached `max`).
    fn march(&self, x: f64, y: f64, a: f64, max: f64, mask: &[bool]) -> (f64, bool) {
        let (dx, dy) = (a.cos(), a.sin());
        let (gx, gy) = ((x - self.origin.0) / self.res, (y - self.origin.1) / self.res);
        let (mut c, mut r) = (gx.floor() as i64, gy.floor() as i64);
        let step = |d: f64| if d > 0.0 { 1 } else { -1 };
        let (sc, sr) = (step(dx), step(dy));
        // Distances (in cells) along the ray between cell edges, and to the next edge; a ray
        // parallel to an axis never crosses that axis's edges.
        let next = |d: f64, g: f64, i: i64| match d {
            d if d.abs() < 1e-12 => (f64::INFINITY, f64::INFINITY),
            d if d > 0.0 => (1.0 / d, (i as f64 + 1.0 - g) / d),
            d => (-1.0 / d, (g - i as f64) / -d),
        };
        let ((dtx, mut tx), (dty, mut ty)) = (next(dx, gx, c), next(dy, gy, r));
        let (max_cells, mut t) = (max / self.res, 0.0);
        loop {
            if !(c >= 0 && r >= 0 && c < self.size.0 && r < self.size.1) {
                return (t * self.res, false);
            }
            if mask[(r * self.size.0 + c) as usize] {
                return (t * self.res, true);
            }
            if tx < ty {
                t = tx;
                tx += dtx;
                c += sc;
            } else {
                t = ty;
                ty += dty;
                r += sr;
            }
            if t >= max_cells {
                return (max, false);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4 x 4 m free room with walls one cell thick, 0.05 m cells, origin (0, 0).
    fn room() -> OccupancyGrid {
        let mut m = OccupancyGrid::new(80, 80, 0.05, Pose2::default(), GRID_FREE);
        for i in 0..80 {
            for (c, r) in [(i, 0), (i, 79), (0, i), (79, i)] {
                m.set(c, r, GRID_OCCUPIED);
            }
        }
        m
    }

    #[test]
    fn the_likelihood_field_is_the_formula_at_each_cell() {
        let mut map = room();
        for (c, r) in [(20, 30), (21, 30), (50, 60), (40, 10)] {
            map.set(c, r, GRID_OCCUPIED);
        }
        for (sigma, max) in [(0.2, 2.0), (0.05, 0.3), (5.0, 100.0), (0.2, f64::INFINITY)] {
            let p = AmclParams { laser_sigma_hit: sigma, laser_likelihood_max_dist: max, ..Default::default() };
            let lm = LaserModel::new(&map, &p);
            let occ: Vec<bool> = map.data.iter().map(|&v| v == GRID_OCCUPIED).collect();
            let d = crate::costmap::edt(&occ, map.width, map.height);
            let s2 = 2.0 * sigma * sigma;
            for i in 0..occ.len() {
                assert_eq!(lm.field[i], (-((d[i] * map.resolution).min(max)).powi(2) / s2).exp() as f32, "cell {i}, sigma {sigma}, max {max}");
            }
        }
    }

    #[test]
    fn the_product_model_uses_the_returns_the_ros_stride_misses() {
        // 360 beams, returns only on 6 beams off ROS's 12-beam stride (far walls elsewhere).
        let mut ranges = vec![f32::NAN; 360];
        for i in [5, 6, 7, 185, 186, 187] {
            ranges[i] = 2.0;
        }
        ranges[100] = 3.5; // at range_max: no return
        ranges[101] = 0.05; // below range_min
        let inc = std::f64::consts::TAU / 360.0;
        let scan = LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges };
        assert_eq!(valid_beams(&scan, 30), vec![5, 6, 7, 185, 186, 187]);
        assert!((0..360).step_by(12).all(|i| !valid_beams(&scan, 30).contains(&i)), "none on the stride");
        // More returns than beams: evenly spaced among the returns, max_beams of them.
        let full = LaserScan { ranges: vec![1.0; 360], ..scan.clone() };
        assert_eq!(valid_beams(&full, 30), (0..360).step_by(12).collect::<Vec<_>>());
        // And the product model weighs with them: a particle off the truth loses.
        let p = AmclParams::default();
        let mut lm = LaserModel::new(&room(), &p);
        let truth = Pose2::new(2.0, 2.0, 0.0);
        let ranges = (0..360).map(|i| if i % 12 == 5 { lm.ray_range(truth.x, truth.y, scan.angle(i), 3.5) as f32 } else { f32::NAN }).collect();
        let sparse = LaserScan { ranges, ..scan };
        let mut parts = vec![(truth, 1.0), (Pose2::new(2.3, 2.0, 0.0), 1.0)];
        lm.weigh(&p, &sparse, Pose2::default(), &mut parts, false);
        assert!(parts[0].1 > 10.0 * parts[1].1, "{parts:?}");
    }

    #[test]
    fn ray_cast_ranges_stop_at_the_first_wall_cell() {
        let lm = LaserModel::new(&room(), &AmclParams::default());
        // From (2.0, 2.0): the east wall's cell starts at x = 3.95.
        assert!((lm.ray_range(2.0, 2.0, 0.0, 10.0) - 1.95).abs() < 1e-9);
        assert!((lm.ray_range(2.0, 2.0, std::f64::consts::PI, 10.0) - 1.95).abs() < 1e-9);
        assert!((lm.ray_range(2.0, 2.0, std::f64::consts::FRAC_PI_2, 10.0) - 1.95).abs() < 1e-9);
        // Diagonal: to the corner cells.
        let d = lm.ray_range(2.0, 2.0, std::f64::consts::FRAC_PI_4, 10.0);
        assert!((d - 1.95 * 2f64.sqrt()).abs() < 0.08, "{d}");
        assert_eq!(lm.ray_range(2.0, 2.0, 0.0, 1.0), 1.0);
    }

    #[test]
    fn beams_without_a_return_tell_where_a_wall_ends() {
        // A wall along x = 4 from y = 0 to y = 4 in a free 10 x 10 m map. From (3, 3.9) facing
        // east the beams below ~6 degrees hit the wall; those above pass its end and return
        // nothing. A particle 0.4 m south sees its returns on the same wall (the likelihood
        // field cannot tell them apart), but it would have had returns where the scan has none.
        let mut map = OccupancyGrid::new(200, 200, 0.05, Pose2::default(), GRID_FREE);
        for r in 0..80 {
            map.set(80, r, GRID_OCCUPIED);
        }
        let truth = Pose2::new(3.0, 3.9, 0.0);
        let south = Pose2::new(3.0, 3.5, 0.0);
        let n = 121;
        let inc = std::f64::consts::FRAC_PI_3 * 2.0 / (n - 1) as f64;
        let weigh = |likelihood: f64| {
            let p = AmclParams { laser_no_return_likelihood: likelihood, laser_max_beams: 60, ..Default::default() };
            let mut lm = LaserModel::new(&map, &p);
            let ranges = (0..n).map(|i| lm.ray_range(truth.x, truth.y, -std::f64::consts::FRAC_PI_3 + i as f64 * inc, 3.5) as f32).map(|r| if r >= 3.5 { f32::NAN } else { r }).collect();
            let scan = LaserScan { angle_min: -std::f64::consts::FRAC_PI_3, angle_max: std::f64::consts::FRAC_PI_3, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges };
            assert!(scan.returns() > 30 && scan.returns() < n - 30, "{}", scan.returns());
            let mut parts = vec![(truth, 1.0), (south, 1.0)];
            lm.weigh(&p, &scan, Pose2::default(), &mut parts, false);
            parts[0].1 / parts[1].1
        };
        let ros = weigh(1.0);
        assert!((0.5..2.0).contains(&ros), "without the beams that return nothing, both fit: {ros}");
        let with = weigh(0.1);
        assert!(with > 1e6, "with them the truth wins: {with}");
        // A clear ray is never blocked by a wall beyond range_max, nor by leaving the map.
        let lm = LaserModel::new(&map, &AmclParams::default());
        let cr = &lm.clear_rays;
        assert!(cr.blocked(3.0, 2.0, 1.0, 0.0, 1.5) && !cr.blocked(3.0, 2.0, 1.0, 0.0, 0.9) && !cr.blocked(3.0, 2.0, -1.0, 0.0, 50.0));
    }

    #[test]
    fn sphere_tracing_finds_what_the_grid_traversal_finds() {
        // Random boxes and single cells in the room; rays from random points, headings and
        // lengths: the tracer agrees with the cell-by-cell traversal over the occupied cells.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        // `count` boxes of up to `size` cells a side, corners in 1..`reach`.
        fn boxes(map: &mut OccupancyGrid, rng: &mut rand_chacha::ChaCha8Rng, count: usize, reach: usize, size: usize) {
            for _ in 0..count {
                let (c, r, w, h) = (rng.gen_range(1..reach), rng.gen_range(1..reach), rng.gen_range(1..size), rng.gen_range(1..size));
                for i in c..c + w {
                    for j in r..r + h {
                        map.set(i, j, GRID_OCCUPIED);
                    }
                }
            }
        }
        let mut map = room();
        boxes(&mut map, &mut rng, 12, 70, 8);
        let lm = LaserModel::new(&map, &AmclParams::default());
        let occupied: Vec<bool> = map.data.iter().map(|&v| v == GRID_OCCUPIED).collect();
        let (mut blocked, n) = (0, 20_000);
        for _ in 0..n {
            let (x, y, a, len) = (rng.gen_range(-0.5..4.5), rng.gen_range(-0.5..4.5), rng.gen_range(-4.0..4.0), rng.gen_range(0.0..5.0));
            let want = lm.march(x, y, a, len, &occupied).1;
            assert_eq!(lm.clear_rays.blocked(x, y, a.cos(), a.sin(), len), want, "from ({x}, {y}) heading {a} for {len} m");
            blocked += want as usize;
        }
        assert!(blocked > n / 4 && blocked < n * 3 / 4, "{blocked}");
        // Clouds of particles, tight to spread, in a 12 x 12 m hall with boxes: the bound that
        // skips traces changes no count.
        let mut hall = OccupancyGrid::new(240, 240, 0.05, Pose2::default(), GRID_FREE);
        for i in 0..240 {
            for (c, r) in [(i, 0), (i, 239), (0, i), (239, i)] {
                hall.set(c, r, GRID_OCCUPIED);
            }
        }
        boxes(&mut hall, &mut rng, 10, 220, 20);
        let lm = LaserModel::new(&hall, &AmclParams::default());
        let mut any_blocked = false;
        for spread in [0.02, 0.1, 0.3, 1.0] {
            let (cx, cy, cyaw) = (rng.gen_range(4.0..8.0), rng.gen_range(4.0..8.0), rng.gen_range(-3.0..3.0));
            let lasers: Vec<Pose2> = (0..400)
                .map(|_| Pose2::new(cx + spread * rng.gen_range(-1.0..1.0), cy + spread * rng.gen_range(-1.0..1.0), cyaw + spread * rng.gen_range(-1.0..1.0)))
                .collect();
            let bearings: Vec<f64> = (0..30).map(|k| -3.1 + k as f64 * 0.21).collect();
            let (exact, all) = lm.clear_rays.blocked_counts(&lasers, &bearings, 3.1, false);
            let (fast, traced) = lm.clear_rays.blocked_counts(&lasers, &bearings, 3.1, true);
            assert_eq!(fast, exact, "spread {spread}");
            any_blocked |= exact.iter().any(|&k| k > 0);
            assert_eq!(all, 400 * 30);
            if spread <= 0.02 {
                assert!(traced < all / 2, "a tight cloud skips most traces: {traced} of {all}");
            }
        }
        assert!(any_blocked);
    }

    /// The weight of a particle at `pose` for a scan taken at `truth` with each model.
    fn weights(model: LaserModelType, truth: Pose2, poses: &[Pose2]) -> Vec<f64> {
        let map = room();
        let p = AmclParams { laser_model_type: model, ..Default::default() };
        let mut lm = LaserModel::new(&map, &p);
        let n = 90;
        let inc = std::f64::consts::TAU / n as f64;
        let ranges = (0..n).map(|i| lm.ray_range(truth.x, truth.y, truth.yaw - std::f64::consts::PI + i as f64 * inc, 3.5) as f32).map(|r| if r >= 3.5 { f32::NAN } else { r }).collect();
        let scan = LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges };
        let mut parts: Vec<(Pose2, f64)> = poses.iter().map(|&q| (q, 1.0)).collect();
        lm.weigh(&p, &scan, Pose2::default(), &mut parts, false);
        parts.iter().map(|x| x.1).collect()
    }

    #[test]
    fn every_model_prefers_the_true_pose() {
        let truth = Pose2::new(1.2, 1.6, 0.4);
        let poses = [truth, Pose2::new(1.4, 1.6, 0.4), Pose2::new(1.2, 1.6, 0.6), Pose2::new(2.5, 2.5, 0.4)];
        for model in [LaserModelType::LikelihoodField, LaserModelType::LikelihoodFieldProb, LaserModelType::Beam] {
            let w = weights(model, truth, &poses);
            assert!(w[1..].iter().all(|&x| x < w[0]), "{model:?}: {w:?}");
        }
        // The product is far sharper than ROS's sum of cubes.
        let cubed = weights(LaserModelType::LikelihoodField, truth, &poses);
        let prob = weights(LaserModelType::LikelihoodFieldProb, truth, &poses);
        assert!(prob[0] / prob[1] > 100.0 * cubed[0] / cubed[1], "{prob:?} {cubed:?}");
    }
}
