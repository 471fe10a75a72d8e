//! Every input of fuzz/regressions/TARGET/ (inputs that once crashed, hung or exhausted memory
//! under `scripts/fuzz.sh`) run on stable through the fuzz target's own body, which this file
//! includes from fuzz/src/lib.rs: each must end in an error naming the input or a result that
//! passes the target's checks, quickly.

#[path = "../../fuzz/src/lib.rs"]
#[allow(dead_code)]
mod harness;

use crate::common::repo_root;
use std::time::{Duration, Instant};

#[test]
fn fuzz_regression_inputs_are_errors_or_usable_results() {
    let dir = repo_root().join("fuzz/regressions");
    let mut ran = 0;
    for entry in std::fs::read_dir(&dir).expect("fuzz/regressions") {
        let entry = entry.expect("a fuzz/regressions entry");
        if !entry.path().is_dir() {
            continue;
        }
        let target = entry.file_name().to_string_lossy().to_string();
        assert!(harness::TARGETS.contains(&target.as_str()), "fuzz/regressions/{target} names no fuzz target");
        for input in std::fs::read_dir(entry.path()).expect("a target's regressions") {
            let path = input.expect("a regression input").path();
            let data = std::fs::read(&path).expect("a regression input's bytes");
            let t0 = Instant::now();
            // A panic fails the test and names the input.
            let result = std::panic::catch_unwind(|| harness::run(&target, &data));
            assert!(result.is_ok(), "{} panicked", path.display());
            // The fuzzer's limit is 10 s per input in an optimised build; a debug build gets more.
            assert!(t0.elapsed() < Duration::from_secs(60), "{} took {:?}", path.display(), t0.elapsed());
            ran += 1;
        }
    }
    eprintln!("fuzz_regressions: {ran} inputs");
}
