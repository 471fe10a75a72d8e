//! Convex vertices of a floor's obstacle segments: the corners a shortest path can wrap
//! around. Where the pieces of one straight wall meet, or inside a flat obstacle, the
//! segments that end at a vertex leave no gap wider than a half turn, and no path bends
//! there.

use rayon::prelude::*;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A vertex's cell on a 10 micrometre lattice (truncated, without a libm call): segment ends
/// that meet share it.
pub(crate) fn vertex_key(v: [f64; 2]) -> (i64, i64) {
    const Q: f64 = 1e5;
    ((v[0] * Q) as i64, (v[1] * Q) as i64)
}

/// Least turn of the boundary at a vertex for a path to bend there (rad): a vertex whose
/// segments leave no gap wider than a half turn plus this is flat (pieces of one straight
/// wall) or reflex, and no shortest path bends at it.
const CONVEX_GAP: f64 = 1e-3;

/// Which ends of some of a floor's obstacle segments are convex vertices: those where the
/// directions of all the segments that end there leave a gap wider than a half turn (by
/// [`CONVEX_GAP`]), free space a path can wrap around. A lone end is convex; segments shorter
/// than the lattice's quantum have no direction and are left out.
pub(crate) struct ConvexVertices {
    /// Lattice key of each vertex asked about, and whether it is convex.
    convex: HashMap<(i64, i64), bool, BuildHasherDefault<KeyHasher>>,
}

impl ConvexVertices {
    /// The ends of the segments `wanted` marks, looked at among all of `segments`.
    pub(crate) fn new(segments: &[[[f64; 2]; 2]], wanted: &[bool]) -> ConvexVertices {
        let mut index: HashMap<(i64, i64), u32, BuildHasherDefault<KeyHasher>> = HashMap::default();
        for (s, _) in segments.iter().zip(wanted).filter(|(_, &w)| w) {
            for v in s {
                let n = index.len() as u32;
                index.entry(vertex_key(*v)).or_insert(n);
            }
        }
        // Each vertex's directions (rad), gathered in parallel and sorted per vertex.
        let index = &index;
        let mut dirs: Vec<(u32, f64)> = segments
            .par_chunks(4096)
            .flat_map_iter(|chunk| {
                chunk.iter().flat_map(|s| {
                    let (ka, kb) = (vertex_key(s[0]), vertex_key(s[1]));
                    let ends = if ka == kb { [None, None] } else { [Some((ka, s[0], s[1])), Some((kb, s[1], s[0]))] };
                    ends.into_iter().flatten().filter_map(|(k, a, b)| index.get(&k).map(|&j| (j, (b[1] - a[1]).atan2(b[0] - a[0]))))
                })
            })
            .collect();
        dirs.par_sort_unstable_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
        let mut flat = vec![false; index.len()];
        for group in dirs.chunk_by(|x, y| x.0 == y.0) {
            flat[group[0].0 as usize] = widest_gap(group.iter().map(|d| d.1)) <= std::f64::consts::PI + CONVEX_GAP;
        }
        ConvexVertices { convex: index.iter().map(|(&k, &j)| (k, !flat[j as usize])).collect() }
    }

    /// Whether `v` (m) is a convex vertex (true for a point not asked about: no pruning).
    pub(crate) fn is_convex(&self, v: [f64; 2]) -> bool {
        self.convex.get(&vertex_key(v)).copied().unwrap_or(true)
    }
}

/// The widest gap (rad) between consecutive directions around a point, given them sorted in
/// `[-pi, pi]`, the gap from the last round to the first included (a whole turn for one
/// direction, 0 for none).
pub(crate) fn widest_gap(mut sorted: impl Iterator<Item = f64>) -> f64 {
    let Some(first) = sorted.next() else { return 0.0 };
    let (mut last, mut gap) = (first, f64::NEG_INFINITY);
    for a in sorted {
        gap = gap.max(a - last);
        last = a;
    }
    gap.max(first + std::f64::consts::TAU - last)
}

/// FxHash's multiply-rotate hash: fast for the lattice keys, and the same on every run.
#[derive(Default)]
struct KeyHasher(u64);

impl Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(b as u64);
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn convex_vertices_are_where_the_segments_leave_more_than_a_half_turn_free() {
        let segs = [
            // A wall in two pieces meeting at (1, 0): flat.
            [[0.0, 0.0], [1.0, 0.0]],
            [[1.0, 0.0], [2.0, 0.0]],
            // A corner at (5, 0): free through 270 degrees; a zero-length sliver there has no
            // direction and changes nothing.
            [[4.0, 0.0], [5.0, 0.0]],
            [[5.0, 0.0], [5.0, 1.0]],
            [[5.0, 0.0], [5.0, 0.0]],
            // Three segments a third of a turn apart at (8, 0): no gap over a half turn.
            [[8.0, 0.0], [9.0, 0.0]],
            [[8.0, 0.0], [7.5, 0.866]],
            [[8.0, 0.0], [7.5, -0.866]],
            // A wall's end at (3, 3), meeting nothing.
            [[3.0, 3.0], [4.0, 3.0]],
        ];
        let c = ConvexVertices::new(&segs, &[true; 9]);
        assert!(!c.is_convex([1.0, 0.0]), "pieces of one wall");
        assert!(c.is_convex([5.0, 0.0]), "a corner");
        assert!(!c.is_convex([8.0, 0.0]), "surrounded");
        assert!(c.is_convex([3.0, 3.0]), "a lone end");
        // A vertex nobody asked about is not pruned.
        assert!(c.is_convex([20.0, 20.0]));
        // Only the marked segments' ends are asked about; all segments count for them.
        let c = ConvexVertices::new(&segs, &[true, false, false, false, false, false, false, false, false]);
        assert!(!c.is_convex([1.0, 0.0]));
        assert!(c.is_convex([8.0, 0.0]), "not asked about");
    }
}
