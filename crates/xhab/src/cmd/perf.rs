//! `xhab perf`: speed figures of one scene, as JSON. Parses the flags into the library's
//! [`PerfOptions`], calls [`measure_scene`], prints.

use crate::cli::{PerfArgs, PerfGroupArg};
use crate::scene_arg::scene_options;
use anyhow::Result;
use std::process::ExitCode;
use xhab_bridge::scene_perf::{measure_scene, PerfGroup, PerfOptions};

pub fn run(a: &PerfArgs) -> Result<ExitCode> {
    let o = PerfOptions {
        scene: a.scene.clone(),
        scene_options: scene_options(&a.scene_opts),
        seconds: a.seconds,
        physics: super::bench::physics_options(&a.physics),
        measure_physics: a.physics.physics,
        sensors: a.sensors.clone(),
        camera: super::render::camera_options(&a.camera),
        batch: a.camera.batch,
        amcl: a.amcl,
        nav: a.nav,
        groups: a.only.iter().map(|&g| perf_group(g)).collect(),
    };
    let perf = measure_scene(&o)?;
    if let Some(note) = &perf.renderer_note {
        super::render::print_renderer_note(note);
    }
    // Through a Value, whose keys are sorted: the order `xhab perf` has always printed.
    let j = serde_json::to_value(&perf)?;
    if a.json {
        println!("{j}");
    } else {
        println!("{}", serde_json::to_string_pretty(&j)?);
    }
    Ok(ExitCode::SUCCESS)
}

/// The library's group of a `--only` value.
fn perf_group(g: PerfGroupArg) -> PerfGroup {
    match g {
        PerfGroupArg::Geodesic => PerfGroup::Geodesic,
        PerfGroupArg::Grid => PerfGroup::Grid,
        PerfGroupArg::Discrete => PerfGroup::Discrete,
        PerfGroupArg::Physics => PerfGroup::Physics,
        PerfGroupArg::Sensors => PerfGroup::Sensors,
        PerfGroupArg::Amcl => PerfGroup::Amcl,
    }
}
