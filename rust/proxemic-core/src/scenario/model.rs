//! The validated scenario: the types [`super::build`] produces from the raw file tables, and
//! the accessors the world and the bindings use.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::check::{Checker, err};
use super::raw::{
    d_collision, d_gather_radius, d_k_nearest, d_lead_minutes, d_lidar_range, d_lidar_rays, d_person_height,
    d_person_radius, d_person_speed, d_personal_space, d_progress, d_speed_jitter, d_success, d_time, d_true,
};
use crate::error::Result;

/// Number of vertices used to approximate a circle as a polygon.
pub const CIRCLE_VERTICES: usize = 24;

/// Named walking speeds (m/s) accepted by `person.speed`: `normal` is the mean desired speed of
/// Helbing & Molnar 1995 (1.34 m/s, rounded); `fast`, `slow` and `elderly` (a frail older adult,
/// as in a care center) are this project's choices, not values from the papers.
pub const SPEED_PRESETS: [(&str, f64); 4] = [("fast", 1.6), ("normal", 1.3), ("slow", 0.9), ("elderly", 0.6)];

/// Seat spacing along a bench or sofa (metres): one person per 0.6 m of its width.
pub const SEAT_SPACING: f64 = 0.6;

/// Kinds of static objects. The kind decides the default height and how the object is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
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

    pub(super) fn is_round_capable(self) -> bool {
        matches!(self, ObjectKind::RoundTable | ObjectKind::Pillar | ObjectKind::Plinth | ObjectKind::Exhibit)
    }
}

/// Scripted pedestrian behaviours (`person.behaviour`). Every moving person walks with the
/// social force model of [`crate::pedestrians`]; paths between places are planned on the static
/// map, so only walker and guide routes must be free of walls themselves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
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
    /// A recorded person: not written in `[[person]]` but made from each track of a
    /// `[[replay]]` file. Follows its track exactly (linear interpolation between samples), is
    /// present only from its first sample to its last, and walks with the social force model
    /// toward the track once a robot comes within the replay's `react_radius`.
    Replay,
}

/// Built-in planners a robot can run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PlannerKind {
    /// Plain 8-connected A* on the inflated static map, followed by a pure-pursuit path follower.
    /// It avoids walls and furniture, not people: the baseline of every comparison.
    Astar,
    /// Social A* on the social cost map (people's zones, groups, object spaces at R(t)), re-planned
    /// when the agenda or the people change the path's cost, followed by the same path follower.
    SocialAstar,
    /// proxemic's own social planner: Calderita's social cost map for the global path (social
    /// A*, re-planned on triggers), Daza's local control (ORCA when only robots are around and one
    /// is in the collision cone, Social Momentum near people and groups, path following otherwise)
    /// and our comfort term in Social Momentum. It is none of the papers' systems as published:
    /// see [`PlannerKind::Daza2021`] and [`PlannerKind::Sousa2022`] for those.
    Social,
    /// Non-social baseline: the plain A* path followed with ORCA every step; people are
    /// non-cooperating agents (the robot takes the whole avoidance, van den Berg et al. 2011 with
    /// alpha = 1) at their body radius, the robots running ORCA this step cooperate (half each).
    /// No social terms. Formerly named `orca`.
    AstarOrca,
    /// Non-social baseline: the plain A* path, stopping while someone (person or robot) is in the
    /// corridor ahead within the stopping distance, and re-planning the plain A* path around the
    /// blockers after a 2 s wait ([`crate::control::stop_and_wait`]).
    AstarStop,
    /// Plain A* global path; Social Momentum whenever people are near.
    SocialMomentum,
    /// Plain A* global path deformed by an elastic band (static clearance and people's spaces).
    Eband,
    /// Daza et al. 2021 Algorithm 1 as published: the plain A* global path; each step the
    /// nearest detected mobile object decides ([`crate::control::daza2021::daza2021_decide`]):
    /// a person (or a human group) runs Social Momentum with no comfort term, keeping out of the
    /// people's intimate zones and the groups' o-spaces; only robots on a collision course run
    /// ORCA among the robots only; otherwise the path is followed. Hall radii 0.5 / 1 / 4 m.
    Daza2021,
    /// Sousa et al. 2022: [`PlannerKind::Daza2021`]'s local step (Algorithm 1) whose Social
    /// Momentum keeps out of the personal level of the fully asymmetric Gaussians of the people
    /// and of the Delaunay groups (a group as one individual), reshaped by the socialization
    /// features (§4.5), on a global path planned on the cost map of those Gaussians (§3.1, Fig.
    /// 3: "the provided path planning method must include the values of Gaussian functions as a
    /// cost function"): the scenario's social map of the individuals, searched by A* and
    /// re-planned on triggers like [`PlannerKind::SocialAstar`]'s.
    Sousa2022,
    /// Calderita et al.'s system as published: Dijkstra on the time-dependent social cost map
    /// with the people's zones as contours of the summed density (§4.1, §5.1-5.2), the elastic
    /// band (`k_c`, `k_r`, §5.3) deforming that path, re-planned when the agenda or the people
    /// raise its cost ([`crate::plan::social`]).
    Calderita,
}

impl PlannerKind {
    /// Parses a planner name as used in scenario files and on the command line.
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "astar" => Some(PlannerKind::Astar),
            "social_astar" => Some(PlannerKind::SocialAstar),
            "social" => Some(PlannerKind::Social),
            "astar_orca" => Some(PlannerKind::AstarOrca),
            "astar_stop" => Some(PlannerKind::AstarStop),
            "social_momentum" => Some(PlannerKind::SocialMomentum),
            "eband" => Some(PlannerKind::Eband),
            "daza2021" => Some(PlannerKind::Daza2021),
            "sousa2022" => Some(PlannerKind::Sousa2022),
            "calderita" => Some(PlannerKind::Calderita),
            _ => None,
        }
    }

    /// The names accepted by [`PlannerKind::parse`].
    pub const NAMES: &'static [&'static str] = &[
        "astar",
        "social_astar",
        "social",
        "astar_orca",
        "astar_stop",
        "social_momentum",
        "eband",
        "daza2021",
        "sousa2022",
        "calderita",
    ];

    /// Whether the planner runs Daza et al. 2021 Algorithm 1 as published (with Sousa 2022's
    /// Gaussians for [`PlannerKind::Sousa2022`]): its local step is
    /// [`crate::control::daza2021`]'s.
    pub fn daza2021_family(self) -> bool {
        matches!(self, PlannerKind::Daza2021 | PlannerKind::Sousa2022)
    }

    /// Whether the planner's global path is the social A* path (re-planned on triggers); for
    /// [`PlannerKind::Sousa2022`] it is Sousa 2022 §3.1's path on the Gaussians' cost map.
    pub fn social_global(self) -> bool {
        matches!(
            self,
            PlannerKind::SocialAstar | PlannerKind::Social | PlannerKind::Calderita | PlannerKind::Sousa2022
        )
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
    /// Replay: the track, `[t, x, y]` samples (seconds after the episode start, scene metres),
    /// at least two, in strictly increasing time.
    pub track: Vec<[f64; 3]>,
    /// Replay: the person reacts once a robot's centre comes within this distance (metres; 0:
    /// never).
    pub react_radius: f64,
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
            track: Vec::new(),
            react_radius: 0.0,
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
    /// The built-in planner's progress monitor (defaults: on, 0.5 m in 15 s); file table
    /// `progress = { enabled, distance, window }`.
    pub progress: crate::control::progress::ProgressParams,
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

    /// The gains' names, in the order of the fields: the keys of a robot's `eband` table and the
    /// names [`Scenario::with_eband_gains`] accepts.
    pub const NAMES: [&'static str; 3] = ["contraction_gain", "repulsion_gain", "social_gain"];

    /// `gains` (name, value) as one optional value per gain, in the order of [`Self::NAMES`]
    /// (a name given twice keeps its last value). Errors name `{field}.<name>` for a name not in
    /// [`Self::NAMES`] (the first such name in lexicographic order).
    pub(super) fn by_name(file: &str, field: &str, gains: &[(&str, f64)]) -> Result<[Option<f64>; 3]> {
        let mut unknown: Vec<&str> = gains.iter().map(|g| g.0).filter(|n| !Self::NAMES.contains(n)).collect();
        unknown.sort_unstable();
        if let Some(name) = unknown.first() {
            return Err(err(
                file,
                format!("{field}.{name}"),
                format!("an elastic-band gain among {:?}", Self::NAMES),
                format!("{name:?}"),
            ));
        }
        let mut values = [None; 3];
        for (name, v) in gains {
            if let Some(k) = Self::NAMES.iter().position(|n| n == name) {
                values[k] = Some(*v);
            }
        }
        Ok(values)
    }

    /// These gains with each `Some` value (in the order of [`Self::NAMES`]) replaced, checked
    /// against `[0, MAX]` (errors name `{field}.<gain>`).
    pub(super) fn merged(&self, file: &str, field: &str, values: [Option<f64>; 3]) -> Result<Self> {
        let ck = Checker { file };
        let mut g = *self;
        let slots = [&mut g.contraction_gain, &mut g.repulsion_gain, &mut g.social_gain];
        for ((name, new), slot) in Self::NAMES.iter().zip(values).zip(slots) {
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
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
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
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
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

impl Default for Sensors {
    fn default() -> Self {
        Sensors { lidar_rays: d_lidar_rays(), lidar_range: d_lidar_range(), k_nearest: d_k_nearest() }
    }
}

/// Reward weights. The reward is the sum of the terms; each term is reported separately.
#[derive(Clone, Debug, Serialize, Deserialize, JsonSchema)]
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

impl Scenario {
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

    /// JSON of the validated scenario (defaults filled in, world polygons computed).
    ///
    /// # Errors
    /// serde_json's error if the scenario cannot be serialised (a bug: every field is plain data).
    pub fn to_json(&self) -> serde_json::Result<String> {
        serde_json::to_string(self)
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
