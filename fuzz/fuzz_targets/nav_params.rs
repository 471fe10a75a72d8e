//! Fuzz target `nav_params`: the body, its input layout and its checks are `xhab_fuzz::nav_params`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/nav_params/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::nav_params(data));
