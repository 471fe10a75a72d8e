//! Buildings with storeys and stairs: floors, storey grids joined by their flights.

use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::stair_building::{stair_building, StairBuildingParams};
use xhab_sim::world::World;
use xhab_types::Point2;

#[test]
fn the_stair_building_has_two_storeys_whose_grids_share_the_flight() {
    let p = StairBuildingParams::default();
    let world = World::new(stair_building(&p), AgentParams::default());
    let z: Vec<f64> = world.floors.iter().map(|f| f.z).collect();
    assert_eq!(z.len(), 2, "floors {:?}", world.floors);
    assert!(z[0].abs() < 1e-6 && (z[1] - p.storey_height).abs() < 1e-6, "{z:?}");
    let (g0, g1) = (world.grid(0).unwrap(), world.grid(1).unwrap());
    let yc = 0.55;
    // The middle of the flight is navigable from both storeys; the floor under the upper
    // storey only from the lower.
    let mid = Point2::new(p.stair_x + 7.5 * p.tread, yc);
    assert!(g0.is_navigable(mid) && g1.is_navigable(mid));
    assert!(g0.is_navigable(Point2::new(1.0, 2.0)));
    assert!(g1.is_navigable(Point2::new(1.0, 2.0)));
    // One island per storey reaches the flight.
    assert_eq!(g0.island_at(Point2::new(1.0, 2.0)), g0.island_at(mid));
    assert_eq!(g1.island_at(Point2::new(9.0, 2.0)), g1.island_at(mid));
    for (k, g) in [&g0, &g1].iter().enumerate() {
        eprintln!("storey {k}: {} navigable cells, {} islands", g.navigable_cells(), g.islands.len());
    }
}

#[test]
fn dump_stair_profile() {
    let p = StairBuildingParams::default();
    let world = World::new(stair_building(&p), AgentParams::default());
    for k in 0..2 {
        let g = world.grid(k).unwrap();
        let mut line = String::new();
        for i in 0..100 {
            let x = 2.0 + i as f64 * 0.07;
            let q = Point2::new(x, 0.55);
            line += &format!("{:.2}:{}{} ", g.ground_at(q).unwrap_or(f64::NAN), if g.is_navigable(q) { "N" } else { "-" }, if g.on_stairs(q) { "s" } else { "" });
        }
        eprintln!("storey {k}: {line}");
        let mut line = String::new();
        for i in 0..40 {
            let y = 0.0 + i as f64 * 0.1;
            let q = Point2::new(5.1, y);
            line += &format!("{:.2}:{} ", g.ground_at(q).unwrap_or(f64::NAN), if g.is_navigable(q) { "N" } else { "-" });
        }
        eprintln!("storey {k} across: {line}");
    }
}
