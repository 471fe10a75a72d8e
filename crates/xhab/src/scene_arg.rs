//! Resolving a SCENE argument (a file, or `procedural[:SEED]`) into a loaded world.

use crate::cli::{SceneOpts, UpAxisArg};
use anyhow::{bail, Context, Result};
use std::path::Path;
use xhab_sim::navgrid::AgentParams;
use xhab_sim::scene::{self, LoadOptions, Scene, UpAxis};
use xhab_sim::world::World;

/// Loads the scene named by `arg`.
pub fn load_scene(arg: &str, opts: &SceneOpts) -> Result<Scene> {
    if let Some(seed) = procedural_seed(arg)? {
        return Ok(scene::house::generate_house(seed, &scene::house::HouseParams::default()));
    }
    let load = LoadOptions {
        up_axis: match opts.up_axis {
            UpAxisArg::Y => UpAxis::Y,
            UpAxisArg::Z => UpAxis::Z,
        },
        drop_ceilings: !opts.keep_ceilings,
    };
    scene::load(Path::new(arg), &load).with_context(|| format!("loading scene {arg}"))
}

/// The seed of a `procedural[:SEED]` argument, or `None` for a file.
pub fn procedural_seed(arg: &str) -> Result<Option<u64>> {
    if arg == "procedural" {
        return Ok(Some(0));
    }
    if let Some(s) = arg.strip_prefix("procedural:") {
        return match s.parse() {
            Ok(v) => Ok(Some(v)),
            Err(_) => bail!("bad scene '{arg}': the seed after 'procedural:' must be a whole number"),
        };
    }
    Ok(None)
}

/// The agent parameters of the scene options.
pub fn agent_params(opts: &SceneOpts) -> AgentParams {
    AgentParams { radius: opts.agent_radius.unwrap_or(0.1), height: opts.agent_height, cell_size: opts.cell_size, ..Default::default() }
}

/// Loads the scene and wraps it in a world.
pub fn load_world(arg: &str, opts: &SceneOpts) -> Result<World> {
    let scene = load_scene(arg, opts)?;
    let world = World::new(scene, agent_params(opts));
    if world.floors.is_empty() {
        bail!("scene {arg}: no walkable floor found (is the up axis right? try --up-axis z)");
    }
    Ok(world)
}

/// The floor index for a `--floor` value: `auto` or a height in metres (Habitat's y = our z).
pub fn floor_index(world: &World, floor: &str) -> Result<usize> {
    if floor == "auto" {
        return world.default_floor().context("the scene has no floor");
    }
    let z: f64 = floor.parse().map_err(|_| anyhow::anyhow!("bad --floor '{floor}': expected 'auto' or a height in metres"))?;
    world.floor_at(z).with_context(|| {
        let known: Vec<String> = world.floors.iter().map(|f| format!("{:.2}", f.z)).collect();
        format!("no floor within 0.5 m of height {z} (floors at [{}] m)", known.join(", "))
    })
}

/// Parses `X,Y,Z` (Habitat frame) into a world-frame point.
pub fn parse_habitat_point(s: &str, what: &str) -> Result<xhab_types::Point3> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>())
        .collect::<std::result::Result<_, _>>()
        .map_err(|_| anyhow::anyhow!("bad {what} '{s}': expected X,Y,Z in metres"))?;
    if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
        bail!("bad {what} '{s}': expected three finite numbers X,Y,Z");
    }
    Ok(xhab_types::Point3::from_habitat([v[0], v[1], v[2]]))
}
