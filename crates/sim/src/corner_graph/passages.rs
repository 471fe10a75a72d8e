//! Narrow passages of a floor: the boundary cells of passages at most three cells wide, and
//! the bend points on the arcs about the convex vertices there, which the cells miss (see
//! [`arc_nodes`]).

use crate::navgrid::convex_vertices::ConvexVertices;
use crate::navgrid::NavGrid;
use rayon::prelude::*;
use xhab_types::Point2;

/// Angular step of the bend points placed on the arcs about the obstacles' vertices (degrees).
pub(super) const ARC_STEP_DEG: f64 = 30.0;

/// Bend points on the arcs about the convex vertices of the obstacle segments in narrow
/// passages: every [`ARC_STEP_DEG`] on a circle just wide enough that the chord between two
/// neighbours keeps the agent radius, kept where nothing is nearer than the vertex (the arc's
/// free part) and a boundary cell within one is in a passage at most three cells wide, with
/// the outward normal and island of each. The cells miss these: beside a corner in a passage
/// under two cells wide they have the other side's obstacle nearest, so the corner's arc got
/// no anchor and paths through the passage went the long way round (found by the property
/// tests). Elsewhere the boundary cells' anchors cover the arcs.
pub(super) fn arc_nodes(grid: &NavGrid, passage: &[bool], near_passage: &[bool], convex: Option<&ConvexVertices>) -> Vec<([f64; 2], [f64; 2], u32)> {
    const Q: f64 = 1e5;
    let step = ARC_STEP_DEG.to_radians();
    let big = arc_radius(grid);
    let (w, h) = grid.size();
    // A flat or reflex vertex has no arc a path wraps around.
    let mut verts: Vec<[i64; 2]> = grid
        .segments
        .par_iter()
        .flat_map_iter(|s| s.iter().copied())
        .filter(|&v| arc_vertex(grid, near_passage, v) && convex.is_none_or(|c| c.is_convex(v)))
        .map(|v| [(v[0] * Q).round() as i64, (v[1] * Q).round() as i64])
        .collect();
    verts.par_sort_unstable();
    verts.dedup();
    let turns: Vec<(f64, f64)> = (0..(360.0 / ARC_STEP_DEG).round() as usize).map(|k| (k as f64 * step).sin_cos()).collect();
    let turns = &turns;
    verts
        .par_iter()
        .flat_map_iter(|v| {
            let v = [v[0] as f64 / Q, v[1] as f64 / Q];
            turns.iter().filter_map(move |&(sin, cos)| {
                let p = [v[0] + big * cos, v[1] + big * sin];
                let i = grid.cell_of(Point2::new(p[0], p[1]))?;
                // Only in narrow passages: elsewhere the boundary cells' anchors cover the arc.
                let (c, rr) = (i % w, i / w);
                let in_passage = (rr.saturating_sub(1)..=(rr + 1).min(h - 1))
                    .any(|y| (c.saturating_sub(1)..=(c + 1).min(w - 1)).any(|x| passage[y * w + x]));
                if !in_passage {
                    return None;
                }
                let d = grid.nearest_segment_distance(i, &[p, p])?;
                if d < big - 1e-5 {
                    return None;
                }
                let island = grid.island_at(Point2::new(p[0], p[1]))?;
                Some((p, [cos, sin], island))
            })
        })
        .collect()
}

/// Radius of the circles [`arc_nodes`] places bend points on (m): just wide enough that the
/// chord between two neighbours keeps the agent radius.
pub(super) fn arc_radius(grid: &NavGrid) -> f64 {
    grid.params.radius / (ARC_STEP_DEG.to_radians() / 2.0).cos() + 1e-6
}

/// Per cell, whether a vertex there can have an arc point kept ([`arc_nodes`]): within a cell
/// of a passage cell, so within that and the arc's radius (in cells, rounded up, and one
/// more) of the vertex's own cell.
pub(super) fn arc_reach(grid: &NavGrid, passage: &[bool]) -> Vec<bool> {
    let (w, h) = grid.size();
    dilate(passage, w, h, (arc_radius(grid) / grid.resolution()).ceil() as usize + 2)
}

/// Whether vertex `v` (m) may have arc points ([`arc_reach`]; a vertex off the grid may).
pub(super) fn arc_vertex(grid: &NavGrid, near_passage: &[bool], v: [f64; 2]) -> bool {
    grid.cell_of(Point2::new(v[0], v[1])).is_none_or(|i| near_passage[i])
}

/// `mask` grown by `reach` cells in every direction (a square of side `2 reach + 1`).
fn dilate(mask: &[bool], w: usize, h: usize, reach: usize) -> Vec<bool> {
    if w == 0 || h == 0 {
        return Vec::new();
    }
    // Along rows, then along columns, each by counts of the marked cells before each one:
    // a window holds a marked cell when the counts at its ends differ. Rows in parallel.
    let mut rows = vec![false; w * h];
    rows.par_chunks_mut(w).zip(mask.par_chunks(w)).for_each_init(Vec::new, |count, (out, row)| {
        count.clear();
        count.push(0u32);
        for &m in row {
            count.push(count[count.len() - 1] + m as u32);
        }
        for (c, o) in out.iter_mut().enumerate() {
            *o = count[(c + reach).min(w - 1) + 1] > count[c.saturating_sub(reach)];
        }
    });
    // Marked cells above each row's cells, per column.
    let mut above = vec![0u32; (h + 1) * w];
    for r in 0..h {
        let (done, next) = above.split_at_mut((r + 1) * w);
        for ((n, &a), &m) in next[..w].iter_mut().zip(&done[r * w..]).zip(&rows[r * w..(r + 1) * w]) {
            *n = a + m as u32;
        }
    }
    let mut out = vec![false; w * h];
    out.par_chunks_mut(w).enumerate().for_each(|(r, out)| {
        let (lo, hi) = (&above[r.saturating_sub(reach) * w..][..w], &above[((r + reach).min(h - 1) + 1) * w..][..w]);
        for ((o, &a), &b) in out.iter_mut().zip(lo).zip(hi) {
            *o = b > a;
        }
    });
    out
}

/// Per cell, whether it is a boundary cell in a passage at most three cells wide: cells off
/// the region within three on both sides along a row, a column or a diagonal.
pub(super) fn passage_cells(grid: &NavGrid) -> Vec<bool> {
    let (w, h) = grid.size();
    let (wi, hi) = (w as isize, h as isize);
    let nav = |c: isize, r: isize| c >= 0 && r >= 0 && c < wi && r < hi && grid.is_nav_cell((r * wi + c) as usize);
    (0..w * h)
        .into_par_iter()
        .map(|i| {
            let (c, r) = ((i % w) as isize, (i / w) as isize);
            let off_within = |dx: isize, dy: isize| (1..=3).any(|k| !nav(c + k * dx, r + k * dy));
            grid.corner[i] && [(1, 0), (0, 1), (1, 1), (1, -1)].iter().any(|&(dx, dy)| off_within(dx, dy) && off_within(-dx, -dy))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::dilate;

    #[test]
    fn dilate_grows_by_a_square() {
        let (w, h) = (23, 17);
        let mask: Vec<bool> = (0..w * h).map(|i| (i * 7919 + 11) % 53 == 0).collect();
        for reach in [0, 1, 3, 30] {
            let got = dilate(&mask, w, h, reach);
            for r in 0..h {
                for c in 0..w {
                    let want = (r.saturating_sub(reach)..=(r + reach).min(h - 1)).any(|y| (c.saturating_sub(reach)..=(c + reach).min(w - 1)).any(|x| mask[y * w + x]));
                    assert_eq!(got[r * w + c], want, "reach {reach} at ({c}, {r})");
                }
            }
        }
        assert!(dilate(&[], 0, 0, 2).is_empty());
    }
}
