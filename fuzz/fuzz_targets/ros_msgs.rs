//! Fuzz target `ros_msgs`: the body, its input layout and its checks are `xhab_fuzz::ros_msgs`
//! (fuzz/src/lib.rs), which the stable test `fuzz_regressions` also runs on fuzz/regressions/ros_msgs/.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| xhab_fuzz::ros_msgs(data));
