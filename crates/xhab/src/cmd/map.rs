//! `xhab map`: a map_server map and a picture of a scene's floor, derived from the scene's
//! geometry or (`--explore`) built by a robot exploring it.

use crate::cli::{CameraOpts, MapArgs, SceneOpts};
use crate::scene_arg::{floor_index, load_geometry, scene_options};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use xhab_bridge::exploration_run::{explore_scene, ExploreOptions};
use xhab_types::{OccupancyGrid, Pose2};

pub fn run(a: &MapArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let mut opts = a.scene_opts.clone();
    opts.cell_size = a.resolution;
    if a.explore {
        return explore(a, &opts, t0);
    }
    let world = load_geometry(&a.scene, &opts)?;
    if a.floor == "all" {
        let yamls = xhab_bridge::setup::write_storey_maps(&world, &a.out, a.laser_height).with_context(|| format!("writing the storeys' maps of {}", a.scene))?;
        for (k, y) in yamls.iter().enumerate() {
            eprintln!("xhab: wrote {} (storey {k}, floor at {:.3} m)", y.display(), world.floors[k].z);
        }
        eprintln!("xhab: wrote {}.png (all {} storeys side by side) in {:.2} s", a.out.display(), yamls.len(), t0.elapsed().as_secs_f64());
        return Ok(ExitCode::SUCCESS);
    }
    let floor = floor_index(&world, &a.floor)?;
    let grid = world.grid(floor).with_context(|| format!("building the map of {}", a.scene))?;
    let map = xhab_bridge::setup::floor_map(&world, &grid, a.laser_height)?;
    let (yaml, png) = write_map(&map, &a.out)?;
    let (free, occ) = counts(&map);
    eprintln!(
        "xhab: wrote {} ({}x{} cells at {} m, floor at {:.3} m, {:.1} m^2 free, {} occupied cells) and {} in {:.2} s",
        yaml.display(),
        map.width,
        map.height,
        map.resolution,
        world.floors[floor].z,
        free as f64 * map.resolution * map.resolution,
        occ,
        png.display(),
        t0.elapsed().as_secs_f64()
    );
    Ok(ExitCode::SUCCESS)
}

/// `--explore`: the robot explores the floor; writes the map it built, its path drawn on the
/// picture, and how the map agrees with the one derived from the geometry.
fn explore(a: &MapArgs, opts: &SceneOpts, t0: Instant) -> Result<ExitCode> {
    let start = match &a.start {
        Some(s) => {
            let v = super::navigate::numbers(s, 3, "--start (X,Y,YAW)")?;
            Some(Pose2::new(v[0], v[1], v[2]))
        }
        None => None,
    };
    let o = ExploreOptions {
        scene: a.scene.clone(),
        scene_options: scene_options(opts),
        floor: a.floor.clone(),
        robot: a.robot.clone(),
        start,
        nav_params: a.nav_params.clone(),
        max_time: a.max_time,
        seed: a.seed,
        renderer: super::render::camera_options(&CameraOpts { renderer: a.renderer, resolution: 256, hfov: 90.0, camera_height: None, batch: None }).renderer,
    };
    let run = explore_scene(&o)?;
    super::render::print_renderer_note(&run.renderer_note);
    for w in &run.warnings {
        eprintln!("xhab: warning: {w}");
    }
    let x = &run.exploration;
    let (yaml, png) = write_map(&x.map, &a.out)?;
    run.picture().save(&png)?;
    let agree = &run.agreement;
    let (free_m2, occ) = run.counts();
    let report = serde_json::json!({
        "scene": a.scene,
        "robot": run.robot,
        "start": [run.start.x, run.start.y, run.start.yaw],
        "end": x.end,
        "sim_s": x.sim_s,
        "travel_m": x.travel_m,
        "targets_reached": x.targets_reached,
        "targets_abandoned": x.targets_abandoned,
        "free_m2": free_m2,
        "occupied_cells": occ,
        "reference_free_coverage": agree.free_coverage,
        "connected_free_coverage": agree.connected_free_coverage,
        "free_occupied_in_reference": agree.free_occupied_in_reference,
        "wall_s": t0.elapsed().as_secs_f64(),
        "map": yaml,
    });
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    }
    eprintln!(
        "xhab: explored for {:.0} s simulated ({:.1} m driven, {} frontiers reached, {} abandoned, ended: {:?}) in {:.2} s; \
         the map covers {:.1}% of the free space of the scene's map ({:.1}% of the part connected to the start), \
         {:.2}% of its free cells are occupied there; wrote {} and {}",
        x.sim_s,
        x.travel_m,
        x.targets_reached,
        x.targets_abandoned,
        x.end,
        t0.elapsed().as_secs_f64(),
        100.0 * agree.free_coverage,
        100.0 * agree.connected_free_coverage,
        100.0 * agree.free_occupied_in_reference,
        yaml.display(),
        png.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Writes OUT.yaml + OUT.pgm (map_server) and OUT.png; returns the YAML and PNG paths.
pub fn write_map(map: &OccupancyGrid, out: &Path) -> Result<(PathBuf, PathBuf)> {
    Ok(xhab_bridge::setup::write_map(map, out)?)
}

fn counts(m: &OccupancyGrid) -> (usize, usize) {
    let free = m.data.iter().filter(|&&v| v == xhab_types::GRID_FREE).count();
    let occ = m.data.iter().filter(|&&v| v == xhab_types::GRID_OCCUPIED).count();
    (free, occ)
}
