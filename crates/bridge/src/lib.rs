//! Wiring between agents and environments.
//!
//! [`agents`]: the agents `xhab bench --agent` can run; [`runner`]: in-process episode runs,
//! sequential or parallel with identical results.
#![warn(missing_docs)]

pub mod agents;
pub mod explore;
pub mod global_localization;
pub mod nav_agent;
pub mod runner;
pub mod scan_source;
pub mod ros;
