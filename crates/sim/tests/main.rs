//! Integration tests of xhab-sim, one binary (topic files below).
#[path = "../../../tests/support/data.rs"]
mod data;
mod common;
mod env_oracle;
mod physics;
mod scenes;
mod geodesic_closed_form;
mod geodesic_vs_field;
mod raster;
mod gpu;
mod textures;
mod storeys;
mod exact_geodesic;
mod properties;
mod scan_slice;
