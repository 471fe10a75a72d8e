//! xhab's exact shortest paths for a list of point pairs, to set beside another planner's
//! (`scripts/peer_path_quality.sh` sets them beside habitat-sim's `find_path`).
//!
//! `cargo run --release -p xhab-sim --example pair_paths -- SCENE PAIRS.json OUT.json
//! [--radius R]` reads `{"rows": [{"a": [x, y, z], "b": [x, y, z]}, ...]}` (Habitat frame,
//! y up, m) and writes one entry per row, in order: the path's bend points in the same frame,
//! start and goal included, or `null` where no walkable path joins them. `--radius` sets the
//! disc agent's radius (m, default 0.1, the other parameters stay at their defaults): a
//! planner whose free space is narrower can be matched by a larger radius.

use std::path::Path;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{load, LoadOptions};
use xhab_sim::world::World;
use xhab_types::Point3;

fn main() {
    if let Err(e) = run() {
        eprintln!("pair_paths: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), String> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut params = AgentParams::default();
    if let Some(i) = args.iter().position(|a| a == "--radius") {
        let r = args.get(i + 1).and_then(|v| v.parse::<f64>().ok()).filter(|r| r.is_finite() && *r > 0.0);
        params.radius = r.ok_or("--radius wants a length in metres above 0")?;
        args.drain(i..i + 2);
    }
    let [scene, pairs, out] = args.as_slice() else {
        return Err("usage: pair_paths SCENE PAIRS.json OUT.json [--radius R]".into());
    };
    let scene = load(Path::new(scene), &LoadOptions::default()).map_err(|e| e.to_string())?;
    let world = World::new(scene, params);
    let text = std::fs::read_to_string(pairs).map_err(|e| format!("{pairs}: {e}"))?;
    let doc: serde_json::Value = serde_json::from_str(&text).map_err(|e| format!("{pairs}: {e}"))?;
    let rows = doc["rows"].as_array().ok_or(format!("{pairs}: no \"rows\" list"))?;
    let mut paths = Vec::with_capacity(rows.len());
    for (k, row) in rows.iter().enumerate() {
        let point = |end: &str| -> Result<Point3, String> {
            let v: Vec<f64> = row[end].as_array().map(|v| v.iter().filter_map(|x| x.as_f64()).collect()).unwrap_or_default();
            match v.as_slice() {
                &[x, y, z] => Ok(Point3::from_habitat([x, y, z])),
                _ => Err(format!("{pairs}: rows[{k}].{end} is not [x, y, z]")),
            }
        };
        let path = xhab_sim::storey_path::path(&world, point("a")?, point("b")?);
        paths.push(serde_json::json!(path.map(|p| p.into_iter().map(Point3::to_habitat).collect::<Vec<_>>())));
    }
    std::fs::write(out, serde_json::Value::Array(paths).to_string()).map_err(|e| format!("{out}: {e}"))
}
