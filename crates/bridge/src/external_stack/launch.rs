//! `--launch CMD`: the stack under test as a child process group, stopped at the end.

use crate::ros::node::RosError;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A process started with `--launch`, stopped (its whole process group) on drop.
pub struct Launched(Child);

impl Drop for Launched {
    fn drop(&mut self) {
        // `--` before the negative id: procps-ng's kill reads `-TERM -1234` as signal TERM
        // to process group -1 (its first digit), i.e. to every process it may signal.
        let group = format!("-{}", self.0.id());
        let _ = Command::new("kill").args(["-s", "TERM", "--", &group]).stderr(Stdio::null()).status();
        let t = Instant::now();
        while t.elapsed() < Duration::from_secs(3) {
            if let Ok(Some(_)) = self.0.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(50));
        }
        let _ = Command::new("kill").args(["-s", "KILL", "--", &group]).stderr(Stdio::null()).status();
        let _ = self.0.wait();
    }
}

/// Starts `cmd` with `sh -c` in a process group of its own, with the extra environment `env`.
pub fn launch(cmd: &str, env: &[(&str, &str)]) -> Result<Launched, RosError> {
    use std::os::unix::process::CommandExt;
    let mut c = Command::new("sh");
    c.args(["-c", cmd]).stdin(Stdio::null()).process_group(0);
    for (k, v) in env {
        c.env(k, v);
    }
    let child = c.spawn().map_err(|e| RosError::Node(format!("--launch '{cmd}': {e}")))?;
    tracing::info!("started the stack: {cmd}");
    Ok(Launched(child))
}
