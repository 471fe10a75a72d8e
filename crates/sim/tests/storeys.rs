//! Buildings with storeys and stairs: floors, storey grids joined by their flights.

use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::navgrid::AgentParams;
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::scene::stair_building::{stair_building, Partition, StairBuildingParams};
use xhab_sim::storey_path;
use xhab_sim::world::World;
use xhab_types::{Point2, Point3};

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
}

#[test]
fn a_grids_build_laps_name_the_steps_its_kind_of_storey_took() {
    let names = |g: &xhab_sim::navgrid::NavGrid| g.build_laps().laps().iter().map(|l| l.0).collect::<Vec<&str>>();
    let world = World::new(stair_building(&StairBuildingParams::default()), AgentParams::default());
    let storey = world.grid(0).unwrap();
    assert!(storey.has_stairs());
    let flat = World::new(xhab_sim::scene::house::default_house(3), AgentParams::default());
    let floor = flat.grid(flat.default_floor().unwrap()).unwrap();
    assert!(!floor.has_stairs());
    for (g, own, other) in [(&storey, "banded clearance", "enclosed, boundary edges"), (&floor, "enclosed, boundary edges", "banded clearance")] {
        let n = names(g);
        assert_eq!(n.first(), Some(&"band edges"), "{n:?}");
        assert_eq!(n.last(), Some(&"corners"), "{n:?}");
        assert!(n.contains(&own) && !n.contains(&other), "{n:?}");
        assert!(g.build_laps().laps().iter().all(|l| l.1 >= 0.0 && l.1.is_finite()));
    }
}

#[test]
fn a_point_on_the_flight_is_navigable_at_the_height_of_the_tread_under_it() {
    let p = StairBuildingParams::default();
    let world = World::new(stair_building(&p), AgentParams::default());
    for storey in 0..2 {
        let g = world.grid(storey).unwrap();
        // Steps 2 to 14 belong to both storeys' grids (1 and 15 are within a climb of a floor).
        for k in 2..=14 {
            let q = Point2::new(p.stair_x + (k as f64 - 0.5) * p.tread, 0.55);
            let z = g.ground_at(q).unwrap();
            assert!((z - k as f64 * p.riser()).abs() < 1e-4, "storey {storey}, step {k}: ground {z}");
            assert!(g.is_navigable(q) && g.on_stairs(q), "storey {storey}, step {k}");
        }
        // Beside the flight, the floor below is walled off by the flight's side (a drop).
        assert!(!g.is_navigable(Point2::new(p.stair_x + 7.5 * p.tread, p.stair_y().1 + 0.05)));
    }
}

/// Planar tangent points from `p` to the circle at `c` of radius `r`, as angles (rad).
fn tangent_angles(p: [f64; 2], c: [f64; 2], r: f64) -> (f64, f64) {
    let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
    let (a, b) = (dy.atan2(dx), (r / dx.hypot(dy)).acos());
    (a + b, a - b)
}

fn on_circle(c: [f64; 2], r: f64, t: f64) -> [f64; 2] {
    [c[0] + r * t.cos(), c[1] + r * t.sin()]
}

fn d2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn within(got: f64, want: f64, what: &str) {
    let err = (got - want).abs() / want;
    eprintln!("{what}: {got:.4} m against {want:.4} m ({:.3}%)", 100.0 * err);
    assert!(err <= 0.005, "{what}: {got} against the closed form {want} ({:.3}%)", 100.0 * err);
}

#[test]
fn a_straight_climb_is_one_leg_from_the_floor_below_to_the_floor_above() {
    let p = StairBuildingParams::default();
    let world = World::new(stair_building(&p), AgentParams::default());
    let (a, b) = (Point3::new(1.0, 0.55, 0.0), Point3::new(9.0, 0.55, p.storey_height));
    assert_eq!((world.storey_of(a), world.storey_of(b)), (Some(0), Some(1)));
    assert_eq!(world.connected_storeys(), vec![(0, 1)]);
    let want = (8.0f64.powi(2) + p.storey_height.powi(2)).sqrt();
    within(storey_path::distance(&world, a, b), want, "straight up the flight");
    // The same backwards.
    within(storey_path::distance(&world, b, a), want, "straight down the flight");
}

#[test]
fn a_climb_round_a_partition_bends_on_the_floor_below_as_the_closed_form_says() {
    let mut p = StairBuildingParams::default();
    p.partition = Some(Partition { x: 2.0, from_y: 0.45, thickness: 0.1 });
    let world = World::new(stair_building(&p), AgentParams::default());
    let r = world.params.radius;
    let (a, b) = ([1.0, 3.0], [9.0, 0.55]);
    // Around the partition's two lower corners (circles of the agent's radius), then one
    // straight leg up the flight.
    let (c1, c2) = ([1.95, 0.45], [2.05, 0.45]);
    let t1 = tangent_angles(a, c1, r).0; // left of c1
    let t2 = tangent_angles(b, c2, r).1 + 2.0 * std::f64::consts::PI; // below c2
    let down = 1.5 * std::f64::consts::PI;
    let flat = d2(a, on_circle(c1, r, t1)) + r * (down - t1) + d2(c1, c2) + r * (t2 - down);
    let last = d2(on_circle(c2, r, t2), b);
    let want = flat + (last.powi(2) + p.storey_height.powi(2)).sqrt();
    let got = storey_path::distance(&world, Point3::new(a[0], a[1], 0.0), Point3::new(b[0], b[1], p.storey_height));
    within(got, want, "round the partition and up");
}

#[test]
fn storeys_no_flight_joins_are_infinitely_far_apart() {
    let p = StairBuildingParams { stairs: false, ..Default::default() };
    let world = World::new(stair_building(&p), AgentParams::default());
    assert_eq!(world.floors.len(), 2);
    assert!(world.connected_storeys().is_empty());
    let d = storey_path::distance(&world, Point3::new(1.0, 0.55, 0.0), Point3::new(9.0, 0.55, p.storey_height));
    assert!(d.is_infinite(), "{d}");
    // Each storey alone is still walkable.
    assert!(storey_path::distance(&world, Point3::new(1.0, 0.55, 0.0), Point3::new(9.0, 0.55, 0.0)).is_finite());
}

fn episode(a: [f64; 3], yaw: f64, b: [f64; 3]) -> Episode {
    Episode {
        episode_id: "0".into(),
        scene_id: "stairs".into(),
        start_position: Point3::new(a[0], a[1], a[2]),
        start_yaw: yaw,
        goals: vec![Goal { position: Point3::new(b[0], b[1], b[2]), radius: 0.2 }],
        geodesic_distance: None,
        info: serde_json::Value::Null,
    }
}

/// Runs the shortest-path follower to the end; returns the metrics and the heights it passed.
fn follow(world: &World, ep: &Episode) -> (xhab_sim::metrics::EpisodeMetrics, Vec<f64>) {
    let mut env = KinematicEnv::in_world(world, ep, TaskConfig::default()).unwrap();
    let mut oracle = ShortestPathFollower::new();
    let mut heights = vec![env.height()];
    while !env.is_done() {
        let a = oracle.act(&env);
        env.step(a);
        heights.push(env.height());
    }
    (env.metrics(), heights)
}

#[test]
fn the_oracle_climbs_the_flight_to_a_goal_upstairs_and_comes_back_down() {
    let p = StairBuildingParams::default();
    let world = World::new(stair_building(&p), AgentParams::default());
    let h = p.storey_height;
    for (a, b) in [([1.0, 2.0, 0.0], [9.0, 2.0, h]), ([9.0, 2.0, h], [1.0, 2.0, 0.0]), ([1.0, 0.55, 0.0], [9.5, 3.5, h])] {
        let (m, z) = follow(&world, &episode(a, 0.3, b));
        eprintln!("{a:?} -> {b:?}: success {} spl {:.4} d0 {:.3} path {:.3} steps {}", m.success, m.spl, m.start_distance, m.path_length, m.steps);
        assert_eq!(m.success, 1.0, "{m:?}");
        assert!(m.spl >= 0.95, "{m:?}");
        // The agent's height follows the flight: it ends on the goal's storey and never
        // jumps more than a riser at a step.
        assert!((z[z.len() - 1] - b[2]).abs() < 1e-6, "ends at height {}", z[z.len() - 1]);
        assert!(z.windows(2).all(|w| (w[1] - w[0]).abs() <= p.riser() * 2.0 + 1e-9), "{z:?}");
    }
}

#[test]
fn the_two_storey_procedural_house_has_both_storeys_joined_by_its_flight() {
    use xhab_sim::scene::house::{generate_house, HouseParams};
    // One storey stays the house it always was, bit for bit.
    assert_eq!(generate_house(3, &HouseParams::default()), generate_house(3, &HouseParams { storeys: 1, ..Default::default() }));
    let p = HouseParams { storeys: 2, ..Default::default() };
    for seed in 0..4 {
        let world = World::new(generate_house(seed, &p), AgentParams::default());
        let z: Vec<f64> = world.floors.iter().map(|f| f.z).collect();
        assert_eq!(z.len(), 2, "seed {seed}: floors {z:?}");
        assert!(z[0].abs() < 1e-4 && (z[1] - (p.wall_height + xhab_sim::scene::house::SLAB)).abs() < 1e-4, "seed {seed}: {z:?}");
        assert_eq!(world.connected_storeys(), vec![(0, 1)], "seed {seed}");
        // Straight up the flight's centre line, from the hall's south landing to its north
        // landing upstairs: one leg.
        use xhab_sim::scene::house::{risers, HALL, STAIR_FOOT, STAIR_WIDTH, TREAD};
        let x = -HALL + p.wall_thickness / 2.0 + STAIR_WIDTH / 2.0;
        let y_top = STAIR_FOOT + (risers(z[1]).0 - 1) as f64 * TREAD;
        let (a, b) = (Point3::new(x, 0.5, 0.0), Point3::new(x, y_top + 1.5, z[1]));
        let want = ((b.y - a.y).powi(2) + z[1].powi(2)).sqrt();
        within(storey_path::distance(&world, a, b), want, &format!("seed {seed}: up the house's flight"));
        within(storey_path::distance(&world, b, a), want, &format!("seed {seed}: down the house's flight"));
        for k in 0..2 {
            let g = world.grid(k).unwrap();
            let total: usize = g.islands.iter().map(|i| i.cells).sum();
            let largest = g.islands.iter().map(|i| i.cells).max().unwrap();
            assert!(largest as f64 >= 0.95 * total as f64, "seed {seed} storey {k}: {largest} of {total} cells connected");
        }
    }
}

/// Share of the occupied cells of a slice through storey `k` at 1 m above its floor (off its
/// flights, which a slice cuts across but the storey walks on) that lie within 0.10 m of an
/// occupied cell of the storey's map.
fn slice_agreement(world: &World, k: usize) -> f64 {
    let g = world.grid(k).unwrap();
    let reference = g.slice_map(&world.scene, 1.0, 0.05);
    let map = g.occupancy_grid();
    let (w, h) = (map.width as isize, map.height as isize);
    let occupied = |c: isize, r: isize| c >= 0 && r >= 0 && c < w && r < h && map.data[(r * w + c) as usize] == xhab_types::GRID_OCCUPIED;
    let (mut near, mut total) = (0usize, 0usize);
    for r in 0..h {
        for c in 0..w {
            let i = (r * w + c) as usize;
            if reference.data[i] != xhab_types::GRID_OCCUPIED || g.cell_is_stair(i) {
                continue;
            }
            total += 1;
            if (-2..=2).any(|dr: isize| (-2..=2).any(|dc: isize| dc * dc + dr * dr <= 4 && occupied(c + dc, r + dr))) {
                near += 1;
            }
        }
    }
    near as f64 / total.max(1) as f64
}

#[test]
fn each_storeys_map_holds_the_walls_a_slice_through_that_storey_cuts() {
    use xhab_sim::scene::house::{generate_house, HouseParams};
    let house = World::new(generate_house(0, &HouseParams { storeys: 2, ..Default::default() }), AgentParams::default());
    let stairs = World::new(stair_building(&StairBuildingParams::default()), AgentParams::default());
    for (name, world) in [("house", &house), ("stair building", &stairs)] {
        for k in 0..2 {
            let a = slice_agreement(world, k);
            eprintln!("{name}, storey {k}: {:.1}% of the slice's occupied cells within 0.10 m of the map's", 100.0 * a);
            assert!(a >= 0.95, "{name}, storey {k}: {a}");
        }
    }
}

/// Drives `robot` straight along the stair building's flight from `a` towards `b` (forward
/// moves only, 40 of them) under physics; returns the environment at the end.
fn drive_straight(robot: &str, a: [f64; 3], yaw: f64, b: [f64; 3]) -> xhab_sim::physics_env::PhysicsEnv {
    use xhab_sim::physics_env::{PhysicsConfig, PhysicsEnv};
    use xhab_sim::robot::{PhysicsScene, RobotProfile};
    let p = StairBuildingParams::default();
    let scene = stair_building(&p);
    let ps = PhysicsScene::new(&scene).unwrap();
    let prof = RobotProfile::named_or_file(robot).unwrap();
    let world = World::new(scene, AgentParams { radius: prof.radius, ..Default::default() });
    let mut env = PhysicsEnv::in_world(&world, &ps, &episode(a, yaw, b), TaskConfig::default(), &prof, PhysicsConfig::default(), 1).unwrap();
    for _ in 0..40 {
        env.step(xhab_sim::action::Action::MoveForward);
    }
    env
}

#[test]
fn a_locobot_climbs_the_flight_and_a_turtlebot_is_stuck_at_its_first_step_with_the_cause() {
    let h = StairBuildingParams::default().storey_height;
    // Up: the LoCoBot (step_height 0.2) reaches the upper floor; the Burger (0) stops at the
    // first riser and says so.
    let up = drive_straight("locobot", [1.5, 0.55, 0.0], 0.0, [9.0, 0.55, h]);
    assert!(up.robot().ground_z().is_some_and(|z| (z - h).abs() < 0.01), "locobot ends on the ground at {:?}", up.robot().ground_z());
    assert!(!up.stuck() || up.pose().x > 9.5, "locobot stuck at {:?}", up.pose());
    let burger = drive_straight("turtlebot3_burger", [1.5, 0.55, 0.0], 0.0, [9.0, 0.55, h]);
    assert!(burger.stuck(), "burger at {:?}", burger.pose());
    assert!(burger.robot().ground_z().is_some_and(|z| z.abs() < 0.01), "the burger must not climb: ground {:?}", burger.robot().ground_z());
    let cause = burger.stuck_cause().unwrap_or_default();
    assert!(cause.contains("step 0.17 m high") || cause.contains("step 0.18 m high"), "{cause}");
    // Down: the LoCoBot walks down; the Burger stops at the top edge instead of falling.
    let down = drive_straight("locobot", [8.5, 0.55, h], std::f64::consts::PI, [1.0, 0.55, 0.0]);
    assert!(down.robot().ground_z().is_some_and(|z| z.abs() < 0.01), "locobot ends on the ground at {:?}", down.robot().ground_z());
    let burger = drive_straight("turtlebot3_burger", [8.5, 0.55, h], std::f64::consts::PI, [1.0, 0.55, 0.0]);
    assert!(burger.stuck() && burger.robot().ground_z().is_some_and(|z| (z - h).abs() < 0.01), "burger at {:?}", burger.pose());
    assert!(burger.stuck_cause().unwrap_or_default().contains("a drop of 0.1"), "{:?}", burger.stuck_cause());
}

