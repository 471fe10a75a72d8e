//! `xhab map`: a map_server map and a picture of a scene's floor.

use crate::cli::MapArgs;
use crate::report::MapPicture;
use crate::scene_arg::{floor_index, load_world};
use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use xhab_types::OccupancyGrid;

pub fn run(a: &MapArgs) -> Result<ExitCode> {
    let t0 = Instant::now();
    let mut opts = a.scene_opts.clone();
    opts.cell_size = a.resolution;
    let world = load_world(&a.scene, &opts)?;
    let floor = floor_index(&world, &a.floor)?;
    let grid = world.grid(floor).with_context(|| format!("building the map of {}", a.scene))?;
    let map = grid.occupancy_grid();
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

/// Writes OUT.yaml + OUT.pgm (map_server) and OUT.png; returns the YAML and PNG paths.
pub fn write_map(map: &OccupancyGrid, out: &Path) -> Result<(PathBuf, PathBuf)> {
    super::ensure_parent(out)?;
    let yaml = with_ext(out, "yaml");
    let png = with_ext(out, "png");
    xhab_nav::map_server::save_map(map, &yaml).with_context(|| format!("writing map {}", yaml.display()))?;
    MapPicture::new(map).save(&png)?;
    Ok((yaml, png))
}

fn with_ext(p: &Path, ext: &str) -> PathBuf {
    let mut s = p.as_os_str().to_owned();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

fn counts(m: &OccupancyGrid) -> (usize, usize) {
    let free = m.data.iter().filter(|&&v| v == xhab_types::GRID_FREE).count();
    let occ = m.data.iter().filter(|&&v| v == xhab_types::GRID_OCCUPIED).count();
    (free, occ)
}
