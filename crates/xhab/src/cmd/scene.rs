//! `xhab scene generate|info`.

use crate::cli::SceneCommand;
use crate::scene_arg::load_world;
use anyhow::{Context, Result};
use std::process::ExitCode;
use xhab_sim::scene::house::{generate_house, HouseParams};

pub fn run(c: &SceneCommand) -> Result<ExitCode> {
    match c {
        SceneCommand::Generate { seed, out } => {
            let scene = generate_house(*seed, &HouseParams::default());
            super::ensure_parent(out)?;
            xhab_sim::scene::write_glb(&scene, out).with_context(|| format!("writing {}", out.display()))?;
            eprintln!("xhab: wrote {} ({} triangles)", out.display(), scene.triangle_count());
        }
        SceneCommand::Info { scene, scene_opts } => {
            let world = load_world(scene, scene_opts)?;
            let b = world.scene.bounds();
            let mut floors = Vec::new();
            for (i, f) in world.floors.iter().enumerate() {
                let g = world.grid(i)?;
                let mut islands: Vec<_> = g.islands.iter().map(|k| serde_json::json!({"area_m2": k.area, "radius_m": k.radius})).collect();
                islands.truncate(10);
                floors.push(serde_json::json!({
                    "height_m": f.z, "walkable_area_m2": f.area,
                    "navigable_area_m2": g.navigable_cells() as f64 * g.resolution().powi(2),
                    "islands": g.islands.len(), "largest_islands": islands,
                }));
            }
            let j = serde_json::json!({
                "triangles": world.scene.triangle_count(),
                "meshes": world.scene.meshes.len(),
                "bounds_min": b.min, "bounds_max": b.max,
                "floors": floors,
            });
            println!("{}", serde_json::to_string_pretty(&j)?);
        }
    }
    Ok(ExitCode::SUCCESS)
}
