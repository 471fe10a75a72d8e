//! The xhab navigation stack: knows nothing of the simulator or of ROS.
//!
//! For now: [`map_io`], map_server's PGM + YAML format, read and written exactly.
#![warn(missing_docs)]
pub mod map_io;
pub mod map_server;
