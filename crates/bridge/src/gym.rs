//! A Gymnasium-style PointNav environment: `reset` and `step` with Habitat's observations,
//! reward and metrics, with or without physics, single ([`PointNav`]) or batched and stepped
//! in parallel ([`VecPointNav`]). The Python package wraps these; nothing here knows Python.
//!
//! Conventions are habitat-lab's: `pointgoal_with_gps_compass` is (distance (m), bearing (rad,
//! CCW, 0 ahead)); `gps` is the position relative to the start in the start's frame as
//! (forward, right) (m); `compass` the heading relative to the start (rad, CCW, in (-pi, pi]).
//! The reward of a step is the decrease of the geodesic distance to the goal (m) minus a
//! slack of 0.01, plus 2.5 on success (Habitat's `NavRLEnv`).
//!
//! Episodes come from a dataset (in file order, cycling) or are generated with Habitat's rules
//! on the fly. Episode number `g` (counted from the last seeding) of environment `first` of
//! `stride` is the dataset's episode `(first + g * stride) % len`, or the generated episode
//! seeded by the seed and `first + g * stride`, so a batch of environments plays the same
//! episodes, with the same noise, whatever its size and thread count.

use crate::agents::AgentKind;
use crate::camera_capture::{capture, RenderStats};
use crate::runner::{make_env, EpisodeEnv, RunConfig};
use crate::setup::{generate, EnvSetup, SetupError};
use rayon::prelude::*;
use std::sync::Arc;
use xhab_sim::action::Action;
pub use xhab_sim::env::EnvSnapshot;
use xhab_sim::env::Observation;
use xhab_sim::episode::{Dataset, Episode};
use xhab_sim::metrics::EpisodeMetrics;
use xhab_sim::sensors::CameraFrame;
use xhab_types::Twist;

/// Reward of every step (Habitat's `slack_reward`).
pub const SLACK_REWARD: f64 = -0.01;
/// Reward added on success (Habitat's `success_reward`).
pub const SUCCESS_REWARD: f64 = 2.5;

/// Why a reset or step failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum GymError {
    /// `reset` asked for an episode id the dataset does not have.
    #[error("no episode with id '{id}' in {file}")]
    UnknownEpisode {
        /// The id asked for.
        id: String,
        /// The episodes file.
        file: String,
    },
    /// The episode asked for cannot run.
    #[error("episode {id} is invalid: {reason}")]
    InvalidEpisode {
        /// Its id.
        id: String,
        /// Why.
        reason: String,
    },
    /// An episode id was asked for but episodes are generated.
    #[error("episode_id needs an episodes file: without one, episodes are generated")]
    NoEpisodesFile,
    /// No episode of the dataset can run.
    #[error("no valid episode in {file} (the first one: {reason})")]
    NoValidEpisode {
        /// The episodes file.
        file: String,
        /// Why the first one is invalid.
        reason: String,
    },
    /// `step` before the first `reset`.
    #[error("call reset() before step()")]
    NotReset,
    /// `step` after the episode ended.
    #[error("the episode is over: call reset()")]
    EpisodeOver,
    /// `step_twist` without physics.
    #[error("step_twist needs physics")]
    NeedsPhysics,
    /// A twist or duration that is not finite, or a negative duration.
    #[error("bad twist: velocities must be finite and the duration finite and >= 0 (s)")]
    BadTwist,
    /// One action per environment is needed.
    #[error("expected {expected} actions, got {got}")]
    ActionCount {
        /// Environments.
        expected: usize,
        /// Actions given.
        got: usize,
    },
    /// Episodes could not be generated.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The camera failed.
    #[error("{0}")]
    Render(String),
}

/// Where an environment's episodes come from.
#[derive(Debug, Clone)]
pub enum EpisodeSource {
    /// A dataset, played in order and cycling.
    Dataset {
        /// The episodes.
        dataset: Arc<Dataset>,
        /// Its file, for messages.
        file: String,
    },
    /// Generated with Habitat's rules, one per reset.
    Generated {
        /// The floor: `auto` or a height (m).
        floor: String,
    },
}

/// What the agent observes, as habitat-lab names and shapes it (see the module's conventions).
#[derive(Debug, Clone, PartialEq)]
pub struct GymObservation {
    /// `pointgoal_with_gps_compass`: distance (m) and bearing (rad, CCW, 0 ahead) of the goal.
    pub pointgoal: [f32; 2],
    /// `gps`: position relative to the start, in the start's frame, as (forward, right) (m).
    pub gps: [f32; 2],
    /// `compass`: heading relative to the start (rad, CCW, in (-pi, pi]).
    pub compass: f32,
    /// The camera's images (`depth` in m, 0 = no return; `rgb`), when the setup has sensors.
    pub frame: Option<CameraFrame>,
}

impl GymObservation {
    /// Habitat's observation from the simulator's (whose GPS is (forward, left)).
    pub fn new(obs: &Observation, frame: Option<CameraFrame>) -> Self {
        GymObservation {
            pointgoal: [obs.pointgoal[0] as f32, obs.pointgoal[1] as f32],
            gps: [obs.gps.x as f32, -obs.gps.y as f32],
            compass: obs.compass as f32,
            frame,
        }
    }
}

/// The `info` of a step: Habitat's metrics so far and the episode.
#[derive(Debug, Clone, PartialEq)]
pub struct GymInfo {
    /// The episode's id.
    pub episode_id: String,
    /// Geodesic distance to the nearest goal (m).
    pub distance_to_goal: f64,
    /// 1 if stop was called inside the success radius, else 0.
    pub success: f64,
    /// SPL (0 until success).
    pub spl: f64,
    /// Soft SPL.
    pub soft_spl: f64,
    /// Collisions so far.
    pub collisions: u32,
    /// Whether this step's motion was blocked or deflected.
    pub collided: bool,
    /// Actions so far.
    pub steps: u32,
    /// Path travelled (m).
    pub path_length: f64,
    /// Whether the agent called stop.
    pub called_stop: bool,
}

impl GymInfo {
    fn new(episode_id: &str, m: &EpisodeMetrics, collided: bool) -> Self {
        GymInfo {
            episode_id: episode_id.to_string(),
            distance_to_goal: m.distance_to_goal,
            success: m.success,
            spl: m.spl,
            soft_spl: m.soft_spl,
            collisions: m.collisions,
            collided,
            steps: m.steps,
            path_length: m.path_length,
            called_stop: m.called_stop,
        }
    }
}

/// The result of a reset (reward 0, neither flag set) or a step.
#[derive(Debug, Clone, PartialEq)]
pub struct GymStep {
    /// The observation after it.
    pub obs: GymObservation,
    /// The step's reward.
    pub reward: f64,
    /// The agent called stop.
    pub terminated: bool,
    /// The step limit (or, for velocity agents, the time limit) ended the episode.
    pub truncated: bool,
    /// Metrics so far.
    pub info: GymInfo,
}

/// The running episode.
struct Current {
    env: EpisodeEnv,
    episode_id: String,
    /// The episode's number for seeds: its dataset index, or its generated number.
    index: usize,
    prev_distance: f64,
    step: u64,
    done: bool,
}

/// One PointNav environment (see the module's documentation).
pub struct PointNav {
    setup: Arc<EnvSetup>,
    source: Arc<EpisodeSource>,
    cfg: RunConfig,
    first: usize,
    stride: usize,
    /// Episodes started since the last seeding.
    cursor: usize,
    current: Option<Current>,
}

/// A well-mixed 64-bit value of `x` (splitmix64's finaliser).
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9e37_79b9_7f4a_7c15);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

impl PointNav {
    /// An environment playing episodes `first`, `first + stride`, ... of `source`; `seed`
    /// drives generated episodes, odometry noise and depth noise.
    pub fn new(setup: Arc<EnvSetup>, source: Arc<EpisodeSource>, first: usize, stride: usize, seed: u64) -> Self {
        let cfg = setup.run_config(AgentKind::Oracle, 1, seed);
        PointNav { setup, source, cfg, first, stride: stride.max(1), cursor: 0, current: None }
    }

    /// The setup.
    pub fn setup(&self) -> &Arc<EnvSetup> {
        &self.setup
    }

    /// Starts the next episode, or the one with `episode_id` (datasets only). `seed` re-seeds
    /// the environment and starts its episode sequence again.
    pub fn reset(&mut self, seed: Option<u64>, episode_id: Option<&str>) -> Result<GymStep, GymError> {
        if let Some(s) = seed {
            self.cfg.seed = s;
            self.cursor = 0;
        }
        self.current = None;
        let (made, ep_id, index) = match (&*self.source, episode_id) {
            (EpisodeSource::Generated { .. }, Some(_)) => return Err(GymError::NoEpisodesFile),
            (EpisodeSource::Dataset { dataset, file }, Some(id)) => {
                let index = dataset.episodes.iter().position(|e| e.episode_id == id).ok_or_else(|| GymError::UnknownEpisode { id: id.to_string(), file: file.clone() })?;
                let ep = &dataset.episodes[index];
                let (made, _) = make_env(&self.setup.world, ep, index, &self.cfg).map_err(|reason| GymError::InvalidEpisode { id: id.to_string(), reason })?;
                (made, ep.episode_id.clone(), index)
            }
            (EpisodeSource::Dataset { dataset, file }, None) => {
                let n = dataset.episodes.len();
                let mut first_reason = None;
                let mut found = None;
                for _ in 0..n.max(1) {
                    let index = (self.first + self.cursor * self.stride) % n.max(1);
                    self.cursor += 1;
                    let Some(ep) = dataset.episodes.get(index) else { break };
                    match make_env(&self.setup.world, ep, index, &self.cfg) {
                        Ok((made, _)) => {
                            found = Some((made, ep.episode_id.clone(), index));
                            break;
                        }
                        Err(reason) => {
                            first_reason.get_or_insert(format!("episode {}: {reason}", ep.episode_id));
                        }
                    }
                }
                found.ok_or_else(|| GymError::NoValidEpisode { file: file.clone(), reason: first_reason.unwrap_or_else(|| "the file has no episodes".into()) })?
            }
            (EpisodeSource::Generated { floor }, None) => {
                let index = self.first + self.cursor * self.stride;
                self.cursor += 1;
                let mut ds = generate(&self.setup.world, &self.setup.scene, floor, 1, mix(self.cfg.seed ^ mix(index as u64)), &self.setup.scene)?;
                let mut ep: Episode = ds.episodes.remove(0);
                ep.episode_id = index.to_string();
                let (made, _) = make_env(&self.setup.world, &ep, index, &self.cfg).map_err(|reason| GymError::InvalidEpisode { id: ep.episode_id.clone(), reason })?;
                (made, ep.episode_id, index)
            }
        };
        let mut cur = Current { env: made, episode_id: ep_id, index, prev_distance: 0.0, step: 0, done: false };
        let m = cur.env.as_dyn().metrics();
        cur.prev_distance = m.distance_to_goal;
        let obs = self.observe(&cur)?;
        let info = GymInfo::new(&cur.episode_id, &m, false);
        self.current = Some(cur);
        Ok(GymStep { obs, reward: 0.0, terminated: false, truncated: false, info })
    }

    /// The observation of the running episode now (the camera frame of its current step).
    fn observe(&self, cur: &Current) -> Result<GymObservation, GymError> {
        let env = match &cur.env {
            EpisodeEnv::Plain(e) => e as &dyn xhab_sim::env::DiscreteEnv,
            EpisodeEnv::Physics(e) => e,
        };
        let frame = match self.cfg.sensors.as_deref() {
            Some(rig) => Some(capture(rig, env.pose(), env.height(), self.cfg.seed, cur.index, cur.step, &mut RenderStats::default()).map_err(GymError::Render)?),
            None => None,
        };
        Ok(GymObservation::new(&env.observe(), frame))
    }

    /// Applies one of Habitat's discrete actions.
    pub fn step(&mut self, action: Action) -> Result<GymStep, GymError> {
        self.advance(|env| match env {
            EpisodeEnv::Plain(e) => Ok(xhab_sim::env::DiscreteEnv::step(e, action).collided),
            EpisodeEnv::Physics(e) => Ok(xhab_sim::env::DiscreteEnv::step(e, action).collided),
        })
    }

    /// Holds `linear` (m/s) and `angular` (rad/s, CCW) velocities for `duration` (s) under
    /// physics (a velocity agent's control cycle); the episode ends at the time limit
    /// (`max_episode_steps` control periods). Stop with `step(Action::Stop)`.
    pub fn step_twist(&mut self, linear: f64, angular: f64, duration: f64) -> Result<GymStep, GymError> {
        if !(linear.is_finite() && angular.is_finite() && duration.is_finite() && duration >= 0.0) {
            return Err(GymError::BadTwist);
        }
        self.advance(|env| match env {
            EpisodeEnv::Plain(_) => Err(GymError::NeedsPhysics),
            EpisodeEnv::Physics(e) => {
                e.drive(Twist { linear, angular }, duration);
                Ok(false)
            }
        })
    }

    /// Moves the running episode on with `f` (which says whether it collided) and scores it.
    fn advance(&mut self, f: impl FnOnce(&mut EpisodeEnv) -> Result<bool, GymError>) -> Result<GymStep, GymError> {
        let mut cur = self.current.take().ok_or(GymError::NotReset)?;
        if cur.done {
            self.current = Some(cur);
            return Err(GymError::EpisodeOver);
        }
        let collided = match f(&mut cur.env) {
            Ok(c) => c,
            Err(e) => {
                self.current = Some(cur);
                return Err(e);
            }
        };
        cur.step += 1;
        let env = cur.env.as_dyn();
        let m = env.metrics();
        cur.done = env.is_done();
        let mut reward = cur.prev_distance - m.distance_to_goal + SLACK_REWARD;
        if m.success > 0.0 {
            reward += SUCCESS_REWARD;
        }
        cur.prev_distance = m.distance_to_goal;
        let terminated = m.called_stop;
        let truncated = cur.done && !terminated;
        let info = GymInfo::new(&cur.episode_id, &m, collided);
        let obs = self.observe(&cur);
        self.current = Some(cur);
        Ok(GymStep { obs: obs?, reward, terminated, truncated, info })
    }

    /// A snapshot of the running episode for oracles (`None` before the first reset).
    pub fn snapshot(&self) -> Option<EnvSnapshot> {
        self.current.as_ref().map(|c| match &c.env {
            EpisodeEnv::Plain(e) => EnvSnapshot::of(e),
            EpisodeEnv::Physics(e) => EnvSnapshot::of(e),
        })
    }

    /// The running episode's metrics (`None` before the first reset).
    pub fn metrics(&self) -> Option<EpisodeMetrics> {
        self.current.as_ref().map(|c| match &c.env {
            EpisodeEnv::Plain(e) => xhab_sim::env::DiscreteEnv::metrics(e),
            EpisodeEnv::Physics(e) => xhab_sim::env::DiscreteEnv::metrics(e),
        })
    }
}

/// `n` PointNav environments stepped together, in parallel on `threads` threads, with
/// Gymnasium's next-step autoreset: the step after an episode ends resets that environment
/// (its action is ignored; reward 0, neither flag set).
pub struct VecPointNav {
    envs: Vec<PointNav>,
    pool: Option<rayon::ThreadPool>,
    needs_reset: Vec<bool>,
}

impl VecPointNav {
    /// `n` environments over `source` (environment `i` plays episodes `i`, `i + n`, ...), all
    /// seeded with `seed`.
    pub fn new(setup: Arc<EnvSetup>, source: Arc<EpisodeSource>, n: usize, threads: usize, seed: u64) -> Self {
        let n = n.max(1);
        let envs = (0..n).map(|i| PointNav::new(setup.clone(), source.clone(), i, n, seed)).collect();
        let pool = (threads > 1).then(|| rayon::ThreadPoolBuilder::new().num_threads(threads).build().ok()).flatten();
        // Grids are built once, before the workers start.
        for f in 0..setup.world.floors.len() {
            let _ = setup.world.grid(f);
        }
        VecPointNav { envs, pool, needs_reset: vec![false; n] }
    }

    /// Number of environments.
    pub fn len(&self) -> usize {
        self.envs.len()
    }

    /// Whether there is no environment (never: at least one is made).
    pub fn is_empty(&self) -> bool {
        self.envs.is_empty()
    }

    /// The environments.
    pub fn envs(&self) -> &[PointNav] {
        &self.envs
    }

    fn each<T: Send>(&mut self, f: impl Fn(usize, &mut PointNav, bool) -> T + Sync + Send) -> Vec<T> {
        let needs = &self.needs_reset;
        match &self.pool {
            Some(pool) => pool.install(|| self.envs.par_iter_mut().enumerate().map(|(i, e)| f(i, e, needs[i])).collect()),
            None => self.envs.iter_mut().enumerate().map(|(i, e)| f(i, e, needs[i])).collect(),
        }
    }

    /// Resets every environment (re-seeded with `seed` when given).
    pub fn reset(&mut self, seed: Option<u64>) -> Result<Vec<GymStep>, GymError> {
        let out: Result<Vec<GymStep>, GymError> = self.each(|_, e, _| e.reset(seed, None)).into_iter().collect();
        self.needs_reset.iter_mut().for_each(|r| *r = false);
        out
    }

    /// Steps every environment with its action (autoresetting those whose episode ended at
    /// the previous step).
    pub fn step(&mut self, actions: &[Action]) -> Result<Vec<GymStep>, GymError> {
        if actions.len() != self.envs.len() {
            return Err(GymError::ActionCount { expected: self.envs.len(), got: actions.len() });
        }
        self.advance(|i, e| e.step(actions[i]))
    }

    /// Holds each environment's `(linear m/s, angular rad/s)` twist for `duration` s under
    /// physics ([`PointNav::step_twist`]), with the same autoreset as [`VecPointNav::step`].
    pub fn step_twist(&mut self, twists: &[(f64, f64)], duration: f64) -> Result<Vec<GymStep>, GymError> {
        if twists.len() != self.envs.len() {
            return Err(GymError::ActionCount { expected: self.envs.len(), got: twists.len() });
        }
        self.advance(|i, e| e.step_twist(twists[i].0, twists[i].1, duration))
    }

    /// Moves every environment on with `f`, or resets those whose episode ended.
    fn advance(&mut self, f: impl Fn(usize, &mut PointNav) -> Result<GymStep, GymError> + Sync + Send) -> Result<Vec<GymStep>, GymError> {
        let out: Vec<GymStep> = self.each(|i, e, reset| if reset { e.reset(None, None) } else { f(i, e) }).into_iter().collect::<Result<_, _>>()?;
        for (r, s) in self.needs_reset.iter_mut().zip(&out) {
            *r = s.terminated || s.truncated;
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::setup::EnvOptions;
    use xhab_sim::oracle::ShortestPathFollower;

    fn setup() -> Arc<EnvSetup> {
        Arc::new(EnvSetup::build(&EnvOptions::new("procedural:1")).unwrap())
    }

    #[test]
    fn oracle_episode_ends_in_success_with_habitat_reward() {
        let s = setup();
        let mut env = PointNav::new(s, Arc::new(EpisodeSource::Generated { floor: "auto".into() }), 0, 1, 3);
        let r = env.reset(None, None).unwrap();
        let d0 = r.info.distance_to_goal;
        let mut oracle = ShortestPathFollower::new();
        let mut total = 0.0;
        let mut steps = 0;
        loop {
            let a = oracle.act(&env.snapshot().unwrap());
            let s = env.step(a).unwrap();
            total += s.reward;
            steps += 1;
            if s.terminated || s.truncated {
                assert!(s.terminated && s.info.success == 1.0);
                let expected = d0 - s.info.distance_to_goal + SLACK_REWARD * steps as f64 + SUCCESS_REWARD;
                assert!((total - expected).abs() < 1e-9, "{total} vs {expected}");
                break;
            }
        }
        assert!(matches!(env.step(Action::Stop), Err(GymError::EpisodeOver)));
    }

    #[test]
    fn vector_episodes_do_not_depend_on_size_or_threads() {
        let s = setup();
        let src = Arc::new(EpisodeSource::Generated { floor: "auto".into() });
        let first = |n: usize, threads: usize| {
            let mut v = VecPointNav::new(s.clone(), src.clone(), n, threads, 5);
            v.reset(None).unwrap().into_iter().map(|r| (r.info.episode_id, r.info.distance_to_goal)).collect::<Vec<_>>()
        };
        let one = first(1, 1);
        let three = first(3, 2);
        assert_eq!(one[0], three[0]);
        assert_eq!(first(3, 1), three);
    }
}
