//! The shared third-party data, for every test that reads it (included with `#[path]` by
//! tests/e2e and the crates' own integration tests, so the lookup and its skip rule live here
//! once).

use std::path::PathBuf;

/// The shared data folder (`$XHAB_DATA`, else `../shared` beside the workspace), or `None`
/// with a loud message when it is missing; panics when `XHAB_REQUIRE_DATA=1` demands it.
pub fn data_dir(test: &str) -> Option<PathBuf> {
    let dir = std::env::var_os("XHAB_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared")));
    if dir.join("scenes").is_dir() {
        return Some(dir);
    }
    if std::env::var("XHAB_REQUIRE_DATA").as_deref() == Ok("1") {
        panic!("{test}: XHAB_REQUIRE_DATA=1 but the shared data is missing at {}", dir.display());
    }
    skipped(test, &format!("shared data not found at {} (set XHAB_DATA)", dir.display()));
    None
}

/// Says loudly that `test` skipped and why: on stderr, and as a line of the file
/// `$XHAB_SKIP_LOG` when set, which the README's test command prints as a summary at the end
/// (cargo hides the stderr of passing tests).
#[allow(dead_code)]
pub fn skipped(test: &str, reason: &str) {
    eprintln!("SKIPPED {test}: {reason}");
    if let Some(log) = std::env::var_os("XHAB_SKIP_LOG") {
        use std::io::Write;
        if let Ok(mut f) = std::fs::OpenOptions::new().create(true).append(true).open(log) {
            let _ = writeln!(f, "{test}: {reason}");
        }
    }
}

/// The workspace's root folder.
#[allow(dead_code)]
pub fn repo_root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}
