//! The figures of `xhab perf` as a criterion suite (`cargo bench -p xhab-bridge --bench perf`),
//! so that regressions show up run to run: per scene, benchmarks named after the JSON fields
//! they stand for (`map_build` for `map_build_s`, `geodesic_pair_queries` for
//! `geodesic_pair_queries_per_s`, ...), each timing one operation as `xhab_bridge::scene_perf`
//! does; and `lidar_scan`, one scan of the navigation loop (part of `nav_real_time_factor`,
//! which is too long a run for a criterion sample). Scenes: the procedural house (always) and `scenes/turtlebot3_house.glb` from the
//! shared data (`$XHAB_DATA`, else `../shared`) when it is there. Rendering uses the CPU
//! rasteriser at 256 x 256 (the same renderer on every machine). Sample sizes are small, so
//! the whole suite runs in a few minutes; `cargo bench -p xhab-bridge --bench perf -- NAME`
//! runs the benchmarks whose name contains NAME.

use criterion::{criterion_group, criterion_main, BatchSize, Criterion, Throughput};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::Duration;
use xhab_bridge::setup::{self, CameraOptions, PhysicsOptions, SceneOptions};
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::sensors::{CameraParams, RendererKind};
use xhab_sim::world::World;

#[path = "../../../tests/support/data.rs"]
mod data;

/// A random discrete action without stop, as `xhab perf` draws them.
fn random_action(rng: &mut ChaCha8Rng) -> Action {
    match rng.gen_range(0..4) {
        0 | 1 => Action::MoveForward,
        2 => Action::TurnLeft,
        _ => Action::TurnRight,
    }
}

/// Every benchmark of one scene (`arg` as the SCENE argument), in the group `name`.
fn bench_scene(c: &mut Criterion, name: &str, arg: &str) {
    let opts = SceneOptions::default();
    let scene = setup::load_scene(arg, &opts).expect("scene loads");
    let params = setup::agent_params(&opts);
    let mut g = c.benchmark_group(name);
    g.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));

    // map_build_s: floor detection, navigation grid and corner graph.
    g.bench_function("map_build", |b| {
        b.iter(|| {
            let w = World::new(scene.clone(), params.clone());
            let f = w.default_floor().expect("a floor");
            black_box(w.grid(f).expect("a grid").corner_graph());
        })
    });

    let world = World::new(scene.clone(), params.clone());
    let grid = world.grid(world.default_floor().expect("a floor")).expect("a grid");
    let cells = grid.cells_on_islands(1.5);
    let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let points: Vec<_> = (0..64).map(|_| grid.sample_navigable_point(&cells, &mut rng).expect("a navigable point")).collect();

    // geodesic_pair_queries_per_s: cold point-to-point queries, a new pair each time.
    g.throughput(Throughput::Elements(1));
    let mut k = 0usize;
    g.bench_function("geodesic_pair_queries", |b| {
        b.iter(|| {
            k += 1;
            let (p, q) = (points[k % points.len()].xy(), points[(k * 7 + 3) % points.len()].xy());
            black_box(xhab_sim::geodesic::geodesic_distance(&grid, p, q))
        })
    });

    // Episodes from the sampled points, their starts built once.
    let starts: Vec<KinematicEnv> = (0..16)
        .filter_map(|i| {
            let ep = Episode {
                episode_id: i.to_string(),
                scene_id: arg.to_string(),
                start_position: points[i + 16],
                start_yaw: 0.0,
                goals: vec![Goal { position: points[i], radius: 0.2 }],
                geodesic_distance: None,
                info: serde_json::Value::Null,
            };
            KinematicEnv::new(grid.clone(), &ep, TaskConfig::default()).ok()
        })
        .collect();
    assert!(!starts.is_empty(), "{name}: no valid episode");

    // discrete_steps_per_s: random actions without rendering, 500 per episode.
    g.throughput(Throughput::Elements(500));
    let mut act_rng = ChaCha8Rng::seed_from_u64(11);
    let mut e = 0usize;
    g.bench_function("discrete_steps", |b| {
        b.iter_batched(
            || {
                e += 1;
                let actions: Vec<Action> = (0..500).map(|_| random_action(&mut act_rng)).collect();
                (starts[e % starts.len()].clone(), actions)
            },
            |(mut env, actions)| {
                for a in actions {
                    env.step(a);
                }
                black_box(env.distance_to_goal())
            },
            BatchSize::SmallInput,
        )
    });

    // depth_steps_per_s (and with RGB): one step and one 256 x 256 view.
    let (renderer, _) = setup::build_renderer(Some(RendererKind::Raster), &scene).expect("a renderer");
    let cam = setup::camera_params(&CameraOptions::default(), CameraParams::default().mount_height).expect("a camera");
    g.throughput(Throughput::Elements(1));
    for rgb in [false, true] {
        let mut env = starts[0].clone();
        let mut act_rng = ChaCha8Rng::seed_from_u64(17);
        g.bench_function(if rgb { "depth_rgb_steps" } else { "depth_steps" }, |b| {
            b.iter(|| {
                env.step(random_action(&mut act_rng));
                if env.is_done() {
                    env = starts[0].clone();
                }
                let floor_z = env.grid().floor_z;
                if rgb {
                    black_box(renderer.depth_rgb(env.pose(), floor_z, &cam).expect("renders"));
                } else {
                    black_box(renderer.depth(env.pose(), floor_z, &cam).expect("renders"));
                }
            })
        });
    }

    // physics_steps_per_s: raw physics steps of the default robot, driving and turning.
    let popts = PhysicsOptions::default();
    let profile = setup::robot_profile(&popts.robot).expect("a robot profile");
    let pscene = xhab_sim::robot::PhysicsScene::new(&scene).expect("a physics scene");
    let start = points[16];
    let mut robot = xhab_sim::robot::RigidRobot::new(&pscene, &profile, xhab_types::Pose2::new(start.x, start.y, 0.0), grid.floor_z, &popts.config().physics)
        .expect("the robot is placed");
    let mut n = 0u64;
    g.bench_function("physics_steps", |b| {
        b.iter(|| {
            n += 1;
            let twist = if (n / 120) % 2 == 1 { xhab_types::Twist { linear: 0.0, angular: 0.5 } } else { xhab_types::Twist { linear: 0.25, angular: 0.0 } };
            robot.step_physics(twist);
        })
    });

    // amcl_update_ms: 5,000 particles, 60 beams.
    let rs = setup::ray_scene(&scene).expect("a ray scene");
    let map = grid.occupancy_grid();
    let ap = xhab_nav::amcl::AmclParams {
        min_particles: xhab_bridge::scene_perf::PERF_AMCL_PARTICLES,
        max_particles: xhab_bridge::scene_perf::PERF_AMCL_PARTICLES,
        laser_max_beams: xhab_bridge::scene_perf::PERF_AMCL_BEAMS,
        ..Default::default()
    };
    let mut amcl = xhab_nav::amcl::Amcl::new(&map, ap, 1);
    let mut pose = xhab_types::Pose2::new(start.x, start.y, 0.0);
    amcl.init(pose, 0.2, 0.1);
    let mut lidar = xhab_sim::sensors::Lidar::new(xhab_sim::sensors::LidarParams { beams: 360, ..Default::default() }, 2);
    let scan = lidar.scan(&rs, pose, grid.floor_z);
    amcl.update(pose, &scan, xhab_types::Pose2::default());
    // The lidar scan the navigation loop takes every 0.1 s (360 beams against the scene's cut
    // at the scan plane), from a new pose each time.
    let mut q = 0usize;
    g.bench_function("lidar_scan", |b| {
        b.iter(|| {
            q += 1;
            let p = points[q % points.len()];
            black_box(lidar.scan(&rs, xhab_types::Pose2::new(p.x, p.y, q as f64 * 0.1), grid.floor_z))
        })
    });

    let mut m = 0u32;
    g.bench_function("amcl_update", |b| {
        b.iter(|| {
            // Alternate small moves so that every call passes update_min_d.
            m += 1;
            pose = pose.compose(xhab_types::Pose2::new(0.21 * if m % 2 == 1 { -1.0 } else { 1.0 }, 0.0, 0.0));
            black_box(amcl.update(pose, &scan, xhab_types::Pose2::default()))
        })
    });
    g.finish();
}

fn perf(c: &mut Criterion) {
    bench_scene(c, "house", "procedural");
    if let Some(d) = data::data_dir("perf bench on turtlebot3_house") {
        let p = d.join("scenes").join("turtlebot3_house.glb");
        if p.is_file() {
            bench_scene(c, "turtlebot3_house", &p.to_string_lossy());
        } else {
            eprintln!("SKIPPED turtlebot3_house: {} not found", p.display());
        }
    }
}

criterion_group!(benches, perf);
criterion_main!(benches);
