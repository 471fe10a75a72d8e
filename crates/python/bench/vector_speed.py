"""Steps per second of ``xhab.VectorPointNavEnv`` through Python (random actions, one depth
camera), beside ``xhab perf --sensors depth`` on the same scene (the Python layer's overhead)
and, with ``--habitat``, beside habitat-sim 0.2.2 stepping with the same depth sensor
(../shared/peers/habitat, built by its setup.sh). Rounds are interleaved; medians reported.

    python crates/python/bench/vector_speed.py SCENE.glb [--n 1 2] [--resolution 256] [--seconds 3]
        [--rounds 3] [--cli target/release/xhab] [--habitat ../shared/peers/habitat]

Build the package in release (``pip install ./crates/python``) for figures worth comparing.
Prints one JSON document on stdout.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess
import tempfile
import time

import numpy as np

import xhab


def vector_steps_per_s(scene, n, threads, resolution, seconds, renderer, max_steps):
    """Environment steps per second (n per call) with random actions, as habitat's figure:
    move_forward 1/2, turn_left 1/4, turn_right 1/4, from a new start every ``max_steps``
    (50, as ``xhab perf`` and habitat's script restart). No action is stop, so every
    environment's episode ends at the same step; the call after it (the autoreset, which
    sets up new episodes) is left out of the timing, as both peers set up outside theirs."""
    env = xhab.VectorPointNavEnv(n, scene, sensors=("depth",), resolution=resolution, renderer=renderer,
                                 threads=threads, seed=0, max_steps=max_steps)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    choice = np.array([1, 1, 2, 3])
    ended = False
    steps, spent, t_end = 0, 0.0, time.perf_counter() + seconds * 3
    while spent < seconds and time.perf_counter() < t_end:
        actions = choice[rng.integers(0, 4, n)]
        t0 = time.perf_counter()
        _, _, terminated, truncated, _ = env.step(actions)
        dt = time.perf_counter() - t0
        if not ended:
            spent += dt
            steps += n
        ended = bool((terminated | truncated).any())
    env.close()
    return steps / spent


def cli_depth_steps_per_s(cli, scene, resolution, seconds, renderer):
    perf = subprocess.run([cli, "perf", scene, "--json", "-q", "--sensors", "depth", "--resolution", str(resolution),
                           "--renderer", renderer, "--seconds", str(seconds)], check=True, capture_output=True, text=True)
    return json.loads(perf.stdout)["depth_steps_per_s"]


def habitat_depth_steps_per_s(peer_dir, hpython, scene, resolution, seconds):
    """habitat-sim's ``sim.step`` + one depth image per second, through the peer's own script."""
    zup = pathlib.Path(tempfile.gettempdir()) / ("xhab_peer_" + pathlib.Path(scene).stem + "_zup.glb")
    if not zup.exists() or os.path.getmtime(zup) < os.path.getmtime(scene):
        subprocess.run([hpython, str(peer_dir / "convert.py"), scene, str(zup)], check=True, capture_output=True)
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        subprocess.run([hpython, str(peer_dir / "hab_side.py"), str(zup), "--out", out.name, "--seconds", "0.2",
                        "--depth-seconds", str(seconds), "--resolution", str(resolution)], check=True, capture_output=True)
        return json.load(open(out.name))["depth_steps_per_s"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("--n", type=int, nargs="+", default=[1, 2])
    p.add_argument("--resolution", type=int, default=256)
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--renderer", default="auto")
    p.add_argument("--max-steps", type=int, default=50,
                   help="steps from each start (50, as xhab perf and habitat's script)")
    p.add_argument("--cli", help="the xhab CLI, to run `xhab perf --sensors depth` for comparison")
    p.add_argument("--habitat", help="the habitat peer's folder (../shared/peers/habitat), to time habitat-sim too")
    p.add_argument("--hpython", default="/opt/habpeer/bin/hpython", help="the peer's Python launcher")
    a = p.parse_args()
    rounds = {"python": {str(n): [] for n in a.n}, "cli": [], "habitat": []}
    for _ in range(a.rounds):
        for n in a.n:
            rounds["python"][str(n)].append(vector_steps_per_s(a.scene, n, n, a.resolution, a.seconds, a.renderer, a.max_steps))
        if a.cli:
            rounds["cli"].append(cli_depth_steps_per_s(a.cli, a.scene, a.resolution, a.seconds, a.renderer))
        if a.habitat:
            rounds["habitat"].append(habitat_depth_steps_per_s(pathlib.Path(a.habitat), a.hpython, a.scene, a.resolution, a.seconds))
    med = {k: statistics.median(v) for k, v in rounds["python"].items()}
    out = {"scene": a.scene, "resolution": a.resolution, "seconds": a.seconds, "rounds": rounds,
           "vector_steps_per_s": med, "cpus": os.cpu_count(), "load_after": os.getloadavg()}
    if a.cli:
        cli = statistics.median(rounds["cli"])
        out["cli_depth_steps_per_s"] = cli
        # The overhead of the Python layer: one environment, one thread, against the CLI's loop.
        out["python_overhead"] = 1.0 - med[str(a.n[0])] / cli
    if a.habitat:
        hab = statistics.median(rounds["habitat"])
        out["habitat_depth_steps_per_s"] = hab
        out["ratio_over_habitat"] = {n: v / hab for n, v in med.items()}
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
