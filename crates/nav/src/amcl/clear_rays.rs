//! Beams without a return against the map: which particles' rays would cross an occupied cell
//! within range (what `likelihood_field_prob` weighs such a beam by).
//!
//! A ray is traced by sphere tracing on the map's clearance (distance to the nearest occupied
//! cell): far from the walls it skips, near them it steps cell by cell, so it finds what a grid
//! traversal finds. Most particles of a converged filter need no trace at all: a particle whose
//! laser stands `dp` from the cloud's mean laser pose and turned `da` from its heading has its
//! ray within `dp + s * da` of the mean ray at distance `s` along it; where the mean ray keeps
//! more clearance than that all along, the particle's ray is clear. That bound is exact (it only
//! skips traces whose answer it knows), so the counts are the same as tracing every ray.

use xhab_types::{normalize_angle, LaserScan, OccupancyGrid, Pose2};

/// Largest clearance the tracer reads (cells).
pub(crate) const CLEARANCE_CAP: u32 = 32;

/// Heading differences (rad) from the cloud's mean for which the clear-ray bound is worked
/// out per beam; a particle turned further is traced.
const HEADING_BINS: [f64; 6] = [0.01, 0.02, 0.05, 0.1, 0.2, 0.4];

/// The map's clearance, for tracing rays.
#[derive(Debug, Clone)]
pub(crate) struct ClearRays {
    /// Per cell: distance from its centre to the nearest occupied cell's centre (cells, 0 in an
    /// occupied cell, at most [`CLEARANCE_CAP`]).
    clearance: Vec<f32>,
    origin: (f64, f64),
    res: f64,
    size: (i64, i64),
}

impl ClearRays {
    /// The clearance of `map` (yaw-0 origin, as the laser models read it) from the squared
    /// distances `d2` (cells^2) of its cells to the nearest occupied cell, exact up to at least
    /// `CLEARANCE_CAP^2` (the likelihood field's [`squared_edt`], worked out once for both).
    ///
    /// [`squared_edt`]: crate::distance_field::squared_edt
    pub(crate) fn new(map: &OccupancyGrid, d2: &[u32]) -> Self {
        let clearance = d2.iter().map(|&k| (k.min(CLEARANCE_CAP * CLEARANCE_CAP) as f32).sqrt()).collect();
        ClearRays { clearance, origin: (map.origin.x, map.origin.y), res: map.resolution, size: (map.width as i64, map.height as i64) }
    }

    /// Clearance (cells) of the cell holding grid point (px, py) (cells), `None` off the map.
    fn at(&self, px: f64, py: f64) -> Option<(f64, i64, i64)> {
        // Truncation is the floor on the map (non-negative coordinates).
        if !(px >= 0.0 && py >= 0.0) {
            return None;
        }
        let (c, r) = (px as i64, py as i64);
        (c < self.size.0 && r < self.size.1).then(|| (self.clearance[(r * self.size.0 + c) as usize] as f64, c, r))
    }

    /// Whether the ray from (x, y) (m) along the unit direction (dx, dy) crosses an occupied
    /// cell within `len` (m) before it leaves the map. From a point in a cell whose centre is D
    /// cells from the nearest occupied centre, nothing occupied is nearer than D - sqrt(2), so
    /// the ray skips that far; nearer the walls it steps to the next cell edge.
    pub(crate) fn blocked(&self, x: f64, y: f64, dx: f64, dy: f64, len: f64) -> bool {
        let (gx, gy) = ((x - self.origin.0) / self.res, (y - self.origin.1) / self.res);
        let len = len / self.res;
        // Distance along the ray (cells) from coordinate g in cell i to the next cell edge along d.
        let to_edge = |g: f64, i: i64, d: f64| match d {
            d if d > 1e-12 => (i as f64 + 1.0 - g) / d,
            d if d < -1e-12 => (g - i as f64) / -d,
            _ => f64::INFINITY,
        };
        let mut t = 0.0;
        loop {
            let (px, py) = (gx + dx * t, gy + dy * t);
            let Some((d, c, r)) = self.at(px, py) else { return false };
            if d == 0.0 {
                return true;
            }
            let skip = d - std::f64::consts::SQRT_2;
            t += if skip >= 1.0 { skip } else { to_edge(px, c, dx).min(to_edge(py, r, dy)) + 1e-9 };
            if t >= len {
                return false;
            }
        }
    }

    /// For each laser pose of `lasers` (m, rad; the particles' lasers in the map), how many of
    /// the beams at `bearings` (rad, in the laser frame) would cross an occupied cell within
    /// `len` (m), and how many rays were traced. `shortcut`: skip the traces the cloud's bound
    /// proves clear (same counts).
    pub(crate) fn blocked_counts(&self, lasers: &[Pose2], bearings: &[f64], len: f64, shortcut: bool) -> (Vec<u32>, usize) {
        let mut counts = vec![0u32; lasers.len()];
        let mut traced = 0;
        if lasers.is_empty() {
            return (counts, traced);
        }
        // The cloud's mean laser pose, and each particle's offset and turn from it.
        let n = lasers.len() as f64;
        let (mx, my) = (lasers.iter().map(|l| l.x).sum::<f64>() / n, lasers.iter().map(|l| l.y).sum::<f64>() / n);
        let myaw = lasers.iter().map(|l| l.yaw.sin()).sum::<f64>().atan2(lasers.iter().map(|l| l.yaw.cos()).sum::<f64>());
        let offsets: Vec<(f64, Option<usize>)> = lasers
            .iter()
            .map(|l| {
                let da = normalize_angle(l.yaw - myaw).abs();
                ((l.x - mx).hypot(l.y - my), HEADING_BINS.iter().position(|&b| da <= b))
            })
            .collect();
        let steps = (len / self.res).ceil().max(0.0) as usize;
        for &b in bearings {
            // Per heading bin: the largest offset whose rays this bound proves clear (m).
            let mut room = [f64::NEG_INFINITY; HEADING_BINS.len()];
            if shortcut {
                let (s, c) = (myaw + b).sin_cos();
                let (gx, gy) = ((mx - self.origin.0) / self.res, (my - self.origin.1) / self.res);
                room = [f64::INFINITY; HEADING_BINS.len()];
                for j in 0..=steps {
                    // Between samples the mean ray moves a cell: one cell less clearance.
                    let sj = j as f64;
                    let clear = match self.at(gx + c * sj, gy + s * sj) {
                        Some((d, _, _)) => (d - std::f64::consts::SQRT_2 - 1.0) * self.res,
                        None => f64::NEG_INFINITY,
                    };
                    for (k, bin) in HEADING_BINS.iter().enumerate() {
                        room[k] = room[k].min(clear - (sj + 1.0) * self.res * bin);
                    }
                    if room[0] <= 0.0 {
                        break;
                    }
                }
            }
            for (i, l) in lasers.iter().enumerate() {
                let (dp, bin) = offsets[i];
                if bin.is_some_and(|k| dp < room[k]) {
                    continue;
                }
                let (s, c) = (l.yaw + b).sin_cos();
                counts[i] += self.blocked(l.x, l.y, c, s, len) as u32;
                traced += 1;
            }
        }
        (counts, traced)
    }
}

/// How well the returns of `scan` pin the laser's position down: the smaller eigenvalue of
/// `sum n n^T` over the returns' surface normals `n` (unit; each from the return's two
/// neighbours, where both are returns within `max_gap` m of it). A room's corner gives about
/// half the returns; one straight wall, or none, about 0.
pub(crate) fn weakest_constraint(scan: &LaserScan, max_gap: f64) -> f64 {
    let point = |i: usize| {
        let (r, a) = (scan.ranges[i] as f64, scan.angle(i));
        (r * a.cos(), r * a.sin())
    };
    let (mut sxx, mut sxy, mut syy) = (0.0, 0.0, 0.0);
    for i in 1..scan.ranges.len().saturating_sub(1) {
        if !(scan.is_return(i - 1) && scan.is_return(i) && scan.is_return(i + 1)) {
            continue;
        }
        let (a, p, b) = (point(i - 1), point(i), point(i + 1));
        let near = |q: (f64, f64)| (q.0 - p.0).hypot(q.1 - p.1) <= max_gap;
        if !(near(a) && near(b)) {
            continue;
        }
        let (tx, ty) = (b.0 - a.0, b.1 - a.1);
        let l2 = tx * tx + ty * ty;
        if l2 <= 0.0 {
            continue;
        }
        // The normal (-ty, tx) / |t|: n n^T = (ty^2, -tx ty; -tx ty, tx^2) / |t|^2.
        sxx += ty * ty / l2;
        sxy -= tx * ty / l2;
        syy += tx * tx / l2;
    }
    let (m, d) = (0.5 * (sxx + syy), (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt());
    m - d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 360-beam scan (1 degree apart, range_max 3.5) from the origin of the points where
    /// `hit(angle)` says a beam returns (m), NaN where it says none.
    fn scan(hit: impl Fn(f64) -> Option<f64>) -> LaserScan {
        let inc = std::f64::consts::TAU / 360.0;
        let ranges = (0..360).map(|i| hit(-std::f64::consts::PI + i as f64 * inc).map_or(f32::NAN, |r| r as f32)).collect();
        LaserScan { angle_min: -std::f64::consts::PI, angle_max: std::f64::consts::PI - inc, angle_increment: inc, range_min: 0.1, range_max: 3.5, ranges }
    }

    /// Range along heading `a` to the line x = `d` (m), within the laser's range.
    fn wall_x(a: f64, d: f64) -> Option<f64> {
        let r = d / a.cos();
        (r > 0.0 && r < 3.5).then_some(r)
    }

    #[test]
    fn one_straight_wall_leaves_its_direction_open_and_a_corner_does_not() {
        let wall = scan(|a| wall_x(a, 1.0));
        assert!(wall.returns() > 100);
        assert!(weakest_constraint(&wall, 0.3) < 1e-6, "{}", weakest_constraint(&wall, 0.3));
        // A corridor: two parallel walls.
        let corridor = scan(|a| wall_x(a, 1.0).or(wall_x(a, -1.0)));
        assert!(weakest_constraint(&corridor, 0.3) < 1e-6);
        // A corner: x = 1 and y = 1.
        let corner = scan(|a| {
            let ry = 1.0 / a.sin();
            let ry = (ry > 0.0 && ry < 3.5).then_some(ry);
            match (wall_x(a, 1.0), ry) {
                (Some(x), Some(y)) => Some(x.min(y)),
                (x, y) => x.or(y),
            }
        });
        assert!(weakest_constraint(&corner, 0.3) > 20.0, "{}", weakest_constraint(&corner, 0.3));
        // No return at all: nothing pinned.
        assert_eq!(weakest_constraint(&scan(|_| None), 0.3), 0.0);
    }
}
