//! Physics mode: no tunnelling, determinism, the oracle under Algorithm 1, NaN commands.

use std::sync::Arc;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, TaskConfig};
use xhab_sim::navgrid::{AgentParams, NavGrid};
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::physics_env::{PhysicsConfig, PhysicsEnv};
use xhab_sim::robot::{PhysicsParams, PhysicsScene, RigidRobot, RobotProfile};
use xhab_sim::scene::Scene;
use xhab_types::{Pose2, Twist};

use crate::common::{episode, room_with_door as room, GREY};

fn wall_scene() -> Scene {
    let mut s = Scene::default();
    s.add_box("floor", [-5.0, -5.0, -0.05], [5.0, 5.0, 0.0], GREY);
    s.add_box("wall", [2.0, -5.0, 0.0], [2.1, 5.0, 2.5], GREY);
    s
}

#[test]
fn no_profile_tunnels_through_a_wall_at_any_speed() {
    let ps = PhysicsScene::new(&wall_scene()).unwrap();
    for name in RobotProfile::builtin_names() {
        for factor in [1.0, 10.0] {
            let mut p = RobotProfile::builtin(name).unwrap();
            // Raise the limits too, so that the clamp is not what saves the robot.
            p.max_linear *= factor;
            p.max_linear_accel *= factor * 10.0;
            let mut r = RigidRobot::new(&ps, &p, Pose2::new(0.0, 0.0, 0.0), 0.0, &PhysicsParams::default()).unwrap();
            let mut max_x = f64::MIN;
            for _ in 0..600 {
                r.step_physics(Twist { linear: p.max_linear, angular: 0.0 });
                max_x = max_x.max(r.pose().x);
            }
            assert!(max_x < 2.0, "{name} at {factor}x: reached x = {max_x} (wall at 2.0)");
            assert!(max_x > 2.0 - p.radius - 0.05, "{name} at {factor}x: stopped early at {max_x}");
            assert!(r.z() > 0.0 && r.z() < 2.0, "{name}: left the floor (z = {})", r.z());
        }
    }
}

fn run(env: &mut dyn DiscreteEnv) -> Vec<Pose2> {
    let mut o = ShortestPathFollower::new();
    let mut traj = vec![env.pose()];
    while !env.is_done() {
        let a = o.act(env);
        env.step(a);
        traj.push(env.pose());
    }
    traj
}

#[test]
fn oracle_under_physics_matches_the_kinematic_run() {
    let scene = room();
    let grid = Arc::new(NavGrid::build(&scene, &AgentParams::default(), 0.0).unwrap());
    let ps = PhysicsScene::new(&scene).unwrap();
    let prof = RobotProfile::builtin("habitat").unwrap();
    for (sx, sy, gx, gy) in [(1.0, 1.0, 1.0, 5.0), (5.5, 0.5, 0.5, 5.5)] {
        let ep = episode(sx, sy, 0.4, gx, gy);
        let mut k = KinematicEnv::new(grid.clone(), &ep, TaskConfig::default()).unwrap();
        run(&mut k);
        let mut p = PhysicsEnv::new(grid.clone(), &ps, &ep, TaskConfig::default(), &prof, PhysicsConfig::default(), 1).unwrap();
        run(&mut p);
        let (mk, mp) = (k.metrics(), p.metrics());
        eprintln!("kinematic {mk:?}\nphysics   {mp:?} sim {:.1} s stuck {}", p.sim_s(), p.stuck());
        assert_eq!(mp.success, 1.0, "{mp:?}");
        assert!((mp.spl - mk.spl).abs() < 0.05, "{mp:?} vs {mk:?}");
        assert!((p.sim_s() - mp.steps as f64 + 1.0).abs() < 1e-6, "one simulated second per action but stop");
    }
}

#[test]
fn physics_is_deterministic_across_threads() {
    let scene = room();
    let grid = Arc::new(NavGrid::build(&scene, &AgentParams::default(), 0.0).unwrap());
    let ps = PhysicsScene::new(&scene).unwrap();
    let prof = RobotProfile::builtin("locobot").unwrap();
    let once = || {
        let mut p = PhysicsEnv::new(grid.clone(), &ps, &episode(1.0, 1.0, 0.4, 5.0, 5.0), TaskConfig::default(), &prof, PhysicsConfig::default(), 9).unwrap();
        let t = run(&mut p);
        (t.iter().map(|q| (q.x.to_bits(), q.y.to_bits(), q.yaw.to_bits())).collect::<Vec<_>>(), p.odometry())
    };
    let a = once();
    assert_eq!(a, once());
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let b = pool.install(|| {
        use rayon::prelude::*;
        (0..2).into_par_iter().map(|_| once()).collect::<Vec<_>>()
    });
    assert!(b.iter().all(|x| *x == a));
}

#[test]
fn nan_commands_never_reach_the_solver() {
    let ps = PhysicsScene::new(&wall_scene()).unwrap();
    let p = RobotProfile::builtin("turtlebot3_burger").unwrap();
    let mut r = RigidRobot::new(&ps, &p, Pose2::default(), 0.0, &PhysicsParams::default()).unwrap();
    for _ in 0..30 {
        r.step_physics(Twist { linear: f64::NAN, angular: f64::INFINITY });
    }
    let q = r.pose();
    assert!(q.x.is_finite() && q.y.is_finite() && q.yaw.is_finite());
    assert_eq!(r.rejected_commands, 30);
}

#[test]
fn the_body_follows_a_ramp_and_small_bumps() {
    use xhab_sim::scene::Mesh;
    let mut s = Scene::default();
    s.add_box("floor", [-2.0, -2.0, -0.05], [8.0, 2.0, 0.0], GREY);
    // A 8.5 degree ramp from x = 1 to 3 up to 0.3 m, then a plateau to x = 6.
    s.meshes.push(Mesh::new(
        "ramp",
        vec![[1.0, -2.0, 0.0], [3.0, -2.0, 0.3], [3.0, 2.0, 0.3], [1.0, 2.0, 0.0]],
        vec![[0, 1, 2], [0, 2, 3]],
        GREY,
    ));
    s.add_box("plateau", [3.0, -2.0, 0.0], [6.0, 2.0, 0.3], GREY);
    // A 2 cm cable on the plateau.
    s.add_box("cable", [4.5, -2.0, 0.3], [4.55, 2.0, 0.32], GREY);
    let ps = PhysicsScene::new(&s).unwrap();
    let p = RobotProfile::builtin("locobot").unwrap();
    let mut r = RigidRobot::new(&ps, &p, Pose2::new(0.0, 0.0, 0.0), 0.0, &PhysicsParams::default()).unwrap();
    let z0 = r.z();
    for _ in 0..(60.0 * 5.5 / 0.5) as usize {
        r.step_physics(Twist { linear: 0.5, angular: 0.0 });
    }
    let q = r.pose();
    eprintln!("after the ramp: x = {:.3}, z - z0 = {:.3}", q.x, r.z() - z0);
    assert!(q.x > 5.0, "stopped at x = {}", q.x);
    assert!((r.z() - z0 - 0.3).abs() < 0.03, "z rose by {}", r.z() - z0);
}
