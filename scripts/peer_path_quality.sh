#!/usr/bin/env bash
# How far habitat-sim's PathFinder.find_path (the peer `xhab perf`'s pair queries are timed
# against) is from the shortest path: its distances beside xhab's exact ones on the same
# seeded pairs of the two houses, at the agent's radius (0.1 m) and at a radius that matches
# habitat's narrower navmesh (0.16 m: on turtlebot3_house xhab's paths then stay within 1.7 cm
# of it, so a find_path answer longer than xhab's by more than what that stray allows is
# longer than a path its own navmesh holds; aws_small_house's furniture differs more).
#
#   scripts/peer_path_quality.sh [OUT_DIR]     (default: a new folder under /tmp)
#
# Needs the peer built (../shared/peers/habitat/setup.sh) and its Z-up scenes, which
# side_by_side.sh writes under $HABPEER/scenes (converted here when missing). About a minute.
set -euo pipefail
cd "$(dirname "$0")/.."
HABPEER=${HABPEER:-/opt/habpeer}
PEER_DIR=$(realpath -m "${HABITAT_PEER_DIR:-../shared/peers/habitat}")
SCENE_DIR=$(realpath -m "${XHAB_DATA:-../shared}/scenes")
HPY=$HABPEER/bin/hpython
[ -x "$HPY" ] || { echo "peer_path_quality: no habitat-sim peer at $HABPEER (run $PEER_DIR/setup.sh)" >&2; exit 1; }
out=${1:-$(mktemp -d /tmp/peer_path_quality.XXXXXX)}
mkdir -p "$out" "$HABPEER/scenes"
: >"$out/summary.txt"
: >"$out/habitat.log"
cargo build -q --release -p xhab-sim --example pair_paths --locked
bin=$(realpath -m "${CARGO_TARGET_DIR:-target}")/release/examples/pair_paths
radii="0.1 0.16"
for s in turtlebot3_house aws_small_house; do
  zup=$HABPEER/scenes/${s}_zup.glb
  [ -f "$zup" ] || "$HPY" "$PEER_DIR/convert.py" "$SCENE_DIR/$s.glb" "$zup" >&2
  HABITAT_PEER_DIR=$PEER_DIR "$HPY" scripts/peer/hab_paths.py pairs "$zup" "$out/$s.pairs.json" 600 >>"$out/habitat.log" 2>&1
  for r in $radii; do
    "$bin" "$SCENE_DIR/$s.glb" "$out/$s.pairs.json" "$out/$s.xhab_$r.json" --radius "$r"
    HABITAT_PEER_DIR=$PEER_DIR "$HPY" scripts/peer/hab_paths.py stray "$zup" "$out/$s.pairs.json" "$out/$s.xhab_$r.json" "$out/$s.stray_$r.json" >>"$out/habitat.log" 2>&1
  done
  python3 scripts/peer/path_quality.py "$out" "$s" $radii | tee -a "$out/summary.txt"
done
echo "peer_path_quality: $out/summary.txt"
