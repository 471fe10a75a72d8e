//! The map a planar laser sees: scene geometry crossing a thin horizontal band (the scan
//! plane), on the navigation grid's cells.
//!
//! A floor's [`NavGrid::occupancy_grid`] marks everything in the agent's body band, so a
//! table is a solid block; a lidar 0.2 m above the floor sees only its legs. Localising that
//! lidar against the body-band map weighs every beam that passes under a table top as a
//! miss. A SLAM map built with the robot's own lidar has the legs only: this is that map,
//! made from the geometry.

use super::{raster, NavGrid};
use crate::scene::Scene;
use xhab_types::{OccupancyGrid, GRID_OCCUPIED, GRID_UNKNOWN};

impl NavGrid {
    /// The map of what a planar laser at `height` above the floor sees (m), cells of this grid:
    /// occupied where geometry crosses `[height - half_band, height + half_band]`, unknown
    /// where the body-band map is occupied but the scan plane is clear (under a table top:
    /// not a place to stand, not a place the laser returns from), as the body-band map
    /// elsewhere (free on walkable floor, unknown off the floor).
    pub fn slice_map(&self, scene: &Scene, height: f64, half_band: f64) -> OccupancyGrid {
        let spec = self.spec;
        let (lo, hi) = (self.floor_z + height - half_band, self.floor_z + height + half_band);
        let mut hit = vec![false; spec.w * spec.h];
        for t in scene.triangles() {
            let t = t.map(|p| p.map(|v| v as f64));
            let zlo = t[0][2].min(t[1][2]).min(t[2][2]);
            let zhi = t[0][2].max(t[1][2]).max(t[2][2]);
            if zhi < lo || zlo > hi {
                continue;
            }
            raster::for_each_cell(&spec, &t, |c, r, a, b| {
                if b >= lo && a <= hi {
                    hit[r * spec.w + c] = true;
                }
            });
        }
        let mut g = self.occupancy_grid();
        for (i, v) in g.data.iter_mut().enumerate() {
            *v = if hit[i] {
                GRID_OCCUPIED
            } else if self.occupied[i] {
                GRID_UNKNOWN
            } else {
                *v
            };
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use crate::navgrid::{AgentParams, NavGrid};
    use crate::scene::Scene;
    use xhab_types::{Point2, GRID_FREE, GRID_OCCUPIED, GRID_UNKNOWN};

    #[test]
    fn a_table_is_a_block_in_the_body_band_and_four_legs_in_the_scan_plane() {
        let mut s = Scene::default();
        s.add_box("floor", [-1.0, -1.0, -0.05], [5.0, 5.0, 0.0], [0.5; 4]);
        // A 1 x 1 m table top at 0.7-0.75 m on four 3 cm legs, each inside one cell.
        s.add_box("top", [1.0, 1.0, 0.7], [2.0, 2.0, 0.75], [0.5; 4]);
        for (x, y) in [(1.0, 1.0), (1.95, 1.0), (1.0, 1.95), (1.95, 1.95)] {
            s.add_box("leg", [x + 0.01, y + 0.01, 0.0], [x + 0.04, y + 0.04, 0.7], [0.5; 4]);
        }
        let g = NavGrid::build(&s, &AgentParams::default(), 0.0).unwrap();
        let body = g.occupancy_grid();
        let laser = g.slice_map(&s, 0.2, 0.025);
        let at = |m: &xhab_types::OccupancyGrid, x: f64, y: f64| {
            let (c, r) = m.world_to_cell(Point2::new(x, y)).unwrap();
            m.get(c, r)
        };
        assert_eq!(at(&body, 1.5, 1.5), GRID_OCCUPIED);
        assert_eq!(at(&laser, 1.5, 1.5), GRID_UNKNOWN);
        assert_eq!(at(&laser, 1.025, 1.025), GRID_OCCUPIED);
        assert_eq!(at(&laser, 1.975, 1.975), GRID_OCCUPIED);
        assert_eq!(at(&laser, 3.5, 3.5), GRID_FREE);
        let occ = laser.data.iter().filter(|&&v| v == GRID_OCCUPIED).count();
        assert_eq!(occ, 4, "one cell per leg");
    }
}
