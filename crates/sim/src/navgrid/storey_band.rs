//! Occupancy and clearance on a storey with stairs: every cell's body band stands on its own
//! ground (a tread's, the floor's), not on the floor's height, and a drop of more than a climb
//! between neighbouring cells is an edge for the cells above it.

use super::band_edges;
use super::clearance::{self, Seg};
use super::raster::{self, GridSpec};
use super::AgentParams;
use crate::scene::Scene;

/// What [`clearance`] works out.
pub(super) struct Banded {
    /// Obstacle segments (m), each of which counts only for cells whose band its piece reaches.
    pub segments: Vec<Seg>,
    /// Distance from each cell centre to its nearest counting segment (m, capped).
    pub clear: Vec<f32>,
    /// That segment's index per cell (`u32::MAX`: none within the cap).
    pub nearest: Vec<u32>,
    /// Cells at the foot of a drop: lower than a neighbour by more than a climb.
    pub drops: Vec<usize>,
}

/// Occupancy (into `occupied`, with closed solids filled by the roofs in `roof`), obstacle
/// segments and their distances for the storey at `floor_z` (m) whose cells stand on `ground`
/// (m, NaN where none; such cells get the floor's band). Sloped faces are cut into
/// [`band_edges::SLICE`] slices so a cell sees only the part within its own band (to a slice).
#[allow(clippy::too_many_arguments)]
pub(super) fn clearance(
    scene: &Scene,
    params: &AgentParams,
    spec: &GridSpec,
    floor_z: f64,
    ground: &[f32],
    occupied: &mut [bool],
    roof: &mut [(f32, bool)],
    cap: f64,
) -> Banded {
    let band = |i: usize| {
        let g = if ground[i].is_finite() { ground[i] as f64 } else { floor_z };
        (g + params.max_climb, g + params.height)
    };
    let (gmin, gmax) = ground.iter().filter(|g| g.is_finite()).fold((floor_z, floor_z), |(a, b), &g| (a.min(g as f64), b.max(g as f64)));
    let (wide_lo, wide_hi) = (gmin + params.max_climb, gmax + params.height);
    occupied.iter_mut().for_each(|o| *o = false);
    roof.iter_mut().for_each(|r| *r = (f32::INFINITY, false));
    let mut banded = Vec::new();
    for t in scene.triangles() {
        let t = t.map(|p| p.map(|v| v as f64));
        let zlo = t[0][2].min(t[1][2]).min(t[2][2]);
        let zhi = t[0][2].max(t[1][2]).max(t[2][2]);
        if zhi <= wide_lo && zhi < gmin - params.max_climb {
            continue;
        }
        let faces_up = raster::normal_z_sign(&t) > 0.0;
        raster::for_each_cell(spec, &t, |c, r, lo, hi| {
            let i = r * spec.w + c;
            let (blo, bhi) = band(i);
            if lo >= bhi && (lo as f32) < roof[i].0 {
                roof[i] = (lo as f32, faces_up);
            }
            if hi > blo && lo < bhi {
                occupied[i] = true;
            }
        });
        if zhi > wide_lo && zlo < wide_hi {
            band_edges::band_segments_sliced(&t, wide_lo, wide_hi, &mut banded);
        }
    }
    super::fill_enclosed(occupied, ground, roof, spec);
    // A canonical order, duplicates (shared mesh edges at the same heights) once.
    banded.sort_by(|a, b| {
        let k = |s: &(Seg, [f32; 2])| [s.0[0][0], s.0[0][1], s.0[1][0], s.0[1][1], s.1[0] as f64, s.1[1] as f64];
        let (ka, kb) = (k(a), k(b));
        ka.iter().zip(&kb).map(|(x, y)| x.total_cmp(y)).find(|o| o.is_ne()).unwrap_or(std::cmp::Ordering::Equal)
    });
    banded.dedup();
    let segments: Vec<Seg> = banded.iter().map(|s| s.0).collect();
    let heights: Vec<[f32; 2]> = banded.iter().map(|s| s.1).collect();
    let (clear, nearest) = clearance::segment_distance_where(spec, &segments, cap, &[], |k, i| {
        let (blo, bhi) = band(i);
        heights[k][1] as f64 > blo && (heights[k][0] as f64) < bhi
    });
    let (w, h) = (spec.w, spec.h);
    let mut drops = Vec::new();
    for i in 0..w * h {
        if ground[i].is_nan() {
            continue;
        }
        let (c, r) = (i % w, i / w);
        let higher = |j: usize| ground[j].is_finite() && (ground[j] - ground[i]) as f64 > params.max_climb;
        if (c > 0 && higher(i - 1)) || (c + 1 < w && higher(i + 1)) || (r > 0 && higher(i - w)) || (r + 1 < h && higher(i + w)) {
            drops.push(i);
        }
    }
    Banded { segments, clear, nearest, drops }
}

/// Makes each drop in `drops` an edge for the cells within `cap` (m) above it by more than
/// `climb` (m): their clearance is at most the distance to the lower cell's near side (below a
/// drop, its riser is geometry already).
pub(super) fn apply_drops(clear: &mut [f32], nearest: &mut [u32], ground: &[f32], drops: &[usize], spec: &GridSpec, cap: f64, climb: f64) {
    let (w, h, res) = (spec.w as isize, spec.h as isize, spec.res);
    let reach = (cap / res).ceil() as isize;
    for &m in drops {
        let (mc, mr) = ((m % spec.w) as isize, (m / spec.w) as isize);
        for dr in -reach..=reach {
            for dc in -reach..=reach {
                let (c, r) = (mc + dc, mr + dr);
                if c < 0 || r < 0 || c >= w || r >= h {
                    continue;
                }
                let i = (r * w + c) as usize;
                if !(ground[i].is_finite() && (ground[i] - ground[m]) as f64 > climb) {
                    continue;
                }
                let e = ((((dc * dc + dr * dr) as f64).sqrt() - 0.5) * res).max(0.0) as f32;
                if e < clear[i] {
                    clear[i] = e;
                    nearest[i] = u32::MAX;
                }
            }
        }
    }
}
