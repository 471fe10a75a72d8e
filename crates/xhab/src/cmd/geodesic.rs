//! `xhab geodesic`: one geodesic distance.

use crate::cli::GeodesicArgs;
use crate::scene_arg::{load_world, parse_habitat_point};
use anyhow::{Context, Result};
use std::process::ExitCode;
use xhab_sim::geodesic::geodesic_distance;

pub fn run(a: &GeodesicArgs) -> Result<ExitCode> {
    let from = parse_habitat_point(&a.from, "--from")?;
    let to = parse_habitat_point(&a.to, "--to")?;
    let world = load_world(&a.scene, &a.scene_opts)?;
    let grid = world.grid_at(from.z).context("--from")?;
    let same_floor = (to.z - from.z).abs() <= xhab_sim::world::FLOOR_MATCH;
    let from_ok = grid.is_navigable(from.xy());
    let to_ok = grid.is_navigable(to.xy());
    let d = if same_floor && from_ok && to_ok {
        geodesic_distance(&grid, from.xy(), to.xy())
    } else {
        f64::INFINITY
    };
    let text = if d.is_finite() { format!("{d:.6}") } else { "inf".to_string() };
    if a.json {
        let j = serde_json::json!({
            "geodesic_distance": if d.is_finite() { serde_json::json!(d) } else { serde_json::json!("inf") },
            "from": from.to_habitat(), "to": to.to_habitat(),
            "from_navigable": from_ok, "to_navigable": to_ok, "same_floor": same_floor,
        });
        println!("{j}");
    } else {
        println!("{text}");
    }
    if !from_ok {
        eprintln!("xhab: warning: --from is not navigable for the agent");
    }
    if !to_ok {
        eprintln!("xhab: warning: --to is not navigable for the agent");
    }
    Ok(ExitCode::SUCCESS)
}
