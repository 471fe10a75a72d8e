//! Fuzz target `episodes`: the body, its input layout and its checks are `xhab_fuzz::episodes`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/episodes/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::episodes(data));
