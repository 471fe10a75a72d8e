"""Shared fixtures: a small procedural scene, episodes generated in it, and the xhab CLI.

The CLI (for comparisons with ``xhab bench``) is ``$XHAB_BIN``, else ``target/debug/xhab``
or ``target/release/xhab`` of this repository; ``scripts/python_tests.sh`` builds it and sets
``XHAB_BIN``. Without one those tests skip loudly, unless ``XHAB_REQUIRE_CLI=1``.
"""

import json
import os
import pathlib
import subprocess

import pytest

import xhab

REPO = pathlib.Path(__file__).resolve().parents[2]
SCENE = "procedural:1"


@pytest.fixture(scope="session")
def episodes(tmp_path_factory):
    """Six episodes with Habitat's rules in the procedural house (seed 1)."""
    path = tmp_path_factory.mktemp("episodes") / "pointnav.json.gz"
    xhab.generate_episodes(SCENE, 6, seed=0, out=path)
    return path


def _cli():
    env = os.environ.get("XHAB_BIN")
    if env:
        return pathlib.Path(env)
    for p in (REPO / "target" / "debug" / "xhab", REPO / "target" / "release" / "xhab"):
        if p.exists():
            return p
    return None


@pytest.fixture(scope="session")
def cli_bench(tmp_path_factory):
    """Runs ``xhab bench --agent AGENT`` (oracle unless given) and returns its JSON report."""
    exe = _cli()
    if exe is None or not exe.exists():
        msg = "no xhab CLI (set XHAB_BIN or build it with `cargo build -p xhab`)"
        if os.environ.get("XHAB_REQUIRE_CLI") == "1":
            pytest.fail(msg)
        pytest.skip("SKIPPED LOUDLY: " + msg)
    out_dir = tmp_path_factory.mktemp("cli")

    def run(episodes, *args, agent="oracle"):
        out = out_dir / f"bench{len(list(out_dir.iterdir()))}.json"
        subprocess.run([str(exe), "--quiet", "bench", "--scene", SCENE, "--episodes", str(episodes), "--agent", agent,
                        "--out", str(out), *args], check=True, capture_output=True)
        return json.loads(out.read_text())

    return run


def pytest_runtest_logreport(report):
    """Records a skipped test and its reason in ``$XHAB_SKIP_LOG``, when set, for the summary
    the README's test command prints at the end."""
    log = os.environ.get("XHAB_SKIP_LOG")
    if log and report.skipped:
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else str(report.longrepr)
        with open(log, "a") as f:
            f.write("%s: %s\n" % (report.nodeid, reason))
