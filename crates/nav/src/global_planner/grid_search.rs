//! Dijkstra and A* over the costmap's cells, 8-connected with exact diagonal lengths, on a
//! [`CostModel`] that makes cells near obstacles dearer without a ceiling.
//!
//! The cost of a step between neighbouring cells a and b is
//! `length * (w(a) + w(b)) / 2` with `w(c) = (neutral_cost + cost_factor * c) / neutral_cost`,
//! so a free cell costs its length in metres. ROS global_planner uses
//! `min(neutral_cost + cost_factor * c, lethal_cost - 1)` instead: with the defaults every
//! cell of cost 68 or more (within about 0.13 m of the inscribed radius) costs the same, so
//! inside that band the cheapest path is the shortest one and plans hug walls. Without the
//! ceiling, `w` keeps rising to 16.1 at cost 252, and the cheapest path keeps the clearance
//! that pays for its extra length. A diagonal step is allowed only when both cells beside it
//! are passable, so paths never squeeze between two obstacles touching at a corner.

use super::planner_params::GlobalPlannerParams;
use crate::costmap_2d::{traverse_segment, Costmap2D, MAX_NON_OBSTACLE, UNKNOWN};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use xhab_types::Point2;

/// How costmap costs turn into traversal costs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CostModel {
    /// Cost of a free cell per cell length.
    pub neutral_cost: f64,
    /// Weight of the costmap's cost.
    pub cost_factor: f64,
    /// Costs at or above this are impassable.
    pub lethal_cost: i32,
    /// Unknown cells are passable at cost [`MAX_NON_OBSTACLE`].
    pub allow_unknown: bool,
}

impl CostModel {
    /// The model of planner parameters `p`.
    pub fn from_params(p: &GlobalPlannerParams) -> Self {
        Self {
            neutral_cost: p.neutral_cost,
            cost_factor: p.cost_factor,
            lethal_cost: p.lethal_cost,
            allow_unknown: p.allow_unknown,
        }
    }

    /// Whether a cell of cost `c` may be entered.
    pub fn passable(&self, c: u8) -> bool {
        if c == UNKNOWN {
            self.allow_unknown
        } else {
            (c as i32) < self.lethal_cost
        }
    }

    /// Traversal cost per metre of a cell of cost `c` (1 for free), `f64::INFINITY` when
    /// impassable.
    pub fn weight(&self, c: u8) -> f64 {
        if !self.passable(c) {
            return f64::INFINITY;
        }
        let c = if c == UNKNOWN { MAX_NON_OBSTACLE } else { c };
        self.weight_of_cost(c as f64)
    }

    /// Traversal cost per metre of cost value `c`, ignoring passability.
    pub fn weight_of_cost(&self, c: f64) -> f64 {
        (self.neutral_cost + self.cost_factor * c) / self.neutral_cost
    }

    /// The weight of every cell of `costmap`.
    pub fn weights(&self, costmap: &Costmap2D) -> Vec<f64> {
        costmap.costs().iter().map(|&c| self.weight(c)).collect()
    }
}

/// Whether every cell the segment `a -> b` (m, world frame) crosses is on the map and has a
/// finite weight.
pub fn segment_passable(costmap: &Costmap2D, weights: &[f64], a: Point2, b: Point2) -> bool {
    let (x0, y0) = costmap.world_to_map_continuous(a);
    let (x1, y1) = costmap.world_to_map_continuous(b);
    let (sx, sy) = (costmap.size_x() as i64, costmap.size_y() as i64);
    let mut ok = true;
    traverse_segment(x0, y0, x1, y1, |x, y| {
        ok = x >= 0 && y >= 0 && x < sx && y < sy && weights[(y * sx + x) as usize].is_finite();
        ok
    });
    ok
}

/// Cost of the straight segment `a -> b` (m, world frame) over a weight grid: the weights
/// sampled every quarter cell, times length; infinite when it crosses an impassable cell or
/// leaves the map.
pub fn segment_cost(costmap: &Costmap2D, weights: &[f64], a: Point2, b: Point2) -> f64 {
    if !segment_passable(costmap, weights, a, b) {
        return f64::INFINITY;
    }
    let len = a.dist(b);
    let res = costmap.resolution();
    let n = (len / (0.25 * res)).ceil().max(1.0) as usize;
    let ds = len / n as f64;
    let mut total = 0.0;
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let p = Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
        let Some((x, y)) = costmap.world_to_map(p) else {
            return f64::INFINITY;
        };
        let w = weights[costmap.index(x, y)];
        if !w.is_finite() {
            return f64::INFINITY;
        }
        let half = if k == 0 || k == n { 0.5 } else { 1.0 };
        total += half * w * ds;
    }
    total
}

/// What a search found.
#[derive(Debug, Clone)]
pub struct SearchResult {
    /// Cheapest cost from the start to each settled cell (`f64::INFINITY` if not reached).
    pub cost: Vec<f64>,
    /// Predecessor of each reached cell (`u32::MAX` for the start and unreached cells).
    pub parent: Vec<u32>,
    /// Whether the goal was reached.
    pub found: bool,
    /// Cells expanded.
    pub expanded: usize,
}

impl SearchResult {
    /// The cells from the start to `cell` (inclusive), if `cell` was reached.
    pub fn cells_to(&self, cell: usize) -> Option<Vec<usize>> {
        if !self.cost[cell].is_finite() {
            return None;
        }
        let mut out = vec![cell];
        let mut c = cell;
        while self.parent[c] != u32::MAX {
            c = self.parent[c] as usize;
            out.push(c);
        }
        out.reverse();
        Some(out)
    }
}

/// Cheapest 8-connected path over `weights` (per metre, see [`CostModel::weights`]) of a
/// `size_x` x `size_y` grid of `resolution` (m) from cell `start` to cell `goal`; A* with the
/// octile distance when `astar`, else Dijkstra. Without a path every reachable cell is settled.
pub fn search(
    weights: &[f64],
    size_x: usize,
    size_y: usize,
    resolution: f64,
    start: usize,
    goal: usize,
    astar: bool,
) -> SearchResult {
    let n = size_x * size_y;
    let mut cost = vec![f64::INFINITY; n];
    let mut parent = vec![u32::MAX; n];
    let mut closed = vec![false; n];
    let (gx, gy) = ((goal % size_x) as f64, (goal / size_x) as f64);
    let heuristic = |i: usize| {
        if !astar {
            return 0.0;
        }
        let (dx, dy) = (
            ((i % size_x) as f64 - gx).abs(),
            ((i / size_x) as f64 - gy).abs(),
        );
        (dx.max(dy) + (std::f64::consts::SQRT_2 - 1.0) * dx.min(dy)) * resolution
    };
    let mut heap = BinaryHeap::new();
    cost[start] = 0.0;
    heap.push(Reverse((heuristic(start).to_bits(), start as u32)));
    let diag = resolution * std::f64::consts::SQRT_2;
    let mut expanded = 0;
    let mut found = false;
    while let Some(Reverse((_, m))) = heap.pop() {
        let m = m as usize;
        if closed[m] {
            continue;
        }
        closed[m] = true;
        expanded += 1;
        if m == goal {
            found = true;
            break;
        }
        let (x, y) = ((m % size_x) as isize, (m / size_x) as isize);
        let wm = weights[m];
        let passable = |cx: isize, cy: isize| {
            cx >= 0
                && cy >= 0
                && (cx as usize) < size_x
                && (cy as usize) < size_y
                && weights[cy as usize * size_x + cx as usize].is_finite()
        };
        for (dx, dy) in [
            (1, 0),
            (-1, 0),
            (0, 1),
            (0, -1),
            (1, 1),
            (1, -1),
            (-1, 1),
            (-1, -1),
        ] {
            let (nx, ny) = (x + dx, y + dy);
            if !passable(nx, ny) {
                continue;
            }
            let diagonal = dx != 0 && dy != 0;
            if diagonal && !(passable(x + dx, y) && passable(x, y + dy)) {
                continue;
            }
            let k = ny as usize * size_x + nx as usize;
            if closed[k] {
                continue;
            }
            let len = if diagonal { diag } else { resolution };
            let c = cost[m] + len * 0.5 * (wm + weights[k]);
            if c < cost[k] {
                cost[k] = c;
                parent[k] = m as u32;
                heap.push(Reverse(((c + heuristic(k)).to_bits(), k as u32)));
            }
        }
    }
    SearchResult {
        cost,
        parent,
        found,
        expanded,
    }
}
