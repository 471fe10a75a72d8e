//! Building what a run needs from its options: the world of a SCENE argument (a file or
//! `procedural[:SEED]`), the floor, the robot and its physics, the renderer and the camera.
//!
//! The CLI and the Python package both call these, so both take the same inputs and fail
//! with the same messages. [`EnvSetup::build`] puts them together for one environment;
//! [`EnvSetup::run_config`] turns that into the runner's [`RunConfig`].

use crate::agents::AgentKind;
use crate::runner::{PhysicsSetup, RunConfig};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;
use xhab_sim::env::TaskConfig;
use xhab_sim::episode::{generate_episodes, read_dataset, Dataset, DatasetError, GenerateError, GeneratorParams};
use xhab_sim::navgrid::{AgentParams, NavGrid, NavGridError};
use xhab_sim::physics_env::PhysicsConfig;
use xhab_sim::robot::{PhysicsError, PhysicsScene, ProfileError, RobotProfile};
use xhab_sim::scene::{self, LoadOptions, Scene, SceneError, UpAxis};
use xhab_sim::sensors::{CameraParams, CameraRig, DepthNoise, RayScene, RenderError, Renderer, RendererKind};
use xhab_sim::world::World;
use xhab_types::{OccupancyGrid, Point3};

pub use xhab_nav::map_server::save_map;

/// Why an environment could not be set up. Each message names the argument as the CLI
/// spells it; the sources carry the details (print the chain, as `{:#}` does with anyhow).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SetupError {
    /// `procedural:SEED` with a seed that is not a whole number.
    #[error("bad scene '{0}': the seed after 'procedural:' must be a whole number")]
    ProceduralSeed(String),
    /// `--storeys` out of range.
    #[error("--storeys {0}: the procedural house has 1 to 16 storeys")]
    BadStoreys(usize),
    /// The scene file could not be loaded.
    #[error("loading scene {arg}")]
    Scene {
        /// The SCENE argument.
        arg: String,
        /// Why.
        #[source]
        source: SceneError,
    },
    /// The scene has no floor to walk on.
    #[error("scene {0}: no walkable floor found (is the up axis right? try --up-axis z)")]
    NoWalkableFloor(String),
    /// `auto` was asked for and the scene has no floor.
    #[error("the scene has no floor")]
    NoFloor,
    /// A floor that is neither `auto` nor a number.
    #[error("bad --floor '{0}': expected 'auto' or a height in metres")]
    BadFloor(String),
    /// No floor near the height asked for.
    #[error("no floor within 0.5 m of height {z} (floors at [{known}] m)")]
    NoFloorAt {
        /// The height asked for (m).
        z: f64,
        /// The floors' heights, comma-separated (m).
        known: String,
    },
    /// The navigation grid of a floor could not be built.
    #[error(transparent)]
    Grid(#[from] NavGridError),
    /// Episodes could not be generated.
    #[error("generating episodes in {scene}")]
    Generate {
        /// The SCENE argument.
        scene: String,
        /// Why.
        #[source]
        source: GenerateError,
    },
    /// The episodes file could not be read.
    #[error("reading episodes {path}")]
    Episodes {
        /// The file.
        path: String,
        /// Why.
        #[source]
        source: DatasetError,
    },
    /// A laser height outside the agent's body band.
    #[error("--laser-height {height}: must lie above the floor and below the agent height ({agent_height} m)")]
    BadLaserHeight {
        /// The height asked for (m).
        height: f64,
        /// The agent's height (m).
        agent_height: f64,
    },
    /// The robot profile could not be loaded.
    #[error("--robot {name}")]
    Robot {
        /// The profile's name or file.
        name: String,
        /// Why.
        #[source]
        source: ProfileError,
    },
    /// The scene's rigid mesh could not be built.
    #[error("building the physics world")]
    Physics(#[source] PhysicsError),
    /// Resolution or field of view out of range.
    #[error("bad camera: --resolution must be in 1..=4096 and --hfov in (0, 180)")]
    BadCamera,
    /// Camera height not a positive number.
    #[error("bad camera: --camera-height must be a positive number of metres")]
    BadCameraHeight,
    /// A sensor name other than `depth` and `rgb`.
    #[error("--sensors: unknown sensor '{0}' (depth, rgb)")]
    UnknownSensor(String),
    /// Depth noise out of range.
    #[error("--depth-noise must be >= 0 and --edge-dropout in [0, 1]")]
    BadNoise,
    /// The renderer could not be built.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The wgpu renderer asked for explicitly could not be built.
    #[error("--renderer wgpu: {0}")]
    Wgpu(RenderError),
    /// A map_server map could not be loaded.
    #[error("loading map {}", path.display())]
    Map {
        /// The YAML file.
        path: std::path::PathBuf,
        /// Why.
        #[source]
        source: xhab_nav::map_server::MapError,
    },
    /// The floor has no navigable point to start from.
    #[error("no navigable point in the scene")]
    NoNavigablePoint,
    /// The scene has no triangles for a lidar to hit.
    #[error("the scene has no triangles to scan")]
    NothingToScan,
}

/// How to read a scene and which agent its grids are built for (the CLI's `Scene` and
/// `Agent` options).
#[derive(Debug, Clone, PartialEq)]
pub struct SceneOptions {
    /// Up axis of OBJ/PLY files (glTF is always y up; default y).
    pub up_axis: UpAxis,
    /// Keep meshes named "ceiling" (default false: dropped).
    pub keep_ceilings: bool,
    /// Agent radius (m) [default: 0.1, or the robot's radius under physics].
    pub agent_radius: Option<f64>,
    /// Agent height (m, default 1.5).
    pub agent_height: f64,
    /// Cell size of the navigation grid (m, default 0.05).
    pub cell_size: f64,
    /// Storeys of the procedural house (default 1; more are joined by a stair hall).
    pub storeys: usize,
    /// Read the scene file's textures (default true): needed only to render RGB, and most
    /// of a textured scene's load time.
    pub textures: bool,
}

impl Default for SceneOptions {
    fn default() -> Self {
        Self { up_axis: UpAxis::Y, keep_ceilings: false, agent_radius: None, agent_height: 1.5, cell_size: 0.05, storeys: 1, textures: true }
    }
}

/// The built-in two-storey test building with one straight flight, whose geodesics are known
/// in closed form (`scene::stair_building`).
pub const STAIR_BUILDING: &str = "stair_building";

/// The seed of a `procedural[:SEED]` argument, or `None` for a file.
///
/// # Example
/// ```
/// use xhab_bridge::setup::procedural_seed;
/// assert_eq!(procedural_seed("procedural").unwrap(), Some(0));
/// assert_eq!(procedural_seed("procedural:7").unwrap(), Some(7));
/// assert_eq!(procedural_seed("house.glb").unwrap(), None);
/// assert!(procedural_seed("procedural:x").is_err());
/// ```
pub fn procedural_seed(arg: &str) -> Result<Option<u64>, SetupError> {
    if arg == "procedural" {
        return Ok(Some(0));
    }
    if let Some(s) = arg.strip_prefix("procedural:") {
        return s.parse().map(Some).map_err(|_| SetupError::ProceduralSeed(arg.to_string()));
    }
    Ok(None)
}

/// Loads the scene named by `arg`: a `.glb`/`.gltf`/`.obj`/`.ply` file, `procedural[:SEED]`
/// (with `opts.storeys` storeys) or [`STAIR_BUILDING`].
pub fn load_scene(arg: &str, opts: &SceneOptions) -> Result<Scene, SetupError> {
    if opts.storeys == 0 || opts.storeys > 16 {
        return Err(SetupError::BadStoreys(opts.storeys));
    }
    if let Some(seed) = procedural_seed(arg)? {
        return Ok(scene::house::generate_house(seed, &scene::house::HouseParams { storeys: opts.storeys, ..Default::default() }));
    }
    if arg == STAIR_BUILDING {
        return Ok(scene::stair_building::stair_building(&Default::default()));
    }
    let load = LoadOptions { up_axis: opts.up_axis, drop_ceilings: !opts.keep_ceilings, textures: opts.textures };
    scene::load(Path::new(arg), &load).map_err(|source| SetupError::Scene { arg: arg.to_string(), source })
}

/// The agent the navigation grids are built for (radius 0.1 m unless given).
pub fn agent_params(opts: &SceneOptions) -> AgentParams {
    AgentParams { radius: opts.agent_radius.unwrap_or(0.1), height: opts.agent_height, cell_size: opts.cell_size, ..Default::default() }
}

/// Loads the scene and wraps it in a world; fails when no floor is found.
pub fn load_world(arg: &str, opts: &SceneOptions) -> Result<World, SetupError> {
    let scene = load_scene(arg, opts)?;
    let world = World::new(scene, agent_params(opts));
    if world.floors.is_empty() {
        return Err(SetupError::NoWalkableFloor(arg.to_string()));
    }
    Ok(world)
}

/// [`load_world`] without the scene file's textures, for what reads no colour (maps,
/// geodesics, episodes, scans, depth): decoding them is most of a textured scene's load.
pub fn load_geometry(arg: &str, opts: &SceneOptions) -> Result<World, SetupError> {
    load_world(arg, &SceneOptions { textures: false, ..opts.clone() })
}

/// The floor index for a floor argument: `auto` (the lowest), a storey number `N` (a whole
/// number below the number of storeys, lowest 0) or a height in metres (Habitat's y, our z).
pub fn floor_index(world: &World, floor: &str) -> Result<usize, SetupError> {
    if floor == "auto" {
        return world.default_floor().ok_or(SetupError::NoFloor);
    }
    if let Ok(n) = floor.parse::<usize>() {
        if n < world.floors.len() {
            return Ok(n);
        }
    }
    let z: f64 = floor.parse().map_err(|_| SetupError::BadFloor(floor.to_string()))?;
    world.floor_at(z).ok_or_else(|| {
        let known: Vec<String> = world.floors.iter().map(|f| format!("{:.2}", f.z)).collect();
        SetupError::NoFloorAt { z, known: known.join(", ") }
    })
}

/// Generates `count` PointNav episodes with Habitat's rules on the floor `floor` (`auto` or a
/// height) of the world loaded from `scene`; `scene_id` goes into each episode.
pub fn generate(world: &World, scene: &str, floor: &str, count: usize, seed: u64, scene_id: &str) -> Result<Dataset, SetupError> {
    let i = floor_index(world, floor)?;
    let grid = world.grid(i)?;
    generate_episodes(&grid, scene_id, count, seed, &GeneratorParams::default()).map_err(|source| SetupError::Generate { scene: scene.to_string(), source })
}

/// Generates `count` PointNav episodes whose start and goal stand on different storeys joined
/// by stairs (`xhab episodes --cross-floor`), with Habitat's other rules.
pub fn generate_cross_floor(world: &World, scene: &str, count: usize, seed: u64, scene_id: &str) -> Result<Dataset, SetupError> {
    xhab_sim::episode::generate_cross_storey_episodes(world, scene_id, count, seed, &GeneratorParams::default())
        .map_err(|source| SetupError::Generate { scene: scene.to_string(), source })
}

/// Reads a Habitat PointNav episodes file (`.json.gz` or `.json`).
pub fn read_episodes(path: &Path) -> Result<Dataset, SetupError> {
    read_dataset(path).map_err(|source| SetupError::Episodes { path: path.display().to_string(), source })
}

/// The map of a floor's grid as `xhab map` makes it: what the agent's body band hits, or with
/// `laser_height` (m above the floor) what a planar laser at that height sees.
pub fn floor_map(world: &World, grid: &NavGrid, laser_height: Option<f64>) -> Result<OccupancyGrid, SetupError> {
    Ok(match laser_height {
        Some(h) if !(h.is_finite() && h > 0.0 && h < grid.params.height) => return Err(SetupError::BadLaserHeight { height: h, agent_height: grid.params.height }),
        Some(h) => grid.slice_map(&world.scene, h, crate::nav_agent::SCAN_PLANE_HALF_BAND),
        None => grid.occupancy_grid(),
    })
}

/// Loads a map_server map (its YAML file and the image it names).
pub fn load_static_map(path: &Path) -> Result<OccupancyGrid, SetupError> {
    xhab_nav::map_server::load_map(path).map(|(map, _)| map).map_err(|source| SetupError::Map { path: path.to_path_buf(), source })
}

/// The scene's triangles for ray casting (lidar scans); fails on a scene without any.
pub fn ray_scene(scene: &Scene) -> Result<RayScene, SetupError> {
    RayScene::new(scene).ok_or(SetupError::NothingToScan)
}

/// A map that could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteMapError {
    /// The folder could not be created.
    #[error("creating folder {}", path.display())]
    Folder {
        /// The folder.
        path: std::path::PathBuf,
        /// Why.
        #[source]
        source: std::io::Error,
    },
    /// The map_server files could not be written.
    #[error("writing map {}", path.display())]
    Map {
        /// The YAML file.
        path: std::path::PathBuf,
        /// Why.
        #[source]
        source: xhab_nav::map_server::MapError,
    },
    /// The picture could not be written.
    #[error(transparent)]
    Picture(#[from] crate::map_picture::PictureError),
}

/// Writes `OUT.yaml` + `OUT.pgm` (map_server) and the picture `OUT.png` of `map`, creating
/// the folder; returns the YAML and PNG paths. What `xhab map` and `xhab.make_map` write.
pub fn write_map(map: &OccupancyGrid, out: &Path) -> Result<(std::path::PathBuf, std::path::PathBuf), WriteMapError> {
    if let Some(d) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(d).map_err(|source| WriteMapError::Folder { path: d.to_path_buf(), source })?;
    }
    let with_ext = |ext: &str| {
        let mut s = out.as_os_str().to_owned();
        s.push(".");
        s.push(ext);
        std::path::PathBuf::from(s)
    };
    let (yaml, png) = (with_ext("yaml"), with_ext("png"));
    save_map(map, &yaml).map_err(|source| WriteMapError::Map { path: yaml.clone(), source })?;
    crate::map_picture::MapPicture::new(map).save(&png)?;
    Ok((yaml, png))
}

/// Writes every storey's map as `OUT_floorN` (map_server YAML + PGM, and a picture) and a
/// picture of all storeys side by side as `OUT.png`; returns the YAML files, lowest storey
/// first. What `xhab map --floor all` writes.
pub fn write_storey_maps(world: &World, out: &Path, laser_height: Option<f64>) -> Result<Vec<std::path::PathBuf>, WriteStoreyMapsError> {
    let mut maps = Vec::new();
    let mut yamls = Vec::new();
    for k in 0..world.floors.len() {
        let grid = world.grid(k).map_err(|e| WriteStoreyMapsError::Setup(e.into()))?;
        let map = floor_map(world, &grid, laser_height).map_err(WriteStoreyMapsError::Setup)?;
        let mut name = out.as_os_str().to_owned();
        name.push(format!("_floor{k}"));
        let (yaml, _) = write_map(&map, Path::new(&name))?;
        yamls.push(yaml);
        maps.push(map);
    }
    let mut png = out.as_os_str().to_owned();
    png.push(".png");
    crate::map_picture::save_side_by_side(&maps, Path::new(&png)).map_err(WriteMapError::from)?;
    Ok(yamls)
}

/// Why `xhab map --floor all` could not write its maps.
#[derive(Debug, thiserror::Error)]
pub enum WriteStoreyMapsError {
    /// A storey's map could not be made.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// A file could not be written.
    #[error(transparent)]
    Write(#[from] WriteMapError),
}

/// A geodesic distance query between two points and what decided it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeodesicQuery {
    /// Geodesic distance of the disc agent (m); infinite across islands or floors, or when
    /// either end is not navigable.
    pub distance: f64,
    /// Whether the start is navigable for the agent.
    pub from_navigable: bool,
    /// Whether the goal is navigable for the agent.
    pub to_navigable: bool,
    /// Whether both ends are on one floor (within 0.5 m).
    pub same_floor: bool,
}

/// The geodesic distance from `from` to `to` (world frame, m) on the floor of `from`.
pub fn geodesic(world: &World, from: Point3, to: Point3) -> Result<GeodesicQuery, NavGridError> {
    let grid = world.grid_at(from.z)?;
    let same_floor = (to.z - from.z).abs() <= xhab_sim::world::FLOOR_MATCH;
    let from_navigable = grid.is_navigable(from.xy());
    let to_navigable = grid.is_navigable(to.xy());
    let distance = if same_floor && from_navigable && to_navigable {
        xhab_sim::geodesic::geodesic_distance(&grid, from.xy(), to.xy())
    } else {
        f64::INFINITY
    };
    Ok(GeodesicQuery { distance, from_navigable, to_navigable, same_floor })
}

/// A robot profile by built-in name or YAML file.
pub fn robot_profile(name: &str) -> Result<RobotProfile, SetupError> {
    RobotProfile::named_or_file(name).map_err(|source| SetupError::Robot { name: name.to_string(), source })
}

/// The physics mode's options (the CLI's `Physics` options without the switch).
#[derive(Debug, Clone, PartialEq)]
pub struct PhysicsOptions {
    /// Robot profile: habitat, locobot, turtlebot3_burger, turtlebot3_waffle, or a .yaml file
    /// (default habitat).
    pub robot: String,
    /// Seconds each discrete action's velocities are held (s, default 1; T of Algorithm 1).
    pub control_period: f64,
    /// Physics steps per simulated second (Hz, default 60).
    pub steps_per_sec: f64,
}

impl Default for PhysicsOptions {
    fn default() -> Self {
        Self { robot: "habitat".into(), control_period: 1.0, steps_per_sec: 60.0 }
    }
}

impl PhysicsOptions {
    /// The physics settings of these options: the control period and the physics rate, the
    /// rest (gravity, odometry noise, stuck detection) at their defaults.
    pub fn config(&self) -> PhysicsConfig {
        PhysicsConfig {
            control_period: self.control_period,
            physics: xhab_sim::robot::PhysicsParams { steps_per_sec: self.steps_per_sec, ..Default::default() },
            ..Default::default()
        }
    }
}

/// The physics setup: the robot, the scene's rigid mesh (shared by every episode) and the
/// settings.
pub fn physics_setup(world: &World, o: &PhysicsOptions) -> Result<PhysicsSetup, SetupError> {
    let profile = robot_profile(&o.robot)?;
    let t = Instant::now();
    let scene = PhysicsScene::new(&world.scene).map_err(SetupError::Physics)?;
    tracing::info!("physics mesh built in {:.3} s", t.elapsed().as_secs_f64());
    Ok(PhysicsSetup { scene: Arc::new(scene), profile, config: o.config() })
}

/// The camera's options (the CLI's `Camera` options).
#[derive(Debug, Clone, PartialEq)]
pub struct CameraOptions {
    /// The renderer; `None` is `auto` (wgpu on a real GPU, else the CPU rasteriser).
    pub renderer: Option<RendererKind>,
    /// Image width and height (px, default 256).
    pub resolution: usize,
    /// Horizontal field of view (degrees, default 90).
    pub hfov: f64,
    /// Camera height above the floor (m) [default: the robot profile's under physics, else
    /// 1.25, Habitat's agent].
    pub camera_height: Option<f64>,
}

impl Default for CameraOptions {
    fn default() -> Self {
        Self { renderer: None, resolution: 256, hfov: 90.0, camera_height: None }
    }
}

/// Camera parameters from the options; the camera height, or else `default_height` (m).
pub fn camera_params(o: &CameraOptions, default_height: f64) -> Result<CameraParams, SetupError> {
    if o.resolution == 0 || o.resolution > 4096 || !(o.hfov > 0.0 && o.hfov < 180.0) {
        return Err(SetupError::BadCamera);
    }
    let mount_height = o.camera_height.unwrap_or(default_height);
    if !(mount_height.is_finite() && mount_height > 0.0) {
        return Err(SetupError::BadCameraHeight);
    }
    Ok(CameraParams { width: o.resolution, height: o.resolution, hfov_deg: o.hfov, mount_height, ..Default::default() })
}

/// The renderer asked for (`None`: auto), built for `scene`, and a note on which it is and
/// why (e.g. ` (auto: no GPU renderer: ...)`) for a log line after its name.
pub fn build_renderer(kind: Option<RendererKind>, scene: &Scene) -> Result<(Renderer, String), SetupError> {
    Ok(match kind {
        None => {
            let (r, why) = Renderer::auto(scene)?;
            (r, format!(" (auto: {why})"))
        }
        Some(RendererKind::Wgpu) => {
            let r = Renderer::new(RendererKind::Wgpu, scene).map_err(SetupError::Wgpu)?;
            let info = match &r {
                Renderer::Wgpu(g) => format!(" ({})", g.adapter_info()),
                _ => String::new(),
            };
            (r, info)
        }
        Some(k) => (Renderer::new(k, scene)?, String::new()),
    })
}

/// Whether the sensors named (`depth`, `rgb`) include RGB; fails on any other name.
pub fn parse_sensors<S: AsRef<str>>(names: &[S]) -> Result<bool, SetupError> {
    let mut rgb = false;
    for s in names {
        match s.as_ref() {
            "depth" => {}
            "rgb" => rgb = true,
            other => return Err(SetupError::UnknownSensor(other.to_string())),
        }
    }
    Ok(rgb)
}

/// The depth noise: standard deviation at 1 m (m, growing with depth squared) and the
/// probability that a pixel on a depth edge reads no return (both 0 = off).
pub fn depth_noise(sigma_at_1m: f64, edge_dropout: f64) -> Result<DepthNoise, SetupError> {
    if !(sigma_at_1m >= 0.0 && sigma_at_1m.is_finite()) || !(0.0..=1.0).contains(&edge_dropout) {
        return Err(SetupError::BadNoise);
    }
    Ok(DepthNoise { sigma_at_1m, edge_threshold: 0.1, edge_dropout })
}

/// Everything one environment needs, as the CLI's `bench` options give it.
#[derive(Debug, Clone)]
pub struct EnvOptions {
    /// The SCENE argument: a file or `procedural[:SEED]`.
    pub scene: String,
    /// How to read it and the agent's size.
    pub scene_options: SceneOptions,
    /// Physics (Algorithm 1 under rapier3d), or teleport-and-slide when `None`.
    pub physics: Option<PhysicsOptions>,
    /// Camera images every observation carries: empty, `depth`, or `depth` and `rgb`.
    pub sensors: Vec<String>,
    /// The camera.
    pub camera: CameraOptions,
    /// Depth noise at 1 m (m, default 0: off).
    pub depth_noise: f64,
    /// Depth edge dropout probability (default 0: off).
    pub edge_dropout: f64,
    /// The task (step sizes, step limit, success radius).
    pub task: TaskConfig,
}

impl EnvOptions {
    /// Options for `scene` with every default: no physics, no camera, Habitat's task.
    pub fn new(scene: impl Into<String>) -> Self {
        Self {
            scene: scene.into(),
            scene_options: SceneOptions::default(),
            physics: None,
            sensors: Vec::new(),
            camera: CameraOptions::default(),
            depth_noise: 0.0,
            edge_dropout: 0.0,
            task: TaskConfig::default(),
        }
    }
}

/// A loaded environment: the world, physics and camera, shared by every episode and thread.
#[derive(Debug, Clone)]
pub struct EnvSetup {
    /// The SCENE argument.
    pub scene: String,
    /// The world (grids built on first use).
    pub world: Arc<World>,
    /// Physics, if asked for.
    pub physics: Option<PhysicsSetup>,
    /// The camera, if any sensor was asked for.
    pub sensors: Option<Arc<CameraRig>>,
    /// The task.
    pub task: TaskConfig,
    /// Which renderer the camera uses and why, e.g. `raster (auto: no GPU renderer: ...)`.
    pub renderer_note: Option<String>,
}

impl EnvSetup {
    /// Loads the scene and builds physics and camera as `xhab bench` does: under physics the
    /// grids are built for the robot's radius (unless one is given) and the camera sits at
    /// the robot's camera height.
    pub fn build(o: &EnvOptions) -> Result<EnvSetup, SetupError> {
        let mut scene_options = o.scene_options.clone();
        if let Some(p) = &o.physics {
            if scene_options.agent_radius.is_none() {
                scene_options.agent_radius = Some(robot_profile(&p.robot)?.radius);
            }
        }
        let rgb = parse_sensors(&o.sensors)?;
        // Without an RGB camera nothing reads a colour: the textures are left unread.
        scene_options.textures &= rgb;
        let world = load_world(&o.scene, &scene_options)?;
        let physics = o.physics.as_ref().map(|p| physics_setup(&world, p)).transpose()?;
        let noise = depth_noise(o.depth_noise, o.edge_dropout)?;
        let (sensors, renderer_note) = if o.sensors.is_empty() {
            (None, None)
        } else {
            let camera_height = physics.as_ref().map_or(CameraParams::default().mount_height, |p| p.profile.camera_height);
            let params = camera_params(&o.camera, camera_height)?;
            let (renderer, why) = build_renderer(o.camera.renderer, &world.scene)?;
            let note = format!("{}{why}", renderer.name());
            (Some(Arc::new(CameraRig { renderer: Arc::new(renderer), params, rgb, noise })), Some(note))
        };
        Ok(EnvSetup { scene: o.scene.clone(), world: Arc::new(world), physics, sensors, task: o.task.clone(), renderer_note })
    }

    /// The runner's configuration for this setup with a discrete agent (`agent` names the
    /// built-in one `run_dataset` would build; `run_dataset_with` ignores it).
    pub fn run_config(&self, agent: AgentKind, threads: usize, seed: u64) -> RunConfig {
        RunConfig {
            agent,
            task: self.task.clone(),
            threads: threads.max(1),
            record_trajectories: false,
            physics: self.physics.clone(),
            seed,
            nav: None,
            sensors: self.sensors.clone(),
            episode_indices: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(r: Result<impl std::fmt::Debug, SetupError>) -> String {
        r.expect_err("should fail").to_string()
    }

    #[test]
    fn messages_name_the_argument() {
        assert_eq!(err(procedural_seed("procedural:-1")), "bad scene 'procedural:-1': the seed after 'procedural:' must be a whole number");
        assert_eq!(err(parse_sensors(&["depth", "lidar"])), "--sensors: unknown sensor 'lidar' (depth, rgb)");
        assert_eq!(err(depth_noise(-1.0, 0.0)), "--depth-noise must be >= 0 and --edge-dropout in [0, 1]");
        assert_eq!(err(camera_params(&CameraOptions { resolution: 0, ..Default::default() }, 1.0)), "bad camera: --resolution must be in 1..=4096 and --hfov in (0, 180)");
        assert!(err(load_world("/nonexistent/house.glb", &SceneOptions::default())).starts_with("loading scene /nonexistent/house.glb"));
    }

    #[test]
    fn an_environment_reads_the_textures_only_for_an_rgb_camera() {
        use xhab_sim::scene::{Texture, Wrap};
        let mut scene = scene::house::generate_house(2, &Default::default());
        let m = &mut scene.meshes[0];
        m.uvs = vec![[0.5, 0.5]; m.positions.len()];
        m.texture = Some(0);
        scene.textures.push(Texture { name: "grey".into(), width: 1, height: 1, rgba: std::sync::Arc::new(vec![128, 128, 128, 255]), wrap_s: Wrap::Repeat, wrap_t: Wrap::Repeat });
        let dir = std::env::temp_dir().join(format!("xhab_setup_textures_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("house.glb");
        scene::write_glb(&scene, &path).unwrap();
        let textures = |sensors: &[&str]| {
            let mut o = EnvOptions::new(path.to_string_lossy());
            o.sensors = sensors.iter().map(|s| s.to_string()).collect();
            EnvSetup::build(&o).unwrap().world.scene.textures.len()
        };
        assert_eq!(textures(&[]), 0);
        assert_eq!(textures(&["depth"]), 0);
        assert_eq!(textures(&["depth", "rgb"]), 1);
        assert_eq!(load_scene(&path.to_string_lossy(), &SceneOptions::default()).unwrap().textures.len(), 1);
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn procedural_world_has_a_floor_and_episodes() {
        let w = load_world("procedural:1", &SceneOptions::default()).unwrap();
        assert_eq!(floor_index(&w, "auto").unwrap(), 0);
        assert!(err(floor_index(&w, "x")).contains("bad --floor 'x'"));
        let ds = generate(&w, "procedural:1", "auto", 3, 0, "procedural:1").unwrap();
        assert_eq!(ds.episodes.len(), 3);
        let e = &ds.episodes[0];
        let q = geodesic(&w, e.start_position, e.goals[0].position).unwrap();
        assert!((q.distance - e.geodesic_distance.unwrap()).abs() < 1e-9);
    }
}
