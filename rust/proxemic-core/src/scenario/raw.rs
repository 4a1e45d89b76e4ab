//! The file representation: serde structs mirroring the TOML tables (unknown fields rejected)
//! and the default of every optional field.

use serde::Deserialize;

use super::model::{Behaviour, ObjectKind, PlannerKind, Randomize, RewardWeights, Sensors};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScenario {
    pub(super) scene: RawScene,
    #[serde(default)]
    pub(super) wall: Vec<RawWall>,
    #[serde(default)]
    pub(super) object: Vec<RawObject>,
    #[serde(default)]
    pub(super) person: Vec<RawPerson>,
    #[serde(default)]
    pub(super) robot: Vec<RawRobot>,
    #[serde(default)]
    pub(super) episode: RawEpisode,
    #[serde(default)]
    pub(super) sensors: Sensors,
    #[serde(default)]
    pub(super) reward: RewardWeights,
    #[serde(default)]
    pub(super) proxemics: RawProxemics,
    #[serde(default)]
    pub(super) agenda: RawAgenda,
    #[serde(default)]
    pub(super) activity: Vec<RawActivity>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawProxemics {
    #[serde(default = "d_zones")]
    pub(super) zones: String,
    pub(super) zone_radii: Option<[f64; 3]>,
    #[serde(default = "d_space")]
    pub(super) space: String,
    pub(super) sigma: Option<f64>,
    pub(super) sigma_front: Option<f64>,
    pub(super) sigma_rear: Option<f64>,
    pub(super) sigma_left: Option<f64>,
    pub(super) sigma_right: Option<f64>,
    #[serde(default = "d_cost_mode")]
    pub(super) cost_mode: String,
    #[serde(default = "d_personal_cost")]
    pub(super) personal_cost: f64,
    #[serde(default = "d_social_cost")]
    pub(super) social_cost: f64,
    #[serde(default = "d_public_cost")]
    pub(super) public_cost: f64,
    #[serde(default = "d_continuous_gain")]
    pub(super) continuous_gain: f64,
    #[serde(default = "d_groups")]
    pub(super) groups: String,
    pub(super) d_max: Option<f64>,
    pub(super) orientation_rule: Option<bool>,
    #[serde(default = "d_aggregate")]
    pub(super) aggregate: String,
    #[serde(default)]
    pub(super) features: Vec<String>,
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

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawInfluence {
    #[serde(default)]
    pub(super) front: Vec<f64>,
    #[serde(default)]
    pub(super) rear: Vec<f64>,
    #[serde(default)]
    pub(super) left: Vec<f64>,
    #[serde(default)]
    pub(super) right: Vec<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAgenda {
    #[serde(default = "d_idle")]
    pub(super) idle: f64,
    #[serde(default = "d_active")]
    pub(super) active: f64,
    #[serde(default = "d_ramp_minutes")]
    pub(super) ramp_minutes: f64,
}

impl Default for RawAgenda {
    fn default() -> Self {
        RawAgenda { idle: d_idle(), active: d_active(), ramp_minutes: d_ramp_minutes() }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawActivity {
    pub(super) object: String,
    pub(super) start: String,
    pub(super) end: String,
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

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub(super) name: String,
    pub(super) bounds: [f64; 4],
    #[serde(default = "d_resolution")]
    pub(super) resolution: f64,
    #[serde(default = "d_start_time")]
    pub(super) start_time: String,
    #[serde(default = "d_control_hz")]
    pub(super) control_hz: f64,
    #[serde(default = "d_physics_hz")]
    pub(super) physics_hz: f64,
    #[serde(default = "d_wall_height")]
    pub(super) wall_height: f64,
    #[serde(default)]
    pub(super) description: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawWall {
    pub(super) from: [f64; 2],
    pub(super) to: [f64; 2],
    #[serde(default = "d_wall_thickness")]
    pub(super) thickness: f64,
    pub(super) height: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObject {
    pub(super) name: String,
    pub(super) kind: ObjectKind,
    pub(super) pose: [f64; 3],
    pub(super) size: Option<[f64; 2]>,
    pub(super) radius: Option<f64>,
    pub(super) height: Option<f64>,
    #[serde(default = "d_true")]
    pub(super) solid: bool,
    pub(super) interaction: Option<RawInteraction>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, tag = "shape", rename_all = "snake_case")]
pub(super) enum RawInteraction {
    Trapezoid { length: f64, near_width: f64, far_width: f64 },
    Rectangle { margin: f64 },
    Circle { radius: f64 },
    Polygon { points: Vec<[f64; 2]> },
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPerson {
    pub(super) name: Option<String>,
    #[serde(default = "d_behaviour")]
    pub(super) behaviour: Behaviour,
    pub(super) pose: Option<[f64; 3]>,
    #[serde(default)]
    pub(super) route: Vec<[f64; 2]>,
    /// Metres per second, or a preset name ([`SPEED_PRESETS`](super::SPEED_PRESETS)).
    pub(super) speed: Option<toml::Value>,
    #[serde(default)]
    pub(super) dwell: f64,
    #[serde(default)]
    pub(super) exhibits: Vec<toml::Value>,
    pub(super) home: Option<[f64; 2]>,
    pub(super) spot: Option<[f64; 2]>,
    pub(super) start: Option<toml::Value>,
    pub(super) end: Option<toml::Value>,
    pub(super) seat: Option<String>,
    #[serde(default)]
    pub(super) place: usize,
    pub(super) guide: Option<String>,
    pub(super) stops: Option<Vec<usize>>,
    #[serde(default)]
    pub(super) attends: Vec<String>,
    #[serde(default = "d_lead_minutes")]
    pub(super) lead_minutes: f64,
    #[serde(default = "d_gather_radius")]
    pub(super) gather_radius: f64,
    #[serde(default = "d_person_radius")]
    pub(super) radius: f64,
    #[serde(default = "d_person_height")]
    pub(super) height: f64,
    pub(super) group: Option<u32>,
    #[serde(default = "d_true")]
    pub(super) aware: bool,
    #[serde(default)]
    pub(super) features: Vec<f64>,
    pub(super) emotional_state: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRobot {
    pub(super) name: Option<String>,
    pub(super) start: [f64; 3],
    pub(super) goal: Option<[f64; 2]>,
    pub(super) approach: Option<RawApproach>,
    #[serde(default = "d_planner")]
    pub(super) planner: PlannerKind,
    #[serde(default = "d_robot_radius")]
    pub(super) radius: f64,
    #[serde(default = "d_max_speed")]
    pub(super) max_speed: f64,
    #[serde(default = "d_max_angular_speed")]
    pub(super) max_angular_speed: f64,
    #[serde(default = "d_max_accel")]
    pub(super) max_accel: f64,
    #[serde(default = "d_inflation_margin")]
    pub(super) inflation_margin: f64,
    #[serde(default)]
    pub(super) eband: RawEbandGains,
    #[serde(default)]
    pub(super) waypoints: Vec<[f64; 2]>,
    #[serde(default)]
    pub(super) dwell: f64,
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEbandGains {
    pub(super) contraction_gain: Option<f64>,
    pub(super) repulsion_gain: Option<f64>,
    pub(super) social_gain: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawApproach {
    pub(super) person: Option<String>,
    pub(super) group: Option<u32>,
    #[serde(default = "d_side")]
    pub(super) side: String,
    pub(super) level: Option<f64>,
}

pub(super) fn d_side() -> String {
    "auto".into()
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEpisode {
    #[serde(default = "d_max_time")]
    pub(super) max_time: f64,
    #[serde(default = "d_success_radius")]
    pub(super) success_radius: f64,
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
