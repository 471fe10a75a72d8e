//! The `xhab` command line.
fn main() {}
