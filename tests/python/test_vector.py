"""``xhab.VectorPointNavEnv``: stacked observations, next-step autoreset, and per-episode
results that depend neither on the number of environments nor on the thread count."""

import numpy as np
import pytest

import xhab
from conftest import SCENE


def oracle_results(env, n, episodes_wanted, max_calls=5000):
    """Steps every environment with the shortest-path oracle; returns each finished
    episode's final info and the first observations, keyed by episode id."""
    followers = [xhab.ShortestPathFollower() for _ in range(n)]
    obs, infos = env.reset(seed=0)
    first = {infos["episode_id"][i]: {k: v[i].copy() for k, v in obs.items()} for i in range(n)}
    results, done = {}, np.zeros(n, dtype=bool)
    for _ in range(max_calls):
        actions = []
        for i in range(n):
            if done[i]:
                followers[i].reset()
                actions.append(3)  # ignored: this step resets environment i
            else:
                actions.append(followers[i].act(env.view(i)))
        obs, rewards, terminated, truncated, infos = env.step(actions)
        for i in range(n):
            if done[i]:
                assert rewards[i] == 0 and not terminated[i] and not truncated[i]
                first.setdefault(infos["episode_id"][i], {k: v[i].copy() for k, v in obs.items()})
            elif terminated[i] or truncated[i]:
                results.setdefault(infos["episode_id"][i], {k: infos[k][i] for k in ("steps", "spl", "success", "collisions", "distance_to_goal")})
        done = terminated | truncated
        if len(results) >= episodes_wanted:
            return results, first
    raise AssertionError("episodes did not finish")


@pytest.mark.parametrize("n,threads", [(1, 1), (3, 1), (3, 2), (4, 2)])
def test_results_do_not_depend_on_n_or_threads(episodes, n, threads):
    kw = dict(sensors=("depth",), resolution=16, renderer="raster", threads=threads)
    ref, ref_first = oracle_results(xhab.VectorPointNavEnv(1, SCENE, episodes, **kw), 1, 6)
    got, got_first = oracle_results(xhab.VectorPointNavEnv(n, SCENE, episodes, **kw), n, 6)
    assert got == ref
    for k in set(got_first) & set(ref_first):
        for key in ref_first[k]:
            assert np.array_equal(got_first[k][key], ref_first[k][key]), (k, key)


def test_stacked_spaces_and_shapes():
    env = xhab.VectorPointNavEnv(3, SCENE, sensors=("depth", "rgb"), resolution=8, renderer="raster", threads=2)
    obs, infos = env.reset(seed=1)
    assert obs["depth"].shape == (3, 8, 8, 1) and obs["rgb"].shape == (3, 8, 8, 3)
    assert obs["pointgoal_with_gps_compass"].shape == (3, 2) and obs["compass"].shape == (3, 1)
    assert obs in env.observation_space
    assert infos["_distance_to_goal"].all() and infos["distance_to_goal"].shape == (3,)
    obs, rewards, terminated, truncated, infos = env.step(env.action_space.sample())
    assert rewards.shape == (3,) and terminated.dtype == bool
    with pytest.raises(ValueError, match="expected 3 actions"):
        env.step([0, 0])
    env.close()


def test_step_twist_batches_velocity_commands():
    env = xhab.VectorPointNavEnv(2, SCENE, sensors=(), physics=True, seed=3, threads=2)
    env.reset(seed=3)
    poses = [env.view(i).pose for i in range(2)]
    obs, rewards, terminated, truncated, infos = env.step_twist([[0.0, 0.5], [0.0, -0.5]], 1.0)
    turned = [np.angle(np.exp(1j * (env.view(i).pose[2] - poses[i][2]))) for i in range(2)]
    assert turned[0] > 0.4 and turned[1] < -0.4
    assert list(infos["steps"]) == [1, 1] and not terminated.any()
    single = xhab.PointNavEnv(SCENE, sensors=(), physics=True, seed=3)
    single.reset(seed=3)
    single.step_twist(0.0, 0.5, 1.0)
    assert single.view().pose == env.view(0).pose
    with pytest.raises(ValueError, match="twists"):
        env.step_twist([[0.1, 0.0]], 1.0)
