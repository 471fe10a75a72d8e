#!/usr/bin/env bash
# Feature agreement: every dependency that `cargo build -p xhab` (the CLI the Python tests and
# the soak run) or maturin's build of crates/python compiles must get the same features as in
# `cargo test --workspace`, or cargo compiles it (and every crate above it) a second time:
# about a hundred crates and several minutes of CI. crates/workspace-hack turns on what the
# members and tests turn on; this check names a dependency whose features still differ.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each package and its features for this machine, one line each; the arguments choose the
# packages and edges.
host=$(rustc -vV | sed -n 's/^host: //p')
tree() {
  cargo tree --locked "$@" -f '{p}|{f}' --prefix none --no-dedupe --target "$host" |
    sed 's/ (\*)$//; s/ (proc-macro)$//' | sort -u
}
# What the target runs (build scripts and proc macros left out) must match exactly; over
# all edges, each package's features must be among the workspace's (a build script's copy of
# a package may differ from the target's).
target_ws=$(tree --workspace -e normal,dev,no-proc-macro)
all_ws=$(tree --workspace -e normal,build,dev)
fail=0
for pkg in xhab xhab-python; do
  # (Into variables first: a failing cargo tree in a process substitution would pass unseen.)
  target_pkg=$(tree -p "$pkg" -e normal,no-proc-macro)
  all_pkg=$(tree -p "$pkg" -e normal,build)
  missing=$( (comm -23 <(printf '%s\n' "$target_pkg") <(printf '%s\n' "$target_ws")
              comm -23 <(printf '%s\n' "$all_pkg") <(printf '%s\n' "$all_ws")) | sort -u)
  if [ -n "$missing" ]; then
    echo "feature agreement: cargo build -p $pkg would compile these again (add their features to crates/workspace-hack):" >&2
    sed 's/^/  /; s/|/ features: /' <<<"$missing" >&2
    fail=1
  fi
done
if [ $fail = 0 ]; then echo "feature agreement: ok"; fi
exit $fail
