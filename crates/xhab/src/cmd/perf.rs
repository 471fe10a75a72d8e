//! `xhab perf`: speed figures of one scene, as JSON.
//!
//! Each figure times only the operation it names: map build (floor detection, the
//! navigation grid and its corner graph, as habitat's navmesh build includes its path
//! finder), geodesic queries against an episode's goal field (the per-step
//! `distance_to_goal`), the goal field's build (an episode's setup), cold point-to-point
//! queries, and discrete steps (motion with sliding plus the step's metric update) without
//! rendering.

use crate::cli::PerfArgs;
use crate::scene_arg::{agent_params, load_scene};
use anyhow::{Context, Result};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::process::ExitCode;
use std::time::Instant;
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, Env, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::goal_field::GoalField;
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::world::World;

pub fn run(a: &PerfArgs) -> Result<ExitCode> {
    let scene = load_scene(&a.scene, &a.scene_opts)?;
    let tris = scene.triangle_count();
    let params = agent_params(&a.scene_opts);
    // Map build: best of three (floor detection + grid).
    let mut build_s = f64::INFINITY;
    let mut world = None;
    for _ in 0..3 {
        let t = Instant::now();
        let w = World::new(scene.clone(), params.clone());
        let f = w.default_floor().context("no walkable floor")?;
        w.grid(f)?.corner_graph();
        build_s = build_s.min(t.elapsed().as_secs_f64());
        world = Some(w);
    }
    let world = world.context("no world")?;
    let grid = world.grid(world.default_floor().context("no floor")?)?;
    let cells = grid.cells_on_islands(1.5);
    let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut sample = || grid.sample_navigable_point(&cells, &mut rng).context("no navigable point");

    // Geodesic fields and queries.
    let goals: Vec<_> = (0..8).map(|_| sample()).collect::<Result<_>>()?;
    let queries: Vec<_> = (0..4096).map(|_| sample().map(|p| p.xy())).collect::<Result<_>>()?;
    let mut field_s = 0.0;
    let mut fields = Vec::new();
    for g in &goals {
        let t = Instant::now();
        fields.push(GoalField::new(&grid, &[g.xy()]));
        field_s += t.elapsed().as_secs_f64();
    }
    let field_s = field_s / goals.len() as f64;
    let mut checksum = 0.0;
    // Cold point-to-point queries: a goal-directed search per pair.
    let t = Instant::now();
    let mut pairs = 0u64;
    while t.elapsed().as_secs_f64() < a.seconds * 0.25 || pairs < 8 {
        let (p, q) = (queries[pairs as usize % queries.len()], goals[pairs as usize % goals.len()].xy());
        let d = xhab_sim::geodesic::geodesic_distance(&grid, p, q);
        if d.is_finite() {
            checksum += d;
        }
        pairs += 1;
    }
    let pair_rate = pairs as f64 / t.elapsed().as_secs_f64();
    let (mut nq, mut q_s) = (0u64, 0.0);
    while q_s < a.seconds * 0.5 {
        let t = Instant::now();
        for f in &fields {
            for q in &queries {
                let d = f.distance(&grid, *q);
                if d.is_finite() {
                    checksum += d;
                }
            }
        }
        q_s += t.elapsed().as_secs_f64();
        nq += (fields.len() * queries.len()) as u64;
    }

    // Discrete steps: random actions (no stop) and the oracle, timing env.step only.
    let episodes: Vec<Episode> = (0..16)
        .map(|i| -> Result<Episode> {
            let s = sample()?;
            let g = goals[i % goals.len()];
            Ok(Episode {
                episode_id: i.to_string(),
                scene_id: a.scene.clone(),
                start_position: s,
                start_yaw: 0.0,
                goals: vec![Goal { position: g, radius: 0.2 }],
                geodesic_distance: None,
                info: serde_json::Value::Null,
            })
        })
        .collect::<Result<_>>()?;
    // Each episode's start (its goal field included) is built once and cloned for every run.
    let starts: Vec<Env> = episodes.iter().filter_map(|ep| Env::new(grid.clone(), ep, TaskConfig::default()).ok()).collect();
    if starts.is_empty() {
        anyhow::bail!("no valid episode to step (no sampled start reaches its goal)");
    }
    let mut act_rng = ChaCha8Rng::seed_from_u64(11);
    let (mut steps, mut step_s) = (0u64, 0.0);
    let (mut osteps, mut ostep_s) = (0u64, 0.0);
    while step_s + ostep_s < a.seconds {
        for start in &starts {
            let mut env = start.clone();
            let actions: Vec<Action> = (0..500)
                .map(|_| random_action(&mut act_rng))
                .collect();
            let t = Instant::now();
            for &act in &actions {
                env.step(act);
            }
            checksum += env.distance_to_goal().min(1e3);
            step_s += t.elapsed().as_secs_f64();
            steps += actions.len() as u64;

            let mut env = start.clone();
            let mut oracle = ShortestPathFollower::new();
            let t = Instant::now();
            while !env.is_done() {
                let act = oracle.act(&env);
                env.step(act);
                osteps += 1;
            }
            ostep_s += t.elapsed().as_secs_f64();
        }
    }
    let mut j = serde_json::json!({
        "scene": a.scene,
        "triangles": tris,
        "floor_height_m": grid.floor_z,
        "navigable_area_m2": grid.navigable_cells() as f64 * grid.resolution().powi(2),
        "cell_size_m": grid.resolution(),
        "map_build_s": build_s,
        "geodesic_queries_per_s": nq as f64 / q_s,
        "geodesic_field_build_s": field_s,
        "geodesic_pair_queries_per_s": pair_rate,
        "discrete_steps_per_s": steps as f64 / step_s,
        "oracle_steps_per_s": osteps as f64 / ostep_s,
        "threads": 1,
        "checksum": checksum,
    });
    if !a.sensors.is_empty() {
        let sp = sensor_perf(&world, &starts, a)?;
        if let (Some(m), serde_json::Value::Object(p)) = (j.as_object_mut(), sp) {
            m.extend(p);
        }
    }
    if a.amcl {
        let ap = amcl_perf(&world, &grid, &episodes, a)?;
        if let (Some(m), serde_json::Value::Object(p)) = (j.as_object_mut(), ap) {
            m.extend(p);
        }
    }
    if a.nav {
        let np = xhab_bridge::nav_perf::nav_perf(&world, &a.scene, &a.physics.robot)?;
        if let (Some(m), serde_json::Value::Object(p)) = (j.as_object_mut(), serde_json::to_value(np)?) {
            m.extend(p);
        }
    }
    if a.physics.physics {
        let ph = physics_perf(&world, &grid, &episodes, a)?;
        if let (Some(m), serde_json::Value::Object(p)) = (j.as_object_mut(), ph) {
            m.extend(p);
        }
    }
    if a.json {
        println!("{j}");
    } else {
        println!("{}", serde_json::to_string_pretty(&j)?);
    }
    Ok(ExitCode::SUCCESS)
}

/// Physics figures: raw physics steps of one robot, and discrete actions via Algorithm 1.
fn physics_perf(world: &World, grid: &std::sync::Arc<xhab_sim::navgrid::NavGrid>, episodes: &[Episode], a: &PerfArgs) -> Result<serde_json::Value> {
    use xhab_sim::physics_env::{PhysicsConfig, PhysicsEnv};
    use xhab_sim::robot::{PhysicsParams, PhysicsScene, RigidRobot, RobotProfile};
    use xhab_types::Twist;
    let profile = RobotProfile::named_or_file(&a.physics.robot)?;
    let t = Instant::now();
    let scene = PhysicsScene::new(&world.scene)?;
    let mesh_s = t.elapsed().as_secs_f64();
    let params = PhysicsParams { steps_per_sec: a.physics.steps_per_sec, ..Default::default() };
    let ep = &episodes[0];
    let start = xhab_types::Pose2::new(ep.start_position.x, ep.start_position.y, 0.0);
    let mut robot = RigidRobot::new(&scene, &profile, start, grid.floor_z, &params)?;
    let (mut n, t) = (0u64, Instant::now());
    while t.elapsed().as_secs_f64() < a.seconds * 0.5 {
        for k in 0..600 {
            // Drive forward and turn in alternating two-second blocks: contacts included.
            let twist = if (k / 120) % 2 == 0 { Twist { linear: 0.25, angular: 0.0 } } else { Twist { linear: 0.0, angular: 0.5 } };
            robot.step_physics(twist);
        }
        n += 600;
    }
    let steps_per_s = n as f64 / t.elapsed().as_secs_f64();
    let mut act_rng = ChaCha8Rng::seed_from_u64(13);
    let config = PhysicsConfig { control_period: a.physics.control_period, physics: params, ..Default::default() };
    let (mut actions, mut act_s) = (0u64, 0.0);
    while act_s < a.seconds * 0.5 {
        for (i, ep) in episodes.iter().enumerate() {
            let Ok(mut env) = PhysicsEnv::new(grid.clone(), &scene, ep, TaskConfig::default(), &profile, config.clone(), i as u64) else { continue };
            let t = Instant::now();
            for _ in 0..50 {
                let act = random_action(&mut act_rng);
                env.step(act);
            }
            act_s += t.elapsed().as_secs_f64();
            actions += 50;
        }
    }
    Ok(serde_json::json!({
        "robot": profile.name,
        "physics_mesh_build_s": mesh_s,
        "physics_steps_per_s": steps_per_s,
        "physics_action_steps_per_s": actions as f64 / act_s,
        "physics_real_time_factor": steps_per_s / a.physics.steps_per_sec,
    }))
}

/// Discrete steps that render the camera at every step (`--sensors depth[,rgb]`), and with
/// `--batch N` views rendered N at a time (N agents stepping together).
fn sensor_perf(world: &World, starts: &[Env], a: &PerfArgs) -> Result<serde_json::Value> {
    for s in &a.sensors {
        if s != "depth" && s != "rgb" {
            anyhow::bail!("--sensors: unknown sensor '{s}' (depth, rgb)");
        }
    }
    let cam = super::render::camera(&a.camera, xhab_sim::sensors::CameraParams::default().mount_height)?;
    let rgb = a.sensors.iter().any(|s| s == "rgb");
    let t = Instant::now();
    let r = super::render::renderer(&a.camera, &world.scene)?;
    let build_s = t.elapsed().as_secs_f64();
    let mut act_rng = ChaCha8Rng::seed_from_u64(17);
    let (mut steps, mut s) = (0u64, 0.0);
    let mut checksum = 0.0f64;
    while s < a.seconds {
        for start in starts {
            let mut env = start.clone();
            let floor_z = env.grid().floor_z;
            let t = Instant::now();
            for _ in 0..50 {
                let act = random_action(&mut act_rng);
                env.step(act);
                let img = if rgb {
                    let (d, c) = r.depth_rgb(env.pose(), floor_z, &cam)?;
                    checksum += c[c.len() / 2] as f64;
                    d
                } else {
                    r.depth(env.pose(), floor_z, &cam)?
                };
                checksum += img.data[img.data.len() / 2] as f64;
            }
            s += t.elapsed().as_secs_f64();
            steps += 50;
            if s >= a.seconds {
                break;
            }
        }
    }
    let mut out = serde_json::json!({
        "renderer": r.name(),
        "sensors": a.sensors,
        "resolution": cam.width,
        "render_threads": rayon::current_num_threads(),
        "sensor_build_s": build_s,
        "depth_steps_per_s": steps as f64 / s,
        "sensor_checksum": checksum,
    });
    if let Some(n) = a.camera.batch.filter(|&n| n > 0) {
        // N agents, each stepping its own episode; their N views rendered in one call.
        let mut envs: Vec<Env> = starts.iter().cycle().take(n).cloned().collect();
        let (mut views_done, mut s) = (0u64, 0.0);
        while s < a.seconds {
            let t = Instant::now();
            for _ in 0..20 {
                let views: Vec<(xhab_types::Pose2, f64)> = envs.iter_mut().map(|e| {
                    e.step(random_action(&mut act_rng));
                    (e.pose(), e.grid().floor_z)
                }).collect();
                let imgs = r.depth_batch(&views, &cam)?;
                checksum += imgs.iter().map(|i| i.data[i.data.len() / 2] as f64).sum::<f64>();
                views_done += views.len() as u64;
            }
            s += t.elapsed().as_secs_f64();
        }
        out["batch"] = serde_json::json!(envs.len());
        out["depth_batch_steps_per_s"] = serde_json::json!(views_done as f64 / s);
        out["sensor_checksum"] = serde_json::json!(checksum);
    }
    Ok(out)
}

/// A random discrete action without stop: forward half the time, turns otherwise.
fn random_action(rng: &mut ChaCha8Rng) -> Action {
    match rng.gen_range(0..4) {
        0 | 1 => Action::MoveForward,
        2 => Action::TurnLeft,
        _ => Action::TurnRight,
    }
}

/// AMCL update time with 5,000 particles and 60 beams (motion model, weighting, resampling
/// every second update), on one core.
fn amcl_perf(world: &World, grid: &std::sync::Arc<xhab_sim::navgrid::NavGrid>, episodes: &[Episode], a: &PerfArgs) -> Result<serde_json::Value> {
    use xhab_nav::amcl::{Amcl, AmclParams};
    use xhab_sim::sensors::{Lidar, LidarParams, RayScene};
    let rs = RayScene::new(&world.scene).context("the scene has no triangles")?;
    let map = grid.occupancy_grid();
    // Exactly 5,000 particles: init() spreads max(min, max / 2) and KLD may not go below min.
    let params = AmclParams { min_particles: 5000, max_particles: 5000, laser_max_beams: 60, ..Default::default() };
    let mut amcl = Amcl::new(&map, params, 1);
    let start = episodes[0].start_position;
    let mut pose = xhab_types::Pose2::new(start.x, start.y, 0.0);
    amcl.init(pose, 0.2, 0.1);
    let mut lidar = Lidar::new(LidarParams { beams: 360, ..Default::default() }, 2);
    let scan = lidar.scan(&rs, pose, grid.floor_z);
    amcl.update(pose, &scan, xhab_types::Pose2::default());
    let (mut n, mut s) = (0u32, 0.0);
    while s < a.seconds || n < 10 {
        // Alternate small moves so that every call passes update_min_d.
        pose = pose.compose(xhab_types::Pose2::new(0.21 * if n % 2 == 0 { 1.0 } else { -1.0 }, 0.0, 0.0));
        let t = Instant::now();
        amcl.update(pose, &scan, xhab_types::Pose2::default());
        s += t.elapsed().as_secs_f64();
        n += 1;
    }
    Ok(serde_json::json!({ "amcl_particles": amcl.len(), "amcl_beams": 60, "amcl_update_ms": 1000.0 * s / n as f64 }))
}
