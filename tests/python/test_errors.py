"""Bad input raises Python exceptions with the CLI's messages; nothing panics."""

import pytest

import xhab
from conftest import SCENE


def test_missing_scene_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError, match="loading scene .*nope.glb"):
        xhab.PointNavEnv(str(tmp_path / "nope.glb"))


def test_missing_episodes_file_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError, match="reading episodes"):
        xhab.PointNavEnv(SCENE, tmp_path / "nope.json.gz")
    with pytest.raises(FileNotFoundError):
        xhab.evaluate(lambda o: 0, SCENE, tmp_path / "nope.json.gz")


@pytest.mark.parametrize("kwargs,message", [
    (dict(scene="procedural:x"), "bad scene 'procedural:x': the seed after 'procedural:' must be a whole number"),
    (dict(sensors=("depth", "lidar")), "--sensors: unknown sensor 'lidar' (depth, rgb)"),
    (dict(resolution=0), "bad camera: --resolution must be in 1..=4096 and --hfov in (0, 180)"),
    (dict(physics=True, robot="r2d2"), "--robot r2d2: unknown robot profile 'r2d2'"),
    (dict(depth_noise=-1.0), "--depth-noise must be >= 0 and --edge-dropout in [0, 1]"),
    (dict(renderer="opengl"), "renderer: unknown renderer 'opengl'"),
    (dict(floor="upstairs"), "bad --floor 'upstairs'"),
])
def test_bad_options_are_value_errors(kwargs, message):
    kwargs = dict(kwargs)
    scene = kwargs.pop("scene", SCENE)
    with pytest.raises(ValueError) as e:
        env = xhab.PointNavEnv(scene, **kwargs)
        env.reset()
    assert message in str(e.value)


def test_unknown_option_is_type_error():
    with pytest.raises(TypeError, match="unknown option 'resolutoin'"):
        xhab.PointNavEnv(SCENE, resolutoin=64)


def test_bad_calls(episodes):
    env = xhab.PointNavEnv(SCENE, episodes, sensors=())
    with pytest.raises(RuntimeError, match="reset"):
        env.step(1)
    env.reset()
    for bad in (4, -1, "forward", 1.5):
        with pytest.raises(ValueError, match="bad action"):
            env.step(bad)
    with pytest.raises(ValueError, match="no episode with id 'missing'"):
        env.reset(options={"episode_id": "missing"})
    with pytest.raises(ValueError, match="bad twist"):
        xhab.PointNavEnv(SCENE, sensors=(), physics=True).step_twist(float("nan"), 0, 1)
    with pytest.raises(ValueError, match="episode_id needs an episodes file"):
        xhab.PointNavEnv(SCENE, sensors=()).reset(options={"episode_id": "0"})
    with pytest.raises(ValueError, match="agent 'walker'"):
        xhab.bench(SCENE, episodes, agent="walker")
    with pytest.raises(ValueError, match="localization: unknown 'gps'"):
        xhab.bench(SCENE, episodes, agent="nav", localization="gps")
    with pytest.raises(FileNotFoundError, match="missing.yaml"):
        xhab.bench(SCENE, episodes, agent="nav", nav_params=["missing.yaml"])
    with pytest.raises(ValueError, match="needs laser scans"):
        xhab.bench(SCENE, episodes, agent="nav", localization="amcl", scan_source=None)
    with pytest.raises(ValueError, match="at least one"):
        xhab.VectorPointNavEnv(0, SCENE)
