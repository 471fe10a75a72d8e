//! The speed figures of one scene (`xhab perf SCENE`): [`measure_scene`] and its result,
//! whose JSON is the contract `xhab perf --json` prints and scripts read.
//!
//! Each figure times only the operation it names: map build (floor detection, the
//! navigation grid and its corner graph, as habitat's navmesh build includes its path
//! finder), geodesic queries against an episode's goal field (the per-step
//! `distance_to_goal`), the goal field's build (an episode's setup), cold point-to-point
//! queries, and discrete steps (motion with sliding plus the step's metric update) without
//! rendering. Optional sections time rendering at every step, AMCL updates, the native
//! navigation loop ([`crate::nav_perf`]) and physics.
//!
//! [`PerfOptions::groups`] (`xhab perf --only GROUP`) runs some [`PerfGroup`]s alone; the
//! figures of the groups not run are absent from the JSON (never zero or null). The grid is
//! built whatever the groups, since every figure stands on it; only `grid` times it.

use crate::nav_perf::{nav_perf, NavPerf, NavPerfError};
use crate::setup::{self, CameraOptions, PhysicsOptions, SceneOptions, SetupError};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;
use std::sync::Arc;
use std::time::Instant;
use xhab_sim::action::Action;
use xhab_sim::env::{DiscreteEnv, KinematicEnv, EnvView, TaskConfig};
use xhab_sim::episode::{Episode, Goal};
use xhab_sim::goal_field::GoalField;
use xhab_sim::navgrid::NavGrid;
use xhab_sim::oracle::ShortestPathFollower;
use xhab_sim::robot::PhysicsError;
use xhab_sim::sensors::{CameraParams, RenderError};
use xhab_sim::world::World;

/// Goal fields built and queried for the geodesic figures.
pub const PERF_GOALS: usize = 8;
/// Query points per goal field.
pub const PERF_QUERIES: usize = 4096;
/// Episodes the step figures cycle through.
pub const PERF_EPISODES: usize = 16;
/// Particles of the AMCL figure.
pub const PERF_AMCL_PARTICLES: usize = 5000;
/// Beams per AMCL update of the AMCL figure.
pub const PERF_AMCL_BEAMS: usize = 60;

/// A group of figures that `xhab perf --only GROUP` runs alone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PerfGroup {
    /// `geodesic_queries_per_s`, `geodesic_field_build_s`, `geodesic_pair_queries_per_s`.
    Geodesic,
    /// `map_build_s` (best of three).
    Grid,
    /// `discrete_steps_per_s`, `oracle_steps_per_s`.
    Discrete,
    /// The physics section (`physics_steps_per_s`, `physics_action_steps_per_s`, ...).
    Physics,
    /// The rendering section (`depth_steps_per_s`, ...); `depth` when no sensor is given.
    Sensors,
    /// The AMCL section (`amcl_update_ms`, ...).
    Amcl,
}

impl PerfGroup {
    /// Every group, in the order the figures are measured.
    pub const ALL: [PerfGroup; 6] = [PerfGroup::Grid, PerfGroup::Geodesic, PerfGroup::Discrete, PerfGroup::Sensors, PerfGroup::Amcl, PerfGroup::Physics];
    /// The groups' names, as `--only` spells them.
    pub const NAMES: [&'static str; 6] = ["geodesic", "grid", "discrete", "physics", "sensors", "amcl"];

    /// The name `--only` spells this group with.
    pub fn name(self) -> &'static str {
        match self {
            PerfGroup::Geodesic => "geodesic",
            PerfGroup::Grid => "grid",
            PerfGroup::Discrete => "discrete",
            PerfGroup::Physics => "physics",
            PerfGroup::Sensors => "sensors",
            PerfGroup::Amcl => "amcl",
        }
    }

    /// The group of a name as `--only` spells it, `None` for an unknown name.
    pub fn from_name(name: &str) -> Option<PerfGroup> {
        PerfGroup::ALL.into_iter().find(|g| g.name() == name)
    }
}

/// What to measure on which scene, as `xhab perf`'s flags give it.
#[derive(Debug, Clone)]
pub struct PerfOptions {
    /// The SCENE argument: a file or `procedural[:SEED]`.
    pub scene: String,
    /// How to read it and the agent's size (the grid is built for this agent).
    pub scene_options: SceneOptions,
    /// Seconds to spend on each timed figure (s, approximate; must be > 0).
    pub seconds: f64,
    /// The robot (physics figures and the navigation loop) and the physics settings.
    pub physics: PhysicsOptions,
    /// Time physics: raw physics steps and discrete actions under physics (`--physics`).
    pub measure_physics: bool,
    /// Sensors to render at every step: empty (no rendering figures), `depth`, or `depth`
    /// and `rgb`.
    pub sensors: Vec<String>,
    /// The camera of the rendering figures (its height defaults to Habitat's 1.25 m).
    pub camera: CameraOptions,
    /// Also time batched rendering, this many views per call (`--batch`; 0 or `None`: not).
    pub batch: Option<usize>,
    /// Time AMCL updates (5,000 particles, 60 beams).
    pub amcl: bool,
    /// Time the native navigation loop on a fixed episode set ([`crate::nav_perf`]).
    pub nav: bool,
    /// Run only these groups (`--only`), whatever `measure_physics`, `sensors` and `amcl`
    /// say (`sensors` then defaults to `depth`); empty: the base figures and the sections
    /// the flags ask for. `nav` is no group: its flag alone decides.
    pub groups: Vec<PerfGroup>,
}

impl PerfOptions {
    /// The base figures of `scene` with every default: one second per figure, no optional
    /// section.
    pub fn new(scene: impl Into<String>) -> Self {
        Self {
            scene: scene.into(),
            scene_options: SceneOptions::default(),
            seconds: 1.0,
            physics: PhysicsOptions::default(),
            measure_physics: false,
            sensors: Vec::new(),
            camera: CameraOptions::default(),
            batch: None,
            amcl: false,
            nav: false,
            groups: Vec::new(),
        }
    }

    /// Whether the figures of group `g` are measured: it is listed in `groups`, or `groups`
    /// is empty and `g` is a base group or its section's flag is set.
    pub fn runs(&self, g: PerfGroup) -> bool {
        if !self.groups.is_empty() {
            return self.groups.contains(&g);
        }
        match g {
            PerfGroup::Geodesic | PerfGroup::Grid | PerfGroup::Discrete => true,
            PerfGroup::Physics => self.measure_physics,
            PerfGroup::Sensors => !self.sensors.is_empty(),
            PerfGroup::Amcl => self.amcl,
        }
    }

    /// The sensors the rendering figures render: `sensors`, or `depth` when the `sensors`
    /// group was asked for by `--only` alone.
    pub fn rendered_sensors(&self) -> Vec<String> {
        if self.sensors.is_empty() && self.runs(PerfGroup::Sensors) {
            vec!["depth".to_string()]
        } else {
            self.sensors.clone()
        }
    }
}

/// The figures of one scene. Serialized (through `serde_json::Value`, whose keys are sorted)
/// it is exactly the JSON `xhab perf --json` prints: the optional sections' fields sit at the
/// top level, absent when the section was not asked for, and a figure of a [`PerfGroup`]
/// not run is absent too.
#[derive(Debug, Clone, Serialize)]
pub struct ScenePerf {
    /// The SCENE argument.
    pub scene: String,
    /// Triangles of the scene.
    pub triangles: usize,
    /// Height of the measured (lowest) floor (m).
    pub floor_height_m: f64,
    /// Navigable area of that floor (m²).
    pub navigable_area_m2: f64,
    /// Cell size of the navigation grid (m).
    pub cell_size_m: f64,
    /// Map build, best of three: floor detection, grid and corner graph (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map_build_s: Option<f64>,
    /// Geodesic distance queries against built goal fields (1/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geodesic_queries_per_s: Option<f64>,
    /// Mean build time of one goal field (s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geodesic_field_build_s: Option<f64>,
    /// Cold point-to-point geodesic queries, one goal-directed search each (1/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geodesic_pair_queries_per_s: Option<f64>,
    /// Discrete steps with random actions, no rendering (1/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub discrete_steps_per_s: Option<f64>,
    /// Discrete steps of the shortest-path oracle, its decisions included (1/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub oracle_steps_per_s: Option<f64>,
    /// Threads the figures ran on (always 1).
    pub threads: usize,
    /// Sum of the queried distances, so that no query is optimised away (m).
    pub checksum: f64,
    /// Rendering at every step (`sensors` not empty).
    #[serde(flatten)]
    pub rendering: Option<RenderPerf>,
    /// AMCL updates (`amcl`).
    #[serde(flatten)]
    pub amcl: Option<AmclPerf>,
    /// The navigation loop (`nav`).
    #[serde(flatten)]
    pub nav: Option<NavPerf>,
    /// Physics (`measure_physics`).
    #[serde(flatten)]
    pub physics: Option<PhysicsPerf>,
    /// Which renderer rendered and why, e.g. `raster (auto: no GPU renderer: ...)`, for a
    /// log line (not in the JSON).
    #[serde(skip)]
    pub renderer_note: Option<String>,
}

/// Discrete steps that render the camera at every step.
#[derive(Debug, Clone, Serialize)]
pub struct RenderPerf {
    /// The renderer's name (`raycast`, `raster`, `wgpu`).
    pub renderer: String,
    /// The sensors rendered (`depth`, `rgb`).
    pub sensors: Vec<String>,
    /// Image width and height (px).
    pub resolution: usize,
    /// Threads of the rendering pool.
    pub render_threads: usize,
    /// Build time of the renderer (s).
    pub sensor_build_s: f64,
    /// Steps with one rendered view each (1/s).
    pub depth_steps_per_s: f64,
    /// Sum of sampled pixels, so that no render is optimised away.
    pub sensor_checksum: f64,
    /// Views per batched render call, if batching was timed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub batch: Option<usize>,
    /// Views rendered in batches, each with its agent's step and the same sensors as
    /// `depth_steps_per_s` (depth, and RGB when asked) (1/s).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub depth_batch_steps_per_s: Option<f64>,
}

/// AMCL updates on one core.
#[derive(Debug, Clone, Serialize)]
pub struct AmclPerf {
    /// Particles in the filter.
    pub amcl_particles: usize,
    /// Beams per update.
    pub amcl_beams: usize,
    /// Mean time of one update: motion model, weighting, resampling every second update (ms).
    pub amcl_update_ms: f64,
}

/// One robot under physics.
#[derive(Debug, Clone, Serialize)]
pub struct PhysicsPerf {
    /// The robot profile's name.
    pub robot: String,
    /// Build time of the scene's rigid mesh (s).
    pub physics_mesh_build_s: f64,
    /// Raw physics steps, contacts included (1/s).
    pub physics_steps_per_s: f64,
    /// Discrete actions under physics, via Algorithm 1 (1/s).
    pub physics_action_steps_per_s: f64,
    /// Simulated seconds per wall second of the raw physics steps.
    pub physics_real_time_factor: f64,
}

/// Why a scene could not be measured. Messages name the flag, as the CLI spells it.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PerfError {
    /// The scene, robot, camera or renderer could not be set up.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// `seconds` is not a positive number.
    #[error("--seconds must be a positive number of seconds")]
    BadSeconds,
    /// No sampled start could reach its goal.
    #[error("no valid episode to step (no sampled start reaches its goal)")]
    NoValidEpisode,
    /// The robot could not be placed under physics.
    #[error(transparent)]
    Physics(#[from] PhysicsError),
    /// A view could not be rendered.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The navigation loop could not be timed.
    #[error(transparent)]
    Nav(#[from] NavPerfError),
}

/// Measures the figures `o` asks for on its scene, one thread (rendering excepted), and
/// returns them.
pub fn measure_scene(o: &PerfOptions) -> Result<ScenePerf, PerfError> {
    if !(o.seconds > 0.0 && o.seconds.is_finite()) {
        return Err(PerfError::BadSeconds);
    }
    // Checked before the long figures, so that a typo fails at once.
    let sensors = o.rendered_sensors();
    let rgb = setup::parse_sensors(&sensors)?;
    // Only RGB reads the textures: without it they are left unread (as `xhab bench` does).
    let scene = setup::load_scene(&o.scene, &SceneOptions { textures: o.scene_options.textures && rgb, ..o.scene_options.clone() })?;
    let tris = scene.triangle_count();
    let params = setup::agent_params(&o.scene_options);
    let no_floor = || SetupError::NoWalkableFloor(o.scene.clone());
    // Map build: best of three (floor detection + grid + corner graph) when timed, else once.
    let mut build_s = f64::INFINITY;
    let mut world = None;
    for _ in 0..if o.runs(PerfGroup::Grid) { 3 } else { 1 } {
        // The copy of the scene is the benchmark's, not the build's: made before the clock.
        let copy = scene.clone();
        let t = Instant::now();
        let w = World::new(copy, params.clone());
        let f = w.default_floor().ok_or_else(no_floor)?;
        w.grid(f).map_err(SetupError::Grid)?.corner_graph();
        build_s = build_s.min(t.elapsed().as_secs_f64());
        world = Some(w);
    }
    let world = world.ok_or_else(no_floor)?;
    let grid = world.grid(world.default_floor().ok_or_else(no_floor)?).map_err(SetupError::Grid)?;
    let cells = grid.cells_on_islands(1.5);
    let cells = if cells.is_empty() { grid.cells_on_islands(0.0) } else { cells };
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut sample = || grid.sample_navigable_point(&cells, &mut rng).ok_or(PerfError::Setup(SetupError::NoNavigablePoint));

    // The same points whatever the groups, so that a group's figures do not depend on the
    // others being run.
    let goals: Vec<_> = (0..PERF_GOALS).map(|_| sample()).collect::<Result<_, _>>()?;
    let queries: Vec<_> = (0..PERF_QUERIES).map(|_| sample().map(|p| p.xy())).collect::<Result<_, _>>()?;
    let episodes: Vec<Episode> = (0..PERF_EPISODES)
        .map(|i| -> Result<Episode, PerfError> {
            let s = sample()?;
            let g = goals[i % goals.len()];
            Ok(Episode {
                episode_id: i.to_string(),
                scene_id: o.scene.clone(),
                start_position: s,
                start_yaw: 0.0,
                goals: vec![Goal { position: g, radius: 0.2 }],
                geodesic_distance: None,
                info: serde_json::Value::Null,
            })
        })
        .collect::<Result<_, _>>()?;
    let mut checksum = 0.0;
    let geodesic = if o.runs(PerfGroup::Geodesic) { Some(geodesic_perf(&grid, &goals, &queries, o.seconds, &mut checksum)) } else { None };

    // Each episode's start (its goal field included) is built once and cloned for every run.
    let need_starts = o.runs(PerfGroup::Discrete) || o.runs(PerfGroup::Sensors);
    let starts: Vec<KinematicEnv> =
        if need_starts { episodes.iter().filter_map(|ep| KinematicEnv::new(grid.clone(), ep, TaskConfig::default()).ok()).collect() } else { Vec::new() };
    if need_starts && starts.is_empty() {
        return Err(PerfError::NoValidEpisode);
    }
    let discrete = if o.runs(PerfGroup::Discrete) { Some(discrete_perf(&starts, o.seconds, &mut checksum)) } else { None };
    let mut out = ScenePerf {
        scene: o.scene.clone(),
        triangles: tris,
        floor_height_m: grid.floor_z,
        navigable_area_m2: grid.navigable_cells() as f64 * grid.resolution().powi(2),
        cell_size_m: grid.resolution(),
        map_build_s: o.runs(PerfGroup::Grid).then_some(build_s),
        geodesic_queries_per_s: geodesic.map(|g| g.queries_per_s),
        geodesic_field_build_s: geodesic.map(|g| g.field_build_s),
        geodesic_pair_queries_per_s: geodesic.map(|g| g.pair_queries_per_s),
        discrete_steps_per_s: discrete.map(|d| d.0),
        oracle_steps_per_s: discrete.map(|d| d.1),
        threads: 1,
        checksum,
        rendering: None,
        amcl: None,
        nav: None,
        physics: None,
        renderer_note: None,
    };
    if o.runs(PerfGroup::Sensors) {
        let (r, note) = render_perf(&world, &starts, o, &sensors, rgb)?;
        out.rendering = Some(r);
        out.renderer_note = Some(note);
    }
    if o.runs(PerfGroup::Amcl) {
        out.amcl = Some(amcl_perf(&world, &grid, &episodes, o.seconds)?);
    }
    if o.nav {
        out.nav = Some(nav_perf(&world, &o.scene, &o.physics.robot)?);
    }
    if o.runs(PerfGroup::Physics) {
        out.physics = Some(physics_perf(&world, &grid, &episodes, o)?);
    }
    Ok(out)
}

/// The geodesic figures of one grid.
#[derive(Debug, Clone, Copy)]
struct GeodesicPerf {
    /// Queries against built goal fields (1/s).
    queries_per_s: f64,
    /// Mean build time of one goal field (s).
    field_build_s: f64,
    /// Cold point-to-point queries (1/s).
    pair_queries_per_s: f64,
}

/// Times goal-field builds (one per goal), cold point-to-point queries (a quarter of
/// `seconds`) and queries against the built fields (half of `seconds`); adds the finite
/// distances to `checksum`.
fn geodesic_perf(grid: &Arc<NavGrid>, goals: &[xhab_types::Point3], queries: &[xhab_types::Point2], seconds: f64, checksum: &mut f64) -> GeodesicPerf {
    let mut field_s = 0.0;
    let mut fields = Vec::new();
    for g in goals {
        let t = Instant::now();
        fields.push(GoalField::new(grid, &[g.xy()]));
        field_s += t.elapsed().as_secs_f64();
    }
    let field_s = field_s / goals.len() as f64;
    // Cold point-to-point queries: a goal-directed search per pair.
    let t = Instant::now();
    let mut pairs = 0u64;
    while t.elapsed().as_secs_f64() < seconds * 0.25 || pairs < 8 {
        let (p, q) = (queries[pairs as usize % queries.len()], goals[pairs as usize % goals.len()].xy());
        let d = xhab_sim::geodesic::geodesic_distance(grid, p, q);
        if d.is_finite() {
            *checksum += d;
        }
        pairs += 1;
    }
    let pair_rate = pairs as f64 / t.elapsed().as_secs_f64();
    let (mut nq, mut q_s) = (0u64, 0.0);
    while q_s < seconds * 0.5 {
        let t = Instant::now();
        for f in &fields {
            for q in queries {
                let d = f.distance(grid, *q);
                if d.is_finite() {
                    *checksum += d;
                }
            }
        }
        q_s += t.elapsed().as_secs_f64();
        nq += (fields.len() * queries.len()) as u64;
    }
    GeodesicPerf { queries_per_s: nq as f64 / q_s, field_build_s: field_s, pair_queries_per_s: pair_rate }
}

/// Discrete steps for about `seconds`: random actions (no stop) and the oracle from each
/// start, timing `env.step` (and the oracle's decisions) only. Returns (random steps/s,
/// oracle steps/s).
fn discrete_perf(starts: &[KinematicEnv], seconds: f64, checksum: &mut f64) -> (f64, f64) {
    let mut act_rng = ChaCha8Rng::seed_from_u64(11);
    let (mut steps, mut step_s) = (0u64, 0.0);
    let (mut osteps, mut ostep_s) = (0u64, 0.0);
    while step_s + ostep_s < seconds {
        for start in starts {
            let mut env = start.clone();
            let actions: Vec<Action> = (0..500).map(|_| random_action(&mut act_rng)).collect();
            let t = Instant::now();
            for &act in &actions {
                env.step(act);
            }
            *checksum += env.distance_to_goal().min(1e3);
            step_s += t.elapsed().as_secs_f64();
            steps += actions.len() as u64;

            let mut env = start.clone();
            let mut oracle = ShortestPathFollower::new();
            let t = Instant::now();
            while !env.is_done() {
                let act = oracle.act(&env);
                env.step(act);
                osteps += 1;
            }
            ostep_s += t.elapsed().as_secs_f64();
        }
    }
    (steps as f64 / step_s, osteps as f64 / ostep_s)
}

/// Physics figures: raw physics steps of one robot, and discrete actions via Algorithm 1.
fn physics_perf(world: &World, grid: &Arc<NavGrid>, episodes: &[Episode], o: &PerfOptions) -> Result<PhysicsPerf, PerfError> {
    use xhab_sim::physics_env::PhysicsEnv;
    use xhab_sim::robot::{PhysicsScene, RigidRobot};
    use xhab_types::Twist;
    let profile = setup::robot_profile(&o.physics.robot)?;
    let t = Instant::now();
    let scene = PhysicsScene::new(&world.scene).map_err(SetupError::Physics)?;
    let mesh_s = t.elapsed().as_secs_f64();
    let config = o.physics.config();
    let ep = &episodes[0];
    let start = xhab_types::Pose2::new(ep.start_position.x, ep.start_position.y, 0.0);
    let mut robot = RigidRobot::new(&scene, &profile, start, grid.floor_z, &config.physics)?;
    let (mut n, t) = (0u64, Instant::now());
    while t.elapsed().as_secs_f64() < o.seconds * 0.5 {
        for k in 0..600 {
            // Drive forward and turn in alternating two-second blocks: contacts included.
            let twist = if (k / 120) % 2 == 0 { Twist { linear: 0.25, angular: 0.0 } } else { Twist { linear: 0.0, angular: 0.5 } };
            robot.step_physics(twist);
        }
        n += 600;
    }
    let steps_per_s = n as f64 / t.elapsed().as_secs_f64();
    let mut act_rng = ChaCha8Rng::seed_from_u64(13);
    let (mut actions, mut act_s) = (0u64, 0.0);
    while act_s < o.seconds * 0.5 {
        for (i, ep) in episodes.iter().enumerate() {
            let Ok(mut env) = PhysicsEnv::new(grid.clone(), &scene, ep, TaskConfig::default(), &profile, config.clone(), i as u64) else { continue };
            let t = Instant::now();
            for _ in 0..50 {
                let act = random_action(&mut act_rng);
                env.step(act);
            }
            act_s += t.elapsed().as_secs_f64();
            actions += 50;
        }
    }
    Ok(PhysicsPerf {
        robot: profile.name,
        physics_mesh_build_s: mesh_s,
        physics_steps_per_s: steps_per_s,
        physics_action_steps_per_s: actions as f64 / act_s,
        physics_real_time_factor: steps_per_s / o.physics.steps_per_sec,
    })
}

/// Discrete steps that render the camera at every step (depth, and RGB when `rgb`), and with
/// a batch of N views rendered N at a time (N agents stepping together). Returns the figures
/// and which renderer rendered and why.
fn render_perf(world: &World, starts: &[KinematicEnv], o: &PerfOptions, sensors: &[String], rgb: bool) -> Result<(RenderPerf, String), PerfError> {
    let cam = setup::camera_params(&o.camera, CameraParams::default().mount_height)?;
    let t = Instant::now();
    let (r, why) = setup::build_renderer(o.camera.renderer, &world.scene)?;
    let build_s = t.elapsed().as_secs_f64();
    let mut act_rng = ChaCha8Rng::seed_from_u64(17);
    let (mut steps, mut s) = (0u64, 0.0);
    let mut checksum = 0.0f64;
    while s < o.seconds {
        for start in starts {
            let mut env = start.clone();
            let floor_z = env.grid().floor_z;
            let t = Instant::now();
            for _ in 0..50 {
                let act = random_action(&mut act_rng);
                env.step(act);
                let img = if rgb {
                    let (d, c) = r.depth_rgb(env.pose(), floor_z, &cam)?;
                    checksum += c[c.len() / 2] as f64;
                    d
                } else {
                    r.depth(env.pose(), floor_z, &cam)?
                };
                checksum += img.data[img.data.len() / 2] as f64;
            }
            s += t.elapsed().as_secs_f64();
            steps += 50;
            if s >= o.seconds {
                break;
            }
        }
    }
    let mut out = RenderPerf {
        renderer: r.name().to_string(),
        sensors: sensors.to_vec(),
        resolution: cam.width,
        render_threads: rayon::current_num_threads(),
        sensor_build_s: build_s,
        depth_steps_per_s: steps as f64 / s,
        sensor_checksum: checksum,
        batch: None,
        depth_batch_steps_per_s: None,
    };
    if let Some(n) = o.batch.filter(|&n| n > 0) {
        // N agents, each stepping its own episode; their N views rendered in one call.
        let mut envs: Vec<KinematicEnv> = starts.iter().cycle().take(n).cloned().collect();
        let (mut views_done, mut s) = (0u64, 0.0);
        while s < o.seconds {
            let t = Instant::now();
            for _ in 0..20 {
                let views: Vec<(xhab_types::Pose2, f64)> = envs
                    .iter_mut()
                    .map(|e| {
                        e.step(random_action(&mut act_rng));
                        (e.pose(), e.grid().floor_z)
                    })
                    .collect();
                // The same sensors as the single views: depth, and RGB when asked.
                if rgb {
                    let imgs = r.depth_rgb_batch(&views, &cam)?;
                    checksum += imgs.iter().map(|(d, c)| d.data[d.data.len() / 2] as f64 + c[c.len() / 2] as f64).sum::<f64>();
                } else {
                    let imgs = r.depth_batch(&views, &cam)?;
                    checksum += imgs.iter().map(|i| i.data[i.data.len() / 2] as f64).sum::<f64>();
                }
                views_done += views.len() as u64;
            }
            s += t.elapsed().as_secs_f64();
        }
        out.batch = Some(envs.len());
        out.depth_batch_steps_per_s = Some(views_done as f64 / s);
        out.sensor_checksum = checksum;
    }
    Ok((out, format!("{}{why}", r.name())))
}

/// A random discrete action without stop: forward half the time, turns otherwise.
fn random_action(rng: &mut ChaCha8Rng) -> Action {
    match rng.gen_range(0..4) {
        0 | 1 => Action::MoveForward,
        2 => Action::TurnLeft,
        _ => Action::TurnRight,
    }
}

/// AMCL update time with 5,000 particles and 60 beams (motion model, weighting, resampling
/// every second update), on one core, for about `seconds`.
fn amcl_perf(world: &World, grid: &NavGrid, episodes: &[Episode], seconds: f64) -> Result<AmclPerf, PerfError> {
    use xhab_nav::amcl::{Amcl, AmclParams};
    use xhab_sim::sensors::{Lidar, LidarParams};
    let rs = setup::ray_scene(&world.scene)?;
    let map = grid.occupancy_grid();
    // Exactly 5,000 particles: init() spreads max(min, max / 2) and KLD may not go below min.
    let params = AmclParams { min_particles: PERF_AMCL_PARTICLES, max_particles: PERF_AMCL_PARTICLES, laser_max_beams: PERF_AMCL_BEAMS, ..Default::default() };
    let mut amcl = Amcl::new(&map, params, 1);
    let start = episodes[0].start_position;
    let mut pose = xhab_types::Pose2::new(start.x, start.y, 0.0);
    amcl.init(pose, 0.2, 0.1);
    let mut lidar = Lidar::new(LidarParams { beams: 360, ..Default::default() }, 2);
    let scan = lidar.scan(&rs, pose, grid.floor_z);
    amcl.update(pose, &scan, xhab_types::Pose2::default());
    let (mut n, mut s) = (0u32, 0.0);
    while s < seconds || n < 10 {
        // Alternate small moves so that every call passes update_min_d.
        pose = pose.compose(xhab_types::Pose2::new(0.21 * if n % 2 == 0 { 1.0 } else { -1.0 }, 0.0, 0.0));
        let t = Instant::now();
        amcl.update(pose, &scan, xhab_types::Pose2::default());
        s += t.elapsed().as_secs_f64();
        n += 1;
    }
    Ok(AmclPerf { amcl_particles: amcl.len(), amcl_beams: PERF_AMCL_BEAMS, amcl_update_ms: 1000.0 * s / n as f64 })
}

#[cfg(test)]
mod tests {
    use super::*;
    use xhab_sim::sensors::RendererKind;

    /// Short figures on a small procedural house.
    fn quick() -> PerfOptions {
        PerfOptions { seconds: 0.02, ..PerfOptions::new("procedural:3") }
    }

    fn keys(p: &ScenePerf) -> Vec<String> {
        match serde_json::to_value(p).unwrap() {
            serde_json::Value::Object(m) => m.keys().cloned().collect(),
            v => panic!("not an object: {v}"),
        }
    }

    fn positive(name: &str, x: f64) {
        assert!(x.is_finite() && x > 0.0, "{name} = {x}");
    }

    #[test]
    fn base_figures_exist_and_are_positive() {
        let p = measure_scene(&quick()).unwrap();
        assert_eq!(p.scene, "procedural:3");
        assert!(p.triangles > 0);
        assert_eq!(p.threads, 1);
        assert!((p.cell_size_m - 0.05).abs() < 1e-12);
        assert!(p.floor_height_m.is_finite());
        for (n, x) in [
            ("navigable_area_m2", p.navigable_area_m2),
            ("map_build_s", p.map_build_s.unwrap()),
            ("geodesic_queries_per_s", p.geodesic_queries_per_s.unwrap()),
            ("geodesic_field_build_s", p.geodesic_field_build_s.unwrap()),
            ("geodesic_pair_queries_per_s", p.geodesic_pair_queries_per_s.unwrap()),
            ("discrete_steps_per_s", p.discrete_steps_per_s.unwrap()),
            ("oracle_steps_per_s", p.oracle_steps_per_s.unwrap()),
            ("checksum", p.checksum),
        ] {
            positive(n, x);
        }
        assert!(p.rendering.is_none() && p.amcl.is_none() && p.nav.is_none() && p.physics.is_none());
        // The JSON contract: exactly these keys (sorted, as `xhab perf` prints them).
        let expected = [
            "cell_size_m", "checksum", "discrete_steps_per_s", "floor_height_m", "geodesic_field_build_s", "geodesic_pair_queries_per_s",
            "geodesic_queries_per_s", "map_build_s", "navigable_area_m2", "oracle_steps_per_s", "scene", "threads", "triangles",
        ];
        assert_eq!(keys(&p), expected);
    }

    #[test]
    fn optional_sections_add_their_fields() {
        let o = PerfOptions {
            sensors: vec!["depth".into(), "rgb".into()],
            camera: CameraOptions { renderer: Some(RendererKind::Raster), resolution: 16, ..Default::default() },
            batch: Some(3),
            amcl: true,
            nav: true,
            measure_physics: true,
            ..quick()
        };
        let p = measure_scene(&o).unwrap();
        let r = p.rendering.as_ref().expect("rendering figures");
        assert_eq!((r.renderer.as_str(), r.resolution, r.batch), ("raster", 16, Some(3)));
        assert_eq!(r.sensors, ["depth", "rgb"]);
        assert!(r.render_threads >= 1);
        positive("depth_steps_per_s", r.depth_steps_per_s);
        positive("depth_batch_steps_per_s", r.depth_batch_steps_per_s.unwrap());
        assert!(r.sensor_build_s >= 0.0 && r.sensor_checksum.is_finite());
        assert!(p.renderer_note.as_deref().is_some_and(|n| n.starts_with("raster")));
        let a = p.amcl.as_ref().expect("amcl figures");
        assert_eq!((a.amcl_particles, a.amcl_beams), (PERF_AMCL_PARTICLES, PERF_AMCL_BEAMS));
        positive("amcl_update_ms", a.amcl_update_ms);
        let ph = p.physics.as_ref().expect("physics figures");
        assert_eq!(ph.robot, "habitat");
        positive("physics_steps_per_s", ph.physics_steps_per_s);
        positive("physics_action_steps_per_s", ph.physics_action_steps_per_s);
        assert!((ph.physics_real_time_factor - ph.physics_steps_per_s / 60.0).abs() < 1e-9 * ph.physics_real_time_factor);
        let nav = p.nav.as_ref().expect("navigation loop figures");
        assert!(nav.nav_episodes > 0 && nav.nav_episodes <= crate::nav_perf::NAV_PERF_EPISODES, "{nav:?}");
        positive("nav_real_time_factor", nav.nav_real_time_factor);
        positive("nav_sim_s", nav.nav_sim_s);
        let k = keys(&p);
        for f in [
            "renderer", "sensors", "resolution", "render_threads", "sensor_build_s", "depth_steps_per_s", "sensor_checksum", "batch", "depth_batch_steps_per_s",
            "amcl_particles", "amcl_beams", "amcl_update_ms", "robot", "physics_mesh_build_s", "physics_steps_per_s", "physics_action_steps_per_s",
            "physics_real_time_factor", "map_build_s", "discrete_steps_per_s", "nav_real_time_factor", "nav_sim_s", "nav_wall_s", "nav_episodes",
            "nav_success", "nav_spl",
        ] {
            assert!(k.iter().any(|x| x == f), "missing {f} in {k:?}");
        }
        assert!(!k.iter().any(|x| x == "renderer_note"), "{k:?}");
        // Without a batch, its two fields are absent.
        let p = measure_scene(&PerfOptions { sensors: vec!["depth".into()], camera: o.camera.clone(), ..quick() }).unwrap();
        let k = keys(&p);
        assert!(k.iter().any(|x| x == "depth_steps_per_s") && !k.iter().any(|x| x == "batch" || x == "depth_batch_steps_per_s" || x.starts_with("nav_")), "{k:?}");
    }

    /// The fields every run has, whatever the groups: the scene's facts.
    const FACTS: [&str; 7] = ["cell_size_m", "checksum", "floor_height_m", "navigable_area_m2", "scene", "threads", "triangles"];

    /// The figures each group adds to the JSON.
    fn group_fields(g: PerfGroup) -> &'static [&'static str] {
        match g {
            PerfGroup::Geodesic => &["geodesic_field_build_s", "geodesic_pair_queries_per_s", "geodesic_queries_per_s"],
            PerfGroup::Grid => &["map_build_s"],
            PerfGroup::Discrete => &["discrete_steps_per_s", "oracle_steps_per_s"],
            PerfGroup::Physics => &["physics_action_steps_per_s", "physics_mesh_build_s", "physics_real_time_factor", "physics_steps_per_s", "robot"],
            PerfGroup::Sensors => &["depth_steps_per_s", "render_threads", "renderer", "resolution", "sensor_build_s", "sensor_checksum", "sensors"],
            PerfGroup::Amcl => &["amcl_beams", "amcl_particles", "amcl_update_ms"],
        }
    }

    #[test]
    fn each_group_alone_gives_exactly_its_figures() {
        let camera = CameraOptions { renderer: Some(RendererKind::Raster), resolution: 8, ..Default::default() };
        for g in PerfGroup::ALL {
            // The procedural house, as `xhab perf procedural:3 --only GROUP` measures it.
            let p = measure_scene(&PerfOptions { groups: vec![g], camera: camera.clone(), ..quick() }).unwrap();
            let mut want: Vec<&str> = FACTS.iter().chain(group_fields(g)).copied().collect();
            want.sort_unstable();
            assert_eq!(keys(&p), want, "--only {}", g.name());
            let j = serde_json::to_value(&p).unwrap();
            for f in group_fields(g) {
                assert!(!j[f].is_null(), "--only {}: {f} is null", g.name());
                if let Some(x) = j[f].as_f64() {
                    assert!(x.is_finite() && x >= 0.0, "--only {}: {f} = {x}", g.name());
                }
            }
        }
    }

    #[test]
    fn groups_combine_and_an_empty_list_means_the_flags() {
        let p = measure_scene(&PerfOptions { groups: vec![PerfGroup::Grid, PerfGroup::Geodesic, PerfGroup::Grid], ..quick() }).unwrap();
        let mut want: Vec<&str> = FACTS.iter().chain(group_fields(PerfGroup::Grid)).chain(group_fields(PerfGroup::Geodesic)).copied().collect();
        want.sort_unstable();
        assert_eq!(keys(&p), want);
        positive("map_build_s", p.map_build_s.unwrap());
        // `--only sensors` renders depth when no sensor is given; the sensors flag's own
        // choice is kept otherwise.
        let o = PerfOptions { groups: vec![PerfGroup::Sensors], ..quick() };
        assert_eq!(o.rendered_sensors(), ["depth"]);
        let o = PerfOptions { sensors: vec!["depth".into(), "rgb".into()], ..o };
        assert_eq!(o.rendered_sensors(), ["depth", "rgb"]);
        // Without groups, the flags decide the sections, as before `--only` existed.
        let o = quick();
        assert!(o.runs(PerfGroup::Grid) && o.runs(PerfGroup::Geodesic) && o.runs(PerfGroup::Discrete));
        assert!(!o.runs(PerfGroup::Physics) && !o.runs(PerfGroup::Sensors) && !o.runs(PerfGroup::Amcl));
        assert!(o.rendered_sensors().is_empty());
        // A flag does not add its section to an explicit group list.
        let o = PerfOptions { groups: vec![PerfGroup::Grid], measure_physics: true, amcl: true, ..quick() };
        assert!(!o.runs(PerfGroup::Physics) && !o.runs(PerfGroup::Amcl) && !o.runs(PerfGroup::Discrete));
    }

    #[test]
    fn group_names_round_trip() {
        for g in PerfGroup::ALL {
            assert_eq!(PerfGroup::from_name(g.name()), Some(g));
            assert!(PerfGroup::NAMES.contains(&g.name()));
        }
        assert_eq!(PerfGroup::NAMES.len(), PerfGroup::ALL.len());
        assert_eq!(PerfGroup::from_name("gpu"), None);
    }

    #[test]
    fn bad_options_are_errors_naming_the_flag() {
        let e = |o: PerfOptions| measure_scene(&o).expect_err("should fail").to_string();
        assert_eq!(e(PerfOptions { seconds: 0.0, ..quick() }), "--seconds must be a positive number of seconds");
        assert_eq!(e(PerfOptions { seconds: f64::NAN, ..quick() }), "--seconds must be a positive number of seconds");
        assert_eq!(e(PerfOptions { sensors: vec!["lidar".into()], ..quick() }), "--sensors: unknown sensor 'lidar' (depth, rgb)");
        assert!(e(PerfOptions::new("/nonexistent/house.glb")).starts_with("loading scene /nonexistent/house.glb"));
        let robot = PhysicsOptions { robot: "no_such_robot".into(), ..Default::default() };
        assert!(e(PerfOptions { measure_physics: true, physics: robot, ..quick() }).starts_with("--robot no_such_robot"));
        let camera = CameraOptions { resolution: 0, ..Default::default() };
        assert!(e(PerfOptions { sensors: vec!["depth".into()], camera, ..quick() }).contains("--resolution"));
    }
}
