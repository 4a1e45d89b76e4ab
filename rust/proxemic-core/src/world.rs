//! The world: ties scenario, map, planners, pedestrians and metrics together behind one `step`.
//!
//! The Python env owns the physics. A control step has three parts, which the Python binding
//! runs as one call (`World.step`, the GIL released around the core's parts):
//! 1. [`World::command`]: turns the policies' normalised actions into limited robot-frame
//!    commands; robots without an action (NaN) execute their built-in planner's command;
//! 2. the caller writes the commands and the people's poses into MuJoCo and steps the physics;
//! 3. [`World::step`] with the robots' new poses, velocities and contact flags: advances the
//!    people, accumulates metrics and reward terms, builds the observations, and runs each
//!    robot's built-in planner for the next command.
//!
//! All outputs are written into one caller-owned `f64` buffer laid out as described by
//! [`Layout`] (one row of [`Layout::stride`] values per robot), plus a `(people, PERSON_OUT)`
//! buffer of the people's poses and contact hints, so a step allocates nothing and crosses the
//! language boundary once.

use crate::plan::social::{SocialPath, SocialPlanning, Trigger};

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::control::eband::{EbandParams, ElasticBand};
use crate::control::mode_switch::{
    Mode, OtherRobot, Person as CtlPerson, SocialControlParams, choose_mode, social_momentum_step,
};
use crate::control::orca::{ObstacleSet, Orca, OrcaAgent, OrcaParams};
use crate::control::{FollowerParams, Limits, PathFollower, body_to_world, world_to_body};
use crate::error::{CoreError, Result};
use crate::groups::RobotDisc;
use crate::map::geometry::{Bounds, StaticGeometry};
use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use crate::map::lidar::Scanner;
use crate::math::{Vec2, wrap_angle};
use crate::metrics::{
    EpisodeRecorder, EpisodeReport, InteractionLink, InteractionObject, MetricParams, OSpace, Outcome,
    RecorderSetup, SceneLog, Snapshot, interactions,
};
use crate::pedestrians::scripts::{Script, plan_scripts};
use crate::pedestrians::{Crowd, GuideState, SocialForceParams};
use crate::plan::geodesic::GoalField;
use crate::plan::{CostGrid, PathPlanner, SearchMode, smooth_path, snap_to_passable};
use crate::scenario::{Behaviour, PlannerKind, Scenario};

/// Contact flag bit: the robot touched a person during the physics step.
pub const CONTACT_PERSON: u8 = 1;
/// Contact flag bit: the robot touched a wall or furniture.
pub const CONTACT_STATIC: u8 = 2;
/// Contact flag bit: the robot touched another robot.
pub const CONTACT_ROBOT: u8 = 4;

/// Number of values per person in the people observation.
pub const PERSON_FEATURES: usize = 5;
/// Number of values in the robot observation.
pub const ROBOT_FEATURES: usize = 5;
/// Number of values per other robot in the robots observation: id (the robot's index), position
/// (x, y) and velocity (vx, vy) in the observer's frame, radius, and 1 while that robot's episode
/// is running (0 once it has ended: it then stands still).
pub const PEER_FEATURES: usize = 7;
/// Names of the reward terms, in the order they are summed.
pub const REWARD_TERMS: [&str; 5] = ["progress", "success", "collision", "time", "personal_space"];
/// Radius of the personal zone used by the personal-space reward term (metres, centre distance;
/// Hall's personal distance as used by HuNav/SEAN).
pub const PERSONAL_ZONE: f64 = 1.2;
/// Bound on velocities in observations (m/s); values beyond are clipped (documented in the env).
pub const OBS_MAX_SPEED: f64 = 5.0;
/// Bound on the angular velocity in observations (rad/s).
pub const OBS_MAX_ANGULAR: f64 = 10.0;
/// Values per person in the people buffer: x, y, heading (world frame, m and rad), a contact
/// hint (1.0 while the person is within [`CONTACT_RANGE`] of a robot, else 0.0), and the
/// heading as the w and z of a yaw quaternion (cos and sin of half the heading, for MuJoCo).
pub const PERSON_OUT: usize = 6;
/// Surface gap (m) within which the physics must test a robot against the static geometry or a
/// person for contacts. Beyond it nothing can touch during one control step: closing 0.5 m in
/// 0.1 s takes 5 m/s, and robots move at most 0.55 m/s, people at most 1.3 times their preferred
/// speed; a robot moving faster than [`CONTACT_RANGE`] per control period is always tested.
/// The hints only let the physics skip pairs that cannot collide: contacts are the same.
pub const CONTACT_RANGE: f64 = 0.5;

/// One named section of a robot's row in the output buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Section {
    /// Offset within the row.
    pub offset: usize,
    /// Number of values.
    pub len: usize,
}

/// Layout of a robot's row in the output buffer.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Values per robot row.
    pub stride: usize,
    /// Named sections: `command` (3: vx, vy, wz, robot frame, to execute), `planner_action` (3:
    /// the built-in planner's command as a normalised action), `obs_robot` (5), `obs_people`
    /// (k * 5), `obs_people_mask` (k), `obs_lidar` (rays), `obs_robots` ((n - 1) * 7, the other
    /// robots within sensor range, nearest first, see [`PEER_FEATURES`]), `obs_robots_mask`
    /// (n - 1), `reward_terms` (5), `reward` (1),
    /// `flags` (4: terminated, truncated, success, collision), `pose` (3: x, y, theta), `mode`
    /// (1: the local planner's mode, see [`Mode::code`]), `near_static` (1: 1.0 while the robot is
    /// within [`CONTACT_RANGE`] of a wall or object, else 0.0: whether the physics must test it
    /// against the static geometry), `near_robot` (1: 1.0 while another robot is within
    /// [`CONTACT_RANGE`] of it, else 0.0), `time_of_day` (1: seconds after midnight, the same in
    /// every row).
    pub sections: Vec<(&'static str, Section)>,
}

impl Layout {
    fn new(k: usize, rays: usize, robots: usize) -> Self {
        let others = robots.saturating_sub(1);
        let sizes: [(&'static str, usize); 16] = [
            ("command", 3),
            ("planner_action", 3),
            ("obs_robot", ROBOT_FEATURES),
            ("obs_people", k * PERSON_FEATURES),
            ("obs_people_mask", k),
            ("obs_lidar", rays),
            ("obs_robots", others * PEER_FEATURES),
            ("obs_robots_mask", others),
            ("reward_terms", REWARD_TERMS.len()),
            ("reward", 1),
            ("flags", 4),
            ("pose", 3),
            ("mode", 1),
            ("near_static", 1),
            ("near_robot", 1),
            ("time_of_day", 1),
        ];
        let mut offset = 0;
        let mut sections = Vec::with_capacity(sizes.len());
        for (name, len) in sizes {
            sections.push((name, Section { offset, len }));
            offset += len;
        }
        Layout { stride: offset, sections }
    }

    /// The section called `name`.
    pub fn section(&self, name: &str) -> Option<Section> {
        self.sections.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
    }
}

/// Per-robot state that does not change between episodes.
struct RobotStatic {
    planner: PlannerKind,
    /// The elastic band's parameters (eband planner only).
    eband: EbandParams,
    /// For approach tasks, the point to face near the goal (the person approached).
    face: Option<Vec2>,
    limits: Limits,
    radius: f64,
    goal: Vec2,
    grid_index: usize,
    /// The targets in order: the waypoints of a tour, then the goal (just the goal otherwise).
    route: Vec<Vec2>,
    /// The geodesic distance field of each target of `route`.
    fields: Vec<GoalField>,
    /// Seconds the robot stands at each waypoint (0: it passes through).
    dwell: f64,
    /// Geodesic length from the nominal start through the route (m).
    geodesic_from_start: f64,
    /// The plain A* path from the nominal start to the first target (cached: the start only
    /// changes with jitter).
    nominal_path: Vec<Vec2>,
    /// The plain A* paths between consecutive targets (`legs[k]` from target k to k + 1).
    legs: Vec<Vec<Vec2>>,
}

/// Per-robot state of the running episode.
struct RobotRuntime {
    pose: [f64; 3],
    velocity: Vec2,
    wz: f64,
    /// Last executed command, world frame.
    exec_v: Vec2,
    exec_wz: f64,
    /// The built-in planner's proposed command, world frame.
    proposed_v: Vec2,
    proposed_wz: f64,
    follower: PathFollower,
    /// The episode's recording, from which the metrics are computed.
    recorder: EpisodeRecorder,
    outcome: Outcome,
    geodesic: f64,
    user_command: bool,
    /// The social path (social planners only) and when it was last planned.
    social_path: Option<SocialPath>,
    last_plan_step: usize,
    replans: usize,
    /// The elastic band (eband planner only).
    band: Option<ElasticBand>,
    mode: Mode,
    /// Index in the route of the current target.
    leg: usize,
    /// Whether the robot stands at its current target (a tour stop), and for how much longer (s).
    dwelling: bool,
    dwell_left: f64,
}

/// On an approach task the robot turns to face the person within this distance of the goal (m).
const APPROACH_FACING_DISTANCE: f64 = 1.0;

/// Added to every radius ORCA sees (metres): ORCA lets bodies touch, the physics counts a touch.
const ORCA_MARGIN: f64 = 0.08;

/// Social planners check their path every this many control steps...
const SOCIAL_CHECK_PERIOD: usize = 3;
/// ...and re-plan at most once per this many steps.
const SOCIAL_MIN_REPLAN: usize = 10;
/// Without a trigger, a social path is re-planned every this many steps anyway, and replaced
/// when the new one is cheaper (see [`SOCIAL_REPLAN_GAIN`]): a way that people blocked when the
/// path was made may have cleared.
const SOCIAL_REFRESH: usize = 20;
/// A re-planned social path replaces the current one only when it costs at least this fraction
/// less than what is left of the current one on the same map (or the current one is blocked):
/// without it, two ways of nearly equal cost (around a gallery or along the corridor) took turns
/// as people moved and the robot wandered between them.
const SOCIAL_REPLAN_GAIN: f64 = 0.15;
/// The largest ratio of the shortest 8-connected grid path to the straight line between its
/// ends, `cos 22.5° + (sqrt 2 - 1) sin 22.5°` (at 22.5°): a grid geodesic divided by it never
/// exceeds the true one.
const GRID_DETOUR: f64 = 1.082_392_200_292_394;

/// A cost grid shared by all robots with the same inflation radius.
struct InflatedGrid {
    radius: f64,
    grid: CostGrid,
}

/// The simulated world of one scenario.
pub struct World {
    scenario: Scenario,
    geometry: StaticGeometry,
    /// Distance from every cell to the static geometry (for the people's wall forces).
    field: DistanceField,
    /// The social model, maps and global planner.
    social: SocialPlanning,
    /// Local planners.
    control: SocialControlParams,
    orca: Orca,
    obstacles: ObstacleSet,
    grids: Vec<InflatedGrid>,
    statics: Vec<RobotStatic>,
    robots: Vec<RobotRuntime>,
    crowd: Crowd,
    /// Each person's behaviour script, planned once on the static map.
    scripts: Vec<Script>,
    planner: PathPlanner,
    layout: Layout,
    rng: ChaCha8Rng,
    steps: usize,
    started: bool,
    scratch_people: Vec<(f64, usize)>,
    scratch_discs: Vec<(Vec2, f64)>,
    /// Per robot, its lidar (buffers, and the static part of its last scan).
    scanners: Vec<Scanner>,
    /// Per robot, whether its episode had ended before the current step (its observation is
    /// then no longer updated).
    ended: Vec<bool>,
    /// Per robot: whether its built-in planner runs (see [`World::set_planning`]).
    planning: Vec<bool>,
    /// The objects with an interaction space (metrics: person-object interactions, object
    /// spaces), in the order of the social planner's object names.
    interaction_objects: Vec<InteractionObject>,
    /// The current instant's ground-truth o-spaces, interactions and object activities.
    now: GroundTruth,
    /// The scene since the reset, for every robot's metrics.
    log: SceneLog,
}

/// The ground truth of one instant that the metrics need: the groups' o-spaces, the interaction
/// segments and, per object with an interaction space, whether its activity is on.
#[derive(Clone, Debug, Default)]
struct GroundTruth {
    ospaces: Vec<OSpace>,
    links: Vec<InteractionLink>,
    active: Vec<bool>,
}

impl GroundTruth {
    /// This instant among `crowd`, for the scene log.
    fn snapshot<'a>(&'a self, crowd: &'a Crowd) -> Snapshot<'a> {
        Snapshot {
            positions: &crowd.pos,
            velocities: &crowd.vel,
            headings: &crowd.heading,
            ospaces: &self.ospaces,
            links: &self.links,
            active: &self.active,
        }
    }
}

/// Free space (m) kept between a robot's start area and the people who start walking near it:
/// the common evaluation radius of the intimate zone, 0.45 m, so that no episode begins with an
/// intrusion the robot could not avoid.
pub const START_CLEARANCE: f64 = 0.45;

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

fn scenario_err(s: &Scenario, field: String, expected: String, found: String) -> CoreError {
    CoreError::Scenario { file: s.source.clone(), field, expected, found }
}

impl World {
    /// Builds the world: static geometry, inflated grids, goal fields and the plain A* paths
    /// from the nominal starts. Fails if a robot's start or goal is inside or too close to the
    /// static geometry, if a goal is unreachable, if a person starts or walks through it, or if
    /// a person's behaviour finds no room (a viewing place, a place at an activity or in a
    /// conversation, a tour's gathering arc) or no path ([`plan_scripts`]).
    pub fn new(scenario: Scenario) -> Result<Self> {
        let b = scenario.scene.bounds;
        let bounds = Bounds { min: Vec2::new(b[0], b[1]), max: Vec2::new(b[2], b[3]) };
        let polygons: Vec<Vec<Vec2>> =
            scenario.static_polygons().into_iter().map(|p| p.into_iter().map(v2).collect()).collect();
        let geometry = StaticGeometry::new(polygons, bounds)?;
        let spec = GridSpec::covering(bounds, scenario.scene.resolution)?;
        let occupancy = OccupancyGrid::rasterize(&geometry, spec);
        let field = DistanceField::from_occupancy(&occupancy);

        check_people(&scenario, &geometry)?;

        let mut grids: Vec<InflatedGrid> = Vec::new();
        let mut planner = PathPlanner::new();
        let mut statics = Vec::with_capacity(scenario.robots.len());
        for (i, r) in scenario.robots.iter().enumerate() {
            let clearance_needed = r.radius;
            let places = std::iter::once(("start".to_string(), Vec2::new(r.start[0], r.start[1])))
                .chain(r.waypoints.iter().enumerate().map(|(k, w)| (format!("waypoints[{k}]"), v2(*w))))
                .chain(std::iter::once(("goal".to_string(), v2(r.goal))));
            for (name, p) in places {
                let clear = geometry.distance(p);
                if geometry.contains(p) || clear < clearance_needed {
                    let what = if geometry.contains(p) {
                        "inside a wall or object".to_string()
                    } else {
                        format!("only {clear:.2} m from a wall or object")
                    };
                    return Err(scenario_err(
                        &scenario,
                        format!("robot[{i}].{name}"),
                        format!(
                            "a position at least {clearance_needed:.2} m (the robot radius) from walls and furniture"
                        ),
                        format!("{:?} ({what})", [p.x, p.y]),
                    ));
                }
            }
            let inflate = r.radius + r.inflation_margin;
            let grid_index = match grids.iter().position(|g| (g.radius - inflate).abs() < 1e-12) {
                Some(k) => k,
                None => {
                    grids.push(InflatedGrid { radius: inflate, grid: CostGrid::inflated(&field, inflate) });
                    grids.len() - 1
                }
            };
            let grid = &grids[grid_index].grid;
            let goal = v2(r.goal);
            let start = Vec2::new(r.start[0], r.start[1]);
            let route: Vec<Vec2> = r.waypoints.iter().map(|w| v2(*w)).chain(std::iter::once(goal)).collect();
            let target_field = |k: usize| {
                if k + 1 == route.len() {
                    format!("robot[{i}].goal")
                } else {
                    format!("robot[{i}].waypoints[{k}]")
                }
            };
            let mut fields = Vec::with_capacity(route.len());
            let mut paths: Vec<Vec<Vec2>> = Vec::with_capacity(route.len());
            let mut geodesic_from_start = 0.0;
            for (k, &target) in route.iter().enumerate() {
                let cell = snap_to_passable(grid, target).ok_or_else(|| {
                    scenario_err(
                        &scenario,
                        target_field(k),
                        format!(
                            "a place with {inflate:.2} m clearance (robot radius + inflation margin) nearby"
                        ),
                        format!("{:?}", [target.x, target.y]),
                    )
                })?;
                let from = if k == 0 { start } else { route[k - 1] };
                let f = GoalField::compute(grid, cell);
                geodesic_from_start += f.distance(from);
                fields.push(f);
                paths.push(plan_path(&mut planner, grid, from, target).ok_or_else(|| {
                    CoreError::Planning {
                        file: scenario.source.clone(),
                        field: target_field(k),
                        message: format!(
                            "no collision-free path for a robot of radius {:.2} m from {:?} to {:?}",
                            r.radius,
                            [from.x, from.y],
                            [target.x, target.y]
                        ),
                    }
                })?);
            }
            // A tour must not lead the robot across its goal before the end (the episode would
            // succeed there).
            let success = scenario.episode.success_radius;
            if let Some(k) = paths[..paths.len() - 1]
                .iter()
                .position(|path| path.iter().any(|q| (q - goal).norm() <= success + 0.5))
            {
                return Err(scenario_err(
                    &scenario,
                    format!("robot[{i}].waypoints[{k}]"),
                    format!(
                        "a tour whose paths to its waypoints stay more than {:.2} m (success radius + 0.5 m) from the goal",
                        success + 0.5
                    ),
                    format!("the path to waypoints[{k}] passes the goal {:?}", r.goal),
                ));
            }
            let nominal_path = paths.remove(0);
            let limits = Limits {
                max_speed: r.max_speed,
                max_angular_speed: r.max_angular_speed,
                max_accel: r.max_accel,
                max_angular_accel: Limits::PEPPER.max_angular_accel,
            };
            statics.push(RobotStatic {
                planner: r.planner,
                eband: r.eband.params(),
                face: r.approach.as_ref().map(|a| v2(a.face)),
                limits,
                radius: r.radius,
                goal,
                grid_index,
                route,
                fields,
                dwell: r.dwell,
                geodesic_from_start,
                nominal_path,
                legs: paths,
            });
        }
        // People's places and paths after the robots' (a tour's stops must be valid first).
        let scripts = plan_scripts(&scenario, &geometry, &field)?;
        let layout =
            Layout::new(scenario.sensors.k_nearest, scenario.sensors.lidar_rays, scenario.robots.len());
        let grid_refs: Vec<(&CostGrid, f64)> = grids.iter().map(|g| (&g.grid, g.radius)).collect();
        let social = SocialPlanning::new(&scenario, &grid_refs)?;
        let obstacles = ObstacleSet::from_geometry(&geometry)?;
        let orca = Orca::new(OrcaParams::default())?;
        let mut world = World {
            control: SocialControlParams::default(),
            orca,
            obstacles,
            geometry,
            field,
            social,
            grids,
            statics,
            robots: Vec::new(),
            crowd: Crowd::default(),
            scripts,
            planner,
            layout,
            rng: ChaCha8Rng::seed_from_u64(0),
            steps: 0,
            started: false,
            scratch_people: Vec::new(),
            scratch_discs: Vec::new(),
            scanners: vec![Scanner::default(); scenario.robots.len()],
            ended: vec![false; scenario.robots.len()],
            planning: vec![true; scenario.robots.len()],
            interaction_objects: scenario
                .objects
                .iter()
                .filter_map(|o| {
                    o.interaction.as_ref().map(|space| InteractionObject {
                        polygon: space.polygon.iter().map(|q| v2(*q)).collect(),
                        centre: Vec2::new(o.pose[0], o.pose[1]),
                    })
                })
                .collect(),
            now: GroundTruth::default(),
            log: SceneLog::new(Vec::new(), Vec::new()),
            scenario,
        };
        // The objects are the world's for good; the people's radii come with each reset.
        world.log =
            SceneLog::new(Vec::new(), world.interaction_objects.iter().map(|o| o.polygon.clone()).collect());
        let clear = world.start_areas();
        world.crowd = Crowd::spawn_scripted(
            &world.scenario.persons,
            &world.scripts,
            &world.scenario.episode.randomize,
            SocialForceParams::default(),
            &clear,
            &mut world.rng,
        );
        Ok(world)
    }

    /// The discs no walker may start in (centre, radius in m): each robot's nominal start with
    /// the robot's radius, its start jitter and [`START_CLEARANCE`].
    fn start_areas(&self) -> Vec<(Vec2, f64)> {
        let jitter = self.scenario.episode.randomize.robot_start_jitter * std::f64::consts::SQRT_2;
        self.scenario
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(r, st)| (Vec2::new(r.start[0], r.start[1]), st.radius + jitter + START_CLEARANCE))
            .collect()
    }

    /// The validated scenario.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The static geometry.
    pub fn geometry(&self) -> &StaticGeometry {
        &self.geometry
    }

    /// Layout of the per-robot output rows.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Number of robots.
    pub fn num_robots(&self) -> usize {
        self.statics.len()
    }

    /// Number of people.
    pub fn num_people(&self) -> usize {
        self.scenario.persons.len()
    }

    /// Control steps since the last reset.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Simulation time since the last reset (s).
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.scenario.control_dt()
    }

    /// Time of day (seconds after midnight) at the current step.
    pub fn time_of_day(&self) -> f64 {
        (self.scenario.scene.start_time + self.time()).rem_euclid(86400.0)
    }

    /// The inflated cost grid robot `i` plans on.
    pub fn cost_grid(&self, i: usize) -> Option<&CostGrid> {
        self.statics.get(i).map(|s| &self.grids[s.grid_index].grid)
    }

    /// The global path robot `i` is following (world-frame waypoints).
    pub fn path(&self, i: usize) -> Option<&[Vec2]> {
        self.robots.get(i).map(|r| r.follower.path())
    }

    /// Geodesic (shortest collision-free) distance from robot `i`'s nominal start to its goal (m).
    pub fn geodesic_start_distance(&self, i: usize) -> Option<f64> {
        self.statics.get(i).map(|s| s.geodesic_from_start)
    }

    /// Plans a plain A* path for robot `i`'s footprint between two points.
    pub fn plan(&mut self, i: usize, start: Vec2, goal: Vec2) -> Option<Vec<Vec2>> {
        let grid = &self.grids[self.statics.get(i)?.grid_index].grid;
        plan_path(&mut self.planner, grid, start, goal)
    }

    /// Chooses which robots' built-in planners run (one flag per robot; all run by default).
    /// A robot whose planner is off is driven only by [`World::command`]: it computes no path
    /// updates, local planner or re-plans (saving their cost when a policy drives it), its
    /// `planner_action` is a stop command and its `mode` follow_path. It stays an obstacle, and
    /// the other robots' planners still see it. Kept across resets.
    pub fn set_planning(&mut self, planning: &[bool]) -> Result<()> {
        if planning.len() != self.num_robots() {
            return Err(CoreError::input(
                "planning",
                format!("{} flags (one per robot)", self.num_robots()),
                format!("{} flags", planning.len()),
            ));
        }
        self.planning = planning.to_vec();
        Ok(())
    }

    /// Every metric of every robot's episode so far (`design/metrics.md`; the zones are the
    /// scenario's Hall zones, the thresholds [`MetricParams::default`]).
    ///
    /// # Errors
    /// [`CoreError::Input`] before the first reset, or if a recorded value is not finite.
    pub fn episode_metrics(&self) -> Result<Vec<EpisodeReport>> {
        let all: Vec<usize> = (0..self.robots.len()).collect();
        self.robot_metrics(&all)
    }

    /// [`World::episode_metrics`] of the robots `robots` only (indices, in the order given).
    ///
    /// # Errors
    /// As [`World::episode_metrics`], and [`CoreError::Input`] for an index out of range.
    pub fn robot_metrics(&self, robots: &[usize]) -> Result<Vec<EpisodeReport>> {
        if !self.started {
            return Err(CoreError::input(
                "episode_metrics",
                "a call after reset()",
                "a call before the first reset()",
            ));
        }
        if let Some(&bad) = robots.iter().find(|&&i| i >= self.robots.len()) {
            return Err(CoreError::input(
                "robots",
                format!("robot indices below {}", self.robots.len()),
                bad.to_string(),
            ));
        }
        let z = self.social.config().zones;
        let clearance = |p: Vec2| self.geometry.distance(p);
        robots
            .iter()
            .map(|&i| {
                self.robots[i].recorder.evaluate(
                    &self.log,
                    &clearance,
                    [z.intimate, z.personal, z.social],
                    MetricParams::default(),
                )
            })
            .collect()
    }

    /// The recorded poses `[x, y, theta]` of robot `i` since the reset, instant 0 first.
    pub fn trajectory(&self, i: usize) -> Option<&[[f64; 3]]> {
        self.robots.get(i).map(|r| r.recorder.poses())
    }

    /// The plain A* path from robot `i`'s episode start to its goal (Daza et al. 2021's D_A*).
    pub fn astar_path(&self, i: usize) -> Option<&[Vec2]> {
        self.robots.get(i).map(|r| r.recorder.astar_path())
    }

    /// Updates the ground-truth o-spaces, interactions and object activities of this instant.
    fn observe_interactions(&mut self) {
        interactions(
            &self.crowd.pos,
            &self.crowd.vel,
            &self.crowd.group,
            &self.interaction_objects,
            &mut self.now.ospaces,
            &mut self.now.links,
        );
        let tod = self.time_of_day();
        self.social.object_activity(tod, &mut self.now.active);
    }

    /// The people: positions, velocities, headings and radii.
    pub fn crowd(&self) -> &Crowd {
        &self.crowd
    }

    fn check_out(&self, out: &[f64], people_out: &[f64]) -> Result<()> {
        let want = self.layout.stride * self.num_robots();
        if out.len() != want {
            return Err(CoreError::input(
                "out",
                format!("{want} values ({} robots x {})", self.num_robots(), self.layout.stride),
                format!("{} values", out.len()),
            ));
        }
        let want_p = self.num_people() * PERSON_OUT;
        if people_out.len() != want_p {
            return Err(CoreError::input(
                "people_out",
                format!("{want_p} values ({} people x {PERSON_OUT})", self.num_people()),
                format!("{} values", people_out.len()),
            ));
        }
        Ok(())
    }

    /// Starts a new episode from `seed`: respawns the people, places the robots (with the
    /// scenario's start jitter), plans their paths and fills `out` (observations at the start,
    /// the first planner command, the start poses in `pose`) and `people_out` ([`PERSON_OUT`]
    /// values per person).
    pub fn reset(&mut self, seed: u64, out: &mut [f64], people_out: &mut [f64]) -> Result<()> {
        self.check_out(out, people_out)?;
        self.rng = ChaCha8Rng::seed_from_u64(seed);
        let clear = self.start_areas();
        self.crowd = Crowd::spawn_scripted(
            &self.scenario.persons,
            &self.scripts,
            &self.scenario.episode.randomize,
            SocialForceParams::default(),
            &clear,
            &mut self.rng,
        );
        self.steps = 0;
        // The last episode's recorders are restarted (their buffers keep their memory).
        let mut recorders: Vec<Option<EpisodeRecorder>> =
            self.robots.drain(..).map(|r| Some(r.recorder)).collect();
        self.observe_interactions();
        self.log.restart(&self.crowd.radius);
        self.log.push(&self.now.snapshot(&self.crowd));
        let jitter = self.scenario.episode.randomize.robot_start_jitter;
        for i in 0..self.statics.len() {
            let r = &self.scenario.robots[i];
            let nominal = Vec2::new(r.start[0], r.start[1]);
            let mut start = nominal;
            if jitter > 0.0 {
                // Draw until the jittered start is clear of the static geometry (bounded tries).
                for _ in 0..16 {
                    let c = nominal
                        + Vec2::new(
                            self.rng.random_range(-jitter..=jitter),
                            self.rng.random_range(-jitter..=jitter),
                        );
                    if !self.geometry.contains(c) && self.geometry.distance(c) >= self.statics[i].radius {
                        start = c;
                        break;
                    }
                }
            }
            let st = &self.statics[i];
            let path = if start == nominal {
                st.nominal_path.clone()
            } else {
                let grid = &self.grids[st.grid_index].grid;
                plan_path(&mut self.planner, grid, start, st.route[0])
                    .unwrap_or_else(|| st.nominal_path.clone())
            };
            let pose = [start.x, start.y, wrap_angle(r.start[2])];
            let geodesic = st.fields[0].distance(start);
            // The reference path and length of a tour run through its waypoints.
            let mut astar_path = path.clone();
            let mut geodesic_length = geodesic;
            for (k, leg) in st.legs.iter().enumerate() {
                astar_path.extend_from_slice(&leg[1..]);
                geodesic_length += st.fields[k + 1].distance(st.route[k]);
            }
            let setup = RecorderSetup {
                dt: self.scenario.control_dt(),
                robot_radius: st.radius,
                goal: st.goal,
                success_radius: self.scenario.episode.success_radius,
                astar_path,
                geodesic_length,
            };
            let recorder = match recorders.get_mut(i).and_then(Option::take) {
                Some(mut r) => {
                    r.restart(setup, pose);
                    r
                }
                None => EpisodeRecorder::new(setup, pose),
            };
            self.robots.push(RobotRuntime {
                pose,
                velocity: Vec2::zeros(),
                wz: 0.0,
                exec_v: Vec2::zeros(),
                exec_wz: 0.0,
                proposed_v: Vec2::zeros(),
                proposed_wz: 0.0,
                follower: PathFollower::new(path, FollowerParams::default()),
                recorder,
                outcome: Outcome::Running,
                geodesic,
                user_command: false,
                social_path: None,
                last_plan_step: 0,
                replans: 0,
                band: None,
                mode: Mode::FollowPath,
                leg: 0,
                dwelling: false,
                dwell_left: 0.0,
            });
        }
        self.started = true;
        self.ended.fill(false);
        for i in 0..self.robots.len() {
            if self.statics[i].planner == PlannerKind::Eband {
                self.robots[i].band =
                    ElasticBand::new(self.robots[i].follower.path(), self.statics[i].eband).ok();
            }
        }
        if (0..self.robots.len()).any(|i| self.planning[i] && self.statics[i].planner.social_global()) {
            self.perceive()?;
            let tod = self.time_of_day();
            for i in 0..self.robots.len() {
                if self.planning[i] && self.statics[i].planner.social_global() {
                    let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
                    self.social_plan(i, p, tod);
                    self.robots[i].replans = 0;
                }
            }
        }
        let stride = self.layout.stride;
        for i in 0..self.robots.len() {
            let row = &mut out[i * stride..(i + 1) * stride];
            row.fill(0.0);
        }
        self.observe_all(out);
        self.plan_all(out);
        self.write_people(out, people_out);
        Ok(())
    }

    /// The first half of a control step: executes normalised actions instead of the built-in
    /// planners' commands. `actions` holds 3 values per robot in [-1, 1] (vx, vy scaled by the
    /// robot's max speed, wz by its max angular speed, robot frame); values outside are clipped
    /// to [-1, 1] as in Gymnasium's MuJoCo environments. All three values NaN let the robot's
    /// built-in planner drive it (autopilot). The limited commands are written to `out`'s
    /// `command`, which the physics then executes before [`World::step`]. The Python binding
    /// makes the two halves and the physics between them one call (`World.step`).
    ///
    /// # Errors
    /// [`CoreError::Input`] before the first reset, for a wrong number of values, or for a robot
    /// whose values are partly non-finite; nothing is changed then.
    pub fn command(&mut self, actions: &[f64], out: &mut [f64]) -> Result<()> {
        let n = self.num_robots();
        if !self.started {
            return Err(CoreError::input(
                "command",
                "a call after reset()",
                "a call before the first reset()",
            ));
        }
        if actions.len() != 3 * n || out.len() != self.layout.stride * n {
            return Err(CoreError::input(
                "actions",
                format!("{} values ({n} robots x 3)", 3 * n),
                format!("{} values", actions.len()),
            ));
        }
        for (i, a) in actions.chunks_exact(3).enumerate() {
            if !a.iter().all(|v| v.is_nan()) && a.iter().any(|v| !v.is_finite()) {
                return Err(CoreError::input(
                    format!("action[{i}]"),
                    "3 finite numbers in [-1, 1] (vx, vy, wz normalised), or 3 NaN (autopilot)",
                    format!("[{}, {}, {}]", a[0], a[1], a[2]),
                ));
            }
        }
        let dt = self.scenario.control_dt();
        let cmd = self.layout.section("command").map_or(0, |s| s.offset);
        for (i, a) in actions.chunks_exact(3).enumerate() {
            if a.iter().all(|v| v.is_nan()) {
                continue;
            }
            let st = &self.statics[i];
            let rb = &mut self.robots[i];
            if rb.outcome != Outcome::Running {
                continue;
            }
            let body = Vec2::new(a[0].clamp(-1.0, 1.0), a[1].clamp(-1.0, 1.0)) * st.limits.max_speed;
            let wz = a[2].clamp(-1.0, 1.0) * st.limits.max_angular_speed;
            let desired = body_to_world(body, rb.pose[2]);
            let (v, w) = st.limits.apply(desired, wz, rb.exec_v, rb.exec_wz, dt);
            rb.proposed_v = v;
            rb.proposed_wz = w;
            rb.user_command = true;
            let b = world_to_body(v, rb.pose[2]);
            let row = &mut out[i * self.layout.stride..];
            row[cmd] = b.x;
            row[cmd + 1] = b.y;
            row[cmd + 2] = w;
        }
        Ok(())
    }

    /// The second half of a control step, after the physics executed `out`'s `command`: `state`
    /// holds 6 values per robot (x, y, theta, and the world-frame velocities vx, vy, wz),
    /// `contacts` one byte of `CONTACT_*` bits per robot. Advances the people, records the
    /// metrics and rewards, builds the observations and runs the built-in planners for the next
    /// command; fills `out` and `people_out` (see [`Layout`] and [`PERSON_OUT`]).
    pub fn step(
        &mut self,
        state: &[f64],
        contacts: &[u8],
        out: &mut [f64],
        people_out: &mut [f64],
    ) -> Result<()> {
        if !self.started {
            return Err(CoreError::input("step", "a call after reset()", "a call before the first reset()"));
        }
        self.check_out(out, people_out)?;
        let n = self.num_robots();
        if state.len() != 6 * n {
            return Err(CoreError::input(
                "state",
                format!("{} values ({n} robots x 6)", 6 * n),
                format!("{} values", state.len()),
            ));
        }
        if contacts.len() != n {
            return Err(CoreError::input(
                "contacts",
                format!("{n} values"),
                format!("{} values", contacts.len()),
            ));
        }
        if let Some(k) = state.iter().position(|v| !v.is_finite()) {
            return Err(CoreError::input(
                format!("state[{}][{}]", k / 6, k % 6),
                "finite robot poses and velocities",
                format!("{}", state[k]),
            ));
        }
        let dt = self.scenario.control_dt();
        for (e, rb) in self.ended.iter_mut().zip(&self.robots) {
            *e = rb.outcome != Outcome::Running;
        }
        // The executed command becomes the reference for the acceleration limit.
        for rb in &mut self.robots {
            rb.exec_v = rb.proposed_v;
            rb.exec_wz = rb.proposed_wz;
            rb.user_command = false;
        }
        for (i, rb) in self.robots.iter_mut().enumerate() {
            let s = &state[6 * i..6 * i + 6];
            rb.pose = [s[0], s[1], wrap_angle(s[2])];
            rb.velocity = Vec2::new(s[3], s[4]);
            rb.wz = s[5];
        }
        // People move to the same instant as the robots (the followers of a tour see its robot).
        let guides: Vec<GuideState> = self
            .robots
            .iter()
            .map(|rb| GuideState {
                pos: Vec2::new(rb.pose[0], rb.pose[1]),
                target: rb.leg + 1,
                dwelling: rb.dwelling || rb.outcome == Outcome::Success,
            })
            .collect();
        self.crowd.set_guides(&guides);
        let robots: Vec<(Vec2, f64, Vec2)> = self
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(rb, st)| (Vec2::new(rb.pose[0], rb.pose[1]), st.radius, rb.velocity))
            .collect();
        self.crowd.step(dt, &robots, &self.geometry, &self.field);
        self.steps += 1;
        self.observe_interactions();
        self.log.push(&self.now.snapshot(&self.crowd));
        self.advance_tours(dt);
        let out_of_time = self.time() >= self.scenario.episode.max_time - 1e-9;
        let stride = self.layout.stride;
        let sec = |name: &str| self.layout.section(name).map_or(0, |s| s.offset);
        let (terms_off, reward_off, flags_off) = (sec("reward_terms"), sec("reward"), sec("flags"));
        let w = self.scenario.reward.clone();
        for i in 0..n {
            let pose = self.robots[i].pose;
            let p = Vec2::new(pose[0], pose[1]);
            let d = self.closest_person(p);
            let robot_gap = self.closest_robot_gap(i);
            if self.robots[i].outcome != Outcome::Running {
                let row = &mut out[i * stride..(i + 1) * stride];
                row[terms_off..terms_off + REWARD_TERMS.len()].fill(0.0);
                row[reward_off] = 0.0;
                continue;
            }
            let st = &self.statics[i];
            let rb = &mut self.robots[i];
            // Two robots overlapping at a control instant collide even if the physics missed it
            // (Francis et al.'s agent collisions, AC).
            rb.recorder.observe_robot_gap(robot_gap);
            let bits = contacts[i] | if robot_gap < 0.0 { CONTACT_ROBOT } else { 0 };
            let outcome = rb.recorder.record(&self.log, pose, bits, out_of_time);
            rb.outcome = outcome;
            let row = &mut out[i * stride..(i + 1) * stride];
            let terms = &mut row[terms_off..terms_off + REWARD_TERMS.len()];
            let geo = st.fields[rb.leg].distance(p);
            let progress = if geo.is_finite() && rb.geodesic.is_finite() { rb.geodesic - geo } else { 0.0 };
            if geo.is_finite() {
                rb.geodesic = geo;
            }
            terms[0] = w.progress * progress;
            terms[1] = if outcome == Outcome::Success { w.success } else { 0.0 };
            terms[2] = if outcome == Outcome::Collision { w.collision } else { 0.0 };
            terms[3] = w.time;
            terms[4] = w.personal_space * ((PERSONAL_ZONE - d) / PERSONAL_ZONE).max(0.0);
            // Summed in the documented order, so Python's sum of the terms equals it exactly.
            let mut total = 0.0;
            for t in terms.iter() {
                total += *t;
            }
            row[reward_off] = total;
            let flags = &mut row[flags_off..flags_off + 4];
            flags[0] = f64::from(u8::from(matches!(outcome, Outcome::Success | Outcome::Collision)));
            flags[1] = f64::from(u8::from(outcome == Outcome::Timeout));
            flags[2] = f64::from(u8::from(outcome == Outcome::Success));
            flags[3] = f64::from(u8::from(outcome == Outcome::Collision));
        }
        self.observe_all(out);
        self.plan_all(out);
        self.write_people(out, people_out);
        Ok(())
    }

    /// Tours: a robot that reaches its current waypoint stands there for its `dwell` seconds,
    /// then heads for the next target (re-planning its path); progress is measured toward the
    /// new target from then on.
    fn advance_tours(&mut self, dt: f64) {
        let radius = self.scenario.episode.success_radius;
        let mut next = Vec::new();
        for (i, (rb, st)) in self.robots.iter_mut().zip(&self.statics).enumerate() {
            if rb.outcome != Outcome::Running || rb.leg + 1 >= st.route.len() {
                continue;
            }
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            if !rb.dwelling && (p - st.route[rb.leg]).norm() <= radius {
                rb.dwelling = true;
                rb.dwell_left = st.dwell;
            }
            if rb.dwelling {
                if rb.dwell_left <= 1e-9 {
                    rb.dwelling = false;
                    rb.dwell_left = 0.0;
                    rb.leg += 1;
                    rb.geodesic = st.fields[rb.leg].distance(p);
                    next.push(i);
                } else {
                    rb.dwell_left -= dt;
                }
            }
        }
        for i in next {
            self.start_leg(i);
        }
    }

    /// Plans robot `i`'s path to its (new) current target with its planner.
    fn start_leg(&mut self, i: usize) {
        let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
        let st = &self.statics[i];
        let target = st.route[self.robots[i].leg];
        let grid = &self.grids[st.grid_index].grid;
        let path = plan_path(&mut self.planner, grid, p, target).unwrap_or_else(|| vec![p, target]);
        let rb = &mut self.robots[i];
        rb.follower = PathFollower::new(path, FollowerParams::default());
        rb.social_path = None;
        if st.planner == PlannerKind::Eband {
            rb.band = ElasticBand::new(rb.follower.path(), st.eband).ok();
        }
        if self.planning[i] && st.planner.social_global() && self.perceive().is_ok() {
            let tod = self.time_of_day();
            self.social_plan(i, p, tod);
        }
    }

    /// Closest person to `p`: (centre distance, surface gap for a robot of `radius`).
    /// Centre distance from `p` to the closest person (m; +inf without people).
    fn closest_person(&self, p: Vec2) -> f64 {
        self.crowd.pos.iter().map(|q| (q - p).norm()).fold(f64::INFINITY, f64::min)
    }

    /// Closest surface gap from robot `i` to any other robot (+inf alone).
    fn closest_robot_gap(&self, i: usize) -> f64 {
        let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
        let r = self.statics[i].radius;
        let mut best = f64::INFINITY;
        for (j, (o, st)) in self.robots.iter().zip(&self.statics).enumerate() {
            if j != i {
                best = best.min((Vec2::new(o.pose[0], o.pose[1]) - p).norm() - r - st.radius);
            }
        }
        best
    }

    /// Writes the people's poses and contact hints into `people_out`, and each robot's
    /// `near_static` hint and the time of day into its row of `out`.
    fn write_people(&self, out: &mut [f64], people_out: &mut [f64]) {
        let stride = self.layout.stride;
        let sec = |name: &str| self.layout.section(name).map_or(0, |s| s.offset);
        let (near_off, robot_off, tod_off) = (sec("near_static"), sec("near_robot"), sec("time_of_day"));
        let dt = self.scenario.control_dt();
        let tod = self.time_of_day();
        // Robot discs grown by the contact range and what the robot can travel in one period.
        let reach: Vec<(Vec2, f64)> = self
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(rb, st)| {
                let travel = (rb.velocity.norm() * dt).min(1e6);
                (Vec2::new(rb.pose[0], rb.pose[1]), st.radius + CONTACT_RANGE + travel)
            })
            .collect();
        for (i, &(p, r)) in reach.iter().enumerate() {
            // Centre distance to the nearest wall or object edge, looked up within `r` only (a
            // robot cannot be deep inside an object: the physics pushes it out first).
            let near = self.geometry.boundary_distance_within(p, r) < r;
            let near_robot = reach
                .iter()
                .enumerate()
                .any(|(j, &(q, rq))| j != i && (q - p).norm_squared() < (r + rq - CONTACT_RANGE).powi(2));
            let row = &mut out[i * stride..(i + 1) * stride];
            row[near_off] = f64::from(u8::from(near));
            row[robot_off] = f64::from(u8::from(near_robot));
            row[tod_off] = tod;
        }
        for (k, chunk) in people_out.chunks_exact_mut(PERSON_OUT).enumerate() {
            let q = self.crowd.pos[k];
            let rk = self.crowd.radius[k];
            let near = reach.iter().any(|&(p, r)| (q - p).norm_squared() < (r + rk) * (r + rk));
            chunk[0] = q.x;
            chunk[1] = q.y;
            let h = self.crowd.heading[k];
            chunk[2] = h;
            chunk[3] = f64::from(u8::from(near));
            let (sin, cos) = (0.5 * h).sin_cos();
            chunk[4] = cos;
            chunk[5] = sin;
        }
    }

    /// Fills the observation sections and `pose` of every robot's row (only `pose` for robots
    /// whose episode had ended before this step: their last observation stays).
    fn observe_all(&mut self, out: &mut [f64]) {
        let stride = self.layout.stride;
        let sec = |name: &str| self.layout.section(name).map_or(0, |s| s.offset);
        let (o_robot, o_people, o_mask, o_lidar, o_pose) =
            (sec("obs_robot"), sec("obs_people"), sec("obs_people_mask"), sec("obs_lidar"), sec("pose"));
        let (o_peers, o_peer_mask) = (sec("obs_robots"), sec("obs_robots_mask"));
        let others = self.robots.len().saturating_sub(1);
        let k = self.scenario.sensors.k_nearest;
        let rays = self.scenario.sensors.lidar_rays;
        let range = self.scenario.sensors.lidar_range;
        let diag = self.obs_position_bound();
        for i in 0..self.robots.len() {
            let rb = &self.robots[i];
            let st = &self.statics[i];
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            let th = rb.pose[2];
            let row = &mut out[i * stride..(i + 1) * stride];
            row[o_pose..o_pose + 3].copy_from_slice(&rb.pose);
            if self.ended[i] {
                continue;
            }
            let g = world_to_body(st.route[rb.leg] - p, th);
            let v = world_to_body(rb.velocity, th);
            let obs = &mut row[o_robot..o_robot + ROBOT_FEATURES];
            obs[0] = g.x.clamp(-diag, diag);
            obs[1] = g.y.clamp(-diag, diag);
            obs[2] = v.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            obs[3] = v.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            obs[4] = rb.wz.clamp(-OBS_MAX_ANGULAR, OBS_MAX_ANGULAR);
            // K nearest people within sensor range, ties broken by index.
            self.scratch_people.clear();
            for (j, q) in self.crowd.pos.iter().enumerate() {
                let d = (q - p).norm();
                if d <= range {
                    self.scratch_people.push((d, j));
                }
            }
            self.scratch_people.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let people = &mut row[o_people..o_people + k * PERSON_FEATURES];
            people.fill(0.0);
            let mut mask = [0.0; 64];
            for (slot, &(_, j)) in self.scratch_people.iter().take(k).enumerate() {
                let rel = world_to_body(self.crowd.pos[j] - p, th);
                let vel = world_to_body(self.crowd.vel[j], th);
                let f = &mut people[slot * PERSON_FEATURES..(slot + 1) * PERSON_FEATURES];
                f[0] = rel.x.clamp(-range, range);
                f[1] = rel.y.clamp(-range, range);
                f[2] = vel.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[3] = vel.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[4] = self.crowd.radius[j];
                mask[slot] = 1.0;
            }
            row[o_mask..o_mask + k].copy_from_slice(&mask[..k]);
            // The other robots within sensor range, nearest first (ties by index), with their ids.
            self.scratch_people.clear();
            for (j, o) in self.robots.iter().enumerate() {
                let d = (Vec2::new(o.pose[0], o.pose[1]) - p).norm();
                if j != i && d <= range {
                    self.scratch_people.push((d, j));
                }
            }
            self.scratch_people.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let peers = &mut row[o_peers..o_peers + others * PEER_FEATURES];
            peers.fill(0.0);
            for (slot, &(_, j)) in self.scratch_people.iter().enumerate() {
                let o = &self.robots[j];
                let rel = world_to_body(Vec2::new(o.pose[0], o.pose[1]) - p, th);
                let vel = world_to_body(o.velocity, th);
                let f = &mut peers[slot * PEER_FEATURES..(slot + 1) * PEER_FEATURES];
                f[0] = j as f64;
                f[1] = rel.x.clamp(-range, range);
                f[2] = rel.y.clamp(-range, range);
                f[3] = vel.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[4] = vel.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[5] = self.statics[j].radius;
                f[6] = f64::from(u8::from(o.outcome == Outcome::Running));
            }
            let seen = self.scratch_people.len();
            let peer_mask = &mut row[o_peer_mask..o_peer_mask + others];
            peer_mask.fill(0.0);
            peer_mask[..seen].fill(1.0);
            // Lidar sees the static world, the people and the other robots.
            self.scratch_discs.clear();
            for (q, r) in self.crowd.pos.iter().zip(&self.crowd.radius) {
                self.scratch_discs.push((*q, *r));
            }
            for (j, (other, ost)) in self.robots.iter().zip(&self.statics).enumerate() {
                if j != i {
                    self.scratch_discs.push((Vec2::new(other.pose[0], other.pose[1]), ost.radius));
                }
            }
            let scan = &mut row[o_lidar..o_lidar + rays];
            // Failures are an empty buffer or non-finite inputs, which the layout and the checks
            // of `step` rule out.
            let _ = self.scanners[i].scan(&self.geometry, &self.scratch_discs, p, th, range, scan);
        }
    }

    /// Bound on goal offsets in observations: the diagonal of the map, rounded up (metres).
    pub fn obs_position_bound(&self) -> f64 {
        let b = self.scenario.scene.bounds;
        ((b[2] - b[0]).hypot(b[3] - b[1])).ceil()
    }

    /// The robots as discs for perception (position, radius, velocity).
    fn robot_discs(&self) -> Vec<RobotDisc> {
        self.robots
            .iter()
            .zip(&self.statics)
            .map(|(r, s)| RobotDisc {
                pos: Vec2::new(r.pose[0], r.pose[1]),
                radius: s.radius,
                vel: r.velocity,
            })
            .collect()
    }

    /// Perceives the people's groups and individuals now.
    pub fn perceive(&mut self) -> Result<()> {
        let discs = self.robot_discs();
        self.social.perceive(&self.crowd, &discs)
    }

    /// The social model, maps and planner.
    pub fn social(&self) -> &SocialPlanning {
        &self.social
    }

    /// The index of robot `i`'s inflated grid (and social map), or an input error.
    fn grid_of(&self, i: usize) -> Result<usize> {
        self.statics.get(i).map(|st| st.grid_index).ok_or_else(|| {
            CoreError::input("robot", format!("an index below {}", self.statics.len()), i.to_string())
        })
    }

    /// Updates robot `i`'s social map for the current people and the agenda at `time_of_day`.
    pub fn update_social_map(&mut self, i: usize, time_of_day: f64) -> Result<()> {
        let k = self.grid_of(i)?;
        if self.social.perception().is_none() {
            self.perceive()?;
        }
        self.social.update_map(k, time_of_day);
        Ok(())
    }

    /// Plans a social A* path for robot `i`'s footprint between two points at `time_of_day`,
    /// with the people as perceived now.
    pub fn plan_social(
        &mut self,
        i: usize,
        start: Vec2,
        goal: Vec2,
        time_of_day: f64,
    ) -> Result<Option<Vec<Vec2>>> {
        let k = self.grid_of(i)?;
        self.perceive()?;
        Ok(self.social.plan(&mut self.planner, k, start, goal, time_of_day).map(|p| p.points))
    }

    /// Robot `i`'s social map (as last updated).
    pub fn social_map_of(&self, i: usize) -> Option<&crate::socialmap::SocialMap> {
        self.social.map(self.statics.get(i)?.grid_index)
    }

    /// Number of times robot `i`'s social path was re-planned (and changed) this episode.
    pub fn replans(&self, i: usize) -> usize {
        self.robots.get(i).map_or(0, |r| r.replans)
    }

    /// (Re-)plans robot `i`'s social path from `p`; falls back to the plain path when the goal
    /// is unreachable on the social map (for example inside someone's intimate zone). A new
    /// social path replaces the current one only when it is [`SOCIAL_REPLAN_GAIN`] cheaper.
    fn social_plan(&mut self, i: usize, p: Vec2, time_of_day: f64) {
        let st = &self.statics[i];
        let k = st.grid_index;
        let goal = st.route[self.robots[i].leg];
        let left = self.robots[i].social_path.as_ref().map(|old| {
            let grid = &self.grids[k].grid;
            self.social.remaining_cost(old, p, time_of_day, |a, b| segment_clear(grid, a, b))
        });
        if let Some(left) = left {
            // No path can cost less than the way's length, and none is shorter than the geodesic
            // distance (the 8-connected field overestimates it by at most 8.24%, and the cost
            // counts the path in samples): when what is left is already within the gain of that,
            // a search could not find a path worth changing to.
            let field = &st.fields[self.robots[i].leg];
            let shortest = field.distance(p) / GRID_DETOUR
                - 2.0 * field.resolution()
                - crate::plan::social::SAMPLE_SPACING;
            if left.is_finite() && (1.0 - SOCIAL_REPLAN_GAIN) * left <= shortest {
                self.robots[i].last_plan_step = self.steps;
                return;
            }
        }
        let plan = self.social.plan(&mut self.planner, k, p, goal, time_of_day);
        if let (Some(new), Some(left)) = (&plan, left)
            && left.is_finite()
            && SocialPlanning::planned_cost(new) > (1.0 - SOCIAL_REPLAN_GAIN) * left
        {
            // Not worth a change of way: keep the current path, look again later.
            self.robots[i].last_plan_step = self.steps;
            return;
        }
        let rb = &mut self.robots[i];
        match plan {
            Some(sp) => {
                rb.follower = PathFollower::new(sp.points.clone(), FollowerParams::default());
                rb.social_path = Some(sp);
            }
            None => {
                let grid = &self.grids[k].grid;
                if let Some(path) = plan_path(&mut self.planner, grid, p, goal) {
                    rb.follower = PathFollower::new(path, FollowerParams::default());
                }
                rb.social_path = None;
            }
        }
        rb.last_plan_step = self.steps;
        rb.replans += 1;
    }

    /// Re-planning triggers of the social planners (every few steps).
    fn social_checks(&mut self) {
        let due: Vec<usize> = (0..self.robots.len())
            .filter(|&i| {
                let rb = &self.robots[i];
                self.statics[i].planner.social_global()
                    && self.planning[i]
                    && rb.outcome == Outcome::Running
                    && !rb.dwelling
                    && self.steps > 0
                    && self.steps.is_multiple_of(SOCIAL_CHECK_PERIOD)
                    && self.steps >= rb.last_plan_step + SOCIAL_MIN_REPLAN
            })
            .collect();
        if due.is_empty() {
            return;
        }
        if self.perceive().is_err() {
            return;
        }
        let tod = self.time_of_day();
        for i in due {
            let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
            let off_path = self.robots[i].follower.step_preview_cross_track(p) > 1.0;
            let trigger = match &self.robots[i].social_path {
                Some(path) => self.social.check(path, p, tod),
                None => Trigger::Blocked, // on the plain fallback: try the social map again
            };
            let stale = self.steps >= self.robots[i].last_plan_step + SOCIAL_REFRESH;
            if trigger != Trigger::None || off_path || stale {
                self.social_plan(i, p, tod);
            }
        }
    }

    /// The people (and robots that joined human interactions) as the local planners see them:
    /// each person keeps the robot's centre out of their intimate zone; each group adds one
    /// heavier individual covering its o-space. Entries carry the robot index they stand for,
    /// if any, so a robot does not avoid itself.
    fn controller_people(&self, robot_radius: f64) -> Vec<(CtlPerson, Option<usize>)> {
        let intimate = self.social.config().zones.intimate;
        let personal = self.social.config().zones.personal;
        let keep = |r: f64| r.max(intimate - robot_radius);
        let c = &self.crowd;
        let mut out: Vec<(CtlPerson, Option<usize>)> = Vec::with_capacity(c.len() + 4);
        let per = self.social.perception();
        let group_of =
            |k: usize| per.map(|p| p.groups.members[p.groups.labels[k]].len() > 1).unwrap_or(false);
        for k in 0..c.len() {
            let weight = if group_of(k) { self.control.group_weight } else { 1.0 };
            out.push((
                CtlPerson {
                    pos: c.pos[k],
                    vel: c.vel[k],
                    keep_out: keep(c.radius[k]),
                    weight,
                    comfort: personal,
                },
                None,
            ));
        }
        if let Some(p) = per {
            for ind in &p.individuals {
                if ind.members.len() + ind.robots.len() < 2 {
                    continue;
                }
                let mut pts: Vec<Vec2> = ind.members.iter().map(|&k| c.pos[k]).collect();
                pts.extend(
                    ind.robots
                        .iter()
                        .filter_map(|&r| self.robots.get(r))
                        .map(|r| Vec2::new(r.pose[0], r.pose[1])),
                );
                let ospace = pts.iter().map(|q| (q - ind.centre).norm()).sum::<f64>() / pts.len() as f64;
                let vel = ind.members.iter().fold(Vec2::zeros(), |a, &k| a + c.vel[k])
                    / ind.members.len().max(1) as f64;
                out.push((
                    CtlPerson {
                        pos: ind.centre,
                        vel,
                        keep_out: ospace,
                        weight: self.control.group_weight,
                        comfort: 0.0,
                    },
                    None,
                ));
                for &r in &ind.robots {
                    if let (Some(rb), Some(st)) = (self.robots.get(r), self.statics.get(r)) {
                        let q = Vec2::new(rb.pose[0], rb.pose[1]);
                        out.push((
                            CtlPerson {
                                pos: q,
                                vel: rb.velocity,
                                keep_out: keep(st.radius),
                                weight: 1.0,
                                comfort: personal,
                            },
                            Some(r),
                        ));
                    }
                }
            }
        }
        out
    }

    /// Runs every robot's built-in planner: the next command (written to `command`), the same
    /// command as a normalised action (`planner_action`) and the local planner's `mode`.
    fn plan_all(&mut self, out: &mut [f64]) {
        let stride = self.layout.stride;
        let sec = |name: &str| self.layout.section(name).map_or(0, |s| s.offset);
        let (cmd, act, mode_off) = (sec("command"), sec("planner_action"), sec("mode"));
        let dt = self.scenario.control_dt();
        self.social_checks();
        let n = self.robots.len();
        let local = |k: PlannerKind| {
            matches!(k, PlannerKind::Social | PlannerKind::SocialMomentum | PlannerKind::Orca)
        };
        if (0..n).any(|i| {
            let k = self.statics[i].planner;
            self.planning[i] && (local(k) || k == PlannerKind::Eband)
        }) {
            // Groups and robots joining them, as perceived now (the social planners' perception).
            let _ = self.perceive();
        }
        let mut desired: Vec<Vec2> = vec![Vec2::zeros(); n];
        let mut orca_active: Vec<usize> = Vec::new();
        let mut partial_goals: Vec<Vec2> = vec![Vec2::zeros(); n];
        for i in 0..n {
            if self.robots[i].outcome != Outcome::Running || !self.planning[i] {
                self.robots[i].mode = Mode::FollowPath;
                continue;
            }
            if self.robots[i].dwelling {
                // At a tour stop: stand still (the desired velocity stays zero).
                self.robots[i].mode = Mode::Wait;
                continue;
            }
            let planner = self.statics[i].planner;
            let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
            let theta = self.robots[i].pose[2];
            if planner == PlannerKind::Eband {
                self.update_band(i, p);
            }
            // Path following: the nominal command, and the partial goal for the local planners.
            let st = &self.statics[i];
            let grid = &self.grids[st.grid_index].grid;
            let visible = |a: Vec2, b: Vec2| segment_clear(grid, a, b);
            let rb = &mut self.robots[i];
            let mut o =
                rb.follower.step_visible(p, theta, st.limits.max_speed, st.limits.max_accel, dt, &visible);
            if o.cross_track > rb.follower.params().replan_distance && !planner.social_global() {
                // Pushed off the path (by people or contacts): re-plan from here.
                if let Some(path) = plan_path(&mut self.planner, grid, p, st.route[rb.leg]) {
                    rb.follower = PathFollower::new(path, FollowerParams::default());
                    o = rb.follower.step(p, theta, st.limits.max_speed, st.limits.max_accel, dt);
                    if planner == PlannerKind::Eband {
                        rb.band = ElasticBand::new(rb.follower.path(), st.eband).ok();
                    }
                }
            }
            partial_goals[i] = rb.follower.point_ahead(self.control.partial_goal);
            desired[i] = o.velocity;
            if !local(planner) {
                rb.mode = Mode::FollowPath;
                continue;
            }
            let people: Vec<CtlPerson> = self
                .controller_people(st.radius)
                .into_iter()
                .filter(|(_, r)| *r != Some(i))
                .map(|(q, _)| q)
                .collect();
            let others: Vec<OtherRobot> = (0..n)
                .filter(|&j| j != i)
                .map(|j| OtherRobot {
                    pos: Vec2::new(self.robots[j].pose[0], self.robots[j].pose[1]),
                    vel: self.robots[j].velocity,
                    radius: self.statics[j].radius,
                })
                .collect();
            let rb = &self.robots[i];
            let mode = match planner {
                PlannerKind::Orca => Mode::Orca,
                PlannerKind::SocialMomentum => {
                    let near = people.iter().any(|q| (q.pos - p).norm() <= self.control.people_range);
                    if near { Mode::SocialMomentum } else { Mode::FollowPath }
                }
                _ => {
                    let m = choose_mode(p, rb.exec_v, st.radius, &people, &others, &self.control);
                    // Hysteresis: once avoiding robots, keep ORCA while any is still within range
                    // (leaving it on a clear cone would steer straight back into the conflict).
                    let robots_near = others.iter().any(|o| (o.pos - p).norm() <= self.control.robot_range);
                    if m == Mode::FollowPath && rb.mode == Mode::Orca && robots_near { Mode::Orca } else { m }
                }
            };
            let mode = match mode {
                Mode::SocialMomentum => {
                    let (v, m) = social_momentum_step(
                        p,
                        rb.exec_v,
                        st.radius,
                        partial_goals[i],
                        &people,
                        &others,
                        Some(&self.geometry),
                        &st.limits,
                        dt,
                        &self.control,
                    );
                    desired[i] = v;
                    m
                }
                Mode::Orca => {
                    orca_active.push(i);
                    Mode::Orca
                }
                m => m,
            };
            self.robots[i].mode = mode;
        }
        if !orca_active.is_empty() {
            self.orca_step(&orca_active, &partial_goals, &mut desired, dt);
        }
        for i in 0..n {
            let st = &self.statics[i];
            let rb = &mut self.robots[i];
            let (v, w) = if rb.outcome == Outcome::Running {
                // Heading policy: face the direction of motion; on an approach task, face the
                // person over the last metre.
                let d = desired[i];
                let p = Vec2::new(rb.pose[0], rb.pose[1]);
                let gain = FollowerParams::default().heading_gain;
                let wz = match st.face {
                    Some(q) if (st.goal - p).norm() < APPROACH_FACING_DISTANCE => {
                        let to = q - p;
                        gain * wrap_angle(to.y.atan2(to.x) - rb.pose[2])
                    }
                    _ if d.norm() > FollowerParams::default().min_turn_speed => {
                        gain * wrap_angle(d.y.atan2(d.x) - rb.pose[2])
                    }
                    _ => 0.0,
                };
                st.limits.apply(d, wz, rb.exec_v, rb.exec_wz, dt)
            } else {
                // Finished robots are commanded to stop (within the deceleration limit).
                st.limits.apply(Vec2::zeros(), 0.0, rb.exec_v, rb.exec_wz, dt)
            };
            rb.proposed_v = v;
            rb.proposed_wz = w;
            let b = world_to_body(v, rb.pose[2]);
            let row = &mut out[i * stride..(i + 1) * stride];
            row[cmd] = b.x;
            row[cmd + 1] = b.y;
            row[cmd + 2] = w;
            row[act] = (b.x / st.limits.max_speed).clamp(-1.0, 1.0);
            row[act + 1] = (b.y / st.limits.max_speed).clamp(-1.0, 1.0);
            row[act + 2] = (w / st.limits.max_angular_speed).clamp(-1.0, 1.0);
            row[mode_off] = f64::from(rb.mode.code());
        }
    }

    /// ORCA for the robots in `active` (one batched call): every robot reciprocates, people do
    /// not (the robot takes the whole avoidance); static geometry as obstacle edges.
    fn orca_step(&mut self, active: &[usize], partial_goals: &[Vec2], desired: &mut [Vec2], dt: f64) {
        let mut agents: Vec<OrcaAgent> = Vec::with_capacity(self.robots.len() + self.crowd.len());
        for (j, (rb, st)) in self.robots.iter().zip(&self.statics).enumerate() {
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            let pref = if active.contains(&j) {
                // Toward the partial goal at the speed the path follower wanted (it brakes at the end).
                let to = partial_goals[j] - p;
                let speed = desired[j].norm().min(st.limits.max_speed);
                if to.norm() > 1e-9 { to * (speed / to.norm()) } else { Vec2::zeros() }
            } else {
                rb.exec_v
            };
            agents.push(OrcaAgent {
                pos: p,
                vel: rb.exec_v,
                pref_vel: pref,
                // A safety margin: ORCA lets discs touch, the physics counts touching as contact.
                radius: st.radius + ORCA_MARGIN,
                max_speed: st.limits.max_speed,
                // Only robots computing ORCA this step take their share of the avoidance.
                reciprocal: active.contains(&j),
                id: j as u64,
            });
        }
        let intimate = self.social.config().zones.intimate;
        for k in 0..self.crowd.len() {
            agents.push(OrcaAgent {
                pos: self.crowd.pos[k],
                vel: self.crowd.vel[k],
                pref_vel: self.crowd.vel[k],
                radius: self.crowd.radius[k].max(intimate - 0.24) + ORCA_MARGIN,
                max_speed: 2.5,
                reciprocal: false,
                id: 1_000_000 + k as u64,
            });
        }
        let mut out = vec![Vec2::zeros(); agents.len()];
        if self.orca.compute(&agents, active, &self.obstacles, dt, self.steps as u64, &mut out).is_ok() {
            for &i in active {
                desired[i] = out[i];
            }
        }
    }

    /// Moves robot `i`'s elastic band one optimisation pass and follows it.
    fn update_band(&mut self, i: usize, p: Vec2) {
        let field = &self.field;
        // The band's bubbles are free space for the robot's centre: clearance minus its footprint.
        let body = self.statics[i].radius + self.scenario.robots[i].inflation_margin;
        let clearance = |q: Vec2| field.at(q) - body;
        let individuals = self.social.perception().map(|per| per.individuals.clone()).unwrap_or_default();
        let social = |q: Vec2| individuals.iter().map(|ind| ind.value(q)).fold(0.0, f64::max);
        let rb = &mut self.robots[i];
        if let Some(band) = rb.band.as_mut()
            && band.set_start(p).is_ok()
        {
            band.update(&clearance, Some(&social));
            rb.follower = PathFollower::new(band.points().to_vec(), FollowerParams::default());
        }
    }
}

/// Whether the straight segment `ab` crosses only passable cells of `grid` (sampled every half
/// cell; cells the segment starts in are allowed, so a robot already in the inflation can leave).
fn segment_clear(grid: &CostGrid, a: Vec2, b: Vec2) -> bool {
    let len = (b - a).norm();
    let n = (len / (0.5 * grid.spec.resolution)).ceil() as usize;
    let start = grid.spec.cell_of(a);
    (1..=n).all(|k| {
        let q = a + (b - a) * (k as f64 / n as f64);
        match grid.spec.cell_of(q) {
            Some(c) => Some(c) == start || grid.passable(c.0, c.1),
            None => false,
        }
    })
}

/// Plain A* (weight 0) from `start` to `goal` on `grid`, smoothed, as world-frame waypoints
/// that start at `start` and end exactly at `goal`.
fn plan_path(planner: &mut PathPlanner, grid: &CostGrid, start: Vec2, goal: Vec2) -> Option<Vec<Vec2>> {
    let s = snap_to_passable(grid, start)?;
    let g = snap_to_passable(grid, goal)?;
    let path = planner.plan(grid, s, g, SearchMode { weight: 0.0, heuristic: true })?;
    let mut pts = smooth_path(grid, &path, 0.0);
    if let Some(first) = pts.first_mut() {
        *first = start;
    }
    pts.push(goal);
    Some(pts)
}

/// People must start clear of the static geometry (seated people excepted: they sit on it),
/// wait at homes clear of it, and walk routes that do not cross it.
fn check_people(s: &Scenario, geometry: &StaticGeometry) -> Result<()> {
    for (i, p) in s.persons.iter().enumerate() {
        let (field, pos) = match (p.behaviour, p.home) {
            (Behaviour::Standing, _) => ("pose", Vec2::new(p.pose[0], p.pose[1])),
            (_, Some(h)) => ("home", v2(h)),
            _ => ("", Vec2::zeros()),
        };
        if !field.is_empty() && (geometry.contains(pos) || geometry.distance(pos) < p.radius) {
            return Err(scenario_err(
                s,
                format!("person[{i}].{field}"),
                format!(
                    "a position at least {:.2} m (the person's radius) from walls and furniture",
                    p.radius
                ),
                format!("[{}, {}]", pos.x, pos.y),
            ));
        }
        for (k, w) in p.route.iter().enumerate() {
            let a = v2(*w);
            if geometry.contains(a) || geometry.distance(a) < p.radius {
                return Err(scenario_err(
                    s,
                    format!("person[{i}].route[{k}]"),
                    format!(
                        "a waypoint at least {:.2} m (the person's radius) from walls and furniture",
                        p.radius
                    ),
                    format!("[{}, {}]", a.x, a.y),
                ));
            }
            let b = v2(p.route[(k + 1) % p.route.len()]);
            if geometry.segment_hits(a, b) {
                return Err(scenario_err(
                    s,
                    format!("person[{i}].route[{k}]"),
                    format!(
                        "a route leg to route[{}] that does not cross walls or furniture",
                        (k + 1) % p.route.len()
                    ),
                    format!("a leg from [{}, {}] to [{}, {}] through static geometry", a.x, a.y, b.x, b.y),
                ));
            }
        }
    }
    Ok(())
}
