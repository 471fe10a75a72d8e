//! Fuzz target `map_image`: the body, its input layout and its checks are `xhab_fuzz::map_image`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/map_image/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::map_image(data));
