#!/usr/bin/env bash
# The maps the project ships (maps/), regenerated: for each procedural house seed the README
# and the examples use (0: `xhab demo`, `procedural`; 1: the Python examples), the
# traversability map (what the agent's body band hits: for costmaps and planning) and the
# scan-plane map (what a planar laser 0.2 m above the floor sees, as the default lidar does:
# for amcl), each as map_server YAML + PGM and a PNG picture.
#
#   scripts/make_maps.sh [OUT_DIR]        (default maps/; XHAB=path/to/xhab to use a built CLI)
#
# tests/e2e/maps.rs runs this into a temporary folder and fails if the result differs from
# what is committed: rerun it when the map generator's output changes on purpose.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-maps}
if [ -z "${XHAB:-}" ]; then
  cargo build -q -p xhab --locked
  # (A relative CARGO_TARGET_DIR is cargo's, from here: made absolute for the runs below.)
  XHAB=$(realpath -m "${CARGO_TARGET_DIR:-target}")/debug/xhab
fi
mkdir -p "$out"
for seed in 0 1; do
  "$XHAB" -q map "procedural:$seed" --out "$out/procedural_$seed"
  "$XHAB" -q map "procedural:$seed" --laser-height 0.2 --out "$out/procedural_${seed}_scan"
done
