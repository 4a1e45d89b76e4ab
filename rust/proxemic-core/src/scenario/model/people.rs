//! The people of a validated scenario: behaviours, named speeds, [`Person`].

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::scenario::raw::{
    d_gather_radius, d_lead_minutes, d_person_height, d_person_radius, d_person_speed,
};

/// Named walking speeds (m/s) accepted by `person.speed`: `normal` is the mean desired speed of
/// Helbing & Molnar 1995 (1.34 m/s, rounded); `fast`, `slow` and `elderly` (a frail older adult,
/// as in a care center) are this project's choices, not values from the papers.
pub const SPEED_PRESETS: [(&str, f64); 4] = [("fast", 1.6), ("normal", 1.3), ("slow", 0.9), ("elderly", 0.6)];

/// Seat spacing along a bench or sofa (metres): one person per 0.6 m of its width.
pub const SEAT_SPACING: f64 = 0.6;

/// How a person reacts to robots (`person.reaction`, `[[group]]`'s `reaction`, `scene.reaction`;
/// the person's own value wins, then its group's, then the scene's, default `aware`). The
/// parameters of each are [`crate::pedestrians::ReactionParams`] (`docs/people.md`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Reaction {
    /// The robot is invisible (CrowdNav's default): no force, no keep-out; the person walks
    /// through its space, and a contact is then the person's doing.
    Ignore,
    /// The robot is a body with a personal space, avoided like a person of its size: the social
    /// force of a person plus a keep-out around its body that grows with the robot's speed.
    #[default]
    Aware,
    /// Like `aware`, and steps aside (or waits, if there is no room) to let a moving robot pass.
    Yield,
    /// Approaches a robot it notices to about 1 m and follows it for a while, then goes on.
    Curious,
    /// Keeps a larger distance than `aware` and slows down near a robot.
    Cautious,
}

impl Reaction {
    /// The names accepted in scenario files and generator specs.
    pub const NAMES: [&'static str; 5] = ["ignore", "aware", "yield", "curious", "cautious"];

    /// Parses a name of [`Reaction::NAMES`].
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "ignore" => Some(Reaction::Ignore),
            "aware" => Some(Reaction::Aware),
            "yield" => Some(Reaction::Yield),
            "curious" => Some(Reaction::Curious),
            "cautious" => Some(Reaction::Cautious),
            _ => None,
        }
    }

    /// The name of the reaction (as in [`Reaction::NAMES`]).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
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
    /// How the person reacts to robots (default [`Reaction::Aware`]).
    pub reaction: Reaction,
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
    /// is not in the episode (see [`crate::scenario::Scenario::with_robots`]: the tour then waits at its start).
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
            reaction: Reaction::Aware,
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
