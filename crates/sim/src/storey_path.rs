//! Shortest paths across storeys, through the flights of stairs that two storeys' grids share.
//!
//! Each storey's grid holds the middle of every flight that joins it to the storey above
//! (see [`crate::navgrid::StoreyBounds`]), so a path from one storey to the next changes grid
//! somewhere on that overlap. A [`Portal`] samples the overlap's middle tread; a path's planar
//! length is the least over the portal points of the two storeys' planar geodesics (any path
//! up the flight crosses that tread). Its length is then measured as Habitat measures a
//! navmesh path: the 3D lengths of the straight legs between the planar path's bend points,
//! each bend point at the height of the surface under it ([`NavGrid::surface_height`]) (a flight climbed straight is one leg
//! from its foot's floor to its top's). Storeys without stairs keep planar lengths.

use crate::geodesic::geodesic_distance;
use crate::goal_field::GoalField;
use crate::navgrid::NavGrid;
use crate::world::World;
use xhab_types::{Point2, Point3};

/// Points per portal: spread over the middle tread, a few centimetres apart on a stair a
/// metre wide, so the crossing point is missed by at most that (a path's length changes by
/// the square of it over the path's length).
const PORTAL_POINTS: usize = 16;

/// Where the grids of storeys `lower` and `lower + 1` overlap on a flight.
#[derive(Debug, Clone, PartialEq)]
pub struct Portal {
    /// The lower storey's index.
    pub lower: usize,
    /// Points on the flight's middle tread, navigable in both storeys' grids (m; z is the
    /// tread's height).
    pub points: Vec<Point3>,
}

/// The portals between adjacent storeys of `world` (none between storeys no flight joins).
pub(crate) fn find_portals(world: &World) -> Vec<Portal> {
    let mut out = Vec::new();
    for k in 0..world.floors.len().saturating_sub(1) {
        let (Ok(a), Ok(b)) = (world.grid(k), world.grid(k + 1)) else { continue };
        if !a.has_stairs() || !b.has_stairs() || a.size() != b.size() {
            continue;
        }
        // Cells both storeys navigate at the same height, on a flight in both.
        let shared: Vec<usize> = (0..a.ground.len())
            .filter(|&i| a.stair[i] && b.stair[i] && a.is_nav_cell(i) && b.is_nav_cell(i) && (a.ground[i] - b.ground[i]).abs() < 1e-4)
            .collect();
        if shared.is_empty() {
            continue;
        }
        // Every flight's middle tread: per component of the overlap, the cells at its median
        // height.
        for comp in components(&a, &shared) {
            let mut z: Vec<f32> = comp.iter().map(|&i| a.ground[i]).collect();
            z.sort_by(|x, y| x.total_cmp(y));
            let mid = z[z.len() / 2];
            let tread: Vec<usize> = comp.iter().copied().filter(|&i| (a.ground[i] - mid).abs() < 1e-4).collect();
            let points = spread(&a, &tread, PORTAL_POINTS)
                .into_iter()
                .map(|i| {
                    let c = a.center(i);
                    Point3::new(c[0], c[1], a.ground[i] as f64)
                })
                .collect();
            out.push(Portal { lower: k, points });
        }
    }
    out
}

/// 8-connected components of `cells` (sorted cell indices of `grid`), each sorted.
fn components(grid: &NavGrid, cells: &[usize]) -> Vec<Vec<usize>> {
    let (w, h) = grid.size();
    let set: std::collections::BTreeSet<usize> = cells.iter().copied().collect();
    let mut seen = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for &s in cells {
        if !seen.insert(s) {
            continue;
        }
        let mut comp = vec![s];
        let mut stack = vec![s];
        while let Some(i) = stack.pop() {
            let (c, r) = ((i % w) as isize, (i / w) as isize);
            for dr in -1..=1 {
                for dc in -1..=1 {
                    let (cc, rr) = (c + dc, r + dr);
                    if cc < 0 || rr < 0 || cc >= w as isize || rr >= h as isize {
                        continue;
                    }
                    let j = (rr * w as isize + cc) as usize;
                    if set.contains(&j) && seen.insert(j) {
                        comp.push(j);
                        stack.push(j);
                    }
                }
            }
        }
        comp.sort();
        out.push(comp);
    }
    out
}

/// Up to `k` of `cells`, spread out: the first cell, then each time the cell farthest from
/// those chosen (ties to the lower index), so the result is the same on every run.
fn spread(grid: &NavGrid, cells: &[usize], k: usize) -> Vec<usize> {
    if cells.len() <= k {
        return cells.to_vec();
    }
    let pos: Vec<[f64; 2]> = cells.iter().map(|&i| grid.center(i)).collect();
    let mut chosen = vec![0usize];
    let mut near: Vec<f64> = pos.iter().map(|p| dist(*p, pos[0])).collect();
    while chosen.len() < k {
        let (mut best, mut far) = (0, -1.0);
        for (j, &d) in near.iter().enumerate() {
            if d > far {
                (best, far) = (j, d);
            }
        }
        chosen.push(best);
        for (j, p) in pos.iter().enumerate() {
            near[j] = near[j].min(dist(*p, pos[best]));
        }
    }
    chosen.sort();
    chosen.into_iter().map(|j| cells[j]).collect()
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Geodesic distance between two points of `world` on any storeys (m), measured as Habitat
/// measures a navmesh path (see the module's notes); infinite when no walkable path joins
/// them. Each point's storey is [`World::storey_of`]'s.
pub fn distance(world: &World, a: Point3, b: Point3) -> f64 {
    path(world, a, b).map_or(f64::INFINITY, |p| length(&p))
}

/// The shortest path between two points of `world` as 3D bend points (m), `a` first; `None`
/// when no walkable path joins them.
pub fn path(world: &World, a: Point3, b: Point3) -> Option<Vec<Point3>> {
    let (Some(sa), Some(sb)) = (world.storey_of(a), world.storey_of(b)) else { return None };
    if sa > sb {
        let mut p = path(world, b, a)?;
        p.reverse();
        return Some(p);
    }
    let grids: Vec<std::sync::Arc<NavGrid>> = (sa..=sb).map(|k| world.grid(k).ok()).collect::<Option<_>>()?;
    let (a2, b2) = (Point2::new(a.x, a.y), Point2::new(b.x, b.y));
    if sa == sb {
        let g = &grids[0];
        if !geodesic_distance(g, a2, b2).is_finite() {
            return None;
        }
        return Some(lift(g, &GoalField::new(g, &[b2]).path(g, a2)));
    }
    // Planar distances hop by hop: the best way to each portal point of the next flight.
    let portals = world.portals();
    let hops: Vec<Vec<Point2>> = (sa..sb)
        .map(|k| portals.iter().filter(|p| p.lower == k).flat_map(|p| p.points.iter().map(|q| Point2::new(q.x, q.y))).collect())
        .collect();
    if hops.iter().any(|h| h.is_empty()) {
        return None;
    }
    // best[h][j]: planar length from a to point j of hop h, and the point of hop h - 1 it came by.
    let mut best: Vec<Vec<(f64, usize)>> = Vec::new();
    for (h, pts) in hops.iter().enumerate() {
        let g = &grids[h];
        let row = pts
            .iter()
            .map(|&t| {
                if h == 0 {
                    (geodesic_distance(g, a2, t), usize::MAX)
                } else {
                    hops[h - 1]
                        .iter()
                        .enumerate()
                        .map(|(j, &s)| (best[h - 1][j].0 + geodesic_distance(g, s, t), j))
                        .fold((f64::INFINITY, usize::MAX), |x, y| if y.0 < x.0 { y } else { x })
                }
            })
            .collect();
        best.push(row);
    }
    let last = grids.last()?;
    let (total, mut j) = hops[hops.len() - 1]
        .iter()
        .enumerate()
        .map(|(j, &t)| (best[hops.len() - 1][j].0 + geodesic_distance(last, t, b2), j))
        .fold((f64::INFINITY, usize::MAX), |x, y| if y.0 < x.0 { y } else { x });
    if !total.is_finite() {
        return None;
    }
    // The chosen crossing points, first hop first.
    let mut cross = vec![Point2::new(0.0, 0.0); hops.len()];
    for h in (0..hops.len()).rev() {
        cross[h] = hops[h][j];
        j = best[h][j].1;
    }
    // Each storey's piece of the path, lifted onto its surfaces; a crossing point is a bend
    // only where the path turns there.
    let mut out: Vec<Point3> = Vec::new();
    for (k, g) in grids.iter().enumerate() {
        let from = if k == 0 { a2 } else { cross[k - 1] };
        let to = if k == grids.len() - 1 { b2 } else { cross[k] };
        let piece = lift(g, &GoalField::new(g, &[to]).path(g, from));
        if out.is_empty() {
            out = piece;
        } else {
            out.pop();
            out.extend(piece);
        }
    }
    Some(straighten_crossings(out, &cross))
}

/// Removes crossing points where the path runs straight through them (turning by less than
/// two degrees): there the two storeys' legs are one leg, as on a navmesh.
fn straighten_crossings(path: Vec<Point3>, cross: &[Point2]) -> Vec<Point3> {
    let mut out: Vec<Point3> = Vec::with_capacity(path.len());
    for (i, p) in path.iter().enumerate() {
        let is_cross = cross.iter().any(|c| (c.x - p.x).abs() < 1e-9 && (c.y - p.y).abs() < 1e-9);
        if is_cross && i > 0 && i + 1 < path.len() {
            let (a, b) = (out[out.len() - 1], path[i + 1]);
            let (u, v) = ([p.x - a.x, p.y - a.y], [b.x - p.x, b.y - p.y]);
            let (lu, lv) = (u[0].hypot(u[1]), v[0].hypot(v[1]));
            let straight = lu < 1e-9 || lv < 1e-9 || (u[0] * v[0] + u[1] * v[1]) / (lu * lv) > 2f64.to_radians().cos();
            if straight {
                continue;
            }
        }
        out.push(*p);
    }
    out
}

/// The planar polyline on `grid` at the heights of the surfaces under it (m), as
/// [`NavGrid::surface_height`] gives them.
fn lift(grid: &NavGrid, pts: &[Point2]) -> Vec<Point3> {
    let mut out: Vec<Point3> = Vec::with_capacity(pts.len());
    for p in pts {
        let z = grid.surface_height(*p);
        // Consecutive duplicates (a path ending on its goal) add nothing.
        if out.last().is_some_and(|q| (q.x - p.x).abs() < 1e-12 && (q.y - p.y).abs() < 1e-12) {
            continue;
        }
        out.push(Point3::new(p.x, p.y, z));
    }
    out
}

/// Length of a 3D polyline (m).
pub fn length(path: &[Point3]) -> f64 {
    path.windows(2).map(|w| ((w[1].x - w[0].x).powi(2) + (w[1].y - w[0].y).powi(2) + (w[1].z - w[0].z).powi(2)).sqrt()).sum()
}
