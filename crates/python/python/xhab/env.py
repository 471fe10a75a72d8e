"""Gymnasium environments over xhab's Rust core (``xhab._xhab.Core`` and ``VecCore``).

The Rust side does the work (episodes, stepping, physics, rendering, reward, metrics); this
module only shapes its output as Gymnasium expects: observation and action spaces, numpy
arrays over the buffers Rust filled (images are copied once, from the renderer into the
buffer the array views), and the vector API's info dicts.
"""

import os

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from . import _xhab

#: Habitat's discrete actions.
STOP, MOVE_FORWARD, TURN_LEFT, TURN_RIGHT = 0, 1, 2, 3

_SEED_MASK = (1 << 64) - 1

#: The dtypes of the info columns the Rust core sends (``episode_id`` comes as a list of str).
_INFO_DTYPES = {"distance_to_goal": np.float64, "success": np.float64, "spl": np.float64, "soft_spl": np.float64,
                "collisions": np.int64, "collided": np.bool_, "steps": np.int64, "path_length": np.float64,
                "called_stop": np.bool_}


def options(**kwargs):
    """The Rust core's option dict: keywords whose value is not None (sensors as a list)."""
    out = {}
    for k, v in kwargs.items():
        if v is None:
            continue
        if k == "sensors":
            if isinstance(v, str):
                v = [s for s in v.split(",") if s]
            v = [str(s) for s in v]
        out[k] = v
    return out


def _seed(seed):
    return None if seed is None else int(seed) & _SEED_MASK


def observation(raw, shape, sensors):
    """One observation as numpy arrays over the Rust core's buffers (no copy)."""
    o = {}
    if shape is not None:
        h, w, _ = shape
        if "depth" in sensors:
            o["depth"] = np.frombuffer(raw["depth"], np.float32).reshape(h, w, 1)
        if "rgb" in sensors:
            o["rgb"] = np.frombuffer(raw["rgb"], np.uint8).reshape(h, w, 3)
    o["pointgoal_with_gps_compass"] = np.array(raw["pointgoal_with_gps_compass"], np.float32)
    o["gps"] = np.array(raw["gps"], np.float32)
    o["compass"] = np.array([raw["compass"]], np.float32)
    return o


class AgentAdapter:
    """Gives a user's agent (a callable, or an object with ``act`` and optionally ``reset``)
    the observations ``PointNavEnv`` gives; ``xhab.evaluate`` runs it (and deep-copies it per
    episode when episodes run in parallel)."""

    def __init__(self, agent, shape, sensors, privileged):
        if not (callable(getattr(agent, "act", None)) or callable(agent)):
            raise TypeError("agent: expected a callable act(obs) -> action, or an object with act(obs)")
        self.agent, self.shape, self.sensors, self.privileged = agent, shape, set(sensors), privileged

    def act(self, raw, view=None):
        act = getattr(self.agent, "act", None) or self.agent
        obs = observation(raw, self.shape, self.sensors)
        return act(obs, view) if self.privileged else act(obs)

    def reset(self):
        reset = getattr(self.agent, "reset", None)
        if callable(reset):
            reset()


def _observation_space(sensors, shape, max_depth, noisy):
    d = {}
    if shape is not None:
        h, w, _ = shape
        if "depth" in sensors:
            high = np.inf if noisy else max_depth
            d["depth"] = spaces.Box(0.0, high, (h, w, 1), np.float32)
        if "rgb" in sensors:
            d["rgb"] = spaces.Box(0, 255, (h, w, 3), np.uint8)
    d["pointgoal_with_gps_compass"] = spaces.Box(-np.inf, np.inf, (2,), np.float32)
    d["gps"] = spaces.Box(-np.inf, np.inf, (2,), np.float32)
    d["compass"] = spaces.Box(-np.pi, np.pi, (1,), np.float32)
    return spaces.Dict(d)


class PointNavEnv(gym.Env):
    """Habitat's PointNav task as a ``gymnasium.Env``.

    Args:
        scene: a ``.glb``/``.gltf``/``.obj``/``.ply`` file or ``procedural[:SEED]``.
        episodes: a Habitat PointNav episodes file (``.json.gz``); episodes are played in
            order, cycling. Without one, each reset generates an episode with Habitat's rules.
        physics: run each action as Algorithm 1 under rapier3d (velocities held for
            ``control_period`` s) with the ``robot`` profile (habitat, locobot,
            turtlebot3_burger, turtlebot3_waffle or a YAML file).
        sensors: camera images in the observation: ``("depth",)``, ``("depth", "rgb")`` or ``()``.
        resolution, hfov: the square image's size (px) and horizontal field of view (deg).
        seed: seeds generated episodes and the depth and odometry noise.
        floor: the floor generated episodes are on: ``"auto"`` (lowest) or a height (m).
        **kwargs: ``renderer`` (auto, raster, raycast, wgpu), ``camera_height``,
            ``depth_noise``, ``edge_dropout``, ``max_steps`` (500), ``success_distance``
            (0.2 m), ``forward_step_size`` (0.25 m), ``turn_angle`` (10 deg),
            ``control_period`` (1 s), ``steps_per_sec`` (60), ``agent_radius``,
            ``agent_height``, ``cell_size``, ``up_axis``, ``keep_ceilings``.

    Observations (habitat-lab's names): ``depth`` float32 HxWx1 (m, 0 = no return), ``rgb``
    uint8 HxWx3, ``pointgoal_with_gps_compass`` float32[2] (distance m, bearing rad CCW),
    ``gps`` float32[2] (forward, right of the start, m), ``compass`` float32[1] (rad CCW from
    the start heading). Reward: decrease of the geodesic distance to the goal - 0.01, +2.5 on
    success. ``terminated``: the agent called stop; ``truncated``: the step limit. ``info``:
    ``distance_to_goal``, ``success``, ``spl``, ``soft_spl``, ``collisions``, ``collided``,
    ``steps``, ``path_length``, ``called_stop``, ``episode_id``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 10}

    def __init__(self, scene, episodes=None, *, physics=False, robot="habitat", sensors=("depth",), resolution=256,
                 hfov=90, seed=0, floor="auto", render_mode=None, **kwargs):
        super().__init__()
        sensors = options(sensors=sensors)["sensors"]
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode: {render_mode!r} is not supported (None or 'rgb_array')")
        if render_mode == "rgb_array" and not sensors:
            raise ValueError("render_mode='rgb_array' shows the camera: give sensors=('depth',) or ('depth', 'rgb')")
        opts = options(physics=physics, robot=robot, sensors=sensors, resolution=resolution, hfov=hfov, **kwargs)
        self._core = _xhab.Core(str(scene), None if episodes is None else os.fspath(episodes), str(floor),
                                _seed(seed), opts)
        self._sensors = set(sensors)
        self._shape = self._core.image_shape
        self.observation_space = _observation_space(self._sensors, self._shape, self._core.max_depth, self._core.noisy_depth)
        self.action_space = spaces.Discrete(4)
        self.render_mode = render_mode
        self._last = None

    def _obs(self, raw):
        self._last = observation(raw, self._shape, self._sensors)
        return self._last

    def render(self):
        """With ``render_mode="rgb_array"``: the camera's last image as uint8 HxWx3 (the RGB
        image, or depth as grey, near = bright, no return = black); otherwise None."""
        if self.render_mode != "rgb_array" or self._last is None:
            return None
        if "rgb" in self._last:
            return self._last["rgb"].copy()
        d = self._last["depth"][..., 0]
        top = float(self._core.max_depth or 10.0)
        g = np.where(d > 0, 255.0 * (1.0 - np.clip(d / top, 0.0, 1.0)), 0.0).astype(np.uint8)
        return np.repeat(g[..., None], 3, axis=2)

    def reset(self, *, seed=None, options=None):
        """Starts the next episode, or ``options["episode_id"]``; ``seed`` re-seeds the
        environment and starts its episode sequence again."""
        super().reset(seed=seed)
        episode_id = (options or {}).get("episode_id")
        raw, info = self._core.reset(_seed(seed), None if episode_id is None else str(episode_id))
        return self._obs(raw), info

    def step(self, action):
        raw, reward, terminated, truncated, info = self._core.step(action)
        return self._obs(raw), reward, terminated, truncated, info

    def step_twist(self, linear, angular, duration):
        """Holds ``linear`` (m/s) and ``angular`` (rad/s, CCW) velocities for ``duration`` s
        under physics (``physics=True``); stop with ``step(0)``. Returns what ``step`` does."""
        raw, reward, terminated, truncated, info = self._core.step_twist(float(linear), float(angular), float(duration))
        return self._obs(raw), reward, terminated, truncated, info

    def view(self):
        """What an oracle sees of the running episode (``EpisodeView``): ground-truth pose
        and geodesic distances; ``xhab.ShortestPathFollower().act(env.view())`` is the
        shortest-path action."""
        return self._core.view()

    def geodesic_distance(self, a, b):
        """Geodesic distance (m) between Habitat-frame points ``[x, y, z]`` in this scene."""
        return self._core.geodesic_distance([float(v) for v in a], [float(v) for v in b])

    @property
    def episode_ids(self):
        """The episodes file's ids in order (None when episodes are generated)."""
        return self._core.episode_ids

    @property
    def renderer(self):
        """The camera's renderer and why it was chosen (None without sensors)."""
        return self._core.renderer

    def close(self):
        self._core = None


class VectorPointNavEnv(gym.vector.VectorEnv):
    """``n`` PointNav environments stepped together in Rust, in parallel on ``threads``
    threads with the GIL released. Observations are stacked numpy arrays; autoreset is
    Gymnasium's next-step mode (the step after an episode ends resets that environment and
    ignores its action). Environment ``i`` plays episodes ``i``, ``i + n``, ... of the file (or
    the generated episodes with those numbers), with noise seeded per episode, so each
    episode's result depends neither on ``n`` nor on ``threads``. Other arguments are
    ``PointNavEnv``'s."""

    metadata = {"render_modes": [], "autoreset_mode": gym.vector.AutoresetMode.NEXT_STEP}

    def __init__(self, n, scene, episodes=None, *, threads=None, physics=False, robot="habitat", sensors=("depth",),
                 resolution=256, hfov=90, seed=0, floor="auto", **kwargs):
        if int(n) < 1:
            raise ValueError(f"n: at least one environment is needed, got {n}")
        sensors = options(sensors=sensors)["sensors"]
        opts = options(physics=physics, robot=robot, sensors=sensors, resolution=resolution, hfov=hfov, **kwargs)
        threads = min(int(n), os.cpu_count() or 1) if threads is None else int(threads)
        self._core = _xhab.VecCore(int(n), str(scene), None if episodes is None else os.fspath(episodes), str(floor),
                                   _seed(seed), threads, opts)
        self.num_envs = int(n)
        self._sensors = set(sensors)
        self._shape = self._core.image_shape
        self.single_observation_space = _observation_space(self._sensors, self._shape, self._core.max_depth,
                                                           self._core.noisy_depth)
        self.single_action_space = spaces.Discrete(4)
        self.observation_space = gym.vector.utils.batch_space(self.single_observation_space, self.num_envs)
        self.action_space = gym.vector.utils.batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None

    def _obs(self, raw):
        n = self.num_envs
        o = {}
        if self._shape is not None:
            h, w, _ = self._shape
            if "depth" in self._sensors:
                o["depth"] = np.frombuffer(raw["depth"], np.float32).reshape(n, h, w, 1)
            if "rgb" in self._sensors:
                o["rgb"] = np.frombuffer(raw["rgb"], np.uint8).reshape(n, h, w, 3)
        o["pointgoal_with_gps_compass"] = np.frombuffer(raw["pointgoal_with_gps_compass"], np.float32).reshape(n, 2)
        o["gps"] = np.frombuffer(raw["gps"], np.float32).reshape(n, 2)
        o["compass"] = np.frombuffer(raw["compass"], np.float32).reshape(n, 1)
        return o

    def _batch(self, b):
        """Observations, rewards, flags and Gymnasium's vector info layout (an array per key
        and a ``_key`` mask) from the Rust core's columns."""
        n = self.num_envs
        infos = {}
        for key, col in b["info"].items():
            infos[key] = np.array(col, dtype=object) if key == "episode_id" else np.frombuffer(col, _INFO_DTYPES[key])
            infos["_" + key] = np.ones(n, dtype=bool)
        return (self._obs(b["obs"]), np.frombuffer(b["reward"], np.float64), np.frombuffer(b["terminated"], np.bool_),
                np.frombuffer(b["truncated"], np.bool_), infos)

    def reset(self, *, seed=None, options=None):
        """Resets every environment; ``seed`` (an int) re-seeds them all."""
        if options:
            raise ValueError("options: VectorPointNavEnv.reset takes none (episodes follow the file's order)")
        if isinstance(seed, (list, tuple)):
            raise ValueError("seed: one int for all environments (each plays its own episodes)")
        obs, _, _, _, infos = self._batch(self._core.reset(_seed(seed)))
        return obs, infos

    def step(self, actions):
        return self._batch(self._core.step(np.asarray(actions).reshape(-1).tolist()))

    def step_twist(self, twists, duration):
        """Holds each environment's ``(linear m/s, angular rad/s)`` velocities (an ``(n, 2)``
        array) for ``duration`` s under physics (``physics=True``), with ``step``'s autoreset."""
        tw = np.asarray(twists, dtype=np.float64)
        if tw.size != 2 * self.num_envs:
            raise ValueError(f"twists: expected {self.num_envs} (linear, angular) pairs, got an array of shape {tw.shape}")
        tw = tw.reshape(self.num_envs, 2)
        return self._batch(self._core.step_twist([(float(v), float(w)) for v, w in tw], float(duration)))

    def view(self, i):
        """What an oracle sees in environment ``i`` (see ``PointNavEnv.view``)."""
        return self._core.view(int(i))

    def close_extras(self, **kwargs):
        self._core = None
