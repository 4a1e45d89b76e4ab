//! The file representation: serde structs mirroring the TOML tables (unknown fields rejected)
//! and the default of every optional field.

use schemars::JsonSchema;
use serde::{Deserialize, Deserializer};

use super::model::{Behaviour, ObjectKind, PlannerKind, Randomize, Reaction, RewardWeights, Sensors};

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "proxemic scenario", rename = "Scenario")]
/// A proxemic scenario file (TOML). A file may start with `extends = "base.toml"` (a path relative
/// to it) and `append = ["person", ...]`: see the scenario reference in the docs.
pub(super) struct RawScenario {
    /// Scene-wide settings.
    pub(super) scene: RawScene,
    /// Straight walls (`[[wall]]`).
    #[serde(default)]
    pub(super) wall: Vec<RawWall>,
    /// Furniture and exhibits (`[[object]]`), with their interaction spaces.
    #[serde(default)]
    pub(super) object: Vec<RawObject>,
    /// Scripted people (`[[person]]`).
    #[serde(default)]
    pub(super) person: Vec<RawPerson>,
    /// Settings per group of people (`[[group]]`): their reaction to robots.
    #[serde(default)]
    pub(super) group: Vec<RawGroup>,
    /// Robots (`[[robot]]`), at least one.
    #[serde(default)]
    pub(super) robot: Vec<RawRobot>,
    /// Episode settings.
    #[serde(default)]
    pub(super) episode: RawEpisode,
    /// Observation settings.
    #[serde(default)]
    pub(super) sensors: Sensors,
    /// Reward weights.
    #[serde(default)]
    pub(super) reward: RewardWeights,
    /// The social model: zones, personal space, groups, socialization features.
    #[serde(default)]
    pub(super) proxemics: RawProxemics,
    /// R(t), the object-space factor over the day (Calderita §5.2.2).
    #[serde(default)]
    pub(super) agenda: RawAgenda,
    /// Agenda items (`[[activity]]`): an activity on an object, in time of day.
    #[serde(default)]
    pub(super) activity: Vec<RawActivity>,
    /// Recorded crowds (`[[replay]]`): every track of a `t,id,x,y` CSV file becomes a person who
    /// follows it.
    #[serde(default)]
    pub(super) replay: Vec<RawReplay>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// A recorded crowd (`[[replay]]`): a CSV file with the header `t,id,x,y` (seconds, any label,
/// metres); each `id`'s rows, in increasing time, are one person's track, followed exactly
/// (linear interpolation between samples) from its first sample to its last, when the person
/// appears and leaves.
pub(super) struct RawReplay {
    /// Path of the CSV file, relative to the scenario file.
    pub(super) file: String,
    /// A person reacts when a robot's centre comes within this distance of theirs (metres; 0,
    /// the default: never): from then on they walk with the social force model toward their
    /// track instead of following it exactly.
    #[serde(default)]
    pub(super) react_radius: f64,
    /// Where the recording's origin lies in the scene, `[x, y]` (metres; default `[0, 0]`).
    #[serde(default, deserialize_with = "exact")]
    #[schemars(with = "[f64; 2]")]
    pub(super) offset: [f64; 2],
    /// Rotation of the recording's axes in the scene (radians, counter-clockwise; default 0),
    /// applied before `offset`: scene = R(rotate) (x, y) + offset.
    #[serde(default)]
    pub(super) rotate: f64,
    /// Recording time at the episode's start (seconds; default 0): a sample at `t` happens
    /// `t - t0` seconds into the episode.
    #[serde(default)]
    pub(super) t0: f64,
    /// Body radius of the replayed people (metres), in (0, 0.5]; default 0.2.
    #[serde(default = "d_person_radius")]
    pub(super) radius: f64,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// The social model (`[proxemics]`).
pub(super) struct RawProxemics {
    /// Hall's zone radii preset: `evaluation` (0.45 / 1.2 / 3.6 m) or `daza2021` (0.5 / 1.0 / 4.0 m).
    #[serde(default = "d_zones")]
    pub(super) zones: String,
    /// Explicit zone radii `[intimate, personal, social]` (metres, centre to centre, increasing).
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 3]>")]
    pub(super) zone_radii: Option<[f64; 3]>,
    /// Base personal-space preset: `daza2021`, `calderita` or `sousa2022`.
    #[serde(default = "d_space")]
    pub(super) space: String,
    /// One sigma for every side (metres), overriding the preset's.
    pub(super) sigma: Option<f64>,
    /// Front sigma (metres), overriding the preset's.
    pub(super) sigma_front: Option<f64>,
    /// Rear sigma (metres), overriding the preset's.
    pub(super) sigma_rear: Option<f64>,
    /// Left sigma (metres), overriding the preset's.
    pub(super) sigma_left: Option<f64>,
    /// Right sigma (metres), overriding the preset's.
    pub(super) sigma_right: Option<f64>,
    /// `zones` (discrete Calderita costs) or `continuous` (1 + gain · personal-space value).
    #[serde(default = "d_cost_mode")]
    pub(super) cost_mode: String,
    /// Traversal factor inside the personal zone.
    #[serde(default = "d_personal_cost")]
    pub(super) personal_cost: f64,
    /// Traversal factor inside the social zone.
    #[serde(default = "d_social_cost")]
    pub(super) social_cost: f64,
    /// Traversal factor of the public zone and free space.
    #[serde(default = "d_public_cost")]
    pub(super) public_cost: f64,
    /// Gain of the continuous cost mode.
    #[serde(default = "d_continuous_gain")]
    pub(super) continuous_gain: f64,
    /// Group detection: `delaunay`, `density`, `fformation` or `none`.
    #[serde(default = "d_groups")]
    pub(super) groups: String,
    /// Distance rule d_max of the Delaunay detector (metres; default 1.5).
    pub(super) d_max: Option<f64>,
    /// Whether the Delaunay detector uses the orientation rule (default true).
    pub(super) orientation_rule: Option<bool>,
    /// How a group's feature values combine: `mean`, `min` or `mode`.
    #[serde(default = "d_aggregate")]
    pub(super) aggregate: String,
    /// Socialization feature names, in the order of each person's `features` (Sousa et al. 2022).
    #[serde(default)]
    pub(super) features: Vec<String>,
    /// Influence vectors per side, one value per feature each, in [-1, 1].
    #[serde(default)]
    pub(super) influence: RawInfluence,
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

#[derive(Deserialize, JsonSchema, Default)]
#[serde(deny_unknown_fields)]
/// How each socialization feature scales each side of the personal space (Sousa et al. 2022).
pub(super) struct RawInfluence {
    /// Front side, one value per feature.
    #[serde(default)]
    pub(super) front: Vec<f64>,
    /// Rear side, one value per feature.
    #[serde(default)]
    pub(super) rear: Vec<f64>,
    /// Left side, one value per feature.
    #[serde(default)]
    pub(super) left: Vec<f64>,
    /// Right side, one value per feature.
    #[serde(default)]
    pub(super) right: Vec<f64>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// R(t) parameters (Calderita §5.2.2).
pub(super) struct RawAgenda {
    /// Object-space factor with nothing scheduled.
    #[serde(default = "d_idle")]
    pub(super) idle: f64,
    /// Factor while an activity runs.
    #[serde(default = "d_active")]
    pub(super) active: f64,
    /// Ramp before and after an activity (minutes).
    #[serde(default = "d_ramp_minutes")]
    pub(super) ramp_minutes: f64,
}

impl Default for RawAgenda {
    fn default() -> Self {
        RawAgenda { idle: d_idle(), active: d_active(), ramp_minutes: d_ramp_minutes() }
    }
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// An activity on an object, in time of day.
pub(super) struct RawActivity {
    /// The object (by name) whose interaction space the activity uses.
    pub(super) object: String,
    /// Start, `"HH:MM"`.
    pub(super) start: String,
    /// End, `"HH:MM"` (after the start; past midnight allowed).
    pub(super) end: String,
    /// Name (may be empty).
    #[serde(default)]
    pub(super) name: String,
}

pub(super) fn d_zones() -> String {
    "evaluation".into()
}
pub(super) fn d_space() -> String {
    "calderita".into()
}
pub(super) fn d_cost_mode() -> String {
    "zones".into()
}
pub(super) fn d_personal_cost() -> f64 {
    4.0
}
pub(super) fn d_social_cost() -> f64 {
    2.0
}
pub(super) fn d_public_cost() -> f64 {
    1.0
}
pub(super) fn d_continuous_gain() -> f64 {
    3.0
}
pub(super) fn d_groups() -> String {
    "delaunay".into()
}
pub(super) fn d_aggregate() -> String {
    "mean".into()
}
pub(super) fn d_idle() -> f64 {
    1.5
}
pub(super) fn d_active() -> f64 {
    3.5
}
pub(super) fn d_ramp_minutes() -> f64 {
    45.0
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// Scene-wide settings (`[scene]`).
pub(super) struct RawScene {
    /// Scene name.
    pub(super) name: String,
    /// `[xmin, ymin, xmax, ymax]` of the map (metres).
    #[serde(deserialize_with = "exact")]
    #[schemars(with = "[f64; 4]")]
    pub(super) bounds: [f64; 4],
    /// Grid resolution (metres per cell), in (0, 1].
    #[serde(default = "d_resolution")]
    pub(super) resolution: f64,
    /// Time of day at t = 0, `"HH:MM"`.
    #[serde(default = "d_start_time")]
    pub(super) start_time: String,
    /// Control rate (Hz).
    #[serde(default = "d_control_hz")]
    pub(super) control_hz: f64,
    /// Physics rate (Hz), an integer multiple of `control_hz`.
    #[serde(default = "d_physics_hz")]
    pub(super) physics_hz: f64,
    /// Default wall height (metres).
    #[serde(default = "d_wall_height")]
    pub(super) wall_height: f64,
    /// One-paragraph description.
    #[serde(default)]
    pub(super) description: String,
    /// The people's default reaction to robots (`ignore`, `aware`, `yield`, `curious`,
    /// `cautious`; default `aware`; see `docs/people.md`).
    #[serde(default)]
    pub(super) reaction: Reaction,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// Settings of the people sharing a group id (`[[group]]`).
pub(super) struct RawGroup {
    /// The group id (as in `person.group`).
    pub(super) id: u32,
    /// The reaction to robots of the group's members without their own `reaction`.
    pub(super) reaction: Reaction,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// A straight wall segment with thickness (`[[wall]]`).
pub(super) struct RawWall {
    /// Start point `[x, y]` of the centre line (metres).
    #[serde(deserialize_with = "exact")]
    #[schemars(with = "[f64; 2]")]
    pub(super) from: [f64; 2],
    /// End point `[x, y]` of the centre line (metres).
    #[serde(deserialize_with = "exact")]
    #[schemars(with = "[f64; 2]")]
    pub(super) to: [f64; 2],
    /// Thickness (metres).
    #[serde(default = "d_wall_thickness")]
    pub(super) thickness: f64,
    /// Height (metres; default the scene's `wall_height`).
    pub(super) height: Option<f64>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// A static object: furniture, an exhibit (`[[object]]`).
pub(super) struct RawObject {
    /// Unique name.
    pub(super) name: String,
    /// Kind: decides the default height and how the object is drawn.
    pub(super) kind: ObjectKind,
    /// Pose `[x, y, theta]` (metres, radians); theta is the direction the object faces.
    #[serde(deserialize_with = "exact")]
    #[schemars(with = "[f64; 3]")]
    pub(super) pose: [f64; 3],
    /// `[depth, width]` along the object's facing axis and across it (metres); or give `radius`.
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 2]>")]
    pub(super) size: Option<[f64; 2]>,
    /// Radius of a round object (metres).
    pub(super) radius: Option<f64>,
    /// Height (metres; default by kind).
    pub(super) height: Option<f64>,
    /// Whether the object blocks motion.
    #[serde(default = "d_true")]
    pub(super) solid: bool,
    /// Interaction space (Calderita §4.2): where people stand to use or look at the object.
    pub(super) interaction: Option<RawInteraction>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields, tag = "shape", rename_all = "snake_case")]
/// An interaction space, by `shape`.
pub(super) enum RawInteraction {
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
    /// An explicit world-frame polygon, `[x, y]` vertices (metres), simple.
    Polygon {
        /// The vertices.
        #[serde(deserialize_with = "polygon_points")]
        #[schemars(with = "Vec<[f64; 2]>")]
        points: Vec<[f64; 2]>,
    },
}

/// `deserialize_with` of a polygon's `points` (its error names the field: the path of an
/// internally tagged enum's content ends at the enum).
fn polygon_points<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f64; 2]>, D::Error> {
    entries_exact(Vec::<Vec<f64>>::deserialize(d)?, "points entry")
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// A scripted person (`[[person]]`); which fields apply depends on `behaviour`.
pub(super) struct RawPerson {
    /// Unique name (default `person_<index>`).
    pub(super) name: Option<String>,
    /// What the person does (each behaviour's fields are in its description).
    #[serde(default = "d_behaviour")]
    pub(super) behaviour: Behaviour,
    /// Pose `[x, y, theta]` (metres, radians): standing people.
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 3]>")]
    pub(super) pose: Option<[f64; 3]>,
    /// Closed route of `[x, y]` waypoints (metres): walkers and guides.
    #[serde(default, deserialize_with = "vec_exact")]
    #[schemars(with = "Vec<[f64; 2]>")]
    pub(super) route: Vec<[f64; 2]>,
    /// Metres per second, or a preset name ([`SPEED_PRESETS`](super::SPEED_PRESETS)): `fast`,
    /// `normal`, `slow`, `elderly`. Default 1.0 m/s.
    #[schemars(with = "Option<NumberOrText>")]
    pub(super) speed: Option<toml::Value>,
    /// Pause at each stop (s).
    #[serde(default)]
    pub(super) dwell: f64,
    /// Visitors: the objects visited in turn, by name or index into `[[object]]`.
    #[serde(default)]
    #[schemars(with = "Vec<NameOrIndex>")]
    pub(super) exhibits: Vec<toml::Value>,
    /// Conversation, resident, staff: `[x, y]` where the person is when not busy (metres).
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 2]>")]
    pub(super) home: Option<[f64; 2]>,
    /// Conversation: `[x, y]` of the o-space centre (metres).
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 2]>")]
    pub(super) spot: Option<[f64; 2]>,
    /// Conversation: when it forms, seconds into the episode or `"HH:MM"`.
    #[schemars(with = "Option<NumberOrText>")]
    pub(super) start: Option<toml::Value>,
    /// Conversation: when it breaks up, seconds into the episode or `"HH:MM"`.
    #[schemars(with = "Option<NumberOrText>")]
    pub(super) end: Option<toml::Value>,
    /// Seated: the bench, sofa or chair (an object name).
    pub(super) seat: Option<String>,
    /// Seated: the seat index along the object's width (one per 0.6 m).
    #[serde(default)]
    pub(super) place: usize,
    /// Follower: the guide, a person's name or `"robot:<name>"`.
    pub(super) guide: Option<String>,
    /// Walker and guide: indices of the route waypoints where the person dwells (default all).
    pub(super) stops: Option<Vec<usize>>,
    /// Resident, staff: the objects (names) whose agenda activities the person attends.
    #[serde(default)]
    pub(super) attends: Vec<String>,
    /// Resident, staff: arrival lead before an activity starts (minutes).
    #[serde(default = "d_lead_minutes")]
    pub(super) lead_minutes: f64,
    /// Follower: arc radius around the guide at stops (metres).
    #[serde(default = "d_gather_radius")]
    pub(super) gather_radius: f64,
    /// Body radius (metres), in (0, 0.5].
    #[serde(default = "d_person_radius")]
    pub(super) radius: f64,
    /// Height (metres).
    #[serde(default = "d_person_height")]
    pub(super) height: f64,
    /// Ground-truth group id (conversations share one).
    pub(super) group: Option<u32>,
    /// Older spelling: `aware = false` is `reaction = "ignore"` (`true`, the default, leaves the
    /// reaction to `reaction`, the group's or the scene's).
    #[serde(default = "d_true")]
    pub(super) aware: bool,
    /// How the person reacts to robots: `ignore`, `aware`, `yield`, `curious` or `cautious`
    /// (default: its group's, else the scene's; see `docs/people.md`).
    pub(super) reaction: Option<Reaction>,
    /// Socialization feature values in (0, 1], one per `proxemics.features` name.
    #[serde(default)]
    pub(super) features: Vec<f64>,
    /// Emotional state (a named feature preset of Sousa et al. 2022).
    pub(super) emotional_state: Option<String>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// A robot (`[[robot]]`): a Pepper-like holonomic base, or a differential-drive base
/// (`drive = "differential"`).
pub(super) struct RawRobot {
    /// Unique name (default `robot_<index>`).
    pub(super) name: Option<String>,
    /// Start pose `[x, y, theta]` (metres, radians).
    #[serde(deserialize_with = "exact")]
    #[schemars(with = "[f64; 3]")]
    pub(super) start: [f64; 3],
    /// Goal `[x, y]` (metres); or give `approach`.
    #[serde(default, deserialize_with = "opt_exact")]
    #[schemars(with = "Option<[f64; 2]>")]
    pub(super) goal: Option<[f64; 2]>,
    /// An approach task: go to the edge of a person's (or group's) personal space and face them.
    pub(super) approach: Option<RawApproach>,
    /// Built-in planner.
    #[serde(default = "d_planner")]
    pub(super) planner: PlannerKind,
    /// Footprint radius (metres; Pepper's by default).
    #[serde(default = "d_robot_radius")]
    pub(super) radius: f64,
    /// Maximum linear speed (m/s), the norm of (vx, vy).
    #[serde(default = "d_max_speed")]
    pub(super) max_speed: f64,
    /// Maximum angular speed (rad/s).
    #[serde(default = "d_max_angular_speed")]
    pub(super) max_angular_speed: f64,
    /// Maximum linear acceleration (m/s²).
    #[serde(default = "d_max_accel")]
    pub(super) max_accel: f64,
    /// Maximum angular acceleration (rad/s²), in (0, 100] (default 3.0, Pepper's).
    #[serde(default = "d_max_angular_accel")]
    pub(super) max_angular_accel: f64,
    /// How the base moves: `holonomic` (default; any planar velocity) or `differential`
    /// (unicycle kinematics: forward speed and turn rate, no sideways motion).
    #[serde(default)]
    pub(super) drive: crate::control::Drive,
    /// Extra clearance added to the radius when inflating the map (metres).
    #[serde(default = "d_inflation_margin")]
    pub(super) inflation_margin: f64,
    /// Gains of the elastic band (the `eband` planner).
    #[serde(default)]
    pub(super) eband: RawEbandGains,
    /// Places `[x, y]` visited in order before the goal (metres): a tour.
    #[serde(default, deserialize_with = "vec_exact")]
    #[schemars(with = "Vec<[f64; 2]>")]
    pub(super) waypoints: Vec<[f64; 2]>,
    /// Seconds the robot stands still at each waypoint, in [0, 3600].
    #[serde(default)]
    pub(super) dwell: f64,
    /// The built-in planner's progress monitor (every built-in planner runs it).
    #[serde(default)]
    pub(super) progress: RawProgress,
}

#[derive(Deserialize, JsonSchema, Default)]
#[serde(deny_unknown_fields)]
/// The progress monitor: a robot that has not come `distance` metres closer to its target
/// (geodesic distance) within `window` seconds recovers (backs out, re-plans round the people
/// blocking it).
pub(super) struct RawProgress {
    /// Whether the monitor runs (default true).
    pub(super) enabled: Option<bool>,
    /// Progress that counts (metres of geodesic distance), in (0, 10] (default 0.5).
    pub(super) distance: Option<f64>,
    /// Time to make it (s), in (0, 600] (default 15).
    pub(super) window: Option<f64>,
}

#[derive(Deserialize, JsonSchema, Default)]
#[serde(deny_unknown_fields)]
/// The elastic band's force gains (dimensionless), as tuned by `proxemic tune` (Calderita §5.4).
pub(super) struct RawEbandGains {
    /// Contraction gain `k_c` (default 1.0).
    pub(super) contraction_gain: Option<f64>,
    /// Repulsion gain `k_r` from static obstacles (default 0.5).
    pub(super) repulsion_gain: Option<f64>,
    /// Gain of the people's spaces (default 0.5).
    pub(super) social_gain: Option<f64>,
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// An approach task: the goal is computed from a person's or a group's personal space.
pub(super) struct RawApproach {
    /// The person approached (by name).
    pub(super) person: Option<String>,
    /// The group approached (by group id).
    pub(super) group: Option<u32>,
    /// Side of the approach: `auto`, `front`, `left`, `right` or `rear`.
    #[serde(default = "d_side")]
    pub(super) side: String,
    /// Personal-space level whose edge is the goal.
    pub(super) level: Option<f64>,
}

pub(super) fn d_side() -> String {
    "auto".into()
}

#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
/// Episode settings (`[episode]`).
pub(super) struct RawEpisode {
    /// Time limit (s); the episode is truncated when it is reached.
    #[serde(default = "d_max_time")]
    pub(super) max_time: f64,
    /// The robot succeeds when its centre is within this distance of the goal (metres).
    #[serde(default = "d_success_radius")]
    pub(super) success_radius: f64,
    /// Per-episode randomisation.
    #[serde(default)]
    pub(super) randomize: Randomize,
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

pub(super) fn d_resolution() -> f64 {
    0.1
}
pub(super) fn d_start_time() -> String {
    "09:00".to_string()
}
pub(super) fn d_control_hz() -> f64 {
    10.0
}
pub(super) fn d_physics_hz() -> f64 {
    100.0
}
pub(super) fn d_wall_height() -> f64 {
    2.5
}
pub(super) fn d_wall_thickness() -> f64 {
    0.2
}
pub(super) fn d_true() -> bool {
    true
}
pub(super) fn d_behaviour() -> Behaviour {
    Behaviour::Walker
}
pub(super) fn d_person_speed() -> f64 {
    1.0
}
pub(super) fn d_lead_minutes() -> f64 {
    2.0
}
pub(super) fn d_gather_radius() -> f64 {
    1.5
}
pub(super) fn d_person_radius() -> f64 {
    0.2
}
pub(super) fn d_person_height() -> f64 {
    1.7
}
pub(super) fn d_planner() -> PlannerKind {
    PlannerKind::Astar
}
pub(super) fn d_robot_radius() -> f64 {
    0.24
}
pub(super) fn d_max_speed() -> f64 {
    0.55
}
pub(super) fn d_max_angular_speed() -> f64 {
    2.0
}
pub(super) fn d_max_accel() -> f64 {
    0.55
}
pub(super) fn d_max_angular_accel() -> f64 {
    crate::control::Limits::PEPPER.max_angular_accel
}
pub(super) fn d_inflation_margin() -> f64 {
    0.06
}
pub(super) fn d_max_time() -> f64 {
    180.0
}
pub(super) fn d_success_radius() -> f64 {
    0.3
}
pub(super) fn d_speed_jitter() -> f64 {
    0.1
}
pub(super) fn d_lidar_rays() -> usize {
    72
}
pub(super) fn d_lidar_range() -> f64 {
    8.0
}
pub(super) fn d_k_nearest() -> usize {
    8
}
pub(super) fn d_progress() -> f64 {
    1.0
}
pub(super) fn d_success() -> f64 {
    10.0
}
pub(super) fn d_collision() -> f64 {
    -10.0
}
pub(super) fn d_time() -> f64 {
    -0.01
}
pub(super) fn d_personal_space() -> f64 {
    -0.1
}

/// Schema-only: a number or a text (`speed = 1.2` or `speed = "slow"`, `start = 30` or `"10:30"`).
#[derive(JsonSchema)]
#[schemars(untagged)]
#[allow(dead_code)]
enum NumberOrText {
    /// A number.
    Number(f64),
    /// A name or a time of day `"HH:MM"`.
    Text(String),
}

/// Schema-only: an object by name or by index into `[[object]]`.
#[derive(JsonSchema)]
#[schemars(untagged)]
#[allow(dead_code)]
enum NameOrIndex {
    /// An index.
    Index(usize),
    /// A name.
    Name(String),
}

/// An array of exactly `N` numbers (serde's fixed-size arrays let TOML's extra elements pass).
fn to_array<E: serde::de::Error, const N: usize>(v: Vec<f64>) -> Result<[f64; N], E> {
    let n = v.len();
    v.try_into().map_err(|_| {
        E::custom(format!(
            "invalid length: an array of {n} numbers, expected an array of exactly {N} numbers"
        ))
    })
}

/// `deserialize_with` of a `[f64; N]` field: refuses an array of another length.
pub(super) fn exact<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<[f64; N], D::Error> {
    to_array(Vec::<f64>::deserialize(d)?)
}

/// `deserialize_with` of an `Option<[f64; N]>` field (with `default`).
pub(super) fn opt_exact<'de, D: Deserializer<'de>, const N: usize>(
    d: D,
) -> Result<Option<[f64; N]>, D::Error> {
    Option::<Vec<f64>>::deserialize(d)?.map(to_array).transpose()
}

/// `deserialize_with` of a `Vec<[f64; N]>` field: every entry has exactly `N` numbers.
pub(super) fn vec_exact<'de, D: Deserializer<'de>, const N: usize>(d: D) -> Result<Vec<[f64; N]>, D::Error> {
    entries_exact(Vec::<Vec<f64>>::deserialize(d)?, "entry")
}

fn entries_exact<E: serde::de::Error, const N: usize>(
    entries: Vec<Vec<f64>>,
    what: &str,
) -> Result<Vec<[f64; N]>, E> {
    entries
        .into_iter()
        .enumerate()
        .map(|(i, p)| {
            let n = p.len();
            p.try_into().map_err(|_| {
                E::custom(format!(
                    "invalid length: {what} {i} has {n} numbers, expected arrays of exactly {N} numbers each"
                ))
            })
        })
        .collect()
}
