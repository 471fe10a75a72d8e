"""xhab: fast, deterministic Habitat-style PointNav in Python.

- ``PointNavEnv``: a ``gymnasium.Env`` with habitat-lab's observations (``depth``, ``rgb``,
  ``pointgoal_with_gps_compass``, ``gps``, ``compass``), actions (0 stop, 1 move_forward,
  2 turn_left, 3 turn_right), reward and metrics; ``physics=True`` runs each action as
  Algorithm 1 under rapier3d, and ``step_twist(v, w, duration)`` drives with velocities.
- ``VectorPointNavEnv``: n environments stepped in parallel in Rust (``gymnasium.vector``
  conventions, next-step autoreset).
- ``evaluate(agent, scene, episodes)``: any Python agent on every episode, with the same
  report as ``xhab bench --out``; ``bench`` runs a built-in agent (oracle, nav, ros).
- ``experiment(spec)``: a study (scenes x agents x ±physics ±ROS x seeds) as
  ``xhab experiment`` runs it, whole or one shard; ``merge`` combines shards.
- ``geodesic_distance``, ``generate_episodes``, ``make_map``: the CLI's other jobs.

Scenes are ``.glb``/``.gltf``/``.obj``/``.ply`` files or ``procedural[:SEED]``. Points are in
Habitat's frame ``[x, y, z]`` with y up (metres).
"""

import json as _json
import os as _os

from . import _xhab
from ._xhab import EpisodeView, ShortestPathFollower
from .env import AgentAdapter as _AgentAdapter, PointNavEnv, VectorPointNavEnv, options as _options

__all__ = [
    "PointNavEnv",
    "VectorPointNavEnv",
    "evaluate",
    "bench",
    "geodesic_distance",
    "generate_episodes",
    "make_map",
    "experiment",
    "merge",
    "ShortestPathFollower",
    "EpisodeView",
]


def evaluate(agent, scene, episodes, *, physics=False, robot="habitat", sensors=(), resolution=256, hfov=90,
             threads=1, seed=0, privileged=False, agent_name=None, **kwargs):
    """Runs ``agent`` on every episode of the ``episodes`` file and returns the report that
    ``xhab bench --out`` writes (a dict with the same fields: ``aggregate``, ``episodes``,
    ``invalid``, ...).

    ``agent`` is a callable ``act(obs) -> action`` or an object with ``act(obs)`` and,
    optionally, ``reset()`` (called before each episode). ``obs`` holds the observations that
    ``PointNavEnv`` gives. With ``privileged=True``, ``act(obs, view)`` also receives an
    ``EpisodeView`` (ground-truth pose, geodesic distances) for oracles, e.g. with
    ``ShortestPathFollower().act(view)``. With ``threads > 1`` episodes run in parallel,
    each with its own ``copy.deepcopy`` of the agent; results do not depend on it.
    Other keywords are ``PointNavEnv``'s (``max_steps``, ``success_distance``, ``renderer``,
    ``control_period``, ...). Ctrl-C stops the run with ``KeyboardInterrupt``.
    """
    opts = _options(physics=physics, robot=robot, sensors=sensors, resolution=resolution, hfov=hfov, **kwargs)
    name = agent_name or getattr(agent, "name", None) or getattr(agent, "__name__", None) or type(agent).__name__
    shape = (int(resolution), int(resolution), "rgb" in opts["sensors"]) if opts["sensors"] else None
    adapter = _AgentAdapter(agent, shape, opts["sensors"], bool(privileged))
    report = _xhab.evaluate(adapter, str(scene), _os.fspath(episodes), int(threads), int(seed), bool(privileged), str(name), opts)
    return _json.loads(report)


_BENCH_EXTRAS = ("localization", "map", "nav_params", "scan_source", "ros_master", "launch", "episode_timeout",
                 "map_odom", "goal_interface", "controller_frequency")


def bench(scene, episodes, *, agent="oracle", physics=False, robot="habitat", sensors=(), threads=1, seed=0, **kwargs):
    """``xhab bench`` with a built-in agent, through the same library call as the CLI;
    returns the report (the dict ``xhab bench --out`` writes).

    ``agent``: ``"oracle"`` (Habitat's shortest-path follower), ``"nav"`` (xhab's native
    stack: costmaps, planner, DWA, navigator; it drives the ``robot`` under physics) or
    ``"ros"`` (an external ROS 1 stack, as ``xhab bench --agent ros``). Navigation keywords:
    ``localization`` (``"ground-truth"``, ``"odom"``, ``"amcl"``), ``map`` (map_server YAML),
    ``nav_params`` (ROS parameter files, ``"FILE[@NAMESPACE]"``, layered), ``scan_source``
    (``"lidar"``, ``"depth"`` or ``None`` for no scans). External stack keywords:
    ``ros_master``, ``launch``, ``episode_timeout``, ``map_odom``, ``goal_interface``,
    ``controller_frequency``. Other keywords are ``PointNavEnv``'s. Unknown nav parameters
    come back as ``UserWarning``s.
    """
    extras = {k: kwargs.pop(k) for k in list(kwargs) if k in _BENCH_EXTRAS}
    if "nav_params" in extras and isinstance(extras["nav_params"], (str, _os.PathLike)):
        extras["nav_params"] = [extras["nav_params"]]
    if "nav_params" in extras:
        extras["nav_params"] = [_os.fspath(f) for f in extras["nav_params"]]
    if extras.get("map") is not None:
        extras["map"] = _os.fspath(extras["map"])
    # The nav and ros agents drive with velocities: always under physics, with ``robot``.
    physics = physics or agent in ("nav", "ros")
    opts = _options(physics=physics, robot=robot, sensors=sensors, **kwargs)
    return _json.loads(_xhab.bench(str(scene), _os.fspath(episodes), str(agent), int(threads), int(seed), opts, extras))


def geodesic_distance(scene, a, b, **kwargs):
    """Geodesic distance (m) of the disc agent between Habitat-frame points ``a`` and ``b``
    (``[x, y, z]``, y up); ``inf`` across islands or floors or where either is not navigable.
    Loads the scene each call: inside an environment use ``env.geodesic_distance``."""
    return _xhab.geodesic_distance(str(scene), [float(v) for v in a], [float(v) for v in b], _options(**kwargs))


def generate_episodes(scene, count, seed=0, out=None, *, floor="auto", scene_id=None, cross_floor=False, **kwargs):
    """PointNav episodes generated with Habitat's rules (byte-identical for a seed); written
    to ``out`` (``.json.gz`` or ``.json``) when given. With ``cross_floor=True``, pairs on
    different storeys joined by stairs (``xhab episodes --cross-floor``; ``floor`` does not
    apply). Returns the dataset in Habitat's JSON layout (``{"episodes": [...]}``)."""
    text = _xhab.generate_episodes(str(scene), int(count), int(seed), None if out is None else _os.fspath(out),
                                   str(floor), scene_id, bool(cross_floor), _options(**kwargs))
    return _json.loads(text)


def make_map(scene, out, *, resolution=0.05, floor="auto", laser_height=None, **kwargs):
    """Writes the ROS map_server map ``OUT.yaml`` + ``OUT.pgm`` of a floor and its picture
    ``OUT.png``, as ``xhab map`` does. Returns ``{"yaml", "png", "width", "height", "resolution"}``."""
    yaml, png, w, h, r = _xhab.make_map(str(scene), _os.fspath(out), float(resolution), str(floor),
                                        None if laser_height is None else float(laser_height), _options(**kwargs))
    return {"yaml": yaml, "png": png, "width": w, "height": h, "resolution": r}


def experiment(spec, out=None, *, shard=None, report=True):
    """Runs a study as ``xhab experiment`` does and returns its results (the dict
    ``results.json`` holds: ``runs`` with each run's ``aggregate``, ``episodes`` one row per
    run x episode, ``skipped``), or ``None`` for a shard.

    ``spec``: a YAML file's path, or the spec itself as a dict (the YAML's fields: ``name``,
    ``scenes``, ``agents``, ``configurations``, ``seeds``, ...). ``out``: the study's folder
    (default ``results/NAME``); finished runs there are skipped, so a rerun resumes.
    ``shard``: ``"K/N"`` to run one slice (``merge`` combines them). ``report``: write
    ``OUT/report/index.html``. Ctrl-C stops after the episode in progress; what finished stays.
    """
    if isinstance(spec, dict):
        text, source = _json.dumps(spec), "<dict>"
    else:
        source = _os.fspath(spec)
        with open(source, encoding="utf-8") as f:
            text = f.read()
    out = None if out is None else _os.fspath(out)
    results, _folder = _xhab.experiment(text, source, out, None if shard is None else str(shard), bool(report))
    return None if results is None else _json.loads(results)


def merge(dirs, out=None, *, report=True):
    """Merges the shards of a study (``experiment(..., shard="K/N")`` folders) into ``out``
    (default: the first folder) as ``xhab merge`` does; returns the results dict."""
    if isinstance(dirs, (str, _os.PathLike)):
        dirs = [dirs]
    out = None if out is None else _os.fspath(out)
    return _json.loads(_xhab.merge([_os.fspath(d) for d in dirs], out, bool(report)))
