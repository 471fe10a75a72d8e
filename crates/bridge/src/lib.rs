//! Wiring between agents and environments: in-process runs of episodes.
#![warn(missing_docs)]
