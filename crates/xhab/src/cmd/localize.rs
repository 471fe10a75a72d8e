//! `xhab localize`: global localisation trials (AMCL from a uniform spread).

use crate::cli::LocalizeArgs;
use crate::scene_arg::load_world;
use anyhow::{Context, Result};
use std::process::ExitCode;
use std::sync::Arc;
use xhab_bridge::global_localization::{run_trials, GlobalLocConfig};
use xhab_bridge::nav_agent::{Localization, NavSetup};
use xhab_sim::robot::RobotProfile;
use xhab_bridge::scan_source::ScanSource;
use xhab_sim::sensors::RayScene;

pub fn run(a: &LocalizeArgs) -> Result<ExitCode> {
    let mut opts = a.scene_opts.clone();
    let mut ph = a.physics.clone();
    ph.physics = true;
    let profile = RobotProfile::named_or_file(&ph.robot).with_context(|| format!("--robot {}", ph.robot))?;
    opts.agent_radius.get_or_insert(profile.radius);
    let world = load_world(&a.scene, &opts)?;
    let ds = xhab_sim::episode::read_dataset(&a.episodes).with_context(|| format!("reading episodes {}", a.episodes.display()))?;
    let physics = super::bench::physics_setup(&world, &ph)?.context("physics setup")?;
    let mut params = super::nav_params(&a.nav_params, Some(&profile))?;
    if a.particles == 0 {
        anyhow::bail!("--particles must be at least 1");
    }
    params.amcl.max_particles = a.particles;
    let rs = RayScene::new(&world.scene).context("the scene has no triangles to scan")?;
    let setup = NavSetup { params, map: None, localization: Localization::Amcl, scan: Some(ScanSource::lidar(Arc::new(rs), profile.laser.lidar())), scan_period: 0.1 };
    let map = match &a.map {
        Some(m) => Some(xhab_nav::map_server::load_map(m).with_context(|| format!("loading map {}", m.display()))?.0),
        None => None,
    };
    let cfg = GlobalLocConfig { tolerance: a.tolerance, max_travel: a.max_travel, seed: a.seed };
    let t = std::time::Instant::now();
    let trials = run_trials(&world, &ds.episodes, a.trials, &physics, &setup, map.as_ref(), &cfg);
    let n = trials.len().max(1) as f64;
    let conv = trials.iter().filter(|t| t.converged).count();
    let mean_travel = trials.iter().filter_map(|t| t.travel_at_convergence_m).sum::<f64>() / conv.max(1) as f64;
    let still = trials.iter().filter(|t| t.final_error_m < a.tolerance).count();
    let report = serde_json::json!({
        "scene": a.scene,
        "trials": trials.len(),
        "tolerance_m": a.tolerance,
        "particles": a.particles,
        "amcl": setup.params.amcl,
        "max_travel_m": a.max_travel,
        "converged_fraction": conv as f64 / n,
        "mean_travel_at_convergence_m": mean_travel,
        "within_tolerance_at_end_fraction": still as f64 / n,
        "wall_s": t.elapsed().as_secs_f64(),
        "per_trial": trials,
    });
    if let Some(out) = &a.out {
        super::ensure_parent(out)?;
        std::fs::write(out, serde_json::to_string_pretty(&report)? + "\n").with_context(|| format!("writing {}", out.display()))?;
    }
    println!(
        "global localisation: {conv}/{} trials converged (< {} m within {} m of travel; mean travel {:.2} m); {still} within tolerance at the end",
        trials.len(), a.tolerance, a.max_travel, mean_travel
    );
    Ok(ExitCode::SUCCESS)
}
