//! `xhab._xhab`, the native half of the `xhab` Python package: conversions between Python
//! and `xhab_bridge`'s library API, and nothing else. Environments, episodes, rewards, runs
//! and reports are the bridge's (`setup`, `gym`, `runner`, `report`); the Python half
//! (`python/xhab/`) wraps these classes as Gymnasium environments.
//!
//! Errors become Python exceptions with the CLI's messages (the whole chain of causes, as
//! the CLI prints it): `FileNotFoundError` when a file is missing, `ValueError` for bad input,
//! `RuntimeError` for calls out of order. Long runs release the GIL and check for Ctrl-C.

mod study;

use pyo3::exceptions::{PyFileNotFoundError, PyKeyboardInterrupt, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyByteArray, PyDict};
use std::error::Error;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use xhab_bridge::agents::{AgentKind, DiscreteAgent};
use xhab_bridge::benchmark::{run_bench_until, BenchOptions, ScanKind};
use xhab_bridge::nav_agent::Localization;
use xhab_bridge::ros::external::MapOdom;
use xhab_bridge::ros::move_base_client::GoalInterface;
use xhab_bridge::gym::{EnvSnapshot, EpisodeSource, GymError, GymInfo, GymObservation, GymStep, PointNav, VecPointNav};
use xhab_bridge::report::BenchReport;
use xhab_bridge::runner::{run_dataset_with, Outcome};
use xhab_bridge::setup::{self, CameraOptions, EnvOptions, EnvSetup, PhysicsOptions, SceneOptions};
use xhab_sim::action::Action;
use xhab_sim::env::{EnvView, Observation};
use xhab_sim::episode::Dataset;
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::scene::UpAxis;
use xhab_sim::sensors::{CameraFrame, RendererKind};
use xhab_types::Point3;

/// The Python exception for a library error: the message is the chain of causes joined by
/// ": " (as the CLI prints it); a missing file anywhere in the chain is `FileNotFoundError`.
fn py_err(e: &(dyn Error + 'static)) -> PyErr {
    let mut msg = e.to_string();
    let mut not_found = false;
    let mut cur = Some(e);
    while let Some(c) = cur {
        if let Some(io) = c.downcast_ref::<std::io::Error>() {
            not_found |= io.kind() == std::io::ErrorKind::NotFound;
        }
        if !std::ptr::eq(c, e) {
            msg.push_str(": ");
            msg.push_str(&c.to_string());
        }
        cur = c.source();
    }
    if not_found {
        PyFileNotFoundError::new_err(msg)
    } else {
        PyValueError::new_err(msg)
    }
}

fn gym_err(e: GymError) -> PyErr {
    match e {
        GymError::NotReset | GymError::EpisodeOver => PyRuntimeError::new_err(e.to_string()),
        e => py_err(&e),
    }
}

/// Habitat's action from a Python value (an int, or anything with `__index__`).
fn action(v: &Bound<'_, PyAny>) -> PyResult<Action> {
    let bad = || PyValueError::new_err(format!("bad action {v}: actions are 0 stop, 1 move_forward, 2 turn_left, 3 turn_right"));
    let i: i64 = v.extract().or_else(|_| v.call_method0("__index__").and_then(|x| x.extract())).map_err(|_| bad())?;
    Action::from_index(i).ok_or_else(bad)
}

/// Reads an option from `o` (absent or None: the default).
fn opt<'py, T: pyo3::conversion::FromPyObjectOwned<'py>>(o: &Bound<'py, PyDict>, key: &str) -> PyResult<Option<T>> {
    match o.get_item(key)? {
        Some(v) if !v.is_none() => v.extract::<T>().map(Some).map_err(|e| {
            let e: PyErr = e.into();
            PyTypeError::new_err(format!("{key}: {e}"))
        }),
        _ => Ok(None),
    }
}

const OPTION_KEYS: &[&str] = &[
    "physics", "robot", "control_period", "steps_per_sec", "sensors", "resolution", "hfov", "renderer", "camera_height", "depth_noise", "edge_dropout",
    "success_distance", "max_steps", "forward_step_size", "turn_angle", "agent_radius", "agent_height", "cell_size", "up_axis", "keep_ceilings",
    "storeys",
];

/// The environment's options from Python keywords (unknown keys are a `TypeError`).
fn env_options(scene: &str, o: &Bound<'_, PyDict>) -> PyResult<EnvOptions> {
    for k in o.keys() {
        let k: String = k.extract()?;
        if !OPTION_KEYS.contains(&k.as_str()) {
            return Err(PyTypeError::new_err(format!("unknown option '{k}' (options: {})", OPTION_KEYS.join(", "))));
        }
    }
    let mut e = EnvOptions::new(scene);
    let d = SceneOptions::default();
    e.scene_options = SceneOptions {
        up_axis: match opt::<String>(o, "up_axis")?.as_deref() {
            None | Some("y") => UpAxis::Y,
            Some("z") => UpAxis::Z,
            Some(x) => return Err(PyValueError::new_err(format!("up_axis: '{x}' is not 'y' or 'z'"))),
        },
        keep_ceilings: opt(o, "keep_ceilings")?.unwrap_or(d.keep_ceilings),
        agent_radius: opt(o, "agent_radius")?,
        agent_height: opt(o, "agent_height")?.unwrap_or(d.agent_height),
        cell_size: opt(o, "cell_size")?.unwrap_or(d.cell_size),
        storeys: opt(o, "storeys")?.unwrap_or(d.storeys),
        textures: d.textures,
    };
    if opt(o, "physics")?.unwrap_or(false) {
        let p = PhysicsOptions::default();
        e.physics = Some(PhysicsOptions {
            robot: opt(o, "robot")?.unwrap_or(p.robot),
            control_period: opt(o, "control_period")?.unwrap_or(p.control_period),
            steps_per_sec: opt(o, "steps_per_sec")?.unwrap_or(p.steps_per_sec),
        });
    }
    e.sensors = opt(o, "sensors")?.unwrap_or_default();
    let c = CameraOptions::default();
    e.camera = CameraOptions {
        renderer: match opt::<String>(o, "renderer")?.as_deref() {
            None | Some("auto") => None,
            Some("raster") => Some(RendererKind::Raster),
            Some("raycast") => Some(RendererKind::Raycast),
            Some("wgpu") => Some(RendererKind::Wgpu),
            Some(x) => return Err(PyValueError::new_err(format!("renderer: unknown renderer '{x}' (auto, raster, raycast, wgpu)"))),
        },
        resolution: opt(o, "resolution")?.unwrap_or(c.resolution),
        hfov: opt(o, "hfov")?.unwrap_or(c.hfov),
        camera_height: opt(o, "camera_height")?,
    };
    e.depth_noise = opt(o, "depth_noise")?.unwrap_or(0.0);
    e.edge_dropout = opt(o, "edge_dropout")?.unwrap_or(0.0);
    let t = &mut e.task;
    t.success_distance = opt(o, "success_distance")?.unwrap_or(t.success_distance);
    t.max_episode_steps = opt(o, "max_steps")?.unwrap_or(t.max_episode_steps);
    t.forward_step_size = opt(o, "forward_step_size")?.unwrap_or(t.forward_step_size);
    t.turn_angle = opt(o, "turn_angle")?.unwrap_or(t.turn_angle);
    Ok(e)
}

/// Builds the setup (scene, physics, camera) without the GIL.
fn build_setup(py: Python<'_>, scene: &str, o: &Bound<'_, PyDict>) -> PyResult<EnvSetup> {
    let opts = env_options(scene, o)?;
    py.detach(move || EnvSetup::build(&opts)).map_err(|e| py_err(&e))
}

/// The episode source: a file, or generated on `floor`.
fn episode_source(py: Python<'_>, episodes: Option<PathBuf>, floor: String) -> PyResult<EpisodeSource> {
    Ok(match episodes {
        Some(p) => {
            let dataset = py.detach(|| setup::read_episodes(&p)).map_err(|e| py_err(&e))?;
            EpisodeSource::Dataset { dataset: Arc::new(dataset), file: p.display().to_string() }
        }
        None => EpisodeSource::Generated { floor },
    })
}

/// Native-endian bytes of `f32` values, written into `out`.
fn put_f32(out: &mut [u8], v: &[f32]) {
    for (o, x) in out.chunks_exact_mut(4).zip(v) {
        o.copy_from_slice(&x.to_ne_bytes());
    }
}

/// Image sizes of a setup: (height, width, rgb).
fn image_shape(s: &EnvSetup) -> Option<(usize, usize, bool)> {
    s.sensors.as_ref().map(|r| (r.params.height, r.params.width, r.rgb))
}

/// The observation of one environment as a dict: images as `bytearray`s (one copy of the
/// rendered frame), the rest as tuples; the Python half makes numpy arrays of them.
fn obs_dict<'py>(py: Python<'py>, o: &GymObservation, frame: Option<&CameraFrame>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    if let Some(f) = frame {
        d.set_item("depth", PyByteArray::new_with(py, f.depth.data.len() * 4, |b| {
            put_f32(b, &f.depth.data);
            Ok(())
        })?)?;
        if let Some(rgb) = &f.rgb {
            d.set_item("rgb", PyByteArray::new(py, rgb))?;
        }
    }
    d.set_item("pointgoal_with_gps_compass", (o.pointgoal[0], o.pointgoal[1]))?;
    d.set_item("gps", (o.gps[0], o.gps[1]))?;
    d.set_item("compass", o.compass)?;
    Ok(d)
}

fn info_dict<'py>(py: Python<'py>, i: &GymInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("episode_id", &i.episode_id)?;
    d.set_item("distance_to_goal", i.distance_to_goal)?;
    d.set_item("success", i.success)?;
    d.set_item("spl", i.spl)?;
    d.set_item("soft_spl", i.soft_spl)?;
    d.set_item("collisions", i.collisions)?;
    d.set_item("collided", i.collided)?;
    d.set_item("steps", i.steps)?;
    d.set_item("path_length", i.path_length)?;
    d.set_item("called_stop", i.called_stop)?;
    Ok(d)
}

/// A Habitat-frame point `[x, y, z]` (y up) in the world frame.
fn habitat_point(p: [f64; 3], what: &str) -> PyResult<Point3> {
    if p.iter().any(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!("bad {what} {p:?}: expected three finite numbers X,Y,Z")));
    }
    Ok(Point3::from_habitat(p))
}

/// What an oracle may see of a running episode: the pose, the task, the geodesic field.
/// A snapshot: it does not follow the episode after the step it was taken at.
#[pyclass(module = "xhab._xhab", frozen)]
struct EpisodeView(EnvSnapshot);

#[pymethods]
impl EpisodeView {
    /// The agent's ground-truth pose `(x, y, yaw)` in the world frame (m, m, rad; z up).
    #[getter]
    fn pose(&self) -> (f64, f64, f64) {
        let p = self.0.pose();
        (p.x, p.y, p.yaw)
    }
    /// Geodesic distance from the agent to the nearest goal (m).
    fn distance_to_goal(&self) -> f64 {
        self.0.distance_to_goal()
    }
    /// Geodesic distance to the nearest goal from the world-frame point `(x, y)` (m; inf
    /// where not navigable).
    fn distance_from(&self, x: f64, y: f64) -> f64 {
        self.0.field().distance(self.0.grid(), xhab_types::Point2::new(x, y))
    }
}

/// Habitat's greedy shortest-path follower (the CLI's `--agent oracle`): `act(view)` gives
/// the action that follows the geodesic path; `reset()` before each episode.
#[pyclass(module = "xhab._xhab", name = "ShortestPathFollower")]
#[derive(Default)]
struct ShortestPathFollowerPy(ShortestPathFollower);

#[pymethods]
impl ShortestPathFollowerPy {
    #[new]
    fn new() -> Self {
        Self::default()
    }
    /// The next action (Habitat's numbering) for the episode seen by `view`.
    fn act(&mut self, view: &EpisodeView) -> i64 {
        self.0.act(&view.0) as i64
    }
    /// Forgets the episode.
    fn reset(&mut self) {
        self.0.reset();
    }
}

/// One PointNav environment (wrapped by `xhab.PointNavEnv`).
#[pyclass(module = "xhab._xhab")]
struct Core {
    env: PointNav,
    episode_ids: Option<Vec<String>>,
}

#[pymethods]
impl Core {
    #[new]
    #[pyo3(signature = (scene, episodes, floor, seed, options))]
    fn new(py: Python<'_>, scene: &str, episodes: Option<PathBuf>, floor: String, seed: u64, options: &Bound<'_, PyDict>) -> PyResult<Self> {
        let s = build_setup(py, scene, options)?;
        let source = episode_source(py, episodes, floor)?;
        let episode_ids = match &source {
            EpisodeSource::Dataset { dataset, .. } => Some(dataset.episodes.iter().map(|e| e.episode_id.clone()).collect()),
            EpisodeSource::Generated { .. } => None,
        };
        Ok(Core { env: PointNav::new(Arc::new(s), Arc::new(source), 0, 1, seed), episode_ids })
    }

    /// `(height, width, rgb)` of the camera, or None without sensors.
    #[getter]
    fn image_shape(&self) -> Option<(usize, usize, bool)> {
        image_shape(self.env.setup())
    }
    /// The camera's range (m).
    #[getter]
    fn max_depth(&self) -> Option<f64> {
        self.env.setup().sensors.as_ref().map(|r| r.params.max_depth)
    }
    /// Whether depth noise is on.
    #[getter]
    fn noisy_depth(&self) -> bool {
        self.env.setup().sensors.as_ref().is_some_and(|r| r.noise.sigma_at_1m > 0.0)
    }
    /// Which renderer and why.
    #[getter]
    fn renderer(&self) -> Option<String> {
        self.env.setup().renderer_note.clone()
    }
    /// Whether the environment runs under physics.
    #[getter]
    fn physics(&self) -> bool {
        self.env.setup().physics.is_some()
    }
    /// The episodes file's ids, in order (None when episodes are generated).
    #[getter]
    fn episode_ids(&self) -> Option<Vec<String>> {
        self.episode_ids.clone()
    }

    #[pyo3(signature = (seed=None, episode_id=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>, episode_id: Option<String>) -> PyResult<(Bound<'py, PyDict>, Bound<'py, PyDict>)> {
        let env = &mut self.env;
        let r = py.detach(|| env.reset(seed, episode_id.as_deref())).map_err(gym_err)?;
        Ok((obs_dict(py, &r.obs, r.obs.frame.as_ref())?, info_dict(py, &r.info)?))
    }

    fn step<'py>(&mut self, py: Python<'py>, action: &Bound<'py, PyAny>) -> PyResult<StepTuple<'py>> {
        let a = self::action(action)?;
        let env = &mut self.env;
        let r = py.detach(|| env.step(a)).map_err(gym_err)?;
        step_tuple(py, &r)
    }

    fn step_twist<'py>(&mut self, py: Python<'py>, linear: f64, angular: f64, duration: f64) -> PyResult<StepTuple<'py>> {
        let env = &mut self.env;
        let r = py.detach(|| env.step_twist(linear, angular, duration)).map_err(gym_err)?;
        step_tuple(py, &r)
    }

    /// What an oracle sees now (None before the first reset).
    fn view(&self) -> Option<EpisodeView> {
        self.env.snapshot().map(EpisodeView)
    }

    /// Geodesic distance between two Habitat-frame points `[x, y, z]` (m; inf when not
    /// connected or not navigable).
    fn geodesic_distance(&self, py: Python<'_>, a: [f64; 3], b: [f64; 3]) -> PyResult<f64> {
        let (a, b) = (habitat_point(a, "a")?, habitat_point(b, "b")?);
        let world = &self.env.setup().world;
        py.detach(|| setup::geodesic(world, a, b)).map(|q| q.distance).map_err(|e| py_err(&e))
    }
}

/// What `step` returns: observation, reward, terminated, truncated, info.
type StepTuple<'py> = (Bound<'py, PyDict>, f64, bool, bool, Bound<'py, PyDict>);

fn step_tuple<'py>(py: Python<'py>, r: &GymStep) -> PyResult<StepTuple<'py>> {
    Ok((obs_dict(py, &r.obs, r.obs.frame.as_ref())?, r.reward, r.terminated, r.truncated, info_dict(py, &r.info)?))
}

/// `n` environments stepped in parallel (wrapped by `xhab.VectorPointNavEnv`).
#[pyclass(module = "xhab._xhab")]
struct VecCore {
    envs: VecPointNav,
    shape: Option<(usize, usize, bool)>,
}

/// Stacked observations: one `bytearray` per key, environment after environment.
fn stacked<'py>(py: Python<'py>, steps: &[GymStep], shape: Option<(usize, usize, bool)>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = steps.len();
    if let Some((h, w, rgb)) = shape {
        let px = h * w;
        d.set_item("depth", PyByteArray::new_with(py, n * px * 4, |b| {
            for (chunk, s) in b.chunks_exact_mut(px * 4).zip(steps) {
                if let Some(f) = &s.obs.frame {
                    put_f32(chunk, &f.depth.data);
                }
            }
            Ok(())
        })?)?;
        if rgb {
            d.set_item("rgb", PyByteArray::new_with(py, n * px * 3, |b| {
                for (chunk, s) in b.chunks_exact_mut(px * 3).zip(steps) {
                    if let Some(c) = s.obs.frame.as_ref().and_then(|f| f.rgb.as_ref()) {
                        chunk.copy_from_slice(c);
                    }
                }
                Ok(())
            })?)?;
        }
    }
    let small = |f: &dyn Fn(&GymObservation) -> Vec<f32>, k: usize| {
        PyByteArray::new_with(py, n * k * 4, |b| {
            for (chunk, s) in b.chunks_exact_mut(k * 4).zip(steps) {
                put_f32(chunk, &f(&s.obs));
            }
            Ok(())
        })
    };
    d.set_item("pointgoal_with_gps_compass", small(&|o| o.pointgoal.to_vec(), 2)?)?;
    d.set_item("gps", small(&|o| o.gps.to_vec(), 2)?)?;
    d.set_item("compass", small(&|o| vec![o.compass], 1)?)?;
    Ok(d)
}

/// A plain value numpy reads with `np.frombuffer` (native byte order).
trait Column: Copy {
    /// Its size in bytes.
    const SIZE: usize;
    /// Writes its bytes into `out` (`SIZE` long).
    fn put(self, out: &mut [u8]);
}

impl Column for f64 {
    const SIZE: usize = 8;
    fn put(self, out: &mut [u8]) {
        out.copy_from_slice(&self.to_ne_bytes());
    }
}

impl Column for i64 {
    const SIZE: usize = 8;
    fn put(self, out: &mut [u8]) {
        out.copy_from_slice(&self.to_ne_bytes());
    }
}

impl Column for u8 {
    const SIZE: usize = 1;
    fn put(self, out: &mut [u8]) {
        out[0] = self;
    }
}

/// One value per step as a `bytearray` column.
fn raw<'py, T: Column>(py: Python<'py>, steps: &[GymStep], f: impl Fn(&GymStep) -> T) -> PyResult<Bound<'py, PyByteArray>> {
    PyByteArray::new_with(py, steps.len() * T::SIZE, |b| {
        for (chunk, s) in b.chunks_exact_mut(T::SIZE).zip(steps) {
            f(s).put(chunk);
        }
        Ok(())
    })
}

/// A batch of steps, column by column: `obs` (see [`stacked`]), `reward` (float64),
/// `terminated` and `truncated` (uint8), and `info`, one column per key (float64, int64,
/// uint8, or a list of str for `episode_id`), so the Python half makes each array with one
/// `np.frombuffer`.
fn batch<'py>(py: Python<'py>, r: &[GymStep], shape: Option<(usize, usize, bool)>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("obs", stacked(py, r, shape)?)?;
    d.set_item("reward", raw(py, r, |s| s.reward)?)?;
    d.set_item("terminated", raw(py, r, |s| s.terminated as u8)?)?;
    d.set_item("truncated", raw(py, r, |s| s.truncated as u8)?)?;
    let i = PyDict::new(py);
    i.set_item("episode_id", r.iter().map(|s| s.info.episode_id.as_str()).collect::<Vec<_>>())?;
    i.set_item("distance_to_goal", raw(py, r, |s| s.info.distance_to_goal)?)?;
    i.set_item("success", raw(py, r, |s| s.info.success)?)?;
    i.set_item("spl", raw(py, r, |s| s.info.spl)?)?;
    i.set_item("soft_spl", raw(py, r, |s| s.info.soft_spl)?)?;
    i.set_item("collisions", raw(py, r, |s| s.info.collisions as i64)?)?;
    i.set_item("collided", raw(py, r, |s| s.info.collided as u8)?)?;
    i.set_item("steps", raw(py, r, |s| s.info.steps as i64)?)?;
    i.set_item("path_length", raw(py, r, |s| s.info.path_length)?)?;
    i.set_item("called_stop", raw(py, r, |s| s.info.called_stop as u8)?)?;
    d.set_item("info", i)?;
    Ok(d)
}

#[pymethods]
impl VecCore {
    #[new]
    #[pyo3(signature = (n, scene, episodes, floor, seed, threads, options))]
    fn new(py: Python<'_>, n: usize, scene: &str, episodes: Option<PathBuf>, floor: String, seed: u64, threads: usize, options: &Bound<'_, PyDict>) -> PyResult<Self> {
        if n == 0 {
            return Err(PyValueError::new_err("n: at least one environment is needed"));
        }
        let s = Arc::new(build_setup(py, scene, options)?);
        let source = Arc::new(episode_source(py, episodes, floor)?);
        let shape = image_shape(&s);
        let envs = py.detach(|| VecPointNav::new(s, source, n, threads, seed));
        Ok(VecCore { envs, shape })
    }

    #[getter]
    fn image_shape(&self) -> Option<(usize, usize, bool)> {
        self.shape
    }
    #[getter]
    fn max_depth(&self) -> Option<f64> {
        self.envs.envs()[0].setup().sensors.as_ref().map(|r| r.params.max_depth)
    }
    #[getter]
    fn noisy_depth(&self) -> bool {
        self.envs.envs()[0].setup().sensors.as_ref().is_some_and(|r| r.noise.sigma_at_1m > 0.0)
    }

    /// Resets every environment; returns the batch (see `batch`).
    #[pyo3(signature = (seed=None))]
    fn reset<'py>(&mut self, py: Python<'py>, seed: Option<u64>) -> PyResult<Bound<'py, PyDict>> {
        let envs = &mut self.envs;
        let r = py.detach(|| envs.reset(seed)).map_err(gym_err)?;
        batch(py, &r, self.shape)
    }

    /// Steps every environment with its action; returns the batch.
    fn step<'py>(&mut self, py: Python<'py>, actions: Vec<Bound<'py, PyAny>>) -> PyResult<Bound<'py, PyDict>> {
        let actions: Vec<Action> = actions.iter().map(action).collect::<PyResult<_>>()?;
        let envs = &mut self.envs;
        let r = py.detach(|| envs.step(&actions)).map_err(gym_err)?;
        batch(py, &r, self.shape)
    }

    /// Holds each environment's `(linear, angular)` twist for `duration` s under physics.
    fn step_twist<'py>(&mut self, py: Python<'py>, twists: Vec<(f64, f64)>, duration: f64) -> PyResult<Bound<'py, PyDict>> {
        let envs = &mut self.envs;
        let r = py.detach(|| envs.step_twist(&twists, duration)).map_err(gym_err)?;
        batch(py, &r, self.shape)
    }

    /// What an oracle sees in environment `i` now.
    fn view(&self, i: usize) -> PyResult<Option<EpisodeView>> {
        let e = self.envs.envs().get(i).ok_or_else(|| PyValueError::new_err(format!("no environment {i}")))?;
        Ok(e.snapshot().map(EpisodeView))
    }
}

/// What an evaluation shares between its agents: the first error, and the cancel flag.
#[derive(Default)]
struct Shared {
    error: Mutex<Option<PyErr>>,
    cancel: AtomicBool,
}

impl Shared {
    /// Keeps the first error and stops the run.
    fn fail(&self, e: PyErr) {
        if let Ok(mut g) = self.error.lock() {
            g.get_or_insert(e);
        }
        self.cancel.store(true, Ordering::Relaxed);
    }
}

/// A Python agent: `act(obs)` (or `act(obs, view)` when privileged) and an optional `reset()`.
struct PyAgent {
    act: Py<PyAny>,
    reset: Option<Py<PyAny>>,
    privileged: bool,
    shared: Arc<Shared>,
}

/// The bound `act` and `reset` of an agent object, or a plain callable as `act`.
fn bind(agent: &Bound<'_, PyAny>) -> PyResult<(Py<PyAny>, Option<Py<PyAny>>)> {
    if let Ok(act) = agent.getattr("act") {
        let reset = agent.getattr("reset").ok().filter(|r| r.is_callable());
        return Ok((act.unbind(), reset.map(Bound::unbind)));
    }
    if agent.is_callable() {
        return Ok((agent.clone().unbind(), None));
    }
    Err(PyTypeError::new_err("agent: expected a callable act(obs) -> action, or an object with act(obs)"))
}

impl DiscreteAgent for PyAgent {
    fn act(&mut self, _env: &dyn EnvView, _frame: Option<&CameraFrame>) -> Action {
        self.shared.fail(PyRuntimeError::new_err("a Python agent needs the runner's observation"));
        Action::Stop
    }

    fn act_observed(&mut self, env: &dyn EnvView, obs: &Observation, frame: Option<&CameraFrame>) -> Action {
        if self.shared.cancel.load(Ordering::Relaxed) {
            return Action::Stop;
        }
        let r = Python::attach(|py| -> PyResult<Action> {
            // Runs the signal handlers when on the main thread (sequential evaluations).
            py.check_signals()?;
            let o = obs_dict(py, &GymObservation::new(obs, None), frame)?;
            let act = self.act.bind(py);
            let a = if self.privileged { act.call1((o, EpisodeView(EnvSnapshot::of(env))))? } else { act.call1((o,))? };
            action(&a)
        });
        r.unwrap_or_else(|e| {
            self.shared.fail(e);
            Action::Stop
        })
    }

    fn reset(&mut self) {
        if let Some(r) = &self.reset {
            if let Err(e) = Python::attach(|py| r.bind(py).call0().map(drop)) {
                self.shared.fail(e);
            }
        }
    }
}

/// Runs `ds` with agents from `make` (one per episode) without the GIL, checking for Ctrl-C,
/// and returns the report's JSON. `inline`: on this thread, for Python agents that run
/// sequentially (they check for Ctrl-C themselves); otherwise in a worker thread.
#[allow(clippy::too_many_arguments)]
fn run_report(py: Python<'_>, s: &EnvSetup, ds: &Dataset, threads: usize, seed: u64, agent_name: &str, episodes_file: &str, shared: &Arc<Shared>, make: &(dyn Fn(usize) -> Box<dyn DiscreteAgent> + Sync), inline: bool) -> PyResult<String> {
    let cfg = s.run_config(AgentKind::Oracle, threads, seed);
    let t0 = Instant::now();
    let (world, cfg_ref, cancel) = (&s.world, &cfg, &shared.cancel);
    let run = move || run_dataset_with(world, ds, cfg_ref, make, cancel, &|| {});
    let result = if inline {
        // On this thread: a Python agent's calls check for Ctrl-C at every step.
        py.detach(move || std::panic::catch_unwind(std::panic::AssertUnwindSafe(run))).ok()
    } else {
        // In a worker thread, while this one checks for Ctrl-C.
        match interruptible(py, cancel, run) {
            Ok(r) => Some(r),
            Err(e) => {
                shared.fail(e);
                None
            }
        }
    };
    let wall = t0.elapsed().as_secs_f64();
    if let Some(e) = shared.error.lock().ok().and_then(|mut g| g.take()) {
        return Err(e);
    }
    let outcomes: Vec<Outcome> = match result {
        Some(Ok(o)) => o,
        Some(Err(_)) => return Err(PyKeyboardInterrupt::new_err("the evaluation was cancelled")),
        None => return Err(PyRuntimeError::new_err("internal error: the run stopped unexpectedly")),
    };
    let report = BenchReport::new(&outcomes, wall, &cfg, agent_name, &s.scene, episodes_file, false);
    report.to_json().map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// Evaluates a Python agent on every episode of a file; returns the report's JSON.
#[pyfunction]
#[pyo3(signature = (agent, scene, episodes, threads, seed, privileged, agent_name, options))]
#[allow(clippy::too_many_arguments)]
fn evaluate(py: Python<'_>, agent: Bound<'_, PyAny>, scene: &str, episodes: PathBuf, threads: usize, seed: u64, privileged: bool, agent_name: &str, options: &Bound<'_, PyDict>) -> PyResult<String> {
    let (act, reset) = bind(&agent)?;
    let s = build_setup(py, scene, options)?;
    let ds = py.detach(|| setup::read_episodes(&episodes)).map_err(|e| py_err(&e))?;
    let shared = Arc::new(Shared::default());
    let agent = agent.unbind();
    let deepcopy = py.import("copy")?.getattr("deepcopy")?.unbind();
    let make = |_: usize| -> Box<dyn DiscreteAgent> {
        let (act, reset) = if threads <= 1 {
            Python::attach(|py| (act.clone_ref(py), reset.as_ref().map(|r| r.clone_ref(py))))
        } else {
            // Episodes run in parallel: each gets its own copy of the agent.
            match Python::attach(|py| deepcopy.bind(py).call1((agent.bind(py),)).and_then(|a| bind(&a))) {
                Ok(b) => b,
                Err(e) => {
                    shared.fail(e);
                    Python::attach(|py| (act.clone_ref(py), None))
                }
            }
        };
        Box::new(PyAgent { act, reset, privileged, shared: shared.clone() })
    };
    run_report(py, &s, &ds, threads, seed, agent_name, &episodes.display().to_string(), &shared, &make, threads <= 1)
}

/// The keys `xhab.bench` takes beyond the environment's (the nav stack and an external stack).
const BENCH_KEYS: &[&str] = &["localization", "map", "nav_params", "scan_source", "ros_master", "launch", "episode_timeout", "map_odom", "goal_interface", "controller_frequency"];

/// The nav and external-stack options of `xhab.bench` (unknown keys are a `TypeError`).
fn bench_extras(o: &mut BenchOptions, d: &Bound<'_, PyDict>) -> PyResult<()> {
    for k in d.keys() {
        let k: String = k.extract()?;
        if !BENCH_KEYS.contains(&k.as_str()) {
            return Err(PyTypeError::new_err(format!("unknown option '{k}' (options: {})", BENCH_KEYS.join(", "))));
        }
    }
    if let Some(l) = opt::<String>(d, "localization")? {
        o.nav.localization = match l.as_str() {
            "ground-truth" | "ground_truth" => Localization::GroundTruth,
            "odom" => Localization::Odom,
            "amcl" => Localization::Amcl,
            _ => return Err(PyValueError::new_err(format!("localization: unknown '{l}' (ground-truth, odom, amcl)"))),
        };
    }
    o.nav.map = opt(d, "map")?;
    for f in opt::<Vec<String>>(d, "nav_params")?.unwrap_or_default() {
        o.nav.params.push(f.parse().map_err(|e: xhab_bridge::benchmark::ParamError| PyValueError::new_err(format!("nav_params: {e}")))?);
    }
    if let Some(src) = d.get_item("scan_source")? {
        o.nav.scans = match src.extract::<Option<String>>()?.as_deref() {
            None | Some("none") => None,
            Some("lidar") => Some(ScanKind::Lidar),
            Some("depth") => Some(ScanKind::Depth),
            Some(x) => return Err(PyValueError::new_err(format!("scan_source: unknown '{x}' (lidar, depth, None)"))),
        };
    }
    let e = &mut o.external;
    e.master = opt(d, "ros_master")?;
    o.ros_master = e.master.clone();
    e.launch = opt(d, "launch")?;
    e.episode_timeout = opt(d, "episode_timeout")?.unwrap_or(e.episode_timeout);
    e.controller_frequency = opt(d, "controller_frequency")?.unwrap_or(e.controller_frequency);
    if let Some(m) = opt::<String>(d, "map_odom")? {
        e.map_odom = match m.as_str() {
            "stack" => MapOdom::Stack,
            "ground-truth" | "ground_truth" => MapOdom::GroundTruth,
            _ => return Err(PyValueError::new_err(format!("map_odom: unknown '{m}' (stack, ground-truth)"))),
        };
    }
    if let Some(g) = opt::<String>(d, "goal_interface")? {
        e.goal_interface = match g.as_str() {
            "action" => GoalInterface::Action,
            "simple" => GoalInterface::Simple,
            _ => return Err(PyValueError::new_err(format!("goal_interface: unknown '{g}' (action, simple)"))),
        };
    }
    Ok(())
}

/// Runs `f` in a worker thread while this one (the main thread, where Python runs signal
/// handlers) waits without the GIL, checking for Ctrl-C every 50 ms; on an exception from a
/// signal handler `cancel` is set, `f` is awaited and the exception returned.
fn interruptible<T: Send>(py: Python<'_>, cancel: &AtomicBool, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    let (tx, mut rx) = std::sync::mpsc::channel();
    let mut interrupted = None;
    let r = std::thread::scope(|scope| {
        scope.spawn(move || {
            let _ = tx.send(std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)));
        });
        loop {
            let (back, r) = py.detach(move || {
                let r = rx.recv_timeout(Duration::from_millis(50));
                (rx, r)
            });
            rx = back;
            match r {
                Ok(r) => break Some(r),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals() {
                        cancel.store(true, Ordering::Relaxed);
                        interrupted.get_or_insert(e);
                    }
                }
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break None,
            }
        }
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    match r {
        Some(Ok(v)) => Ok(v),
        Some(Err(_)) | None => Err(PyRuntimeError::new_err("internal error: the run stopped unexpectedly")),
    }
}

/// Benchmarks a built-in agent (`oracle`, `nav`, or an external ROS stack with `ros`) as
/// `xhab bench` does, through the same library call; returns the report's JSON.
#[pyfunction(name = "bench")]
#[pyo3(signature = (scene, episodes, agent, threads, seed, options, extras))]
#[allow(clippy::too_many_arguments)]
fn bench_builtin(py: Python<'_>, scene: &str, episodes: PathBuf, agent: &str, threads: usize, seed: u64, options: &Bound<'_, PyDict>, extras: &Bound<'_, PyDict>) -> PyResult<String> {
    let mut o = BenchOptions::new(scene, episodes);
    o.agent = match agent {
        "oracle" => AgentKind::Oracle,
        "nav" => AgentKind::Nav,
        "ros" => AgentKind::Ros,
        "ros2" => AgentKind::Ros2,
        _ => return Err(PyValueError::new_err(format!("agent '{agent}': unknown (oracle, nav, ros, ros2)"))),
    };
    o.env = env_options(scene, options)?;
    o.threads = threads.max(1);
    o.seed = seed;
    bench_extras(&mut o, extras)?;
    let cancel = AtomicBool::new(false);
    let run = interruptible(py, &cancel, || run_bench_until(&o, &cancel, &|_, _| {}))?.map_err(|e| py_err(&e))?;
    for w in &run.warnings {
        let msg = std::ffi::CString::new(w.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &py.get_type::<pyo3::exceptions::PyUserWarning>(), &msg, 1)?;
    }
    run.report.to_json().map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// Geodesic distance between Habitat-frame points in a scene (m; inf when not connected).
#[pyfunction]
#[pyo3(signature = (scene, a, b, options))]
fn geodesic_distance(py: Python<'_>, scene: &str, a: [f64; 3], b: [f64; 3], options: &Bound<'_, PyDict>) -> PyResult<f64> {
    let (a, b) = (habitat_point(a, "a")?, habitat_point(b, "b")?);
    let opts = env_options(scene, options)?;
    py.detach(|| -> Result<f64, Box<dyn Error + Send + Sync>> {
        let world = setup::load_world(&opts.scene, &opts.scene_options)?;
        Ok(setup::geodesic(&world, a, b)?.distance)
    })
    .map_err(|e| py_err(&*e))
}

/// Generates episodes with Habitat's rules; writes them to `out` when given; returns the
/// dataset as Habitat's JSON text.
#[pyfunction]
#[pyo3(signature = (scene, count, seed, out, floor, scene_id, cross_floor, options))]
#[allow(clippy::too_many_arguments)]
fn generate_episodes(py: Python<'_>, scene: &str, count: usize, seed: u64, out: Option<PathBuf>, floor: &str, scene_id: Option<String>, cross_floor: bool, options: &Bound<'_, PyDict>) -> PyResult<String> {
    let opts = env_options(scene, options)?;
    py.detach(|| -> Result<String, Box<dyn Error + Send + Sync>> {
        let world = setup::load_world(&opts.scene, &opts.scene_options)?;
        let id = scene_id.as_deref().unwrap_or(scene);
        let ds = if cross_floor { setup::generate_cross_floor(&world, scene, count, seed, id)? } else { setup::generate(&world, scene, floor, count, seed, id)? };
        if let Some(p) = &out {
            ensure_parent(p)?;
            xhab_sim::episode::write_dataset(&ds, p).map_err(|e| format!("writing {}: {e}", p.display()))?;
        }
        Ok(xhab_sim::episode::to_json_string(&ds)?)
    })
    .map_err(|e| py_err(&*e))
}

fn ensure_parent(p: &Path) -> Result<(), String> {
    match p.parent().filter(|d| !d.as_os_str().is_empty()) {
        Some(d) => std::fs::create_dir_all(d).map_err(|e| format!("creating folder {}: {e}", d.display())),
        None => Ok(()),
    }
}

/// Writes the map_server map (`OUT.yaml` + `OUT.pgm`) and the picture `OUT.png` of a floor,
/// as `xhab map` does; returns `(yaml path, png path, width, height, resolution)`.
#[pyfunction]
#[pyo3(signature = (scene, out, resolution, floor, laser_height, options))]
#[allow(clippy::type_complexity)]
fn make_map(py: Python<'_>, scene: &str, out: PathBuf, resolution: f64, floor: &str, laser_height: Option<f64>, options: &Bound<'_, PyDict>) -> PyResult<(String, String, usize, usize, f64)> {
    let mut opts = env_options(scene, options)?;
    opts.scene_options.cell_size = resolution;
    py.detach(|| -> Result<(String, String, usize, usize, f64), Box<dyn Error + Send + Sync>> {
        let world = setup::load_world(&opts.scene, &opts.scene_options)?;
        let i = setup::floor_index(&world, floor)?;
        let grid = world.grid(i)?;
        let map = setup::floor_map(&world, &grid, laser_height)?;
        let (yaml, png) = setup::write_map(&map, &out)?;
        Ok((yaml.display().to_string(), png.display().to_string(), map.width, map.height, map.resolution))
    })
    .map_err(|e| py_err(&*e))
}

/// The native module.
#[pymodule]
fn _xhab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Core>()?;
    m.add_class::<VecCore>()?;
    m.add_class::<EpisodeView>()?;
    m.add_class::<ShortestPathFollowerPy>()?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(bench_builtin, m)?)?;
    m.add_function(wrap_pyfunction!(geodesic_distance, m)?)?;
    m.add_function(wrap_pyfunction!(generate_episodes, m)?)?;
    m.add_function(wrap_pyfunction!(make_map, m)?)?;
    m.add_function(wrap_pyfunction!(study::experiment, m)?)?;
    m.add_function(wrap_pyfunction!(study::merge, m)?)?;
    Ok(())
}
