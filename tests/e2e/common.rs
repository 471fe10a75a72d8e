//! Helpers shared by the integration tests.

#[path = "../support/data.rs"]
mod data;
pub use data::{data_dir, repo_root, skipped};

/// The `xhab` binary built for these tests.
pub fn xhab() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_xhab"))
}
