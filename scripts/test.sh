#!/usr/bin/env bash
# The whole test suite, from a fresh Debian machine with Rust: installs what the tests need,
# checks formatting-independent rules (dependency direction), then runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

# System packages the tests need: real ROS 1 from Debian for the interop tests (rosmaster,
# rospy, rostopic, rosbag and the message definitions rospy loads), and Mesa's Vulkan driver
# (llvmpipe) so that the wgpu renderer runs headless without a GPU; python3-venv for the
# Python package's virtual environment; slurm-wlm and munge for the real single-node SLURM
# cluster the experiment tests submit to (scripts/slurm_local.sh).
pkgs=(slurm-wlm munge
      python3-rosmaster python3-rospy python3-rostopic python3-rosbag
      python3-std-msgs python3-geometry-msgs python3-sensor-msgs python3-nav-msgs
      python3-tf2-msgs python3-rosgraph-msgs python3-actionlib python3-actionlib-msgs
      python3-tf2-ros python3-move-base-msgs python3-std-srvs
      mesa-vulkan-drivers python3-venv chromium)
need=()
for p in "${pkgs[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  # As root run apt-get directly; otherwise through sudo (env passes the variable through
  # sudo, and an empty $SUDO would turn the assignment into a command name).
  if [ "$(id -u)" = 0 ]; then SUDO=(); else SUDO=(sudo); fi
  "${SUDO[@]}" apt-get update -qq
  "${SUDO[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}"
fi

# Real ROS 2 for the interop tests: rclpy on Fast DDS and the message packages from PyPI
# (cp311 wheels, so Python 3.11), in their own virtual environment; installed once.
ros2_venv=.venv-ros2
if ! "$ros2_venv/bin/python" -c 'import rclpy, sensor_msgs.msg, nav_msgs.msg, geometry_msgs.msg, rosgraph_msgs.msg, action_msgs.msg' 2>/dev/null; then
  py311=$(command -v python3.11 || true)
  if [ -z "$py311" ]; then
    echo "xhab test: python3.11 is needed for ROS 2's wheels (ros-kilted-rclpy)" >&2
    exit 1
  fi
  "$py311" -m venv "$ros2_venv"
  "$ros2_venv/bin/pip" install -q 'ros-kilted-rclpy[fastrtps]' ros-kilted-std-msgs \
    ros-kilted-geometry-msgs ros-kilted-sensor-msgs ros-kilted-nav-msgs ros-kilted-action-msgs
fi

# Shared third-party data (scenes, maps, episodes) lives beside the project.
if [ -z "${XHAB_DATA:-}" ] && [ -d ../shared ]; then
  export XHAB_DATA="$(cd ../shared && pwd)"
fi
# Wherever the data exists, the tests that read it must run, not skip (a skip passes
# silently under cargo): require it unless the caller said otherwise.
if [ -d "${XHAB_DATA:-../shared}/scenes" ]; then
  export XHAB_REQUIRE_DATA="${XHAB_REQUIRE_DATA:-1}"
fi
if [ "${XHAB_REQUIRE_DATA:-0}" = 1 ] && [ ! -d "${XHAB_DATA:-../shared}/scenes" ]; then
  echo "xhab test: XHAB_REQUIRE_DATA=1 but no shared data at ${XHAB_DATA:-../shared}" >&2
  exit 1
fi

# The interop tests must run, not skip, wherever this script installed ROS.
export XHAB_REQUIRE_ROS=1
export XHAB_REQUIRE_ROS2=1
export XHAB_REQUIRE_GPU=1
export XHAB_REQUIRE_SLURM=1
export XHAB_REQUIRE_CHROMIUM=1
./scripts/check_deps.sh
# The CLI and the Python extension build on the test build's dependencies, not a copy.
./scripts/check_features.sh
# A test run builds once: incremental caches would only add gigabytes to the disk
# (set CARGO_INCREMENTAL=1 to keep them while iterating).
export CARGO_INCREMENTAL="${CARGO_INCREMENTAL:-0}"
# Every test that skips says so in this file too (cargo hides the stderr of passing tests);
# the summary is printed at the end, pass or fail.
skip_log="$(mktemp)"
export XHAB_SKIP_LOG="$skip_log"
skip_summary() {
  if [ -s "$skip_log" ]; then
    echo "xhab test: $(sort -u "$skip_log" | wc -l) test(s) skipped:"
    sort -u "$skip_log" | sed 's/^/  /'
  else
    echo "xhab test: no test skipped"
  fi
  rm -f "$skip_log"
}
trap skip_summary EXIT
cargo test --workspace --locked 2>&1
# The Python package (crates/python): wheel built into .venv, pytest.
./scripts/python_tests.sh
# The soak's short variant (200 oracle episodes per configuration, resident memory checked);
# the full 10,000-episode soak (scripts/soak.sh) is outside CI's time budget.
soak_out="$(mktemp -d)"
SOAK_SHORT=1 ./scripts/soak.sh "$soak_out"
rm -rf "$soak_out"
