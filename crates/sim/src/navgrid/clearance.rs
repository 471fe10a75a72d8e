//! Clearance: the exact planar distance from each cell centre to the nearest obstacle.
//!
//! Obstacles are the scene's triangles clipped to the agent's body band and projected onto
//! the ground plane; their edges are 2D segments, and distances to segments are exact (no
//! grid quantisation), which is what keeps geodesics within 0.5% of the true length.
//! Cells without floor count as obstacles through a Euclidean distance transform.

/// A 2D segment (m).
pub(crate) type Seg = [[f64; 2]; 2];

/// Distance between two segments (m): 0 when they cross.
pub(crate) fn segment_segment_distance(a: &Seg, b: &Seg) -> f64 {
    let cross = |o: [f64; 2], p: [f64; 2], q: [f64; 2]| (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0]);
    let d1 = cross(a[0], a[1], b[0]);
    let d2 = cross(a[0], a[1], b[1]);
    let d3 = cross(b[0], b[1], a[0]);
    let d4 = cross(b[0], b[1], a[1]);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0)) {
        return 0.0;
    }
    // Squared distances and one square root (`hypot` guards against overflow that metre-scale
    // coordinates never reach, and was the line-of-sight test's largest cost).
    let pd2 = |p: [f64; 2], s: &Seg| {
        let c = closest_on_segment(p, s);
        let (dx, dy) = (c[0] - p[0], c[1] - p[1]);
        dx * dx + dy * dy
    };
    pd2(a[0], b).min(pd2(a[1], b)).min(pd2(b[0], a)).min(pd2(b[1], a)).sqrt()
}

/// A segment in its own frame (unit direction and normal), for bounding its distance to
/// other segments cheaply ([`SegmentLine::clear_of`]).
pub(crate) struct SegmentLine {
    /// The segment (m).
    pub seg: Seg,
    /// Unit direction from its start to its end, and its length (m); zero for a segment
    /// shorter than a nanometre (no bound).
    dir: [f64; 2],
    len: f64,
}

impl SegmentLine {
    /// The segment from `a` to `b` (m).
    pub fn new(a: [f64; 2], b: [f64; 2]) -> SegmentLine {
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = (d[0] * d[0] + d[1] * d[1]).sqrt();
        let dir = if l > 1e-9 { [d[0] / l, d[1] / l] } else { [0.0, 0.0] };
        SegmentLine { seg: [a, b], dir, len: l }
    }

    /// Whether [`segment_segment_distance`] from this segment to `o` is at least `min` (m).
    /// When `o` lies wholly on one side of the line, or wholly before its start or beyond its
    /// end, farther than `min` (with a nanometre to spare for rounding), so does the segment:
    /// no exact distance is needed.
    #[inline]
    pub fn clear_of(&self, o: &Seg, min: f64) -> bool {
        let a = self.seg[0];
        let u = self.dir;
        let (p, q) = ([o[0][0] - a[0], o[0][1] - a[1]], [o[1][0] - a[0], o[1][1] - a[1]]);
        // Across the line (normal `(-u1, u0)`), then along it.
        let (s0, s1) = (u[0] * p[1] - u[1] * p[0], u[0] * q[1] - u[1] * q[0]);
        let (t0, t1) = (u[0] * p[0] + u[1] * p[1], u[0] * q[0] + u[1] * q[1]);
        let far = min + 1e-9;
        if s0.min(s1) >= far || s0.max(s1) <= -far || t0.max(t1) <= -far || t0.min(t1) >= self.len + far {
            return true;
        }
        segment_segment_distance(&self.seg, o) >= min
    }
}

/// The last few obstacle segments found clear of one [`SegmentLine`] (a ring of 16), so that
/// the cells of one line-of-sight walk, which share most neighbours, test each once.
pub(crate) struct SeenSegments {
    ids: [u32; 16],
    next: usize,
}

impl SeenSegments {
    /// None seen yet.
    pub fn new() -> SeenSegments {
        SeenSegments { ids: [u32::MAX; 16], next: 0 }
    }

    /// Whether segment `k` is among the last 16 found clear.
    pub fn contains(&self, k: u32) -> bool {
        self.ids.contains(&k)
    }

    /// Remembers segment `k` as clear (forgetting the oldest).
    pub fn insert(&mut self, k: u32) {
        self.ids[self.next] = k;
        self.next = (self.next + 1) % self.ids.len();
    }
}

/// Closest point of segment `s` to `p`.
pub(crate) fn closest_on_segment(p: [f64; 2], s: &Seg) -> [f64; 2] {
    let d = [s[1][0] - s[0][0], s[1][1] - s[0][1]];
    let l2 = d[0] * d[0] + d[1] * d[1];
    let t = if l2 <= 0.0 { 0.0 } else { (((p[0] - s[0][0]) * d[0] + (p[1] - s[0][1]) * d[1]) / l2).clamp(0.0, 1.0) };
    [s[0][0] + t * d[0], s[0][1] + t * d[1]]
}

/// Rows of the grid one thread fills at a time in [`segment_distance_where`].
const SEGMENT_BAND_ROWS: usize = 16;

/// Exact distance (m, capped at `cap`) from each cell centre to the segments, and the index of
/// the nearest segment of each cell within the cap (`u32::MAX` beyond it); cells where `skip`
/// is true (when it is not empty) are left at the cap, without a segment.
pub(crate) fn segment_distance(spec: &super::raster::GridSpec, segs: &[Seg], cap: f64, skip: &[bool]) -> (Vec<f32>, Vec<u32>) {
    segment_distance_where(spec, segs, cap, skip, |_, _| true)
}

/// [`segment_distance`] counting for cell `i` only the segments `k` that `counts(k, i)` accepts
/// (on a storey with stairs: those within the body band above the cell's own ground).
pub(crate) fn segment_distance_where(
    spec: &super::raster::GridSpec,
    segs: &[Seg],
    cap: f64,
    skip: &[bool],
    counts: impl Fn(usize, usize) -> bool + Sync,
) -> (Vec<f32>, Vec<u32>) {
    use rayon::prelude::*;
    let n = spec.w * spec.h;
    let mut dist = vec![cap as f32; n];
    let mut near = vec![u32::MAX; n];
    let mut best = vec![cap * cap; n];
    // Each segment's cells (those whose centre lies within `cap` of its bounding box).
    let boxes: Vec<Option<(usize, usize, usize, usize)>> = segs
        .iter()
        .map(|s| {
            let xmin = s[0][0].min(s[1][0]) - cap;
            let xmax = s[0][0].max(s[1][0]) + cap;
            let ymin = s[0][1].min(s[1][1]) - cap;
            let ymax = s[0][1].max(s[1][1]) + cap;
            let c0 = ((xmin - spec.x0) / spec.res - 0.5).ceil().max(0.0) as usize;
            let c1 = ((xmax - spec.x0) / spec.res - 0.5).floor().min(spec.w as f64 - 1.0);
            let r0 = ((ymin - spec.y0) / spec.res - 0.5).ceil().max(0.0) as usize;
            let r1 = ((ymax - spec.y0) / spec.res - 0.5).floor().min(spec.h as f64 - 1.0);
            (c1 >= 0.0 && r1 >= 0.0).then_some((c0, c1 as usize, r0, r1 as usize))
        })
        .collect();
    // Cells not skipped, summed over each rectangle from the grid's corner: a segment whose
    // cells are all skipped changes none and is left out.
    let open = (!skip.is_empty()).then(|| {
        let w1 = spec.w + 1;
        let mut sum = vec![0u32; w1 * (spec.h + 1)];
        for r in 0..spec.h {
            let mut row = 0u32;
            for c in 0..spec.w {
                row += !skip[r * spec.w + c] as u32;
                sum[(r + 1) * w1 + c + 1] = sum[r * w1 + c + 1] + row;
            }
        }
        sum
    });
    let reaches_open = |(c0, c1, r0, r1): (usize, usize, usize, usize)| match &open {
        None => true,
        Some(sum) => {
            let w1 = spec.w + 1;
            sum[(r1 + 1) * w1 + c1 + 1] + sum[r0 * w1 + c0] != sum[r0 * w1 + c1 + 1] + sum[(r1 + 1) * w1 + c0]
        }
    };
    // Each band's segments, in order (most reach one band or two).
    let mut in_band: Vec<Vec<u32>> = vec![Vec::new(); spec.h.div_ceil(SEGMENT_BAND_ROWS)];
    for (k, b) in boxes.iter().enumerate() {
        if let Some((_, _, r0, r1)) = b.filter(|b| b.0 <= b.1 && b.2 <= b.3 && reaches_open(*b)) {
            for list in &mut in_band[r0 / SEGMENT_BAND_ROWS..=r1 / SEGMENT_BAND_ROWS] {
                list.push(k as u32);
            }
        }
    }
    // Bands of rows in parallel, each taking the segments in order (the same nearest segment
    // per cell as one pass, any thread count).
    let band = SEGMENT_BAND_ROWS * spec.w;
    best.par_chunks_mut(band).zip(near.par_chunks_mut(band)).enumerate().for_each(|(b, (best, near))| {
        let (b0, b1) = (b * SEGMENT_BAND_ROWS, ((b + 1) * SEGMENT_BAND_ROWS).min(spec.h));
        for &k in &in_band[b] {
            let k = k as usize;
            let s = &segs[k];
            let Some((c0, c1, r0, r1)) = boxes[k] else { continue };
            let (sx0, sx1) = (s[0][0].min(s[1][0]), s[0][0].max(s[1][0]));
            let (sy0, sy1) = (s[0][1].min(s[1][1]), s[0][1].max(s[1][1]));
            for r in r0.max(b0)..=r1.min(b1 - 1) {
                let py = spec.y0 + (r as f64 + 0.5) * spec.res;
                let by = (sy0 - py).max(py - sy1).max(0.0);
                for c in c0..=c1 {
                    let i = r * spec.w + c;
                    if !skip.is_empty() && skip[i] {
                        continue;
                    }
                    let px = spec.x0 + (c as f64 + 0.5) * spec.res;
                    // The segment's bounding box is no nearer than the nearest found so far
                    // (less a billionth, far above the rounding of the exact distance): this
                    // segment cannot take the cell.
                    let bx = (sx0 - px).max(px - sx1).max(0.0);
                    if (bx * bx + by * by) * (1.0 - 1e-9) >= best[i - b0 * spec.w] {
                        continue;
                    }
                    let q = closest_on_segment([px, py], s);
                    let d2 = (q[0] - px).powi(2) + (q[1] - py).powi(2);
                    if d2 < best[i - b0 * spec.w] && counts(k, i) {
                        best[i - b0 * spec.w] = d2;
                        near[i - b0 * spec.w] = k as u32;
                    }
                }
            }
        }
    });
    for i in 0..n {
        if best[i] < cap * cap {
            dist[i] = best[i].sqrt() as f32;
        }
    }
    (dist, near)
}

/// Euclidean distance transform: for each cell, the distance (in cells) from its centre to
/// the nearest centre of a cell where `blocked` is true, exact up to `sqrt(cap)` (`cap` in
/// cells^2), infinite beyond it or when none is.
pub(crate) fn edt(blocked: &[bool], w: usize, h: usize, cap: u32) -> Vec<f32> {
    let mut d2 = Vec::new();
    xhab_types::distance_field::squared_edt(w, h, |c, r| blocked[r * w + c], cap, &mut d2);
    d2.into_iter().map(|v| if v <= cap { (v as f64).sqrt() as f32 } else { f32::INFINITY }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distances() {
        let a = [[0.0, 0.0], [1.0, 0.0]];
        assert_eq!(segment_segment_distance(&a, &[[0.5, -1.0], [0.5, 1.0]]), 0.0);
        assert!((segment_segment_distance(&a, &[[2.0, 1.0], [2.0, 3.0]]) - 2f64.sqrt()).abs() < 1e-12);
        assert!((segment_segment_distance(&a, &[[0.2, 0.3], [0.8, 0.3]]) - 0.3).abs() < 1e-12);
    }

    #[test]
    fn edt_matches_brute_force() {
        let (w, h) = (13, 9);
        let blocked: Vec<bool> = (0..w * h).map(|i| (i * 7919 + 3) % 17 == 0).collect();
        let d = edt(&blocked, w, h, u32::MAX - 1);
        // Capped at 5 cells: the same up to it, infinite beyond.
        let capped = edt(&blocked, w, h, 25);
        for (a, b) in d.iter().zip(&capped) {
            assert!(if *a <= 5.0 { a == b } else { b.is_infinite() }, "{a} capped to {b}");
        }
        for r in 0..h {
            for c in 0..w {
                let mut best = f64::INFINITY;
                for rr in 0..h {
                    for cc in 0..w {
                        if blocked[rr * w + cc] {
                            best = best.min(((c as f64 - cc as f64).powi(2) + (r as f64 - rr as f64).powi(2)).sqrt());
                        }
                    }
                }
                assert!((d[r * w + c] as f64 - best).abs() < 1e-5, "({c},{r}): {} vs {best}", d[r * w + c]);
            }
        }
    }

    #[test]
    fn segment_distance_takes_the_first_nearest_segment_of_every_cell() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
        let spec = super::super::raster::GridSpec { x0: -0.3, y0: 0.1, res: 0.05, w: 70, h: 50 };
        // Short pieces of walls (collinear runs, shared ends, crossings) and strays.
        let mut segs: Vec<Seg> = Vec::new();
        for _ in 0..40 {
            let (x, y, a) = (rng.gen_range(-0.5..3.5), rng.gen_range(0.0..2.6), rng.gen_range(0..8) as f64 * std::f64::consts::FRAC_PI_4);
            let mut p = [x, y];
            for _ in 0..rng.gen_range(1..6) {
                let l = rng.gen_range(0.02..0.4);
                let q = [p[0] + l * a.cos(), p[1] + l * a.sin()];
                segs.push([p, q]);
                p = q;
            }
        }
        let cap = 0.38;
        let skip: Vec<bool> = (0..spec.w * spec.h).map(|i| i % 13 == 0).collect();
        let (d, near) = segment_distance(&spec, &segs, cap, &skip);
        for r in 0..spec.h {
            for c in 0..spec.w {
                let i = r * spec.w + c;
                let p = [spec.x0 + (c as f64 + 0.5) * spec.res, spec.y0 + (r as f64 + 0.5) * spec.res];
                // Every segment in order, the same arithmetic; a later one takes the cell only
                // when strictly nearer.
                let (mut best, mut k) = (cap * cap, u32::MAX);
                if !skip[i] {
                    for (j, s) in segs.iter().enumerate() {
                        let q = closest_on_segment(p, s);
                        let d2 = (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
                        if d2 < best {
                            (best, k) = (d2, j as u32);
                        }
                    }
                }
                assert_eq!(near[i], k, "cell ({c}, {r})");
                let want = if best < cap * cap { best.sqrt() as f32 } else { cap as f32 };
                assert_eq!(d[i].to_bits(), want.to_bits(), "cell ({c}, {r})");
            }
        }
    }

    #[test]
    fn segment_distance_is_exact() {
        let spec = super::super::raster::GridSpec { x0: 0.0, y0: 0.0, res: 0.1, w: 20, h: 20 };
        let segs = vec![[[1.0, 0.0], [1.0, 2.0]]];
        let (d, near) = segment_distance(&spec, &segs, 0.5, &[]);
        // Cell (7, 3) centre at x = 0.75: 0.25 m from the segment.
        assert!((d[3 * 20 + 7] - 0.25).abs() < 1e-6);
        assert_eq!(near[3 * 20 + 7], 0);
        assert_eq!(near[3 * 20], u32::MAX);
        assert_eq!(d[3 * 20], 0.5);
    }
}
