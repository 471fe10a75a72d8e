//! PointNav episodes: the data model, Habitat's dataset files and the episode generator.

pub mod dataset;
mod generator;
mod types;

pub use generator::{generate_episodes, GenerateError, GeneratorParams};
pub use types::{Dataset, Episode, Goal};
