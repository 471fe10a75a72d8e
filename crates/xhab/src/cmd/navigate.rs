//! `xhab navigate`: one run of the native stack under physics, drawn over the map. Parses the
//! flags into the library's [`NavigateOptions`], calls [`navigate_once`], prints.

use crate::cli::NavigateArgs;
use crate::scene_arg::scene_options;
use anyhow::{bail, Result};
use std::process::ExitCode;
use xhab_bridge::navigate::{navigate_once, NavigateOptions};
use xhab_bridge::runner::Outcome;
use xhab_types::{Point2, Pose2};

/// `n` comma-separated finite numbers of the flag `what`.
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
    let o = NavigateOptions {
        scene: a.scene.clone(),
        scene_options: scene_options(&a.scene_opts),
        map: a.map.clone(),
        start: Pose2::new(s[0], s[1], s[2]),
        goal: Point2::new(g[0], g[1]),
        nav_params: a.nav_params.clone(),
        robot: a.robot.clone(),
        time_limit: a.time_limit,
    };
    let run = navigate_once(&o)?;
    for w in &run.warnings {
        eprintln!("xhab: warning: {w}");
    }
    let code = match &run.outcome {
        Outcome::Ran(r) => {
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
    super::ensure_parent(&a.out)?;
    run.picture().save(&a.out)?;
    eprintln!("xhab: wrote {}", a.out.display());
    Ok(code)
}
