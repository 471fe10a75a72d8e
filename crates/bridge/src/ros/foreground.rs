//! Running a ROS node in the foreground: on its own runtime until it ends or the process is
//! interrupted (Ctrl-C), as `xhab ros sim|nav|agent` do.

use super::node::RosError;
use std::future::Future;

/// Runs `node` on a two-worker tokio runtime until it ends (its result) or Ctrl-C (`Ok`).
pub fn run_until_ctrl_c(node: impl Future<Output = Result<(), RosError>>) -> Result<(), RosError> {
    let rt = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().map_err(|e| RosError::Node(format!("tokio runtime: {e}")))?;
    rt.block_on(async {
        tokio::select! {
            r = node => r,
            _ = tokio::signal::ctrl_c() => Ok(()),
        }
    })
}
