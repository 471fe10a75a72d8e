//! Geodesic distance: shortest paths for the disc agent in continuous space.
//!
//! A [`GeodesicField`] holds, for every navigable cell of a [`NavGrid`], the length of the
//! shortest any-angle path from the cell centre to the nearest goal, and the *anchor* that
//! path passes last: a goal, or a bend point on the region's boundary. It is built by a
//! Dijkstra wavefront whose nodes inherit their parent's anchor while they can see it (as in
//! Theta*), and bend only at convex corners of the region, whose bend points lie exactly at
//! `radius` from the obstacle. A query at any point `p` is then `D(anchor) + |anchor - p|`:
//! O(1), with no grid-step error.

use crate::navgrid::{NavGrid, SeenSegments, SegmentLine};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use xhab_types::Point2;

/// Shortest-path distances from every navigable cell to a set of goals.
#[derive(Debug, Clone)]
pub struct GeodesicField {
    goals: Vec<Point2>,
    goal_islands: Vec<u32>,
    /// Distance at each cell centre (m); infinite where unreached.
    dist: Vec<f64>,
    /// Distance at each cell's anchor point (m).
    anchor_dist: Vec<f64>,
    /// Anchor per cell: a cell index (its anchor point), `n + k` for goal k, `u32::MAX` unreached.
    parent: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl GeodesicField {
    /// Computes the field towards `goals` (m, planar) on `grid`. Goals off the region are
    /// attached to the nearest navigable cell within two cells; farther ones are ignored.
    pub fn new(grid: &NavGrid, goals: &[Point2]) -> GeodesicField {
        Self::build(grid, goals)
    }

    fn build(grid: &NavGrid, goals: &[Point2]) -> GeodesicField {
        let (w, h) = grid.size();
        let n = w * h;
        let mut f = GeodesicField {
            goals: goals.to_vec(),
            goal_islands: Vec::new(),
            dist: vec![f64::INFINITY; n],
            anchor_dist: vec![f64::INFINITY; n],
            parent: vec![NONE; n],
        };
        let mut heap = BinaryHeap::new();
        for (k, &g) in goals.iter().enumerate() {
            let Some(i) = grid.cell_of(g).filter(|&i| grid.is_nav_cell(i)).or_else(|| grid.nearest_nav_cell(g, 2)) else {
                continue;
            };
            f.goal_islands.push(grid.island_of[i]);
            let c = grid.center(i);
            let d = (c[0] - g.x).hypot(c[1] - g.y);
            if d < f.dist[i] {
                f.dist[i] = d;
                f.parent[i] = (n + k) as u32;
                heap.push(Reverse((d.to_bits(), i as u32)));
            }
        }
        let mut done = vec![false; n];
        while let Some(Reverse((_, m))) = heap.pop() {
            let m = m as usize;
            if done[m] {
                continue;
            }
            done[m] = true;
            let q = f.parent[m];
            // The distance at m's own anchor point, for paths that bend at m.
            f.anchor_dist[m] = if grid.corner[m] {
                let (qp, qd) = f.anchor_of(grid, q);
                qd + dist2(qp, grid.anchor[m])
            } else {
                f.dist[m]
            };
            let (qp, qd) = f.anchor_of(grid, q);
            let (c, rr) = ((m % w) as isize, (m / w) as isize);
            for (dc, dr) in [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (-1, 1), (1, -1), (1, 1)] {
                let (kc, kr) = (c + dc, rr + dr);
                if kc < 0 || kr < 0 || kc >= w as isize || kr >= h as isize {
                    continue;
                }
                let k = (kr * w as isize + kc) as usize;
                if done[k] || !grid.is_nav_cell(k) {
                    continue;
                }
                if dc != 0 && dr != 0 {
                    // No squeezing diagonally between two blocked cells.
                    let a = (rr * w as isize + kc) as usize;
                    let b = (kr * w as isize + c) as usize;
                    if !grid.is_nav_cell(a) || !grid.is_nav_cell(b) {
                        continue;
                    }
                }
                let ck = grid.center(k);
                // Through m's anchor first (a line of sight test only when it would improve k),
                // else bending at m.
                let via_q = qd + dist2(qp, ck);
                let (cand, par) = if via_q < f.dist[k] && f.parent[k] != q && segment_clear(grid, qp, ck, LOS_EPS) {
                    (via_q, q)
                } else {
                    (f.anchor_dist[m] + dist2(grid.anchor[m], ck), m as u32)
                };
                if cand < f.dist[k] {
                    f.dist[k] = cand;
                    f.parent[k] = par;
                    heap.push(Reverse((cand.to_bits(), k as u32)));
                }
            }
        }
        f
    }

    /// The goals (m).
    pub fn goals(&self) -> &[Point2] {
        &self.goals
    }

    /// Anchor point and distance of parent id `q`.
    fn anchor_of(&self, grid: &NavGrid, q: u32) -> ([f64; 2], f64) {
        let n = self.dist.len();
        if q as usize >= n {
            let g = self.goals[q as usize - n];
            ([g.x, g.y], 0.0)
        } else {
            (grid.anchor[q as usize], self.anchor_dist[q as usize])
        }
    }

    /// The reached cell that stands for `p`: its own, or the nearest reached one within two cells.
    fn cell_for(&self, grid: &NavGrid, p: Point2) -> Option<usize> {
        let i = grid.cell_of(p)?;
        if self.parent[i] != NONE {
            return Some(i);
        }
        let j = grid.nearest_nav_cell(p, 2)?;
        (self.parent[j] != NONE).then_some(j)
    }

    /// Geodesic distance from `p` (m, planar) to the nearest goal (m); infinite when `p` is
    /// off the region or on an island without a goal.
    pub fn distance(&self, grid: &NavGrid, p: Point2) -> f64 {
        match self.cell_for(grid, p) {
            Some(i) => {
                let (a, d) = self.anchor_of(grid, self.parent[i]);
                d + dist2(a, [p.x, p.y])
            }
            None => f64::INFINITY,
        }
    }
}

/// Geodesic distance between two points of one floor (m); infinite across islands. Answered
/// by the floor's [`CornerGraph`](crate::corner_graph::CornerGraph), no field needed.
pub fn geodesic_distance(grid: &NavGrid, from: Point2, to: Point2) -> f64 {
    grid.corner_graph().distance(grid, from, to)
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Tolerance of the line-of-sight test (m): how far inside the clearance radius a segment
/// may pass. Bend points lie exactly on the radius, one cell apart along an arc, and the chord
/// between two of them dips about 3 mm inside it; a path that cuts a corner by this much is
/// shorter than the exact one by under 1 cm.
pub(crate) const LOS_EPS: f64 = 0.003;

/// A bound (in cells) on the distance from a cell's centre to any point of the cell.
const HALF_DIAGONAL: f64 = 0.7072;

/// Cells between the samples of [`segment_clear`]'s first pass.
const SAMPLE_STRIDE: f64 = 6.0;

/// One cell in the fixed point of [`segment_clear`]'s samples.
const FIXED_ONE: f64 = 4_294_967_296.0;

/// Per cell of `grid`, the line-of-sight tolerance (m) below which [`segment_clear`]'s test of
/// that cell fails for every segment through it: infinite where the cell is off the region,
/// `radius - d - half diagonal` where the cell's nearest obstacle segment is `d` from its
/// centre (every point of the cell is nearer to it than the radius by that much), `radius -
/// clearance` where the edge of the floor is the only obstacle near (and more than a quarter
/// cell inside the radius), and minus infinity where some segment through the cell may pass.
/// Rounded down, so that a sample in such a cell rejects only what the exact test rejects.
pub(crate) fn block_margins(grid: &NavGrid) -> Vec<f32> {
    let (w, h) = grid.size();
    let res = grid.resolution();
    let r = grid.params.radius;
    let sure = sure_clearance(grid);
    (0..w * h)
        .map(|i| {
            let cl = grid.clearance[i] as f64;
            if cl >= sure {
                return f32::NEG_INFINITY;
            }
            if cl <= 0.0 {
                return f32::INFINITY;
            }
            let c = grid.center(i);
            let m = match grid.nearest_point(i, c) {
                Some(q) => r - ((q[0] - c[0]).powi(2) + (q[1] - c[1]).powi(2)).sqrt() - HALF_DIAGONAL * res,
                // The walk's test reads the clearance only where no segment is near at all.
                None if grid.nearest_segment_distance(i, &[c, c]).is_none() && r - cl > 0.25 * res => r - cl,
                None => return f32::NEG_INFINITY,
            };
            if m <= 0.0 {
                f32::NEG_INFINITY
            } else {
                (m - 1e-6) as f32
            }
        })
        .collect()
}

/// The clearance (m) from which every segment through a cell is clear there: the radius plus
/// the cell's half-diagonal. [`segment_clear`]'s walk settles a cell by its clearance alone
/// from here up (and at 0, off the region); between, it reads the cell's near segments.
pub(crate) fn sure_clearance(grid: &NavGrid) -> f64 {
    grid.params.radius + HALF_DIAGONAL * grid.resolution()
}

/// One bit per cell: whether its block margin (see [`block_margins`]) exceeds [`LOS_EPS`].
pub(crate) fn los_bits(margins: &[f32]) -> Vec<u64> {
    let mut bits = vec![0u64; margins.len().div_ceil(64)];
    for (i, &m) in margins.iter().enumerate() {
        if m as f64 > LOS_EPS {
            bits[i >> 6] |= 1 << (i & 63);
        }
    }
    bits
}

/// Whether the agent can slide along the straight segment from `a` to `b` (m), `eps` (m) inside
/// the clearance radius allowed: every cell the
/// segment crosses is either clear by a whole cell's half-diagonal, or its nearest obstacle
/// obstacle segment is at least `radius` from it (exact along walls and at convex corners).
///
/// A first pass samples the segment every [`SAMPLE_STRIDE`] cells and fails at once on a
/// sample in a cell that fails every segment ([`block_margins`]): most segments between
/// distant points cross a wall, and finding that costs a few look-ups instead of a walk. A
/// sample within a millionth of a cell of a cell's edge is skipped, so every sampled cell is
/// one the walk crosses: the answer is the walk's.
pub(crate) fn segment_clear(grid: &NavGrid, a: [f64; 2], b: [f64; 2], eps: f64) -> bool {
    let (w, h) = grid.size();
    let res = grid.resolution();
    let o = grid.origin();
    let r = grid.params.radius;
    let sure = sure_clearance(grid);
    // The end points in cells.
    let fx0 = (a[0] - o.x) / res;
    let fy0 = (a[1] - o.y) / res;
    let fx1 = (b[0] - o.x) / res;
    let fy1 = (b[1] - o.y) / res;
    let inside = |x: f64, y: f64| x >= 0.0 && y >= 0.0 && x < w as f64 && y < h as f64;
    if !inside(fx0, fy0) || !inside(fx1, fy1) {
        return false;
    }
    let samples = ((fx1 - fx0).abs().max((fy1 - fy0).abs()) / SAMPLE_STRIDE) as usize;
    if samples > 0 {
        // The samples in fixed point (cells times 2^32; coordinates are non-negative here), so
        // that each costs two additions. A sample is used only when it is farther from its
        // cell's edges than a millionth of a cell plus the rounding of the fixed point (half a
        // unit per sample and at the start).
        let step = 1.0 / (samples + 1) as f64;
        // Rounded half away from zero, without a libm call.
        let fixed = |v: f64| (v * FIXED_ONE + 0.5f64.copysign(v)) as i64;
        let (mut x, mut y) = (fixed(fx0), fixed(fy0));
        let (sx, sy) = (fixed((fx1 - fx0) * step), fixed((fy1 - fy0) * step));
        let margin = (1e-6 * FIXED_ONE) as u32 + samples as u32 + 2;
        let span = u32::MAX - 2 * margin;
        let inner = |v: i64| (v as u32).wrapping_sub(margin) < span;
        let cell = |x: i64, y: i64| (y >> 32) as usize * w + (x >> 32) as usize;
        if eps <= LOS_EPS {
            // The bits (small enough for the first-level cache) where they hold for `eps`.
            let bits = &grid.los_blocked;
            for _ in 0..samples {
                x += sx;
                y += sy;
                if inner(x) && inner(y) && {
                    let i = cell(x, y);
                    bits[i >> 6] >> (i & 63) & 1 != 0
                } {
                    return false;
                }
            }
        } else {
            for _ in 0..samples {
                x += sx;
                y += sy;
                if inner(x) && inner(y) && grid.block_margin[cell(x, y)] as f64 > eps {
                    return false;
                }
            }
        }
    }
    // The walk (Amanatides-Woo traversal of the cells the segment crosses), for segments the
    // samples did not settle; only it needs the segment's own frame.
    let line = SegmentLine::new(a, b);
    let mut seen = SeenSegments::new();
    let mut check = |i: usize| -> bool {
        let cl = grid.clearance[i] as f64;
        if cl >= sure {
            return true;
        }
        if cl <= 0.0 {
            return false;
        }
        match grid.nearest_segments_clear(i, &line, r - eps, &mut seen) {
            Some(clear) => clear,
            None => cl >= r - eps.max(0.25 * res),
        }
    };
    let (mut x, mut y) = (fx0.floor() as i64, fy0.floor() as i64);
    let (x1, y1) = (fx1.floor() as i64, fy1.floor() as i64);
    let (dx, dy) = (fx1 - fx0, fy1 - fy0);
    let sx = if dx > 0.0 { 1 } else { -1 };
    let sy = if dy > 0.0 { 1 } else { -1 };
    let t_dx = if dx != 0.0 { (1.0 / dx).abs() } else { f64::INFINITY };
    let t_dy = if dy != 0.0 { (1.0 / dy).abs() } else { f64::INFINITY };
    let mut t_mx = if dx > 0.0 { ((x + 1) as f64 - fx0) * t_dx } else if dx < 0.0 { (fx0 - x as f64) * t_dx } else { f64::INFINITY };
    let mut t_my = if dy > 0.0 { ((y + 1) as f64 - fy0) * t_dy } else if dy < 0.0 { (fy0 - y as f64) * t_dy } else { f64::INFINITY };
    let steps = (x1 - x).abs() + (y1 - y).abs();
    if !check((y as usize) * w + x as usize) {
        return false;
    }
    for _ in 0..steps {
        if t_mx < t_my {
            x += sx;
            t_mx += t_dx;
        } else {
            y += sy;
            t_my += t_dy;
        }
        if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 || !check((y as usize) * w + x as usize) {
            return false;
        }
    }
    true
}
