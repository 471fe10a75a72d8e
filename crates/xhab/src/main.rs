//! The `xhab` command line: parses, runs a command from `cmd/`, reports.
//!
//! Data goes to stdout, messages to stderr with an `xhab:` prefix. Exit codes: 0 success,
//! 1 ran but a check failed, 2 error.

mod cli;
mod cmd;
mod scene_arg;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = cli::Cli::parse();
    // RustDDS logs its internal state at warn and error (a peer leaving, endpoints removed at
    // exit), and ros2-client warns when $ROS_DISTRO is unset: quiet unless XHAB_LOG asks.
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_env_filter(tracing_subscriber::EnvFilter::try_from_env("XHAB_LOG").unwrap_or_else(|_| "warn,rustdds=off,ros2_client=error".into()))
        .without_time()
        .init();
    match cmd::run(&cli) {
        Ok(code) => code,
        Err(e) => {
            if is_broken_pipe(&e) {
                return ExitCode::SUCCESS;
            }
            eprintln!("xhab: error: {}", error_message(&e));
            ExitCode::from(2)
        }
    }
}

/// The error and its causes joined by ": ", leaving out a cause whose text the message so far
/// already carries (library errors often print their source themselves, and anyhow's `{:#}`
/// would then repeat it: "x.yaml: No such file or directory: No such file or directory").
fn error_message(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.is_empty() {
            out = text;
        } else if !out.contains(&text) {
            out.push_str(": ");
            out.push_str(&text);
        }
    }
    out
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.downcast_ref::<std::io::Error>().is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe))
}

#[cfg(test)]
mod tests {
    use super::error_message;

    #[derive(Debug)]
    struct Wrapped(std::io::Error);
    impl std::fmt::Display for Wrapped {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            write!(f, "e.json: {}", self.0)
        }
    }
    impl std::error::Error for Wrapped {
        fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
            Some(&self.0)
        }
    }

    #[test]
    fn a_cause_already_in_the_message_is_not_repeated() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory");
        let e = anyhow::Error::new(Wrapped(io)).context("reading episodes e.json");
        assert_eq!(error_message(&e), "reading episodes e.json: e.json: No such file or directory");
        // A cause not in the message is kept.
        let e = anyhow::anyhow!("bad value").context("params.yaml: key max_vel_x");
        assert_eq!(error_message(&e), "params.yaml: key max_vel_x: bad value");
    }
}
