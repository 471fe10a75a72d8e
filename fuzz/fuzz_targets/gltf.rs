//! Fuzz target `gltf`: the body, its input layout and its checks are `xhab_fuzz::gltf`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/gltf/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::gltf(data));
