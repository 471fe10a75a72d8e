//! Triangle-to-cell rasterisation: which triangles touch a cell, at which heights.
//!
//! Conservative and exact: each triangle is clipped against a cell's square column, and the
//! height range of the clipped polygon decides what the cell holds. No sampling, so thin
//! walls and chair legs are never missed.

/// A convex polygon in 3D with at most a few vertices (clipping a triangle by four planes).
pub(crate) type Poly = Vec<[f64; 3]>;

/// Clips `poly` to `lo <= p[axis] <= hi` (Sutherland-Hodgman, two half-planes).
pub(crate) fn clip_slab(poly: &[[f64; 3]], axis: usize, lo: f64, hi: f64, out: &mut Poly) {
    let mut tmp: Poly = Vec::with_capacity(poly.len() + 2);
    clip_half(poly, axis, lo, true, &mut tmp);
    out.clear();
    clip_half(&tmp, axis, hi, false, out);
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
    let c0 = (((xmin - g.x0) / g.res).floor().max(0.0)) as usize;
    let c1 = (((xmax - g.x0) / g.res).floor() as isize).min(g.w as isize - 1);
    let r0 = (((ymin - g.y0) / g.res).floor().max(0.0)) as usize;
    let r1 = (((ymax - g.y0) / g.res).floor() as isize).min(g.h as isize - 1);
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
    let mut row_poly: Poly = Vec::with_capacity(8);
    let mut cell_poly: Poly = Vec::with_capacity(10);
    for r in r0.max(rows.start)..=r1.min(rows.end.saturating_sub(1)) {
        let ylo = g.y0 + r as f64 * g.res;
        clip_slab(tri, 1, ylo + inset, ylo + g.res - inset, &mut row_poly);
        if row_poly.is_empty() {
            continue;
        }
        for c in c0..=c1 {
            let xlo = g.x0 + c as f64 * g.res;
            clip_slab(&row_poly, 0, xlo + inset, xlo + g.res - inset, &mut cell_poly);
            if let Some((lo, hi)) = z_range(&cell_poly) {
                f(c, r, lo, hi);
            }
        }
    }
}

/// Unit normal's z component magnitude of a triangle (1 for horizontal, 0 for vertical);
/// `None` for a degenerate triangle.
pub(crate) fn abs_normal_z(t: &[[f64; 3]; 3]) -> Option<f64> {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
    let v = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len <= 1e-12 {
        return None;
    }
    Some((n[2] / len).abs())
}

/// Sign of the triangle's normal's z component (+1 facing up, -1 facing down, 0 vertical),
/// for counter-clockwise winding seen from outside.
pub(crate) fn normal_z_sign(t: &[[f64; 3]; 3]) -> f64 {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1]];
    let v = [t[2][0] - t[0][0], t[2][1] - t[0][1]];
    let nz = u[0] * v[1] - u[1] * v[0];
    if nz.abs() < 1e-12 {
        0.0
    } else {
        nz.signum()
    }
}

/// Area of a triangle (m^2) and of its projection on the ground plane (m^2).
pub(crate) fn areas(t: &[[f64; 3]; 3]) -> (f64, f64) {
    let u = [t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]];
    let v = [t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]];
    let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
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
