//! PointNav episodes: Habitat's dataset files and the episode generator.

pub mod dataset;
