//! Fuzz target `ply`: the body, its input layout and its checks are `xhab_fuzz::ply`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/ply/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::ply(data));
