//! The corners of each cluster's triangles without repeats, so that a view transforms and
//! projects each corner once (in a loop the compiler vectorises) instead of three times per
//! triangle, and rejects triangles from the projected corners.

use super::{Cluster, Tri, View, NEAR};
use crate::rounding::{ceil_bounded, floor_bounded};
use std::collections::HashMap;

/// Each cluster's distinct triangle corners (world frame, m, one array per axis) and, per
/// triangle, the indices of its corners among its cluster's.
pub(super) struct ClusterCorners {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    /// Cluster `i`'s corners are `start[i]..start[i + 1]`.
    start: Vec<u32>,
    /// The corners of triangle `t` (in the scene's triangle order) within its cluster.
    pub(super) tri: Vec<[u16; 3]>,
}

impl ClusterCorners {
    /// Collects the corners of `clusters` (runs of `tris`); corners are the same when their
    /// coordinates are bit for bit equal.
    pub(super) fn new(tris: &[Tri], clusters: &[Cluster]) -> ClusterCorners {
        let mut c = ClusterCorners { x: Vec::new(), y: Vec::new(), z: Vec::new(), start: vec![0], tri: Vec::with_capacity(tris.len()) };
        let mut seen: HashMap<[u32; 3], u16> = HashMap::new();
        for cl in clusters {
            seen.clear();
            let base = c.x.len();
            for t in &tris[cl.start as usize..cl.end as usize] {
                let idx = t.v.map(|p| {
                    *seen.entry(p.map(f32::to_bits)).or_insert_with(|| {
                        c.x.push(p[0]);
                        c.y.push(p[1]);
                        c.z.push(p[2]);
                        (c.x.len() - 1 - base) as u16
                    })
                });
                c.tri.push(idx);
            }
            c.start.push(c.x.len() as u32);
        }
        c
    }

    /// Transforms the corners of cluster `i` into `out`.
    pub(super) fn to_view(&self, i: usize, view: &View, out: &mut ViewCorners) {
        let r = self.start[i] as usize..self.start[i + 1] as usize;
        out.project(view, &self.x[r.clone()], &self.y[r.clone()], &self.z[r]);
    }
}

/// One cluster's corners in a view: camera frame (m; x right, y down, z forward), whether each
/// lies behind the near plane or beyond `max_depth`, and for those in front of the near plane
/// the pixel box a triangle's bounding box is the union of (see [`ViewCorners::bbox`]).
#[derive(Default)]
pub(super) struct ViewCorners {
    x: Vec<f32>,
    y: Vec<f32>,
    z: Vec<f32>,
    /// Bit 0: behind the near plane; bit 1: beyond `max_depth`.
    code: Vec<u8>,
    /// First column, minus the last column, first row, minus the last row of the pixel
    /// centres within the bounding-box margin of the corner's projection, clamped to the
    /// image: a triangle's box is the element-wise minimum of its corners' (one vector op).
    px: Vec<[i16; 4]>,
}

/// Margin of triangle bounding boxes (px), against rounding.
pub(super) const MARGIN: f32 = 0.01;

impl ViewCorners {
    fn project(&mut self, view: &View, wx: &[f32], wy: &[f32], wz: &[f32]) {
        let n = wx.len();
        for a in [&mut self.x, &mut self.y, &mut self.z] {
            a.resize(n, 0.0);
        }
        self.px.resize(n, [0; 4]);
        self.code.resize(n, 0);
        let (x, y, z, code, px) = (&mut self.x[..n], &mut self.y[..n], &mut self.z[..n], &mut self.code[..n], &mut self.px[..n]);
        let (wy, wz) = (&wy[..n], &wz[..n]);
        let (wf, hf) = (view.w as f32, view.h as f32);
        let (wm, hm) = (view.w as i32 - 1, view.h as i32 - 1);
        for i in 0..n {
            let q = view.to_cam([wx[i], wy[i], wz[i]]);
            (x[i], y[i], z[i]) = (q[0], q[1], q[2]);
            code[i] = (q[2] < NEAR) as u8 | ((q[2] > view.far) as u8) << 1;
            let r = 1.0 / q[2];
            let (u, v) = (view.cx + view.fx * (q[0] * r), view.cy + view.fy * (q[1] * r));
            // Rounding and clamping are monotone, so a triangle's box is the min / max of these.
            px[i] = [
                ceil_bounded(clamp(u - MARGIN, -1.0, wf)).max(0) as i16,
                -(floor_bounded(clamp(u + MARGIN, -1.0, wf)).min(wm) as i16),
                ceil_bounded(clamp(v - MARGIN, -1.0, hf)).max(0) as i16,
                -(floor_bounded(clamp(v + MARGIN, -1.0, hf)).min(hm) as i16),
            ];
        }
    }

    /// Corner `i` in the camera frame.
    #[inline(always)]
    pub(super) fn cam(&self, i: u16) -> [f32; 3] {
        let i = i as usize;
        [self.x[i], self.y[i], self.z[i]]
    }

    /// For the triangle with corners `c`: `Err(())` when it is wholly behind the near plane or
    /// beyond `max_depth`, `Ok(None)` when it crosses the near plane, else `Ok(Some(box))`
    /// with its pixel bounding box `[u0, u1, v0, v1]` (empty when it covers no pixel centre).
    #[inline(always)]
    pub(super) fn bbox(&self, c: [u16; 3]) -> Result<Option<[i32; 4]>, ()> {
        let [a, b, c] = c.map(|i| i as usize);
        let (all, any) = (self.code[a] & self.code[b] & self.code[c], (self.code[a] | self.code[b] | self.code[c]) & 1);
        if all != 0 {
            return Err(());
        }
        if any != 0 {
            return Ok(None);
        }
        let (pa, pb, pc) = (self.px[a], self.px[b], self.px[c]);
        let m: [i16; 4] = std::array::from_fn(|k| pa[k].min(pb[k]).min(pc[k]));
        Ok(Some([m[0] as i32, -(m[1] as i32), m[2] as i32, -(m[3] as i32)]))
    }
}

/// `x` limited to `[lo, hi]`, NaN to `lo`.
#[inline(always)]
fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    let x = if x > lo { x } else { lo };
    if x < hi {
        x
    } else {
        hi
    }
}
