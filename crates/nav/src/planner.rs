//! Global planner: A* (or Dijkstra) on a costmap with a cost that keeps paths away from
//! walls, then string-pulled into straight legs where the straight line stays cheap.
//!
//! The step cost is `length * (neutral_cost + cost_factor * cell_cost) / neutral_cost`, as ROS
//! global_planner, but cell costs are the raw inflation values: there is no flat ceiling at
//! which every cell near a wall costs the same, so paths keep the inflation-optimal distance
//! from walls instead of hugging them.

use crate::costmap::{Costmap, INSCRIBED};
use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use xhab_types::{Point2, Pose2};

/// Planner parameters (ROS global_planner names).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlannerParams {
    /// A* (true) or Dijkstra (false) (default true; same paths, A* explores less).
    pub use_astar: bool,
    /// Cost of a free cell (default 50).
    pub neutral_cost: f64,
    /// Weight of the cell cost (default 3.0, as ROS).
    pub cost_factor: f64,
    /// How far from an occupied goal a free goal may be taken (m, default 0.5).
    pub default_tolerance: f64,
    /// Highest cell cost a straightened leg may cross (default 60: about 0.25 m from walls with the default inflation).
    pub smooth_max_cost: u8,
}

impl Default for PlannerParams {
    fn default() -> Self {
        Self { use_astar: true, neutral_cost: 50.0, cost_factor: 3.0, default_tolerance: 0.5, smooth_max_cost: 60 }
    }
}

/// Why no plan was made.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum PlanError {
    /// The start is outside the costmap.
    #[error("the start is outside the map")]
    StartOutsideMap,
    /// The goal is outside the costmap.
    #[error("the goal is outside the map")]
    GoalOutsideMap,
    /// The start is in an obstacle with no free cell nearby.
    #[error("the start is occupied")]
    StartOccupied,
    /// The goal is occupied and no free cell lies within the tolerance.
    #[error("the goal is occupied and no free cell is within tolerance")]
    GoalOccupied,
    /// No path connects start and goal.
    #[error("no path from start to goal")]
    NoPath,
}

/// The planner's working memory, kept between plans so that a plan costs what it explores
/// rather than the size of the map.
#[derive(Debug, Clone, Default)]
pub struct PlanScratch {
    dist: Vec<f64>,
    prev: Vec<u32>,
    /// `dist` and `prev` hold for cell i only when `stamp[i] == generation`.
    stamp: Vec<u32>,
    generation: u32,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    /// The last search's cells, for [`plan_on_version`]: found on costmap `version` from
    /// cell `s` to cell `g` (the goal's own cell `gi`) with the parameters `params`.
    memo: Option<SearchMemo>,
}

/// A search's result and what it depended on.
#[derive(Debug, Clone)]
struct SearchMemo {
    version: u64,
    size: (usize, usize),
    s: usize,
    g: usize,
    params: PlannerParams,
    cells: Vec<usize>,
}

impl PlanScratch {
    /// Forgets the last search (its costmap versions no longer apply: a new map).
    pub fn forget_search(&mut self) {
        self.memo = None;
    }

    /// Starts a search over `n` cells: every distance infinite.
    fn reset(&mut self, n: usize) {
        if self.stamp.len() != n || self.generation == u32::MAX {
            self.dist = vec![f64::INFINITY; n];
            self.prev = vec![u32::MAX; n];
            self.stamp = vec![0; n];
            self.generation = 0;
        }
        self.generation += 1;
        self.heap.clear();
    }

    #[inline]
    fn dist(&self, i: usize) -> f64 {
        if self.stamp[i] == self.generation {
            self.dist[i]
        } else {
            f64::INFINITY
        }
    }

    #[inline]
    fn set(&mut self, i: usize, d: f64, prev: u32) {
        self.stamp[i] = self.generation;
        self.dist[i] = d;
        self.prev[i] = prev;
    }
}

/// Plans from `start` to `goal` on `cm`; the path runs from start to goal with headings along it.
pub fn plan(cm: &Costmap, start: Point2, goal: Point2, p: &PlannerParams) -> Result<Vec<Pose2>, PlanError> {
    plan_with(&mut PlanScratch::default(), cm, start, goal, p)
}

/// [`plan`] with working memory kept from earlier plans (the same result).
pub fn plan_with(scratch: &mut PlanScratch, cm: &Costmap, start: Point2, goal: Point2, p: &PlannerParams) -> Result<Vec<Pose2>, PlanError> {
    plan_on_version(scratch, cm, None, start, goal, p)
}

/// [`plan_with`] on a costmap whose costs are those of `version` (the caller's counter, changed
/// whenever any cost changes): a search between the same cells on the same version is not run
/// again (the same result; move_base replans on every controller failure, and a robot that
/// stands still asks for the same search many times).
pub fn plan_on_version(scratch: &mut PlanScratch, cm: &Costmap, version: Option<u64>, start: Point2, goal: Point2, p: &PlannerParams) -> Result<Vec<Pose2>, PlanError> {
    let (w, h) = (cm.width, cm.height);
    let (sc, sr) = cm.cell(start).ok_or(PlanError::StartOutsideMap)?;
    let (gc, gr) = cm.cell(goal).ok_or(PlanError::GoalOutsideMap)?;
    let s = nearest_free(cm, sr * w + sc, 0.35).ok_or(PlanError::StartOccupied)?;
    let g = nearest_free(cm, gr * w + gc, p.default_tolerance).ok_or(PlanError::GoalOccupied)?;
    let gpos = cm.center(g % w, g / w);
    let memo_hit = |m: &SearchMemo| Some(m.version) == version && m.size == (w, h) && (m.s, m.g) == (s, g) && m.params == *p;
    let cells = match scratch.memo.as_ref().filter(|m| memo_hit(m)) {
        Some(m) => m.cells.clone(),
        None => {
            let cells = search(scratch, cm, s, g, gpos, p)?;
            scratch.memo = version.map(|version| SearchMemo { version, size: (w, h), s, g, params: p.clone(), cells: cells.clone() });
            cells
        }
    };
    let mut pts: Vec<Point2> = cells.iter().map(|&i| cm.center(i % w, i / w)).collect();
    pts[0] = start;
    if g == gr * w + gc {
        *pts.last_mut().unwrap_or(&mut Point2::default()) = goal;
    }
    let pts = string_pull(cm, &pts, p.smooth_max_cost);
    Ok(with_headings(&densify(&pts, cm.resolution * 2.0)))
}

/// A* (or Dijkstra without `use_astar`) over the costmap's cells from cell `s` to cell `g`
/// (centred at `gpos`): the cells of the cheapest path, `s` first.
fn search(scratch: &mut PlanScratch, cm: &Costmap, s: usize, g: usize, gpos: Point2, p: &PlannerParams) -> Result<Vec<usize>, PlanError> {
    let (w, h) = (cm.width, cm.height);
    let free = |i: usize| cm.cost[i] < INSCRIBED;
    let heur = |i: usize| if p.use_astar { cm.center(i % w, i / w).dist(gpos) / cm.resolution } else { 0.0 };
    scratch.reset(w * h);
    let sc = scratch;
    sc.set(s, 0.0, u32::MAX);
    sc.heap.push(Reverse((heur(s).to_bits(), s as u32)));
    while let Some(Reverse((_, m))) = sc.heap.pop() {
        let m = m as usize;
        if m == g {
            break;
        }
        let (c, r) = ((m % w) as isize, (m / w) as isize);
        let dm = sc.dist(m);
        for (dc, dr, len) in [(1, 0, 1.0), (-1, 0, 1.0), (0, 1, 1.0), (0, -1, 1.0), (1, 1, std::f64::consts::SQRT_2), (1, -1, std::f64::consts::SQRT_2), (-1, 1, std::f64::consts::SQRT_2), (-1, -1, std::f64::consts::SQRT_2)] {
            let (kc, kr) = (c + dc, r + dr);
            if kc < 0 || kr < 0 || kc >= w as isize || kr >= h as isize {
                continue;
            }
            let k = kr as usize * w + kc as usize;
            if !free(k) {
                continue;
            }
            if dc != 0 && dr != 0 && (!free(r as usize * w + kc as usize) || !free(kr as usize * w + c as usize)) {
                continue;
            }
            let nd = dm + len * (p.neutral_cost + p.cost_factor * cm.cost[k] as f64) / p.neutral_cost;
            if nd < sc.dist(k) {
                sc.set(k, nd, m as u32);
                sc.heap.push(Reverse(((nd + heur(k)).to_bits(), k as u32)));
            }
        }
    }
    if !sc.dist(g).is_finite() {
        return Err(PlanError::NoPath);
    }
    let mut cells = vec![g];
    while let Some(&last) = cells.last() {
        if last == s {
            break;
        }
        cells.push(sc.prev[last] as usize);
    }
    cells.reverse();
    Ok(cells)
}

/// The nearest cell cheaper than INSCRIBED within `tol` (m) of cell `i` (breadth first).
fn nearest_free(cm: &Costmap, i: usize, tol: f64) -> Option<usize> {
    if cm.cost[i] < INSCRIBED {
        return Some(i);
    }
    let reach = (tol / cm.resolution).ceil() as isize;
    let (c, r) = ((i % cm.width) as isize, (i / cm.width) as isize);
    let mut best: Option<(isize, usize)> = None;
    for dr in -reach..=reach {
        for dc in -reach..=reach {
            let (kc, kr) = (c + dc, r + dr);
            if kc < 0 || kr < 0 || kc >= cm.width as isize || kr >= cm.height as isize || dc * dc + dr * dr > reach * reach {
                continue;
            }
            let k = kr as usize * cm.width + kc as usize;
            if cm.cost[k] < INSCRIBED && best.is_none_or(|b| dc * dc + dr * dr < b.0) {
                best = Some((dc * dc + dr * dr, k));
            }
        }
    }
    best.map(|b| b.1)
}

/// Whether the straight segment crosses only cells cheaper than `max_cost`.
pub fn segment_cost_ok(cm: &Costmap, a: Point2, b: Point2, max_cost: u8) -> bool {
    let n = (a.dist(b) / (cm.resolution * 0.5)).ceil().max(1.0) as usize;
    (0..=n).all(|k| {
        let t = k as f64 / n as f64;
        cm.cost_at(Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))) < max_cost
    })
}

/// Greedy string pulling: from each kept point, jump to the farthest point in cheap sight.
/// A leg never crosses a cell as costly as `max_cost`, not even from a costly point: from a
/// start (or a goal) near a wall the path keeps the search's cells, which leave the costly band
/// down its gradient, rather than a straight leg that runs along the wall at the start's cost
/// (where a footprint wider than the inscribed radius rubs it the whole way).
fn string_pull(cm: &Costmap, pts: &[Point2], max_cost: u8) -> Vec<Point2> {
    if pts.len() <= 2 {
        return pts.to_vec();
    }
    let mut out = vec![pts[0]];
    let mut i = 0;
    while i < pts.len() - 1 {
        let mut j = i + 1;
        // A leg from a point as costly as `max_cost` fails at its first cell: keep the next.
        let mut k = if cm.cost_at(pts[i]) >= max_cost { i + 1 } else { pts.len() - 1 };
        // Farthest visible point, scanning back from the end (paths are short; fine).
        while k > i + 1 {
            if segment_cost_ok(cm, pts[i], pts[k], max_cost) {
                j = k;
                break;
            }
            k -= 1;
        }
        out.push(pts[j]);
        i = j;
    }
    out
}

/// Points every `step` (m) along the polyline, ends kept.
fn densify(pts: &[Point2], step: f64) -> Vec<Point2> {
    let mut out = vec![pts[0]];
    for w in pts.windows(2) {
        let n = (w[0].dist(w[1]) / step).ceil().max(1.0) as usize;
        for k in 1..=n {
            let t = k as f64 / n as f64;
            out.push(Point2::new(w[0].x + t * (w[1].x - w[0].x), w[0].y + t * (w[1].y - w[0].y)));
        }
    }
    out
}

fn with_headings(pts: &[Point2]) -> Vec<Pose2> {
    (0..pts.len())
        .map(|i| {
            let (a, b) = if i + 1 < pts.len() { (pts[i], pts[i + 1]) } else if i > 0 { (pts[i - 1], pts[i]) } else { (pts[i], pts[i]) };
            Pose2::new(pts[i].x, pts[i].y, (b.y - a.y).atan2(b.x - a.x))
        })
        .collect()
}

/// Length of a path (m).
pub fn path_length(path: &[Pose2]) -> f64 {
    path.windows(2).map(|w| w[0].position().dist(w[1].position())).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap::{CostmapParams, LETHAL};
    use xhab_types::OccupancyGrid;

    /// A 4 x 4 m room split by a wall at x = 2 with a gap at y in [3, 3.6].
    fn maze() -> Costmap {
        let mut m = OccupancyGrid::new(80, 80, 0.05, Pose2::default(), 0);
        for r in 0..80 {
            for c in 0..80 {
                let border = c == 0 || r == 0 || c == 79 || r == 79;
                let wall = (39..=40).contains(&c) && !(60..72).contains(&r);
                if border || wall {
                    m.set(c, r, 100);
                }
            }
        }
        Costmap::from_map(&m, &CostmapParams { inflation_radius: 0.3, ..Default::default() })
    }

    #[test]
    fn plans_through_the_gap_close_to_the_shortest_path() {
        let cm = maze();
        let (s, g) = (Point2::new(1.0, 1.0), Point2::new(3.0, 1.0));
        let mut lengths = Vec::new();
        for use_astar in [true, false] {
            let path = plan(&cm, s, g, &PlannerParams { use_astar, ..Default::default() }).unwrap();
            assert!(path.iter().all(|q| cm.cost_at(q.position()) < INSCRIBED));
            // Through the gap: some point with y > 3.
            assert!(path.iter().any(|q| q.y > 3.0 && (q.x - 2.0).abs() < 0.1));
            lengths.push(path_length(&path));
        }
        // Through the middle of the 0.6 m gap (y = 3.3), as a wall-avoiding planner should:
        // 2 * hypot(1, 2.3) = 5.02 m; the point-robot bound via the gap's corner is 4.47 m.
        let exact = 2.0 * 1f64.hypot(2.3);
        assert!(lengths[0] >= 2.0 * 1f64.hypot(2.0) && lengths[0] < exact * 1.03, "{lengths:?} vs {exact}");
        assert!((lengths[0] - lengths[1]).abs() < 0.05 * exact, "{lengths:?}");
    }

    #[test]
    fn kept_working_memory_gives_the_same_plans() {
        let cm = maze();
        let mut scratch = PlanScratch::default();
        let queries = [((1.0, 1.0), (3.0, 1.0)), ((3.5, 3.5), (0.5, 0.5)), ((1.0, 1.0), (9.0, 1.0)), ((2.0, 3.3), (3.8, 0.2)), ((1.0, 1.0), (3.0, 1.0))];
        for ((sx, sy), (gx, gy)) in queries {
            let (a, b) = (Point2::new(sx, sy), Point2::new(gx, gy));
            let p = PlannerParams::default();
            assert_eq!(plan_with(&mut scratch, &cm, a, b, &p), plan(&cm, a, b, &p));
        }
        // Another map size resets it.
        let small = Costmap::from_map(&OccupancyGrid::new(30, 20, 0.05, Pose2::default(), 0), &CostmapParams::default());
        let (a, b) = (Point2::new(0.2, 0.2), Point2::new(1.3, 0.8));
        assert_eq!(plan_with(&mut scratch, &small, a, b, &PlannerParams::default()), plan(&small, a, b, &PlannerParams::default()));
    }

    #[test]
    fn a_start_and_goal_beside_a_wall_get_a_path_that_leaves_it_between_them() {
        // A long wall at y = 2 (rows 40-41); start and goal 0.15 m below it, 3 m apart, where
        // the default inflation costs 152. A straight leg at the start's cost used to hug the
        // wall all the way; the path now leaves the costly band (cost < smooth_max_cost) in
        // between, as the search's cells do.
        let mut m = OccupancyGrid::new(100, 80, 0.05, Pose2::default(), 0);
        for c in 0..100 {
            m.set(c, 40, 100);
            m.set(c, 41, 100);
        }
        let cm = Costmap::from_map(&m, &CostmapParams::default());
        let (s, g) = (Point2::new(1.0, 1.85), Point2::new(4.0, 1.85));
        let p = PlannerParams::default();
        assert!(cm.cost_at(s) > p.smooth_max_cost && cm.cost_at(g) > p.smooth_max_cost);
        let path = plan(&cm, s, g, &p).unwrap();
        let middle: Vec<&Pose2> = path.iter().filter(|q| q.x > 1.8 && q.x < 3.2).collect();
        assert!(!middle.is_empty() && middle.iter().all(|q| cm.cost_at(q.position()) < p.smooth_max_cost), "{path:?}");
        assert!(path_length(&path) < 3.0 * 1.15, "{path:?}");
    }

    #[test]
    fn a_remembered_search_gives_the_plan_a_new_search_gives() {
        let mut m = OccupancyGrid::new(100, 80, 0.05, Pose2::default(), 0);
        for r in 10..70 {
            m.set(50, r, 100);
        }
        let p = PlannerParams::default();
        let mut cm = Costmap::from_map(&m, &CostmapParams::default());
        let mut scratch = PlanScratch::default();
        let goal = Point2::new(4.0, 2.0);
        // The same version: the search is remembered, and each start's plan is still its own.
        for start in [Point2::new(1.0, 2.0), Point2::new(1.01, 2.02), Point2::new(1.5, 1.0)] {
            let got = plan_on_version(&mut scratch, &cm, Some(7), start, goal, &p).unwrap();
            assert_eq!(got, plan(&cm, start, goal, &p).unwrap(), "{start:?}");
        }
        assert!(scratch.memo.is_some());
        // A wall across the way on a new version: the remembered search is not used.
        for c in 0..100 {
            let i = 40 * cm.width + c;
            if c != 20 {
                cm.cost[i] = LETHAL;
            }
        }
        let start = Point2::new(1.5, 1.0);
        let got = plan_on_version(&mut scratch, &cm, Some(8), start, goal, &p);
        assert_eq!(got, plan(&cm, start, goal, &p));
    }

    #[test]
    fn enclosed_goals_fail_cleanly() {
        let cm = maze();
        assert_eq!(plan(&cm, Point2::new(1.0, 1.0), Point2::new(9.0, 1.0), &PlannerParams::default()), Err(PlanError::GoalOutsideMap));
        let mut m = OccupancyGrid::new(40, 40, 0.05, Pose2::default(), 0);
        for k in 0..40 {
            m.set(20, k, 100);
        }
        let cm = Costmap::from_map(&m, &CostmapParams::default());
        assert_eq!(plan(&cm, Point2::new(0.3, 1.0), Point2::new(1.7, 1.0), &PlannerParams::default()), Err(PlanError::NoPath));
    }
}
