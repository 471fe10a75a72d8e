//! DWA behaviour in small worlds: the obvious choice in the open, turning to a goal behind,
//! never driving into a wall.

use super::trajectory::advance;
use super::*;
use crate::costmap_2d::{CostmapParams, LayeredCostmap, INSCRIBED, LETHAL};
use xhab_types::{OccupancyGrid, Point2};

/// A 5 x 5 m local costmap (round robot of 0.1 m), with a wall at x = 3 m when `wall`.
fn local(wall: bool) -> Costmap2D {
    let mut m = OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0);
    if wall {
        for r in 0..100 {
            m.set(60, r, 100);
        }
    }
    let mut cm = LayeredCostmap::new(CostmapParams {
        robot_radius: 0.1,
        footprint_padding: 0.0,
        ..Default::default()
    })
    .unwrap();
    cm.set_map(&m);
    cm.update(Pose2::default());
    cm.costmap().clone()
}

fn dwa(params: DwaParams) -> DwaController {
    let mut d =
        DwaController::new(params, crate::costmap_2d::Footprint::circle(0.1), 20.0).unwrap();
    d.set_ignore_goal_yaw(true);
    d
}

/// A straight plan from `a` to `b`, a point every 5 cm.
fn straight(a: Point2, b: Point2) -> Vec<Pose2> {
    let n = (a.dist(b) / 0.05).ceil() as usize;
    let yaw = (b.y - a.y).atan2(b.x - a.x);
    (0..=n)
        .map(|k| {
            Pose2::new(
                a.x + (b.x - a.x) * k as f64 / n as f64,
                a.y + (b.y - a.y) * k as f64 / n as f64,
                yaw,
            )
        })
        .collect()
}

/// Runs the controller on a unicycle at 20 Hz for up to `steps`; returns the poses.
fn drive(d: &mut DwaController, cm: &Costmap2D, start: Pose2, steps: usize) -> Vec<Pose2> {
    let (mut pose, mut vel) = (start, Twist::default());
    let mut out = vec![pose];
    for _ in 0..steps {
        if d.is_goal_reached(pose, vel) {
            break;
        }
        let Ok(t) = d.compute_velocity(pose, vel, cm) else {
            break;
        };
        vel = t;
        pose = advance(pose, t.linear, t.angular, 0.05);
        out.push(pose);
    }
    out
}

#[test]
fn drives_straight_at_a_goal_ahead() {
    let cm = local(false);
    let mut d = dwa(DwaParams::default());
    d.set_plan(&straight(Point2::new(1.0, 2.5), Point2::new(4.0, 2.5)));
    // From rest, the fastest speed in the window (0.125 m/s), no turn.
    let t = d
        .compute_velocity(Pose2::new(1.0, 2.5, 0.0), Twist::default(), &cm)
        .unwrap();
    assert!(
        (t.linear - 0.125).abs() < 1e-9 && t.angular.abs() < 1e-9,
        "{t:?}"
    );
    // At cruise speed it keeps going straight at full speed.
    let t = d
        .compute_velocity(
            Pose2::new(1.5, 2.5, 0.0),
            Twist {
                linear: 0.55,
                angular: 0.0,
            },
            &cm,
        )
        .unwrap();
    assert!(
        (t.linear - 0.55).abs() < 1e-9 && t.angular.abs() < 1e-9,
        "{t:?}"
    );
    // And arrives, stopped, within the tolerance.
    let poses = drive(&mut d, &cm, Pose2::new(1.0, 2.5, 0.0), 400);
    let end = *poses.last().unwrap();
    assert!(end.position().dist(Point2::new(4.0, 2.5)) <= 0.1, "{end:?}");
    assert!(
        poses.iter().all(|p| (p.y - 2.5).abs() < 0.05),
        "strayed from the line"
    );
    assert!(poses.len() < 200, "{} steps", poses.len());
}

#[test]
fn turns_in_place_towards_a_goal_behind_the_short_way() {
    let cm = local(false);
    for (yaw, left) in [(0.3, true), (-0.3, false)] {
        let mut d = dwa(DwaParams::default());
        d.set_plan(&straight(Point2::new(2.0, 2.5), Point2::new(0.5, 2.5)));
        let t = d
            .compute_velocity(Pose2::new(2.0, 2.5, yaw), Twist::default(), &cm)
            .unwrap();
        assert_eq!(t.linear, 0.0, "{t:?}");
        assert_eq!(t.angular > 0.0, left, "yaw {yaw}: {t:?}");
        // Then it gets there.
        let poses = drive(&mut d, &cm, Pose2::new(2.0, 2.5, yaw), 400);
        assert!(poses.last().unwrap().position().dist(Point2::new(0.5, 2.5)) <= 0.1);
    }
}

#[test]
fn in_place_turns_are_scored_by_heading_not_all_alike() {
    // Rotate-first off: the sampler itself must prefer turning towards a path on the left.
    let cm = local(false);
    for (goal_y, left) in [(4.0, true), (1.0, false)] {
        let mut d = dwa(DwaParams {
            rotate_first_angle: std::f64::consts::PI,
            ..Default::default()
        });
        d.set_plan(&straight(Point2::new(2.5, 2.5), Point2::new(2.5, goal_y)));
        let t = d
            .compute_velocity(Pose2::new(2.5, 2.5, 0.0), Twist::default(), &cm)
            .unwrap();
        assert_eq!(t.angular > 0.0, left, "{t:?}");
    }
}

/// A 5 x 5 m costmap with a wall at x = 3 m open for y in [3.5, 4.5] m.
fn wall_with_gap() -> Costmap2D {
    let mut m = OccupancyGrid::new(100, 100, 0.05, Pose2::default(), 0);
    for r in (0..70).chain(90..100) {
        m.set(60, r, 100);
    }
    let mut cm = LayeredCostmap::new(CostmapParams {
        robot_radius: 0.1,
        footprint_padding: 0.0,
        ..Default::default()
    })
    .unwrap();
    cm.set_map(&m);
    cm.update(Pose2::default());
    cm.costmap().clone()
}

fn assert_clear(cm: &Costmap2D, poses: &[Pose2]) {
    for p in poses {
        assert!(
            cm.cost_at(p.position()).unwrap() < INSCRIBED,
            "entered a wall's inscribed zone at {p:?}"
        );
    }
}

#[test]
fn never_drives_into_a_wall_in_front() {
    // Heading at the wall at full speed, the plan turning through the gap: it turns in time.
    let cm = wall_with_gap();
    let mut plan = straight(Point2::new(2.0, 2.5), Point2::new(2.5, 4.0));
    plan.extend(
        straight(Point2::new(2.5, 4.0), Point2::new(3.5, 4.0))
            .into_iter()
            .skip(1),
    );
    plan.extend(
        straight(Point2::new(3.5, 4.0), Point2::new(4.0, 2.5))
            .into_iter()
            .skip(1),
    );
    let mut d = dwa(DwaParams::default());
    d.set_plan(&plan);
    let (mut pose, mut vel) = (
        Pose2::new(2.0, 2.5, 0.0),
        Twist {
            linear: 0.55,
            angular: 0.0,
        },
    );
    let mut poses = vec![pose];
    for _ in 0..600 {
        if d.is_goal_reached(pose, vel) {
            break;
        }
        let t = d.compute_velocity(pose, vel, &cm).unwrap();
        vel = t;
        pose = advance(pose, t.linear, t.angular, 0.05);
        poses.push(pose);
    }
    assert_clear(&cm, &poses);
    assert!(
        pose.position().dist(Point2::new(4.0, 2.5)) <= 0.1,
        "{pose:?}"
    );
    // A goal just short of the wall, approached at full speed: it stops in time.
    let cm = local(true);
    let mut d = dwa(DwaParams::default());
    d.set_plan(&straight(Point2::new(2.0, 2.5), Point2::new(2.8, 2.5)));
    let (mut pose, mut vel) = (
        Pose2::new(2.0, 2.5, 0.0),
        Twist {
            linear: 0.55,
            angular: 0.0,
        },
    );
    let mut poses = vec![pose];
    for _ in 0..200 {
        let Ok(t) = d.compute_velocity(pose, vel, &cm) else {
            break;
        };
        vel = t;
        pose = advance(pose, t.linear, t.angular, 0.05);
        poses.push(pose);
    }
    assert_clear(&cm, &poses);
    assert!(
        pose.position().dist(Point2::new(2.8, 2.5)) <= 0.1,
        "{pose:?}"
    );
    // A plan straight through the wall: no trajectory reaches its goal, so none is taken.
    let mut d = dwa(DwaParams::default());
    d.set_plan(&straight(Point2::new(2.0, 2.5), Point2::new(4.0, 2.5)));
    assert_eq!(
        d.compute_velocity(Pose2::new(2.0, 2.5, 0.0), Twist::default(), &cm),
        Err(ControlError::NoValidTrajectory)
    );
}

#[test]
fn a_long_footprint_keeps_its_nose_off_the_wall() {
    let cm = local(true);
    let long = crate::costmap_2d::Footprint::polygon(
        &[[-0.1, -0.1], [0.6, -0.1], [0.6, 0.1], [-0.1, 0.1]],
        0.0,
    );
    let mut d = DwaController::new(DwaParams::default(), long, 20.0).unwrap();
    d.set_plan(&straight(Point2::new(1.5, 2.5), Point2::new(4.0, 2.5)));
    let poses = drive(&mut d, &cm, Pose2::new(1.5, 2.5, 0.0), 300);
    for p in &poses {
        let nose = Point2::new(p.x + 0.6 * p.yaw.cos(), p.y + 0.6 * p.yaw.sin());
        assert_ne!(cm.cost_at(nose), Some(LETHAL), "nose in the wall at {p:?}");
        assert!(nose.x < 3.0, "{p:?}");
    }
}

#[test]
fn reports_why_it_cannot_drive() {
    let cm = local(false);
    let mut d = dwa(DwaParams::default());
    assert_eq!(
        d.compute_velocity(Pose2::new(1.0, 1.0, 0.0), Twist::default(), &cm),
        Err(ControlError::NoPlan)
    );
    d.set_plan(&straight(Point2::new(1.0, 1.0), Point2::new(2.0, 1.0)));
    assert_eq!(
        d.compute_velocity(Pose2::new(9.0, 1.0, 0.0), Twist::default(), &cm),
        Err(ControlError::RobotOffCostmap)
    );
    assert!(DwaController::new(
        DwaParams {
            sim_time: 0.0,
            ..Default::default()
        },
        crate::costmap_2d::Footprint::circle(0.1),
        20.0
    )
    .is_err());
}
