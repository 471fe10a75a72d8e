//! The corner graph of one floor: the points where shortest paths can bend, and the straight
//! legs between them, built once per [`NavGrid`].
//!
//! A shortest path of the disc agent is straight except where it wraps around a convex corner
//! of an obstacle, at exactly the agent radius from it. The graph's *nodes* are the boundary
//! cells near such corners (see [`reflex_cells`]: convex vertices of the obstacle segments,
//! reflex corners of the floor's edge), at the anchors the grid already places on the
//! region's boundary (the same bend points as [`GeodesicField`]'s, less those along straight
//! walls), and points on the arcs about the corners in narrow passages ([`arc_nodes`]).
//! Two nodes are joined when they see each other ([`segment_clear`]) and the leg is *taut* at
//! both ends: a path that bends at a node leaves it along the boundary's tangent, never
//! straight away from the obstacle, so legs within [`LEG_TAUT_COS`] of a node's outward normal
//! are left out (most of the pairs, and none that a shortest path uses). Nor is a leg tested that
//! leaves a node steeply into the obstacle the node stands off ([`into_cos_for`]): it passes
//! nearer to that obstacle than the radius allows, whatever lies beyond.
//!
//! Queries join their end points to the nodes they see, lazily: a goal-directed search over
//! the graph tests the line of sight of a node only when it would settle the answer. See
//! [`CornerGraph::distance`] and [`crate::goal_field::GoalField`].
//!
//! [`GeodesicField`]: crate::geodesic::GeodesicField

use crate::geodesic::{segment_clear, segment_verdict, Verdict, LOS_EPS};
use crate::navgrid::convex_vertices::ConvexVertices;
use crate::navgrid::{closest_on_segment, NavGrid};
use cut_heap::CutHeap;
use passages::{arc_nodes, arc_radius, arc_reach, arc_vertex, passage_cells};
use rayon::prelude::*;
use walls::Walls;
use xhab_types::Point2;

mod cut_heap;
mod passages;
mod walls;
#[cfg(test)]
mod route_probe;

/// Largest cosine between the line from a point to a node and the node's outward normal for
/// the node to be the point's first bend ([`CornerGraph::joins`]), when the normal comes from
/// the exact obstacle segments (bend points one cell apart on an arc of the agent's radius
/// turn by up to ~30 degrees; this keeps lines up to 50 degrees off the tangent). Legs between
/// nodes use [`LEG_TAUT_COS`].
pub const TAUT_COS: f64 = 0.77;

/// The same for nodes on the edge of the floor, whose normal comes from the cells (coarser).
const TAUT_COS_COARSE: f64 = 0.95;

/// [`TAUT_COS`] for the legs between two nodes (up to 44 degrees off the tangent). A query's
/// end point may stand close to a corner and join a node steeply, so the ends keep
/// [`TAUT_COS`]; between nodes, a tighter cone leaves out an eighth to a fifth of the legs. On
/// 30,000 random pairs in each of the seven shared scenes every answer is the same to the bit
/// with 0.7 and 0.65; from 0.6 down two of cpr_office's come out longer (by up to 0.54%: their
/// path wraps a corner through a leg 40 degrees off the tangent there).
const LEG_TAUT_COS: f64 = 0.7;

/// Bend points of one floor and the taut legs between them.
#[derive(Debug, Clone)]
pub struct CornerGraph {
    /// Position of each node (m): its cell's anchor on the region's boundary.
    pos: Vec<[f64; 2]>,
    /// Outward unit normal of the boundary at each node ([0, 0] when unknown: no pruning).
    normal: Vec<[f64; 2]>,
    /// Largest cosine between a taut leg and the normal, per node.
    taut: Vec<f64>,
    /// Island of each node.
    island: Vec<u32>,
    /// Legs: those of node k are `leg_to[start[k]..start[k + 1]]` (the other node) and
    /// `leg_len` there (m), in the other node's order.
    start: Vec<u32>,
    leg_to: Vec<u32>,
    leg_len: Vec<f64>,
    /// The nodes by square of [`BUCKET_M`]: each non-empty square's bounds (m: x min, y min,
    /// x max, y max) and its nodes, `bucket_nodes[bucket_start[b]..bucket_start[b + 1]]`, in
    /// node order; a query seeds a square's nodes only when its search gets that far.
    bucket_rect: Vec<[f64; 4]>,
    bucket_start: Vec<u32>,
    bucket_nodes: Vec<u32>,
}

/// Side of the squares a query seeds its search by (m).
const BUCKET_M: f64 = 1.0;

impl CornerGraph {
    /// Builds the graph of `grid` (in parallel over nodes; the same graph for any thread count).
    pub fn new(grid: &NavGrid) -> CornerGraph {
        let passage = passage_cells(grid);
        let near_passage = arc_reach(grid, &passage);
        // A storey with stairs counts each segment only for the cells whose body band it
        // reaches, so which segments meet at a vertex depends on the cell: no vertex is called
        // flat there.
        let convex = (!grid.has_stairs()).then(|| convex_vertices(grid, &near_passage));
        let cells = reflex_cells(grid, &passage, convex.as_ref());
        let mut g = CornerGraph {
            pos: cells.iter().map(|&i| grid.anchor[i]).collect(),
            normal: Vec::with_capacity(cells.len()),
            taut: Vec::with_capacity(cells.len()),
            island: cells.iter().map(|&i| grid.island_of[i]).collect(),
            start: Vec::new(),
            leg_to: Vec::new(),
            leg_len: Vec::new(),
            bucket_rect: Vec::new(),
            bucket_start: Vec::new(),
            bucket_nodes: Vec::new(),
        };
        for &i in &cells {
            let (n, t) = outward_normal(grid, i);
            g.normal.push(n);
            g.taut.push(t);
        }
        for (p, n, island) in arc_nodes(grid, &passage, &near_passage, convex.as_ref()) {
            g.pos.push(p);
            g.normal.push(n);
            g.taut.push(TAUT_COS);
            g.island.push(island);
        }
        let n = g.pos.len();
        // Each node's legs to the nodes after it, then mirrored. The taut and island tests
        // run first over all later nodes without a branch, into one flag per node (about half
        // the pairs pass, at random), leaving the candidates for the line-of-sight test.
        let (xs, ys): (Vec<f64>, Vec<f64>) = g.pos.iter().map(|p| (p[0], p[1])).unzip();
        let (nx, ny): (Vec<f64>, Vec<f64>) = g.normal.iter().map(|m| (m[0], m[1])).unzip();
        // A leg that leaves a node steeply into the obstacle it stands off cannot be clear:
        // see `into_cos_for`. Only nodes whose normal comes from an obstacle point at the radius
        // (or the arc radius) are asked.
        let (into, reach2) = (into_cos_for(grid.params.radius, arc_radius(grid)), arc_radius(grid).powi(2));
        let exact: Vec<bool> = g.taut.iter().map(|&t| t == TAUT_COS).collect();
        let taut: Vec<f64> = g.taut.iter().map(|&t| if t == TAUT_COS { LEG_TAUT_COS } else { t }).collect();
        let half: Vec<Vec<(u32, f64)>> = (0..n)
            .into_par_iter()
            .map_init(|| (Vec::new(), Walls::default()), |(pass, walls), a| {
                let (xa, ya, nxa, nya, ta, ia) = (xs[a], ys[a], nx[a], ny[a], taut[a], g.island[a]);
                // The later nodes' arrays cut to one length, so that the loop reads them
                // without bounds checks (and runs over several nodes at once).
                let len = n - a - 1;
                let (xb, yb, nxb, nyb) = (&xs[a + 1..][..len], &ys[a + 1..][..len], &nx[a + 1..][..len], &ny[a + 1..][..len]);
                let (tb, eb, ib) = (&taut[a + 1..][..len], &exact[a + 1..][..len], &g.island[a + 1..][..len]);
                let exact_a = exact[a];
                pass.clear();
                pass.resize(len, false);
                let pass = &mut pass[..len];
                for j in 0..len {
                    let (dx, dy) = (xb[j] - xa, yb[j] - ya);
                    let l2 = dx * dx + dy * dy;
                    // `is_taut` at both ends without the division: `d . n <= taut |d|`.
                    let (da, db) = (dx * nxa + dy * nya, -dx * nxb[j] - dy * nyb[j]);
                    // (every node's taut cosine is positive)
                    let taut_a = (da <= 0.0) | (da * da <= ta * ta * l2);
                    let taut_b = (db <= 0.0) | (db * db <= tb[j] * tb[j] * l2);
                    // `d . n < -into |d|` at either end, for a leg longer than the arc radius.
                    let long = l2 > reach2;
                    let into_a = exact_a & long & heads_into(da, l2, into);
                    let into_b = eb[j] & long & heads_into(db, l2, into);
                    pass[j] = (ib[j] == ia) & (l2 >= 1e-18) & taut_a & taut_b & !into_a & !into_b;
                }
                let pa = g.pos[a];
                let mut out = Vec::new();
                // The walls the tests from `a` run into settle the later tests that must cross
                // them (`walls.rs`).
                walls.clear();
                for b in (0..len).filter(|&j| pass[j]).map(|j| a + 1 + j) {
                    let pb = g.pos[b];
                    if sees(grid, walls, pa, pb, LOS_EPS) {
                        let d = [pb[0] - pa[0], pb[1] - pa[1]];
                        out.push((b as u32, (d[0] * d[0] + d[1] * d[1]).sqrt()));
                    }
                }
                out
            })
            .collect();
        let mut adj: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        for (a, list) in half.iter().enumerate() {
            for &(b, l) in list {
                adj[a].push((b, l));
                adj[b as usize].push((a as u32, l));
            }
        }
        g.start.push(0);
        for list in &mut adj {
            list.sort_by_key(|e| e.0);
            g.leg_to.extend(list.iter().map(|e| e.0));
            g.leg_len.extend(list.iter().map(|e| e.1));
            g.start.push(g.leg_to.len() as u32);
        }
        g.fill_buckets();
        g
    }

    /// Sorts the nodes into squares of [`BUCKET_M`] (see `bucket_rect`).
    fn fill_buckets(&mut self) {
        if self.pos.is_empty() {
            self.bucket_start.push(0);
            return;
        }
        let (x0, y0) = self.pos.iter().fold((f64::INFINITY, f64::INFINITY), |(x, y), p| (x.min(p[0]), y.min(p[1])));
        let square = |p: &[f64; 2]| (((p[1] - y0) / BUCKET_M) as u64, ((p[0] - x0) / BUCKET_M) as u64);
        let mut order: Vec<((u64, u64), u32)> = self.pos.iter().enumerate().map(|(k, p)| (square(p), k as u32)).collect();
        order.sort_unstable();
        self.bucket_start.push(0);
        for (i, &(sq, k)) in order.iter().enumerate() {
            if i == 0 || order[i - 1].0 != sq {
                // A new square: the previous one ends here.
                if i > 0 {
                    self.bucket_start.push(self.bucket_nodes.len() as u32);
                }
                let (xa, ya) = (x0 + sq.1 as f64 * BUCKET_M, y0 + sq.0 as f64 * BUCKET_M);
                self.bucket_rect.push([xa, ya, xa + BUCKET_M, ya + BUCKET_M]);
            }
            self.bucket_nodes.push(k);
        }
        self.bucket_start.push(self.bucket_nodes.len() as u32);
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether the graph has no node (a region without reflex corners: every path is straight).
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Number of legs (each counted once).
    pub fn leg_count(&self) -> usize {
        self.leg_to.len() / 2
    }

    /// Position of node `k` (m).
    pub(crate) fn pos(&self, k: usize) -> [f64; 2] {
        self.pos[k]
    }

    /// Island of node `k`.
    pub(crate) fn island(&self, k: usize) -> u32 {
        self.island[k]
    }

    /// The legs of node `k`: (other node, length in m).
    pub(crate) fn legs(&self, k: usize) -> impl Iterator<Item = (u32, f64)> + '_ {
        let (lo, hi) = (self.start[k] as usize, self.start[k + 1] as usize);
        self.leg_to[lo..hi].iter().copied().zip(self.leg_len[lo..hi].iter().copied())
    }

    /// Whether a leg leaving node `k` along unit direction `u` can be part of a taut path.
    pub(crate) fn is_taut(&self, k: usize, u: [f64; 2]) -> bool {
        let n = self.normal[k];
        u[0] * n[0] + u[1] * n[1] <= self.taut[k]
    }

    /// Whether node `k` can be the first bend of a shortest path from point `p` (m): a taut
    /// leg that `p` sees, `eps` (m) inside the clearance radius allowed.
    pub(crate) fn joins(&self, grid: &NavGrid, k: usize, p: [f64; 2], eps: f64) -> bool {
        self.may_join(grid, k, p, eps).unwrap_or_else(|| segment_clear(grid, p, self.pos[k], eps))
    }

    /// [`CornerGraph::joins`] where its answer needs no line of sight: `Some(true)` for `p`
    /// on the node, `Some(false)` for a leg that is not taut or heads steeply into the
    /// node's obstacle; `None` when the line of sight decides.
    #[inline]
    fn may_join(&self, grid: &NavGrid, k: usize, p: [f64; 2], eps: f64) -> Option<bool> {
        let a = self.pos[k];
        let d = [p[0] - a[0], p[1] - a[1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if l < 1e-9 {
            return Some(true);
        }
        if !self.is_taut(k, [d[0] / l, d[1] / l]) {
            return Some(false);
        }
        // Steeply into the obstacle the node stands off: too near it (see `into_cos_for`; the
        // bound is at least `INTO_COS_MIN`, so most legs are settled without working it out).
        let dn = d[0] * self.normal[k][0] + d[1] * self.normal[k][1];
        if self.taut[k] == TAUT_COS && dn < -INTO_COS_MIN * l && l > arc_radius(grid) && heads_into(dn, l * l, into_cos_eps(grid.params.radius, arc_radius(grid), eps)) {
            return Some(false);
        }
        None
    }

    /// Geodesic distance between two points of the floor (m); infinite across islands or off
    /// the region. A search from `to` over the graph, ordered by the distance so far plus the
    /// straight line to `from`, that tests whether `from` (or `to`) sees a node only when
    /// that node comes first: the first node `from` sees is on the shortest path. Both ends are
    /// exact (a `from` just off the region is seen from the nearest navigable cell's centre
    /// within two); [`GoalField`](crate::goal_field::GoalField) sees from cell centres instead,
    /// so the two differ by up to a cell's diagonal where two routes are nearly equal.
    pub fn distance(&self, grid: &NavGrid, from: Point2, to: Point2) -> f64 {
        let (Some(ia), Some(ib)) = (grid.island_at(from), grid.island_at(to)) else { return f64::INFINITY };
        if ia != ib {
            return f64::INFINITY;
        }
        let (s, g) = ([from.x, from.y], [to.x, to.y]);
        let eg = end_eps(grid, g);
        // What `from` sees is seen from `from` itself on the region, else from the nearest
        // navigable cell's centre within two cells.
        let (c, es) = match grid.cell_of(from).filter(|&i| grid.is_nav_cell(i)) {
            Some(_) => (s, end_eps(grid, s)),
            None => match grid.nearest_nav_cell(from, 2) {
                Some(cs) => (grid.center(cs), LOS_EPS),
                None => return f64::INFINITY,
            },
        };
        if segment_clear(grid, c, g, eg.max(es)) {
            return dist2(s, g);
        }
        SCRATCH.with(|sc| {
            let mut sc = sc.borrow_mut();
            sc.reset(self.len());
            let Scratch { dist, to_from, heap } = &mut *sc;
            // The straight line from node `k` to `from` (m), worked out once per query.
            let mut line = |k: usize| {
                if to_from[k].is_nan() {
                    to_from[k] = dist2(self.pos[k], s);
                }
                to_from[k]
            };
            // Entries: (key bits, tag), the tag `b` for square `b` of nodes, else [`NODE`] |
            // node `k` shifted left by one, its low bit set while the node's leg from `to` is
            // still unverified (a seed). The order is the key's, then squares before nodes,
            // then by node, then reached nodes before seeds. A square's key is a lower bound
            // (less a nanometre, for rounding) of its nodes' seed keys, so it is taken before
            // any of them would have been: the nodes come in the order they would have come
            // had every seed been pushed at the start. The squares are heapified at once.
            let direct = dist2(g, s);
            heap.reset(
                direct * QUEUE_CUT,
                self.bucket_rect.iter().enumerate().map(|(b, r)| {
                    let bound = (rect_dist(r, g) + rect_dist(r, s)).max(direct) - 1e-9;
                    (bound.max(0.0).to_bits(), b as u32)
                }),
            );
            while let Some((key, tag)) = heap.pop() {
                if tag < NODE {
                    let b = tag as usize;
                    for &k in &self.bucket_nodes[self.bucket_start[b] as usize..self.bucket_start[b + 1] as usize] {
                        // A seed that cannot join `to` whatever the line of sight is left out
                        // now rather than when it comes up (the same answer, fewer entries).
                        if self.island[k as usize] == ia && self.may_join(grid, k as usize, g, eg) != Some(false) {
                            let a = self.pos[k as usize];
                            heap.push(((dist2(g, a) + line(k as usize)).to_bits(), NODE | k << 1 | 1));
                        }
                    }
                    continue;
                }
                let k = ((tag & !NODE) >> 1) as usize;
                // Settled nodes read minus infinity (so that no leg improves them).
                let mut dk = dist[k];
                if dk == f64::NEG_INFINITY {
                    continue;
                }
                let a = self.pos[k];
                if tag & 1 == 1 {
                    // Its taut tests passed when it was seeded: only the line of sight is left
                    // (none for a goal on the node).
                    let dg = dist2(g, a);
                    if dg >= 1e-9 && !segment_clear(grid, g, a, eg) {
                        continue;
                    }
                    dk = dk.min(dg);
                } else if f64::from_bits(key) > dk + line(k) + 1e-12 {
                    continue;
                }
                dist[k] = f64::NEG_INFINITY;
                if self.joins(grid, k, c, es) {
                    return dk + line(k);
                }
                for (b, l) in self.legs(k) {
                    let nd = dk + l;
                    if nd < dist[b as usize] {
                        dist[b as usize] = nd;
                        heap.push(((nd + line(b as usize)).to_bits(), NODE | b << 1));
                    }
                }
            }
            f64::INFINITY
        })
    }
}

/// Whether `p` sees `q` (m) at tolerance `eps` ([`segment_clear`]), settled by the walls that
/// earlier tests from `p` at `eps` ran into where it can be (`walls.rs`), and adding the wall
/// this one runs into. (Queries do not use it: it spares them 4-7% of their instructions but
/// no time that shows.)
#[inline]
fn sees(grid: &NavGrid, walls: &mut Walls, p: [f64; 2], q: [f64; 2], eps: f64) -> bool {
    if walls.hide(grid, p, q) {
        return false;
    }
    match segment_verdict(grid, p, q, eps) {
        Verdict::Clear => true,
        Verdict::BlockedAt(i) => {
            walls.add(grid, i, eps);
            false
        }
        Verdict::Blocked => false,
    }
}

/// Where a query's queue starts keeping entries out of its heap: at this many times the
/// straight line between the ends (see [`CutHeap`]).
const QUEUE_CUT: f64 = 1.1;

/// The tag bit of a node's heap entry in [`CornerGraph::distance`]'s search (a square's tag
/// is its index, below it).
const NODE: u32 = 1 << 31;

/// Reusable per-thread search arrays: the distance from the goal so far per node (minus
/// infinity once settled), the straight line from each node to the query's start (m; NaN
/// until needed) and the queue.
#[derive(Default)]
struct Scratch {
    dist: Vec<f64>,
    to_from: Vec<f64>,
    heap: CutHeap,
}

impl Scratch {
    fn reset(&mut self, n: usize) {
        self.dist.clear();
        self.dist.resize(n, f64::INFINITY);
        self.to_from.clear();
        self.to_from.resize(n, f64::NAN);
    }
}

thread_local! {
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// The line-of-sight tolerance at an end point `p` (m) of a query: [`LOS_EPS`], or as far
/// inside the clearance radius as `p` itself stands (an episode's start may stand within the
/// navigability tolerance, and the grid's interpolated clearance can call a point a little
/// closer than that navigable beside a convex corner), up to that tolerance plus a quarter
/// cell.
pub(crate) fn end_eps(grid: &NavGrid, p: [f64; 2]) -> f64 {
    if segment_clear(grid, p, p, LOS_EPS) {
        return LOS_EPS;
    }
    let most = crate::navgrid::NAV_TOLERANCE + 0.25 * grid.resolution();
    let exact = grid.cell_of(Point2::new(p[0], p[1])).and_then(|i| grid.nearest_segment_distance(i, &[p, p]));
    match exact {
        Some(d) => (grid.params.radius - d + 1e-6).clamp(LOS_EPS, most),
        None => crate::navgrid::NAV_TOLERANCE,
    }
}

/// Distance from `p` to the rectangle `r` (x min, y min, x max, y max), 0 inside (m).
fn rect_dist(r: &[f64; 4], p: [f64; 2]) -> f64 {
    let dx = (r[0] - p[0]).max(p[0] - r[2]).max(0.0);
    let dy = (r[1] - p[1]).max(p[1] - r[3]).max(0.0);
    (dx * dx + dy * dy).sqrt()
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    (dx * dx + dy * dy).sqrt()
}

/// Boundary cells where a shortest path may bend, in cell order: those whose nearest obstacle
/// point lies within one cell of a convex vertex ([`ConvexVertices`]: convex corners of the
/// scene's geometry are segment ends; along a straight wall no path bends, so not where the
/// pieces of one wall meet), and those on the edge of the floor at a reflex corner of the
/// cells (a 2 x 2 block with exactly one cell off the region). Narrow passages need no more:
/// their bends are on the arcs ([`arc_nodes`]). On a storey with stairs (no `convex`): within
/// a cell of any vertex, and every cell in a passage at most three cells wide.
fn reflex_cells(grid: &NavGrid, passage: &[bool], convex: Option<&ConvexVertices>) -> Vec<usize> {
    let (w, h) = grid.size();
    let (wi, hi) = (w as isize, h as isize);
    let nav = |c: isize, r: isize| c >= 0 && r >= 0 && c < wi && r < hi && grid.is_nav_cell((r * wi + c) as usize);
    let reflex_block = |i: usize| {
        let (c, r) = ((i % w) as isize, (i / w) as isize);
        [(-1, -1), (0, -1), (-1, 0), (0, 0)].iter().any(|&(bx, by)| {
            let block = [(c + bx, r + by), (c + bx + 1, r + by), (c + bx, r + by + 1), (c + bx + 1, r + by + 1)];
            block.iter().filter(|&&(x, y)| !nav(x, y)).count() == 1
        })
    };
    let res = grid.resolution();
    // Without convexity (a storey with stairs) every vertex may be a bend, and so may every
    // passage cell.
    let near_end = |i: usize| {
        let k = grid.nearest[i];
        if k == u32::MAX {
            return reflex_block(i);
        }
        let q = closest_on_segment(grid.center(i), &grid.segments[k as usize]);
        grid.nearest_around(i).flat_map(|k| grid.segments[k as usize]).any(|v| (q[0] - v[0]).powi(2) + (q[1] - v[1]).powi(2) <= res * res && convex.is_none_or(|c| c.is_convex(v)))
    };
    (0..w * h).into_par_iter().filter(|&i| grid.corner[i] && ((convex.is_none() && passage[i]) || near_end(i))).collect()
}

/// Which of `grid`'s obstacle vertices are convex, for those the bend points ask about: the
/// ends of the nearest segments around each boundary cell ([`reflex_cells`]) and the vertices
/// whose arcs may hold bend points (`near_passage`, [`arc_nodes`]).
fn convex_vertices(grid: &NavGrid, near_passage: &[bool]) -> ConvexVertices {
    let (w, h) = grid.size();
    let mut wanted = vec![false; grid.segments.len()];
    for i in (0..w * h).filter(|&i| grid.corner[i] && grid.nearest[i] != u32::MAX) {
        for k in grid.nearest_around(i) {
            wanted[k as usize] = true;
        }
    }
    for (k, s) in grid.segments.iter().enumerate() {
        if s.iter().any(|&v| arc_vertex(grid, near_passage, v)) {
            wanted[k] = true;
        }
    }
    ConvexVertices::new(&grid.segments, &wanted)
}

/// The cosine with a node's outward normal below which a leg leaving the node (longer than
/// the arc radius) comes nearer to the obstacle point the node stands off than the radius less
/// [`LOS_EPS`] and a millimetre, so that no line of sight can pass: a node stands at the radius
/// (an arc node at the arc radius `R`) from that point along its normal, and a leg leaving at
/// cosine `-c` passes it at `R sqrt(1 - c^2)` once it is `R c` along (a node stands exactly
/// there: its normal and its anchor come from the same obstacle point). Above
/// [`INTO_COS_MIN`] (0.37 for the default radius); above 1 (no leg is left out) for radii too
/// small for the bound. For an agent radius and an arc radius (m).
fn into_cos_for(radius: f64, arc: f64) -> f64 {
    into_cos_eps(radius, arc, LOS_EPS)
}

/// Whether a leg `d` (`dn = d . n` with a node's outward normal `n`, `l2 = |d|^2`) leaves the
/// node at a cosine below `-into` with its normal: `d . n < -into |d|`, without a root.
#[inline]
fn heads_into(dn: f64, l2: f64, into: f64) -> bool {
    (dn < 0.0) & (dn * dn > into * into * l2)
}

/// [`into_cos_for`] for a line-of-sight tolerance `eps` (m) other than [`LOS_EPS`] (a query's
/// end point standing inside the radius gets more).
fn into_cos_eps(radius: f64, arc: f64, eps: f64) -> f64 {
    let near = radius - eps - 1e-3;
    if near <= 0.0 {
        return 2.0;
    }
    (1.0 - (near / arc).powi(2)).max(0.0).sqrt()
}

/// A lower bound of [`into_cos_eps`]: it exceeds the sine of half the arc step (0.259), since
/// the radius is under the arc radius times that step's cosine. A leg less steep than this
/// needs no exact bound.
const INTO_COS_MIN: f64 = 0.25;

/// The boundary's outward unit normal at cell `i` and the taut-leg cosine that goes with it:
/// from the nearest obstacle segment when there is one, else from the cells off the region
/// around it; no normal (no pruning) when neither says.
fn outward_normal(grid: &NavGrid, i: usize) -> ([f64; 2], f64) {
    let c = grid.center(i);
    if let Some(k) = grid.nearest.get(i).copied().filter(|&k| k != u32::MAX) {
        let q = closest_on_segment(c, &grid.segments[k as usize]);
        let d = [c[0] - q[0], c[1] - q[1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        if l > 1e-9 {
            return ([d[0] / l, d[1] / l], TAUT_COS);
        }
    }
    let (w, h) = grid.size();
    let (col, row) = ((i % w) as isize, (i / w) as isize);
    let mut s = [0.0, 0.0];
    for dr in -2..=2isize {
        for dc in -2..=2isize {
            let (x, y) = (col + dc, row + dr);
            let off = x < 0 || y < 0 || x >= w as isize || y >= h as isize || !grid.is_nav_cell((y * w as isize + x) as usize);
            if off && (dc, dr) != (0, 0) {
                let l = ((dc * dc + dr * dr) as f64).sqrt();
                s[0] -= dc as f64 / l;
                s[1] -= dr as f64 / l;
            }
        }
    }
    let l = s[0].hypot(s[1]);
    if l > 1e-9 {
        ([s[0] / l, s[1] / l], TAUT_COS_COARSE)
    } else {
        ([0.0, 0.0], 1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::{into_cos_eps, into_cos_for, INTO_COS_MIN, LOS_EPS};

    #[test]
    fn legs_left_out_steeply_into_the_obstacle_pass_too_near_it() {
        for (radius, eps) in [0.05, 0.1, 0.18, 0.3, 1.0].into_iter().flat_map(|r| [(r, LOS_EPS), (r, 0.0155)]) {
            let arc = radius / 15f64.to_radians().cos() + 1e-6;
            let c = into_cos_eps(radius, arc, eps);
            assert!(c > INTO_COS_MIN && c < 1.0, "{radius}: {c}");
            if eps == LOS_EPS {
                assert_eq!(c, into_cos_for(radius, arc));
            }
            // A node at `d` (the radius or the arc radius) from the obstacle point at the
            // origin, along +y; legs leaving at cosine just below -c with +y, longer than
            // the arc radius, pass nearer than the radius less the tolerance.
            for d in [radius, arc] {
                for k in 0..=100 {
                    let cos = -c - (1.0 - c) * k as f64 / 100.0 - 1e-9;
                    let sin = (1.0 - cos * cos).max(0.0).sqrt();
                    let len = arc * (1.0 + 1e-9);
                    // Nearest approach of the leg from (0, d) along (sin, cos) to the origin.
                    let t = (-d * cos).clamp(0.0, len);
                    let near = (t * sin).hypot(d + t * cos);
                    assert!(near < radius - eps, "radius {radius}, eps {eps}, d {d}, cos {cos}: {near}");
                }
            }
        }
        // Too small a radius for the bound: no leg is left out.
        assert!(into_cos_for(0.004, 0.0042) > 1.0);
    }

}
