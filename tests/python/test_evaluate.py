"""``xhab.evaluate``: a Python agent through the library's runner gives the report of
``xhab bench --out``, and a Python oracle gives exactly the CLI oracle's metrics."""

import signal

import numpy as np
import pytest

import xhab
from conftest import SCENE


class PythonOracle:
    """Habitat's shortest-path follower, driven from Python through the privileged view."""

    def __init__(self):
        self.follower = xhab.ShortestPathFollower()

    def reset(self):
        self.follower.reset()

    def act(self, obs, view):
        return self.follower.act(view)


class ReactiveDepth:
    """Turns away from the nearest depth when closer than 0.5 m, else faces the goal and
    moves forward; stops within 0.2 m of the (Euclidean) goal."""

    def act(self, obs):
        dist, bearing = obs["pointgoal_with_gps_compass"]
        if dist < 0.18:
            return 0
        depth = obs["depth"][..., 0]
        h, w = depth.shape
        centre = depth[h // 3: 2 * h // 3, w // 3: 2 * w // 3]
        near = centre[centre > 0]
        if near.size and near.min() < 0.5:
            return 2 if depth[:, : w // 2].mean() > depth[:, w // 2:].mean() else 3
        if abs(bearing) > np.radians(10):
            return 2 if bearing > 0 else 3
        return 1


def check_same(py, cli):
    """Same episodes, same steps, collisions and stop calls; metrics to 1e-9."""
    assert [e["episode_id"] for e in py["episodes"]] == [e["episode_id"] for e in cli["episodes"]]
    assert py["invalid"]["episode_ids"] == cli["invalid"]["episode_ids"]
    for a, b in zip(py["episodes"], cli["episodes"]):
        for k in ("steps", "collisions", "called_stop"):
            assert a[k] == b[k], (a["episode_id"], k)
        for k in ("success", "spl", "soft_spl", "distance_to_goal", "path_length", "start_distance"):
            assert abs(a[k] - b[k]) <= 1e-9, (a["episode_id"], k, a[k], b[k])
    for k in ("episodes", "success", "spl", "soft_spl", "distance_to_goal", "steps", "collisions"):
        assert abs(py["aggregate"][k] - cli["aggregate"][k]) <= 1e-9, k


def same_keys(a, b, path="report"):
    """The same field names, recursively (dicts) and in the same order."""
    assert list(a) == list(b), path
    for k in a:
        if isinstance(a[k], dict):
            same_keys(a[k], b[k], f"{path}.{k}")
    if "episodes" in a and isinstance(a["episodes"], list) and a["episodes"] and b["episodes"]:
        assert list(a["episodes"][0]) == list(b["episodes"][0])


def test_python_oracle_matches_cli_oracle(episodes, cli_bench):
    cli = cli_bench(episodes)
    py = xhab.evaluate(PythonOracle(), SCENE, episodes, privileged=True)
    check_same(py, cli)
    assert py["aggregate"]["success"] == 1.0
    same_keys({k: v for k, v in py.items() if k != "agent"}, {k: v for k, v in cli.items() if k != "agent"})
    assert py["agent"] == "PythonOracle" and cli["agent"] == "oracle"


def test_python_oracle_matches_cli_oracle_under_physics(episodes, cli_bench):
    cli = cli_bench(episodes, "--physics")
    py = xhab.evaluate(PythonOracle(), SCENE, episodes, physics=True, privileged=True)
    check_same(py, cli)
    for a, b in zip(py["episodes"], cli["episodes"]):
        assert a["sim_s"] == b["sim_s"] and a["stuck"] == b["stuck"]
    assert py["physics"] == cli["physics"]
    same_keys({k: v for k, v in py.items() if k != "agent"}, {k: v for k, v in cli.items() if k != "agent"})


def test_sensors_reach_the_agent_and_the_report(episodes, cli_bench):
    seen = []

    def agent(obs, view):
        seen.append((obs["depth"].shape, obs["depth"].dtype, obs["rgb"].shape, obs["rgb"].dtype))
        return follower.act(view)

    follower = xhab.ShortestPathFollower()
    args = dict(sensors=("depth", "rgb"), resolution=16, renderer="raster")
    cli = cli_bench(episodes, "--sensors", "depth,rgb", "--resolution", "16", "--renderer", "raster")
    py = xhab.evaluate(agent, SCENE, episodes, privileged=True, **args)
    assert set(seen) == {((16, 16, 1), np.dtype(np.float32), (16, 16, 3), np.dtype(np.uint8))}
    assert py["camera"] == cli["camera"]
    assert py["aggregate"]["frames"] == cli["aggregate"]["frames"] == len(seen)


def test_builtin_bench_matches_cli(episodes, cli_bench):
    check_same(xhab.bench(SCENE, episodes), cli_bench(episodes))


def test_builtin_nav_bench_matches_cli(episodes, cli_bench):
    """The native stack through ``xhab.bench`` is the CLI's run: same library call, same numbers."""
    py = xhab.bench(SCENE, episodes, agent="nav", robot="turtlebot3_burger", localization="odom", threads=2)
    cli = cli_bench(episodes, "--robot", "turtlebot3_burger", "--localization", "odom", "--threads", "2", agent="nav")
    check_same(py, cli)
    same_keys(py, cli)
    assert py["agent"] == "nav" and py["nav"]["localization"] == cli["nav"]["localization"]
    assert py["physics"]["robot"] == cli["physics"]["robot"]
    assert py["aggregate"]["success"] > 0.5


def test_threads_do_not_change_results(episodes):
    one = xhab.evaluate(ReactiveDepth(), SCENE, episodes, sensors=("depth",), resolution=32, renderer="raster")
    two = xhab.evaluate(ReactiveDepth(), SCENE, episodes, sensors=("depth",), resolution=32, renderer="raster", threads=2)
    check_same(one, two)
    assert two["threads"] == 2


def test_reactive_agent_with_and_without_physics(episodes):
    """ROS-X-Habitat's experiment shape: one agent, both configurations, failures by cause."""
    out = {}
    for physics in (False, True):
        r = xhab.evaluate(ReactiveDepth(), SCENE, episodes, physics=physics, sensors=("depth",), resolution=32,
                          renderer="raster", max_steps=200)
        agg = r["aggregate"]
        failures = agg["failures"]
        assert set(failures) == {"stuck", "stopped_outside", "step_limit", "aborted", "goal_unreachable_for_costmap"}
        # A discrete Python agent never aborts (only the navigator does).
        assert failures["aborted"] == 0 and failures["goal_unreachable_for_costmap"] == 0
        assert sum(failures.values()) == round(agg["episodes"] * (1 - agg["success"]))
        assert ("sim_s" in agg) == physics and ("stuck" in agg) == physics
        out[physics] = agg
    print({p: {k: a[k] for k in ("success", "spl", "failures")} for p, a in out.items()})


def test_callable_agent_and_reset_calls(episodes):
    calls = {"reset": 0, "act": 0}

    class Stopper:
        def reset(self):
            calls["reset"] += 1

        def act(self, obs):
            calls["act"] += 1
            return np.int64(0)

    r = xhab.evaluate(Stopper(), SCENE, episodes)
    assert calls == {"reset": 6, "act": 6}
    assert all(e["steps"] == 1 and e["called_stop"] for e in r["episodes"])
    r = xhab.evaluate(lambda obs: 0, SCENE, episodes, agent_name="stopper")
    assert r["agent"] == "stopper" and r["aggregate"]["steps"] == 1


def test_agent_errors_propagate(episodes):
    def boom(obs):
        raise ZeroDivisionError("agent failed")

    with pytest.raises(ZeroDivisionError, match="agent failed"):
        xhab.evaluate(boom, SCENE, episodes)
    with pytest.raises(ValueError, match="bad action 7"):
        xhab.evaluate(lambda obs: 7, SCENE, episodes)
    with pytest.raises(TypeError, match="agent"):
        xhab.evaluate(42, SCENE, episodes)


@pytest.fixture
def sigint():
    """Python's own Ctrl-C handler, even where the test runner was started with SIGINT
    ignored (a background job of a non-interactive shell), and the old one put back."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, old)


def test_ctrl_c_interrupts_evaluate(episodes, sigint):
    steps = []

    def agent(obs):
        steps.append(1)
        if len(steps) == 3:
            signal.raise_signal(signal.SIGINT)
        return 2  # turn forever: without the interrupt each episode runs to its step limit

    with pytest.raises(KeyboardInterrupt):
        xhab.evaluate(agent, SCENE, episodes)
    assert len(steps) < 500


def test_ctrl_c_interrupts_a_parallel_evaluate(episodes, sigint):
    import time

    steps = []

    def agent(obs):
        steps.append(1)
        if len(steps) == 3:
            signal.raise_signal(signal.SIGINT)
        time.sleep(0.001)
        return 2

    with pytest.raises(KeyboardInterrupt):
        xhab.evaluate(agent, SCENE, episodes, threads=2)
    assert len(steps) < 1000
