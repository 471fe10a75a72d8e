#!/usr/bin/env bash
# Dependency direction (DESIGN.md section 2): xhab -> experiment -> bridge -> {sim, nav} -> types;
# sim and nav never depend on each other; only bridge may know ROS; only the Python package
# (crates/python -> bridge) knows Python.
set -euo pipefail
cd "$(dirname "$0")/.."
fail=0
deps() {
  local out
  out=$(cargo tree --locked -p "$1" -e normal --prefix none) || { echo "dependency direction: cargo tree -p $1 failed" >&2; exit 1; }
  awk '{print $1}' <<<"$out" | sort -u
}
check() { # crate forbidden...
  local c=$1; shift
  local d; d=$(deps "$c")
  for f in "$@"; do
    if grep -qx "$f" <<<"$d"; then echo "dependency direction: $c depends on $f" >&2; fail=1; fi
  done
}
check xhab-types xhab-sim xhab-nav xhab-bridge roslibrust ros2-client rustdds pyo3
check xhab-sim xhab-nav xhab-bridge roslibrust ros2-client rustdds pyo3
check xhab-nav xhab-sim xhab-bridge roslibrust ros2-client rustdds pyo3
check xhab-bridge xhab-experiment xhab-python pyo3
check xhab-experiment xhab xhab-python pyo3
check xhab xhab-python pyo3
if [ $fail = 0 ]; then echo "dependency direction: ok"; fi
exit $fail
