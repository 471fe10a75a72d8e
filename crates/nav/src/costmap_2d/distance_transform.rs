//! Exact Euclidean distance transform of a grid (Felzenszwalb and Huttenlocher's lower envelope
//! of parabolas, one pass per column then per row): O(cells), no approximation, unlike ROS's
//! inflation which propagates cell by cell from the obstacles in a priority queue.

/// Squared distance (cells^2) from each cell centre to the nearest seed cell centre of a
/// `w` x `h` row-major grid; `f64::INFINITY` everywhere when there is no seed.
pub fn squared_distance_transform(seeds: &[bool], w: usize, h: usize) -> Vec<f64> {
    assert_eq!(seeds.len(), w * h, "seed grid size");
    let mut f: Vec<f64> = seeds
        .iter()
        .map(|&s| if s { 0.0 } else { f64::INFINITY })
        .collect();
    let n = w.max(h);
    let mut scratch = Scratch {
        line: vec![0.0; n],
        out: vec![0.0; n],
        v: vec![0; n],
        z: vec![0.0; n + 1],
    };
    for x in 0..w {
        for y in 0..h {
            scratch.line[y] = f[y * w + x];
        }
        scratch.transform(h);
        for y in 0..h {
            f[y * w + x] = scratch.out[y];
        }
    }
    for y in 0..h {
        scratch.line[..w].copy_from_slice(&f[y * w..(y + 1) * w]);
        scratch.transform(w);
        f[y * w..(y + 1) * w].copy_from_slice(&scratch.out[..w]);
    }
    f
}

struct Scratch {
    line: Vec<f64>,
    out: Vec<f64>,
    v: Vec<usize>,
    z: Vec<f64>,
}

impl Scratch {
    /// 1D squared distance transform of `line[..n]` into `out[..n]`.
    fn transform(&mut self, n: usize) {
        let f = &self.line[..n];
        let Some(first) = f.iter().position(|v| v.is_finite()) else {
            self.out[..n].iter_mut().for_each(|o| *o = f64::INFINITY);
            return;
        };
        let (v, z) = (&mut self.v, &mut self.z);
        let mut k = 0usize;
        v[0] = first;
        z[0] = f64::NEG_INFINITY;
        z[1] = f64::INFINITY;
        for q in first + 1..n {
            if !f[q].is_finite() {
                continue;
            }
            let qf = q as f64;
            loop {
                let p = v[k];
                let pf = p as f64;
                let s = ((f[q] + qf * qf) - (f[p] + pf * pf)) / (2.0 * (qf - pf));
                if s <= z[k] && k > 0 {
                    k -= 1;
                    continue;
                }
                if s <= z[k] {
                    // Only reachable for k == 0 with z[0] = -inf, which `s` cannot undercut.
                    v[0] = q;
                    z[1] = f64::INFINITY;
                } else {
                    k += 1;
                    v[k] = q;
                    z[k] = s;
                    z[k + 1] = f64::INFINITY;
                }
                break;
            }
        }
        k = 0;
        for q in 0..n {
            while z[k + 1] < q as f64 {
                k += 1;
            }
            let d = q as f64 - v[k] as f64;
            self.out[q] = d * d + f[v[k]];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force for comparison.
    fn brute(seeds: &[bool], w: usize, h: usize) -> Vec<f64> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64, (i / w) as f64);
                (0..w * h)
                    .filter(|&j| seeds[j])
                    .map(|j| ((j % w) as f64 - x).powi(2) + ((j / w) as f64 - y).powi(2))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    #[test]
    fn matches_brute_force_on_scattered_seeds() {
        let (w, h) = (23, 17);
        let mut state = 12345u64;
        let seeds: Vec<bool> = (0..w * h)
            .map(|_| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                matches!((state >> 33) % 29, 0)
            })
            .collect();
        assert_eq!(
            squared_distance_transform(&seeds, w, h),
            brute(&seeds, w, h)
        );
    }

    #[test]
    fn no_seed_is_infinite_everywhere() {
        assert!(squared_distance_transform(&[false; 12], 4, 3)
            .iter()
            .all(|d| d.is_infinite()));
        assert_eq!(
            squared_distance_transform(&[true, false, false], 3, 1),
            vec![0.0, 1.0, 4.0]
        );
    }
}
