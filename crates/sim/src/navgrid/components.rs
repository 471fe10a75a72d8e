//! Connected components of a mask over the grid's cells (4-connected), numbered as a flood
//! fill from each unlabelled cell in cell order would number them.

/// 4-connected components of `mask`: label per cell (`u32::MAX` outside) and size per label.
pub(super) fn components(mask: &[bool], w: usize, h: usize) -> (Vec<u32>, Vec<usize>) {
    components_where(mask, w, h, |_, _| true)
}

/// [`components`] where neighbouring cells `i` and `j` of `mask` are joined only when
/// `joins(i, j)`, which must be symmetric (a flight's treads: within a climb of each other).
///
/// Two passes over the rows with a union-find of provisional labels, then the labels renumbered
/// in the order of each component's first cell: the numbers a flood fill started at each
/// unlabelled cell in cell order gives, at a few nanoseconds a cell, without a division.
pub(crate) fn components_where(mask: &[bool], w: usize, h: usize, joins: impl Fn(usize, usize) -> bool) -> (Vec<u32>, Vec<usize>) {
    let mut labels = vec![u32::MAX; w * h];
    // The provisional labels' parents (a root is its own).
    let mut parent: Vec<u32> = Vec::new();
    fn root(parent: &mut [u32], mut k: u32) -> u32 {
        while parent[k as usize] != k {
            // (path halving)
            parent[k as usize] = parent[parent[k as usize] as usize];
            k = parent[k as usize];
        }
        k
    }
    for r in 0..h {
        for c in 0..w {
            let i = r * w + c;
            if !mask[i] {
                continue;
            }
            let left = if c > 0 && mask[i - 1] && joins(i, i - 1) { labels[i - 1] } else { u32::MAX };
            let up = if r > 0 && mask[i - w] && joins(i, i - w) { labels[i - w] } else { u32::MAX };
            labels[i] = match (left, up) {
                (u32::MAX, u32::MAX) => {
                    parent.push(parent.len() as u32);
                    parent.len() as u32 - 1
                }
                (k, u32::MAX) | (u32::MAX, k) => k,
                (a, b) if a == b => a,
                (a, b) => {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    let (lo, hi) = (ra.min(rb), ra.max(rb));
                    parent[hi as usize] = lo;
                    a
                }
            };
        }
    }
    // Each root's final number, given at its component's first cell.
    let mut number = vec![u32::MAX; parent.len()];
    let mut sizes = Vec::new();
    // (runs of one provisional label are the rule: the last one's number is kept)
    let mut last = (u32::MAX, 0u32);
    for l in labels.iter_mut().filter(|l| **l != u32::MAX) {
        if *l != last.0 {
            let k = root(&mut parent, *l) as usize;
            if number[k] == u32::MAX {
                number[k] = sizes.len() as u32;
                sizes.push(0);
            }
            last = (*l, number[k]);
        }
        *l = last.1;
        sizes[last.1 as usize] += 1;
    }
    (labels, sizes)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The flood fill the numbering follows: from each unlabelled cell in cell order.
    fn flood(mask: &[bool], w: usize, h: usize, joins: impl Fn(usize, usize) -> bool) -> (Vec<u32>, Vec<usize>) {
        let mut labels = vec![u32::MAX; w * h];
        let mut sizes = Vec::new();
        for s in 0..w * h {
            if !mask[s] || labels[s] != u32::MAX {
                continue;
            }
            let k = sizes.len() as u32;
            labels[s] = k;
            let (mut stack, mut n) = (vec![s], 0);
            while let Some(i) = stack.pop() {
                n += 1;
                let (c, r) = (i % w, i / w);
                let near = [(c > 0).then(|| i - 1), (c + 1 < w).then(|| i + 1), (r > 0).then(|| i - w), (r + 1 < h).then(|| i + w)];
                for j in near.into_iter().flatten() {
                    if mask[j] && labels[j] == u32::MAX && joins(i, j) {
                        labels[j] = k;
                        stack.push(j);
                    }
                }
            }
            sizes.push(n);
        }
        (labels, sizes)
    }

    #[test]
    fn the_same_labels_and_sizes_as_a_flood_fill_in_cell_order() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        for (w, h, p) in [(1, 1, 0.5), (7, 1, 0.6), (1, 9, 0.6), (23, 17, 0.45), (40, 31, 0.6), (64, 64, 0.7)] {
            for _ in 0..20 {
                let mask: Vec<bool> = (0..w * h).map(|_| rng.gen_bool(p)).collect();
                let height: Vec<i32> = (0..w * h).map(|_| rng.gen_range(0..4)).collect();
                assert_eq!(components(&mask, w, h), flood(&mask, w, h, |_, _| true), "{w}x{h}");
                let climb = |i: usize, j: usize| (height[i] - height[j]).abs() <= 1;
                assert_eq!(components_where(&mask, w, h, climb), flood(&mask, w, h, climb), "{w}x{h}, joined by height");
            }
        }
        // Nested rings joined by one cell each on the left: one component whose provisional
        // labels merge many times.
        let (w, h) = (15, 15);
        let mut mask = vec![false; w * h];
        for r in 0..h {
            for c in 0..w {
                let ring = c.min(r).min(w - 1 - c).min(h - 1 - r);
                mask[r * w + c] = ring % 2 == 0 || (c == ring && r == h / 2);
            }
        }
        let (labels, sizes) = components(&mask, w, h);
        assert_eq!(sizes.len(), 1);
        assert_eq!((labels.clone(), sizes), flood(&mask, w, h, |_, _| true));
    }
}
