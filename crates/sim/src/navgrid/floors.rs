//! Floors: the heights at which a scene has large walkable surfaces.

use super::raster;
use super::AgentParams;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};

/// A floor of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Floor {
    /// Height of the walking surface (m, world z).
    pub z: f64,
    /// Walkable area near that height (m^2, projected).
    pub area: f64,
}

/// Height bin for the walkable-area histogram (m).
const BIN: f64 = 0.05;

/// Floors of `scene`, lowest first: clusters of walkable (slope <= max_slope) area whose
/// total is at least 25% of the largest cluster's and at least 1 m^2. Table tops and beds
/// form small clusters and are left out; a floor's height is the highest well-populated bin
/// of its cluster (the top of a floor slab, not its bottom face).
pub fn detect_floors(scene: &Scene, params: &AgentParams) -> Vec<Floor> {
    let cos_slope = params.max_slope_deg.to_radians().cos();
    let walkable = walkable_triangles(scene, cos_slope);
    // Summed in scene order, whatever the thread count.
    let mut hist: std::collections::BTreeMap<i64, f64> = Default::default();
    for &(bin, proj, _) in &walkable {
        *hist.entry(bin).or_default() += proj;
    }
    // Clusters: runs of bins no more than max_climb apart.
    let gap = (params.max_climb / BIN).ceil().max(1.0) as i64;
    let mut clusters: Vec<Vec<(i64, f64)>> = Vec::new();
    for (&b, &a) in &hist {
        match clusters.last_mut() {
            Some(c) if b - c.last().map(|x| x.0).unwrap_or(b) <= gap => c.push((b, a)),
            _ => clusters.push(vec![(b, a)]),
        }
    }
    // A staircase chains the bins of two storeys into one cluster (each tread is within
    // max_climb of the next): split such a cluster at its storeys' slabs.
    let clusters: Vec<Vec<(i64, f64)>> = clusters.into_iter().flat_map(|c| split_storeys(c, gap)).collect();
    let totals: Vec<f64> = clusters.iter().map(|c| c.iter().map(|x| x.1).sum()).collect();
    let largest = totals.iter().cloned().fold(0.0, f64::max);
    let mut floors = Vec::new();
    for (c, &total) in clusters.iter().zip(&totals) {
        if total < 1.0 || total < 0.25 * largest {
            continue;
        }
        let peak = c.iter().map(|x| x.1).fold(0.0, f64::max);
        let top = c.iter().rev().find(|x| x.1 >= 0.5 * peak).map(|x| x.0).unwrap_or(c[0].0);
        // The exact height: the area-weighted mean of triangle heights in that bin.
        floors.push(Floor { z: exact_height(&walkable, top), area: total });
    }
    floors
}

/// Splits a cluster of height bins that spans more than two climbs (a staircase or ramp
/// joining storeys) at its slabs: bins holding at least [`SLAB_SHARE`] of the cluster's
/// largest bin and at least 1 m^2, each with the bins within `gap` of it; the bins between
/// slabs (the treads) go with the nearer slab. A cluster within two climbs is kept whole, so
/// a single storey's floor is found as before.
fn split_storeys(c: Vec<(i64, f64)>, gap: i64) -> Vec<Vec<(i64, f64)>> {
    let (lo, hi) = (c[0].0, c[c.len() - 1].0);
    if hi - lo <= 2 * gap {
        return vec![c];
    }
    let peak = c.iter().map(|x| x.1).fold(0.0, f64::max);
    // Slab bins, largest first; a bin within 2 gaps of a chosen slab belongs to it.
    let mut order: Vec<&(i64, f64)> = c.iter().filter(|x| x.1 >= SLAB_SHARE * peak && x.1 >= 1.0).collect();
    order.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    let mut slabs: Vec<i64> = Vec::new();
    for x in order {
        if slabs.iter().all(|s| (s - x.0).abs() > 2 * gap) {
            slabs.push(x.0);
        }
    }
    if slabs.len() < 2 {
        return vec![c];
    }
    slabs.sort();
    let mut out: Vec<Vec<(i64, f64)>> = vec![Vec::new(); slabs.len()];
    for x in c {
        let k = (0..slabs.len()).min_by_key(|&k| ((slabs[k] - x.0).abs(), k)).unwrap_or(0);
        // Treads count towards a storey only near its slab: a flight's middle is no floor.
        if (slabs[k] - x.0).abs() <= gap {
            out[k].push(x);
        }
    }
    out
}

/// A bin holding at least this share of its cluster's largest bin may be a storey's slab.
const SLAB_SHARE: f64 = 0.25;

/// The walkable triangles of `scene` (slope within `cos_slope`), in scene order: each one's
/// height bin, projected area (m^2) and centre height (m). Worked out in parallel over chunks
/// of the meshes.
fn walkable_triangles(scene: &Scene, cos_slope: f64) -> Vec<(i64, f64, f64)> {
    use rayon::prelude::*;
    const CHUNK: usize = 4096;
    let chunks = scene.triangle_chunks(CHUNK);
    let parts: Vec<Vec<(i64, f64, f64)>> = chunks
        .par_iter()
        .map(|(m, range)| {
            range
                .clone()
                .filter_map(|ti| {
                    let t = scene.meshes[*m].triangle(ti).map(|p| p.map(|v| v as f64));
                    let nz = raster::abs_normal_z(&t)?;
                    if nz < cos_slope {
                        return None;
                    }
                    let (_, proj) = raster::areas(&t);
                    let zc = (t[0][2] + t[1][2] + t[2][2]) / 3.0;
                    Some(((zc / BIN).round() as i64, proj, zc))
                })
                .collect()
        })
        .collect();
    parts.concat()
}

/// The exact height of a floor whose top bin is `bin`: the area-weighted mean of the centre
/// heights of the walkable triangles in that bin (m).
fn exact_height(walkable: &[(i64, f64, f64)], bin: i64) -> f64 {
    let (mut sa, mut sz) = (0.0, 0.0);
    for &(b, a, zc) in walkable {
        if b == bin {
            sa += a;
            sz += a * zc;
        }
    }
    if sa > 0.0 {
        sz / sa
    } else {
        bin as f64 * BIN
    }
}
