//! Our map of aws_small_house.glb against the original project's SLAM map of the same house:
//! at least 95% of the SLAM map's occupied cells lie within 0.10 m of an occupied cell of ours,
//! aligned by the glTF/ROS frame convention alone (no fitting).

use crate::common::data_dir;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::world::World;
use xhab_types::{OccupancyGrid, GRID_OCCUPIED};

/// Fraction of `reference`'s occupied cells within `tol` (m) of an occupied cell of `ours`.
fn coverage(reference: &OccupancyGrid, ours: &OccupancyGrid, tol: f64) -> (f64, usize) {
    let reach = (tol / ours.resolution).ceil() as i64 + 1;
    let (mut hit, mut total) = (0usize, 0usize);
    for row in 0..reference.height {
        for col in 0..reference.width {
            if reference.get(col, row) != GRID_OCCUPIED {
                continue;
            }
            total += 1;
            let p = reference.cell_center(col, row);
            let c = ((p.x - ours.origin.x) / ours.resolution).floor() as i64;
            let r = ((p.y - ours.origin.y) / ours.resolution).floor() as i64;
            let mut found = false;
            'search: for dr in -reach..=reach {
                for dc in -reach..=reach {
                    let (cc, rr) = (c + dc, r + dr);
                    if cc < 0 || rr < 0 || cc >= ours.width as i64 || rr >= ours.height as i64 {
                        continue;
                    }
                    if ours.get(cc as usize, rr as usize) == GRID_OCCUPIED {
                        let q = ours.cell_center(cc as usize, rr as usize);
                        // Centre to centre: the strict reading of "within 0.10 m".
                        if p.dist(q) <= tol + 1e-9 {
                            found = true;
                            break 'search;
                        }
                    }
                }
            }
            hit += found as usize;
        }
    }
    (hit as f64 / total.max(1) as f64, total)
}

#[test]
fn aws_small_house_map_matches_the_slam_map() {
    let Some(data) = data_dir("aws_small_house_map_matches_the_slam_map") else { return };
    let (slam, _) = xhab_nav::map_server::load_map(&data.join("maps/aws_small_house.yaml")).expect("SLAM map loads");
    let scene = load(&data.join("scenes/aws_small_house.glb"), &LoadOptions::default()).expect("scene loads");
    let world = World::new(scene, AgentParams::default());
    let grid = world.grid(world.default_floor().expect("a floor")).expect("grid");
    let ours = grid.occupancy_grid();
    let (frac, n) = coverage(&slam, &ours, 0.10);
    eprintln!("aws_small_house: {:.2}% of {n} SLAM occupied cells within 0.10 m of ours", frac * 100.0);
    assert!(frac >= 0.95, "only {:.2}% of the SLAM map's occupied cells are matched", frac * 100.0);
}
