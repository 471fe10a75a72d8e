//! `xhab merge`: a study's shards combined into the results of one run, and its report.

use crate::cli::MergeArgs;
use anyhow::Result;
use std::process::ExitCode;

pub fn run(a: &MergeArgs) -> Result<ExitCode> {
    let out = a.out.clone().unwrap_or_else(|| a.dirs[0].clone());
    let (results, page) = xhab_experiment::execute::merge_and_report(&a.dirs, &out, !a.no_report)?;
    super::experiment::print_results(&results, &out);
    if let Some(p) = page {
        println!("report: {}", p.display());
    }
    Ok(ExitCode::SUCCESS)
}
