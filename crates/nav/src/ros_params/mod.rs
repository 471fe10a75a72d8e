//! ROS 1 and Nav2 (ROS 2) parameter files, loaded unchanged: move_base, costmap_2d, dwa_local_planner,
//! base_local_planner, global_planner, navfn and amcl YAML, layered under namespaces as
//! roslaunch's `<rosparam file ns>` does, read into [`NavParams`](crate::navigator::NavParams).
//!
//! - `tree.rs`: layering [`ParamSource`]s (a file's text and namespace), a deep merge.
//! - `registry.rs`: every ROS parameter name with its type, range and noetic default ([`specs`]).
//! - `layout.rs`: a costmap's layers (`plugins` or pre-Hydro) and observation sources.
//! - `load.rs`: ROS's lookup rules into `NavParams` ([`nav_params_from_sources`]), errors for
//!   bad values, warnings for unknown (with "did you mean") and ineffective names;
//!   [`LoadedParams::size_to_robot`].
//! - `nav2.rs`, `nav2_registry.rs`: Nav2 (ROS 2) files (`NODE: {ros__parameters: ...}`), checked
//!   against Nav2's names ([`nav2_specs`]) and read as the ROS 1 names they correspond to.
//! - `files.rs`: `FILE[@NAMESPACE]` arguments ([`ParamFile`]) read from disk ([`load_nav_params`]).

mod error;
mod files;
mod layout;
mod load;
mod nav2;
mod nav2_registry;
mod registry;
mod suggest;
mod tree;
mod value;

pub use error::ParamError;
pub use files::{load_nav_params, ParamFile};
pub use load::{nav_params_from_sources, LoadedParams};
pub use nav2_registry::{nav2_spec, nav2_specs, Nav2Role, Nav2Spec};
pub use registry::{spec, specs, Effect, ParamSpec, RosNode};
pub use tree::ParamSource;

#[cfg(test)]
mod tests;
#[cfg(test)]
mod nav2_tests;
