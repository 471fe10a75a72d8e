//! `xhab map`: a map_server map and a picture of a scene's floor, derived from the scene's
//! geometry or (`--explore`) built by a robot exploring it.

use crate::cli::{CameraOpts, MapArgs};
use xhab_bridge::map_picture::MapPicture;
use crate::scene_arg::{floor_index, load_world};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use xhab_bridge::explore::{default_start, ExploreParams, ExploreSensors};
use xhab_nav::map_agreement::map_agreement;
use xhab_sim::navgrid::NavGrid;
use xhab_sim::robot::{PhysicsScene, RobotProfile};
use xhab_sim::sensors::RayScene;
use xhab_sim::world::World;
use xhab_types::{OccupancyGrid, Point2, Pose2};

pub fn run(a: &MapArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let mut opts = a.scene_opts.clone();
    opts.cell_size = a.resolution;
    let profile = if a.explore { Some(RobotProfile::named_or_file(&a.robot).with_context(|| format!("--robot {}", a.robot))?) } else { None };
    if let Some(p) = &profile {
        opts.agent_radius.get_or_insert(p.radius);
    }
    let world = load_world(&a.scene, &opts)?;
    let floor = floor_index(&world, &a.floor)?;
    let grid = world.grid(floor).with_context(|| format!("building the map of {}", a.scene))?;
    if let Some(profile) = profile {
        return explore(a, &world, &grid, profile, t0);
    }
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
fn explore(a: &MapArgs, world: &World, grid: &NavGrid, profile: RobotProfile, t0: Instant) -> Result<ExitCode> {
    let nav = super::nav_params(&a.nav_params, Some(&profile))?;
    let start = match &a.start {
        Some(s) => {
            let v = super::navigate::numbers(s, 3, "--start (X,Y,YAW)")?;
            Pose2::new(v[0], v[1], v[2])
        }
        None => default_start(grid).context("the floor has no navigable cell to start from")?,
    };
    if !grid.is_navigable(start.position()) {
        anyhow::bail!("--start ({:.2}, {:.2}) is not navigable for the robot", start.x, start.y);
    }
    let physics = PhysicsScene::new(&world.scene)?;
    let rays = RayScene::new(&world.scene).context("the scene has no triangles to scan")?;
    let cam_opts = CameraOpts { renderer: a.renderer, resolution: 256, hfov: 90.0, camera_height: Some(profile.camera_height), batch: None };
    let renderer = super::render::renderer(&cam_opts, &world.scene)?;
    let cam = super::render::camera(&cam_opts, profile.camera_height)?;
    let mut params = ExploreParams { max_time: a.max_time, ..Default::default() };
    // Obstacles are what the robot would hit: from the highest step it climbs to its height.
    params.projection.min_obstacle_height = grid.params.max_climb;
    params.projection.max_obstacle_height = profile.height;
    let sensors = ExploreSensors { rays: &rays, camera: Some((&renderer, cam)) };
    let run = xhab_bridge::explore::explore(grid, &physics, &sensors, &profile, &nav, &params, start, a.seed)?;
    let (yaml, png) = write_map(&run.map, &a.out)?;
    let mut pic = MapPicture::new(&run.map);
    let pts: Vec<Point2> = run.trajectory.iter().map(|p| p.position()).collect();
    pic.polyline(&pts, [230, 120, 0]);
    pic.dot(start.position(), 4, [0, 170, 0]);
    pic.save(&png)?;
    let reference = grid.occupancy_grid();
    let agree = map_agreement(&run.map, &reference, start.position());
    let (free, occ) = counts(&run.map);
    let report = serde_json::json!({
        "scene": a.scene,
        "robot": profile.name,
        "start": [start.x, start.y, start.yaw],
        "end": run.end,
        "sim_s": run.sim_s,
        "travel_m": run.travel_m,
        "targets_reached": run.targets_reached,
        "targets_abandoned": run.targets_abandoned,
        "free_m2": free as f64 * run.map.resolution * run.map.resolution,
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
        run.sim_s,
        run.travel_m,
        run.targets_reached,
        run.targets_abandoned,
        run.end,
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
