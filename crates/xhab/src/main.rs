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
    tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_env_filter(tracing_subscriber::EnvFilter::try_from_env("XHAB_LOG").unwrap_or_else(|_| "warn".into()))
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
