//! The walls that one point's line-of-sight tests have run into, so that later tests from the
//! same point settle without a walk the segments that must cross one.
//!
//! [`segment_verdict`] says which cell stopped a blocked segment when that cell fails every
//! segment through it (its block margin exceeds the tolerance, see
//! [`block_margins`](crate::geodesic::block_margins)). Such cells line up along walls:
//! [`Walls::add`] follows the row and the column through the cell as far as their cells fail
//! every segment too, and keeps the longer run. A segment whose ends lie on either side of a
//! run's row, clear of it, and which crosses the row's middle line strictly between the run's
//! ends, crosses the inside of one of the run's cells; the test's walk visits every cell whose
//! inside the segment crosses, so it would have failed there: the segment is blocked, the
//! answer the test gives. (Likewise for a run along a column.)
//!
//! [`segment_verdict`]: crate::geodesic::segment_verdict

use crate::navgrid::NavGrid;

/// Runs kept per point (the latest replace the oldest).
const KEPT: usize = 8;

/// Most cells a run is followed from the cell that stopped a test, each way.
const REACH: usize = 64;

/// How far (cells) a crossing must lie inside a run's ends, and an end point outside its row
/// or column, so that rounding cannot move it to the other side.
const MARGIN: f64 = 1e-3;

/// A straight run of cells that fail every segment: along row `line` (or column `line`), the
/// columns (or rows) from `lo` to `hi`, in cells from the grid's origin.
#[derive(Clone, Copy, Debug)]
struct Run {
    along_row: bool,
    line: f64,
    lo: f64,
    hi: f64,
}

/// The runs found from one point at one line-of-sight tolerance ([`Walls::clear`] before
/// another).
#[derive(Debug, Default)]
pub(crate) struct Walls {
    runs: Vec<Run>,
    next: usize,
}

impl Walls {
    /// Forgets every run.
    pub fn clear(&mut self) {
        self.runs.clear();
        self.next = 0;
    }

    /// Adds the longer of the row and the column runs through cell `i`, which fails every
    /// segment through it at tolerance `eps` (m), as do the run's other cells.
    pub fn add(&mut self, grid: &NavGrid, i: usize, eps: f64) {
        let (w, h) = grid.size();
        let blocks = |c: usize, r: usize| grid.block_margin[r * w + c] as f64 > eps;
        let (c, r) = (i % w, i / w);
        // The cells from `at` each way (up to `max`, not included) while `on` holds.
        let span = |at: usize, max: usize, on: &dyn Fn(usize) -> bool| {
            let (mut lo, mut hi) = (at, at);
            while lo > 0 && at - lo < REACH && on(lo - 1) {
                lo -= 1;
            }
            while hi + 1 < max && hi - at < REACH && on(hi + 1) {
                hi += 1;
            }
            (lo, hi)
        };
        let (c0, c1) = span(c, w, &|x| blocks(x, r));
        let (r0, r1) = span(r, h, &|y| blocks(c, y));
        let run = if c1 - c0 >= r1 - r0 {
            Run { along_row: true, line: r as f64, lo: c0 as f64, hi: (c1 + 1) as f64 }
        } else {
            Run { along_row: false, line: c as f64, lo: r0 as f64, hi: (r1 + 1) as f64 }
        };
        if self.runs.len() < KEPT {
            self.runs.push(run);
        } else {
            self.runs[self.next] = run;
            self.next = (self.next + 1) % KEPT;
        }
    }

    /// Whether the segment from `a` to `b` (m) crosses a kept run as the module says: then it
    /// is blocked at the tolerance the runs were found at.
    pub fn hide(&self, grid: &NavGrid, a: [f64; 2], b: [f64; 2]) -> bool {
        if self.runs.is_empty() {
            return false;
        }
        let (o, res) = (grid.origin(), grid.resolution());
        let fa = [(a[0] - o.x) / res, (a[1] - o.y) / res];
        let fb = [(b[0] - o.x) / res, (b[1] - o.y) / res];
        self.runs.iter().any(|run| {
            // The coordinates across the run's row (or column) and along it.
            let (across, along) = if run.along_row { (1, 0) } else { (0, 1) };
            let (lo, hi) = (run.line - MARGIN, run.line + 1.0 + MARGIN);
            if !((fa[across] < lo && fb[across] > hi) || (fb[across] < lo && fa[across] > hi)) {
                return false;
            }
            // Where the segment crosses the middle line, along the run.
            let mid = run.line + 0.5;
            let at = fa[along] + (mid - fa[across]) * (fb[along] - fa[along]) / (fb[across] - fa[across]);
            at > run.lo + MARGIN && at < run.hi - MARGIN
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesic::{segment_clear, segment_verdict, Verdict, LOS_EPS};
    use crate::scene::house::default_house;
    use crate::scene::stair_building::{stair_building, StairBuildingParams};
    use crate::world::World;
    use rand::SeedableRng;

    #[test]
    fn a_segment_the_walls_hide_is_one_the_test_blocks() {
        let mut hidden = 0;
        // Two houses and a storey with stairs (whose cells count obstacles by height band).
        for scene in [default_house(3), default_house(8), stair_building(&StairBuildingParams::default())] {
            let world = World::new(scene, Default::default());
            let grid = world.grid(0).expect("a grid");
            let cells = grid.cells_on_islands(0.0);
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
            let mut point = || grid.sample_navigable_point(&cells, &mut rng).expect("a point").xy();
            let mut walls = Walls::default();
            for _ in 0..40 {
                let p = point();
                // The graph's tolerance, and a wider one (a query's end standing inside the
                // radius), whose cells that fail every segment are fewer.
                for eps in [LOS_EPS, 0.02] {
                    walls.clear();
                    for _ in 0..250 {
                        let q = point();
                        let (p2, q2) = ([p.x, p.y], [q.x, q.y]);
                        if walls.hide(&grid, p2, q2) {
                            hidden += 1;
                            assert!(!segment_clear(&grid, p2, q2, eps), "{p2:?} -> {q2:?} at {eps}: hidden but clear");
                            continue;
                        }
                        match segment_verdict(&grid, p2, q2, eps) {
                            Verdict::BlockedAt(i) => {
                                assert!(grid.block_margin[i] as f64 > eps);
                                walls.add(&grid, i, eps);
                            }
                            v => assert_eq!(v == Verdict::Clear, segment_clear(&grid, p2, q2, eps)),
                        }
                    }
                }
            }
        }
        // The walls settle a good share of the tests (else this checks nothing).
        assert!(hidden > 5000, "{hidden}");
    }
}
