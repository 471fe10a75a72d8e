//! Planner tests on small hand-made maps with known answers.

use super::*;
use crate::costmap_2d::{CostmapParams, LayeredCostmap, INSCRIBED, LETHAL};
use xhab_types::{OccupancyGrid, Point2, Pose2};

/// A global costmap (static + inflation, round robot of 0.1 m) of `map`.
fn costmap(map: &OccupancyGrid) -> Costmap2D {
    costmap_inflated(map, 0.55)
}

/// The same with an inflation radius of `inflation_radius` (m).
fn costmap_inflated(map: &OccupancyGrid, inflation_radius: f64) -> Costmap2D {
    let mut params = CostmapParams {
        robot_radius: 0.1,
        footprint_padding: 0.0,
        ..Default::default()
    };
    params.inflation_layer.inflation_radius = inflation_radius;
    let mut cm = LayeredCostmap::new(params).unwrap();
    cm.set_map(map);
    cm.update(Pose2::default());
    cm.costmap().clone()
}

/// A 5 x 3 m room with two baffles: wall A at x = 1.5 m for y < 2 m, wall B at x = 3.5 m for
/// y > 1 m, so the way from the left to the right snakes over A and under B.
fn maze() -> OccupancyGrid {
    let mut m = OccupancyGrid::new(100, 60, 0.05, Pose2::default(), 0);
    for r in 0..60 {
        for c in 0..100 {
            let border = c == 0 || r == 0 || c == 99 || r == 59;
            if border || (c == 30 && r < 40) || (c == 70 && r >= 20) {
                m.set(c, r, 100);
            }
        }
    }
    m
}

fn planner(use_dijkstra: bool, default_tolerance: f64) -> GridPlanner {
    let mut p = GridPlanner::new(GlobalPlannerParams {
        use_dijkstra,
        default_tolerance,
        ..Default::default()
    })
    .unwrap();
    p.set_escape_radius(0.1);
    p
}

/// The highest cost met along the path, sampled every centimetre.
fn max_cost_along(cm: &Costmap2D, path: &[Pose2]) -> u8 {
    let mut worst = 0;
    for w in path.windows(2) {
        let (a, b) = (w[0].position(), w[1].position());
        let n = (a.dist(b) / 0.01).ceil().max(1.0) as usize;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            worst = worst.max(
                cm.cost_at(Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)))
                    .unwrap_or(LETHAL),
            );
        }
    }
    worst
}

/// The length of the path and the smallest distance (m) of its points from a lethal cell.
fn length_and_clearance(cm: &Costmap2D, path: &[Pose2]) -> (f64, f64) {
    let lethal: Vec<Point2> = (0..cm.costs().len())
        .filter(|&i| cm.costs()[i] == LETHAL)
        .map(|i| cm.map_to_world(i % cm.size_x(), i / cm.size_x()))
        .collect();
    let clearance = path
        .iter()
        .map(|p| {
            lethal
                .iter()
                .map(|l| l.dist(p.position()))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min);
    (path_length(path), clearance)
}

/// The shortest path of a disc of radius `r` from `s` over the end `a` of one wall (on the
/// path's right) and under the end `b` of another (on its left) to `g`: tangent, arc, inner
/// tangent, arc, tangent.
fn taut_string(s: Point2, a: Point2, b: Point2, g: Point2, r: f64) -> f64 {
    let ang = |p: Point2, q: Point2| (q.y - p.y).atan2(q.x - p.x);
    let (sa, ab, bg) = (s.dist(a), a.dist(b), b.dist(g));
    let f1 = ang(s, a) + (r / sa).asin();
    let f2 = ang(a, b) - (2.0 * r / ab).asin();
    let f3 = ang(b, g) + (r / bg).asin();
    (sa * sa - r * r).sqrt()
        + r * (f1 - f2)
        + (ab * ab - 4.0 * r * r).sqrt()
        + r * (f3 - f2)
        + (bg * bg - r * r).sqrt()
}

#[test]
fn maze_path_is_the_shortest_for_the_robot_and_equal_for_dijkstra_and_astar() {
    // Without inflation beyond the inscribed radius the cheapest path is the shortest path of
    // the robot's centre, kept 0.1 m off the centres of the walls' end cells: 5.396 m.
    let cm = costmap_inflated(&maze(), 0.1);
    let (s, g) = (Pose2::new(0.75, 0.75, 0.0), Pose2::new(4.25, 2.25, 0.0));
    let known = taut_string(
        s.position(),
        Point2::new(1.525, 1.975),
        Point2::new(3.525, 1.025),
        g.position(),
        0.1,
    );
    assert!((known - 5.3962).abs() < 1e-3, "{known}");
    let mut lengths = Vec::new();
    for use_dijkstra in [true, false] {
        let path = planner(use_dijkstra, 0.0).plan(&cm, s, g).unwrap();
        assert_eq!(path.first().unwrap().position(), s.position());
        assert_eq!(path.last().unwrap().position(), g.position());
        assert!(
            max_cost_along(&cm, &path) < INSCRIBED,
            "the path enters the inscribed zone"
        );
        // Over wall A's end and under wall B's.
        let cross = |x: f64| {
            path.windows(2)
                .find(|w| (w[0].x - x) * (w[1].x - x) <= 0.0)
                .map(|w| w[0].y)
                .unwrap()
        };
        assert!(cross(1.525) > 2.0 && cross(3.525) < 1.0);
        lengths.push(path_length(&path));
    }
    // Cells make the free space a little smaller than the disc's: a bit longer, never shorter.
    assert!(
        lengths[0] >= known && lengths[0] <= 1.03 * known,
        "{lengths:?} vs {known}"
    );
    assert!(
        (lengths[0] - lengths[1]).abs() <= 0.01 * lengths[0],
        "Dijkstra {} vs A* {}",
        lengths[0],
        lengths[1]
    );
}

#[test]
fn with_ros_inflation_the_path_keeps_clear_of_wall_ends() {
    // The same maze with ROS's default inflation (0.55 m, scaling 10, cost_factor 3): the path
    // passes the wall ends about half a metre off, through the middle of the 1 m gaps, where a
    // flat cost ceiling would let it skim the inscribed zone.
    let cm = costmap(&maze());
    let (s, g) = (Pose2::new(0.75, 0.75, 0.0), Pose2::new(4.25, 2.25, 0.0));
    for use_dijkstra in [true, false] {
        let path = planner(use_dijkstra, 0.0).plan(&cm, s, g).unwrap();
        assert!(max_cost_along(&cm, &path) < INSCRIBED);
        let (length, clearance) = length_and_clearance(&cm, &path);
        assert!(clearance > 0.3, "clearance {clearance}");
        assert!(length < 7.5, "length {length}");
    }
}

#[test]
fn astar_expands_fewer_cells_than_dijkstra() {
    let cm = costmap(&maze());
    let (s, g) = (Pose2::new(0.75, 0.75, 0.0), Pose2::new(1.2, 0.5, 0.0));
    let (mut d, mut a) = (planner(true, 0.0), planner(false, 0.0));
    d.plan(&cm, s, g).unwrap();
    a.plan(&cm, s, g).unwrap();
    assert!(
        a.last_expanded() * 3 < d.last_expanded(),
        "A* {} vs Dijkstra {}",
        a.last_expanded(),
        d.last_expanded()
    );
}

#[test]
fn keeps_away_from_walls_in_a_wide_corridor() {
    // A 1.2 m wide straight corridor: the path runs down its middle, not along a wall.
    let mut m = OccupancyGrid::new(80, 40, 0.05, Pose2::default(), 0);
    for c in 0..80 {
        m.set(c, 8, 100);
        m.set(c, 32, 100);
    }
    let cm = costmap(&m);
    let path = planner(true, 0.0)
        .plan(&cm, Pose2::new(0.3, 0.7, 0.0), Pose2::new(3.7, 1.3, 0.0))
        .unwrap();
    let mid: Vec<f64> = path
        .iter()
        .filter(|p| p.x > 1.5 && p.x < 2.5)
        .map(|p| p.y)
        .collect();
    assert!(
        !mid.is_empty() && mid.iter().all(|y| (y - 1.025).abs() < 0.16),
        "{mid:?}"
    );
}

#[test]
fn failures_name_their_cause() {
    let cm = costmap(&maze());
    let mut p = planner(true, 0.0);
    let s = Pose2::new(0.75, 0.75, 0.0);
    assert_eq!(
        p.plan(&cm, s, Pose2::new(9.0, 1.0, 0.0)),
        Err(PlanError::GoalOutsideMap)
    );
    assert_eq!(
        p.plan(&cm, Pose2::new(-1.0, 1.0, 0.0), s),
        Err(PlanError::StartOutsideMap)
    );
    assert_eq!(
        p.plan(&cm, Pose2::new(1.525, 1.0, 0.0), Pose2::new(0.5, 0.5, 0.0)),
        Err(PlanError::StartOccupied)
    );
    // A goal in wall A: occupied without tolerance, the nearest free cell with it.
    let in_wall = Pose2::new(1.51, 1.0, 0.0);
    assert_eq!(p.plan(&cm, s, in_wall), Err(PlanError::GoalOccupied));
    let path = planner(true, 0.3).plan(&cm, s, in_wall).unwrap();
    let end = path.last().unwrap().position();
    assert!(
        end.dist(in_wall.position()) <= 0.3 && end.x < 1.5,
        "{end:?}"
    );
    // A start pressed against a wall (inside the inscribed zone) gets out.
    let path = p
        .plan(&cm, Pose2::new(1.44, 1.0, 0.0), Pose2::new(0.5, 0.5, 0.0))
        .unwrap();
    assert!(path.len() > 2);
}

#[test]
fn enclosed_goal_has_no_path() {
    let mut m = maze();
    for k in 10..=20 {
        m.set(10, k, 100);
        m.set(20, k, 100);
        m.set(k, 10, 100);
        m.set(k, 20, 100);
    }
    let cm = costmap(&m);
    assert_eq!(
        planner(false, 0.0).plan(&cm, Pose2::new(2.5, 2.5, 0.0), Pose2::new(0.75, 0.75, 0.0)),
        Err(PlanError::NoPath)
    );
    // With a tolerance the closest reachable cell is taken instead, as navfn does.
    let path = planner(true, 0.6)
        .plan(&cm, Pose2::new(2.5, 2.5, 0.0), Pose2::new(0.75, 0.75, 0.0))
        .unwrap();
    assert!(
        path.last()
            .unwrap()
            .position()
            .dist(Point2::new(0.75, 0.75))
            <= 0.6
    );
}
