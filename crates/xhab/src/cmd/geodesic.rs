//! `xhab geodesic`: one geodesic distance.

use crate::cli::GeodesicArgs;
use crate::scene_arg::{load_geometry, parse_habitat_point};
use anyhow::{Context, Result};
use std::process::ExitCode;
use xhab_bridge::setup::{geodesic, GeodesicQuery};

pub fn run(a: &GeodesicArgs) -> Result<ExitCode> {
    let from = parse_habitat_point(&a.from, "--from")?;
    let to = parse_habitat_point(&a.to, "--to")?;
    let world = load_geometry(&a.scene, &a.scene_opts)?;
    let GeodesicQuery { distance: d, from_navigable: from_ok, to_navigable: to_ok, same_floor } = geodesic(&world, from, to).context("--from")?;
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
