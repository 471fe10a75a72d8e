//! The queue of [`CornerGraph::distance`](super::CornerGraph::distance)'s search: entries
//! taken smallest first, as a binary heap takes them, but only those at or below a cut are
//! kept in the heap; the others wait in a plain list until the heap runs dry, when the cut
//! rises past the smallest of them. A goal-directed search pushes many entries it never takes
//! (on aws_small_house about five for each it takes): they stay out of the heap, whose pushes
//! and pops are then cheaper.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// How the cut (m) rises when the heap runs dry: past the smallest waiting key `m` (and the
/// old cut) to `m * CUT_GROWTH + CUT_STEP`.
const CUT_GROWTH: f64 = 1.25;
/// See [`CUT_GROWTH`] (m).
const CUT_STEP: f64 = 0.5;

/// Entries `(key, tag)`, keys the bits of non-negative `f64`s (so that their order is the
/// numbers' order), taken smallest first: by key, then by tag.
#[derive(Debug, Default)]
pub(super) struct CutHeap {
    /// Entries at or below the cut, each packed as one number that orders as `(key, tag)`
    /// (one comparison instead of two).
    heap: BinaryHeap<Reverse<u128>>,
    /// The entries above the cut.
    over: Vec<(u64, u32)>,
    /// Entries with keys up to this (bits of an `f64`, m) are in the heap.
    cut: u64,
}

impl CutHeap {
    /// Empties the queue, sets the cut at `cut` (m) and puts `entries` in.
    pub fn reset(&mut self, cut: f64, entries: impl Iterator<Item = (u64, u32)>) {
        self.cut = cut.max(0.0).to_bits();
        self.over.clear();
        let mut below = std::mem::take(&mut self.heap).into_vec();
        below.clear();
        for e in entries {
            if e.0 <= self.cut {
                below.push(Reverse(pack(e)));
            } else {
                self.over.push(e);
            }
        }
        self.heap = BinaryHeap::from(below);
    }

    /// Adds an entry.
    #[inline]
    pub fn push(&mut self, e: (u64, u32)) {
        if e.0 <= self.cut {
            self.heap.push(Reverse(pack(e)));
        } else {
            self.over.push(e);
        }
    }

    /// Takes the smallest entry (by key, then tag), `None` when there is none.
    #[inline]
    pub fn pop(&mut self) -> Option<(u64, u32)> {
        loop {
            if let Some(Reverse(e)) = self.heap.pop() {
                return Some(((e >> 32) as u64, e as u32));
            }
            // Every entry left is above the cut: raise it past the smallest.
            let m = self.over.iter().map(|e| e.0).min()?;
            self.cut = (f64::from_bits(m.max(self.cut)) * CUT_GROWTH + CUT_STEP).to_bits().max(m);
            let mut i = 0;
            while i < self.over.len() {
                if self.over[i].0 <= self.cut {
                    self.heap.push(Reverse(pack(self.over.swap_remove(i))));
                } else {
                    i += 1;
                }
            }
        }
    }
}

/// An entry as one number that orders as `(key, tag)` does: the key above the tag.
#[inline(always)]
fn pack((key, tag): (u64, u32)) -> u128 {
    (key as u128) << 32 | tag as u128
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    #[test]
    fn pops_come_in_a_binary_heaps_order() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut q = CutHeap::default();
        for round in 0..200 {
            let key = |rng: &mut rand_chacha::ChaCha8Rng| rng.gen_range(0.0..20.0f64).to_bits();
            let start: Vec<(u64, u32)> = (0..rng.gen_range(0..50)).map(|_| (key(&mut rng), rng.gen_range(0..8))).collect();
            let mut want: BinaryHeap<Reverse<(u64, u32)>> = start.iter().copied().map(Reverse).collect();
            q.reset(rng.gen_range(0.0..5.0), start.into_iter());
            for _ in 0..300 {
                if rng.gen_bool(0.6) {
                    // Pushes at or above the last key taken, as a search with a consistent
                    // heuristic makes them, and some below.
                    let e = (key(&mut rng), rng.gen_range(0..8));
                    q.push(e);
                    want.push(Reverse(e));
                } else {
                    assert_eq!(q.pop(), want.pop().map(|Reverse(e)| e), "round {round}");
                }
            }
            while let Some(Reverse(e)) = want.pop() {
                assert_eq!(q.pop(), Some(e), "round {round}");
            }
            assert_eq!(q.pop(), None);
        }
    }
}
