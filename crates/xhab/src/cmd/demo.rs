//! `xhab demo`: the whole pipeline on the built-in procedural house, no files needed.
//! Parses the flags into the library's [`DemoOptions`], calls [`run_demo`], prints.

use crate::cli::DemoArgs;
use anyhow::Result;
use std::process::ExitCode;
use std::time::Instant;
use xhab_bridge::demo::{run_demo, DemoOptions};

pub fn run(a: &DemoArgs, quiet: bool) -> Result<ExitCode> {
    let t0 = Instant::now();
    let o = DemoOptions { seed: a.seed, episodes: a.episodes, out: a.out.clone(), threads: a.threads };
    let pb = super::progress(0, quiet, "oracle");
    let run = run_demo(&o, &|done, total| {
        pb.set_length(total as u64);
        pb.set_position(done as u64);
    })?;
    pb.finish_and_clear();
    eprintln!(
        "xhab: procedural house (seed {}): {} triangles, {:.1} m^2 navigable; map {}",
        a.seed,
        run.triangles,
        run.navigable_area_m2,
        run.map_yaml.display()
    );
    eprintln!("xhab: {} episodes in {}", run.episodes, run.episodes_file.display());
    eprintln!("xhab: results {}, trajectories {}", run.results.display(), run.trajectories.display());
    super::bench::print_table(&run.report.aggregate, run.report.invalid.count, "oracle");
    eprintln!("xhab: demo done in {:.2} s", t0.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}
