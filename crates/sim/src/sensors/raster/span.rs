//! Depth rasterisation by row spans: the pixels of a row that a triangle covers are an
//! interval, bounded by one crossing column per edge instead of edge tests at every pixel.

use super::{Setup, View};
use crate::rounding::ceil_bounded;

/// The columns `lo..=hi` (within `u0..=u1`) of the row at `yv` (pixels from the principal
/// point) that triangle `t` covers; `None` when it covers none. `inv_e` is `1 / e` of each edge.
///
/// Along a row, edge `e * xu + f * yv + g >= 0` holds on one side of the column
/// `cx - (f * yv + g) / e`, computed in a way that gives the same float for the neighbouring
/// triangle's copy of the edge (all of `e`, `f`, `g` negated: IEEE rounding is symmetric).
/// Edges with `e > 0` (the owners under the top-left rule) keep the columns at or right of it,
/// those with `e < 0` the columns strictly left of it, so a pixel centre on a shared edge
/// belongs to exactly one of its two triangles: no holes, no double cover. Edges with `e = 0`
/// hold on the whole row or none of it.
#[inline(always)]
pub(super) fn row_span(t: &Setup, inv_e: &[f32; 3], cx: f32, yv: f32, u0: i32, u1: i32) -> Option<(i32, i32)> {
    // Covered: lo <= u < hi_ex (columns as floats, thresholds not yet rounded).
    let (mut lo, mut hi_ex) = (u0 as f32, u1 as f32 + 1.0);
    for (e, ie) in t.edges.iter().zip(inv_e) {
        let g = e[1] * yv + e[2];
        let b = cx - g * ie;
        if e[0] > 0.0 {
            lo = if b > lo { b } else { lo };
        } else if e[0] < 0.0 {
            hi_ex = if b < hi_ex { b } else { hi_ex };
        } else if !(g >= e[3]) {
            return None;
        }
    }
    // (Both within `u0..=u1 + 1`: a NaN crossing never moves them.)
    let lo = ceil_bounded(if lo < u1 as f32 + 1.0 { lo } else { u1 as f32 + 1.0 });
    let hi = ceil_bounded(if hi_ex > u0 as f32 { hi_ex } else { u0 as f32 }) - 1;
    (lo <= hi).then_some((lo, hi))
}

/// Calls `fill(t, v, lo, hi, x0, gz)` for every row span `lo..=hi` of row `v` that triangle
/// `t` of `tris` covers, with `x0` the first column relative to the principal point and `gz`
/// the row's inverse depth at the principal column: the pixel at `lo + i` has inverse depth
/// `t.inv_z[0] * (x0 + i) + gz` (1/m).
#[inline(always)]
fn for_each_span(view: &View, tris: &[Setup], mut fill: impl FnMut(&Setup, usize, usize, usize, f32, f32)) {
    for t in tris {
        let [u0, u1, v0, v1] = t.bbox.map(|x| x as i32);
        let [_, zb, zc] = t.inv_z;
        let inv_e = t.edges.map(|e| 1.0 / e[0]);
        for v in v0..=v1 {
            let yv = v as f32 - view.cy;
            let Some((lo, hi)) = row_span(t, &inv_e, view.cx, yv, u0, u1) else { continue };
            fill(t, v as usize, lo as usize, hi as usize, lo as f32 - view.cx, zb * yv + zc);
        }
    }
}

/// Rasterises `tris` into the inverse depth `zb` (1/m, rows of `view.w`), keeping the
/// nearest.
pub(super) fn raster_depth(view: &View, tris: &[Setup], zb: &mut [f32]) {
    let w = view.w;
    for_each_span(view, tris, |t, v, lo, hi, x0, gz| {
        let za = t.inv_z[0];
        for (i, z) in zb[v * w + lo..=v * w + hi].iter_mut().enumerate() {
            let iz = za * (x0 + i as i32 as f32) + gz;
            *z = if iz > *z { iz } else { *z };
        }
    });
}

/// Rasterises `tris` into the inverse depth `zb` (1/m, rows of `view.w`) and the triangle ids
/// `ids`, keeping the nearest, and of equally near ones the smaller id (so the result does
/// not depend on the order of drawing): the same pixels and the same inverse depths as
/// [`raster_depth`], so a colour render's depth is the depth render's to the bit.
pub(super) fn raster_ids(view: &View, tris: &[Setup], zb: &mut [f32], ids: &mut [u32]) {
    let w = view.w;
    for_each_span(view, tris, |t, v, lo, hi, x0, gz| {
        let za = t.inv_z[0];
        let cols = v * w + lo..=v * w + hi;
        for (i, (z, id)) in zb[cols.clone()].iter_mut().zip(&mut ids[cols]).enumerate() {
            let iz = za * (x0 + i as i32 as f32) + gz;
            if iz > *z || (iz == *z && t.id < *id) {
                *z = iz;
                *id = t.id;
            }
        }
    });
}
