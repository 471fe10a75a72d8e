//! Triangle-to-cell rasterisation: which triangles touch a cell, at which heights.
//!
//! Conservative and exact: each triangle is clipped against a cell's square column, and the
//! height range of the clipped polygon decides what the cell holds (a column wholly inside a
//! sloped triangle holds the plane over its square, so its range is the plane's heights at
//! two corners, without a clip). No sampling, so thin walls and chair legs are never missed.

use crate::rounding::floor_f64;

/// A convex polygon in 3D with at most a few vertices (clipping a triangle by four planes).
pub(crate) type Poly = Vec<[f64; 3]>;

/// Clips `poly` to `lo <= p[axis] <= hi` (Sutherland-Hodgman, two half-planes).
/// `tmp` holds the polygon in between (no allocation once the buffers have grown).
pub(crate) fn clip_slab_with(poly: &[[f64; 3]], axis: usize, lo: f64, hi: f64, tmp: &mut Poly, out: &mut Poly) {
    clip_half(poly, axis, lo, true, tmp);
    out.clear();
    clip_half(tmp, axis, hi, false, out);
}

/// Keeps the part with `p[axis] >= v` (`keep_above`) or `p[axis] <= v`.
fn clip_half(poly: &[[f64; 3]], axis: usize, v: f64, keep_above: bool, out: &mut Poly) {
    out.clear();
    let n = poly.len();
    if n == 0 {
        return;
    }
    let inside = |p: &[f64; 3]| if keep_above { p[axis] >= v } else { p[axis] <= v };
    for i in 0..n {
        let a = poly[i];
        let b = poly[(i + 1) % n];
        let (ia, ib) = (inside(&a), inside(&b));
        if ia {
            out.push(a);
        }
        if ia != ib {
            let t = (v - a[axis]) / (b[axis] - a[axis]);
            let mut p = [0.0; 3];
            for k in 0..3 {
                p[k] = a[k] + t * (b[k] - a[k]);
            }
            p[axis] = v;
            out.push(p);
        }
    }
}

/// Height range (min z, max z) of a polygon; `None` when empty.
pub(crate) fn z_range(poly: &[[f64; 3]]) -> Option<(f64, f64)> {
    if poly.is_empty() {
        return None;
    }
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for p in poly {
        lo = lo.min(p[2]);
        hi = hi.max(p[2]);
    }
    Some((lo, hi))
}

/// Grid geometry shared by the rasteriser: origin (m), cell size (m), size in cells.
#[derive(Debug, Clone, Copy)]
pub(crate) struct GridSpec {
    pub x0: f64,
    pub y0: f64,
    pub res: f64,
    pub w: usize,
    pub h: usize,
}

/// Calls `f(col, row, zmin, zmax)` for every cell whose square column the triangle touches,
/// with the height range of the triangle's part inside that column.
pub(crate) fn for_each_cell(g: &GridSpec, tri: &[[f64; 3]; 3], f: impl FnMut(usize, usize, f64, f64)) {
    for_each_cell_inset(g, tri, 0.0, f)
}

/// [`for_each_cell`] with each column shrunk by `inset` (m) on every side: with a small inset,
/// a face lying on a cell's boundary touches neither cell (the walking surfaces of a storey
/// with stairs: a tread's edge on a boundary is not ground for the cell beyond it).
pub(crate) fn for_each_cell_inset(g: &GridSpec, tri: &[[f64; 3]; 3], inset: f64, f: impl FnMut(usize, usize, f64, f64)) {
    for_each_cell_in_rows(g, tri, inset, 0..g.h, f)
}

/// The rows `rows.start..rows.end` of a triangle's [`for_each_cell_inset`] (a band of the grid
/// that one thread fills; the same cells and height ranges as the whole call gives there).
pub(crate) fn for_each_cell_in_rows(g: &GridSpec, tri: &[[f64; 3]; 3], inset: f64, rows: std::ops::Range<usize>, mut f: impl FnMut(usize, usize, f64, f64)) {
    if rows.is_empty() {
        return;
    }
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for p in tri {
        xmin = xmin.min(p[0]);
        xmax = xmax.max(p[0]);
        ymin = ymin.min(p[1]);
        ymax = ymax.max(p[1]);
    }
    let c0 = (floor_f64((xmin - g.x0) / g.res).max(0.0)) as usize;
    let c1 = (floor_f64((xmax - g.x0) / g.res) as isize).min(g.w as isize - 1);
    let r0 = (floor_f64((ymin - g.y0) / g.res).max(0.0)) as usize;
    let r1 = (floor_f64((ymax - g.y0) / g.res) as isize).min(g.h as isize - 1);
    if c1 < c0 as isize || r1 < r0 as isize {
        return;
    }
    let (c1, r1) = (c1 as usize, r1 as usize);
    // Whole triangle inside one cell: no clipping needed.
    if c0 == c1 && r0 == r1 && inset == 0.0 {
        if rows.contains(&r0) {
            if let Some((lo, hi)) = z_range(tri) {
                f(c0, r0, lo, hi);
            }
        }
        return;
    }
    // The polygons' buffers are the thread's own, reused (fresh ones for a call made from
    // within `f`).
    let rows = r0.max(rows.start)..=r1.min(rows.end.saturating_sub(1));
    CLIPS.with(|cell| match cell.try_borrow_mut() {
        Ok(mut clips) => cells_in_rows(g, tri, inset, rows, c0..=c1, &mut clips, &mut f),
        Err(_) => cells_in_rows(g, tri, inset, rows, c0..=c1, &mut Clips::default(), &mut f),
    });
}

/// Buffers for a row's piece of a triangle, a cell's piece and the clip in between.
#[derive(Default)]
struct Clips {
    row: Poly,
    cell: Poly,
    tmp: Poly,
}

thread_local! {
    static CLIPS: std::cell::RefCell<Clips> = std::cell::RefCell::new(Clips::default());
}

/// The body of [`for_each_cell_in_rows`] over the triangle's `rows` and `cols`.
fn cells_in_rows(
    g: &GridSpec,
    tri: &[[f64; 3]; 3],
    inset: f64,
    rows: std::ops::RangeInclusive<usize>,
    cols: std::ops::RangeInclusive<usize>,
    clips: &mut Clips,
    f: &mut impl FnMut(usize, usize, f64, f64),
) {
    let (c0, c1) = (*cols.start(), *cols.end());
    let Clips { row: row_poly, cell: cell_poly, tmp } = clips;
    let flat = tri[0][2].to_bits() == tri[1][2].to_bits() && tri[1][2].to_bits() == tri[2][2].to_bits() && 2.0 * inset < g.res;
    let plane = if flat || 2.0 * inset >= g.res { None } else { Plane::of(tri) };
    for r in rows {
        let ylo = g.y0 + r as f64 * g.res;
        clip_slab_with(tri, 1, ylo + inset, ylo + g.res - inset, tmp, row_poly);
        if row_poly.is_empty() {
            continue;
        }
        // Only the columns the row's piece reaches (and one more on each side, for a piece
        // ending on a cell's edge and for rounding): the others clip to nothing.
        let (pmin, pmax) = row_poly.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p[0]), b.max(p[0])));
        let pc0 = floor_f64((pmin - g.x0) / g.res) - 1.0;
        let pc1 = floor_f64((pmax - g.x0) / g.res) + 1.0;
        let lo_c = if pc0 > c0 as f64 { pc0 as usize } else { c0 };
        let hi_c = if pc1 < c1 as f64 { pc1 as usize } else { c1 };
        if flat {
            // A level triangle's piece in a cell is at its height wherever the cell's column
            // meets the row's piece, which is convex: where their x ranges overlap (the same
            // cells, and the same bits, as clipping).
            let z = tri[0][2];
            for c in lo_c..=hi_c {
                let xlo = g.x0 + c as f64 * g.res;
                if pmax >= xlo + inset && pmin <= xlo + g.res - inset {
                    f(c, r, z, z);
                }
            }
            continue;
        }
        // The columns wholly inside the triangle (a sloped floor's or ceiling's inner cells):
        // the piece there is the column's square, whose heights are the plane's at its corners.
        let (ya, yb) = (ylo + inset, ylo + g.res - inset);
        // (none where the row's piece is narrower than a column)
        let wide = pmax - pmin >= g.res - 2.0 * inset;
        let inner = match &plane {
            Some(_) if wide => inner_span(tri, ya, yb),
            _ => (f64::INFINITY, f64::NEG_INFINITY),
        };
        for c in lo_c..=hi_c {
            let xlo = g.x0 + c as f64 * g.res;
            let (xa, xb) = (xlo + inset, xlo + g.res - inset);
            if let (Some(p), true) = (&plane, xa >= inner.0 && xb <= inner.1) {
                let (lo, hi) = p.range_over(xa, xb, ya, yb);
                f(c, r, lo, hi);
                continue;
            }
            clip_slab_with(row_poly, 0, xa, xb, tmp, cell_poly);
            if let Some((lo, hi)) = z_range(cell_poly) {
                f(c, r, lo, hi);
            }
        }
    }
}

/// The plane of a triangle whose ground projection has area, as heights over the ground.
struct Plane {
    /// A corner of the triangle (m).
    at: [f64; 3],
    /// Rise per metre along x and along y.
    grad: [f64; 2],
}

impl Plane {
    /// The triangle's plane, if it is at most [`STEEPEST_PLANE_COS`] from level (steeper ones,
    /// walls, have no cell wholly inside their projection worth the arithmetic).
    fn of(t: &[[f64; 3]; 3]) -> Option<Plane> {
        let n = normal(t);
        let n2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        if !(n[2] * n[2] >= STEEPEST_PLANE_COS * STEEPEST_PLANE_COS * n2) || n2 == 0.0 {
            return None;
        }
        Some(Plane { at: t[0], grad: [-n[0] / n[2], -n[1] / n[2]] })
    }

    /// Lowest and highest height of the plane over the rectangle `[xa, xb] x [ya, yb]` (m): at
    /// two of its corners.
    fn range_over(&self, xa: f64, xb: f64, ya: f64, yb: f64) -> (f64, f64) {
        let z = |x: f64, y: f64| self.at[2] + self.grad[0] * (x - self.at[0]) + self.grad[1] * (y - self.at[1]);
        let (xl, xh) = if self.grad[0] >= 0.0 { (xa, xb) } else { (xb, xa) };
        let (yl, yh) = if self.grad[1] >= 0.0 { (ya, yb) } else { (yb, ya) };
        (z(xl, yl), z(xh, yh))
    }
}

/// Least cosine between a triangle's normal and the vertical for [`Plane::of`].
const STEEPEST_PLANE_COS: f64 = 0.2;

/// How far inside a triangle's edges a column must lie to count as wholly inside (m): far
/// above the rounding of the edges' crossings.
const INNER_MARGIN: f64 = 1e-9;

/// The x range over which the triangle's ground projection covers the whole of the rows
/// `ya..yb` (m), shrunk by [`INNER_MARGIN`]; empty (start above end) where it covers none.
/// The projection is convex, so covering both edges of the rows at an x covers all between.
fn inner_span(t: &[[f64; 3]; 3], ya: f64, yb: f64) -> (f64, f64) {
    let across = |y: f64| {
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            let (y0, y1) = (a[1].min(b[1]), a[1].max(b[1]));
            if y < y0 || y > y1 || y0 == y1 {
                continue;
            }
            let x = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
            lo = lo.min(x);
            hi = hi.max(x);
        }
        (lo, hi)
    };
    let (a, b) = (across(ya), across(yb));
    (a.0.max(b.0) + INNER_MARGIN, a.1.min(b.1) - INNER_MARGIN)
}

/// A triangle's normal, not normalised: the cross product of its edges from the first corner
/// (twice its area long; counter-clockwise winding seen from outside gives the outward side).
fn normal(t: &[[f64; 3]; 3]) -> [f64; 3] {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
    let v = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
    [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
}

/// Unit normal's z component magnitude of a triangle (1 for horizontal, 0 for vertical);
/// `None` for a degenerate triangle.
pub(crate) fn abs_normal_z(t: &[[f64; 3]; 3]) -> Option<f64> {
    let n = normal(t);
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len <= 1e-12 {
        return None;
    }
    Some((n[2] / len).abs())
}

/// Sign of the triangle's normal's z component (+1 facing up, -1 facing down, 0 vertical),
/// for counter-clockwise winding seen from outside.
pub(crate) fn normal_z_sign(t: &[[f64; 3]; 3]) -> f64 {
    let nz = normal(t)[2];
    if nz.abs() < 1e-12 {
        0.0
    } else {
        nz.signum()
    }
}

/// Area of a triangle (m^2) and of its projection on the ground plane (m^2).
pub(crate) fn areas(t: &[[f64; 3]; 3]) -> (f64, f64) {
    let n = normal(t);
    (0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt(), 0.5 * n[2].abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vertical_triangle_marks_the_cells_it_crosses() {
        // A vertical wall triangle along y = 0.51 from x = 0 to 1, z 0..2.
        let g = GridSpec { x0: 0.0, y0: 0.0, res: 0.1, w: 10, h: 10 };
        let tri = [[0.0, 0.51, 0.0], [1.0, 0.51, 0.0], [0.0, 0.51, 2.0]];
        let mut cells = Vec::new();
        for_each_cell(&g, &tri, |c, r, lo, hi| cells.push((c, r, lo, hi)));
        assert_eq!(cells.len(), 10);
        assert!(cells.iter().all(|&(_, r, lo, _)| r == 5 && lo.abs() < 1e-12));
        // The wall's height over the cell at x in [0.9, 1.0] is at most 0.2.
        let last = cells.iter().find(|c| c.0 == 9).unwrap();
        assert!((last.3 - 0.2).abs() < 1e-9, "{last:?}");
    }

    #[test]
    fn horizontal_triangle_covers_its_area() {
        let g = GridSpec { x0: 0.0, y0: 0.0, res: 0.1, w: 10, h: 10 };
        let tri = [[0.0, 0.0, 0.3], [1.0, 0.0, 0.3], [0.0, 1.0, 0.3]];
        let mut n = 0;
        for_each_cell(&g, &tri, |_, _, lo, hi| {
            assert!((lo - 0.3).abs() < 1e-12 && (hi - 0.3).abs() < 1e-12);
            n += 1;
        });
        // 10 rows: row r touches cells c with c*0.1 < 1 - r*0.1, i.e. 10 - r cells, plus the diagonal ones.
        assert!((55..=65).contains(&n), "{n}");
    }

    /// Every cell of the triangle's bounding box clipped on its own: row slab, then column slab.
    fn clip_every_cell(g: &GridSpec, tri: &[[f64; 3]; 3], inset: f64) -> Vec<(usize, usize, u64, u64)> {
        let (mut tmp, mut row, mut cell) = (Vec::new(), Vec::new(), Vec::new());
        let cell_of = |v: f64, o: f64, n: usize| (((v - o) / g.res).floor().max(0.0) as usize).min(n - 1);
        let (xs, ys) = (tri.map(|p| cell_of(p[0], g.x0, g.w)), tri.map(|p| cell_of(p[1], g.y0, g.h)));
        let mut out = Vec::new();
        for r in *ys.iter().min().unwrap()..=*ys.iter().max().unwrap() {
            let ylo = g.y0 + r as f64 * g.res;
            clip_slab_with(tri, 1, ylo + inset, ylo + g.res - inset, &mut tmp, &mut row);
            for c in *xs.iter().min().unwrap()..=*xs.iter().max().unwrap() {
                let xlo = g.x0 + c as f64 * g.res;
                clip_slab_with(&row, 0, xlo + inset, xlo + g.res - inset, &mut tmp, &mut cell);
                if let Some((lo, hi)) = z_range(&cell) {
                    out.push((c, r, lo.to_bits(), hi.to_bits()));
                }
            }
        }
        out
    }

    #[test]
    fn only_the_cells_a_row_reaches_and_level_triangles_give_what_clipping_every_cell_gives() {
        let g = GridSpec { x0: -0.3, y0: 0.17, res: 0.05, w: 40, h: 37 };
        let tris = [
            // Level: a floor, one with corners on cell edges, a sliver.
            [[-0.2, 0.2, 0.1], [1.5, 0.4, 0.1], [0.3, 1.9, 0.1]],
            [[-0.25, 0.22, 0.4], [0.45, 0.22, 0.4], [-0.25, 0.92, 0.4]],
            [[0.0, 0.5, 0.0], [1.2, 0.52, 0.0], [0.6, 0.51, 0.0]],
            // Sloped (with inner cells read off the plane), a floor off level by a rounding,
            // steep, and upright.
            [[-0.2, 0.2, 0.1], [1.5, 0.4, 0.9], [0.3, 1.9, 0.4]],
            [[-1.0, -1.0, 0.0], [3.0, 0.5, 1.0], [0.5, 3.0, 2.0]],
            [[-0.2, 0.2, 0.1], [1.5, 0.4, 0.1 + 1e-15], [0.3, 1.9, 0.1]],
            [[-0.2, 0.2, 0.1], [1.5, 0.4, 9.0], [0.3, 1.9, 4.0]],
            [[0.0, 0.61, 0.0], [1.0, 0.61, 0.0], [0.0, 0.61, 2.0]],
        ];
        let mut inner = 0;
        for t in &tris {
            let level = t[0][2] == t[1][2] && t[1][2] == t[2][2];
            for inset in [0.0, 1e-6] {
                let mut fast = Vec::new();
                for_each_cell_inset(&g, t, inset, |c, r, lo, hi| fast.push((c, r, lo.to_bits(), hi.to_bits())));
                let want = clip_every_cell(&g, t, inset);
                if level {
                    let extra: Vec<_> = fast.iter().filter(|x| !want.contains(x)).collect();
                    let missing: Vec<_> = want.iter().filter(|x| !fast.contains(x)).collect();
                    assert_eq!(fast, want, "{t:?} inset {inset}: extra {extra:?} missing {missing:?}");
                    continue;
                }
                // The same cells; heights the same to within rounding (the plane's at a column's
                // corners against the clip's interpolations), and the same bits where clipped.
                let cells = |v: &[(usize, usize, u64, u64)]| v.iter().map(|x| (x.0, x.1)).collect::<Vec<_>>();
                assert_eq!(cells(&fast), cells(&want), "{t:?} inset {inset}");
                for (f, w) in fast.iter().zip(&want) {
                    let (fl, fh, wl, wh) = (f64::from_bits(f.2), f64::from_bits(f.3), f64::from_bits(w.2), f64::from_bits(w.3));
                    assert!((fl - wl).abs() <= 1e-12 && (fh - wh).abs() <= 1e-12, "{t:?} inset {inset} cell {:?}: {fl} {fh} against {wl} {wh}", (f.0, f.1));
                    inner += (f != w) as usize;
                }
            }
        }
        // (the plane's heights differ from the clip's in some last bits: the inner cells took
        // the plane's path)
        assert!(inner > 0);
    }

    #[test]
    fn bands_of_rows_give_the_whole_calls_cells_bit_for_bit() {
        let g = GridSpec { x0: -0.3, y0: 0.17, res: 0.05, w: 40, h: 37 };
        let tris = [
            [[-0.2, 0.2, 0.1], [1.5, 0.4, 0.9], [0.3, 1.9, 0.4]],
            [[0.51, 0.9, 0.0], [0.53, 0.91, 0.7], [0.52, 0.92, 0.3]],
            // Within one cell, and reaching past the grid's edges.
            [[0.01, 0.3, 0.2], [0.02, 0.31, 0.2], [0.015, 0.32, 0.5]],
            [[-1.0, -1.0, 0.0], [3.0, 0.5, 1.0], [0.5, 3.0, 2.0]],
        ];
        for t in &tris {
            let mut whole = Vec::new();
            for_each_cell(&g, t, |c, r, lo, hi| whole.push((c, r, lo.to_bits(), hi.to_bits())));
            for band in [1, 5, 16, 64] {
                let mut banded = Vec::new();
                for b in 0..g.h.div_ceil(band) {
                    for_each_cell_in_rows(&g, t, 0.0, b * band..((b + 1) * band).min(g.h), |c, r, lo, hi| banded.push((c, r, lo.to_bits(), hi.to_bits())));
                }
                assert_eq!(banded, whole, "band {band}");
            }
            let mut none = 0;
            for_each_cell_in_rows(&g, t, 0.0, 3..3, |_, _, _, _| none += 1);
            assert_eq!(none, 0);
        }
    }
}
