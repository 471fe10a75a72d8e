//! Frontiers of a map being built: free cells next to unknown space, grouped into connected
//! frontiers, each with the cheapest cell the robot can reach over known free space (the
//! frontier-based exploration of Yamauchi 1997, with explore_lite's `min_frontier_size`).

use crate::costmap::{Costmap, INSCRIBED};
use serde::{Deserialize, Serialize};
use std::cmp::Reverse;
use std::collections::BinaryHeap;
use xhab_types::{OccupancyGrid, Point2, GRID_FREE, GRID_UNKNOWN};

/// Frontier search parameters (explore_lite names where they exist).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrontierParams {
    /// Smallest frontier worth visiting: its length along the boundary (m, default 0.5).
    pub min_frontier_size: f64,
    /// Targets within this distance of a blacklisted point are skipped (m, default 0.5).
    pub blacklist_radius: f64,
}

impl Default for FrontierParams {
    fn default() -> Self {
        Self { min_frontier_size: 0.5, blacklist_radius: 0.5 }
    }
}

/// One frontier: a connected group of frontier cells.
#[derive(Debug, Clone, PartialEq)]
pub struct Frontier {
    /// Number of cells.
    pub cells: usize,
    /// Length along the boundary (m): cells times resolution.
    pub size_m: f64,
    /// Mean of the cell centres (m).
    pub centroid: Point2,
    /// The frontier cell the robot reaches most cheaply (m), if any is reachable.
    pub target: Option<Point2>,
    /// Path length to `target` over known free space (m); infinite when unreachable.
    pub distance: f64,
}

/// The frontiers of `map`, nearest reachable first (unreachable ones last, by size), with
/// reachability from `robot` over cells that are known free and cheaper than INSCRIBED in
/// `cm` (the costmap of the same map: same size, origin and resolution). A frontier's target
/// is its cheapest cell farther than `blacklist_radius` from every point of `blacklist`.
pub fn find_frontiers(map: &OccupancyGrid, cm: &Costmap, robot: Point2, blacklist: &[Point2], p: &FrontierParams) -> Vec<Frontier> {
    let (w, h) = (map.width, map.height);
    if cm.width != w || cm.height != h || w == 0 || h == 0 {
        return Vec::new();
    }
    let is_frontier = |i: usize| {
        if map.data[i] != GRID_FREE {
            return false;
        }
        let (c, r) = (i % w, i / w);
        (c > 0 && map.data[i - 1] == GRID_UNKNOWN)
            || (c + 1 < w && map.data[i + 1] == GRID_UNKNOWN)
            || (r > 0 && map.data[i - w] == GRID_UNKNOWN)
            || (r + 1 < h && map.data[i + w] == GRID_UNKNOWN)
    };
    let frontier: Vec<bool> = (0..w * h).map(is_frontier).collect();
    let dist = reach(map, cm, robot);
    let mut label = vec![u32::MAX; w * h];
    let mut out = Vec::new();
    for seed in 0..w * h {
        if !frontier[seed] || label[seed] != u32::MAX {
            continue;
        }
        let id = out.len() as u32;
        label[seed] = id;
        let mut stack = vec![seed];
        let (mut n, mut sx, mut sy) = (0usize, 0.0, 0.0);
        let (mut best, mut best_d) = (None, f64::INFINITY);
        while let Some(i) = stack.pop() {
            let (c, r) = (i % w, i / w);
            let q = map.cell_center(c, r);
            n += 1;
            sx += q.x;
            sy += q.y;
            if dist[i] < best_d && blacklist.iter().all(|b| b.dist(q) > p.blacklist_radius) {
                (best, best_d) = (Some(q), dist[i]);
            }
            for (dc, dr) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (kc, kr) = (c as i64 + dc, r as i64 + dr);
                if kc < 0 || kr < 0 || kc >= w as i64 || kr >= h as i64 {
                    continue;
                }
                let k = kr as usize * w + kc as usize;
                if frontier[k] && label[k] == u32::MAX {
                    label[k] = id;
                    stack.push(k);
                }
            }
        }
        let size_m = n as f64 * map.resolution;
        if size_m + 1e-9 < p.min_frontier_size {
            continue;
        }
        out.push(Frontier { cells: n, size_m, centroid: Point2::new(sx / n as f64, sy / n as f64), target: best, distance: best_d });
    }
    out.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(b.cells.cmp(&a.cells)));
    out
}

/// Whether a frontier cell of `map` (free, next to unknown) lies within `radius` (m) of `p`.
pub fn frontier_near(map: &OccupancyGrid, p: Point2, radius: f64) -> bool {
    let (w, h) = (map.width as i64, map.height as i64);
    let k = (radius / map.resolution).ceil() as i64;
    let c0 = ((p.x - map.origin.x) / map.resolution).floor() as i64;
    let r0 = ((p.y - map.origin.y) / map.resolution).floor() as i64;
    let unknown = |c: i64, r: i64| c >= 0 && r >= 0 && c < w && r < h && map.data[(r * w + c) as usize] == GRID_UNKNOWN;
    for r in (r0 - k).max(0)..=(r0 + k).min(h - 1) {
        for c in (c0 - k).max(0)..=(c0 + k).min(w - 1) {
            if map.data[(r * w + c) as usize] == GRID_FREE
                && map.cell_center(c as usize, r as usize).dist(p) <= radius
                && (unknown(c - 1, r) || unknown(c + 1, r) || unknown(c, r - 1) || unknown(c, r + 1))
            {
                return true;
            }
        }
    }
    false
}

/// The nearest frontier with a reachable target.
pub fn nearest_frontier(frontiers: &[Frontier]) -> Option<&Frontier> {
    frontiers.iter().find(|f| f.target.is_some() && f.distance.is_finite())
}

/// Path length (m) from `robot` to every cell over known free cells cheaper than INSCRIBED
/// (Dijkstra, 8-connected, no corner cutting); infinite where unreachable. The robot's own
/// cell counts as passable even inside the inflation, so that it can leave a wall.
fn reach(map: &OccupancyGrid, cm: &Costmap, robot: Point2) -> Vec<f64> {
    let (w, h) = (map.width, map.height);
    let mut dist = vec![f64::INFINITY; w * h];
    let Some((sc, sr)) = cm.cell(robot) else { return dist };
    let passable = |i: usize| map.data[i] == GRID_FREE && cm.cost[i] < INSCRIBED;
    // Start from the robot's cell, or from the nearest passable cell within 0.35 m.
    let s = sr * w + sc;
    let reach_cells = (0.35 / map.resolution).ceil() as i64;
    let mut starts = vec![];
    if passable(s) {
        starts.push((s, 0.0));
    } else {
        for dr in -reach_cells..=reach_cells {
            for dc in -reach_cells..=reach_cells {
                let (c, r) = (sc as i64 + dc, sr as i64 + dr);
                if c >= 0 && r >= 0 && c < w as i64 && r < h as i64 && passable(r as usize * w + c as usize) {
                    let d = ((dc * dc + dr * dr) as f64).sqrt() * map.resolution;
                    if d <= 0.35 {
                        starts.push((r as usize * w + c as usize, d));
                    }
                }
            }
        }
    }
    let mut heap = BinaryHeap::new();
    for (i, d) in starts {
        if d < dist[i] {
            dist[i] = d;
            heap.push(Reverse((d.to_bits(), i as u32)));
        }
    }
    let diag = std::f64::consts::SQRT_2 * map.resolution;
    while let Some(Reverse((db, m))) = heap.pop() {
        let m = m as usize;
        let dm = f64::from_bits(db);
        if dm > dist[m] {
            continue;
        }
        let (c, r) = ((m % w) as i64, (m / w) as i64);
        for (dc, dr) in [(1i64, 0i64), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)] {
            let (kc, kr) = (c + dc, r + dr);
            if kc < 0 || kr < 0 || kc >= w as i64 || kr >= h as i64 {
                continue;
            }
            let k = kr as usize * w + kc as usize;
            if !passable(k) {
                continue;
            }
            let len = if dc != 0 && dr != 0 {
                if !passable(r as usize * w + kc as usize) || !passable(kr as usize * w + c as usize) {
                    continue;
                }
                diag
            } else {
                map.resolution
            };
            let nd = dm + len;
            if nd < dist[k] {
                dist[k] = nd;
                heap.push(Reverse((nd.to_bits(), k as u32)));
            }
        }
    }
    dist
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::costmap::CostmapParams;
    use xhab_types::{Pose2, GRID_OCCUPIED};

    /// A 4 x 2 m corridor, known over its left half, open to the unknown on the right; a
    /// separate known pocket (walled off) with its own frontier.
    fn half_known() -> OccupancyGrid {
        let mut m = OccupancyGrid::new(120, 40, 0.05, Pose2::default(), GRID_UNKNOWN);
        for r in 0..40 {
            for c in 0..120 {
                let wall = r == 0 || r == 39 || c == 0;
                if wall && c < 80 {
                    m.set(c, r, GRID_OCCUPIED);
                } else if c < 40 {
                    m.set(c, r, GRID_FREE);
                }
            }
        }
        // The pocket: cells 60..70 x 10..30 free, surrounded by a wall ring, unknown to the right.
        for r in 9..=30 {
            for c in 59..=70 {
                let ring = r == 9 || r == 30 || c == 59;
                m.set(c, r, if ring { GRID_OCCUPIED } else { GRID_FREE });
            }
        }
        m
    }

    #[test]
    fn finds_the_open_side_as_the_nearest_reachable_frontier() {
        let map = half_known();
        let cm = Costmap::from_map(&map, &CostmapParams::default());
        let p = FrontierParams::default();
        let fs = find_frontiers(&map, &cm, Point2::new(0.5, 1.0), &[], &p);
        assert_eq!(fs.len(), 2, "{fs:?}");
        let near = nearest_frontier(&fs).expect("a reachable frontier");
        // The corridor's frontier: the column of cells at x = 1.95 m, reached along the corridor.
        let t = near.target.unwrap();
        assert!((t.x - 1.975).abs() < 1e-9, "{t:?}");
        assert!((near.distance - 1.475).abs() < 0.15, "{}", near.distance);
        // The walled pocket's frontier is known but unreachable over known free space.
        let pocket = fs.iter().find(|f| f.centroid.x > 3.0).expect("pocket frontier");
        assert!(pocket.distance.is_infinite() && pocket.target.is_none());
        assert!(frontier_near(&map, Point2::new(2.2, 1.0), 0.3));
        assert!(!frontier_near(&map, Point2::new(1.0, 1.0), 0.5));
        // Blacklisting the target moves it along the frontier, out of the blacklisted disc.
        let fs = find_frontiers(&map, &cm, Point2::new(0.5, 1.0), &[t], &p);
        let other = nearest_frontier(&fs).expect("still reachable").target.unwrap();
        assert!(other.dist(t) > p.blacklist_radius && (other.x - 1.975).abs() < 1e-9, "{other:?}");
        // Blacklisting the whole frontier leaves nothing reachable.
        let fs = find_frontiers(&map, &cm, Point2::new(0.5, 1.0), &[Point2::new(1.975, 0.5), Point2::new(1.975, 1.0), Point2::new(1.975, 1.5)], &p);
        assert!(nearest_frontier(&fs).is_none());
    }

    #[test]
    fn small_frontiers_are_ignored() {
        let mut map = OccupancyGrid::new(40, 40, 0.05, Pose2::default(), GRID_FREE);
        map.set(20, 20, GRID_UNKNOWN);
        let cm = Costmap::from_map(&map, &CostmapParams::default());
        let p = FrontierParams::default();
        assert!(find_frontiers(&map, &cm, Point2::new(0.5, 0.5), &[], &p).is_empty());
        let p = FrontierParams { min_frontier_size: 0.2, ..p };
        assert_eq!(find_frontiers(&map, &cm, Point2::new(0.5, 0.5), &[], &p).len(), 1);
    }
}
