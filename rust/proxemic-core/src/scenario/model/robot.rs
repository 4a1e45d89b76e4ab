//! The robots of a validated scenario: planners, [`Robot`], elastic-band gains, approach tasks.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::scenario::check::{Checker, err};

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
    /// ORCA among the robots only; otherwise (line 21) the path is followed and no one is avoided,
    /// as the paper writes it: a robot outside the collision cone and anyone beyond the detection
    /// range are not avoided, a collision risk of the published algorithm. Hall radii 0.5 / 1 / 4 m.
    Daza2021,
    /// Sousa et al. 2022: [`PlannerKind::Daza2021`]'s local step (Algorithm 1) whose Social
    /// Momentum keeps out of the personal level of the fully asymmetric Gaussians of the people
    /// and of the Delaunay groups (a group as one individual), reshaped by the socialization
    /// features (§4.5), on a global path planned on the cost map of those Gaussians (§3.1, Fig.
    /// 3: "the provided path planning method must include the values of Gaussian functions as a
    /// cost function"): the scenario's social map of the individuals, searched by A* and
    /// re-planned on triggers like [`PlannerKind::SocialAstar`]'s.
    Sousa2022,
    /// Sousa et al. 2022 §4.5 as the figures pair it (Figs. 16-17: "the A* path" bent by "the
    /// Social Momentum algorithm considering the proxemic zones"): [`PlannerKind::Sousa2022`]'s
    /// local step, Social Momentum on the people's and groups' asymmetric Gaussians, on the plain
    /// A* global path (as [`PlannerKind::Daza2021`]'s) instead of the cost-map path.
    Sousa2022Astar,
    /// Calderita et al.'s system as published: Dijkstra on the time-dependent social cost map
    /// with the people's zones as contours of the summed density (§4.1, §5.1-5.2), the elastic
    /// band (`k_c`, `k_r`, §5.3) deforming that path, re-planned when the agenda or the people
    /// raise its cost ([`crate::plan::social`]).
    Calderita,
    /// A policy learned with PPO on generated scenes of the tuning split
    /// (`examples/train_ppo.py`, `docs/training.md`), shipped as an array file and run by
    /// [`crate::control::learned`]: the observation in, the normalised action out, with no
    /// global path, local planner or recovery of ours.
    Learned,
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
            "sousa2022_astar" => Some(PlannerKind::Sousa2022Astar),
            "calderita" => Some(PlannerKind::Calderita),
            "learned" => Some(PlannerKind::Learned),
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
        "sousa2022_astar",
        "calderita",
        "learned",
    ];

    /// Whether the planner runs Daza et al. 2021 Algorithm 1 as published (with Sousa 2022's
    /// Gaussians for [`PlannerKind::Sousa2022`]): its local step is
    /// [`crate::control::daza2021`]'s.
    pub fn daza2021_family(self) -> bool {
        matches!(self, PlannerKind::Daza2021 | PlannerKind::Sousa2022 | PlannerKind::Sousa2022Astar)
    }

    /// Whether the planner's Social Momentum keeps out of Sousa 2022's asymmetric Gaussians
    /// ([`PlannerKind::Sousa2022`], [`PlannerKind::Sousa2022Astar`]) rather than Daza's intimate
    /// zones.
    pub fn sousa2022_gaussians(self) -> bool {
        matches!(self, PlannerKind::Sousa2022 | PlannerKind::Sousa2022Astar)
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
    /// Maximum angular acceleration (rad/s^2), in (0, 100]; default 3.0 (Pepper, NAOqi
    /// `MaxAccTheta`). Left out of the serialised robot at its default.
    #[serde(skip_serializing_if = "is_pepper_angular_accel")]
    pub max_angular_accel: f64,
    /// How the base moves ([`crate::control::Drive`]); default holonomic (left out of the
    /// serialised robot then).
    #[serde(skip_serializing_if = "crate::control::Drive::is_holonomic")]
    pub drive: crate::control::Drive,
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

/// Whether `a` is Pepper's angular acceleration limit (the default, not serialised).
fn is_pepper_angular_accel(a: &f64) -> bool {
    *a == crate::control::Limits::PEPPER.max_angular_accel
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
    /// names [`crate::scenario::Scenario::with_eband_gains`] accepts.
    pub const NAMES: [&'static str; 3] = ["contraction_gain", "repulsion_gain", "social_gain"];

    /// `gains` (name, value) as one optional value per gain, in the order of [`Self::NAMES`]
    /// (a name given twice keeps its last value). Errors name `{field}.<name>` for a name not in
    /// [`Self::NAMES`] (the first such name in lexicographic order).
    pub(in crate::scenario) fn by_name(
        file: &str,
        field: &str,
        gains: &[(&str, f64)],
    ) -> Result<[Option<f64>; 3]> {
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
    pub(in crate::scenario) fn merged(
        &self,
        file: &str,
        field: &str,
        values: [Option<f64>; 3],
    ) -> Result<Self> {
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
