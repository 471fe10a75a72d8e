//! Command-line arguments (clap derive). Parsing only: the commands live in `cmd/`.

use clap::{Args, Parser, Subcommand, ValueEnum};
use std::path::PathBuf;
use xhab_nav::ros_params::ParamFile;

/// `--nav-params`, short help.
const NAV_PARAMS_HELP: &str = "Navigation parameters: ROS 1 YAML as move_base and amcl read it, or a Nav2 params file, FILE[@NAMESPACE], repeatable";

/// `--nav-params`, long help.
const NAV_PARAMS_LONG_HELP: &str = "Navigation parameters: ROS 1 YAML as move_base and amcl read it, FILE[@NAMESPACE], repeatable.

Files are layered as roslaunch's <rosparam file=FILE ns=NAMESPACE> loads them: later files override single keys of earlier ones. Keys use ROS's names in move_base's private namespace (its own names, global_costmap/, local_costmap/, DWAPlannerROS/, GlobalPlanner/ or NavfnROS/) and amcl's (amcl/, or at the top). Keys xhab does not use are warned about, never rejected; wrong types and values out of range are errors naming the file and key. A costmap whose shape the files do not give (footprint, robot_radius) takes the robot's.

Nav2 (ROS 2) params files are read too, with no other option: a file whose top-level values hold ros__parameters (controller_server, planner_server, global_costmap/global_costmap, local_costmap/local_costmap, amcl, ...) is read by Nav2's names (DWB's FollowPath, the goal and progress checkers, NavFn's GridBased, the costmap layers) where xhab has the concept, and layered with the other files in order; @NAMESPACE then keeps only the nodes under that namespace. The same rules hold: unknown names are warnings with the nearest Nav2 name, bad values are errors naming the file and the node/parameter key.

Example (TurtleBot3's files, as move_base.launch loads them):
  --nav-params costmap_common_params_burger.yaml@global_costmap
  --nav-params costmap_common_params_burger.yaml@local_costmap
  --nav-params local_costmap_params.yaml --nav-params global_costmap_params.yaml
  --nav-params move_base_params.yaml --nav-params dwa_local_planner_params_burger.yaml";

/// xhab: Habitat-style PointNav benchmarks, maps from 3D scenes, and ROS interop, without Habitat.
///
/// SCENE is a scene file (.glb, .gltf, .obj, .ply) or `procedural[:SEED]` for the built-in
/// procedural house (seed 0 by default).
///
/// Exit codes: 0 success, 1 ran but a check failed, 2 error.
#[derive(Debug, Parser)]
#[command(name = "xhab", version, about, long_about = None)]
pub struct Cli {
    /// Print less (no progress bars).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// The command.
    #[command(subcommand)]
    pub command: Command,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Generate the procedural house, its map and episodes, run the oracle, print the metrics.
    Demo(DemoArgs),
    /// Write a ROS map_server map (NAME.yaml + NAME.pgm) and a picture (NAME.png) of a scene.
    Map(MapArgs),
    /// Generate PointNav episodes with Habitat's rules (gzipped Habitat JSON).
    Episodes(EpisodesArgs),
    /// Print the geodesic distance between two points (Habitat frame, metres).
    Geodesic(GeodesicArgs),
    /// Run an agent on every episode of a dataset and write the metrics as JSON.
    Bench(BenchArgs),
    /// Measure speed on a scene and print the figures (JSON with --json).
    Perf(PerfArgs),
    /// Run the native navigation stack once from a start to a goal and draw it.
    Navigate(NavigateArgs),
    /// Render the depth and RGB images seen from a pose, side by side, as PNG.
    Render(RenderArgs),
    /// Scene tools.
    #[command(subcommand)]
    Scene(SceneCommand),
    /// Global localisation trials: AMCL from a uniform spread while the robot drives.
    Localize(LocalizeArgs),
    /// ROS 1 nodes: the simulator, the native navigation stack, a discrete agent.
    #[command(subcommand)]
    Ros(RosCommand),
    /// ROS 2 nodes (DDS, pure Rust: no ROS installation needed): the simulator.
    #[command(subcommand)]
    Ros2(Ros2Command),
    /// Run a study from a YAML file (scenes x agents x ±physics ±ROS x seeds): per-run bench
    /// reports, results.json/.csv and an HTML report; resumable, shardable, or on SLURM.
    Experiment(ExperimentArgs),
    /// Merge the shards of a study (`experiment --shard K/N` folders) into one result and report.
    Merge(MergeArgs),
    /// Write the HTML report of a study folder (DIR/report/index.html).
    Report(ReportArgs),
}

/// `xhab experiment`.
#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// The study (YAML; see examples/four_configurations.yaml).
    pub spec: PathBuf,
    /// Folder for parts, per-run reports, results and the report [default: results/NAME].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run only shard K of N (1-based) of the runs x episodes; `xhab merge` combines them.
    #[arg(long, value_name = "K/N", conflicts_with = "slurm")]
    pub shard: Option<xhab_experiment::Shard>,
    /// Submit the study as a SLURM array job (one shard per task) plus a merge job.
    #[arg(long)]
    pub slurm: bool,
    /// Shards (array tasks) for --slurm.
    #[arg(long, default_value_t = 4, requires = "slurm")]
    pub shards: usize,
    /// SLURM partition for --slurm.
    #[arg(long, requires = "slurm")]
    pub partition: Option<String>,
    /// SLURM time limit per task for --slurm (e.g. 1:00:00).
    #[arg(long, requires = "slurm")]
    pub time: Option<String>,
    /// Skip the HTML report.
    #[arg(long)]
    pub no_report: bool,
}

/// `xhab merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Folders of the study's shards.
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Where the merged results go [default: the first folder].
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Skip the HTML report.
    #[arg(long)]
    pub no_report: bool,
}

/// `xhab report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// A study folder (with results.json).
    pub dir: PathBuf,
}

/// `xhab localize`.
#[derive(Debug, Args)]
pub struct LocalizeArgs {
    /// The scene.
    #[arg(long)]
    pub scene: String,
    /// Episodes whose starts the trials use (Habitat PointNav .json.gz).
    #[arg(long)]
    pub episodes: PathBuf,
    /// Number of trials.
    #[arg(long, default_value_t = 50)]
    pub trials: usize,
    /// Seed of trial i is SEED + i.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Convergence tolerance (m).
    #[arg(long, default_value_t = 0.2)]
    pub tolerance: f64,
    /// Travel budget (m).
    #[arg(long, default_value_t = 10.0)]
    pub max_travel: f64,
    /// The map AMCL localises on (map_server YAML) [default: the scene cut at the lidar's
    /// height, as `xhab map --laser-height` makes it].
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// `--nav-params`: ROS parameter files, layered.
    #[arg(long, value_name = "FILE[@NAMESPACE]", help = NAV_PARAMS_HELP, long_help = NAV_PARAMS_LONG_HELP)]
    pub nav_params: Vec<ParamFile>,
    /// Particles spread over the free space at the start (sets amcl max_particles for the
    /// trials; KLD sampling shrinks the set as the filter converges). A uniform spread needs
    /// far more than tracking does: with ROS's 5,000 most trials start with no particle near
    /// the truth.
    #[arg(long, default_value_t = 50_000)]
    pub particles: usize,
    /// JSON results file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub physics: PhysicsOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab ros ...` (parsed once per run: the variants' size difference costs nothing).
#[derive(Debug, Subcommand)]
#[allow(clippy::large_enum_variant)]
pub enum RosCommand {
    /// The simulator as a ROS node (scan, odom, tf, clock, camera, map, ground truth; cmd_vel or action in).
    Sim(RosSimArgs),
    /// The native navigation stack as a move_base-compatible node.
    Nav(RosNavArgs),
    /// A discrete Habitat-style agent node (ground truth and goal in, action out).
    Agent(RosAgentArgs),
}

/// Options every ROS node takes.
#[derive(Debug, Clone, Args)]
pub struct RosOpts {
    /// The ROS master (http://HOST:PORT) [default: $ROS_MASTER_URI, else start `rosmaster`].
    #[arg(long, value_name = "URI", help_heading = "ROS")]
    pub ros_master: Option<String>,
    /// Node name.
    #[arg(long, help_heading = "ROS")]
    pub name: Option<String>,
    /// Lock-step: wait for the peer's reply at each step.
    #[arg(long, help_heading = "ROS")]
    pub lockstep: bool,
    /// Seconds to wait for a peer in lock-step before failing.
    #[arg(long, default_value_t = 30.0, help_heading = "ROS")]
    pub ros_timeout: f64,
    /// ROS arguments as rosrun and roslaunch pass them: remappings `from:=to`, `__ns:=NS`,
    /// `__name:=NAME` (`$ROS_NAMESPACE` is honoured too; `__log:=` and the like are ignored).
    #[arg(value_name = "FROM:=TO", help_heading = "ROS")]
    pub ros_args: Vec<String>,
}

/// What `xhab ros sim` and `xhab ros2 sim` simulate and publish.
#[derive(Debug, Args)]
pub struct SimNodeArgs {
    /// The scene (glTF/GLB, OBJ, PLY, or procedural[:SEED]).
    pub scene: String,
    /// Map to publish on `map` (map_server YAML) [default: the scene's own map].
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// Map to publish on `amcl/map`, the one to localise on (map_server YAML) [default without
    /// --map: the scene cut at the lidar's height, as `xhab map --laser-height`; with --map:
    /// none].
    #[arg(long)]
    pub amcl_map: Option<PathBuf>,
    /// Start pose X,Y,YAW (world frame) [default: a random navigable point from --seed].
    #[arg(long)]
    pub start: Option<String>,
    /// Publish the depth camera (and RGB with --rgb).
    #[arg(long)]
    pub camera: bool,
    /// Also publish RGB images.
    #[arg(long)]
    pub rgb: bool,
    /// The camera (renderer, resolution, field of view, height; --batch does not apply).
    #[command(flatten)]
    pub cam: CameraOpts,
    /// Depth noise: standard deviation at 1 m (m), growing with depth squared (0 = off).
    #[arg(long, default_value_t = 0.0)]
    pub depth_noise: f64,
    /// Probability that a pixel on a depth edge (jump > 0.1 m) reads 0 (0 = off).
    #[arg(long, default_value_t = 0.0)]
    pub edge_dropout: f64,
    /// Simulated seconds per wall second (0: as fast as possible).
    #[arg(long, default_value_t = 1.0)]
    pub rate: f64,
    /// Period of the state loop (s).
    #[arg(long, default_value_t = 0.05)]
    pub period: f64,
    /// Stop after this much simulated time (s).
    #[arg(long)]
    pub duration: Option<f64>,
    /// Seed of the start pose and noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Who publishes map -> odom: a localiser of the stack's, or the simulator from ground
    /// truth (as fake_localization, for stacks without one).
    #[arg(long, value_enum, default_value_t = MapOdomArg::Stack)]
    pub map_odom: MapOdomArg,
    #[command(flatten)]
    pub physics: PhysicsOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab ros sim`.
#[derive(Debug, Args)]
pub struct RosSimArgs {
    #[command(flatten)]
    pub sim: SimNodeArgs,
    #[command(flatten)]
    pub ros: RosOpts,
}

/// `xhab ros2 ...`.
#[derive(Debug, Subcommand)]
pub enum Ros2Command {
    /// The simulator as a ROS 2 node (scan, odom, /tf, /tf_static, /clock, camera, map,
    /// ground truth; cmd_vel or action in), with Nav2's QoS.
    Sim(Ros2SimArgs),
    /// The native navigation stack as a ROS 2 node with Nav2's names (`goal_pose`,
    /// `initialpose`, `amcl_pose`; cmd_vel and tf map -> odom out).
    Nav(Ros2NavArgs),
    /// A discrete Habitat-style agent node, the oracle (ground_truth/pose and goal_pose in,
    /// action out).
    Agent(Ros2AgentArgs),
}

/// `xhab ros2 agent`.
#[derive(Debug, Args)]
pub struct Ros2AgentArgs {
    /// The scene (the oracle's privileged knowledge: its grid and geodesics).
    pub scene: String,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
    #[command(flatten)]
    pub ros2: Ros2Opts,
}

/// Options every ROS 2 node takes. The DDS domain is `$ROS_DOMAIN_ID`; discovery stays on
/// this host with `ROS_LOCALHOST_ONLY=1` or `ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST`.
#[derive(Debug, Clone, Args)]
pub struct Ros2Opts {
    /// Node name.
    #[arg(long, help_heading = "ROS 2")]
    pub name: Option<String>,
    /// Lock-step: `sim` waits for one command per cycle; `nav` and `agent` answer each
    /// `xhab/step` of xhab's simulator on `xhab/step_reply` (as in `xhab bench --ros2`).
    #[arg(long, help_heading = "ROS 2")]
    pub lockstep: bool,
    /// Seconds to wait for a command in lock-step before failing.
    #[arg(long, default_value_t = 30.0, help_heading = "ROS 2")]
    pub ros_timeout: f64,
    /// ROS 2 arguments, last on the line: `--ros-args -r FROM:=TO -r __ns:=/NS -r __node:=NAME`
    /// (`-p NAME:=VALUE` is accepted and ignored; `$ROS_NAMESPACE` is honoured too).
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS", help_heading = "ROS 2")]
    pub ros_args: Option<Vec<String>>,
}

/// `xhab ros2 sim`.
#[derive(Debug, Args)]
pub struct Ros2SimArgs {
    #[command(flatten)]
    pub sim: SimNodeArgs,
    #[command(flatten)]
    pub ros2: Ros2Opts,
}

/// What `xhab ros nav` and `xhab ros2 nav` run.
#[derive(Debug, Args)]
pub struct NavNodeArgs {
    /// The static map (map_server YAML) [default: the map received on `map`].
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// The map AMCL localises on, e.g. `xhab map --laser-height` [default: the one received on
    /// `amcl/map`, else the navigation map].
    #[arg(long)]
    pub amcl_map: Option<PathBuf>,
    /// Localisation.
    #[arg(long, value_enum, default_value_t = LocalizationArg::Amcl)]
    pub localization: LocalizationArg,
    /// `--nav-params`: ROS parameter files, layered.
    #[arg(long, value_name = "FILE[@NAMESPACE]", help = NAV_PARAMS_HELP, long_help = NAV_PARAMS_LONG_HELP)]
    pub nav_params: Vec<ParamFile>,
    /// Robot profile whose size the costmaps take where the parameter files give no
    /// footprint or robot_radius: habitat, locobot, turtlebot3_burger, turtlebot3_waffle, or a .yaml file.
    #[arg(long, default_value = "habitat")]
    pub robot: String,
    /// Seed of AMCL.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
}

/// `xhab ros nav`.
#[derive(Debug, Args)]
pub struct RosNavArgs {
    #[command(flatten)]
    pub nav: NavNodeArgs,
    #[command(flatten)]
    pub ros: RosOpts,
}

/// `xhab ros2 nav`.
#[derive(Debug, Args)]
pub struct Ros2NavArgs {
    #[command(flatten)]
    pub nav: NavNodeArgs,
    #[command(flatten)]
    pub ros2: Ros2Opts,
}

/// `xhab ros agent`.
#[derive(Debug, Args)]
pub struct RosAgentArgs {
    /// The scene (the oracle's privileged knowledge: its grid and geodesics).
    pub scene: String,
    #[command(flatten)]
    pub ros: RosOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// How to read a scene.
#[derive(Debug, Clone, Args)]
pub struct SceneOpts {
    /// Up axis of OBJ/PLY files (glTF is always y up).
    #[arg(long, value_enum, default_value_t = UpAxisArg::Y, help_heading = "Scene")]
    pub up_axis: UpAxisArg,
    /// Keep meshes named "ceiling" (dropped by default).
    #[arg(long, help_heading = "Scene")]
    pub keep_ceilings: bool,
    /// Agent radius (m) [default: 0.1, or the robot's radius under --physics].
    #[arg(long, help_heading = "Agent")]
    pub agent_radius: Option<f64>,
    /// Agent height (m).
    #[arg(long, default_value_t = 1.5, help_heading = "Agent")]
    pub agent_height: f64,
    /// Cell size of the navigation grid (m).
    #[arg(long, default_value_t = 0.05, help_heading = "Agent")]
    pub cell_size: f64,
    /// Storeys of the procedural house (SCENE `procedural[:SEED]`), joined by a stair hall.
    #[arg(long, default_value_t = 1, help_heading = "Scene")]
    pub storeys: usize,
}

/// Up axis values.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum UpAxisArg {
    /// y up.
    Y,
    /// z up.
    Z,
}

/// `xhab demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// Seed of the house and of the episodes.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Number of episodes.
    #[arg(long, default_value_t = 50)]
    pub episodes: usize,
    /// Folder for the map, episodes, results and pictures.
    #[arg(long, default_value = "xhab-out/demo")]
    pub out: PathBuf,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
}

/// `xhab map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// The scene.
    pub scene: String,
    /// Output path without extension: writes OUT.yaml, OUT.pgm and OUT.png.
    #[arg(long)]
    pub out: PathBuf,
    /// Map resolution (m per cell).
    #[arg(long, default_value_t = 0.05)]
    pub resolution: f64,
    /// Floor: `auto` (the lowest), a storey number N (0 the lowest), a height in metres
    /// (Habitat's y, i.e. up), or `all`: one map per storey as OUT_floorN.{yaml,pgm,png} and
    /// OUT.png with all storeys side by side.
    #[arg(long, default_value = "auto")]
    pub floor: String,
    /// Map what a planar laser at this height above the floor sees (m; e.g. 0.2): geometry
    /// within 2.5 cm of its scan plane is occupied (a table is its legs), the map AMCL should
    /// localise that laser on. Without it: everything in the agent's body band.
    #[arg(long, conflicts_with = "explore")]
    pub laser_height: Option<f64>,
    /// Build the map by exploring: the robot, under physics with its lidar, goes to the
    /// nearest reachable frontier until none is left, mapping as it goes.
    #[arg(long, help_heading = "Exploration")]
    pub explore: bool,
    /// Robot profile that explores: habitat, locobot, turtlebot3_burger, turtlebot3_waffle, or a .yaml file.
    #[arg(long, default_value = "habitat", help_heading = "Exploration")]
    pub robot: String,
    /// Start X,Y,YAW (world/map frame: m, m, rad) [default: the navigable cell nearest the
    /// centre of the largest island].
    #[arg(long, allow_hyphen_values = true, help_heading = "Exploration")]
    pub start: Option<String>,
    /// `--nav-params`: ROS parameter files, layered.
    #[arg(long, value_name = "FILE[@NAMESPACE]", help = NAV_PARAMS_HELP, long_help = NAV_PARAMS_LONG_HELP, help_heading = "Exploration")]
    pub nav_params: Vec<ParamFile>,
    /// Exploration time limit (simulated s).
    #[arg(long, default_value_t = 1800.0, help_heading = "Exploration")]
    pub max_time: f64,
    /// Seed (lidar noise).
    #[arg(long, default_value_t = 0, help_heading = "Exploration")]
    pub seed: u64,
    /// Renderer of the robot's depth camera.
    #[arg(long, value_enum, default_value_t = RendererArg::Auto, help_heading = "Exploration")]
    pub renderer: RendererArg,
    /// Print the exploration report as JSON on stdout.
    #[arg(long, help_heading = "Exploration")]
    pub json: bool,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab episodes`.
#[derive(Debug, Args)]
pub struct EpisodesArgs {
    /// The scene.
    pub scene: String,
    /// Number of episodes.
    #[arg(long, default_value_t = 30)]
    pub count: usize,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output file (.json.gz or .json).
    #[arg(long)]
    pub out: PathBuf,
    /// Floor: `auto` (the lowest), a storey number N (0 the lowest) or a height in metres
    /// (Habitat's y).
    #[arg(long, default_value = "auto")]
    pub floor: String,
    /// scene_id written into the episodes (default: the SCENE argument).
    #[arg(long)]
    pub scene_id: Option<String>,
    /// Pairs on different storeys joined by stairs (start and goal on floors, not on the
    /// flights); `--floor` does not apply.
    #[arg(long, conflicts_with = "floor")]
    pub cross_floor: bool,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab geodesic`.
#[derive(Debug, Args)]
pub struct GeodesicArgs {
    /// The scene.
    pub scene: String,
    /// Start X,Y,Z (Habitat frame, m).
    #[arg(long, allow_hyphen_values = true)]
    pub from: String,
    /// Goal X,Y,Z (Habitat frame, m).
    #[arg(long, allow_hyphen_values = true)]
    pub to: String,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// Agents for `bench`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AgentArg {
    /// Greedy shortest-path follower over discrete actions.
    Oracle,
    /// The native navigation stack (costmap, A*, DWA, navigator) under physics with velocities.
    Nav,
    /// An external ROS navigation stack (move_base + amcl, a rospy node, `xhab ros nav`),
    /// driven through tf, /clock, initialpose, the move_base action and cmd_vel.
    Ros,
    /// An external ROS 2 navigation stack (Nav2, or any node offering `navigate_to_pose`;
    /// `xhab ros2 nav`), driven through tf, /clock, initialpose, the navigate_to_pose action
    /// and cmd_vel over DDS (domain: $ROS_DOMAIN_ID).
    #[value(name = "ros2")]
    Ros2,
}

/// How goals reach an external stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum GoalInterfaceArg {
    /// The stack's action: move_base (ROS 1), navigate_to_pose (ROS 2).
    Action,
    /// The goal topic: move_base_simple/goal with the outcome read from move_base/status
    /// (ROS 1); goal_pose with the outcome read from navigate_to_pose/_action/status (ROS 2).
    Simple,
}

/// Who publishes map -> odom for an external stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MapOdomArg {
    /// The stack (its own localiser, e.g. amcl).
    Stack,
    /// The simulator, from ground truth (as fake_localization).
    #[value(name = "ground-truth", alias = "ground_truth")]
    GroundTruth,
}

/// How the simulated clock follows an external stack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PaceArg {
    /// After each tick wait for the stack's cmd_vel (up to --cmd-vel-grace).
    Lockstep,
    /// Run at --rate times real time.
    Realtime,
}

/// Localisation of the nav agent.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum LocalizationArg {
    /// Ground truth from the simulator (`ground_truth`, as the README and the JSON spell it;
    /// `ground-truth` is accepted too).
    #[value(name = "ground_truth", alias = "ground-truth")]
    GroundTruth,
    /// Wheel odometry alone (drifts).
    Odom,
    /// AMCL with odometry and the laser scans.
    Amcl,
}

/// `xhab bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// The scene.
    #[arg(long)]
    pub scene: String,
    /// Episodes file (Habitat PointNav .json.gz).
    #[arg(long)]
    pub episodes: PathBuf,
    /// The agent.
    #[arg(long, value_enum, default_value_t = AgentArg::Oracle)]
    pub agent: AgentArg,
    /// JSON results file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// CSV of per-episode results.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Folder for top-down pictures of each episode's trajectory.
    #[arg(long)]
    pub trajectories: Option<PathBuf>,
    /// Worker threads (results do not depend on it).
    #[arg(long, default_value_t = 1)]
    pub threads: usize,
    /// Success radius (m).
    #[arg(long, default_value_t = 0.2)]
    pub success_distance: f64,
    /// Action limit per episode.
    #[arg(long, default_value_t = 500)]
    pub max_steps: u32,
    /// Seed of the run's randomness (odometry noise); episode i uses SEED + i.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Print the process's resident memory (VmRSS, Linux) to stderr after every N finished
    /// episodes, as `xhab: rss after episode N: KIB KiB` (soak tests, scripts/soak.sh); 0: never.
    #[arg(long, value_name = "N", default_value_t = 0)]
    pub rss_every: usize,
    /// Localisation of the nav agent.
    #[arg(long, value_enum, default_value_t = LocalizationArg::GroundTruth, help_heading = "Navigation")]
    pub localization: LocalizationArg,
    /// Static map for the nav agent (map_server YAML) [default: the map `xhab map` makes of the scene].
    #[arg(long, help_heading = "Navigation")]
    pub map: Option<PathBuf>,
    /// `--nav-params`: ROS parameter files, layered.
    #[arg(long, value_name = "FILE[@NAMESPACE]", help = NAV_PARAMS_HELP, long_help = NAV_PARAMS_LONG_HELP, help_heading = "Navigation")]
    pub nav_params: Vec<ParamFile>,
    /// Run the nav agent without laser scans (static map only, no obstacle layer).
    #[arg(long, help_heading = "Navigation")]
    pub no_scans: bool,
    /// Where the nav agent's laser scans come from: a planar lidar (LDS-01: 360 beams, 3.5 m,
    /// 0.2 m up), or the depth camera through depthimage_to_laserscan (the camera's height and
    /// field of view, range 0.45-10 m), as ROS-X-Habitat fed move_base.
    #[arg(long, value_enum, default_value_t = ScanSourceArg::Lidar, help_heading = "Navigation")]
    pub scan_source: ScanSourceArg,
    /// Camera images each observation carries, rendered at every step: `depth`, or `depth,rgb`.
    /// Agents receive them; the JSON reports rendering time.
    #[arg(long, value_delimiter = ',', help_heading = "Camera")]
    pub sensors: Vec<String>,
    /// Standard deviation of the depth noise at 1 m (m; it grows with depth squared) [default: 0, off].
    #[arg(long, default_value_t = 0.0, help_heading = "Camera")]
    pub depth_noise: f64,
    /// Probability that a depth pixel on an edge reads no return [default: 0, off].
    #[arg(long, default_value_t = 0.0, help_heading = "Camera")]
    pub edge_dropout: f64,
    #[command(flatten)]
    pub camera: CameraOpts,
    /// Run the agent and the simulator as separate ROS 1 nodes through a real rosmaster, in lock-step.
    #[arg(long, help_heading = "ROS")]
    pub ros: bool,
    /// Run in-process and over ROS, check that the results agree, report aggregate.ros_overhead.
    #[arg(long, help_heading = "ROS")]
    pub compare_ros: bool,
    /// Run the agent and the simulator as separate ROS 2 nodes (DDS domain $ROS_DOMAIN_ID), in lock-step.
    #[arg(long, help_heading = "ROS", conflicts_with_all = ["ros", "compare_ros"])]
    pub ros2: bool,
    /// Run in-process and over ROS 2, check that the results agree, report aggregate.ros_overhead.
    #[arg(long, help_heading = "ROS", conflicts_with_all = ["ros", "compare_ros", "ros2"])]
    pub compare_ros2: bool,
    /// The ROS master (http://HOST:PORT) [default: start `rosmaster` for the run].
    #[arg(long, value_name = "URI", help_heading = "ROS")]
    pub ros_master: Option<String>,
    /// Seconds to wait for a ROS peer before failing.
    #[arg(long, default_value_t = 30.0, help_heading = "ROS")]
    pub ros_timeout: f64,
    /// How goals reach the stack under test (`--agent ros`).
    #[arg(long, value_enum, default_value_t = GoalInterfaceArg::Action, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub goal_interface: GoalInterfaceArg,
    /// A command that starts the stack (`sh -c CMD`, once the master has /use_sim_time; stopped at the end).
    #[arg(long, value_name = "CMD", help_heading = "External ROS stack (--agent ros, ros2)")]
    pub launch: Option<String>,
    /// Simulated seconds after which an episode's goal is cancelled.
    #[arg(long, default_value_t = 120.0, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub episode_timeout: f64,
    /// Who publishes map -> odom: the stack (its amcl), or the simulator from ground truth.
    #[arg(long, value_enum, default_value_t = MapOdomArg::Stack, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub map_odom: MapOdomArg,
    /// How the clock follows the stack.
    #[arg(long, value_enum, default_value_t = PaceArg::Lockstep, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub pace: PaceArg,
    /// Simulated seconds per wall second with --pace realtime.
    #[arg(long, default_value_t = 1.0, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub rate: f64,
    /// Wall seconds to wait for cmd_vel after each tick with --pace lockstep.
    #[arg(long, default_value_t = 0.5, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub cmd_vel_grace: f64,
    /// ROS arguments of the simulator node, repeatable: `from:=to` remappings, `__ns:=NS`
    /// (`$ROS_NAMESPACE` is honoured too), e.g. to meet a stack running in a robot's namespace.
    #[arg(long = "ros-arg", value_name = "FROM:=TO", help_heading = "External ROS stack (--agent ros, ros2)")]
    pub ros_args: Vec<String>,
    /// ROS 2 arguments of the simulator node with --agent ros2, last on the line:
    /// `--ros-args -r FROM:=TO -r __ns:=/NS -r __node:=NAME` (`$ROS_NAMESPACE` is honoured too).
    #[arg(long = "ros-args", num_args = 0.., allow_hyphen_values = true, value_name = "ARGS", help_heading = "External ROS stack (--agent ros, ros2)")]
    pub ros2_args: Option<Vec<String>>,
    /// Clock ticks per simulated second: set it to the stack's controller_frequency (Hz).
    #[arg(long, default_value_t = 20.0, help_heading = "External ROS stack (--agent ros, ros2)")]
    pub controller_frequency: f64,
    #[command(flatten)]
    pub physics: PhysicsOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// Where the nav agent's scans come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ScanSourceArg {
    /// The planar lidar.
    Lidar,
    /// The depth camera, through depthimage_to_laserscan.
    Depth,
}

/// Physics mode options.
#[derive(Debug, Clone, Args)]
pub struct PhysicsOpts {
    /// Run under rapier3d physics: each action becomes velocities held for --control-period.
    #[arg(long, help_heading = "Physics")]
    pub physics: bool,
    /// Robot profile: habitat, locobot, turtlebot3_burger, turtlebot3_waffle, or a .yaml file.
    #[arg(long, default_value = "habitat", help_heading = "Physics")]
    pub robot: String,
    /// Seconds each discrete action's velocities are held (T of Algorithm 1).
    #[arg(long, default_value_t = 1.0, help_heading = "Physics")]
    pub control_period: f64,
    /// Physics steps per simulated second.
    #[arg(long, default_value_t = 60.0, help_heading = "Physics")]
    pub steps_per_sec: f64,
}

/// Renderers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RendererArg {
    /// wgpu on a real GPU, else the CPU rasteriser (a log line says which and why).
    Auto,
    /// CPU ray casting (parry3d BVH), the reference.
    Raycast,
    /// CPU rasteriser (tiled, frustum-culled, multi-threaded).
    Raster,
    /// wgpu (Vulkan; headless; Mesa's software driver without a GPU).
    Wgpu,
}

/// Camera options.
#[derive(Debug, Clone, Args)]
pub struct CameraOpts {
    /// Renderer.
    #[arg(long, value_enum, default_value_t = RendererArg::Auto, help_heading = "Camera")]
    pub renderer: RendererArg,
    /// Image width and height (px).
    #[arg(long, default_value_t = 256, help_heading = "Camera")]
    pub resolution: usize,
    /// Horizontal field of view (degrees).
    #[arg(long, default_value_t = 90.0, help_heading = "Camera")]
    pub hfov: f64,
    /// Camera height above the floor (m) [default: the robot profile's; 1.25, Habitat's agent].
    #[arg(long, help_heading = "Camera")]
    pub camera_height: Option<f64>,
    /// Also measure batched rendering: N views per call (`perf --sensors`), reported per view.
    #[arg(long, value_name = "N", help_heading = "Camera")]
    pub batch: Option<usize>,
}

/// `xhab render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The scene.
    pub scene: String,
    /// Robot pose X,Y,Z,YAW (world frame: m, m, m of the base, rad).
    #[arg(long, allow_hyphen_values = true)]
    pub pose: String,
    /// Output PNG (depth colour-mapped on the left, RGB on the right).
    #[arg(long, default_value = "view.png")]
    pub out: PathBuf,
    #[command(flatten)]
    pub camera: CameraOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab navigate`.
#[derive(Debug, Args)]
pub struct NavigateArgs {
    /// The scene.
    pub scene: String,
    /// Static map (map_server YAML) [default: the map `xhab map` makes of the scene].
    #[arg(long)]
    pub map: Option<PathBuf>,
    /// Start X,Y,YAW (world/map frame: m, m, rad).
    #[arg(long, allow_hyphen_values = true)]
    pub start: String,
    /// Goal X,Y (world/map frame, m).
    #[arg(long, allow_hyphen_values = true)]
    pub goal: String,
    /// Picture of the run (PNG).
    #[arg(long, default_value = "navigate.png")]
    pub out: PathBuf,
    /// `--nav-params`: ROS parameter files, layered.
    #[arg(long, value_name = "FILE[@NAMESPACE]", help = NAV_PARAMS_HELP, long_help = NAV_PARAMS_LONG_HELP)]
    pub nav_params: Vec<ParamFile>,
    /// Robot profile name or .yaml file.
    #[arg(long, default_value = "habitat")]
    pub robot: String,
    /// Time limit (simulated s).
    #[arg(long, default_value_t = 500.0)]
    pub time_limit: f64,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// `xhab perf`.
#[derive(Debug, Args)]
pub struct PerfArgs {
    /// The scene.
    pub scene: String,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
    /// Seconds to spend on each timed figure (approximate).
    #[arg(long, default_value_t = 1.0)]
    pub seconds: f64,
    #[command(flatten)]
    pub physics: PhysicsOpts,
    /// Sensors to render at every step (`depth`; rgb too with `depth,rgb`).
    #[arg(long, value_delimiter = ',')]
    pub sensors: Vec<String>,
    /// Time AMCL updates (5,000 particles, 60 beams).
    #[arg(long)]
    pub amcl: bool,
    /// Time the native navigation loop (nav agent, physics, lidar, AMCL) on one thread over
    /// a fixed episode set: `nav_real_time_factor`.
    #[arg(long)]
    pub nav: bool,
    /// Run only these groups of figures (repeat the flag or give a comma list), whatever
    /// --physics, --amcl and --sensors say (`sensors` renders depth unless --sensors says
    /// otherwise); the other groups' figures are absent from the JSON. --nav is no group.
    #[arg(long, value_name = "GROUP", value_delimiter = ',')]
    pub only: Vec<PerfGroupArg>,
    #[command(flatten)]
    pub camera: CameraOpts,
    #[command(flatten)]
    pub scene_opts: SceneOpts,
}

/// A group of `xhab perf` figures, for `--only`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PerfGroupArg {
    /// Goal-field builds, queries against them and cold point-to-point queries.
    Geodesic,
    /// The map build: floors, navigation grid and corner graph (`map_build_s`).
    Grid,
    /// Discrete steps without rendering, random and oracle.
    Discrete,
    /// Raw physics steps and discrete actions under physics.
    Physics,
    /// Discrete steps rendering the camera at every step.
    Sensors,
    /// AMCL updates (5,000 particles, 60 beams).
    Amcl,
}

/// `xhab scene ...`.
#[derive(Debug, Subcommand)]
pub enum SceneCommand {
    /// Write the procedural house (or the stair test building) as GLB.
    Generate {
        /// Seed.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Storeys of the house, joined by a stair hall.
        #[arg(long, default_value_t = 1)]
        storeys: usize,
        /// Write the two-storey test building with one straight flight instead (the scene
        /// `stair_building`, whose geodesics are known in closed form).
        #[arg(long, conflicts_with_all = ["seed", "storeys"])]
        stair_building: bool,
        /// Output .glb file.
        #[arg(long)]
        out: PathBuf,
    },
    /// Print facts about a scene: triangles, bounds, storeys (height, areas, islands, which
    /// storeys a flight of stairs joins).
    Info {
        /// The scene.
        scene: String,
        #[command(flatten)]
        scene_opts: SceneOpts,
    },
}
