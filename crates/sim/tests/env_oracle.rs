//! The discrete simulator: sliding, collisions, the step limit, metrics, and the oracle.

use std::sync::Arc;
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView, InvalidEpisode, TaskConfig};
use xhab_sim::navgrid::{AgentParams, NavGrid};
use xhab_sim::oracle::ShortestPathFollower;

use crate::common::{episode, room_with_door, GREY};

/// The room with a door, and a table, as a navigation grid.
fn room() -> Arc<NavGrid> {
    let mut s = room_with_door();
    s.add_box("table", [4.0, 4.0, 0.7], [5.0, 5.0, 0.75], GREY);
    Arc::new(NavGrid::build(&s, &AgentParams::default(), 0.0).unwrap())
}

fn run_oracle(env: &mut KinematicEnv) {
    let mut o = ShortestPathFollower::new();
    while !env.is_done() {
        let a = o.act(env);
        env.step(a);
    }
}

#[test]
fn oracle_reaches_goals_through_the_door_efficiently() {
    let g = room();
    for (sx, sy, gx, gy) in [(1.0, 1.0, 1.0, 5.0), (5.5, 0.5, 0.5, 5.5), (3.0, 2.0, 4.5, 5.6), (0.5, 5.5, 5.5, 3.5)] {
        let mut env = KinematicEnv::new(g.clone(), &episode(sx, sy, 0.3, gx, gy), TaskConfig::default()).unwrap();
        run_oracle(&mut env);
        let m = env.metrics();
        eprintln!("({sx},{sy})->({gx},{gy}): {m:?}");
        assert_eq!(m.success, 1.0, "{m:?}");
        assert!(m.spl > 0.9, "{m:?}");
        assert!(m.called_stop);
    }
}

#[test]
fn moving_into_a_wall_slides_and_counts_a_collision() {
    let g = room();
    // Facing the west wall at 45 degrees, 0.2 m from it: the agent slides north.
    let yaw = 135f64.to_radians();
    let mut env = KinematicEnv::new(g.clone(), &episode(0.25, 1.0, yaw, 5.0, 1.0), TaskConfig::default()).unwrap();
    let mut collisions = 0;
    for _ in 0..6 {
        let r = env.step(Action::MoveForward);
        collisions += r.collided as u32;
        let p = env.pose();
        assert!(g.is_navigable(p.position()), "left the region at {p:?}");
        assert!(p.x >= 0.1 - 0.011, "went through the wall: {p:?}");
    }
    assert!(collisions >= 5, "{collisions}");
    assert_eq!(env.metrics().collisions, collisions);
    // It slid north: more than 0.5 m of progress along the wall.
    assert!(env.pose().y > 1.5, "{:?}", env.pose());
    // Head-on into the wall: no motion at all.
    let mut env = KinematicEnv::new(g.clone(), &episode(0.3, 1.0, std::f64::consts::PI, 5.0, 1.0), TaskConfig::default()).unwrap();
    env.step(Action::MoveForward);
    let r = env.step(Action::MoveForward);
    assert!(r.collided);
    assert!((env.pose().x - 0.1).abs() < 0.012 && (env.pose().y - 1.0).abs() < 1e-6, "{:?}", env.pose());
}

#[test]
fn step_limit_and_stop_end_episodes() {
    let g = room();
    let cfg = TaskConfig::default();
    let mut env = KinematicEnv::new(g.clone(), &episode(1.0, 1.0, 0.0, 1.0, 5.0), cfg.clone()).unwrap();
    let mut n = 0;
    while !env.step(Action::TurnLeft).done {
        n += 1;
    }
    assert_eq!(n + 1, 500);
    let m = env.metrics();
    assert_eq!((m.steps, m.success, m.spl), (500, 0.0, 0.0));
    // Stopping far from the goal fails; soft SPL is 0 with no progress.
    let mut env = KinematicEnv::new(g.clone(), &episode(1.0, 1.0, 0.0, 1.0, 5.0), cfg).unwrap();
    assert!(env.step(Action::Stop).done);
    let m = env.metrics();
    assert_eq!((m.success, m.soft_spl, m.steps), (0.0, 0.0, 1));
}

#[test]
fn invalid_episodes_are_named() {
    let g = room();
    let e = KinematicEnv::new(g.clone(), &episode(4.5, 4.5, 0.0, 1.0, 1.0), TaskConfig::default()).unwrap_err();
    assert!(matches!(e, InvalidEpisode::StartNotNavigable { .. }), "{e}");
    let e = KinematicEnv::new(g.clone(), &episode(1.0, 1.0, 0.0, 0.05, 1.0), TaskConfig::default()).unwrap_err();
    assert!(matches!(e, InvalidEpisode::GoalNotNavigable { .. }), "{e}");
}

#[test]
fn observations_follow_the_conventions() {
    let g = room();
    let mut env = KinematicEnv::new(g.clone(), &episode(1.0, 1.0, 0.0, 1.0, 2.0), TaskConfig::default()).unwrap();
    let o = env.observe();
    // Goal 1 m to the left of an agent facing +x.
    assert!((o.pointgoal[0] - 1.0).abs() < 1e-12 && (o.pointgoal[1] - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    env.step(Action::TurnLeft);
    env.step(Action::MoveForward);
    let o = env.observe();
    assert!((o.compass - 10f64.to_radians()).abs() < 1e-12);
    let (s, c) = 10f64.to_radians().sin_cos();
    assert!((o.gps.x - 0.25 * c).abs() < 1e-12 && (o.gps.y - 0.25 * s).abs() < 1e-12, "{o:?}");
}
