//! Fuzz target `robot_profile`: the body, its input layout and its checks are `xhab_fuzz::robot_profile`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/robot_profile/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::robot_profile(data));
