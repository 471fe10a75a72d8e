//! `xhab report`: the HTML report of a study folder.

use crate::cli::ReportArgs;
use anyhow::Result;
use std::process::ExitCode;

pub fn run(a: &ReportArgs) -> Result<ExitCode> {
    let page = xhab_experiment::report::write_report(&a.dir)?;
    println!("report: {}", page.display());
    Ok(ExitCode::SUCCESS)
}
