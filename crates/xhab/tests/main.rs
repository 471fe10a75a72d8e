//! Integration tests of the xhab workspace on real data and through the CLI.
mod common;
mod cli;
mod map_vs_slam;
mod sensors;
mod raster;
mod ros_interop;
mod ros_names;
mod ros_external;
mod gpu;
mod localization;
mod textures;
mod ros_params;
