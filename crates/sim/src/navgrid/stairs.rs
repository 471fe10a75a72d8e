//! Stairs: the walkable surfaces outside a storey's floor window that join it to the storey
//! above or below, found by flooding from the floor in steps of at most `max_climb`.
//!
//! A storey's grid holds one walking surface per cell. On the floor that is the floor (within
//! `max_climb` of its height, as on a single-storey scene); on a staircase it is the tread the
//! flood reached, up to one climb short of the next storey's floor, so the middle of a flight
//! belongs to both storeys' grids (that overlap is where a path changes grid). A tread above
//! a floor cell wins when the agent has no headroom on the floor there (under the flight).
//! Raised surfaces that lead to no other storey (a stage, a bed) are left out, so a scene
//! without stairs gets exactly its single-storey grid.

use super::raster::{self, GridSpec};
use super::AgentParams;
use crate::scene::Scene;

/// The heights of the neighbouring storeys' floors (m), `None` at the top or bottom.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StoreyBounds {
    /// Floor height of the storey below (m).
    pub below: Option<f64>,
    /// Floor height of the storey above (m).
    pub above: Option<f64>,
}

/// A storey's walking surface with its stairs.
pub(crate) struct StairGround {
    /// Walking surface height per cell (m), NaN where there is none.
    pub ground: Vec<f32>,
    /// True on stair cells (surfaces outside the floor's window, or treads that replaced a
    /// floor without headroom).
    pub stair: Vec<bool>,
}

/// A candidate walking surface of one cell: its height (m), whether geometry stands in the
/// agent's body band above it, and the lowest geometry above the band's foot (height, and
/// whether it faces up: then the surface is inside a closed solid, under a step's top).
#[derive(Clone, Copy)]
struct Surface {
    z: f32,
    blocked: bool,
    above: (f32, bool),
}

impl Surface {
    fn new(z: f32) -> Surface {
        Surface { z, blocked: false, above: (f32::INFINITY, false) }
    }
    /// Records a piece of geometry from `a` to `b` (m) in this cell's column.
    fn see(&mut self, a: f64, b: f64, faces_up: bool, p: &AgentParams) {
        let z = self.z as f64;
        if b > z + p.max_climb && a < z + p.height {
            self.blocked = true;
        }
        if a > z + p.max_climb && (a as f32) < self.above.0 {
            self.above = (a as f32, faces_up);
        }
    }
    /// Whether the agent can stand here: nothing in its body band, not inside a solid.
    fn clear(&self) -> bool {
        !self.blocked && !self.above.1
    }
}

/// Finds the stairs of the storey at `floor_z` and its walking surface with them (the floor
/// by the single-storey rule, faces on cell boundaries left out). `None` when no flight joins
/// another storey.
pub(crate) fn find(scene: &Scene, p: &AgentParams, spec: &GridSpec, floor_z: f64, bounds: StoreyBounds) -> Option<StairGround> {
    if bounds.below.is_none() && bounds.above.is_none() {
        return None;
    }
    let climb = p.max_climb;
    // The storey's window: above the floor below's window, below the floor above's.
    let lo = bounds.below.map_or(f64::NEG_INFINITY, |z| z + climb);
    let hi = bounds.above.map_or(f64::INFINITY, |z| z - climb);
    let (flo, fhi) = (floor_z - climb, floor_z + climb);
    let cos_slope = p.max_slope_deg.to_radians().cos();
    let n = spec.w * spec.h;
    // On a storey with stairs a face on a cell's boundary is ground (or headroom) for neither
    // cell: a tread's edge must not lend its height to the cell beside the flight.
    const INSET: f64 = 1e-6;

    // Candidate surfaces per cell outside the floor's window, merged within a climb (the
    // highest wins, as on the floor).
    let mut pieces: Vec<(u32, f32)> = Vec::new();
    let mut slab_in = vec![f32::NAN; n];
    for t in scene.triangles() {
        let t = t.map(|q| q.map(|v| v as f64));
        let zlo = t[0][2].min(t[1][2]).min(t[2][2]);
        let zhi = t[0][2].max(t[1][2]).max(t[2][2]);
        if zhi < lo || zlo >= hi {
            continue;
        }
        match raster::abs_normal_z(&t) {
            Some(nz) if nz >= cos_slope => {}
            _ => continue,
        }
        raster::for_each_cell_inset(spec, &t, INSET, |c, r, l, h| {
            let i = (r * spec.w + c) as u32;
            if h >= lo && h < hi && !(h >= flo && h <= fhi) {
                pieces.push((i, h as f32));
            }
            // The floor's own surface, by the same rule (the highest within its window).
            if h >= flo && l <= fhi {
                let g = h.min(fhi) as f32;
                let s = &mut slab_in[i as usize];
                if s.is_nan() || g > *s {
                    *s = g;
                }
            }
        });
    }
    if pieces.is_empty() {
        return None;
    }
    pieces.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    // CSR of merged surfaces per cell.
    let mut start = vec![0u32; n + 1];
    let mut surf: Vec<Surface> = Vec::new();
    let mut k = 0;
    for cell in 0..n {
        start[cell] = surf.len() as u32;
        let first = surf.len();
        while k < pieces.len() && pieces[k].0 as usize == cell {
            let z = pieces[k].1;
            let len = surf.len();
            match surf.last_mut() {
                Some(s) if len > first && (z - s.z) as f64 <= climb => s.z = z,
                _ => surf.push(Surface::new(z)),
            }
            k += 1;
        }
    }
    start[n] = surf.len() as u32;
    // Headroom: no geometry between a climb above a surface and the agent's height above it.
    // The floor's own cells get the same test, so a flight can take over a floor cell under it.
    let slab = &slab_in;
    let mut floor: Vec<Option<Surface>> = slab.iter().map(|g| g.is_finite().then(|| Surface::new(*g))).collect();
    for t in scene.triangles() {
        let t = t.map(|q| q.map(|v| v as f64));
        let zhi = t[0][2].max(t[1][2]).max(t[2][2]);
        if zhi <= lo.min(flo) + climb {
            continue;
        }
        let faces_up = raster::normal_z_sign(&t) > 0.0;
        raster::for_each_cell_inset(spec, &t, INSET, |c, r, a, b| {
            let i = r * spec.w + c;
            if let Some(s) = &mut floor[i] {
                s.see(a, b, faces_up, p);
            }
            for s in &mut surf[start[i] as usize..start[i + 1] as usize] {
                s.see(a, b, faces_up, p);
            }
        });
    }
    let slab_clear: Vec<bool> = floor.iter().map(|s| s.is_some_and(|s| s.clear())).collect();
    // Flood from the floor's cells with headroom, over surfaces with headroom, one climb a step.
    let mut ground = slab.to_vec();
    let mut stair = vec![false; n];
    let mut queue: std::collections::VecDeque<usize> = (0..n).filter(|&i| slab_clear[i]).collect();
    let (w, h) = (spec.w, spec.h);
    while let Some(i) = queue.pop_front() {
        let g = ground[i] as f64;
        let (c, r) = (i % w, i / w);
        let mut next = [usize::MAX; 4];
        if c > 0 {
            next[0] = i - 1;
        }
        if c + 1 < w {
            next[1] = i + 1;
        }
        if r > 0 {
            next[2] = i - w;
        }
        if r + 1 < h {
            next[3] = i + w;
        }
        for j in next {
            if j == usize::MAX || stair[j] || slab_clear[j] {
                continue;
            }
            let best = surf[start[j] as usize..start[j + 1] as usize]
                .iter()
                .filter(|s| s.clear() && (s.z as f64 - g).abs() <= climb)
                .min_by(|a, b| (a.z as f64 - g).abs().total_cmp(&(b.z as f64 - g).abs()));
            if let Some(s) = best {
                ground[j] = s.z;
                stair[j] = true;
                queue.push_back(j);
            }
        }
    }
    // Keep the flights that reach another storey: a component of stair cells whose top is
    // within two climbs of the floor above, or whose bottom is within two of the floor below.
    let (labels, sizes) = super::components_where(&stair, w, h, |i, j| (ground[j] - ground[i]).abs() as f64 <= climb);
    let count = sizes.len();
    let mut reach = vec![false; count];
    for i in 0..n {
        if labels[i] == u32::MAX {
            continue;
        }
        let z = ground[i] as f64;
        let up = bounds.above.is_some_and(|a| z >= a - 2.0 * climb);
        let down = bounds.below.is_some_and(|b| z <= b + 2.0 * climb);
        if up || down {
            reach[labels[i] as usize] = true;
        }
    }
    let mut any = false;
    for i in 0..n {
        if labels[i] == u32::MAX {
            continue;
        }
        if reach[labels[i] as usize] {
            any = true;
        } else {
            stair[i] = false;
            ground[i] = slab[i];
        }
    }
    any.then_some(StairGround { ground, stair })
}
