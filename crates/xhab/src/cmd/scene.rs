//! `xhab scene generate|info`.

use crate::cli::SceneCommand;
use crate::scene_arg::load_world;
use anyhow::{Context, Result};
use std::process::ExitCode;

pub fn run(c: &SceneCommand) -> Result<ExitCode> {
    match c {
        SceneCommand::Generate { seed, storeys, stair_building, out } => {
            let name = if *stair_building { xhab_bridge::setup::STAIR_BUILDING.to_string() } else { format!("procedural:{seed}") };
            let opts = xhab_bridge::setup::SceneOptions { storeys: *storeys, ..Default::default() };
            let scene = xhab_bridge::setup::load_scene(&name, &opts)?;
            super::ensure_parent(out)?;
            xhab_sim::scene::write_glb(&scene, out).with_context(|| format!("writing {}", out.display()))?;
            eprintln!("xhab: wrote {} ({} triangles)", out.display(), scene.triangle_count());
        }
        SceneCommand::Info { scene, scene_opts } => {
            let world = load_world(scene, scene_opts)?;
            let b = world.scene.bounds();
            let mut floors = Vec::new();
            let joined = world.connected_storeys();
            for (i, f) in world.floors.iter().enumerate() {
                let g = world.grid(i)?;
                let mut islands: Vec<_> = g.islands.iter().map(|k| serde_json::json!({"area_m2": k.area, "radius_m": k.radius})).collect();
                islands.truncate(10);
                let mut floor = serde_json::json!({
                    "height_m": f.z, "walkable_area_m2": f.area,
                    "navigable_area_m2": g.navigable_cells() as f64 * g.resolution().powi(2),
                    "islands": g.islands.len(), "largest_islands": islands,
                });
                if world.floors.len() > 1 {
                    // Which storeys a flight of stairs joins this one to.
                    let to: Vec<usize> = joined.iter().filter_map(|&(a, b)| if a == i { Some(b) } else if b == i { Some(a) } else { None }).collect();
                    floor["storey"] = i.into();
                    floor["stairs_to"] = to.into();
                }
                floors.push(floor);
            }
            let j = serde_json::json!({
                "triangles": world.scene.triangle_count(),
                "meshes": world.scene.meshes.len(),
                "bounds_min": b.min, "bounds_max": b.max,
                "floors": floors,
                "storeys_joined": joined,
            });
            println!("{}", serde_json::to_string_pretty(&j)?);
        }
    }
    Ok(ExitCode::SUCCESS)
}
