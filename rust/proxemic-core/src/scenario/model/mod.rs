//! The validated scenario: the types [`super::build`] produces from the raw file tables, and
//! the accessors the world and the bindings use. The people's types are in `people.rs`, the
//! robots' in `robot.rs`.

mod people;
mod robot;

pub use people::{Behaviour, Person, Reaction, SEAT_SPACING, SPEED_PRESETS};
pub use robot::{Approach, EbandGains, PlannerKind, Robot};

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::raw::{
    d_collision, d_k_nearest, d_lidar_range, d_lidar_rays, d_personal_space, d_progress, d_speed_jitter,
    d_success, d_time, d_true,
};
use crate::error::Result;
use crate::map::geometry::{Bounds, StaticGeometry};
use crate::math::Vec2;

/// Number of vertices used to approximate a circle as a polygon.
pub const CIRCLE_VERTICES: usize = 24;

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
    /// Look-ahead (metres, in [0, 10]) of the `subgoal` observation: the point this far along
    /// the shortest path to the robot's current target, in the robot's frame. 0 (the default)
    /// leaves the key out of the observation.
    #[serde(default)]
    pub subgoal: f64,
}

impl Default for Sensors {
    fn default() -> Self {
        Sensors {
            lidar_rays: d_lidar_rays(),
            lidar_range: d_lidar_range(),
            k_nearest: d_k_nearest(),
            subgoal: 0.0,
        }
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
    pub fn proxemics_config(&self) -> crate::perception::ProxemicsConfig {
        use crate::groups::{DelaunayParams, DensityParams, FFormationParams, FeatureAggregate, GroupMethod};
        use crate::proxemics::{Asymmetric, HallZones, PersonalSpace, SideInfluences};
        use crate::social_cost_map::{CostMode, SocialCosts};
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
        crate::perception::ProxemicsConfig {
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

    /// The static geometry of [`Scenario::static_polygons`] within the scene's bounds (its
    /// [`StaticGeometry::bounds`]), as the world collides, rasterises and plans with it.
    ///
    /// # Errors
    /// [`crate::CoreError::Input`] as [`StaticGeometry::new`] (a degenerate polygon, bad bounds).
    pub fn static_geometry(&self) -> Result<StaticGeometry> {
        let b = self.scene.bounds;
        let bounds = Bounds { min: Vec2::new(b[0], b[1]), max: Vec2::new(b[2], b[3]) };
        let polygons = self
            .static_polygons()
            .into_iter()
            .map(|poly| poly.into_iter().map(|q| Vec2::new(q[0], q[1])).collect())
            .collect();
        StaticGeometry::new(polygons, bounds)
    }
}
