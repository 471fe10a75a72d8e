//! `xhab localize`: global localisation trials (AMCL from a uniform spread). Parses the flags
//! into the library's [`LocalizeOptions`], calls [`run_localize`], prints.

use crate::cli::LocalizeArgs;
use crate::scene_arg::scene_options;
use anyhow::{Context, Result};
use std::process::ExitCode;
use xhab_bridge::global_localization::{run_localize, GlobalLocConfig, LocalizeOptions};

pub fn run(a: &LocalizeArgs) -> Result<ExitCode> {
    let o = LocalizeOptions {
        scene: a.scene.clone(),
        scene_options: scene_options(&a.scene_opts),
        episodes: a.episodes.clone(),
        trials: a.trials,
        config: GlobalLocConfig { tolerance: a.tolerance, max_travel: a.max_travel, seed: a.seed },
        map: a.map.clone(),
        nav_params: a.nav_params.clone(),
        particles: a.particles,
        // The trials always run under physics, with --robot.
        physics: super::bench::physics_options(&a.physics),
    };
    let report = run_localize(&o)?;
    for w in &report.warnings {
        eprintln!("xhab: warning: {w}");
    }
    if let Some(out) = &a.out {
        super::ensure_parent(out)?;
        // Through a Value, whose keys are sorted: the order `xhab localize` has always written.
        let json = serde_json::to_value(&report)?;
        std::fs::write(out, serde_json::to_string_pretty(&json)? + "\n").with_context(|| format!("writing {}", out.display()))?;
    }
    println!(
        "global localisation: {}/{} trials converged (< {} m within {} m of travel; mean travel {:.2} m); {} within tolerance at the end",
        report.converged(), report.trials, report.tolerance_m, report.max_travel_m, report.mean_travel_at_convergence_m, report.within_tolerance_at_end()
    );
    Ok(ExitCode::SUCCESS)
}
