//! Geodesics on layouts whose shortest paths are known in closed form.
//!
//! The disc agent (radius r) wraps around a convex obstacle corner K along a circle of radius
//! r: length = tangent(S) + r * theta + tangent(G). Layouts are shifted by an odd offset so
//! that no wall lines up with the grid.

use xhab_sim::geodesic::{geodesic_distance, GeodesicField};
use xhab_sim::navgrid::{AgentParams, NavGrid};
use xhab_sim::scene::Scene;
use xhab_types::Point2;

const GREY: [f32; 4] = [0.5, 0.5, 0.5, 1.0];
const OFF: [f32; 2] = [0.0123, 0.0371];

fn add(s: &mut Scene, name: &str, x0: f32, y0: f32, x1: f32, y1: f32, z1: f32) {
    s.add_box(name, [x0 + OFF[0], y0 + OFF[1], if z1 <= 0.0 { -0.05 } else { 0.0 }], [x1 + OFF[0], y1 + OFF[1], z1], GREY);
}

fn p(x: f64, y: f64) -> Point2 {
    Point2::new(x + OFF[0] as f64, y + OFF[1] as f64)
}

/// Length of the shortest path from s to g wrapping once around corner k on the side
/// swept counter-clockwise from s to g (angles in the free region), for radius r.
fn wrap_len(s: [f64; 2], g: [f64; 2], k: [f64; 2], r: f64, ccw: bool) -> f64 {
    let ds = (s[0] - k[0]).hypot(s[1] - k[1]);
    let dg = (g[0] - k[0]).hypot(g[1] - k[1]);
    let a_s = (s[1] - k[1]).atan2(s[0] - k[0]);
    let a_g = (g[1] - k[1]).atan2(g[0] - k[0]);
    let mut sweep = if ccw { a_g - a_s } else { a_s - a_g };
    sweep = sweep.rem_euclid(std::f64::consts::TAU);
    let theta = sweep - (r / ds).acos() - (r / dg).acos();
    assert!(theta > 0.0, "the straight line is free: not a wrapping case");
    (ds * ds - r * r).sqrt() + (dg * dg - r * r).sqrt() + r * theta
}

fn grid(scene: &Scene) -> NavGrid {
    NavGrid::build(scene, &AgentParams::default(), 0.0).expect("grid builds")
}

fn check(name: &str, got: f64, want: f64) {
    let err = (got - want).abs() / want;
    eprintln!("{name}: geodesic {got:.5} m, exact {want:.5} m, error {:.3}%", err * 100.0);
    assert!(err <= 0.005, "{name}: {got} vs exact {want} ({:.3}% off)", err * 100.0);
}

#[test]
fn l_shaped_corridor() {
    let mut s = Scene::default();
    add(&mut s, "floor", -1.0, -1.0, 6.0, 6.0, 0.0);
    add(&mut s, "inner_block", -1.0, 1.0, 3.0, 5.0, 2.5);
    add(&mut s, "wall_bottom", -1.0, -0.1, 5.0, 0.0, 2.5);
    add(&mut s, "wall_right", 4.0, -1.0, 4.1, 5.0, 2.5);
    add(&mut s, "wall_left", -0.1, -1.0, 0.0, 1.0, 2.5);
    add(&mut s, "wall_top", 3.0, 5.0, 4.1, 5.1, 2.5);
    let g = grid(&s);
    let r = g.params.radius;
    // Goal up the vertical leg, start along the horizontal leg: the path bends at K = (3, 1).
    for (sx, sy, gx, gy) in [(0.5, 0.5, 3.5, 3.5), (0.3, 0.2, 3.8, 4.5), (1.7, 0.8, 3.2, 2.0), (2.6, 0.5, 3.5, 1.6)] {
        let want = wrap_len([sx, sy], [gx, gy], [3.0, 1.0], r, true);
        check(&format!("L corridor ({sx},{sy})->({gx},{gy})"), geodesic_distance(&g, p(sx, sy), p(gx, gy)), want);
        // Symmetric.
        check("L corridor reversed", geodesic_distance(&g, p(gx, gy), p(sx, sy)), want);
    }
    // Straight line of sight: euclidean.
    check("L corridor straight", geodesic_distance(&g, p(0.5, 0.5), p(3.5, 0.5)), 3.0);
}

#[test]
fn wall_with_a_door() {
    // A wall along y in [-0.05, 0.05], door x in [-0.45, 0.45].
    let mut s = Scene::default();
    add(&mut s, "floor", -5.0, -5.0, 5.0, 5.0, 0.0);
    add(&mut s, "wall_left", -5.0, -0.05, -0.45, 0.05, 2.5);
    add(&mut s, "wall_right", 0.45, -0.05, 5.0, 0.05, 2.5);
    let g = grid(&s);
    let r = g.params.radius;
    // Through the door and back along the wall: wraps two jamb corners A1 = (-0.45, -0.05)
    // and A2 = (-0.45, 0.05), with the straight 0.1 m of the jamb face in between.
    for (sx, sy) in [(-3.0, -0.5), (-1.5, -1.2), (-4.0, -0.3)] {
        let (a1, a2) = ([-0.45, -0.05], [-0.45, 0.05]);
        // Half path: from S around A1 up to the jamb face (direction +y at A1 + (r, 0)).
        let half = |s: [f64; 2], k: [f64; 2], below: bool| {
            let d = (s[0] - k[0]).hypot(s[1] - k[1]);
            let a_s = (s[1] - k[1]).atan2(s[0] - k[0]);
            let t = if below { a_s + (r / d).acos() } else { a_s - (r / d).acos() };
            (d * d - r * r).sqrt() + r * t.abs()
        };
        let want = half([sx, sy], a1, true) + 0.1 + half([sx, -sy], a2, false);
        check(&format!("door ({sx},{sy})"), geodesic_distance(&g, p(sx, sy), p(sx, -sy)), want);
    }
    // Straight through the door.
    check("door straight", geodesic_distance(&g, p(-0.2, -2.0), p(0.2, 2.0)), (0.4f64).hypot(4.0));
}

#[test]
fn islands_are_infinitely_far_and_goals_take_the_minimum() {
    let mut s = Scene::default();
    add(&mut s, "floor", -3.0, -3.0, 3.0, 3.0, 0.0);
    add(&mut s, "wall", -0.05, -3.0, 0.05, 3.0, 2.5);
    let g = grid(&s);
    assert!(geodesic_distance(&g, p(-1.0, 0.0), p(1.0, 0.0)).is_infinite());
    let f = GeodesicField::new(&g, &[p(-2.0, 0.0), p(-1.0, 1.0), p(1.0, 0.0)]);
    let d = f.distance(&g, p(-1.0, 0.0));
    assert!((d - 1.0).abs() < 1e-9, "{d}");
}


#[test]
fn distances_off_the_region_run_from_its_nearest_point() {
    // A straight corridor 1 m wide: a point inside the wall is off the region, 0.25 m from
    // the corridor's navigable edge (the agent's radius from the wall face).
    let mut s = Scene::default();
    add(&mut s, "floor", -1.0, -1.0, 6.0, 2.0, 0.0);
    add(&mut s, "wall_bottom", -1.0, -0.6, 6.0, 0.0, 2.5);
    add(&mut s, "wall_top", -1.0, 1.0, 6.0, 1.6, 2.5);
    let g = grid(&s);
    let r = g.params.radius;
    let goal = p(4.0, 0.5);
    let f = g.field(&[goal]);
    let on = p(1.0, 0.5);
    assert_eq!(f.distance_snapped(&g, on), (f.distance(&g, on), None));
    let off = p(1.0, -0.15);
    assert!(f.distance(&g, off).is_infinite());
    let (d, offset) = f.distance_snapped(&g, off);
    let offset = offset.expect("off the region");
    // The nearest navigable cell centre is about 0.15 + r away (within a cell).
    assert!((offset - (0.15 + r)).abs() < g.resolution(), "{offset}");
    let straight = (goal.x - off.x).hypot(goal.y - off.y);
    assert!(d.is_finite() && d >= straight - 1e-9 && d < straight + 2.0 * offset, "{d} vs {straight}");
}
