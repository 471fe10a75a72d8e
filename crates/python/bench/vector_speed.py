"""Steps per second of ``xhab.VectorPointNavEnv`` through Python (random actions, depth
camera), beside ``xhab perf --sensors depth`` on the same scene: the Python layer's overhead.

    python crates/python/bench/vector_speed.py SCENE [--n 1 2] [--resolution 256] [--seconds 3] [--cli target/release/xhab]

Build the package in release (``pip install ./crates/python``) for figures worth comparing.
Prints one JSON document on stdout.
"""

import argparse
import json
import subprocess
import time

import numpy as np

import xhab


def vector_steps_per_s(scene, n, threads, resolution, seconds, renderer):
    env = xhab.VectorPointNavEnv(n, scene, sensors=("depth",), resolution=resolution, renderer=renderer,
                                 threads=threads, seed=0)
    env.reset(seed=0)
    rng = np.random.default_rng(0)
    for _ in range(5):
        env.step(rng.integers(1, 4, n))
    steps, t0 = 0, time.perf_counter()
    while time.perf_counter() - t0 < seconds:
        env.step(rng.integers(1, 4, n))
        steps += n
    return steps / (time.perf_counter() - t0)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("--n", type=int, nargs="+", default=[1, 2])
    p.add_argument("--resolution", type=int, default=256)
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--renderer", default="auto")
    p.add_argument("--cli", help="the xhab CLI, to run `xhab perf --sensors depth` for comparison")
    a = p.parse_args()
    out = {"scene": a.scene, "resolution": a.resolution, "vector_steps_per_s": {}}
    for n in a.n:
        out["vector_steps_per_s"][str(n)] = vector_steps_per_s(a.scene, n, n, a.resolution, a.seconds, a.renderer)
    if a.cli:
        perf = subprocess.run([a.cli, "perf", a.scene, "--json", "--sensors", "depth", "--resolution", str(a.resolution),
                               "--renderer", a.renderer, "--seconds", str(a.seconds)], check=True, capture_output=True, text=True)
        cli = json.loads(perf.stdout)["depth_steps_per_s"]
        out["cli_depth_steps_per_s"] = cli
        out["python_overhead"] = 1.0 - out["vector_steps_per_s"][str(a.n[0])] / cli
    print(json.dumps(out, indent=2))


if __name__ == "__main__":
    main()
