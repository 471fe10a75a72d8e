#!/usr/bin/env bash
# Coverage-guided fuzzing of xhab's parsers (cargo-fuzz, libFuzzer).
#
#   scripts/fuzz.sh TARGET SECONDS    fuzz one target for SECONDS
#   scripts/fuzz.sh all SECONDS       each target in turn, SECONDS each
#   scripts/fuzz.sh list              the targets
#
# Needs: the nightly toolchain (`rustup toolchain install nightly`; libFuzzer's coverage
# instrumentation is nightly-only) and cargo-fuzz (`cargo install cargo-fuzz`). The stable
# build and tests never touch fuzz/ (it is its own workspace).
#
# Targets (fuzz/fuzz_targets/): gltf, obj (+MTL), ply, map_yaml, map_image, episodes (JSON and
# .json.gz), robot_profile, nav_params, ros_msgs. Each starts from fuzz/seeds/TARGET (tiny
# valid inputs, written by fuzz/seeds/make_seeds.py) and fuzz/regressions/TARGET (inputs that
# once failed), and grows fuzz/corpus/TARGET (not checked in). A crash, panic, timeout or OOM
# leaves its input in fuzz/artifacts/TARGET/; fix the library, add the minimised input
# (`cargo +nightly fuzz tmin --fuzz-dir fuzz TARGET FILE`) to fuzz/regressions/TARGET and a
# test that reads it (see fuzz/regressions/README.md).
#
# Environment: FUZZ_SANITIZER (default none: the code under test is safe Rust, and what we look
# for are panics, overflows (debug assertions are on), hangs and OOMs; `address` for ASan),
# FUZZ_CGU (codegen units, default 16), FUZZ_TIMEOUT (s per input, default 10), FUZZ_RSS_MB (default 2048), FUZZ_MAX_LEN (bytes,
# default 65536). Logs go to fuzz/logs/TARGET.log; each run ends with one summary line:
# TARGET runs execs/s cov ft corpus status.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
targets=(gltf obj ply map_yaml map_image episodes robot_profile nav_params ros_msgs)

usage() {
    sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'
    exit 2
}

[[ $# -ge 1 ]] || usage
if [[ $1 == list ]]; then
    printf '%s\n' "${targets[@]}"
    exit 0
fi
[[ $# -eq 2 && $2 =~ ^[0-9]+$ ]] || usage
seconds=$2

if ! cargo +nightly --version >/dev/null 2>&1; then
    echo "fuzz.sh: the nightly toolchain is missing: rustup toolchain install nightly" >&2
    exit 2
fi
if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    echo "fuzz.sh: cargo-fuzz is missing: cargo install cargo-fuzz" >&2
    exit 2
fi

sanitizer=${FUZZ_SANITIZER:-none}
# Release with debug assertions and overflow checks; 16 codegen units (FUZZ_CGU) build the
# instrumented dependencies (wgpu, rapier3d, roslibrust, ...) much faster for little speed.
build_flags=(--fuzz-dir fuzz --sanitizer "$sanitizer" --debug-assertions --codegen-units "${FUZZ_CGU:-16}")

run_one() {
    local t=$1
    local corpus=fuzz/corpus/$t log=fuzz/logs/$t.log
    mkdir -p "$corpus" fuzz/logs "fuzz/artifacts/$t"
    local dirs=("$corpus" "fuzz/seeds/$t")
    [[ -d fuzz/regressions/$t ]] && dirs+=("fuzz/regressions/$t")
    local status=ok
    cargo +nightly fuzz run "${build_flags[@]}" "$t" "${dirs[@]}" -- \
        -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb="${FUZZ_RSS_MB:-2048}" \
        -max_len="${FUZZ_MAX_LEN:-65536}" -print_final_stats=1 >"$log" 2>&1 || status=FAILED
    # The last status line libFuzzer printed: "#N  DONE|pulse  cov: C ft: F corp: K/S ... exec/s: E".
    local last runs cov ft corp eps
    last=$(grep -E '^#[0-9]+' "$log" | tail -n 1 || true)
    runs=$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$last")
    cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$last")
    ft=$(sed -nE 's/.*ft: ([0-9]+).*/\1/p' <<<"$last")
    corp=$(sed -nE 's/.*corp: ([0-9]+\/[0-9]+[a-zA-Z]*).*/\1/p' <<<"$last")
    eps=$(sed -nE 's/^stat::average_exec_per_sec: *([0-9]+)/\1/p' "$log" | tail -n 1)
    printf '%-14s runs %-10s exec/s %-7s cov %-6s ft %-7s corpus %-12s %s\n' \
        "$t" "${runs:-?}" "${eps:-?}" "${cov:-?}" "${ft:-?}" "${corp:-?}" "$status"
    if [[ $status != ok ]]; then
        grep -E 'panicked at|ERROR: libFuzzer|SUMMARY|Test unit written' "$log" | head -n 5 >&2 || true
        return 1
    fi
}

if [[ $1 == all ]]; then
    cargo +nightly fuzz build "${build_flags[@]}"
    failed=0
    for t in "${targets[@]}"; do
        run_one "$t" || failed=1
    done
    exit $failed
fi

for t in "${targets[@]}"; do
    if [[ $t == "$1" ]]; then
        run_one "$t"
        exit $?
    fi
done
echo "fuzz.sh: unknown target '$1' (targets: ${targets[*]})" >&2
exit 2
