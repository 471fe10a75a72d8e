//! The scene cut by a horizontal plane, for planar lidar rays: the triangles that cross the
//! plane become 2D segments, bucketed in a uniform grid and walked cell by cell along a ray.
//!
//! A horizontal ray at the plane's height hits a triangle exactly where it hits the segment
//! the plane cuts from it, so a scan cast here matches [`super::RayScene::cast`] (up to
//! rounding: parry3d works in `f32`, this in `f64` from the same `f32` vertices) at a small
//! part of the cost of a 3D BVH query against every triangle. Triangles lying in the plane
//! are dropped, as a 3D ray along a triangle's plane does not hit it either.

/// Side of a bucket of the grid (m), unless the slice is wider than [`MAX_BUCKETS`] of them.
const CELL: f64 = 0.25;
/// Most buckets along either axis (a vast terrain gets larger buckets, not gigabytes).
const MAX_BUCKETS: usize = 4096;

/// The segments a horizontal plane cuts from the scene's triangles, bucketed for ray walks.
#[derive(Debug, Clone)]
pub struct ScanSlice {
    /// Height of the plane (m, world frame).
    pub z: f64,
    /// Segments (x0, y0, x1, y1) (m).
    segments: Vec<[f64; 4]>,
    /// Grid origin: the lower-left corner of bucket (0, 0) (m).
    origin: [f64; 2],
    /// Side of a bucket (m).
    cell: f64,
    /// Buckets along x and y.
    dims: [usize; 2],
    /// Bucket `i`'s segments are `items[starts[i]..starts[i + 1]]` (row-major, x fastest).
    starts: Vec<u32>,
    items: Vec<u32>,
}

impl ScanSlice {
    /// Cuts the triangles (`indices` into `vertices`, in m) with the plane at height `z` (m).
    pub fn new(vertices: &[[f32; 3]], indices: &[[u32; 3]], z: f64) -> ScanSlice {
        let segments: Vec<[f64; 4]> = indices.iter().filter_map(|t| cut(t.map(|i| vertices[i as usize]), z)).collect();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for s in &segments {
            for (x, y) in [(s[0], s[1]), (s[2], s[3])] {
                lo = [lo[0].min(x), lo[1].min(y)];
                hi = [hi[0].max(x), hi[1].max(y)];
            }
        }
        if segments.is_empty() {
            return ScanSlice { z, segments, origin: [0.0; 2], cell: CELL, dims: [0; 2], starts: vec![0], items: Vec::new() };
        }
        let cell = CELL.max((hi[0] - lo[0]).max(hi[1] - lo[1]) / (MAX_BUCKETS - 1) as f64);
        let dims = [((hi[0] - lo[0]) / cell).floor() as usize + 1, ((hi[1] - lo[1]) / cell).floor() as usize + 1];
        let origin = lo;
        // Each segment goes into every bucket its bounding box overlaps (a superset of the
        // buckets it crosses; the ray test decides).
        let span = |s: &[f64; 4]| {
            let c = |v: f64, o: f64, n: usize| (((v - o) / cell).floor().max(0.0) as usize).min(n - 1);
            let (x0, x1) = (c(s[0].min(s[2]), origin[0], dims[0]), c(s[0].max(s[2]), origin[0], dims[0]));
            let (y0, y1) = (c(s[1].min(s[3]), origin[1], dims[1]), c(s[1].max(s[3]), origin[1], dims[1]));
            (x0, x1, y0, y1)
        };
        let mut counts = vec![0u32; dims[0] * dims[1] + 1];
        for s in &segments {
            let (x0, x1, y0, y1) = span(s);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    counts[y * dims[0] + x + 1] += 1;
                }
            }
        }
        for i in 1..counts.len() {
            counts[i] += counts[i - 1];
        }
        let starts = counts;
        let mut fill = starts.clone();
        let mut items = vec![0u32; *starts.last().unwrap_or(&0) as usize];
        for (k, s) in segments.iter().enumerate() {
            let (x0, x1, y0, y1) = span(s);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let b = y * dims[0] + x;
                    items[fill[b] as usize] = k as u32;
                    fill[b] += 1;
                }
            }
        }
        ScanSlice { z, segments, origin, cell, dims, starts, items }
    }

    /// Number of segments the plane cut.
    pub fn len(&self) -> usize {
        self.segments.len()
    }

    /// Whether the plane cut no triangle.
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// Distance along `dir` (in units of `dir`'s length) from `origin` (m, in the plane) to
    /// the first segment, up to `max_t`; `None` when nothing is hit.
    pub fn cast(&self, origin: [f64; 2], dir: [f64; 2], max_t: f64) -> Option<f64> {
        if self.segments.is_empty() {
            return None;
        }
        let [nx, ny] = self.dims;
        let hi = [self.origin[0] + nx as f64 * self.cell, self.origin[1] + ny as f64 * self.cell];
        // Clip the ray to the grid's box (slabs).
        let (mut t0, mut t1) = (0.0f64, max_t);
        for a in 0..2 {
            if dir[a] == 0.0 {
                if origin[a] < self.origin[a] || origin[a] > hi[a] {
                    return None;
                }
            } else {
                let (ta, tb) = ((self.origin[a] - origin[a]) / dir[a], (hi[a] - origin[a]) / dir[a]);
                t0 = t0.max(ta.min(tb));
                t1 = t1.min(ta.max(tb));
            }
        }
        if t0 > t1 {
            return None;
        }
        // The walk (Amanatides and Woo) from the bucket holding the clipped start.
        let start = [origin[0] + t0 * dir[0], origin[1] + t0 * dir[1]];
        let mut cell = [0usize; 2];
        let (mut step, mut t_next, mut t_delta) = ([0isize; 2], [f64::INFINITY; 2], [f64::INFINITY; 2]);
        for a in 0..2 {
            let n = self.dims[a];
            cell[a] = (((start[a] - self.origin[a]) / self.cell).floor().max(0.0) as usize).min(n - 1);
            if dir[a] > 0.0 {
                step[a] = 1;
                t_next[a] = (self.origin[a] + (cell[a] + 1) as f64 * self.cell - origin[a]) / dir[a];
                t_delta[a] = self.cell / dir[a];
            } else if dir[a] < 0.0 {
                step[a] = -1;
                t_next[a] = (self.origin[a] + cell[a] as f64 * self.cell - origin[a]) / dir[a];
                t_delta[a] = -self.cell / dir[a];
            }
        }
        let mut best = f64::INFINITY;
        loop {
            let b = cell[1] * nx + cell[0];
            for &k in &self.items[self.starts[b] as usize..self.starts[b + 1] as usize] {
                if let Some(t) = hit(&self.segments[k as usize], origin, dir) {
                    if t < best {
                        best = t;
                    }
                }
            }
            let exit = t_next[0].min(t_next[1]);
            if best <= exit || exit > t1 {
                break;
            }
            let a = if t_next[0] <= t_next[1] { 0 } else { 1 };
            let c = cell[a] as isize + step[a];
            if c < 0 || c as usize >= self.dims[a] {
                break;
            }
            cell[a] = c as usize;
            t_next[a] += t_delta[a];
        }
        (best <= max_t).then_some(best)
    }
}

/// The segment the plane at height `z` cuts from triangle `v`; `None` when the triangle does
/// not cross it, only touches it at a point, or lies in it.
fn cut(v: [[f32; 3]; 3], z: f64) -> Option<[f64; 4]> {
    let p = v.map(|p| [p[0] as f64, p[1] as f64, p[2] as f64 - z]);
    let mut pts = [[0.0f64; 2]; 3];
    let mut n = 0;
    for i in 0..3 {
        let (a, b) = (p[i], p[(i + 1) % 3]);
        if a[2] == 0.0 {
            pts[n] = [a[0], a[1]];
            n += 1;
        } else if (a[2] < 0.0 && b[2] > 0.0) || (a[2] > 0.0 && b[2] < 0.0) {
            let s = a[2] / (a[2] - b[2]);
            pts[n] = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            n += 1;
        }
        if n == 3 {
            // All three on the plane: the triangle lies in it.
            return None;
        }
    }
    (n == 2 && pts[0] != pts[1]).then(|| [pts[0][0], pts[0][1], pts[1][0], pts[1][1]])
}

/// Where the ray `origin + t dir` (t >= 0) meets segment `s`; `None` when it misses or runs
/// parallel to it.
#[inline]
fn hit(s: &[f64; 4], origin: [f64; 2], dir: [f64; 2]) -> Option<f64> {
    let (ex, ey) = (s[2] - s[0], s[3] - s[1]);
    let denom = dir[0] * ey - dir[1] * ex;
    if denom == 0.0 {
        return None;
    }
    let (wx, wy) = (s[0] - origin[0], s[1] - origin[1]);
    let t = (wx * ey - wy * ex) / denom;
    let u = (wx * dir[1] - wy * dir[0]) / denom;
    (t >= 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A vertical wall (two triangles) at x = `x`, from y = -1 to 1, z = 0 to 1.
    fn wall(x: f32, vertices: &mut Vec<[f32; 3]>, indices: &mut Vec<[u32; 3]>) {
        let b = vertices.len() as u32;
        vertices.extend([[x, -1.0, 0.0], [x, 1.0, 0.0], [x, 1.0, 1.0], [x, -1.0, 1.0]]);
        indices.extend([[b, b + 1, b + 2], [b, b + 2, b + 3]]);
    }

    #[test]
    fn a_ray_stops_at_the_nearest_wall_across_buckets() {
        let (mut v, mut i) = (Vec::new(), Vec::new());
        wall(2.0, &mut v, &mut i);
        wall(3.3, &mut v, &mut i);
        wall(-1.5, &mut v, &mut i);
        let s = ScanSlice::new(&v, &i, 0.2);
        let t = s.cast([0.0, 0.0], [1.0, 0.0], 10.0).unwrap();
        assert!((t - 2.0).abs() < 1e-12, "{t}");
        let t = s.cast([0.0, 0.0], [-1.0, 0.0], 10.0).unwrap();
        assert!((t - 1.5).abs() < 1e-12, "{t}");
        // Slanted: hits x = 2 at y = 2 tan(0.3) (inside the wall's span).
        let (c, sn) = (0.3f64.cos(), 0.3f64.sin());
        let t = s.cast([0.0, 0.0], [c, sn], 10.0).unwrap();
        assert!((t - 2.0 / c).abs() < 1e-9, "{t}");
        // Out of range, and past the walls' ends.
        assert_eq!(s.cast([0.0, 0.0], [1.0, 0.0], 1.9), None);
        assert_eq!(s.cast([0.0, 0.0], [0.0, 1.0], 10.0), None);
        // From outside the grid, walking in.
        let t = s.cast([-5.0, 0.5], [1.0, 0.0], 10.0).unwrap();
        assert!((t - 3.5).abs() < 1e-12, "{t}");
    }

    #[test]
    fn a_vast_slice_gets_larger_buckets_and_the_same_hits() {
        let (mut v, mut i) = (Vec::new(), Vec::new());
        wall(2.0, &mut v, &mut i);
        wall(20_000.0, &mut v, &mut i);
        let s = ScanSlice::new(&v, &i, 0.5);
        assert!(s.dims[0] <= MAX_BUCKETS && s.dims[1] <= MAX_BUCKETS && s.cell > CELL, "{:?} {}", s.dims, s.cell);
        let t = s.cast([0.0, 0.0], [1.0, 0.0], 100.0).unwrap();
        assert!((t - 2.0).abs() < 1e-12, "{t}");
        let t = s.cast([3.0, 0.5], [1.0, 0.0], 1e6).unwrap();
        assert!((t - 19_997.0).abs() < 1e-9, "{t}");
    }

    #[test]
    fn planes_above_below_and_through_triangles() {
        let (mut v, mut i) = (Vec::new(), Vec::new());
        wall(1.0, &mut v, &mut i);
        // A floor triangle lying in the plane z = 0 is dropped; the wall's bottom edge is one
        // segment from the triangle that has it.
        v.extend([[-3.0, -3.0, 0.0], [3.0, -3.0, 0.0], [0.0, 3.0, 0.0]]);
        i.push([4, 5, 6]);
        assert_eq!(ScanSlice::new(&v, &i, 0.0).len(), 1);
        assert_eq!(ScanSlice::new(&v, &i, 1.5).len(), 0);
        assert_eq!(ScanSlice::new(&v, &i, 0.5).len(), 2);
        assert!(ScanSlice::new(&v, &i, 1.5).cast([0.0, 0.0], [1.0, 0.0], 10.0).is_none());
    }
}
