//! End-to-end tests of the xhab workspace: the CLI on real data, ROS interop, the shipped maps,
//! the experiment report in a headless browser.
//! They are the `xhab` package's integration tests (`cargo test -p xhab --test e2e`), kept
//! here at the top level because they cross crates.
mod common;
mod cli;
mod map_vs_slam;
mod sensors;
mod raster;
mod ros_interop;
mod ros2_interop;
mod ros2_external;
mod ros2_lockstep;
mod ros_names;
mod ros_faults;
mod ros_external;
mod gpu;
mod localization;
mod textures;
mod ros_params;
mod maps;
mod experiment;
mod report;
mod malformed;
mod fuzz_regressions;
mod storeys;
