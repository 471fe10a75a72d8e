//! Geodesic distance to an episode's goals, from the floor's [`CornerGraph`], filled lazily.
//!
//! Built in a fraction of a millisecond: one search over the corner graph gives every node's
//! distance to the nearest goal and the next bend point after it. A point's distance is then
//! that of the best *anchor* its cell centre sees (a goal, or a node: the one minimising node
//! distance plus straight line), found the first time the cell is asked about and kept, so
//! per-step queries are O(1) (two cells' lookups and a square root). Cells are answered the same
//! whatever the order or thread they are asked from, so results are deterministic.

use crate::corner_graph::{end_eps, CornerGraph};
use crate::geodesic::{segment_clear, LOS_EPS};
use crate::navgrid::NavGrid;
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use xhab_types::Point2;

const NONE: u32 = u32::MAX;

/// Shortest-path distances to a set of goals on one floor, answered at any point.
#[derive(Debug)]
pub struct GoalField {
    graph: Arc<CornerGraph>,
    goals: Vec<Point2>,
    /// What is left to go from each goal (m): zero for an episode's goals.
    offsets: Vec<f64>,
    /// Island of each goal (`u32::MAX`: off the region).
    goal_island: Vec<u32>,
    /// Line-of-sight tolerance at each goal (m).
    goal_eps: Vec<f64>,
    /// Distance from each node to the nearest goal (m), infinite when unreachable.
    dist: Vec<f64>,
    /// The anchor after each node on its way to the goal: a node, `n + k` for goal k, or `NONE`.
    next: Vec<u32>,
    /// Each cell's anchor once asked for: 0 unknown, 1 none, else anchor id + 2.
    cells: Vec<AtomicU32>,
    /// The anchor found last (`NONE` before any): a bound for the next search, which an agent
    /// walking on usually finds again. Only the search's speed depends on it.
    hint: AtomicU32,
}

impl Clone for GoalField {
    fn clone(&self) -> Self {
        GoalField {
            graph: self.graph.clone(),
            goals: self.goals.clone(),
            offsets: self.offsets.clone(),
            goal_island: self.goal_island.clone(),
            goal_eps: self.goal_eps.clone(),
            dist: self.dist.clone(),
            next: self.next.clone(),
            cells: self.cells.iter().map(|c| AtomicU32::new(c.load(Ordering::Relaxed))).collect(),
            hint: AtomicU32::new(self.hint.load(Ordering::Relaxed)),
        }
    }
}

impl GoalField {
    /// The field towards `goals` (m, planar) on `grid`. Goals off the region count from the
    /// nearest navigable cell within two cells (for their island); farther ones are ignored.
    pub fn new(grid: &NavGrid, goals: &[Point2]) -> GoalField {
        Self::with_offsets(grid, goals, &vec![0.0; goals.len()])
    }

    /// The field towards `goals` (m, planar) where reaching goal `k` leaves `offsets[k]` (m)
    /// still to go: the portals of a flight of stairs, with the way on from each. With zero
    /// offsets, [`GoalField::new`].
    pub fn with_offsets(grid: &NavGrid, goals: &[Point2], offsets: &[f64]) -> GoalField {
        let graph = grid.corner_graph().clone();
        let n = graph.len();
        let goal_island: Vec<u32> = goals.iter().map(|&g| goal_island(grid, g)).collect();
        let goal_eps: Vec<f64> = goals.iter().map(|g| end_eps(grid, [g.x, g.y])).collect();
        let mut dist = vec![f64::INFINITY; n];
        let mut next = vec![NONE; n];
        let mut done = vec![false; n];
        // Entries: (distance bits, node, goal whose straight leg is still to be verified or NONE).
        let mut heap = BinaryHeap::new();
        for k in 0..n {
            for (j, g) in goals.iter().enumerate() {
                if goal_island[j] != NONE && goal_island[j] == graph.island(k) {
                    heap.push(Reverse(((offsets[j] + dist2(graph.pos(k), [g.x, g.y])).to_bits(), k as u32, j as u32)));
                }
            }
        }
        while let Some(Reverse((key, k, seed))) = heap.pop() {
            let k = k as usize;
            if done[k] {
                continue;
            }
            let d = f64::from_bits(key);
            if seed != NONE {
                let g = goals[seed as usize];
                if !graph.joins(grid, k, [g.x, g.y], goal_eps[seed as usize]) {
                    continue;
                }
                if d < dist[k] {
                    dist[k] = d;
                    next[k] = (n + seed as usize) as u32;
                }
            } else if d > dist[k] {
                continue;
            }
            done[k] = true;
            for (b, l) in graph.legs(k) {
                let b = b as usize;
                let nd = dist[k] + l;
                if !done[b] && nd < dist[b] {
                    dist[b] = nd;
                    next[b] = k as u32;
                    heap.push(Reverse((nd.to_bits(), b as u32, NONE)));
                }
            }
        }
        let (w, h) = grid.size();
        GoalField {
            graph,
            goals: goals.to_vec(),
            offsets: offsets.to_vec(),
            goal_island,
            goal_eps,
            dist,
            next,
            cells: (0..w * h).map(|_| AtomicU32::new(0)).collect(),
            hint: AtomicU32::new(NONE),
        }
    }

    /// The goals (m).
    pub fn goals(&self) -> &[Point2] {
        &self.goals
    }

    /// Position (m) and distance to the goal (m) of anchor `q` (a node, or `n + k` for goal k).
    fn anchor(&self, q: u32) -> ([f64; 2], f64) {
        let n = self.graph.len();
        let q = q as usize;
        if q >= n {
            let g = self.goals[q - n];
            ([g.x, g.y], self.offsets[q - n])
        } else {
            (self.graph.pos(q), self.dist[q])
        }
    }

    /// The best anchor that cell `i`'s centre sees, worked out on first use; `None` when the
    /// cell reaches no goal.
    fn cell_anchor(&self, grid: &NavGrid, i: usize) -> Option<u32> {
        match self.cells[i].load(Ordering::Relaxed) {
            0 => {}
            1 => return None,
            v => return Some(v - 2),
        }
        let a = self.find_anchor(grid, i);
        self.cells[i].store(a.map_or(1, |q| q + 2), Ordering::Relaxed);
        if let Some(q) = a {
            self.hint.store(q, Ordering::Relaxed);
        }
        a
    }

    /// The anchor minimising anchor distance plus straight line among those cell `i`'s centre
    /// sees: candidates in increasing order of that sum, the first one seen wins.
    fn find_anchor(&self, grid: &NavGrid, i: usize) -> Option<u32> {
        if !grid.is_nav_cell(i) {
            return None;
        }
        let island = grid.island_of[i];
        let c = grid.center(i);
        let n = self.graph.len();
        // A bound from the neighbours' anchors that this centre sees too (most cells share
        // their neighbours' anchor, and nothing worse than it needs looking at), and from the
        // anchor found last. Any anchor seen bounds the search without dropping its answer,
        // the best seen, so the answer is the same whatever was asked before.
        let (w, h) = grid.size();
        let (col, row) = ((i % w) as isize, (i / w) as isize);
        let neighbours = [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, -1), (-1, 1), (1, 1)].into_iter().filter_map(|(dc, dr)| {
            let (x, y) = (col + dc, row + dr);
            let inside = x >= 0 && y >= 0 && x < w as isize && y < h as isize;
            let v = if inside { self.cells[(y * w as isize + x) as usize].load(Ordering::Relaxed) } else { 0 };
            (v >= 2).then(|| v - 2)
        });
        let hint = Some(self.hint.load(Ordering::Relaxed)).filter(|&q| self.reaches_goal_from(q, island));
        let mut bound = f64::INFINITY;
        let mut tried: [u32; 9] = [NONE; 9];
        let mut t = 0;
        // Line-of-sight answers already worked out here, reused by the candidates below (the
        // bound's anchor comes up again among them, last).
        let mut known: [(u32, bool); 9] = [(NONE, false); 9];
        let mut nk = 0;
        for q in neighbours.chain(hint) {
            if tried[..t].contains(&q) {
                continue;
            }
            tried[t] = q;
            t += 1;
            let (p, d) = self.anchor(q);
            let total = d + dist2(p, c);
            if total < bound {
                let seen = self.sees(grid, q, c);
                known[nk] = (q, seen);
                nk += 1;
                if seen {
                    bound = total;
                }
            }
        }
        let known = &known[..nk];
        let sees = |q: u32| known.iter().find(|e| e.0 == q).map_or_else(|| self.sees(grid, q, c), |e| e.1);
        let mut cand: Vec<(f64, u32)> = Vec::new();
        for (j, g) in self.goals.iter().enumerate() {
            if self.goal_island[j] == island {
                let d = self.offsets[j] + dist2([g.x, g.y], c);
                if d <= bound {
                    cand.push((d, (n + j) as u32));
                }
            }
        }
        for k in 0..n {
            let d = self.dist[k];
            if d < bound && self.graph.island(k) == island {
                let total = d + dist2(self.graph.pos(k), c);
                if total <= bound {
                    cand.push((total, k as u32));
                }
            }
        }
        // The smallest first: a few linear scans (usually one suffices), then a sort.
        let order = |a: &(f64, u32), b: &(f64, u32)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1));
        for _ in 0..8 {
            let k = (0..cand.len()).min_by(|&a, &b| order(&cand[a], &cand[b]))?;
            let (_, q) = cand.swap_remove(k);
            if sees(q) {
                return Some(q);
            }
        }
        // Then smallest first from a heap (built in linear time): the first seen usually
        // comes long before the end, which a full sort would order for nothing.
        let mut heap: BinaryHeap<Reverse<(u64, u32)>> = cand.into_iter().map(|(d, q)| Reverse((d.to_bits(), q))).collect();
        while let Some(Reverse((_, q))) = heap.pop() {
            if sees(q) {
                return Some(q);
            }
        }
        None
    }

    /// Whether anchor `q` (`NONE` for none) lies on `island` and reaches a goal.
    fn reaches_goal_from(&self, q: u32, island: u32) -> bool {
        let n = self.graph.len();
        match q as usize {
            _ if q == NONE => false,
            k if k < n => self.graph.island(k) == island && self.dist[k].is_finite(),
            k => self.goal_island[k - n] == island,
        }
    }

    /// Whether anchor `q` can be the first anchor of a shortest path from `p` (m).
    fn sees(&self, grid: &NavGrid, q: u32, p: [f64; 2]) -> bool {
        let n = self.graph.len();
        if (q as usize) < n {
            self.graph.joins(grid, q as usize, p, LOS_EPS)
        } else {
            let g = self.goals[q as usize - n];
            segment_clear(grid, p, [g.x, g.y], self.goal_eps[q as usize - n])
        }
    }

    /// The cell that stands for `p`: its own if it reaches a goal, else the nearest navigable
    /// cell within two cells that does; with that cell's anchor.
    fn cell_for(&self, grid: &NavGrid, p: Point2) -> Option<(usize, u32)> {
        let i = grid.cell_of(p)?;
        if let Some(q) = self.cell_anchor(grid, i) {
            return Some((i, q));
        }
        let j = grid.nearest_nav_cell(p, 2)?;
        self.cell_anchor(grid, j).map(|q| (j, q))
    }

    /// Geodesic distance from `p` (m, planar) to the nearest goal (m); infinite when `p` is
    /// off the region or on an island without a goal.
    pub fn distance(&self, grid: &NavGrid, p: Point2) -> f64 {
        match self.cell_for(grid, p) {
            Some((_, q)) => {
                let (a, d) = self.anchor(q);
                d + dist2(a, [p.x, p.y])
            }
            None => f64::INFINITY,
        }
    }

    /// Geodesic distance from `p` (m, planar) to the nearest goal, defined off the region
    /// too: where `p` has no distance of its own (off the agent's navigable region, or on an
    /// island without a goal), the distance from the nearest navigable cell centre on a goal's
    /// island plus the straight offset to it, and that offset (m); `None` as the offset when
    /// `p` has its own distance. Infinite only when no cell reaches a goal.
    pub fn distance_snapped(&self, grid: &NavGrid, p: Point2) -> (f64, Option<f64>) {
        let d = self.distance(grid, p);
        if d.is_finite() {
            return (d, None);
        }
        match grid.nearest_cell_where(p, |j| grid.is_nav_cell(j) && self.goal_island.contains(&grid.island_of[j])) {
            Some((j, off)) => {
                let q = grid.center(j);
                (self.distance(grid, Point2::new(q[0], q[1])) + off, Some(off))
            }
            None => (f64::INFINITY, None),
        }
    }

    /// The next point to head for on the shortest path from `p` (m): its cell's anchor when `p`
    /// itself sees it, else the best anchor `p` sees among those of the eight cells around,
    /// skipping anchors closer than `min_dist` (m). `None` when unreachable or when no anchor
    /// is in sight.
    pub fn next_waypoint(&self, grid: &NavGrid, p: Point2, min_dist: f64) -> Option<Point2> {
        let (i, _) = self.cell_for(grid, p)?;
        let n = self.graph.len();
        let (w, h) = grid.size();
        let (c, r) = ((i % w) as isize, (i / w) as isize);
        let mut best: Option<(f64, Point2)> = None;
        // The cell's own anchor first: when `p` sees it, the way through it is at most twice
        // the distance from `p` to the cell centre longer than the best (the triangle
        // inequality), and the eight cells around (each a new anchor search, most of a step's
        // cost) are not looked at.
        let own = std::iter::once((0, 0));
        let around = (-1..=1).flat_map(|dr| (-1..=1).map(move |dc| (dc, dr))).filter(|&d| d != (0, 0));
        for (k, (dc, dr)) in own.chain(around).enumerate() {
            if k == 1 && best.is_some() {
                break;
            }
            let (cc, rr) = (c + dc, r + dr);
            if cc < 0 || rr < 0 || cc >= w as isize || rr >= h as isize {
                continue;
            }
            let Some(mut q) = self.cell_anchor(grid, (rr * w as isize + cc) as usize) else { continue };
            // Walk up past anchors that are too close to be worth heading for.
            for _ in 0..64 {
                let (a, d) = self.anchor(q);
                let far = dist2(a, [p.x, p.y]) >= min_dist;
                if far || q as usize >= n {
                    let total = d + dist2(a, [p.x, p.y]);
                    // Twice the wavefront's tolerance: the agent itself may stand that deep.
                    if best.is_none_or(|b| total < b.0) && segment_clear(grid, [p.x, p.y], a, 2.0 * LOS_EPS) {
                        best = Some((total, Point2::new(a[0], a[1])));
                    }
                    break;
                }
                let next = self.next[q as usize];
                if next == NONE || next == q {
                    break;
                }
                q = next;
            }
        }
        best.map(|b| b.1)
    }

    /// The shortest path from `p` to its goal as a polyline (m), `p` first.
    pub fn path(&self, grid: &NavGrid, p: Point2) -> Vec<Point2> {
        let mut out = vec![p];
        let Some((_, mut q)) = self.cell_for(grid, p) else { return out };
        let n = self.graph.len();
        for _ in 0..=n {
            let (a, _) = self.anchor(q);
            out.push(Point2::new(a[0], a[1]));
            if q as usize >= n {
                break;
            }
            let next = self.next[q as usize];
            if next == NONE || next == q {
                break;
            }
            q = next;
        }
        out
    }
}

/// The island a goal counts on: its cell's, or the nearest navigable cell's within two cells.
fn goal_island(grid: &NavGrid, g: Point2) -> u32 {
    grid.cell_of(g)
        .filter(|&i| grid.is_nav_cell(i))
        .or_else(|| grid.nearest_nav_cell(g, 2))
        .map_or(NONE, |i| grid.island_of[i])
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
    (dx * dx + dy * dy).sqrt()
}
