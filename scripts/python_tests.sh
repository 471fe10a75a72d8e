#!/usr/bin/env bash
# The Python package's tests: makes a virtual environment (.venv, if missing) with maturin,
# pytest, gymnasium and numpy, builds the `xhab` extension into it (`maturin develop`, the
# workspace's dev profile, which optimises), builds the CLI the tests compare against, and
# runs pytest on tests/python. Exits non-zero when anything fails, including when
# pytest collects no test (its exit status 5).
#
# Environment: PYTHON (default python3, CPython >= 3.9), XHAB_VENV (default .venv).
set -euo pipefail
cd "$(dirname "$0")/.."

python=${PYTHON:-python3}
venv=${XHAB_VENV:-.venv}
if [ ! -x "$venv/bin/python" ]; then
  "$python" -m venv "$venv" || {
    echo "xhab python tests: '$python -m venv' failed (on Debian: apt-get install python3-venv)" >&2
    exit 1
  }
fi
venv=$(cd "$venv" && pwd)
"$venv/bin/python" -m pip install -q --disable-pip-version-check maturin pytest gymnasium numpy

# The CLI that `xhab bench` comparisons run.
cargo build -q -p xhab --locked
# (Absolute: pytest runs from crates/python, and a relative CARGO_TARGET_DIR is from here.)
export XHAB_BIN="$(realpath -m "${CARGO_TARGET_DIR:-target}")/debug/xhab"
export XHAB_REQUIRE_CLI=1

# maturin develop installs into the active virtual environment.
(
  cd crates/python
  VIRTUAL_ENV="$venv" PATH="$venv/bin:$PATH" "$venv/bin/maturin" develop -q --locked
)

status=0
"$venv/bin/python" -m pytest -q tests/python "$@" || status=$?
if [ "$status" = 5 ]; then
  echo "xhab python tests: pytest collected no test" >&2
  exit 1
fi
exit "$status"
