"""``xhab.PointNavEnv``: Gymnasium's checker, habitat-lab's observations and reward, the
shortest-path oracle through the Gym loop, physics and velocity control."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import xhab
from conftest import SCENE

SMALL = dict(resolution=16, renderer="raster")


@pytest.mark.parametrize("kwargs", [
    dict(sensors=()),
    dict(sensors=("depth",), **SMALL),
    dict(sensors=("depth", "rgb"), physics=True, **SMALL),
    dict(sensors=("depth", "rgb"), render_mode="rgb_array", **SMALL),
])
def test_check_env(kwargs, episodes):
    check = "render_mode" not in kwargs
    check_env(xhab.PointNavEnv(SCENE, **kwargs), skip_render_check=check)
    check_env(xhab.PointNavEnv(SCENE, episodes, **kwargs), skip_render_check=check)


def test_observations_as_habitat_names_them():
    env = xhab.PointNavEnv(SCENE, sensors=("depth", "rgb"), **SMALL)
    obs, info = env.reset(seed=3)
    assert obs["depth"].shape == (16, 16, 1) and obs["depth"].dtype == np.float32
    assert obs["rgb"].shape == (16, 16, 3) and obs["rgb"].dtype == np.uint8
    assert obs["depth"].max() > 0.1 and obs["rgb"].max() > 0
    for k, n in (("pointgoal_with_gps_compass", 2), ("gps", 2), ("compass", 1)):
        assert obs[k].shape == (n,) and obs[k].dtype == np.float32
    assert np.allclose(obs["gps"], 0, atol=1e-6) and np.allclose(obs["compass"], 0, atol=1e-6)
    assert obs["pointgoal_with_gps_compass"][0] <= info["distance_to_goal"] + 1e-5
    # Turning left: the compass grows (CCW), the goal's bearing falls by the same angle.
    bearing = obs["pointgoal_with_gps_compass"][1]
    obs, *_ = env.step(2)
    assert np.isclose(obs["compass"][0], np.radians(10), atol=1e-6)
    assert np.isclose(np.angle(np.exp(1j * (bearing - obs["pointgoal_with_gps_compass"][1]))), np.radians(10), atol=1e-5)
    # Forward after turning left by 90 degrees: GPS (forward, right) goes to the left, negative.
    env.reset(seed=3)
    for _ in range(9):
        env.step(2)
    before = env.view().pose
    obs, _, _, _, info = env.step(1)
    if not info["collided"]:
        after = env.view().pose
        moved = np.hypot(after[0] - before[0], after[1] - before[1])
        assert np.isclose(obs["gps"][1], -moved, atol=1e-5) and abs(obs["gps"][0]) < 1e-5


def run_oracle(env, **reset):
    follower = xhab.ShortestPathFollower()
    obs, info = env.reset(**reset)
    d0, total = info["distance_to_goal"], 0.0
    while True:
        obs, reward, terminated, truncated, info = env.step(follower.act(env.view()))
        total += reward
        if terminated or truncated:
            return d0, total, terminated, truncated, info


def test_reward_is_habitats():
    env = xhab.PointNavEnv(SCENE, sensors=())
    d0, total, terminated, truncated, info = run_oracle(env, seed=7)
    assert terminated and not truncated and info["success"] == 1.0 and info["called_stop"]
    expected = d0 - info["distance_to_goal"] - 0.01 * info["steps"] + 2.5
    assert abs(total - expected) < 1e-9
    with pytest.raises(RuntimeError, match="episode is over"):
        env.step(0)


@pytest.mark.parametrize("physics", [False, True])
def test_gym_oracle_matches_cli(episodes, cli_bench, physics):
    cli = cli_bench(episodes, *(["--physics"] if physics else []))
    env = xhab.PointNavEnv(SCENE, episodes, sensors=(), physics=physics)
    for e in cli["episodes"]:
        *_, info = run_oracle(env, options={"episode_id": e["episode_id"]})
        assert info["steps"] == e["steps"] and info["collisions"] == e["collisions"]
        assert abs(info["spl"] - e["spl"]) <= 1e-9 and abs(info["distance_to_goal"] - e["distance_to_goal"]) <= 1e-9


def test_episodes_in_file_order_and_by_id(episodes):
    env = xhab.PointNavEnv(SCENE, episodes, sensors=())
    ids = env.episode_ids
    assert [env.reset()[1]["episode_id"] for _ in range(len(ids) + 1)] == ids + ids[:1]
    assert env.reset(options={"episode_id": ids[3]})[1]["episode_id"] == ids[3]
    assert env.reset(seed=1)[1]["episode_id"] == ids[0]


def test_generated_episodes_are_seeded():
    a = xhab.PointNavEnv(SCENE, sensors=(), seed=5)
    b = xhab.PointNavEnv(SCENE, sensors=(), seed=5)
    ra = [a.reset()[1]["distance_to_goal"] for _ in range(3)]
    assert ra == [b.reset()[1]["distance_to_goal"] for _ in range(3)]
    assert a.reset(seed=5)[1]["distance_to_goal"] == ra[0]
    assert a.reset(seed=6)[1]["distance_to_goal"] != ra[0]


def test_step_twist_under_physics():
    env = xhab.PointNavEnv(SCENE, sensors=(), physics=True, seed=2)
    env.reset()
    x0, y0, yaw0 = env.view().pose
    obs, reward, terminated, truncated, info = env.step_twist(0.0, 0.5, 1.0)
    assert abs(np.angle(np.exp(1j * (env.view().pose[2] - yaw0))) - 0.5) < 0.05
    # Steps count control periods of simulated time begun (PhysicsEnv::drive): 1 s is one.
    assert not terminated and info["steps"] == 1
    obs, *_ = env.step_twist(0.2, 0.0, 0.5)
    assert 0.0 < np.hypot(env.view().pose[0] - x0, env.view().pose[1] - y0) < 0.2
    obs, reward, terminated, truncated, info = env.step(0)
    assert terminated and info["called_stop"]
    plain = xhab.PointNavEnv(SCENE, sensors=())
    plain.reset()
    with pytest.raises(ValueError, match="needs physics"):
        plain.step_twist(0.1, 0.0, 1.0)


def test_geodesic_distance_matches_episode_file(episodes, tmp_path):
    data = xhab.generate_episodes(SCENE, 2, seed=4)
    env = xhab.PointNavEnv(SCENE, sensors=())
    for e in data["episodes"]:
        d = e["info"]["geodesic_distance"]
        a, b = e["start_position"], e["goals"][0]["position"]
        assert abs(xhab.geodesic_distance(SCENE, a, b) - d) < 1e-9
        assert abs(env.geodesic_distance(a, b) - d) < 1e-9
    assert xhab.geodesic_distance(SCENE, [100, 0, 100], [0, 0, 0]) == float("inf")
    m = xhab.make_map(SCENE, tmp_path / "maps" / "house")
    assert (tmp_path / "maps" / "house.yaml").exists() and (tmp_path / "maps" / "house.pgm").exists()
    assert m["png"] == str(tmp_path / "maps" / "house.png")
    assert (tmp_path / "maps" / "house.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert m["width"] > 0 and m["resolution"] == 0.05


def test_render_rgb_array():
    env = xhab.PointNavEnv(SCENE, sensors=("depth", "rgb"), resolution=32, render_mode="rgb_array")
    assert env.render() is None
    obs, _ = env.reset()
    frame = env.render()
    assert frame.shape == (32, 32, 3) and frame.dtype == np.uint8
    assert np.array_equal(frame, obs["rgb"])
    depth_only = xhab.PointNavEnv(SCENE, sensors=("depth",), resolution=16, render_mode="rgb_array")
    obs, _ = depth_only.reset()
    grey = depth_only.render()
    assert grey.shape == (16, 16, 3)
    # Nearer is brighter; no return is black.
    d = obs["depth"][..., 0]
    hit = d > 0
    assert hit.any()
    near, far = np.unravel_index(np.argmin(np.where(hit, d, np.inf)), d.shape), np.unravel_index(np.argmax(d), d.shape)
    assert grey[near][0] >= grey[far][0]
    with pytest.raises(ValueError, match="render_mode"):
        xhab.PointNavEnv(SCENE, sensors=(), render_mode="rgb_array")
    with pytest.raises(ValueError, match="render_mode"):
        xhab.PointNavEnv(SCENE, render_mode="human")


def test_cross_floor_episodes_run_through_the_gym_loop(tmp_path):
    # The two-storey house: episodes whose goal is upstairs or downstairs, climbed by the oracle.
    path = tmp_path / "xf.json.gz"
    ds = xhab.generate_episodes("procedural:1", 4, seed=2, out=path, cross_floor=True, storeys=2)
    assert all(abs(e["start_position"][1] - e["goals"][0]["position"][1]) > 2.0 for e in ds["episodes"])
    env = xhab.PointNavEnv("procedural:1", path, sensors=(), storeys=2)
    for e in ds["episodes"]:
        *_, info = run_oracle(env, options={"episode_id": e["episode_id"]})
        assert info["success"] == 1.0 and info["spl"] > 0.9, info
