//! The xhab simulator: Habitat's PointNav task without Habitat.
//!
//! Read in this order: [`scene`] (triangle soup in the world frame, from glTF/OBJ/PLY or the
//! procedural house), [`navgrid`] (the traversable region of a disc agent on one floor),
//! [`geodesic`] (shortest paths in that region), [`storey_path`] (across storeys, up stairs), [`episode`] (PointNav episodes: files and
//! generator), [`env`] (the discrete simulator) and [`metrics`].
//!
//! Frames: the world frame is REP-103 (z up). Habitat files use y up; they are converted once,
//! at the file boundary (`(x, y, z)_habitat = (x, -z, y)_ours`).
#![warn(missing_docs)]

pub mod scene;
pub mod episode;
pub mod navgrid;
mod rounding;
pub mod geodesic;
pub mod corner_graph;
pub mod goal_field;
pub mod field_cache;
pub mod action;
pub mod env;
pub mod kinematic;
pub mod metrics;
pub mod oracle;
pub mod world;
pub mod storey_path;
pub mod storey_route;
pub mod robot;
pub mod physics_env;
pub mod sensors;
