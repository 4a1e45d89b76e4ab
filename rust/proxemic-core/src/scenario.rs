//! Scenario files: parse and validate once.
//!
//! A scenario is a TOML file (`envs/*.toml`) describing the static scene (walls, objects with
//! interaction spaces), the people, the robots and the episode settings. [`Scenario::from_file`]
//! and [`Scenario::from_toml_str`] parse it with serde (unknown fields are rejected), fill in the
//! defaults, check every value, and compute world-frame polygons for walls, object footprints and
//! interaction spaces. The result serialises to JSON ([`Scenario::to_json`]) for the Python side,
//! which never parses the TOML itself.
//!
//! Every error is a [`CoreError::Scenario`] naming the file, the dotted field path
//! (`person[3].route[1]`), what was expected and what arrived.
//!
//! Conventions: SI units, angles in radians counter-clockwise from +x, poses `[x, y, theta]` in the
//! world frame, times of day as `"HH:MM"` or `"HH:MM:SS"` strings.

use serde::{Deserialize, Serialize};
use std::path::Path;

use crate::error::{CoreError, Result};

/// Number of vertices used to approximate a circle as a polygon.
pub const CIRCLE_VERTICES: usize = 24;

// ---------------------------------------------------------------------------------------------
// Raw (file) representation
// ---------------------------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    scene: RawScene,
    #[serde(default)]
    wall: Vec<RawWall>,
    #[serde(default)]
    object: Vec<RawObject>,
    #[serde(default)]
    person: Vec<RawPerson>,
    #[serde(default)]
    robot: Vec<RawRobot>,
    #[serde(default)]
    episode: RawEpisode,
    #[serde(default)]
    sensors: Sensors,
    #[serde(default)]
    reward: RewardWeights,
    #[serde(default)]
    proxemics: RawProxemics,
    #[serde(default)]
    agenda: RawAgenda,
    #[serde(default)]
    activity: Vec<RawActivity>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProxemics {
    #[serde(default = "d_zones")]
    zones: String,
    zone_radii: Option<[f64; 3]>,
    #[serde(default = "d_space")]
    space: String,
    sigma: Option<f64>,
    sigma_front: Option<f64>,
    sigma_rear: Option<f64>,
    sigma_left: Option<f64>,
    sigma_right: Option<f64>,
    #[serde(default = "d_cost_mode")]
    cost_mode: String,
    #[serde(default = "d_personal_cost")]
    personal_cost: f64,
    #[serde(default = "d_social_cost")]
    social_cost: f64,
    #[serde(default = "d_public_cost")]
    public_cost: f64,
    #[serde(default = "d_continuous_gain")]
    continuous_gain: f64,
    #[serde(default = "d_groups")]
    groups: String,
    d_max: Option<f64>,
    orientation_rule: Option<bool>,
    #[serde(default = "d_aggregate")]
    aggregate: String,
    #[serde(default)]
    features: Vec<String>,
    #[serde(default)]
    influence: RawInfluence,
}

impl Default for RawProxemics {
    fn default() -> Self {
        RawProxemics {
            zones: d_zones(),
            zone_radii: None,
            space: d_space(),
            sigma: None,
            sigma_front: None,
            sigma_rear: None,
            sigma_left: None,
            sigma_right: None,
            cost_mode: d_cost_mode(),
            personal_cost: d_personal_cost(),
            social_cost: d_social_cost(),
            public_cost: d_public_cost(),
            continuous_gain: d_continuous_gain(),
            groups: d_groups(),
            d_max: None,
            orientation_rule: None,
            aggregate: d_aggregate(),
            features: Vec::new(),
            influence: RawInfluence::default(),
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawInfluence {
    #[serde(default)]
    front: Vec<f64>,
    #[serde(default)]
    rear: Vec<f64>,
    #[serde(default)]
    left: Vec<f64>,
    #[serde(default)]
    right: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawAgenda {
    #[serde(default = "d_idle")]
    idle: f64,
    #[serde(default = "d_active")]
    active: f64,
    #[serde(default = "d_ramp_minutes")]
    ramp_minutes: f64,
}

impl Default for RawAgenda {
    fn default() -> Self {
        RawAgenda { idle: d_idle(), active: d_active(), ramp_minutes: d_ramp_minutes() }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawActivity {
    object: String,
    start: String,
    end: String,
    #[serde(default)]
    name: String,
}

fn d_zones() -> String {
    "evaluation".into()
}
fn d_space() -> String {
    "calderita".into()
}
fn d_cost_mode() -> String {
    "zones".into()
}
fn d_personal_cost() -> f64 {
    4.0
}
fn d_social_cost() -> f64 {
    2.0
}
fn d_public_cost() -> f64 {
    1.0
}
fn d_continuous_gain() -> f64 {
    3.0
}
fn d_groups() -> String {
    "delaunay".into()
}
fn d_aggregate() -> String {
    "mean".into()
}
fn d_idle() -> f64 {
    1.5
}
fn d_active() -> f64 {
    3.5
}
fn d_ramp_minutes() -> f64 {
    45.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    name: String,
    bounds: [f64; 4],
    #[serde(default = "d_resolution")]
    resolution: f64,
    #[serde(default = "d_start_time")]
    start_time: String,
    #[serde(default = "d_control_hz")]
    control_hz: f64,
    #[serde(default = "d_physics_hz")]
    physics_hz: f64,
    #[serde(default = "d_wall_height")]
    wall_height: f64,
    #[serde(default)]
    description: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWall {
    from: [f64; 2],
    to: [f64; 2],
    #[serde(default = "d_wall_thickness")]
    thickness: f64,
    height: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawObject {
    name: String,
    kind: ObjectKind,
    pose: [f64; 3],
    size: Option<[f64; 2]>,
    radius: Option<f64>,
    height: Option<f64>,
    #[serde(default = "d_true")]
    solid: bool,
    interaction: Option<RawInteraction>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "shape", rename_all = "snake_case")]
enum RawInteraction {
    Trapezoid { length: f64, near_width: f64, far_width: f64 },
    Rectangle { margin: f64 },
    Circle { radius: f64 },
    Polygon { points: Vec<[f64; 2]> },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPerson {
    name: Option<String>,
    #[serde(default = "d_behaviour")]
    behaviour: Behaviour,
    pose: Option<[f64; 3]>,
    #[serde(default)]
    route: Vec<[f64; 2]>,
    /// Metres per second, or a preset name ([`SPEED_PRESETS`]).
    speed: Option<toml::Value>,
    #[serde(default)]
    dwell: f64,
    #[serde(default)]
    exhibits: Vec<toml::Value>,
    home: Option<[f64; 2]>,
    spot: Option<[f64; 2]>,
    start: Option<toml::Value>,
    end: Option<toml::Value>,
    seat: Option<String>,
    #[serde(default)]
    place: usize,
    guide: Option<String>,
    stops: Option<Vec<usize>>,
    #[serde(default)]
    attends: Vec<String>,
    #[serde(default = "d_lead_minutes")]
    lead_minutes: f64,
    #[serde(default = "d_gather_radius")]
    gather_radius: f64,
    #[serde(default = "d_person_radius")]
    radius: f64,
    #[serde(default = "d_person_height")]
    height: f64,
    group: Option<u32>,
    #[serde(default = "d_true")]
    aware: bool,
    #[serde(default)]
    features: Vec<f64>,
    emotional_state: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRobot {
    name: Option<String>,
    start: [f64; 3],
    goal: Option<[f64; 2]>,
    approach: Option<RawApproach>,
    #[serde(default = "d_planner")]
    planner: PlannerKind,
    #[serde(default = "d_robot_radius")]
    radius: f64,
    #[serde(default = "d_max_speed")]
    max_speed: f64,
    #[serde(default = "d_max_angular_speed")]
    max_angular_speed: f64,
    #[serde(default = "d_max_accel")]
    max_accel: f64,
    #[serde(default = "d_inflation_margin")]
    inflation_margin: f64,
    #[serde(default)]
    eband: RawEbandGains,
    #[serde(default)]
    waypoints: Vec<[f64; 2]>,
    #[serde(default)]
    dwell: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawEbandGains {
    contraction_gain: Option<f64>,
    repulsion_gain: Option<f64>,
    social_gain: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawApproach {
    person: Option<String>,
    group: Option<u32>,
    #[serde(default = "d_side")]
    side: String,
    level: Option<f64>,
}

fn d_side() -> String {
    "auto".into()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEpisode {
    #[serde(default = "d_max_time")]
    max_time: f64,
    #[serde(default = "d_success_radius")]
    success_radius: f64,
    #[serde(default)]
    randomize: Randomize,
}

impl Default for RawEpisode {
    fn default() -> Self {
        RawEpisode {
            max_time: d_max_time(),
            success_radius: d_success_radius(),
            randomize: Randomize::default(),
        }
    }
}

fn d_resolution() -> f64 {
    0.1
}
fn d_start_time() -> String {
    "09:00".to_string()
}
fn d_control_hz() -> f64 {
    10.0
}
fn d_physics_hz() -> f64 {
    100.0
}
fn d_wall_height() -> f64 {
    2.5
}
fn d_wall_thickness() -> f64 {
    0.2
}
fn d_true() -> bool {
    true
}
fn d_behaviour() -> Behaviour {
    Behaviour::Walker
}
fn d_person_speed() -> f64 {
    1.0
}
fn d_lead_minutes() -> f64 {
    2.0
}
fn d_gather_radius() -> f64 {
    1.5
}

/// Named walking speeds (m/s) accepted by `person.speed`: `normal` is the mean desired speed of
/// Helbing & Molnar 1995 (1.34 m/s, rounded); `fast`, `slow` and `elderly` (a frail older adult,
/// as in a care center) are this project's choices, not values from the papers.
pub const SPEED_PRESETS: [(&str, f64); 4] = [("fast", 1.6), ("normal", 1.3), ("slow", 0.9), ("elderly", 0.6)];

/// Seat spacing along a bench or sofa (metres): one person per 0.6 m of its width.
pub const SEAT_SPACING: f64 = 0.6;
fn d_person_radius() -> f64 {
    0.2
}
fn d_person_height() -> f64 {
    1.7
}
fn d_planner() -> PlannerKind {
    PlannerKind::Astar
}
fn d_robot_radius() -> f64 {
    0.24
}
fn d_max_speed() -> f64 {
    0.55
}
fn d_max_angular_speed() -> f64 {
    2.0
}
fn d_max_accel() -> f64 {
    0.55
}
fn d_inflation_margin() -> f64 {
    0.06
}
fn d_max_time() -> f64 {
    180.0
}
fn d_success_radius() -> f64 {
    0.3
}

// ---------------------------------------------------------------------------------------------
// Validated representation
// ---------------------------------------------------------------------------------------------

/// Kinds of static objects. The kind decides the default height and how the object is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ObjectKind {
    /// A free-standing exhibit on a plinth.
    Exhibit,
    /// A painting hung on a wall (a thin box).
    Painting,
    /// A poster on a wall.
    Poster,
    /// A television set.
    Tv,
    /// A rectangular table.
    Table,
    /// A round table (give `radius`).
    RoundTable,
    /// A bed.
    Bed,
    /// A physiotherapy stretcher.
    Stretcher,
    /// A sofa.
    Sofa,
    /// A bench.
    Bench,
    /// A plinth or display case.
    Plinth,
    /// A pillar (give `radius` for a round one).
    Pillar,
    /// A cabinet or shelf.
    Cabinet,
    /// A chair.
    Chair,
}

impl ObjectKind {
    /// Default height of the kind (metres).
    pub fn default_height(self) -> f64 {
        match self {
            ObjectKind::Exhibit => 1.4,
            ObjectKind::Painting | ObjectKind::Poster => 1.8,
            ObjectKind::Tv => 1.5,
            ObjectKind::Table | ObjectKind::RoundTable => 0.75,
            ObjectKind::Bed | ObjectKind::Stretcher => 0.6,
            ObjectKind::Sofa => 0.8,
            ObjectKind::Bench => 0.45,
            ObjectKind::Plinth => 1.0,
            ObjectKind::Pillar => 2.5,
            ObjectKind::Cabinet => 1.8,
            ObjectKind::Chair => 0.9,
        }
    }

    fn is_round_capable(self) -> bool {
        matches!(self, ObjectKind::RoundTable | ObjectKind::Pillar | ObjectKind::Plinth | ObjectKind::Exhibit)
    }
}

/// Scripted pedestrian behaviours (`person.behaviour`). Every moving person walks with the
/// social force model of [`crate::pedestrians`]; paths between places are planned on the static
/// map, so only walker and guide routes must be free of walls themselves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Behaviour {
    /// Walks a closed `route` of waypoints at `speed`, pausing `dwell` seconds at the waypoints
    /// listed in `stops` (indices; default every waypoint).
    #[default]
    Walker,
    /// Stands still at `pose`.
    Standing,
    /// Exhibit visitor: walks to the viewing (interaction) space of each object of `exhibits`
    /// (names or indices into `[[object]]`) in turn, dwells `dwell` seconds there facing the
    /// object, and moves on (cyclically).
    Visitor,
    /// Member of a standing conversation (an F-formation) of the people sharing its `group`
    /// id: stands at `home` until `start`, walks with the others to its place on a circle around
    /// the o-space centre `spot`, stands there facing the centre until `end`, then walks home.
    /// `start` and `end` are seconds into the episode (numbers) or times of day ("HH:MM").
    Conversation,
    /// Tour guide: walks its closed `route`, stopping `dwell` seconds at the waypoints listed in
    /// `stops` (indices; default every waypoint), where it turns to face its followers.
    Guide,
    /// Tour follower of the person named `guide`: follows the guide's route; at each stop it
    /// gathers on an arc of radius `gather_radius` (default 1.5 m) around the guide, facing it
    /// (Daza 2021 Fig. 11). It starts in its place at the guide's first waypoint.
    ///
    /// A robot can guide too: `guide = "robot:<name>"` names a `[[robot]]`. The followers start
    /// gathered behind the robot's start, walk where it went (its trail), 1.2 m behind it, and
    /// gather on an arc of `gather_radius` behind it, facing it, at every waypoint where it
    /// dwells (`dwell` > 0) and at its goal, each taking a free place as it arrives. If that
    /// robot is not in the episode (fewer robots), they stand at their place at its start.
    Follower,
    /// Seated on the bench, sofa or chair named `seat`, at seat `place` (0, 1, ... along its
    /// width, one per 0.6 m), facing the seat's front; never moves and cannot be pushed.
    Seated,
    /// Care-center resident: for every activity of the agenda on the objects named in
    /// `attends`, walks from `home` to a place in the object's interaction space, arriving
    /// `lead_minutes` (default 2) before the activity starts, stays facing the object until it
    /// ends, then walks home.
    Resident,
    /// Care-center staff member (a therapist): like a resident, but stands on the far side of
    /// the object, facing the residents.
    Staff,
}

/// Built-in planners a robot can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PlannerKind {
    /// Plain 8-connected A* on the inflated static map, followed by a pure-pursuit path follower.
    /// It avoids walls and furniture, not people: the baseline of every comparison.
    Astar,
    /// Social A* on the social cost map (people's zones, groups, object spaces at R(t)), re-planned
    /// when the agenda or the people change the path's cost, followed by the same path follower.
    SocialAstar,
    /// The full social planner (Daza 2021 Algorithm 1): the social A* global path, ORCA when only
    /// robots are around and one is in the collision cone, Social Momentum near people and groups,
    /// path following otherwise.
    Social,
    /// Plain A* global path; ORCA against everyone (people do not reciprocate).
    Orca,
    /// Plain A* global path; Social Momentum whenever people are near.
    SocialMomentum,
    /// Plain A* global path deformed by an elastic band (static clearance and people's spaces).
    Eband,
}

impl PlannerKind {
    /// Parses a planner name as used in scenario files and on the command line.
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "astar" => Some(PlannerKind::Astar),
            "social_astar" => Some(PlannerKind::SocialAstar),
            "social" => Some(PlannerKind::Social),
            "orca" => Some(PlannerKind::Orca),
            "social_momentum" => Some(PlannerKind::SocialMomentum),
            "eband" => Some(PlannerKind::Eband),
            _ => None,
        }
    }

    /// The names accepted by [`PlannerKind::parse`].
    pub const NAMES: &'static [&'static str] =
        &["astar", "social_astar", "social", "orca", "social_momentum", "eband"];

    /// Whether the planner's global path is the social A* path (re-planned on triggers).
    pub fn social_global(self) -> bool {
        matches!(self, PlannerKind::SocialAstar | PlannerKind::Social)
    }
}

/// Scene-wide settings.
#[derive(Clone, Debug, Serialize)]
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// One-paragraph description (may be empty).
    pub description: String,
    /// `[xmin, ymin, xmax, ymax]` of the map (metres).
    pub bounds: [f64; 4],
    /// Grid resolution (metres per cell), in (0, 1]; default 0.1.
    pub resolution: f64,
    /// Time of day at t = 0 (seconds after midnight); default 09:00.
    pub start_time: f64,
    /// Control rate (Hz); default 10.
    pub control_hz: f64,
    /// Physics rate (Hz), an integer multiple of `control_hz`; default 100.
    pub physics_hz: f64,
    /// Default wall height (metres); default 2.5.
    pub wall_height: f64,
}

/// A straight wall segment with thickness.
#[derive(Clone, Debug, Serialize)]
pub struct Wall {
    /// Start point of the centre line (metres).
    pub from: [f64; 2],
    /// End point of the centre line (metres).
    pub to: [f64; 2],
    /// Thickness (metres); default 0.2.
    pub thickness: f64,
    /// Height (metres).
    pub height: f64,
    /// World-frame footprint polygon (CCW).
    pub polygon: Vec<[f64; 2]>,
}

/// Interaction-space shapes (Calderita §4.2).
#[derive(Clone, Debug, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum InteractionShape {
    /// Isosceles trapezoid in front of the object (TV, poster, painting): `near_width` at the
    /// object's front face, `far_width` at `length` metres in front of it.
    Trapezoid {
        /// Depth in front of the object (metres).
        length: f64,
        /// Width at the object (metres).
        near_width: f64,
        /// Width at the far side (metres).
        far_width: f64,
    },
    /// The object's footprint grown by `margin` (table, bed, stretcher).
    Rectangle {
        /// Margin around the footprint (metres).
        margin: f64,
    },
    /// A circle around the object's centre (round table).
    Circle {
        /// Radius (metres).
        radius: f64,
    },
    /// An explicit world-frame polygon.
    Polygon,
}

/// An object's interaction space.
#[derive(Clone, Debug, Serialize)]
pub struct Interaction {
    /// The shape as written in the file.
    #[serde(flatten)]
    pub shape: InteractionShape,
    /// World-frame polygon (CCW).
    pub polygon: Vec<[f64; 2]>,
}

/// A static object (furniture, exhibit).
#[derive(Clone, Debug, Serialize)]
pub struct Object {
    /// Unique name.
    pub name: String,
    /// Kind.
    pub kind: ObjectKind,
    /// Pose `[x, y, theta]`; theta is the direction the object faces (its viewing side).
    pub pose: [f64; 3],
    /// `[depth, width]` along the object's local x (facing) and y axes (metres); for round
    /// objects `[2r, 2r]`.
    pub size: [f64; 2],
    /// Radius for round objects (metres), else `None`.
    pub radius: Option<f64>,
    /// Height (metres).
    pub height: f64,
    /// Whether the object blocks motion (default true).
    pub solid: bool,
    /// World-frame footprint polygon (CCW).
    pub footprint: Vec<[f64; 2]>,
    /// Interaction space, if any.
    pub interaction: Option<Interaction>,
}

/// A scripted person.
#[derive(Clone, Debug, Serialize)]
pub struct Person {
    /// Unique name.
    pub name: String,
    /// Behaviour.
    pub behaviour: Behaviour,
    /// Initial pose `[x, y, theta]` (a walker or guide starts at its first waypoint facing the
    /// second unless the episode randomises the phase; a seated person's pose is its seat; for
    /// conversations, residents and staff it is `home`; for visitors and followers it is only
    /// a reference point, the first exhibit's centre or the guide's first waypoint: their
    /// places are planned when the world is built).
    pub pose: [f64; 3],
    /// Closed route of waypoints (walkers; empty for standing people).
    pub route: Vec<[f64; 2]>,
    /// Preferred walking speed (m/s), in (0, 2.5]; default 1.0.
    pub speed: f64,
    /// Pause at each waypoint (s), >= 0; default 0.
    pub dwell: f64,
    /// Body radius (metres), in (0, 0.5]; default 0.2.
    pub radius: f64,
    /// Height (metres); default 1.7.
    pub height: f64,
    /// Ground-truth group id, if the person belongs to a group.
    pub group: Option<u32>,
    /// Whether the person sees the robots and yields to them (default true).
    pub aware: bool,
    /// Socialization feature values in (0, 1], one per `proxemics.features` name.
    pub features: Vec<f64>,
    /// Visitors: indices of the objects visited, in order.
    pub exhibits: Vec<usize>,
    /// Conversation, resident, staff: where the person is when not busy.
    pub home: Option<[f64; 2]>,
    /// Conversation: the o-space centre.
    pub spot: Option<[f64; 2]>,
    /// Conversation: when it forms and breaks up (seconds after the episode start; may be
    /// negative for a conversation already under way).
    pub schedule: Option<[f64; 2]>,
    /// Walker and guide: whether each route waypoint is a stop (empty for a walker: every one).
    pub stops: Vec<bool>,
    /// Follower: index of the guide (a person).
    pub guide: Option<usize>,
    /// Follower of a robot (`guide = "robot:<name>"`): index of the robot; `None` if that robot
    /// is not in the episode (see [`Scenario::with_robots`]: the tour then waits at its start).
    pub guide_robot: Option<usize>,
    /// Follower of a robot: the robot's tour, its start, waypoints and goal (`[x, y]`, metres).
    pub tour: Vec<[f64; 2]>,
    /// Follower of a robot: whether each tour point is a stop where followers gather (the start,
    /// the waypoints if the robot dwells there, and the goal).
    pub tour_stops: Vec<bool>,
    /// Follower: arc radius around the guide at stops (metres, default 1.5).
    pub gather_radius: f64,
    /// Resident, staff: indices of the objects whose activities the person attends.
    pub attends: Vec<usize>,
    /// Resident, staff: arrival lead before an activity starts (seconds; default 120).
    pub lead: f64,
}

impl Default for Person {
    fn default() -> Self {
        Person {
            name: String::new(),
            behaviour: Behaviour::Walker,
            pose: [0.0; 3],
            route: Vec::new(),
            speed: d_person_speed(),
            dwell: 0.0,
            radius: d_person_radius(),
            height: d_person_height(),
            group: None,
            aware: true,
            features: Vec::new(),
            exhibits: Vec::new(),
            home: None,
            spot: None,
            schedule: None,
            stops: Vec::new(),
            guide: None,
            guide_robot: None,
            tour: Vec::new(),
            tour_stops: Vec::new(),
            gather_radius: d_gather_radius(),
            attends: Vec::new(),
            lead: d_lead_minutes() * 60.0,
        }
    }
}

/// A robot.
#[derive(Clone, Debug, Serialize)]
pub struct Robot {
    /// Unique name.
    pub name: String,
    /// Start pose `[x, y, theta]`.
    pub start: [f64; 3],
    /// Goal position `[x, y]` (for an approach task, computed from the person's personal space).
    pub goal: [f64; 2],
    /// An approach task: go to the edge of a person's personal space and face them.
    pub approach: Option<Approach>,
    /// Built-in planner.
    pub planner: PlannerKind,
    /// Footprint radius (metres); default 0.24 (Pepper).
    pub radius: f64,
    /// Maximum linear speed (m/s), the norm of (vx, vy); default 0.55 (Pepper).
    pub max_speed: f64,
    /// Maximum angular speed (rad/s); default 2.0 (Pepper).
    pub max_angular_speed: f64,
    /// Maximum linear acceleration (m/s^2); default 0.55 (Pepper).
    pub max_accel: f64,
    /// Extra clearance added to the radius when inflating the map (metres); default 0.06.
    pub inflation_margin: f64,
    /// Gains of the elastic band (used by the `eband` planner); file table `eband = { ... }`.
    pub eband: EbandGains,
    /// Places visited in order before the goal, `[x, y]` each (metres; default none): a tour.
    /// The robot's current target (what its planners aim for and its observation's goal offset
    /// shows) is the next of these, then the goal; the episode succeeds at the goal.
    pub waypoints: Vec<[f64; 2]>,
    /// Seconds the robot stands still at each waypoint (a tour stop), in [0, 3600]; default 0
    /// (it passes through). Followers (`guide = "robot:<name>"`) gather around it there.
    pub dwell: f64,
}

/// The elastic band's force gains (dimensionless, each in `[0, EbandGains::MAX]`), as tuned by
/// `proxemic tune` (Calderita §5.4). Defaults: Calderita's optimum `kc = 120`, `kr = 60` mapped
/// by their ratio (see [`crate::control::eband`]): 1.0, 0.5, 0.5.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct EbandGains {
    /// Contraction gain `k_c`; default 1.0.
    pub contraction_gain: f64,
    /// Repulsion gain `k_r` from static obstacles; default 0.5.
    pub repulsion_gain: f64,
    /// Repulsion gain `k_s` from the social cost; default 0.5.
    pub social_gain: f64,
}

impl Default for EbandGains {
    fn default() -> Self {
        let p = crate::control::eband::EbandParams::default();
        EbandGains {
            contraction_gain: p.contraction_gain,
            repulsion_gain: p.repulsion_gain,
            social_gain: p.social_gain,
        }
    }
}

impl EbandGains {
    /// Largest accepted gain (a bubble's move is clamped to a fraction of its radius anyway).
    pub const MAX: f64 = 100.0;

    /// The elastic band's parameters: these gains, the other fields at their defaults.
    pub fn params(&self) -> crate::control::eband::EbandParams {
        crate::control::eband::EbandParams {
            contraction_gain: self.contraction_gain,
            repulsion_gain: self.repulsion_gain,
            social_gain: self.social_gain,
            ..Default::default()
        }
    }

    /// These gains with each `Some` value replaced, checked (errors name `{field}.<gain>`).
    fn merged(
        &self,
        file: &str,
        field: &str,
        contraction: Option<f64>,
        repulsion: Option<f64>,
        social: Option<f64>,
    ) -> Result<Self> {
        let ck = Checker { file };
        let mut g = *self;
        for (name, new, slot) in [
            ("contraction_gain", contraction, &mut g.contraction_gain),
            ("repulsion_gain", repulsion, &mut g.repulsion_gain),
            ("social_gain", social, &mut g.social_gain),
        ] {
            if let Some(v) = new {
                ck.range(&format!("{field}.{name}"), v, 0.0, Self::MAX, false)?;
                *slot = v;
            }
        }
        Ok(g)
    }
}

/// An approach task (Sousa 2022's waiter serving food from the left and drinks from the right;
/// Calderita's robot coming to face a person to take their attention).
#[derive(Clone, Debug, Serialize)]
pub struct Approach {
    /// Indices of the (standing) people approached: one person, or the members of a group.
    pub people: Vec<usize>,
    /// The side approached: `front`, `left`, `right` (the person's), or as chosen by `auto`.
    pub side: String,
    /// Personal-space value at which the robot's body stops (default: the personal zone's edge).
    pub level: f64,
    /// The point the robot faces at the goal (the person's position).
    pub face: [f64; 2],
}

/// Per-episode randomisation, drawn from the episode's seeded generator.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Randomize {
    /// Start each walker at a uniformly random point of its route (default true).
    #[serde(default = "d_true")]
    pub person_phase: bool,
    /// Relative jitter of walkers' speeds: speed * U(1 - j, 1 + j); in [0, 0.5]; default 0.1.
    #[serde(default = "d_speed_jitter")]
    pub speed_jitter: f64,
    /// Uniform jitter of the robot start position (metres, per axis); default 0.
    #[serde(default)]
    pub robot_start_jitter: f64,
}

fn d_speed_jitter() -> f64 {
    0.1
}

impl Default for Randomize {
    fn default() -> Self {
        Randomize { person_phase: true, speed_jitter: d_speed_jitter(), robot_start_jitter: 0.0 }
    }
}

/// Episode settings.
#[derive(Clone, Debug, Serialize)]
pub struct Episode {
    /// Time limit (s); the episode is truncated when it is reached. Default 180.
    pub max_time: f64,
    /// The robot succeeds when its centre is within this distance of the goal (metres). Default 0.3.
    pub success_radius: f64,
    /// Per-episode randomisation.
    pub randomize: Randomize,
}

/// Observation settings.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sensors {
    /// Number of lidar rays over 360 degrees, in [4, 1440]; default 72.
    #[serde(default = "d_lidar_rays")]
    pub lidar_rays: usize,
    /// Lidar range (metres), in (0, 50]; default 8.
    #[serde(default = "d_lidar_range")]
    pub lidar_range: f64,
    /// Number of nearest people in the observation, in [1, 64]; default 8.
    #[serde(default = "d_k_nearest")]
    pub k_nearest: usize,
}

fn d_lidar_rays() -> usize {
    72
}
fn d_lidar_range() -> f64 {
    8.0
}
fn d_k_nearest() -> usize {
    8
}

impl Default for Sensors {
    fn default() -> Self {
        Sensors { lidar_rays: d_lidar_rays(), lidar_range: d_lidar_range(), k_nearest: d_k_nearest() }
    }
}

/// Reward weights. The reward is the sum of the terms; each term is reported separately.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RewardWeights {
    /// Per metre of progress toward the goal along the geodesic distance; default 1.0.
    #[serde(default = "d_progress")]
    pub progress: f64,
    /// Once, on success; default 10.
    #[serde(default = "d_success")]
    pub success: f64,
    /// Once, on a collision (negative); default -10.
    #[serde(default = "d_collision")]
    pub collision: f64,
    /// Every step (negative); default -0.01.
    #[serde(default = "d_time")]
    pub time: f64,
    /// Every step, times how deep the robot is inside the closest person's personal zone
    /// (1.2 m, centre distance), as a fraction of the zone; default -0.1.
    #[serde(default = "d_personal_space")]
    pub personal_space: f64,
}

fn d_progress() -> f64 {
    1.0
}
fn d_success() -> f64 {
    10.0
}
fn d_collision() -> f64 {
    -10.0
}
fn d_time() -> f64 {
    -0.01
}
fn d_personal_space() -> f64 {
    -0.1
}

impl Default for RewardWeights {
    fn default() -> Self {
        RewardWeights {
            progress: d_progress(),
            success: d_success(),
            collision: d_collision(),
            time: d_time(),
            personal_space: d_personal_space(),
        }
    }
}

/// The social model of the scenario (`[proxemics]`), validated; see [`crate::perception`].
#[derive(Clone, Debug, Serialize)]
pub struct Proxemics {
    /// Hall's zone radii `[intimate, personal, social]` (metres, centre to centre).
    pub zones: [f64; 3],
    /// Name of the base personal-space preset (`daza2021`, `calderita`, `sousa2022`).
    pub space: String,
    /// Base sigmas per side `[front, rear, right, left]` (metres) after overrides.
    pub sigmas: [f64; 4],
    /// `zones` (discrete Calderita costs) or `continuous` (1 + gain * personal-space value).
    pub cost_mode: String,
    /// Traversal factor inside the personal zone (default 4.0).
    pub personal_cost: f64,
    /// Traversal factor inside the social zone (default 2.0).
    pub social_cost: f64,
    /// Traversal factor of the public zone and free space (default 1.0).
    pub public_cost: f64,
    /// Gain of the continuous mode (default 3.0).
    pub continuous_gain: f64,
    /// Group detection: `delaunay`, `density`, `fformation` or `none`.
    pub groups: String,
    /// Distance rule d_max of the Delaunay detector (metres, default 1.5).
    pub d_max: f64,
    /// Whether the Delaunay detector uses the orientation rule (default true).
    pub orientation_rule: bool,
    /// How a group's feature values combine: `mean`, `min`, `mode`.
    pub aggregate: String,
    /// Socialization feature names, in the order of each person's `features`.
    pub features: Vec<String>,
    /// Influence vectors `[front, rear, right, left]`, one value per feature each, in [-1, 1].
    pub influence: [Vec<f64>; 4],
}

/// An agenda item: an activity on an object, in time of day.
#[derive(Clone, Debug, Serialize)]
pub struct ActivitySpec {
    /// Name (may be empty).
    pub name: String,
    /// The object whose interaction space the activity uses.
    pub object: String,
    /// Start (seconds after midnight).
    pub start: f64,
    /// End (seconds after midnight; may exceed 86400 for activities past midnight).
    pub end: f64,
}

/// R(t) parameters (Calderita §5.2.2).
#[derive(Clone, Debug, Serialize)]
pub struct AgendaSpec {
    /// Object-space factor with nothing scheduled (default 1.5).
    pub idle: f64,
    /// Factor while an activity runs (default 3.5).
    pub active: f64,
    /// Ramp before and after an activity (seconds; default 45 minutes).
    pub ramp: f64,
}

/// A validated scenario.
#[derive(Clone, Debug, Serialize)]
pub struct Scenario {
    /// Where it was read from (`<string>` for inline text).
    pub source: String,
    /// Scene settings.
    pub scene: Scene,
    /// Walls.
    pub walls: Vec<Wall>,
    /// Objects.
    pub objects: Vec<Object>,
    /// People.
    pub persons: Vec<Person>,
    /// Robots (at least one).
    pub robots: Vec<Robot>,
    /// Episode settings.
    pub episode: Episode,
    /// Observation settings.
    pub sensors: Sensors,
    /// Reward weights.
    pub reward: RewardWeights,
    /// The social model.
    pub proxemics: Proxemics,
    /// R(t) parameters.
    pub agenda: AgendaSpec,
    /// The agenda's activities.
    pub activities: Vec<ActivitySpec>,
}

// ---------------------------------------------------------------------------------------------
// Parsing
// ---------------------------------------------------------------------------------------------

/// Builds a scenario error.
fn err(
    file: &str,
    field: impl Into<String>,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> CoreError {
    CoreError::Scenario {
        file: file.to_string(),
        field: field.into(),
        expected: expected.into(),
        found: found.into(),
    }
}

/// Robots must not start overlapping: every pair of start discs at least touching-free.
fn check_robot_starts(file: &str, robots: &[Robot]) -> Result<()> {
    for (j, b) in robots.iter().enumerate() {
        for (i, a) in robots[..j].iter().enumerate() {
            let d = (a.start[0] - b.start[0]).hypot(a.start[1] - b.start[1]);
            let need = a.radius + b.radius;
            if d < need {
                return Err(err(
                    file,
                    format!("robot[{j}].start"),
                    format!(
                        "a start at least {need:.2} m (the sum of the radii) from robot[{i}]'s start {:?}",
                        [a.start[0], a.start[1]]
                    ),
                    format!("{:?}, {d:.2} m away (overlapping)", [b.start[0], b.start[1]]),
                ));
            }
        }
    }
    Ok(())
}

/// Arrays of tables a file that `extends` another may add to the base's instead of replacing
/// them, by listing their names in `append` (e.g. `append = ["person"]`).
pub const APPENDABLE: [&str; 5] = ["wall", "object", "person", "robot", "activity"];

/// How many `extends` links a scenario file may chain.
pub const MAX_EXTENDS: usize = 4;

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .map_err(|e| err(&path.display().to_string(), "<file>", "a readable UTF-8 TOML file", e.to_string()))
}

/// The merged table of a file that `extends` another (None if it does not).
fn extended_table(path: &Path, text: &str, depth: usize) -> Result<Option<toml::Table>> {
    if !text.contains("extends") {
        return Ok(None);
    }
    let file = path.display().to_string();
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let (line, col) = e.span().map_or((0, 0), |s| line_col(text, s.start));
        err(&file, format!("<toml line {line}, column {col}>"), "valid TOML", e.message().trim().to_string())
    })?;
    let Some(link) = table.remove("extends") else {
        return Ok(None);
    };
    let Some(name) = link.as_str() else {
        return Err(err(
            &file,
            "extends",
            "a path to a base scenario file (relative to this one)",
            link.to_string(),
        ));
    };
    if depth >= MAX_EXTENDS {
        return Err(err(
            &file,
            "extends",
            format!("at most {MAX_EXTENDS} chained extends"),
            format!("{name:?} at depth {}", depth + 1),
        ));
    }
    let base_path = path.parent().unwrap_or(Path::new(".")).join(name);
    if !base_path.is_file() {
        return Err(err(
            &file,
            "extends",
            "a path to an existing base scenario file (relative to this one)",
            format!("{name:?} ({} does not exist)", base_path.display()),
        ));
    }
    let base_text = read_text(&base_path)?;
    let mut base = match extended_table(&base_path, &base_text, depth + 1)? {
        Some(t) => t,
        None => base_text.parse().map_err(|e: toml::de::Error| {
            err(&base_path.display().to_string(), "<toml>", "valid TOML", e.message().trim().to_string())
        })?,
    };
    let append: Vec<String> = match table.remove("append") {
        None => Vec::new(),
        Some(toml::Value::Array(keys))
            if keys.iter().all(|k| k.as_str().is_some_and(|k| APPENDABLE.contains(&k))) =>
        {
            keys.iter().filter_map(|k| k.as_str().map(str::to_string)).collect()
        }
        Some(v) => {
            return Err(err(
                &file,
                "append",
                format!("a list of table names among {APPENDABLE:?} (their entries are added to the base's)"),
                v.to_string(),
            ));
        }
    };
    for (key, value) in table {
        match (key.as_str(), base.get_mut(&key), value) {
            ("scene", Some(toml::Value::Table(b)), toml::Value::Table(t)) => b.extend(t),
            (k, Some(toml::Value::Array(b)), toml::Value::Array(t)) if append.iter().any(|a| a == k) => {
                b.extend(t)
            }
            (_, _, v) => {
                base.insert(key, v);
            }
        }
    }
    Ok(Some(base))
}

/// Renders a serde path (`person.3.route`) the way the file is written (`person[3].route`).
fn dotted_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for seg in path.iter() {
        match seg {
            Segment::Seq { index } => out.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(key);
            }
            Segment::Unknown => {}
        }
    }
    if out.is_empty() { "<document>".to_string() } else { out }
}

/// Line and column (1-based) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |s| s.chars().count()) + 1;
    (line, col)
}

impl Scenario {
    /// Reads and validates a scenario file. A file with a top-level `extends = "base.toml"`
    /// (a path relative to it) starts from the base file: its `[scene]` keys override the
    /// base's one by one, and every other table or array it has (`[[robot]]`, `[episode]`,
    /// ...) replaces the base's whole, except the arrays named in its `append` list (among
    /// [`APPENDABLE`]), whose entries follow the base's (so `person[i]` in an error message
    /// counts the base's people first). Bases may extend others, up to [`MAX_EXTENDS`] deep.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = read_text(path)?;
        match extended_table(path, &text, 0)? {
            None => Self::from_toml_str(&text, &file),
            Some(table) => {
                let raw: RawScenario =
                    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
                        let field = dotted_path(e.path());
                        let msg = e.into_inner().message().trim().to_string();
                        let (expected, found) = split_serde_message(&msg);
                        err(&file, field, expected, found)
                    })?;
                build(raw, &file)
            }
        }
    }

    /// Parses and validates scenario text; `source` names it in error messages.
    pub fn from_toml_str(text: &str, source: &str) -> Result<Self> {
        let de = toml::de::Deserializer::parse(text).map_err(|e| {
            let (line, col) = e.span().map_or((0, 0), |s| line_col(text, s.start));
            err(
                source,
                format!("<toml line {line}, column {col}>"),
                "valid TOML",
                e.message().trim().to_string(),
            )
        })?;
        let raw: RawScenario = serde_path_to_error::deserialize(de).map_err(|e| {
            let field = dotted_path(e.path());
            let inner = e.into_inner();
            let where_ = inner.span().map(|s| line_col(text, s.start));
            let msg = inner.message().trim().to_string();
            let (expected, found) = split_serde_message(&msg);
            let field = match where_ {
                Some((l, c)) => format!("{field} (line {l}, column {c})"),
                None => field,
            };
            err(source, field, expected, found)
        })?;
        build(raw, source)
    }

    /// The agenda of the given spec and activities (validated: no overlaps, ends after starts).
    pub fn agenda_from(spec: &AgendaSpec, acts: &[ActivitySpec]) -> Result<crate::chronemics::Agenda> {
        let params =
            crate::chronemics::AgendaParams { idle: spec.idle, active: spec.active, ramp: spec.ramp };
        let list =
            acts.iter().map(|a| crate::chronemics::Activity::new(a.object.clone(), a.start, a.end)).collect();
        crate::chronemics::Agenda::new(list, params)
    }

    /// The scenario's agenda.
    pub fn agenda(&self) -> Result<crate::chronemics::Agenda> {
        Self::agenda_from(&self.agenda, &self.activities)
    }

    /// The social model described by `[proxemics]`.
    pub fn social_config(&self) -> crate::perception::SocialConfig {
        use crate::groups::{DelaunayParams, DensityParams, FFormationParams, FeatureAggregate, GroupMethod};
        use crate::proxemics::{Asymmetric, HallZones, PersonalSpace, SideInfluences};
        use crate::socialmap::{CostMode, SocialCosts};
        let p = &self.proxemics;
        let [front, rear, right, left] = p.sigmas;
        let space = match p.space.as_str() {
            "daza2021" if front == rear && rear == right && right == left => {
                PersonalSpace::Symmetric { sigma: front }
            }
            "calderita" if right == left => {
                PersonalSpace::Kirby { sigma_h: front, sigma_r: rear, sigma_s: right }
            }
            _ => PersonalSpace::Asymmetric(Asymmetric { front, rear, right, left }),
        };
        let zones = HallZones { intimate: p.zones[0], personal: p.zones[1], social: p.zones[2] };
        let mode = if p.cost_mode == "continuous" {
            CostMode::Continuous { gain: p.continuous_gain }
        } else {
            CostMode::Zones
        };
        let groups = match p.groups.as_str() {
            "none" => None,
            "density" => Some(GroupMethod::Density(DensityParams::default())),
            "fformation" => Some(GroupMethod::FFormation(FFormationParams::default())),
            _ => Some(GroupMethod::Delaunay(DelaunayParams {
                d_max: p.d_max,
                orientation_rule: p.orientation_rule,
                ..DelaunayParams::default()
            })),
        };
        let aggregate = match p.aggregate.as_str() {
            "min" => FeatureAggregate::Min,
            "mode" => FeatureAggregate::Mode,
            _ => FeatureAggregate::Mean,
        };
        let [fi, ri, rti, li] = p.influence.clone();
        crate::perception::SocialConfig {
            zones,
            space,
            features: p.features.clone(),
            influence: SideInfluences { front: fi, rear: ri, right: rti, left: li },
            costs: SocialCosts {
                intimate: zones.intimate,
                personal: zones.personal,
                social: zones.social,
                personal_cost: p.personal_cost,
                social_cost: p.social_cost,
                public_cost: p.public_cost,
                mode,
                max_factor: 5.0,
                object_margin: 0.0,
            },
            groups,
            aggregate,
            join: crate::groups::JoinParams { personal_radius: zones.personal, ..Default::default() },
        }
    }

    /// A copy with every robot's planner replaced by `name` (one of [`PlannerKind::NAMES`]).
    pub fn with_planner(&self, name: &str) -> Result<Self> {
        let kind = PlannerKind::parse(name).ok_or_else(|| {
            err(&self.source, "planner", format!("one of {:?}", PlannerKind::NAMES), format!("{name:?}"))
        })?;
        let mut s = self.clone();
        for r in &mut s.robots {
            r.planner = kind;
        }
        Ok(s)
    }

    /// A copy with robot `index`'s planner replaced by `name` (one of [`PlannerKind::NAMES`]).
    pub fn with_robot_planner(&self, index: usize, name: &str) -> Result<Self> {
        let field = format!("robot[{index}].planner");
        if index >= self.robots.len() {
            return Err(err(
                &self.source,
                format!("robot[{index}]"),
                format!("a robot index below {}", self.robots.len()),
                index.to_string(),
            ));
        }
        let kind = PlannerKind::parse(name).ok_or_else(|| {
            err(&self.source, field, format!("one of {:?}", PlannerKind::NAMES), format!("{name:?}"))
        })?;
        let mut s = self.clone();
        s.robots[index].planner = kind;
        Ok(s)
    }

    /// A copy with only the first `n` robots (1 <= `n` <= the number of `[[robot]]` entries).
    /// Followers of a robot that is left out stay at their place at its tour's start.
    pub fn with_robots(&self, n: usize) -> Result<Self> {
        if n == 0 || n > self.robots.len() {
            return Err(err(
                &self.source,
                "robots",
                format!(
                    "a number of robots in [1, {}] (the [[robot]] entries of the file)",
                    self.robots.len()
                ),
                n.to_string(),
            ));
        }
        let mut s = self.clone();
        s.robots.truncate(n);
        for p in &mut s.persons {
            if p.guide_robot.is_some_and(|j| j >= n) {
                p.guide_robot = None; // the tour waits at its start for a guide that is not there
            }
        }
        Ok(s)
    }

    /// A copy with every robot's elastic-band gains replaced where `Some` (each a number in
    /// `[0, EbandGains::MAX]`; errors name the field `eband.<gain>`).
    pub fn with_eband_gains(
        &self,
        contraction: Option<f64>,
        repulsion: Option<f64>,
        social: Option<f64>,
    ) -> Result<Self> {
        let mut s = self.clone();
        for r in &mut s.robots {
            r.eband = r.eband.merged(&self.source, "eband", contraction, repulsion, social)?;
        }
        Ok(s)
    }

    /// A copy whose robot `robot` goes to `goal` (world frame, metres; inside `scene.bounds`)
    /// instead of its file goal or approach task. Whether the goal is free space is checked when
    /// a world is built from the scenario.
    pub fn with_goal(&self, robot: usize, goal: [f64; 2]) -> Result<Self> {
        let field = format!("robot[{robot}].goal");
        if robot >= self.robots.len() {
            return Err(err(
                &self.source,
                field,
                format!("a robot index below {}", self.robots.len()),
                format!("{robot}"),
            ));
        }
        Checker { file: &self.source }.inside(&field, goal, self.scene.bounds)?;
        let mut s = self.clone();
        s.robots[robot].goal = goal;
        s.robots[robot].approach = None;
        Ok(s)
    }

    /// A copy whose episode starts at `time` (seconds after midnight, in [0, 86400)) instead of
    /// the file's `scene.start_time`: the agenda's activities (times of day) then fall at another
    /// point of the episode. Times the validated scenario holds as seconds into the episode keep
    /// their value, including a conversation's `start` and `end` written as times of day (they
    /// were converted with the file's start time). Errors name the field `scene.start_time`.
    pub fn with_start_time(&self, time: f64) -> Result<Self> {
        if !(time.is_finite() && (0.0..86400.0).contains(&time)) {
            return Err(err(
                &self.source,
                "scene.start_time",
                "seconds after midnight in [0, 86400)",
                time.to_string(),
            ));
        }
        let mut s = self.clone();
        s.scene.start_time = time;
        Ok(s)
    }

    /// JSON of the validated scenario (defaults filled in, world polygons computed).
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// Seconds per control step.
    pub fn control_dt(&self) -> f64 {
        1.0 / self.scene.control_hz
    }

    /// Number of physics steps per control step.
    pub fn frame_skip(&self) -> usize {
        (self.scene.physics_hz / self.scene.control_hz).round() as usize
    }

    /// Maximum number of control steps of an episode.
    pub fn max_steps(&self) -> usize {
        (self.episode.max_time * self.scene.control_hz).ceil() as usize
    }

    /// Solid static polygons (walls, then solid object footprints) in world coordinates.
    pub fn static_polygons(&self) -> Vec<Vec<[f64; 2]>> {
        let walls = self.walls.iter().map(|w| w.polygon.clone());
        let objects = self.objects.iter().filter(|o| o.solid).map(|o| o.footprint.clone());
        walls.chain(objects).collect()
    }
}

/// serde messages look like "invalid type: string \"x\", expected a number" or
/// "unknown field `foo`, expected one of `a`, `b`"; split them into (expected, found).
fn split_serde_message(msg: &str) -> (String, String) {
    if let Some(idx) = msg.find(", expected ") {
        let found = msg[..idx].trim_start_matches("invalid type: ").trim_start_matches("invalid value: ");
        let expected = &msg[idx + ", expected ".len()..];
        return (expected.to_string(), found.to_string());
    }
    if let Some(rest) = msg.strip_prefix("missing field ") {
        return (format!("the required field {rest}"), "nothing".to_string());
    }
    ("a valid value".to_string(), msg.to_string())
}

struct Checker<'a> {
    file: &'a str,
}

impl Checker<'_> {
    fn finite(&self, field: &str, values: &[f64]) -> Result<()> {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(err(self.file, field, "finite numbers", format!("{v}")));
        }
        Ok(())
    }

    fn range(&self, field: &str, v: f64, lo: f64, hi: f64, lo_open: bool) -> Result<()> {
        let ok_lo = if lo_open { v > lo } else { v >= lo };
        if !v.is_finite() || !ok_lo || v > hi {
            let l = if lo_open { "(" } else { "[" };
            return Err(err(self.file, field, format!("a number in {l}{lo}, {hi}]"), format!("{v}")));
        }
        Ok(())
    }

    fn inside(&self, field: &str, p: [f64; 2], b: [f64; 4]) -> Result<()> {
        self.finite(field, &p)?;
        if p[0] < b[0] || p[0] > b[2] || p[1] < b[1] || p[1] > b[3] {
            return Err(err(
                self.file,
                field,
                format!("a point inside scene.bounds [{}, {}, {}, {}]", b[0], b[1], b[2], b[3]),
                format!("[{}, {}]", p[0], p[1]),
            ));
        }
        Ok(())
    }
}

/// Parses `HH:MM` or `HH:MM:SS` into seconds after midnight.
pub fn parse_time_of_day(s: &str) -> Option<f64> {
    let parts: Vec<&str> = s.trim().split(':').collect();
    if parts.len() < 2 || parts.len() > 3 {
        return None;
    }
    let h: u32 = parts[0].parse().ok()?;
    let m: u32 = parts[1].parse().ok()?;
    let sec: u32 = if parts.len() == 3 { parts[2].parse().ok()? } else { 0 };
    if h > 23 || m > 59 || sec > 59 {
        return None;
    }
    Some(f64::from(h * 3600 + m * 60 + sec))
}

/// Oriented rectangle centred at `c` with half extents along its local axes, CCW.
fn oriented_rect(c: [f64; 2], theta: f64, half_x: f64, half_y: f64) -> Vec<[f64; 2]> {
    let (s, co) = theta.sin_cos();
    [(-half_x, -half_y), (half_x, -half_y), (half_x, half_y), (-half_x, half_y)]
        .iter()
        .map(|&(lx, ly)| [c[0] + co * lx - s * ly, c[1] + s * lx + co * ly])
        .collect()
}

/// Circle approximated by [`CIRCLE_VERTICES`] vertices, CCW, circumscribing the circle (so the
/// polygon contains the disc).
fn circle_polygon(c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    let n = CIRCLE_VERTICES;
    let rr = r / (std::f64::consts::PI / n as f64).cos();
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [c[0] + rr * a.cos(), c[1] + rr * a.sin()]
        })
        .collect()
}

/// Signed area (positive when CCW).
fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        * 0.5
}

fn build(raw: RawScenario, file: &str) -> Result<Scenario> {
    let ck = Checker { file };
    // ---- scene
    let s = &raw.scene;
    ck.finite("scene.bounds", &s.bounds)?;
    let b = s.bounds;
    if !(b[2] > b[0] && b[3] > b[1]) {
        return Err(err(
            file,
            "scene.bounds",
            "[xmin, ymin, xmax, ymax] with xmax > xmin and ymax > ymin",
            format!("{b:?}"),
        ));
    }
    if (b[2] - b[0]) * (b[3] - b[1]) > 1.0e6 {
        return Err(err(file, "scene.bounds", "an area of at most 1 km^2", format!("{b:?}")));
    }
    ck.range("scene.resolution", s.resolution, 0.0, 1.0, true)?;
    let start_time = parse_time_of_day(&s.start_time).ok_or_else(|| {
        err(
            file,
            "scene.start_time",
            "a time of day \"HH:MM\" or \"HH:MM:SS\"",
            format!("{:?}", s.start_time),
        )
    })?;
    ck.range("scene.control_hz", s.control_hz, 0.0, 1000.0, true)?;
    ck.range("scene.physics_hz", s.physics_hz, 0.0, 10000.0, true)?;
    let ratio = s.physics_hz / s.control_hz;
    if ratio < 1.0 || (ratio - ratio.round()).abs() > 1e-9 {
        return Err(err(
            file,
            "scene.physics_hz",
            format!("an integer multiple of scene.control_hz ({})", s.control_hz),
            format!("{}", s.physics_hz),
        ));
    }
    ck.range("scene.wall_height", s.wall_height, 0.0, 20.0, true)?;
    if s.name.trim().is_empty() {
        return Err(err(file, "scene.name", "a non-empty name", "\"\""));
    }
    let scene = Scene {
        name: s.name.clone(),
        description: s.description.clone(),
        bounds: b,
        resolution: s.resolution,
        start_time,
        control_hz: s.control_hz,
        physics_hz: s.physics_hz,
        wall_height: s.wall_height,
    };

    // ---- walls
    let mut walls = Vec::with_capacity(raw.wall.len());
    for (i, w) in raw.wall.iter().enumerate() {
        let f = format!("wall[{i}]");
        ck.finite(&format!("{f}.from"), &w.from)?;
        ck.finite(&format!("{f}.to"), &w.to)?;
        ck.range(&format!("{f}.thickness"), w.thickness, 0.0, 5.0, true)?;
        let height = w.height.unwrap_or(s.wall_height);
        ck.range(&format!("{f}.height"), height, 0.0, 20.0, true)?;
        let (dx, dy) = (w.to[0] - w.from[0], w.to[1] - w.from[1]);
        let len = dx.hypot(dy);
        if len < 1e-6 {
            return Err(err(
                file,
                format!("{f}.to"),
                "a point different from wall.from",
                format!("{:?}", w.to),
            ));
        }
        let c = [(w.from[0] + w.to[0]) * 0.5, (w.from[1] + w.to[1]) * 0.5];
        // Walls extend half a thickness past their end points so that corners close.
        let polygon = oriented_rect(c, dy.atan2(dx), len * 0.5 + w.thickness * 0.5, w.thickness * 0.5);
        walls.push(Wall { from: w.from, to: w.to, thickness: w.thickness, height, polygon });
    }

    // ---- objects
    let mut objects = Vec::with_capacity(raw.object.len());
    for (i, o) in raw.object.iter().enumerate() {
        let f = format!("object[{i}]");
        if o.name.trim().is_empty() {
            return Err(err(file, format!("{f}.name"), "a non-empty name", "\"\""));
        }
        if let Some(j) = raw.object[..i].iter().position(|p| p.name == o.name) {
            return Err(err(
                file,
                format!("{f}.name"),
                format!("a unique name (object[{j}] is also called that)"),
                format!("{:?}", o.name),
            ));
        }
        ck.finite(&format!("{f}.pose"), &o.pose)?;
        ck.inside(&format!("{f}.pose"), [o.pose[0], o.pose[1]], b)?;
        let height = o.height.unwrap_or_else(|| o.kind.default_height());
        ck.range(&format!("{f}.height"), height, 0.0, 20.0, true)?;
        let c = [o.pose[0], o.pose[1]];
        let (size, radius, footprint) = match (o.size, o.radius) {
            (Some(sz), None) => {
                ck.range(&format!("{f}.size[0]"), sz[0], 0.0, 50.0, true)?;
                ck.range(&format!("{f}.size[1]"), sz[1], 0.0, 50.0, true)?;
                (sz, None, oriented_rect(c, o.pose[2], sz[0] * 0.5, sz[1] * 0.5))
            }
            (None, Some(r)) => {
                if !o.kind.is_round_capable() {
                    return Err(err(
                        file,
                        format!("{f}.radius"),
                        format!("size = [depth, width] for a {:?}", o.kind),
                        "radius",
                    ));
                }
                ck.range(&format!("{f}.radius"), r, 0.0, 25.0, true)?;
                ([2.0 * r, 2.0 * r], Some(r), circle_polygon(c, r))
            }
            (Some(_), Some(_)) => {
                return Err(err(file, format!("{f}.radius"), "either size or radius, not both", "both"));
            }
            (None, None) => {
                return Err(err(
                    file,
                    format!("{f}.size"),
                    "size = [depth, width] (or radius for round objects)",
                    "nothing",
                ));
            }
        };
        let interaction = match &o.interaction {
            None => None,
            Some(ri) => Some(build_interaction(&ck, &format!("{f}.interaction"), ri, o, size, radius, b)?),
        };
        objects.push(Object {
            name: o.name.clone(),
            kind: o.kind,
            pose: o.pose,
            size,
            radius,
            height,
            solid: o.solid,
            footprint,
            interaction,
        });
    }

    // ---- persons
    let mut persons = Vec::with_capacity(raw.person.len());
    for (i, p) in raw.person.iter().enumerate() {
        persons.push(build_person(&ck, i, p, &objects, start_time, b)?);
    }
    check_unique(file, "person", persons.iter().map(|p| p.name.as_str()))?;
    link_people(&ck, &raw.person, &mut persons)?;

    // ---- proxemics, features, agenda
    let proxemics = build_proxemics(&ck, &raw.proxemics)?;
    for (i, (person, rp)) in persons.iter_mut().zip(&raw.person).enumerate() {
        person.features = person_features(&ck, i, rp, &proxemics.features)?;
    }
    let (agenda, activities) = build_agenda(&ck, &raw.agenda, &raw.activity, &objects)?;

    // ---- robots
    if raw.robot.is_empty() {
        return Err(err(file, "robot", "at least one [[robot]] table", "none"));
    }
    let mut robots = Vec::with_capacity(raw.robot.len());
    for (i, r) in raw.robot.iter().enumerate() {
        let f = format!("robot[{i}]");
        ck.finite(&format!("{f}.start"), &r.start)?;
        ck.inside(&format!("{f}.start"), [r.start[0], r.start[1]], b)?;
        ck.range(&format!("{f}.radius"), r.radius, 0.0, 2.0, true)?;
        ck.range(&format!("{f}.max_speed"), r.max_speed, 0.0, 5.0, true)?;
        ck.range(&format!("{f}.max_angular_speed"), r.max_angular_speed, 0.0, 10.0, true)?;
        ck.range(&format!("{f}.max_accel"), r.max_accel, 0.0, 20.0, true)?;
        ck.range(&format!("{f}.inflation_margin"), r.inflation_margin, 0.0, 1.0, false)?;
        let (goal, approach) = match (&r.goal, &r.approach) {
            (Some(g), None) => {
                ck.inside(&format!("{f}.goal"), *g, b)?;
                (*g, None)
            }
            (None, Some(a)) => {
                let (g, ap) = build_approach(&ck, &f, a, &persons, &proxemics, r.radius)?;
                ck.inside(&format!("{f}.approach"), g, b)?;
                (g, Some(ap))
            }
            (Some(_), Some(_)) => {
                return Err(err(file, format!("{f}.approach"), "either goal or approach, not both", "both"));
            }
            (None, None) => {
                return Err(err(
                    file,
                    format!("{f}.goal"),
                    "goal = [x, y] (or an approach = { person = ... } task)",
                    "nothing",
                ));
            }
        };
        for (k, w) in r.waypoints.iter().enumerate() {
            ck.inside(&format!("{f}.waypoints[{k}]"), *w, b)?;
        }
        ck.range(&format!("{f}.dwell"), r.dwell, 0.0, 3600.0, false)?;
        if r.dwell > 0.0 && r.waypoints.is_empty() {
            return Err(err(
                file,
                format!("{f}.dwell"),
                "a dwell only with waypoints = [[x, y], ...] to stop at",
                format!("dwell = {} without waypoints", r.dwell),
            ));
        }
        robots.push(Robot {
            name: r.name.clone().unwrap_or_else(|| format!("robot_{i}")),
            start: r.start,
            goal,
            approach,
            planner: r.planner,
            radius: r.radius,
            max_speed: r.max_speed,
            max_angular_speed: r.max_angular_speed,
            max_accel: r.max_accel,
            inflation_margin: r.inflation_margin,
            eband: EbandGains::default().merged(
                file,
                &format!("{f}.eband"),
                r.eband.contraction_gain,
                r.eband.repulsion_gain,
                r.eband.social_gain,
            )?,
            waypoints: r.waypoints.clone(),
            dwell: r.dwell,
        });
    }
    check_unique(file, "robot", robots.iter().map(|r| r.name.as_str()))?;
    link_robot_guides(&ck, &raw.person, &mut persons, &robots)?;
    check_robot_starts(file, &robots)?;

    // ---- episode, sensors, reward
    let e = &raw.episode;
    ck.range("episode.max_time", e.max_time, 0.0, 86400.0, true)?;
    ck.range("episode.success_radius", e.success_radius, 0.0, 10.0, true)?;
    ck.range("episode.randomize.speed_jitter", e.randomize.speed_jitter, 0.0, 0.5, false)?;
    ck.range("episode.randomize.robot_start_jitter", e.randomize.robot_start_jitter, 0.0, 5.0, false)?;
    let sn = &raw.sensors;
    if !(4..=1440).contains(&sn.lidar_rays) {
        return Err(err(file, "sensors.lidar_rays", "an integer in [4, 1440]", sn.lidar_rays.to_string()));
    }
    ck.range("sensors.lidar_range", sn.lidar_range, 0.0, 50.0, true)?;
    if !(1..=64).contains(&sn.k_nearest) {
        return Err(err(file, "sensors.k_nearest", "an integer in [1, 64]", sn.k_nearest.to_string()));
    }
    let rw = &raw.reward;
    for (name, v) in [
        ("progress", rw.progress),
        ("success", rw.success),
        ("collision", rw.collision),
        ("time", rw.time),
        ("personal_space", rw.personal_space),
    ] {
        ck.range(&format!("reward.{name}"), v, -1e6, 1e6, false)?;
    }

    Ok(Scenario {
        source: file.to_string(),
        scene,
        walls,
        objects,
        persons,
        robots,
        episode: Episode {
            max_time: e.max_time,
            success_radius: e.success_radius,
            randomize: e.randomize.clone(),
        },
        sensors: raw.sensors,
        reward: raw.reward,
        proxemics,
        agenda,
        activities,
    })
}

/// Which per-behaviour fields a person may carry; any other one set is an error.
fn behaviour_fields(b: Behaviour) -> &'static [&'static str] {
    match b {
        Behaviour::Walker => &["route", "dwell", "stops"],
        Behaviour::Standing => &["pose"],
        Behaviour::Visitor => &["exhibits", "dwell"],
        Behaviour::Conversation => &["home", "spot", "start", "end"],
        Behaviour::Guide => &["route", "dwell", "stops"],
        Behaviour::Follower => &["guide", "gather_radius"],
        Behaviour::Seated => &["seat", "place"],
        Behaviour::Resident | Behaviour::Staff => &["home", "attends", "lead_minutes"],
    }
}

/// A speed in m/s or a preset name.
fn parse_speed(ck: &Checker<'_>, field: &str, v: Option<&toml::Value>) -> Result<f64> {
    let names: Vec<&str> = SPEED_PRESETS.iter().map(|(n, _)| *n).collect();
    let expected = format!("a number in (0, 2.5] (m/s) or one of the presets {names:?}");
    let speed = match v {
        None => d_person_speed(),
        Some(toml::Value::Float(x)) => *x,
        Some(toml::Value::Integer(x)) => *x as f64,
        Some(toml::Value::String(name)) => SPEED_PRESETS
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| *s)
            .ok_or_else(|| err(ck.file, field, expected.clone(), format!("{name:?}")))?,
        Some(other) => return Err(err(ck.file, field, expected, other.to_string())),
    };
    ck.range(field, speed, 0.0, 2.5, true)?;
    Ok(speed)
}

/// A time as seconds into the episode (a number) or a time of day ("HH:MM"), to seconds after
/// the episode start.
fn parse_episode_time(ck: &Checker<'_>, field: &str, v: &toml::Value, start_time: f64) -> Result<f64> {
    let expected = "seconds into the episode (a number) or a time of day \"HH:MM\"";
    match v {
        toml::Value::Float(x) if x.is_finite() => Ok(*x),
        toml::Value::Integer(x) => Ok(*x as f64),
        toml::Value::String(s) => parse_time_of_day(s)
            .map(|t| t - start_time)
            .ok_or_else(|| err(ck.file, field, expected, format!("{s:?}"))),
        other => Err(err(ck.file, field, expected, other.to_string())),
    }
}

/// An object named (string) or indexed (integer) by `v`.
fn object_ref(ck: &Checker<'_>, field: &str, v: &toml::Value, objects: &[Object]) -> Result<usize> {
    let expected = format!("the name or index of an [[object]] ({} defined)", objects.len());
    match v {
        toml::Value::String(name) => objects
            .iter()
            .position(|o| &o.name == name)
            .ok_or_else(|| err(ck.file, field, expected, format!("{name:?}"))),
        toml::Value::Integer(k) if *k >= 0 && (*k as usize) < objects.len() => Ok(*k as usize),
        other => Err(err(ck.file, field, expected, other.to_string())),
    }
}

fn build_person(
    ck: &Checker<'_>,
    i: usize,
    p: &RawPerson,
    objects: &[Object],
    start_time: f64,
    b: [f64; 4],
) -> Result<Person> {
    let file = ck.file;
    let f = format!("person[{i}]");
    let name = p.name.clone().unwrap_or_else(|| format!("person_{i}"));
    ck.range(&format!("{f}.radius"), p.radius, 0.0, 0.5, true)?;
    ck.range(&format!("{f}.height"), p.height, 0.3, 2.5, false)?;
    let speed = parse_speed(ck, &format!("{f}.speed"), p.speed.as_ref())?;
    ck.range(&format!("{f}.dwell"), p.dwell, 0.0, 3600.0, false)?;
    ck.range(&format!("{f}.lead_minutes"), p.lead_minutes, 0.0, 120.0, false)?;
    ck.range(&format!("{f}.gather_radius"), p.gather_radius, 0.5, 5.0, false)?;
    // Fields that do not belong to the behaviour are errors (a typo would otherwise be ignored).
    let set: [(&str, bool); 12] = [
        ("route", !p.route.is_empty()),
        ("pose", p.pose.is_some()),
        ("exhibits", !p.exhibits.is_empty()),
        ("home", p.home.is_some()),
        ("spot", p.spot.is_some()),
        ("start", p.start.is_some()),
        ("end", p.end.is_some()),
        ("seat", p.seat.is_some()),
        ("guide", p.guide.is_some()),
        ("stops", p.stops.is_some()),
        ("attends", !p.attends.is_empty()),
        ("place", p.place != 0),
    ];
    let allowed = behaviour_fields(p.behaviour);
    if let Some((field, _)) = set.iter().find(|(n, on)| *on && !allowed.contains(n)) {
        let what = match *field {
            "pose" if p.behaviour == Behaviour::Walker => {
                "no pose for a walker (it starts on its route)".into()
            }
            "route" if p.behaviour == Behaviour::Standing => "no route for a standing person".into(),
            _ => format!("no {field} for a {:?} (its fields: {allowed:?})", p.behaviour),
        };
        return Err(err(file, format!("{f}.{field}"), what, "a value"));
    }
    for (k, w) in p.route.iter().enumerate() {
        ck.inside(&format!("{f}.route[{k}]"), *w, b)?;
    }
    let need = |field: &str, v: Option<[f64; 2]>| -> Result<[f64; 2]> {
        let v = v.ok_or_else(|| {
            err(file, format!("{f}.{field}"), format!("{field} = [x, y] for a {:?}", p.behaviour), "nothing")
        })?;
        ck.inside(&format!("{f}.{field}"), v, b)?;
        Ok(v)
    };
    let mut person = Person {
        name,
        behaviour: p.behaviour,
        speed,
        dwell: p.dwell,
        radius: p.radius,
        height: p.height,
        group: p.group,
        aware: p.aware,
        gather_radius: p.gather_radius,
        lead: p.lead_minutes * 60.0,
        ..Person::default()
    };
    let pose = match p.behaviour {
        Behaviour::Walker | Behaviour::Guide => {
            if p.route.len() < 2 {
                return Err(err(
                    file,
                    format!("{f}.route"),
                    format!("at least 2 waypoints for a {:?}", p.behaviour),
                    format!("{} waypoint(s)", p.route.len()),
                ));
            }
            for k in 0..p.route.len() {
                let a = p.route[k];
                let c = p.route[(k + 1) % p.route.len()];
                if (a[0] - c[0]).hypot(a[1] - c[1]) < 1e-6 {
                    return Err(err(
                        file,
                        format!("{f}.route[{}]", (k + 1) % p.route.len()),
                        "a waypoint different from the previous one",
                        format!("{c:?}"),
                    ));
                }
            }
            if p.behaviour == Behaviour::Guide || p.stops.is_some() {
                let n = p.route.len();
                let stops = p.stops.clone().unwrap_or_else(|| (0..n).collect());
                person.stops = vec![false; n];
                for (k, &s) in stops.iter().enumerate() {
                    if s >= n {
                        return Err(err(
                            file,
                            format!("{f}.stops[{k}]"),
                            format!("a waypoint index below {n} (the route's length)"),
                            s.to_string(),
                        ));
                    }
                    person.stops[s] = true;
                }
                if p.behaviour == Behaviour::Guide && !person.stops[0] {
                    return Err(err(
                        file,
                        format!("{f}.stops"),
                        "a list that includes waypoint 0 (the tour starts with a stop there)",
                        format!("{stops:?}"),
                    ));
                }
            }
            let (a, c) = (p.route[0], p.route[1]);
            [a[0], a[1], (c[1] - a[1]).atan2(c[0] - a[0])]
        }
        Behaviour::Standing => {
            let pose = p.pose.ok_or_else(|| {
                err(file, format!("{f}.pose"), "pose = [x, y, theta] for a standing person", "nothing")
            })?;
            ck.finite(&format!("{f}.pose"), &pose)?;
            ck.inside(&format!("{f}.pose"), [pose[0], pose[1]], b)?;
            pose
        }
        Behaviour::Visitor => {
            if p.exhibits.is_empty() {
                return Err(err(file, format!("{f}.exhibits"), "at least one exhibit for a visitor", "none"));
            }
            for (k, v) in p.exhibits.iter().enumerate() {
                let field = format!("{f}.exhibits[{k}]");
                let o = object_ref(ck, &field, v, objects)?;
                if objects[o].interaction.is_none() {
                    return Err(err(
                        file,
                        field,
                        "an object with an interaction (viewing) space",
                        format!("{:?} (has none)", objects[o].name),
                    ));
                }
                person.exhibits.push(o);
            }
            let o = &objects[person.exhibits[0]];
            [o.pose[0], o.pose[1], 0.0] // replaced by the viewing spot when the world is built
        }
        Behaviour::Conversation => {
            let home = need("home", p.home)?;
            person.home = Some(home);
            person.spot = Some(need("spot", p.spot)?);
            let time = |field: &str, v: &Option<toml::Value>| -> Result<f64> {
                let v = v.as_ref().ok_or_else(|| {
                    err(file, format!("{f}.{field}"), "a time for a conversation", "nothing")
                })?;
                parse_episode_time(ck, &format!("{f}.{field}"), v, start_time)
            };
            let (t0, t1) = (time("start", &p.start)?, time("end", &p.end)?);
            if t1 <= t0 {
                return Err(err(
                    file,
                    format!("{f}.end"),
                    format!("a time after start ({t0} s)"),
                    format!("{t1} s"),
                ));
            }
            person.schedule = Some([t0, t1]);
            if p.group.is_none() {
                return Err(err(file, format!("{f}.group"), "the conversation's group id", "nothing"));
            }
            [home[0], home[1], 0.0]
        }
        Behaviour::Follower => {
            if p.guide.is_none() {
                return Err(err(
                    file,
                    format!("{f}.guide"),
                    "the name of a guide [[person]], or \"robot:<name>\" of a [[robot]]",
                    "nothing",
                ));
            }
            [0.0; 3] // placed at the guide's first stop by link_people
        }
        Behaviour::Seated => {
            let seat = p.seat.as_ref().ok_or_else(|| {
                err(file, format!("{f}.seat"), "the name of a bench, sofa or chair [[object]]", "nothing")
            })?;
            let o = objects.iter().find(|o| &o.name == seat).ok_or_else(|| {
                err(
                    file,
                    format!("{f}.seat"),
                    "the name of a bench, sofa or chair [[object]]",
                    format!("{seat:?}"),
                )
            })?;
            if !matches!(o.kind, ObjectKind::Bench | ObjectKind::Sofa | ObjectKind::Chair) {
                return Err(err(
                    file,
                    format!("{f}.seat"),
                    "a bench, sofa or chair",
                    format!("{seat:?}, a {:?}", o.kind),
                ));
            }
            let places = ((o.size[1] / SEAT_SPACING).floor() as usize).max(1);
            if p.place >= places {
                return Err(err(
                    file,
                    format!("{f}.place"),
                    format!("a seat index below {places} ({seat:?} seats {places})"),
                    p.place.to_string(),
                ));
            }
            let along = (p.place as f64 - (places as f64 - 1.0) * 0.5) * SEAT_SPACING;
            let (s, c) = o.pose[2].sin_cos();
            [o.pose[0] - s * along, o.pose[1] + c * along, o.pose[2]]
        }
        Behaviour::Resident | Behaviour::Staff => {
            let home = need("home", p.home)?;
            person.home = Some(home);
            if p.attends.is_empty() {
                return Err(err(
                    file,
                    format!("{f}.attends"),
                    format!("the names of the objects whose activities the {:?} attends", p.behaviour),
                    "none",
                ));
            }
            for (k, name) in p.attends.iter().enumerate() {
                let field = format!("{f}.attends[{k}]");
                let o = object_ref(ck, &field, &toml::Value::String(name.clone()), objects)?;
                if objects[o].interaction.is_none() {
                    return Err(err(
                        file,
                        field,
                        "an object with an interaction space (where its activities take place)",
                        format!("{name:?} (has none)"),
                    ));
                }
                person.attends.push(o);
            }
            [home[0], home[1], 0.0]
        }
    };
    person.pose = pose;
    person.route.clone_from(&p.route);
    Ok(person)
}

/// Prefix of a follower's `guide` naming a robot (`guide = "robot:<name>"`).
pub const ROBOT_GUIDE: &str = "robot:";

/// Followers of robots: the robot's index, its tour and stops, and the follower's reference
/// pose (the robot's start; its place is planned when the world is built).
fn link_robot_guides(
    ck: &Checker<'_>,
    raw: &[RawPerson],
    persons: &mut [Person],
    robots: &[Robot],
) -> Result<()> {
    for (i, (rp, person)) in raw.iter().zip(persons.iter_mut()).enumerate() {
        let Some(name) = rp.guide.as_ref().and_then(|n| n.strip_prefix(ROBOT_GUIDE)) else { continue };
        let j = robots.iter().position(|r| r.name == name).ok_or_else(|| {
            err(
                ck.file,
                format!("person[{i}].guide"),
                format!(
                    "\"robot:<name>\" naming a [[robot]] (one of {:?}), or the name of a person with behaviour = \"guide\"",
                    robots.iter().map(|r| r.name.as_str()).collect::<Vec<_>>()
                ),
                format!("{:?}", rp.guide.as_deref().unwrap_or_default()),
            )
        })?;
        let r = &robots[j];
        person.guide_robot = Some(j);
        person.tour = std::iter::once([r.start[0], r.start[1]])
            .chain(r.waypoints.iter().copied())
            .chain(std::iter::once(r.goal))
            .collect();
        let n = person.tour.len();
        person.tour_stops = (0..n).map(|k| k == 0 || k + 1 == n || r.dwell > 0.0).collect();
        person.pose = [r.start[0], r.start[1], 0.0];
    }
    Ok(())
}

/// Cross-person checks: followers' guides, conversations' shared spot and schedule, and groups
/// of at least two people.
fn link_people(ck: &Checker<'_>, raw: &[RawPerson], persons: &mut [Person]) -> Result<()> {
    let file = ck.file;
    for i in 0..persons.len() {
        let f = format!("person[{i}]");
        if let Some(name) = raw[i].guide.as_ref().filter(|n| !n.starts_with(ROBOT_GUIDE)) {
            let g = persons.iter().position(|q| &q.name == name && q.behaviour == Behaviour::Guide);
            let g = g.ok_or_else(|| {
                err(
                    file,
                    format!("{f}.guide"),
                    "the name of a person with behaviour = \"guide\", or \"robot:<name>\" of a [[robot]]",
                    format!("{name:?}"),
                )
            })?;
            persons[i].guide = Some(g);
            let r = persons[g].route[0];
            persons[i].pose = [r[0], r[1], 0.0]; // the slot is computed when the world is built
        }
        if let Some(g) = persons[i].group {
            let members: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].group == Some(g)).collect();
            if members.len() < 2 {
                return Err(err(
                    file,
                    format!("{f}.group"),
                    "a group id shared by at least 2 people",
                    format!("group {g} with 1 member"),
                ));
            }
            if persons[i].behaviour == Behaviour::Conversation {
                let first = members[0];
                for &k in &members {
                    if persons[k].behaviour != Behaviour::Conversation {
                        return Err(err(
                            file,
                            format!("person[{k}].behaviour"),
                            format!("\"conversation\" like the rest of group {g}"),
                            format!("{:?}", persons[k].behaviour),
                        ));
                    }
                }
                for (field, same) in [
                    ("spot", persons[i].spot == persons[first].spot),
                    ("start", persons[i].schedule.map(|s| s[0]) == persons[first].schedule.map(|s| s[0])),
                    ("end", persons[i].schedule.map(|s| s[1]) == persons[first].schedule.map(|s| s[1])),
                ] {
                    if !same {
                        return Err(err(
                            file,
                            format!("{f}.{field}"),
                            format!("the same {field} as person[{first}] (the same conversation, group {g})"),
                            "a different value",
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Validates `[proxemics]` by building the social model it describes.
fn build_proxemics(ck: &Checker<'_>, r: &RawProxemics) -> Result<Proxemics> {
    let file = ck.file;
    let zones = match (r.zones.as_str(), r.zone_radii) {
        (_, Some(radii)) => radii,
        ("evaluation", None) => [0.45, 1.2, 3.6],
        ("daza2021", None) => [0.5, 1.0, 4.0],
        (other, None) => {
            return Err(err(
                file,
                "proxemics.zones",
                "\"evaluation\" or \"daza2021\" (or zone_radii = [i, p, s])",
                format!("{other:?}"),
            ));
        }
    };
    crate::proxemics::HallZones::new(zones[0], zones[1], zones[2])
        .map_err(|e| prefix_input(file, "proxemics.zone_radii", e))?;
    let mut sigmas = match r.space.as_str() {
        "calderita" => [2.0, 1.0, 4.0 / 3.0, 4.0 / 3.0],
        "daza2021" => [1.0; 4],
        "sousa2022" => [1.0; 4],
        other => {
            return Err(err(
                file,
                "proxemics.space",
                "\"calderita\", \"daza2021\" or \"sousa2022\"",
                format!("{other:?}"),
            ));
        }
    };
    if let Some(sg) = r.sigma {
        ck.range("proxemics.sigma", sg, 0.0, 20.0, true)?;
        sigmas = [sg; 4];
    }
    for (k, (name, v)) in [
        ("sigma_front", r.sigma_front),
        ("sigma_rear", r.sigma_rear),
        ("sigma_right", r.sigma_right),
        ("sigma_left", r.sigma_left),
    ]
    .into_iter()
    .enumerate()
    {
        if let Some(v) = v {
            ck.range(&format!("proxemics.{name}"), v, 0.0, 20.0, true)?;
            sigmas[k] = v;
        }
    }
    if !matches!(r.cost_mode.as_str(), "zones" | "continuous") {
        return Err(err(
            file,
            "proxemics.cost_mode",
            "\"zones\" or \"continuous\"",
            format!("{:?}", r.cost_mode),
        ));
    }
    ck.range("proxemics.public_cost", r.public_cost, 1.0, 5.0, false)?;
    ck.range("proxemics.social_cost", r.social_cost, r.public_cost, 5.0, false)?;
    ck.range("proxemics.personal_cost", r.personal_cost, r.social_cost, 5.0, false)?;
    ck.range("proxemics.continuous_gain", r.continuous_gain, 0.0, 4.0, false)?;
    if !matches!(r.groups.as_str(), "delaunay" | "density" | "fformation" | "none") {
        return Err(err(
            file,
            "proxemics.groups",
            "\"delaunay\", \"density\", \"fformation\" or \"none\"",
            format!("{:?}", r.groups),
        ));
    }
    let d_max = r.d_max.unwrap_or(1.5);
    ck.range("proxemics.d_max", d_max, 0.0, 20.0, true)?;
    if !matches!(r.aggregate.as_str(), "mean" | "min" | "mode") {
        return Err(err(
            file,
            "proxemics.aggregate",
            "\"mean\", \"min\" or \"mode\"",
            format!("{:?}", r.aggregate),
        ));
    }
    let nf = r.features.len();
    let inf = &r.influence;
    let mut influence: [Vec<f64>; 4] =
        [inf.front.clone(), inf.rear.clone(), inf.right.clone(), inf.left.clone()];
    for (side, v) in ["front", "rear", "right", "left"].iter().zip(influence.iter_mut()) {
        if v.is_empty() {
            *v = vec![0.0; nf];
        }
        if v.len() != nf {
            return Err(err(
                file,
                format!("proxemics.influence.{side}"),
                format!("{nf} value(s), one per feature in proxemics.features"),
                format!("{} value(s)", v.len()),
            ));
        }
        for (k, x) in v.iter().enumerate() {
            ck.range(&format!("proxemics.influence.{side}[{k}]"), *x, -1.0, 1.0, false)?;
        }
    }
    Ok(Proxemics {
        zones,
        space: r.space.clone(),
        sigmas,
        cost_mode: r.cost_mode.clone(),
        personal_cost: r.personal_cost,
        social_cost: r.social_cost,
        public_cost: r.public_cost,
        continuous_gain: r.continuous_gain,
        groups: r.groups.clone(),
        d_max,
        orientation_rule: r.orientation_rule.unwrap_or(true),
        aggregate: r.aggregate.clone(),
        features: r.features.clone(),
        influence,
    })
}

/// A person's feature vector: explicit `features`, or the emotional state looked up in Sousa
/// 2022 Table 1; features not given default to their neutral value (0.70 for the emotional
/// state, 0.5 otherwise).
fn person_features(ck: &Checker<'_>, i: usize, raw: &RawPerson, names: &[String]) -> Result<Vec<f64>> {
    let file = ck.file;
    let f = format!("person[{i}]");
    let mut fv: Vec<f64> = names.iter().map(|n| if n == "emotional_state" { 0.70 } else { 0.5 }).collect();
    if !raw.features.is_empty() {
        if raw.features.len() != names.len() {
            return Err(err(
                file,
                format!("{f}.features"),
                format!("{} value(s), one per name in proxemics.features {names:?}", names.len()),
                format!("{} value(s)", raw.features.len()),
            ));
        }
        for (k, v) in raw.features.iter().enumerate() {
            ck.range(&format!("{f}.features[{k}]"), *v, 0.0, 1.0, true)?;
        }
        fv.clone_from(&raw.features);
    }
    if let Some(state) = &raw.emotional_state {
        let k = names.iter().position(|n| n == "emotional_state").ok_or_else(|| {
            err(
                file,
                format!("{f}.emotional_state"),
                "\"emotional_state\" listed in proxemics.features",
                "a scenario without it",
            )
        })?;
        fv[k] = crate::proxemics::emotional_state_value(state).ok_or_else(|| {
            err(
                file,
                format!("{f}.emotional_state"),
                format!("one of {:?}", crate::proxemics::EMOTIONAL_STATES),
                format!("{state:?}"),
            )
        })?;
    }
    Ok(fv)
}

/// The goal of an approach task: the robot's centre one body radius beyond the edge of the
/// person's (feature-adapted) personal space on the requested side, facing the person. `auto`
/// picks, among front, left and right, the side where that edge is nearest (the side the
/// person's features make most welcoming; never the back).
fn build_approach(
    ck: &Checker<'_>,
    f: &str,
    a: &RawApproach,
    persons: &[Person],
    prox: &Proxemics,
    robot_radius: f64,
) -> Result<([f64; 2], Approach)> {
    use crate::proxemics::{Asymmetric, PersonalSpace, SideInfluences, adapt};
    let file = ck.file;
    let members: Vec<usize> = match (&a.person, a.group) {
        (Some(name), None) => {
            let k = persons.iter().position(|p| &p.name == name).ok_or_else(|| {
                err(file, format!("{f}.approach.person"), "the name of a [[person]]", format!("{name:?}"))
            })?;
            vec![k]
        }
        (None, Some(g)) => {
            let m: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].group == Some(g)).collect();
            if m.len() < 2 {
                return Err(err(
                    file,
                    format!("{f}.approach.group"),
                    "the id of a group with at least 2 people",
                    format!("group {g} with {} member(s)", m.len()),
                ));
            }
            m
        }
        _ => {
            return Err(err(
                file,
                format!("{f}.approach"),
                "exactly one of person = \"name\" or group = id",
                "neither or both",
            ));
        }
    };
    for &k in &members {
        if persons[k].behaviour != Behaviour::Standing {
            let field = if a.group.is_some() { "group" } else { "person" };
            return Err(err(
                file,
                format!("{f}.approach.{field}"),
                "standing people (approach targets do not move)",
                format!("{:?}, a {:?}", persons[k].name, persons[k].behaviour),
            ));
        }
    }
    let [front, rear, right, left] = prox.sigmas;
    let base = Asymmetric { front, rear, right, left };
    let [fi, ri, rti, li] = prox.influence.clone();
    let influence = SideInfluences { front: fi, rear: ri, right: rti, left: li };
    // One person, or the group as one individual (Sousa 2022 §3.3.4): its centre, orientation and
    // extents grow the base function; its features are the members' mean.
    let (centre, heading, grown, fv) = if members.len() == 1 {
        let p = &persons[members[0]];
        ([p.pose[0], p.pose[1]], p.pose[2], base, p.features.clone())
    } else {
        use crate::groups::{FeatureAggregate, PersonState, group_as_individual};
        use crate::math::Vec2;
        let states: Vec<PersonState> = members
            .iter()
            .map(|&k| {
                PersonState::standing(Vec2::new(persons[k].pose[0], persons[k].pose[1]), persons[k].pose[2])
            })
            .collect();
        let gi = group_as_individual(&states, &vec![1.0; states.len()], FeatureAggregate::Mean)?;
        let nf = prox.features.len();
        let fv: Vec<f64> = (0..nf)
            .map(|j| members.iter().map(|&k| persons[k].features[j]).sum::<f64>() / members.len() as f64)
            .collect();
        let grown = Asymmetric {
            front: front + gi.front,
            rear: rear + gi.rear,
            right: right + gi.right,
            left: left + gi.left,
        };
        ([gi.centre.x, gi.centre.y], gi.heading, grown, fv)
    };
    let sides = if prox.features.is_empty() { grown } else { adapt(grown, &fv, &influence)? };
    // The personal zone's edge in value terms (see crate::socialmap::SpaceFunction).
    let zone_scale = match prox.space.as_str() {
        "calderita" => right,
        "daza2021" => front,
        _ => (front * rear * right * left).powf(0.25),
    };
    let default_level = (-(prox.zones[1] * prox.zones[1]) / (2.0 * zone_scale * zone_scale)).exp();
    let level = a.level.unwrap_or(default_level);
    ck.range(&format!("{f}.approach.level"), level, 0.0, 1.0, true)?;
    let space = PersonalSpace::Asymmetric(sides);
    let extent = |bearing: f64| space.extent(bearing, level).unwrap_or(f64::INFINITY);
    let half_pi = std::f64::consts::FRAC_PI_2;
    let (side, bearing) = match a.side.as_str() {
        "front" => ("front", 0.0),
        "left" => ("left", half_pi),
        "right" => ("right", -half_pi),
        "auto" => [("front", 0.0), ("left", half_pi), ("right", -half_pi)]
            .into_iter()
            .min_by(|x, y| extent(x.1).total_cmp(&extent(y.1)))
            .unwrap_or(("front", 0.0)),
        other => {
            return Err(err(
                file,
                format!("{f}.approach.side"),
                "\"front\", \"left\", \"right\" or \"auto\"",
                format!("{other:?}"),
            ));
        }
    };
    let d = extent(bearing) + robot_radius;
    let dir = heading + bearing;
    let goal = [centre[0] + d * dir.cos(), centre[1] + d * dir.sin()];
    Ok((goal, Approach { people: members, side: side.to_string(), level, face: centre }))
}

/// Re-labels a core input error as a scenario error under `field`.
fn prefix_input(file: &str, field: &str, e: CoreError) -> CoreError {
    match e {
        CoreError::Input { field: inner, expected, found } => {
            err(file, format!("{field} ({inner})"), expected, found)
        }
        other => other,
    }
}

/// Validates the agenda: times of day, objects with interaction spaces, no overlaps.
fn build_agenda(
    ck: &Checker<'_>,
    raw: &RawAgenda,
    acts: &[RawActivity],
    objects: &[Object],
) -> Result<(AgendaSpec, Vec<ActivitySpec>)> {
    let file = ck.file;
    ck.range("agenda.idle", raw.idle, 1.0, 5.0, false)?;
    ck.range("agenda.active", raw.active, raw.idle, 5.0, false)?;
    ck.range("agenda.ramp_minutes", raw.ramp_minutes, 0.0, 24.0 * 60.0, false)?;
    let spec = AgendaSpec { idle: raw.idle, active: raw.active, ramp: raw.ramp_minutes * 60.0 };
    let mut out = Vec::with_capacity(acts.len());
    for (i, a) in acts.iter().enumerate() {
        let f = format!("activity[{i}]");
        match objects.iter().find(|o| o.name == a.object) {
            None => {
                return Err(err(
                    file,
                    format!("{f}.object"),
                    format!("the name of an [[object]] ({} objects defined)", objects.len()),
                    format!("{:?}", a.object),
                ));
            }
            Some(o) if o.interaction.is_none() => {
                return Err(err(
                    file,
                    format!("{f}.object"),
                    "an object with an interaction space",
                    format!("{:?} (has none)", a.object),
                ));
            }
            Some(_) => {}
        }
        let start = parse_time_of_day(&a.start).ok_or_else(|| {
            err(file, format!("{f}.start"), "a time of day \"HH:MM\"", format!("{:?}", a.start))
        })?;
        let mut end = parse_time_of_day(&a.end).ok_or_else(|| {
            err(file, format!("{f}.end"), "a time of day \"HH:MM\"", format!("{:?}", a.end))
        })?;
        if end <= start {
            if end == 0.0 {
                end = 86400.0; // "24:00" written as "00:00"
            } else {
                return Err(err(
                    file,
                    format!("{f}.end"),
                    format!("a time after start ({})", a.start),
                    format!("{:?}", a.end),
                ));
            }
        }
        out.push(ActivitySpec { name: a.name.clone(), object: a.object.clone(), start, end });
    }
    let agenda = Scenario::agenda_from(&spec, &out);
    agenda.map_err(|e| match e {
        CoreError::Input { field, expected, found } => {
            err(file, field.replace("activities", "activity"), expected, found)
        }
        other => other,
    })?;
    Ok((spec, out))
}

fn check_unique<'a>(file: &str, table: &str, names: impl Iterator<Item = &'a str>) -> Result<()> {
    let names: Vec<&str> = names.collect();
    for (i, n) in names.iter().enumerate() {
        if let Some(j) = names[..i].iter().position(|m| m == n) {
            return Err(err(
                file,
                format!("{table}[{i}].name"),
                format!("a unique name ({table}[{j}] is also called that)"),
                format!("{n:?}"),
            ));
        }
    }
    Ok(())
}

fn build_interaction(
    ck: &Checker<'_>,
    f: &str,
    ri: &RawInteraction,
    o: &RawObject,
    size: [f64; 2],
    radius: Option<f64>,
    bounds: [f64; 4],
) -> Result<Interaction> {
    let c = [o.pose[0], o.pose[1]];
    let th = o.pose[2];
    let (shape, polygon) = match ri {
        RawInteraction::Trapezoid { length, near_width, far_width } => {
            ck.range(&format!("{f}.length"), *length, 0.0, 50.0, true)?;
            ck.range(&format!("{f}.near_width"), *near_width, 0.0, 50.0, true)?;
            ck.range(&format!("{f}.far_width"), *far_width, 0.0, 50.0, true)?;
            let x0 = size[0] * 0.5;
            let x1 = x0 + length;
            let (s, co) = th.sin_cos();
            let local = [
                (x0, -near_width * 0.5),
                (x1, -far_width * 0.5),
                (x1, far_width * 0.5),
                (x0, near_width * 0.5),
            ];
            let poly =
                local.iter().map(|&(lx, ly)| [c[0] + co * lx - s * ly, c[1] + s * lx + co * ly]).collect();
            (
                InteractionShape::Trapezoid {
                    length: *length,
                    near_width: *near_width,
                    far_width: *far_width,
                },
                poly,
            )
        }
        RawInteraction::Rectangle { margin } => {
            ck.range(&format!("{f}.margin"), *margin, 0.0, 20.0, true)?;
            let poly = match radius {
                Some(r) => circle_polygon(c, r + margin),
                None => oriented_rect(c, th, size[0] * 0.5 + margin, size[1] * 0.5 + margin),
            };
            (InteractionShape::Rectangle { margin: *margin }, poly)
        }
        RawInteraction::Circle { radius: r } => {
            ck.range(&format!("{f}.radius"), *r, 0.0, 25.0, true)?;
            (InteractionShape::Circle { radius: *r }, circle_polygon(c, *r))
        }
        RawInteraction::Polygon { points } => {
            if points.len() < 3 {
                return Err(err(
                    ck.file,
                    format!("{f}.points"),
                    "at least 3 points",
                    format!("{} point(s)", points.len()),
                ));
            }
            for (k, p) in points.iter().enumerate() {
                ck.inside(&format!("{f}.points[{k}]"), *p, bounds)?;
            }
            let mut poly = points.clone();
            let area = signed_area(&poly);
            if area.abs() < 1e-9 {
                return Err(err(
                    ck.file,
                    format!("{f}.points"),
                    "a polygon with non-zero area",
                    "a degenerate polygon",
                ));
            }
            if area < 0.0 {
                poly.reverse();
            }
            (InteractionShape::Polygon, poly)
        }
    };
    Ok(Interaction { shape, polygon })
}

#[cfg(test)]
mod tests {
    use super::*;

    const MINIMAL: &str = r#"
[scene]
name = "room"
bounds = [0, 0, 10, 8]

[[wall]]
from = [0, 0]
to = [10, 0]

[[object]]
name = "painting"
kind = "painting"
pose = [5, 7.8, -1.5707963267948966]
size = [0.1, 1.5]
interaction = { shape = "trapezoid", length = 2.0, near_width = 1.5, far_width = 3.0 }

[[person]]
route = [[1, 1], [8, 1], [8, 6]]
speed = 1.2

[[person]]
behaviour = "standing"
pose = [3, 3, 0]

[[robot]]
start = [1, 4, 0]
goal = [9, 4]
"#;

    fn parse(text: &str) -> Result<Scenario> {
        Scenario::from_toml_str(text, "test.toml")
    }

    fn scenario_err(text: &str) -> (String, String, String, String) {
        match parse(text) {
            Err(CoreError::Scenario { file, field, expected, found }) => (file, field, expected, found),
            other => panic!("expected a scenario error, got {other:?}"),
        }
    }

    #[test]
    fn minimal_scenario_fills_defaults() {
        let s = parse(MINIMAL).expect("valid");
        assert_eq!(s.scene.resolution, 0.1);
        assert_eq!(s.scene.start_time, 9.0 * 3600.0);
        assert_eq!(s.frame_skip(), 10);
        assert_eq!(s.max_steps(), 1800);
        assert_eq!(s.persons[0].name, "person_0");
        assert_eq!(s.robots[0].max_speed, 0.55);
        assert_eq!(s.robots[0].radius, 0.24);
        // walker starts at its first waypoint, facing the second
        assert_eq!(s.persons[0].pose, [1.0, 1.0, 0.0]);
        assert_eq!(s.static_polygons().len(), 2);
    }

    #[test]
    fn painting_trapezoid_faces_into_the_room() {
        let s = parse(MINIMAL).expect("valid");
        let poly = &s.objects[0].interaction.as_ref().expect("has space").polygon;
        // facing -y: the far side is 2 m below the painting's front face at y = 7.75
        let ys: Vec<f64> = poly.iter().map(|p| p[1]).collect();
        let min_y = ys.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!((min_y - (7.8 - 0.05 - 2.0)).abs() < 1e-9, "{ys:?}");
        assert!(signed_area(poly) > 0.0);
        // far width 3.0
        let xs: Vec<f64> = poly.iter().map(|p| p[0]).collect();
        let span = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
        assert!((span - 3.0).abs() < 1e-9);
    }

    #[test]
    fn wall_polygon_covers_the_end_caps() {
        let s = parse(MINIMAL).expect("valid");
        let xs: Vec<f64> = s.walls[0].polygon.iter().map(|p| p[0]).collect();
        assert!((xs.iter().cloned().fold(f64::MAX, f64::min) + 0.1).abs() < 1e-9);
        assert!((xs.iter().cloned().fold(f64::MIN, f64::max) - 10.1).abs() < 1e-9);
    }

    #[test]
    fn unknown_field_is_named() {
        let text = MINIMAL.replace("speed = 1.2", "speed = 1.2\nsped = 3");
        let (file, field, expected, found) = scenario_err(&text);
        assert_eq!(file, "test.toml");
        assert!(field.starts_with("person[0]"), "{field}");
        assert!(found.contains("sped"), "{found}");
        assert!(expected.contains("speed"), "{expected}");
    }

    #[test]
    fn missing_field_is_named() {
        let text = MINIMAL.replace("goal = [9, 4]\n", "");
        let (_, field, expected, _) = scenario_err(&text);
        assert!(field.starts_with("robot[0]"), "{field}");
        assert!(expected.contains("goal"), "{expected}");
    }

    #[test]
    fn wrong_type_is_named() {
        let text = MINIMAL.replace("speed = 1.2", "speed = \"sprint\"");
        let (_, field, expected, found) = scenario_err(&text);
        assert!(field.starts_with("person[0].speed"), "{field}");
        assert!(expected.contains("number") && expected.contains("elderly"), "{expected}");
        assert!(found.contains("sprint"), "{found}");
        // a preset name is a speed
        let s = parse(&MINIMAL.replace("speed = 1.2", "speed = \"elderly\"")).expect("valid");
        assert_eq!(s.persons[0].speed, 0.6);
    }

    #[test]
    fn malformed_toml_gives_line() {
        let (_, field, expected, _) = scenario_err("[scene\nname = 1");
        assert!(field.contains("line 1"), "{field}");
        assert_eq!(expected, "valid TOML");
    }

    #[test]
    fn nan_is_rejected_with_field() {
        let text = MINIMAL.replace("speed = 1.2", "speed = nan");
        let (_, field, expected, found) = scenario_err(&text);
        assert_eq!(field, "person[0].speed");
        assert!(expected.contains("(0, 2.5]"));
        assert_eq!(found, "NaN");
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, nan]");
        let (_, field, _, _) = scenario_err(&text);
        assert_eq!(field, "robot[0].goal");
    }

    #[test]
    fn overlapping_robot_starts_are_rejected() {
        let two = format!("{MINIMAL}\n[[robot]]\nstart = [1.3, 4.1, 0]\ngoal = [9, 6]\n");
        let (file, field, expected, found) = scenario_err(&two);
        assert_eq!(file, "test.toml");
        assert_eq!(field, "robot[1].start");
        assert!(expected.contains("0.48 m") && expected.contains("robot[0]"), "{expected}");
        assert!(found.contains("overlapping"), "{found}");
        // Just clear of each other: accepted.
        let ok = two.replace("start = [1.3, 4.1, 0]", "start = [1.5, 4, 0]");
        assert_eq!(parse(&ok).expect("valid").robots.len(), 2);
    }

    #[test]
    fn extends_overrides_scene_keys_and_replaces_tables() {
        let dir = std::env::temp_dir().join(format!("proxemic-extends-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        std::fs::write(dir.join("base.toml"), MINIMAL).expect("write base");
        let child = "extends = \"base.toml\"\n[scene]\nname = \"two\"\n\n\
                     [[robot]]\nstart = [1, 4, 0]\ngoal = [9, 4]\n[[robot]]\nstart = [1, 6, 0]\ngoal = [9, 6]\n";
        std::fs::write(dir.join("child.toml"), child).expect("write child");
        let s = Scenario::from_file(dir.join("child.toml")).expect("valid");
        assert_eq!(s.scene.name, "two");
        assert_eq!(s.scene.bounds, [0.0, 0.0, 10.0, 8.0]); // kept from the base
        assert_eq!(s.persons.len(), 2); // the base's people
        assert_eq!(s.robots.len(), 2); // the child's robots replace the base's
        std::fs::write(dir.join("bad.toml"), "extends = \"nowhere.toml\"\n").expect("write bad");
        match Scenario::from_file(dir.join("bad.toml")) {
            Err(CoreError::Scenario { file, field, found, .. }) => {
                assert!(file.ends_with("bad.toml"), "{file}");
                assert_eq!(field, "extends");
                assert!(found.contains("nowhere.toml"), "{found}");
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
        std::fs::write(dir.join("loop.toml"), "extends = \"loop.toml\"\n").expect("write loop");
        match Scenario::from_file(dir.join("loop.toml")) {
            Err(CoreError::Scenario { field, expected, .. }) => {
                assert_eq!(field, "extends");
                assert!(expected.contains("chained"), "{expected}");
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn robot_subsets_and_per_robot_planners() {
        let two = format!("{MINIMAL}\n[[robot]]\nstart = [1, 6, 0]\ngoal = [9, 6]\n");
        let s = parse(&two).expect("valid");
        assert_eq!(s.with_robots(1).expect("one").robots.len(), 1);
        assert_eq!(s.with_robots(2).expect("two").robots.len(), 2);
        for bad in [0, 3] {
            match s.with_robots(bad) {
                Err(CoreError::Scenario { field, expected, found, .. }) => {
                    assert_eq!(field, "robots");
                    assert!(expected.contains("[1, 2]"), "{expected}");
                    assert_eq!(found, bad.to_string());
                }
                other => panic!("expected a scenario error, got {other:?}"),
            }
        }
        let m = s.with_robot_planner(1, "orca").expect("known planner");
        assert_eq!(m.robots[1].planner, PlannerKind::Orca);
        assert_eq!(m.robots[0].planner, s.robots[0].planner);
        match s.with_robot_planner(1, "teleport") {
            Err(CoreError::Scenario { field, found, .. }) => {
                assert_eq!(field, "robot[1].planner");
                assert_eq!(found, "\"teleport\"");
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
        assert!(s.with_robot_planner(2, "orca").is_err());
    }

    #[test]
    fn out_of_bounds_goal_is_rejected() {
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [19, 4]");
        let (_, field, expected, found) = scenario_err(&text);
        assert_eq!(field, "robot[0].goal");
        assert!(expected.contains("inside scene.bounds"));
        assert_eq!(found, "[19, 4]");
    }

    #[test]
    fn bad_time_of_day() {
        let text =
            MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nstart_time = \"25:00\"");
        let (_, field, _, found) = scenario_err(&text);
        assert_eq!(field, "scene.start_time");
        assert_eq!(found, "\"25:00\"");
        assert_eq!(parse_time_of_day("10:30:15"), Some(37815.0));
    }

    #[test]
    fn physics_rate_must_be_a_multiple() {
        let text = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nphysics_hz = 105");
        let (_, field, _, _) = scenario_err(&text);
        assert_eq!(field, "scene.physics_hz");
    }

    #[test]
    fn walker_needs_two_waypoints_and_standing_needs_a_pose() {
        let text = MINIMAL.replace("route = [[1, 1], [8, 1], [8, 6]]", "route = [[1, 1]]");
        assert_eq!(scenario_err(&text).1, "person[0].route");
        let text = MINIMAL.replace("pose = [3, 3, 0]", "");
        assert_eq!(scenario_err(&text).1, "person[1].pose");
    }

    #[test]
    fn duplicate_names_rejected() {
        let text = format!("{MINIMAL}\n[[robot]]\nname = \"robot_0\"\nstart = [2, 4, 0]\ngoal = [8, 4]\n");
        let (_, field, expected, _) = scenario_err(&text);
        assert_eq!(field, "robot[1].name");
        assert!(expected.contains("robot[0]"));
    }

    #[test]
    fn unknown_planner_lists_the_known_ones() {
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\nplanner = \"teleport\"");
        let (_, field, expected, found) = scenario_err(&text);
        assert!(field.starts_with("robot[0].planner"), "{field}");
        assert!(expected.contains("astar"), "{expected}");
        assert!(found.contains("teleport"), "{found}");
    }

    #[test]
    fn eband_gains_from_the_file_and_by_override_are_checked() {
        let s = parse(MINIMAL).expect("valid");
        assert_eq!(s.robots[0].eband, EbandGains::default());
        assert_eq!((s.robots[0].eband.contraction_gain, s.robots[0].eband.repulsion_gain), (1.0, 0.5));
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { repulsion_gain = 2.0 }");
        let g = parse(&text).expect("valid").robots[0].eband;
        assert_eq!((g.contraction_gain, g.repulsion_gain, g.social_gain), (1.0, 2.0, 0.5));
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { social_gain = -1.0 }");
        let (_, field, expected, found) = scenario_err(&text);
        assert_eq!(field, "robot[0].eband.social_gain");
        assert!(expected.contains("[0, 100]"), "{expected}");
        assert_eq!(found, "-1");
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { kc = 1.0 }");
        assert!(scenario_err(&text).1.starts_with("robot[0].eband"));

        let t = s.with_eband_gains(Some(3.0), None, Some(0.0)).expect("valid gains");
        assert_eq!(t.robots[0].eband.contraction_gain, 3.0);
        assert_eq!(t.robots[0].eband.repulsion_gain, 0.5);
        assert_eq!(t.robots[0].eband.params().social_gain, 0.0);
        match s.with_eband_gains(None, Some(f64::NAN), None) {
            Err(CoreError::Scenario { field, found, .. }) => {
                assert_eq!(field, "eband.repulsion_gain");
                assert_eq!(found, "NaN");
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
    }

    #[test]
    fn goal_override_is_checked() {
        let s = parse(MINIMAL).expect("valid");
        assert_eq!(s.with_goal(0, [5.0, 2.0]).expect("inside").robots[0].goal, [5.0, 2.0]);
        match s.with_goal(0, [50.0, 2.0]) {
            Err(CoreError::Scenario { field, expected, .. }) => {
                assert_eq!(field, "robot[0].goal");
                assert!(expected.contains("inside scene.bounds"), "{expected}");
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
        assert!(matches!(s.with_goal(3, [5.0, 2.0]), Err(CoreError::Scenario { .. })));
    }

    #[test]
    fn no_robot_is_an_error() {
        let text = MINIMAL.split("[[robot]]").next().expect("has a robot table").to_string();
        assert_eq!(scenario_err(&text).1, "robot");
    }

    #[test]
    fn json_round_trip_has_polygons() {
        let s = parse(MINIMAL).expect("valid");
        let v: serde_json::Value = serde_json::from_str(&s.to_json()).expect("json");
        assert_eq!(v["walls"][0]["polygon"].as_array().map(|a| a.len()), Some(4));
        assert_eq!(v["objects"][0]["interaction"]["shape"], "trapezoid");
        assert_eq!(v["robots"][0]["planner"], "astar");
    }

    #[test]
    fn circle_polygon_contains_the_disc() {
        let poly = circle_polygon([0.0, 0.0], 1.0);
        // the inscribed radius of the polygon equals the circle's radius
        for i in 0..poly.len() {
            let a = poly[i];
            let b = poly[(i + 1) % poly.len()];
            let mid = [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
            assert!((mid[0].hypot(mid[1]) - 1.0).abs() < 1e-9);
        }
        assert!(signed_area(&poly) > 0.0);
    }

    const SOCIAL: &str = r#"
[proxemics]
space = "sousa2022"
features = ["emotional_state", "food_need"]
groups = "delaunay"
d_max = 1.2

[proxemics.influence]
front = [0.9, 0.0]
left = [0.5, 0.5]

[[activity]]
object = "painting"
start = "10:00"
end = "11:00"
name = "guided talk"
"#;

    fn social_scenario(extra_person: &str) -> String {
        let text = MINIMAL.replace("speed = 1.2", &format!("speed = 1.2\n{extra_person}"));
        format!("{text}{SOCIAL}")
    }

    #[test]
    fn proxemics_and_agenda_parse() {
        let s = parse(&social_scenario("emotional_state = \"happy\"")).expect("valid");
        assert_eq!(s.persons[0].features, vec![0.98, 0.5]);
        assert_eq!(s.persons[1].features, vec![0.70, 0.5]);
        assert_eq!(s.proxemics.influence[0], vec![0.9, 0.0]);
        assert_eq!(s.proxemics.influence[1], vec![0.0, 0.0]);
        let cfg = s.social_config();
        assert_eq!(cfg.features.len(), 2);
        assert!(matches!(cfg.groups, Some(crate::groups::GroupMethod::Delaunay(p)) if p.d_max == 1.2));
        let agenda = s.agenda().expect("valid agenda");
        assert_eq!(agenda.cost("painting", 10.5 * 3600.0), 3.5);
        assert_eq!(agenda.cost("painting", 8.0 * 3600.0), 1.5);
        assert_eq!(s.activities[0].name, "guided talk");
    }

    #[test]
    fn social_bad_input_names_the_field() {
        let (_, f, e, _) = scenario_err(&social_scenario("emotional_state = \"grumpy\""));
        assert_eq!(f, "person[0].emotional_state");
        assert!(e.contains("happy"));
        let (_, f, _, _) = scenario_err(&social_scenario("features = [0.5]"));
        assert_eq!(f, "person[0].features");
        let (_, f, _, found) = scenario_err(&social_scenario("features = [0.0, 0.5]"));
        assert_eq!((f.as_str(), found.as_str()), ("person[0].features[0]", "0"));
        let (_, f, _, _) =
            scenario_err(&social_scenario("").replace("front = [0.9, 0.0]", "front = [1.5, 0.0]"));
        assert_eq!(f, "proxemics.influence.front[0]");
        let (_, f, _, _) = scenario_err(&social_scenario("").replace("front = [0.9, 0.0]", "front = [0.9]"));
        assert_eq!(f, "proxemics.influence.front");
        let (_, f, _, _) = scenario_err(&social_scenario("").replace("\"sousa2022\"", "\"hall\""));
        assert_eq!(f, "proxemics.space");
    }

    #[test]
    fn agenda_bad_input_names_the_activity() {
        let (_, f, _, found) =
            scenario_err(&social_scenario("").replace("object = \"painting\"", "object = \"tv\""));
        assert_eq!((f.as_str(), found.as_str()), ("activity[0].object", "\"tv\""));
        let (_, f, _, _) = scenario_err(&social_scenario("").replace("end = \"11:00\"", "end = \"09:00\""));
        assert_eq!(f, "activity[0].end");
        let overlap = format!(
            "{}\n[[activity]]\nobject = \"painting\"\nstart = \"10:30\"\nend = \"12:00\"\n",
            social_scenario("")
        );
        let (_, f, _, _) = scenario_err(&overlap);
        assert!(f.contains("activity[0]") && f.contains("activity[1]"), "{f}");
        let text = MINIMAL.replace(
            "interaction = { shape = \"trapezoid\", length = 2.0, near_width = 1.5, far_width = 3.0 }\n",
            "",
        );
        let no_space =
            format!("{text}\n[[activity]]\nobject = \"painting\"\nstart = \"10:00\"\nend = \"11:00\"\n");
        let (_, f, e, _) = scenario_err(&no_space);
        assert_eq!(f, "activity[0].object");
        assert!(e.contains("interaction space"));
    }

    /// Sousa 2022 Table 2: a waiter robot serves food from the person's left and drinks from
    /// their right. With `auto`, the side the person's needs make most welcoming is chosen.
    fn waiter(food: f64, drink: f64, side: &str) -> Scenario {
        let text = format!(
            r#"
[scene]
name = "dinner"
bounds = [0, 0, 10, 10]
[proxemics]
space = "sousa2022"
features = ["food_need", "beverage_need"]
[proxemics.influence]
left = [0.5, 0.0]
right = [0.0, 0.5]
[[person]]
name = "guest"
behaviour = "standing"
pose = [5, 5, 1.5707963267948966]
features = [{food}, {drink}]
[[robot]]
start = [1, 1, 0]
approach = {{ person = "guest", side = "{side}" }}
"#
        );
        parse(&text).expect("valid waiter scene")
    }

    #[test]
    fn approach_goals_follow_the_person_s_needs() {
        // The guest faces +y: their left is -x, their right +x.
        let food = waiter(0.9, 0.1, "auto");
        let a = food.robots[0].approach.as_ref().expect("approach");
        assert_eq!(a.side, "left");
        assert!(food.robots[0].goal[0] < 5.0 && (food.robots[0].goal[1] - 5.0).abs() < 1e-9);
        let drink = waiter(0.1, 0.9, "auto");
        assert_eq!(drink.robots[0].approach.as_ref().expect("approach").side, "right");
        assert!(drink.robots[0].goal[0] > 5.0);
        // The needed side lets the robot come closer than the side without need.
        let near = 5.0 - food.robots[0].goal[0];
        let far = 5.0 - waiter(0.1, 0.9, "left").robots[0].goal[0];
        assert!(near < far, "{near} vs {far}");
        assert_eq!(food.robots[0].approach.as_ref().expect("approach").face, [5.0, 5.0]);
    }

    #[test]
    fn approach_bad_input() {
        let text = MINIMAL.replace("goal = [9, 4]", "approach = { person = \"nobody\" }");
        assert_eq!(scenario_err(&text).1, "robot[0].approach.person");
        let text = MINIMAL.replace("goal = [9, 4]", "approach = { person = \"person_0\" }");
        let (_, f, e, _) = scenario_err(&text);
        assert_eq!(f, "robot[0].approach.person");
        assert!(e.contains("standing"));
        let text =
            MINIMAL.replace("goal = [9, 4]", "approach = { person = \"person_1\", side = \"behind\" }");
        assert_eq!(scenario_err(&text).1, "robot[0].approach.side");
        let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\napproach = { person = \"person_1\" }");
        assert_eq!(scenario_err(&text).1, "robot[0].approach");
    }
}
