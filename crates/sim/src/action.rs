//! Habitat's discrete PointNav actions.

use serde::{Deserialize, Serialize};

/// A discrete action, numbered as in Habitat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// End the episode (0).
    Stop = 0,
    /// Move `forward_step` ahead (1), sliding along obstacles.
    MoveForward = 1,
    /// Turn left by `turn_angle` (2).
    TurnLeft = 2,
    /// Turn right by `turn_angle` (3).
    TurnRight = 3,
}

impl Action {
    /// The action with Habitat's number `i`.
    pub fn from_index(i: i64) -> Option<Action> {
        match i {
            0 => Some(Action::Stop),
            1 => Some(Action::MoveForward),
            2 => Some(Action::TurnLeft),
            3 => Some(Action::TurnRight),
            _ => None,
        }
    }
}
