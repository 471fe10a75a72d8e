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
            eprintln!("xhab: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| c.downcast_ref::<std::io::Error>().is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe))
}
