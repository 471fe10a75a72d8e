//! Layered costmap tests: a global costmap from a map, a rolling local one with scans.

use super::*;
use xhab_types::{LaserScan, OccupancyGrid, Point2, Pose2};

/// A 5 x 5 m room at 0.05 m with a one-cell wall at x = 2.5 m for y < 3.75 m.
fn room() -> OccupancyGrid {
    let mut m = OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0);
    for r in 0..75 {
        m.set(50, r, 100);
    }
    m.set(10, 90, -1);
    m
}

fn params(rolling: bool) -> CostmapParams {
    CostmapParams {
        robot_radius: 0.1,
        footprint_padding: 0.0,
        rolling_window: rolling,
        width: 2.0,
        height: 2.0,
        ..Default::default()
    }
}

#[test]
fn global_costmap_takes_the_map_geometry_and_inflates_it() {
    let mut cm = LayeredCostmap::new(params(false)).unwrap();
    cm.set_map(&room());
    cm.update(Pose2::new(1.0, 1.0, 0.0));
    let m = cm.costmap();
    assert_eq!((m.size_x(), m.size_y(), m.resolution()), (100, 100, 0.05));
    assert_eq!(m.cost(50, 10), LETHAL);
    assert_eq!(m.cost(48, 10), INSCRIBED);
    assert_eq!(m.cost(46, 10), 92); // 0.2 m: 252 * exp(-1)
    assert_eq!(m.cost(50, 90), FREE);
    assert_eq!(
        m.cost(10, 90),
        UNKNOWN,
        "the static layer tracks unknown space by default"
    );
    // Published as an OccupancyGrid the ROS way.
    let g = m.to_occupancy_grid();
    assert_eq!(g.get(50, 10), 100);
    assert_eq!(g.get(48, 10), 99);
}

#[test]
fn rolling_local_costmap_follows_the_robot_and_sees_scans() {
    let mut cm = LayeredCostmap::new(params(true)).unwrap();
    cm.set_map(&room());
    let robot = Pose2::new(1.0, 4.2, 0.0);
    // An unmapped box 0.6 m ahead, seen by a 3-beam scan.
    let scan = LaserScan {
        angle_min: -0.05,
        angle_max: 0.05,
        angle_increment: 0.05,
        range_min: 0.1,
        range_max: 5.0,
        ranges: vec![0.6; 3],
    };
    cm.add_scan(&scan, robot);
    cm.update(robot);
    let m = cm.costmap();
    assert_eq!((m.size_x(), m.size_y()), (40, 40));
    assert!(
        (m.origin().x - 0.0).abs() < 1e-9 && (m.origin().y - 3.2).abs() < 1e-9,
        "{:?}",
        m.origin()
    );
    assert_eq!(m.cost_at(Point2::new(1.61, 4.2)), Some(LETHAL));
    assert_eq!(m.cost_at(Point2::new(1.52, 4.2)), Some(INSCRIBED));
    assert_eq!(m.cost_at(Point2::new(0.95, 4.2)), Some(FREE));
    // Move 1.5 m right: the window now shows the wall's end from the static map, and the mark.
    let robot = Pose2::new(2.5, 4.2, 0.0);
    cm.update(robot);
    let m = cm.costmap();
    assert_eq!(m.cost_at(Point2::new(2.51, 3.7)), Some(LETHAL));
    assert_eq!(m.cost_at(Point2::new(1.61, 4.2)), Some(LETHAL));
    // Clearing recovery: marks farther than 0.5 m go; the static wall stays.
    cm.clear_obstacles_outside(robot.position(), 1.0);
    cm.update(robot);
    let m = cm.costmap();
    assert_eq!(m.cost_at(Point2::new(1.61, 4.2)), Some(FREE));
    assert_eq!(m.cost_at(Point2::new(2.51, 3.7)), Some(LETHAL));
    cm.reset_layers();
    cm.update(robot);
    assert_eq!(
        cm.costmap().cost_at(Point2::new(2.51, 3.7)),
        Some(LETHAL),
        "reset keeps the static map"
    );
}

#[test]
fn bad_parameters_are_named() {
    let e = LayeredCostmap::new(CostmapParams {
        inflation_layer: InflationLayerParams {
            inflation_radius: -0.2,
            ..Default::default()
        },
        ..Default::default()
    })
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "inflation_layer.inflation_radius: must be in [0, 50], got -0.2"
    );
    let e = LayeredCostmap::new(CostmapParams {
        plugins: vec![PluginSpec::new("x", "foo::Bar")],
        ..Default::default()
    })
    .unwrap_err();
    assert!(e.to_string().starts_with("plugins[0].type"), "{e}");
}
