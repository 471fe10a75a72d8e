//! Exact squared Euclidean distance transforms on cell grids (Felzenszwalb and Huttenlocher's
//! lower envelope of parabolas), in whole cells squared, over a window of a larger grid.
//!
//! Squared distances between cell centres are integers, so the result is exact: it does not
//! depend on the order of the passes, on the window (for distances up to the window's margin)
//! or on how the field is assembled, which is what lets costmaps update in pieces.

/// Squared distance (cells^2) of a cell with nothing blocked in reach.
pub const FAR: u32 = u32::MAX;

/// Squared distances (cells^2) from each cell of a `w` x `h` window (row-major) to the
/// nearest cell for which `blocked(col, row)` holds, written into `out`. Distances up to
/// `cap` (cells^2) are exact; larger ones are some value above `cap` ([`FAR`] when nothing is
/// blocked within the window's row and column reach).
pub fn squared_edt(w: usize, h: usize, blocked: impl Fn(usize, usize) -> bool, cap: u32, out: &mut Vec<u32>) {
    out.clear();
    out.resize(w * h, FAR);
    if w == 0 || h == 0 {
        return;
    }
    // Column pass: distance (cells) to the nearest blocked cell in the same column, down then up.
    const NONE: u32 = u32::MAX / 4;
    let mut g = vec![NONE; w * h];
    for r in 0..h {
        for c in 0..w {
            g[r * w + c] = if blocked(c, r) {
                0
            } else if r > 0 {
                g[(r - 1) * w + c].saturating_add(1).min(NONE)
            } else {
                NONE
            };
        }
    }
    for r in (0..h.saturating_sub(1)).rev() {
        for c in 0..w {
            let below = g[(r + 1) * w + c].saturating_add(1);
            if below < g[r * w + c] {
                g[r * w + c] = below;
            }
        }
    }
    // Row pass: lower envelope of the parabolas (c - v)^2 + g(v)^2. Parabolas whose apex is
    // above `cap` can only give distances above it and are left out.
    let mut v = vec![0usize; w];
    let mut z = vec![0f64; w + 1];
    let mut f = vec![0f64; w];
    for r in 0..h {
        let row = &g[r * w..(r + 1) * w];
        let mut k: isize = -1;
        for q in 0..w {
            let gq = row[q] as u64;
            if gq >= NONE as u64 || gq * gq > cap as u64 {
                continue;
            }
            let fq = (gq * gq) as f64;
            f[q] = fq;
            if k < 0 {
                k = 0;
                v[0] = q;
                z[0] = f64::NEG_INFINITY;
                z[1] = f64::INFINITY;
                continue;
            }
            loop {
                let p = v[k as usize];
                let s = ((fq + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
                if s <= z[k as usize] && k > 0 {
                    k -= 1;
                } else if s <= z[k as usize] {
                    v[0] = q;
                    z[1] = f64::INFINITY;
                    break;
                } else {
                    k += 1;
                    v[k as usize] = q;
                    z[k as usize] = s;
                    z[k as usize + 1] = f64::INFINITY;
                    break;
                }
            }
        }
        if k < 0 {
            continue;
        }
        let out_row = &mut out[r * w..(r + 1) * w];
        let mut j = 0usize;
        for q in 0..w {
            while z[j + 1] < q as f64 {
                j += 1;
            }
            let p = v[j];
            let dq = q.abs_diff(p) as u64;
            out_row[q] = (dq * dq + f[p] as u64).min(FAR as u64 - 1) as u32;
        }
    }
}

/// Squared distances (cells^2) from each cell of `out_w` x `out_h` cells to the nearest of
/// `points` (cell coordinates relative to the same origin, possibly outside), exact; cells
/// farther than `reach` cells (along either axis) from every point keep their value. Each point
/// stamps its `(2 reach + 1)^2` neighbourhood: cheap for a few points.
pub fn stamp_points(out: &mut [u32], out_w: usize, out_h: usize, points: &[(isize, isize)], reach: usize) {
    let reach = reach as isize;
    for &(pc, pr) in points {
        let (c0, c1) = ((pc - reach).max(0), (pc + reach + 1).min(out_w as isize));
        let (r0, r1) = ((pr - reach).max(0), (pr + reach + 1).min(out_h as isize));
        for r in r0..r1 {
            let dr = (r - pr) as i64;
            let row = &mut out[r as usize * out_w..(r as usize + 1) * out_w];
            for c in c0..c1 {
                let dc = (c - pc) as i64;
                let d2 = (dc * dc + dr * dr) as u32;
                let x = &mut row[c as usize];
                if d2 < *x {
                    *x = d2;
                }
            }
        }
    }
}

/// Distance (cells, f64) from each cell centre of a `w` x `h` grid (row-major) to the nearest
/// `blocked` cell centre; infinite when nothing is blocked. Exact: the square root of the
/// integer squared distance.
pub fn edt(blocked: &[bool], w: usize, h: usize) -> Vec<f64> {
    let mut d2 = Vec::new();
    squared_edt(w, h, |c, r| blocked[r * w + c], FAR - 1, &mut d2);
    d2.into_iter().map(|v| if v == FAR { f64::INFINITY } else { (v as f64).sqrt() }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic pattern of blocked cells, about `p` of them.
    fn pattern(w: usize, h: usize, p: f64, seed: u64) -> Vec<bool> {
        (0..w * h)
            .map(|i| {
                let x = (seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
                ((x >> 11) as f64 / (1u64 << 53) as f64) < p
            })
            .collect()
    }

    fn brute(blocked: &[bool], w: usize, h: usize) -> Vec<u32> {
        (0..w * h)
            .map(|i| {
                let (c, r) = ((i % w) as i64, (i / w) as i64);
                (0..w * h)
                    .filter(|&j| blocked[j])
                    .map(|j| {
                        let (a, b) = ((j % w) as i64 - c, (j / w) as i64 - r);
                        (a * a + b * b) as u32
                    })
                    .min()
                    .unwrap_or(FAR)
            })
            .collect()
    }

    #[test]
    fn matches_brute_force_and_the_float_transform() {
        for (w, h, p) in [(17usize, 9usize, 0.05), (30, 31, 0.01), (8, 40, 0.2), (25, 25, 0.0), (1, 7, 0.3)] {
            let blocked = pattern(w, h, p, 7);
            let mut out = Vec::new();
            squared_edt(w, h, |c, r| blocked[r * w + c], u32::MAX - 1, &mut out);
            assert_eq!(out, brute(&blocked, w, h), "{w}x{h}");
            let float = edt(&blocked, w, h);
            for i in 0..w * h {
                if out[i] != FAR {
                    assert_eq!((out[i] as f64).sqrt(), float[i]);
                } else {
                    assert!(float[i].is_infinite());
                }
            }
            // Capped: exact up to the cap, above it beyond.
            let cap = 20;
            let mut capped = Vec::new();
            squared_edt(w, h, |c, r| blocked[r * w + c], cap, &mut capped);
            for i in 0..w * h {
                if out[i] <= cap {
                    assert_eq!(capped[i], out[i]);
                } else {
                    assert!(capped[i] > cap);
                }
            }
            // Stamping the blocked cells gives the same field within reach.
            let pts: Vec<(isize, isize)> = (0..w * h).filter(|&i| blocked[i]).map(|i| ((i % w) as isize, (i / w) as isize)).collect();
            let mut stamped = vec![FAR; w * h];
            stamp_points(&mut stamped, w, h, &pts, 6);
            for i in 0..w * h {
                if out[i] <= 36 {
                    assert_eq!(stamped[i], out[i]);
                } else {
                    assert!(stamped[i] > 36);
                }
            }
        }
    }
}
