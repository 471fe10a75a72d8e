//! Fuzz target `obj`: the body, its input layout and its checks are `xhab_fuzz::obj`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/obj/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::obj(data));
