//! `xhab navigate`: one run of the native stack under physics, drawn over the map.

use crate::cli::NavigateArgs;
use xhab_bridge::map_picture::MapPicture;
use crate::scene_arg::load_world;
use anyhow::{bail, Context, Result};
use std::process::ExitCode;
use std::sync::Arc;
use xhab_bridge::nav_agent::{Localization, NavSetup};
use xhab_bridge::runner::{run_episode, Outcome, PhysicsSetup, RunConfig};
use xhab_bridge::agents::AgentKind;
use xhab_nav::costmap::Costmap;
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::physics_env::PhysicsConfig;
use xhab_sim::robot::{PhysicsScene, RobotProfile};
use xhab_types::{Point2, Point3};

pub(crate) fn numbers(s: &str, n: usize, what: &str) -> Result<Vec<f64>> {
    let v: Vec<f64> = s.split(',').map(|t| t.trim().parse::<f64>()).collect::<std::result::Result<_, _>>().map_err(|_| anyhow::anyhow!("bad {what} '{s}'"))?;
    if v.len() != n || v.iter().any(|x| !x.is_finite()) {
        bail!("bad {what} '{s}': expected {n} finite numbers");
    }
    Ok(v)
}

pub fn run(a: &NavigateArgs) -> Result<ExitCode> {
    let s = numbers(&a.start, 3, "--start (X,Y,YAW)")?;
    let g = numbers(&a.goal, 2, "--goal (X,Y)")?;
    let profile = RobotProfile::named_or_file(&a.robot).with_context(|| format!("--robot {}", a.robot))?;
    let mut opts = a.scene_opts.clone();
    opts.agent_radius.get_or_insert(profile.radius);
    let world = load_world(&a.scene, &opts)?;
    let floor = world.default_floor().context("no floor")?;
    let z = world.floors[floor].z;
    let params = super::nav_params(&a.nav_params, Some(&profile))?;
    let map = match &a.map {
        Some(m) => xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0,
        None => world.grid(floor)?.occupancy_grid(),
    };
    let ep = Episode {
        episode_id: "navigate".into(),
        scene_id: a.scene.clone(),
        start_position: Point3::new(s[0], s[1], z),
        start_yaw: s[2],
        goals: vec![Goal { position: Point3::new(g[0], g[1], z), radius: 0.2 }],
        geodesic_distance: None,
        info: serde_json::Value::Null,
    };
    let physics = PhysicsSetup { scene: Arc::new(PhysicsScene::new(&world.scene)?), profile, config: PhysicsConfig::default() };
    let task = TaskConfig { max_episode_steps: (a.time_limit / physics.config.control_period).ceil() as u32, ..Default::default() };
    let rs = xhab_sim::sensors::RayScene::new(&world.scene).context("the scene has no triangles")?;
    let nav = NavSetup {
        params: params.clone(),
        map: Some(Arc::new(map.clone())),
        localization: Localization::GroundTruth,
        scan: Some(xhab_bridge::scan_source::ScanSource::lidar(Arc::new(rs), physics.profile.laser.lidar())),
        scan_period: 0.1,
    };
    let cfg = RunConfig { agent: AgentKind::Nav, task, threads: 1, record_trajectories: true, sensors: None, physics: Some(physics), seed: 0, nav: Some(nav), episode_indices: None };
    let outcome = run_episode(&world, &ep, 0, &cfg);
    let mut pic = MapPicture::new(&map);
    let cm = Costmap::from_map(&map, &params.global_costmap);
    if let Ok(plan) = xhab_nav::planner::plan(&cm, Point2::new(s[0], s[1]), Point2::new(g[0], g[1]), &params.planner) {
        let pts: Vec<Point2> = plan.iter().map(|p| p.position()).collect();
        pic.polyline(&pts, [60, 160, 255]);
    }
    let code = match &outcome {
        Outcome::Ran(r) => {
            if let Some(t) = &r.trajectory {
                let pts: Vec<Point2> = t.iter().map(|p| p.position()).collect();
                pic.polyline(&pts, [230, 120, 0]);
            }
            let m = &r.metrics;
            println!(
                "{}: path {:.2} m (geodesic {:.2} m), {:.1} s simulated, final distance {:.3} m, SPL {:.3}",
                if m.success > 0.0 { "reached" } else { "failed" },
                m.path_length,
                m.start_distance,
                r.sim_s.unwrap_or(0.0),
                m.distance_to_goal,
                m.spl
            );
            if m.success > 0.0 { ExitCode::SUCCESS } else { ExitCode::from(1) }
        }
        Outcome::Invalid(i) => bail!("cannot navigate: {}", i.reason),
    };
    pic.dot(Point2::new(s[0], s[1]), 4, [0, 170, 0]);
    pic.dot(Point2::new(g[0], g[1]), 4, [220, 0, 0]);
    super::ensure_parent(&a.out)?;
    pic.save(&a.out)?;
    eprintln!("xhab: wrote {}", a.out.display());
    Ok(code)
}
