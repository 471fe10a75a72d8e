//! How well a built map agrees with a reference map of the same place: how much of the
//! reference's free space it covers (all of it, and the part connected to where the robot
//! started, which is all a robot can see from inside closed walls), and how much of its own
//! free space the reference holds occupied. Cells are matched by their centres, so the maps may differ in extent, origin and
//! resolution (neither may be rotated).

use serde::{Deserialize, Serialize};
use xhab_types::{OccupancyGrid, Point2, GRID_FREE, GRID_OCCUPIED};

/// Agreement of a built map with a reference.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MapAgreement {
    /// Free cells of the reference.
    pub reference_free_cells: usize,
    /// Fraction of the reference's free cells that are free in the built map (0..1).
    pub free_coverage: f64,
    /// Free cells of the reference connected (8-connected, through free cells) to the start.
    pub connected_free_cells: usize,
    /// Fraction of those that are free in the built map (0..1).
    pub connected_free_coverage: f64,
    /// Free cells of the built map inside the reference's extent.
    pub built_free_cells: usize,
    /// Fraction of the built map's free cells inside the reference's extent that are occupied
    /// in the reference (0..1).
    pub free_occupied_in_reference: f64,
}

/// The value of `map` at point `p` (m), if inside.
fn at(map: &OccupancyGrid, p: Point2) -> Option<i8> {
    map.world_to_cell(p).map(|(c, r)| map.get(c, r))
}

/// The reference's free cells connected to the cell of `start` (m) through free cells.
fn connected_free(reference: &OccupancyGrid, start: Point2) -> Vec<bool> {
    let (w, h) = (reference.width, reference.height);
    let mut seen = vec![false; w * h];
    let Some((c, r)) = reference.world_to_cell(start) else { return seen };
    if reference.get(c, r) != GRID_FREE {
        return seen;
    }
    let mut stack = vec![r * w + c];
    seen[r * w + c] = true;
    while let Some(i) = stack.pop() {
        let (c, r) = ((i % w) as i64, (i / w) as i64);
        for dr in -1..=1 {
            for dc in -1..=1 {
                let (kc, kr) = (c + dc, r + dr);
                if kc < 0 || kr < 0 || kc >= w as i64 || kr >= h as i64 {
                    continue;
                }
                let k = kr as usize * w + kc as usize;
                if !seen[k] && reference.data[k] == GRID_FREE {
                    seen[k] = true;
                    stack.push(k);
                }
            }
        }
    }
    seen
}

/// Compares `built` with `reference`; `start` is where the robot that built it started (m).
pub fn map_agreement(built: &OccupancyGrid, reference: &OccupancyGrid, start: Point2) -> MapAgreement {
    let connected = connected_free(reference, start);
    let (mut ref_free, mut covered, mut conn, mut conn_covered) = (0usize, 0usize, 0usize, 0usize);
    for r in 0..reference.height {
        for c in 0..reference.width {
            if reference.get(c, r) == GRID_FREE {
                let hit = (at(built, reference.cell_center(c, r)) == Some(GRID_FREE)) as usize;
                ref_free += 1;
                covered += hit;
                if connected[r * reference.width + c] {
                    conn += 1;
                    conn_covered += hit;
                }
            }
        }
    }
    let (mut built_free, mut wrong) = (0usize, 0usize);
    for r in 0..built.height {
        for c in 0..built.width {
            if built.get(c, r) == GRID_FREE {
                if let Some(v) = at(reference, built.cell_center(c, r)) {
                    built_free += 1;
                    wrong += (v == GRID_OCCUPIED) as usize;
                }
            }
        }
    }
    MapAgreement {
        reference_free_cells: ref_free,
        free_coverage: covered as f64 / ref_free.max(1) as f64,
        connected_free_cells: conn,
        connected_free_coverage: conn_covered as f64 / conn.max(1) as f64,
        built_free_cells: built_free,
        free_occupied_in_reference: wrong as f64 / built_free.max(1) as f64,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_types::{Pose2, GRID_UNKNOWN};

    #[test]
    fn counts_coverage_and_false_free_cells() {
        let mut reference = OccupancyGrid::new(10, 10, 0.1, Pose2::default(), GRID_FREE);
        for c in 0..10 {
            reference.set(c, 9, GRID_OCCUPIED);
        }
        // Built at half the resolution, shifted so that no cell centre lies on an edge of the
        // other map: coarse cells 1..5 span 0.03..1.03 m.
        let mut built = OccupancyGrid::new(6, 6, 0.2, Pose2::new(-0.17, -0.17, 0.0), GRID_UNKNOWN);
        for r in 1..6 {
            for c in 1..6 {
                built.set(c, r, GRID_FREE);
            }
        }
        // A free cell outside the reference's extent counts for neither.
        built.set(0, 0, GRID_FREE);
        // Reference free: 90 cells (rows 0..8), all inside the built map's free cells.
        let start = Point2::new(0.5, 0.5);
        let a = map_agreement(&built, &reference, start);
        assert_eq!(a.reference_free_cells, 90);
        assert!((a.free_coverage - 1.0).abs() < 1e-12, "{a:?}");
        assert_eq!(a.built_free_cells, 25);
        // The top coarse row's centres (y = 0.93 m) lie on the reference's wall row: 5 of 25.
        assert!((a.free_occupied_in_reference - 5.0 / 25.0).abs() < 1e-12, "{a:?}");
        built.set(1, 1, GRID_OCCUPIED);
        let b = map_agreement(&built, &reference, start);
        assert!((b.free_coverage - 86.0 / 90.0).abs() < 1e-12, "{b:?}");
        assert_eq!((b.connected_free_cells, b.connected_free_coverage), (b.reference_free_cells, b.free_coverage));
        // A wall across the reference at x = 0.5 m cuts the right half off from the start.
        for r in 0..10 {
            reference.set(5, r, GRID_OCCUPIED);
        }
        let c = map_agreement(&built, &reference, Point2::new(0.25, 0.5));
        assert_eq!(c.connected_free_cells, 45);
        assert!((c.connected_free_coverage - 41.0 / 45.0).abs() < 1e-12, "{c:?}");
    }
}
