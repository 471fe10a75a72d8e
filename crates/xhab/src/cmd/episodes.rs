//! `xhab episodes`: PointNav episodes generated with Habitat's rules.

use crate::cli::EpisodesArgs;
use crate::scene_arg::load_geometry;
use anyhow::{Context, Result};
use std::process::ExitCode;
use xhab_sim::episode::write_dataset;

pub fn run(a: &EpisodesArgs) -> Result<ExitCode> {
    let world = load_geometry(&a.scene, &a.scene_opts)?;
    let scene_id = a.scene_id.clone().unwrap_or_else(|| a.scene.clone());
    let ds = if a.cross_floor {
        xhab_bridge::setup::generate_cross_floor(&world, &a.scene, a.count, a.seed, &scene_id)?
    } else {
        xhab_bridge::setup::generate(&world, &a.scene, &a.floor, a.count, a.seed, &scene_id)?
    };
    super::ensure_parent(&a.out)?;
    write_dataset(&ds, &a.out).with_context(|| format!("writing {}", a.out.display()))?;
    let mean = ds.episodes.iter().filter_map(|e| e.geodesic_distance).sum::<f64>() / ds.episodes.len().max(1) as f64;
    eprintln!("xhab: wrote {} episodes to {} (mean geodesic distance {:.2} m)", ds.episodes.len(), a.out.display(), mean);
    Ok(ExitCode::SUCCESS)
}
