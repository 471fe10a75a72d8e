//! Resolving a SCENE argument (a file, or `procedural[:SEED]`) into a loaded world, through
//! `xhab_bridge::setup`, which the Python package shares.

use crate::cli::{SceneOpts, UpAxisArg};
use anyhow::{bail, Result};
use xhab_bridge::setup::{self, SceneOptions};
use xhab_sim::scene::{Scene, UpAxis};
use xhab_sim::world::World;

/// The library's scene options from the command line's.
pub fn scene_options(opts: &SceneOpts) -> SceneOptions {
    SceneOptions {
        up_axis: match opts.up_axis {
            UpAxisArg::Y => UpAxis::Y,
            UpAxisArg::Z => UpAxis::Z,
        },
        keep_ceilings: opts.keep_ceilings,
        agent_radius: opts.agent_radius,
        agent_height: opts.agent_height,
        cell_size: opts.cell_size,
        storeys: opts.storeys,
        textures: true,
    }
}

/// Loads the scene named by `arg`.
pub fn load_scene(arg: &str, opts: &SceneOpts) -> Result<Scene> {
    Ok(setup::load_scene(arg, &scene_options(opts))?)
}

/// Loads the scene and wraps it in a world.
pub fn load_world(arg: &str, opts: &SceneOpts) -> Result<World> {
    Ok(setup::load_world(arg, &scene_options(opts))?)
}

/// [`load_world`] without the scene's textures ([`setup::load_geometry`]), for commands
/// that never render colour (maps, geodesics, episodes).
pub fn load_geometry(arg: &str, opts: &SceneOpts) -> Result<World> {
    Ok(setup::load_geometry(arg, &scene_options(opts))?)
}

/// The floor index for a `--floor` value: `auto` or a height in metres (Habitat's y = our z).
pub fn floor_index(world: &World, floor: &str) -> Result<usize> {
    Ok(setup::floor_index(world, floor)?)
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
