//! Teleport-and-slide motion without physics, as Habitat's `try_step` with allow_sliding.

use crate::geodesic::segment_clear;
use crate::navgrid::{NavGrid, NAV_TOLERANCE};
use xhab_types::Point2;

/// How far inside the agent radius a move may pass (m): the same tolerance as the geodesic's
/// line of sight, so that every straight leg of a shortest path can be walked.
const MOTION_EPS: f64 = crate::geodesic::LOS_EPS;

/// Bisection steps when searching the last free point of a blocked move (2^-14 of a step).
const BISECT: u32 = 14;

/// Moves the agent from `from` towards `to` (m). A move that would leave the navigable region
/// stops at the boundary and slides along it with the motion's tangential part. Returns the
/// end point and whether the move was blocked or deflected (a collision).
pub fn try_step(grid: &NavGrid, from: Point2, to: Point2) -> (Point2, bool) {
    // Moves keep the full radius; an agent that starts a little inside it (an episode start
    // within the navigability tolerance) may move within that tolerance.
    let strict = segment_clear(grid, [from.x, from.y], [from.x, from.y], MOTION_EPS);
    let eps = if strict { MOTION_EPS } else { NAV_TOLERANCE };
    let clear = |a: Point2, b: Point2| segment_clear(grid, [a.x, a.y], [b.x, b.y], eps);
    if clear(from, to) {
        return (to, false);
    }
    let hit = last_free(from, to, &clear);
    // Slide: keep the part of the remaining motion that does not push into the obstacle.
    let rem = [to.x - hit.x, to.y - hit.y];
    let Some(n) = outward_normal(grid, hit) else { return (hit, true) };
    let into = rem[0] * n[0] + rem[1] * n[1];
    if into >= 0.0 {
        return (hit, true);
    }
    let tangent = Point2::new(hit.x + rem[0] - into * n[0], hit.y + rem[1] - into * n[1]);
    if tangent.dist(hit) < 1e-6 {
        return (hit, true);
    }
    if clear(hit, tangent) {
        return (tangent, true);
    }
    (last_free(hit, tangent, &clear), true)
}

/// The farthest point on `a -> b` reachable in a straight line (bisection).
fn last_free(a: Point2, b: Point2, clear: &impl Fn(Point2, Point2) -> bool) -> Point2 {
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let at = |t: f64| Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
    for _ in 0..BISECT {
        let mid = 0.5 * (lo + hi);
        if clear(a, at(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    at(lo)
}

/// Unit vector pointing away from the nearest obstacle at `p`, if there is one nearby.
fn outward_normal(grid: &NavGrid, p: Point2) -> Option<[f64; 2]> {
    let i = grid.cell_of(p)?;
    let v = if let Some(q) = grid.nearest_point(i, [p.x, p.y]) {
        [p.x - q[0], p.y - q[1]]
    } else {
        // Floor edge: the clearance gradient (central differences).
        let e = 0.5 * grid.resolution();
        let gx = grid.clearance_at(Point2::new(p.x + e, p.y)) - grid.clearance_at(Point2::new(p.x - e, p.y));
        let gy = grid.clearance_at(Point2::new(p.x, p.y + e)) - grid.clearance_at(Point2::new(p.x, p.y - e));
        [gx, gy]
    };
    let l = v[0].hypot(v[1]);
    (l > 1e-9).then(|| [v[0] / l, v[1] / l])
}
