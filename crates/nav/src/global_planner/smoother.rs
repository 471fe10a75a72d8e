//! Path post-processing: cost-aware shortcutting of the grid path (an any-angle path whose
//! every straight leg costs no more than the grid path it replaces), resampling, and a light
//! gradient smoother that rounds corners where the costmap allows.

use super::grid_search::{segment_cost, segment_passable};
use crate::costmap_2d::Costmap2D;
use xhab_types::Point2;

/// Grid points looked ahead of the current point for a shortcut.
const MAX_LOOKAHEAD: usize = 400;
/// Failed shortcuts in a row after which the lookahead stops.
const MAX_MISSES: usize = 16;

/// Greedy shortcutting: from each kept point, jump to the farthest point ahead whose straight
/// segment costs (on `weights`) no more than the grid path between them (`cum_cost[i]` is the
/// path's cost from its start to point `i`). Ends are kept.
pub fn shortcut(
    costmap: &Costmap2D,
    weights: &[f64],
    pts: &[Point2],
    cum_cost: &[f64],
) -> Vec<Point2> {
    let n = pts.len();
    if n <= 2 {
        return pts.to_vec();
    }
    let mut out = vec![pts[0]];
    let mut i = 0;
    while i < n - 1 {
        let mut best = i + 1;
        let mut misses = 0;
        let mut j = i + 2;
        while j < n && j - i <= MAX_LOOKAHEAD {
            let grid = cum_cost[j] - cum_cost[i];
            if segment_cost(costmap, weights, pts[i], pts[j]) <= grid * (1.0 + 1e-9) + 1e-9 {
                best = j;
                misses = 0;
            } else {
                misses += 1;
                if misses > MAX_MISSES {
                    break;
                }
            }
            j += 1;
        }
        out.push(pts[best]);
        i = best;
    }
    out
}

/// Points every `spacing` (m) or less along the polyline, its vertices kept.
pub fn densify(pts: &[Point2], spacing: f64) -> Vec<Point2> {
    let Some(&first) = pts.first() else {
        return Vec::new();
    };
    let mut out = vec![first];
    for w in pts.windows(2) {
        let k = (w[0].dist(w[1]) / spacing).ceil().max(1.0) as usize;
        for s in 1..=k {
            let t = s as f64 / k as f64;
            out.push(Point2::new(
                w[0].x + t * (w[1].x - w[0].x),
                w[0].y + t * (w[1].y - w[0].y),
            ));
        }
    }
    out
}

/// Smoothing strength towards the neighbours' midpoint per iteration.
const ALPHA: f64 = 0.3;
/// Pull back towards the original point per iteration.
const BETA: f64 = 0.05;
/// Iterations of the smoother.
const ITERATIONS: usize = 30;
/// How much a move may raise the per-metre cost weight at a point.
const WEIGHT_SLACK: f64 = 0.05;

/// Rounds corners: each interior point moves towards its neighbours' midpoint and a little
/// back towards where it was; a move that would bring it or its two segments into an
/// impassable cell, or raise the cost
/// weight there (beyond a small slack) is not made. Ends stay put.
pub fn smooth(costmap: &Costmap2D, weights: &[f64], pts: &mut [Point2]) {
    let n = pts.len();
    if n < 3 {
        return;
    }
    let weight_at = |p: Point2| {
        costmap
            .world_to_map(p)
            .map_or(f64::INFINITY, |(x, y)| weights[costmap.index(x, y)])
    };
    let orig = pts.to_vec();
    for _ in 0..ITERATIONS {
        for i in 1..n - 1 {
            let p = pts[i];
            let target = Point2::new(
                p.x + ALPHA * (pts[i - 1].x + pts[i + 1].x - 2.0 * p.x) + BETA * (orig[i].x - p.x),
                p.y + ALPHA * (pts[i - 1].y + pts[i + 1].y - 2.0 * p.y) + BETA * (orig[i].y - p.y),
            );
            let w = weight_at(target);
            if w.is_finite()
                && w <= weight_at(p).max(weight_at(orig[i])) + WEIGHT_SLACK
                && segment_passable(costmap, weights, pts[i - 1], target)
                && segment_passable(costmap, weights, target, pts[i + 1])
            {
                pts[i] = target;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn densify_keeps_vertices_and_spacing() {
        let d = densify(
            &[
                Point2::new(0.0, 0.0),
                Point2::new(1.0, 0.0),
                Point2::new(1.0, 0.25),
            ],
            0.1,
        );
        assert_eq!(d.len(), 1 + 10 + 3);
        assert!(d.windows(2).all(|w| w[0].dist(w[1]) <= 0.1 + 1e-12));
        assert_eq!(d[10], Point2::new(1.0, 0.0));
    }
}
