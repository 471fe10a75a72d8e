//! PointNav episodes: the data model, Habitat's dataset files and the episode generator.

mod generator;
mod habitat_json;
mod types;

pub use generator::{generate_cross_storey_episodes, generate_episodes, GenerateError, GeneratorParams};
pub use habitat_json::{parse_dataset, quaternion_from_yaw, read_dataset, to_json_string, write_dataset, yaw_from_quaternion, DatasetError};
pub use types::{Dataset, Episode, Goal};
