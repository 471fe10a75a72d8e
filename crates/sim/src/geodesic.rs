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
/// the clearance radius allowed: every cell the segment crosses is either clear by a whole
/// cell's half-diagonal, or its nearest obstacle segments are at least `radius` from it
/// (exact along walls and at convex corners).
///
/// A first pass samples the segment every [`SAMPLE_STRIDE`] cells and fails at once on a
/// sample in a cell that fails every segment ([`block_margins`]): most segments between
/// distant points cross a wall, and finding that costs a few look-ups instead of a walk. A
/// sample within a millionth of a cell of a cell's edge is skipped, so every sampled cell is
/// one the walk crosses: the answer is the walk's. The walk itself steps over the cells that
/// need no test in one go where the grid says how many there are ([`sure_reach`]).
pub(crate) fn segment_clear(grid: &NavGrid, a: [f64; 2], b: [f64; 2], eps: f64) -> bool {
    segment_verdict(grid, a, b, eps) == Verdict::Clear
}

/// What [`segment_clear`] found of a segment.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    /// The segment is clear.
    Clear,
    /// The segment crosses cell `.0`, which fails every segment through it at this `eps` (its
    /// block margin exceeds `eps`, see [`block_margins`]).
    BlockedAt(usize),
    /// The segment is not clear (it leaves the grid, or passes too near an obstacle in a cell
    /// that some other segment may cross).
    Blocked,
}

/// [`segment_clear`], saying where a blocked segment was stopped when a cell that fails every
/// segment stopped it.
#[inline(always)]
pub(crate) fn segment_verdict(grid: &NavGrid, a: [f64; 2], b: [f64; 2], eps: f64) -> Verdict {
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
        return Verdict::Blocked;
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
                let i = cell(x, y);
                if inner(x) && inner(y) && bits[i >> 6] >> (i & 63) & 1 != 0 {
                    return Verdict::BlockedAt(i);
                }
            }
        } else {
            for _ in 0..samples {
                x += sx;
                y += sy;
                let i = cell(x, y);
                if inner(x) && inner(y) && grid.block_margin[i] as f64 > eps {
                    return Verdict::BlockedAt(i);
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
    // The cells the segment crosses, in order (Amanatides-Woo): after `jx` column and `jy`
    // row boundaries, cell (x0 + sx jx, y0 + sy jy); the next column boundary is at `tx(jx)`
    // along the segment, the next row boundary at `ty(jy)`, and the row's comes first on a tie.
    // (The end points are inside the grid, so truncation is the floor.)
    let (x0, y0) = (fx0 as i64, fy0 as i64);
    let (x1, y1) = (fx1 as i64, fy1 as i64);
    let (dx, dy) = (fx1 - fx0, fy1 - fy0);
    let (sx, sy) = (if dx > 0.0 { 1 } else { -1 }, if dy > 0.0 { 1 } else { -1 });
    let (tx0, t_dx) = first_crossing(fx0, x0, dx);
    let (ty0, t_dy) = first_crossing(fy0, y0, dy);
    let tx = |j: i64| tx0 + j as f64 * t_dx;
    let ty = |j: i64| ty0 + j as f64 * t_dy;
    let steps = (x1 - x0).abs() + (y1 - y0).abs();
    let reach = &grid.sure_reach;
    let (mut jx, mut jy) = (0i64, 0i64);
    loop {
        let (x, y) = (x0 + sx * jx, y0 + sy * jy);
        if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 {
            return Verdict::Blocked;
        }
        let i = y as usize * w + x as usize;
        let k = reach[i] as i64;
        if k == 0 && !check(i) {
            // (`get`, which cannot panic, so that `segment_clear`, which reads no more than
            // that the segment is blocked, loads nothing more.)
            return if grid.block_margin.get(i).is_some_and(|&m| m as f64 > eps) { Verdict::BlockedAt(i) } else { Verdict::Blocked };
        }
        if k >= 2 {
            // Every cell within k - 1 of this one needs no test ([`sure_reach`]): take at once
            // the crossings before the k-th column or row boundary from here (those the
            // traversal takes first, so the same cells follow).
            // (Crossings along one axis lie a fraction 1 / |d| of the segment apart, far above
            // rounding, so the axis whose k-th boundary comes first takes exactly k - 1.)
            let (ax, ay) = (tx(jx + k - 1), ty(jy + k - 1));
            let (nx, ny) = if ax <= ay {
                (k - 1, crossings_before(ty, jy, dy.abs(), ty0, k - 1, ax))
            } else {
                (crossings_before(tx, jx, dx.abs(), tx0, k - 1, ay), k - 1)
            };
            if jx + jy + nx + ny >= steps {
                return Verdict::Clear;
            }
            if nx + ny > 0 {
                (jx, jy) = (jx + nx, jy + ny);
                continue;
            }
        }
        if jx + jy == steps {
            return Verdict::Clear;
        }
        if tx(jx) < ty(jy) {
            jx += 1;
        } else {
            jy += 1;
        }
    }
}

/// Where a segment from `f0` (in cells, in cell `cell`) moving `d` cells crosses its first cell
/// boundary along one axis, as a fraction of its length, and the fraction between boundaries;
/// infinite and 0 when it does not move along that axis.
fn first_crossing(f0: f64, cell: i64, d: f64) -> (f64, f64) {
    let step = (1.0 / d).abs();
    if d > 0.0 {
        (((cell + 1) as f64 - f0) * step, step)
    } else if d < 0.0 {
        ((f0 - cell as f64) * step, step)
    } else {
        (f64::INFINITY, 0.0)
    }
}

/// How many of the crossings `at(j)`, `at(j + 1)`, ... `at(j + most - 1)` come before `t`
/// (`at` is non-decreasing, `at(m) = t0 + m / cells`): worked out from `cells`, then checked
/// against `at` itself.
#[inline(always)]
fn crossings_before(at: impl Fn(i64) -> f64, j: i64, cells: f64, t0: f64, most: i64, t: f64) -> i64 {
    // (NaN, where the segment does not move along this axis, casts to 0.)
    let mut n = (((t - t0) * cells) as i64 - j).clamp(0, most);
    while n > 0 && !(at(j + n - 1) < t) {
        n -= 1;
    }
    while n < most && at(j + n) < t {
        n += 1;
    }
    n
}

/// Per cell of `grid`, the chessboard distance (cells, at most 255) to the nearest cell that
/// [`segment_clear`]'s walk tests (one not clear by [`sure_clearance`]), or off the grid: 0 on
/// such a cell. No cell within `d - 1` of a cell at `d` needs a test, so the walk takes them
/// at once.
pub(crate) fn sure_reach(grid: &NavGrid) -> Vec<u8> {
    let (w, h) = grid.size();
    let sure = sure_clearance(grid);
    // The grid with a border of zeros (off the grid), rows of `pw`.
    let pw = w + 2;
    let mut d = vec![0u8; pw * (h + 2)];
    for (row, cl) in d[pw + 1..].chunks_mut(pw).zip(grid.clearance.chunks(w)) {
        for (x, &c) in row.iter_mut().zip(cl) {
            *x = if c as f64 >= sure { u8::MAX } else { 0 };
        }
    }
    // Two raster passes over the 8-neighbourhood (exact for the chessboard distance), each
    // row from the finished row before it, then along itself.
    let near = |row: &mut [u8], next: &[u8]| {
        for c in 1..pw - 1 {
            row[c] = row[c].min(next[c - 1].min(next[c]).min(next[c + 1]).saturating_add(1));
        }
    };
    for r in 1..=h {
        let (before, rest) = d.split_at_mut(r * pw);
        let row = &mut rest[..pw];
        near(row, &before[(r - 1) * pw..]);
        for c in 1..pw - 1 {
            row[c] = row[c].min(row[c - 1].saturating_add(1));
        }
    }
    for r in (1..=h).rev() {
        let (rest, after) = d.split_at_mut((r + 1) * pw);
        let row = &mut rest[r * pw..];
        near(row, &after[..pw]);
        for c in (1..pw - 1).rev() {
            row[c] = row[c].min(row[c + 1].saturating_add(1));
        }
    }
    let mut out = Vec::with_capacity(w * h);
    for row in d.chunks(pw).skip(1).take(h) {
        out.extend_from_slice(&row[1..=w]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The built-in house's default floor.
    fn house() -> std::sync::Arc<NavGrid> {
        let w = crate::world::World::new(crate::scene::house::default_house(3), Default::default());
        w.grid(w.default_floor().expect("a floor")).expect("a grid")
    }

    /// [`segment_clear`]'s walk as it was before it jumped: every cell the segment crosses, one at
    /// a time.
    fn plain_walk(grid: &NavGrid, a: [f64; 2], b: [f64; 2], eps: f64) -> bool {
        let (w, h) = grid.size();
        let (res, o, sure) = (grid.resolution(), grid.origin(), sure_clearance(grid));
        let (fx0, fy0, fx1, fy1) = ((a[0] - o.x) / res, (a[1] - o.y) / res, (b[0] - o.x) / res, (b[1] - o.y) / res);
        let inside = |x: f64, y: f64| x >= 0.0 && y >= 0.0 && x < w as f64 && y < h as f64;
        if !inside(fx0, fy0) || !inside(fx1, fy1) {
            return false;
        }
        let line = SegmentLine::new(a, b);
        let mut seen = SeenSegments::new();
        let mut check = |i: usize| {
            let cl = grid.clearance[i] as f64;
            cl >= sure || (cl > 0.0 && grid.nearest_segments_clear(i, &line, grid.params.radius - eps, &mut seen).unwrap_or(cl >= grid.params.radius - eps.max(0.25 * res)))
        };
        let (x0, y0) = (fx0.floor() as i64, fy0.floor() as i64);
        let steps = (fx1.floor() as i64 - x0).abs() + (fy1.floor() as i64 - y0).abs();
        let (sx, sy) = (if fx1 > fx0 { 1 } else { -1 }, if fy1 > fy0 { 1 } else { -1 });
        let ((tx0, t_dx), (ty0, t_dy)) = (first_crossing(fx0, x0, fx1 - fx0), first_crossing(fy0, y0, fy1 - fy0));
        // (The crossings summed step by step, as the walk did before it jumped.)
        let (t_dx, t_dy) = (if t_dx == 0.0 { f64::INFINITY } else { t_dx }, if t_dy == 0.0 { f64::INFINITY } else { t_dy });
        let (mut x, mut y, mut t_mx, mut t_my) = (x0, y0, tx0, ty0);
        for _ in 0..=steps {
            if x < 0 || y < 0 || x >= w as i64 || y >= h as i64 || !check(y as usize * w + x as usize) {
                return false;
            }
            if t_mx < t_my {
                x += sx;
                t_mx += t_dx;
            } else {
                y += sy;
                t_my += t_dy;
            }
        }
        true
    }

    #[test]
    fn sure_reach_is_the_chessboard_distance_to_the_cells_a_walk_tests() {
        let grid = house();
        let (w, h) = grid.size();
        let sure = sure_clearance(&grid);
        let tested: Vec<(i64, i64)> = (0..w * h).filter(|&i| !(grid.clearance[i] as f64 >= sure)).map(|i| ((i % w) as i64, (i / w) as i64)).collect();
        assert!(!tested.is_empty() && tested.len() < w * h / 2, "{} of {}", tested.len(), w * h);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for _ in 0..3000 {
            let (c, r) = (rng.gen_range(0..w) as i64, rng.gen_range(0..h) as i64);
            // Off the grid counts as tested: the border is one step beyond the edge cells.
            let edge = (c + 1).min(r + 1).min(w as i64 - c).min(h as i64 - r);
            let want = tested.iter().map(|&(x, y)| (x - c).abs().max((y - r).abs())).fold(edge, i64::min).min(255);
            assert_eq!(grid.sure_reach[r as usize * w + c as usize] as i64, want, "cell ({c}, {r})");
        }
    }

    #[test]
    fn the_walk_jumping_over_sure_cells_answers_as_one_that_tests_every_cell() {
        let grid = house();
        let (w, h) = grid.size();
        let (res, o) = (grid.resolution(), grid.origin());
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        let (mut clear, mut blocked) = (0, 0);
        for k in 0..20_000 {
            let mut p = || [o.x + rng.gen_range(0.0..w as f64) * res, o.y + rng.gen_range(0.0..h as f64) * res];
            let (a, mut b) = (p(), p());
            // Some along rows, columns and diagonals through cell corners (ties in the walk).
            match k % 4 {
                1 => b[1] = a[1],
                2 => b[0] = a[0],
                3 => {
                    let (ca, d) = ([(a[0] - o.x) / res, (a[1] - o.y) / res].map(f64::floor), rng.gen_range(-40..40) as f64);
                    let (a2, b2) = ([o.x + ca[0] * res, o.y + ca[1] * res], [o.x + (ca[0] + d) * res, o.y + (ca[1] + d) * res]);
                    let want = plain_walk(&grid, a2, b2, LOS_EPS);
                    assert_eq!(segment_clear(&grid, a2, b2, LOS_EPS), want, "{a2:?} {b2:?}");
                }
                _ => {}
            }
            for eps in [LOS_EPS, 0.01] {
                let want = plain_walk(&grid, a, b, eps);
                assert_eq!(segment_clear(&grid, a, b, eps), want, "{a:?} {b:?} {eps}");
                if want {
                    clear += 1;
                } else {
                    blocked += 1;
                }
            }
        }
        // Both answers are common, so the comparison means something.
        assert!(clear > 2000 && blocked > 2000, "{clear} clear, {blocked} blocked");
    }
}
