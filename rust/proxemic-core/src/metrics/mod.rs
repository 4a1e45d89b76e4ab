//! Episode metrics (definitions: `docs/metrics.md`; each family's module cites its sources).
//!
//! While an episode runs, a [`SceneLog`] keeps what every robot's metrics share (the people's
//! tracks, the groups' o-spaces and the interaction segments, the object spaces' activity), and
//! an [`EpisodeRecorder`] per robot keeps its poses and contacts per step and decides the
//! episode's [`Outcome`] step by step with the same rules the evaluator applies afterwards, so
//! the env's termination flags and the final [`FullMetrics`] always agree. At the end,
//! [`EpisodeRecorder::evaluate`] gives the full metric set ([`EpisodeReport`]), computed by
//! [`evaluate`] one family at a time:
//! - [`collisions`]: the outcome and the collisions by kind (`docs/metrics.md`, Outcome and collisions);
//! - [`efficiency`]: path length, its ratio, SPL, failures to progress (Efficiency);
//! - [`motion`]: stalled time, speed, acceleration, jerk, heading changes, path irregularity
//!   (Motion quality);
//! - [`proximity`]: distances to people, discomfort, compliance, Hall zones, time to
//!   collision and social force (Distance to people), clearance (Static geometry);
//! - [`approach`]: who approached whom, the intimate- and personal-zone time and entries (body
//!   gaps) split into robot-caused and person-caused by [`fault`]'s rule (its keys follow
//!   [`proximity`]'s zone shares in the report);
//! - [`groups`]: o-spaces and interaction crossings (Groups and interactions);
//! - [`objects`]: the objects' interaction spaces (Calderita et al.'s Ψ per object);
//! - [`papers`]: Daza et al. 2021's `l_ratio`, `smooth_rad2`, `smooth_rad`; Calderita et al.'s
//!   `d_t`, `tau`;
//! - [`snqi`]: the inputs of robot-sf's SNQI composite that the others do not give (near
//!   misses, force-exceed events, comfort exposure).
//! - [`fault`]: who hit whom, the contact events by fault (SEAN 2.0, HuNavSim);
//! - [`people_cost`]: the robot's cost to people (delay, extra distance, path deviation) against
//!   the episode replayed without the robots.
//! - [`recovery`]: the built-in planner's progress monitor (`recoveries`, `monitor_stalled_time`),
//!   not from the trajectory but from the planner, appended after every other key of the report.
//!
//! [`registry`] describes every key of a serialised report (unit, better direction, definition,
//! formula, source): the metric reference of the docs is generated from it.
//!
//! Each family returns its own struct, flattened into [`FullMetrics`] (one key per metric when
//! serialised, in the families' order above, the room-left part of [`proximity`] after
//! [`objects`]). Not computed: see `docs/metrics.md`, Not computed.
//!
//! # Conventions
//! - The robot is sampled at the control instants `t = 0..=T` (`N = T + 1` samples, `T` steps of
//!   `dt` seconds). Step `k` goes from instant `k` to instant `k + 1`.
//! - **Per-instant** metrics (zones, discomfort, compliance, o-space, object spaces, clearance,
//!   distances to people, social force) are taken over all `N` instants, the start included.
//!   Percentages are `100 * count / N`, fractions `count / N`.
//! - **Per-step** metrics (velocity, collisions, time to collision, crossings) are taken over the
//!   `T` steps.
//! - Distances: `d` is centre-to-centre (robot centre to person centre), `gap = d - r_robot -
//!   r_person` is the surface gap. Each field's documentation says which one it uses.
//! - Angles are radians, lengths metres, times seconds.
//! - Every input must be finite (infinite `geodesic_length` excepted, meaning "unreachable");
//!   otherwise [`evaluate`] returns [`crate::error::CoreError::Input`] naming the array and
//!   index. It never panics. An empty trajectory gives counts 0, `false` outcomes and `None` for
//!   every value that needs a sample.
//!
//! # Ground truth of groups and interactions
//! Groups and interactions are the scenario's ground truth, the same for every planner
//! ([`interactions()`]):
//! - a group is the people sharing a `group` id; it has an o-space while it stands gathered:
//!   the largest set of its members standing still (speed below [`STILL_SPEED`]) within
//!   [`GATHERED_RADIUS`] of their mean position, when it has two or more. The o-space is the
//!   circle centred on their mean position through their mean distance to it (Kendon's o-space
//!   as the space the members enclose). Members still walking to their places, or spread over
//!   the floor waiting for their conversation to start, or a tour on the move, form none (an
//!   F-formation is a standing arrangement);
//! - a person-person interaction is the segment between two members of a gathered group;
//! - a person-object interaction is the segment from a person standing still (speed below
//!   [`STILL_SPEED`]) inside an object's interaction space to the object's centre (a visitor
//!   looking at a painting, a senior watching the TV).

pub mod approach;
pub mod collisions;
pub mod efficiency;
pub mod fault;
pub mod groups;
mod input;
mod interactions;
pub mod invariants;
pub mod motion;
pub mod objects;
pub mod papers;
pub mod people_cost;
pub mod proximity;
mod recorder;
pub mod recovery;
pub mod registry;
pub mod snqi;
#[cfg(test)]
mod tests;

use serde::Serialize;

use crate::error::Result;
use crate::math::Vec2;
pub use approach::ApproachMetrics;
pub use collisions::CollisionMetrics;
pub use efficiency::EfficiencyMetrics;
pub use fault::FaultMetrics;
pub use groups::GroupMetrics;
pub use input::{
    DEFAULT_ZONES, EvalContext, Groups, InteractionLink, LinkKind, MetricParams, OSpace, ObjectSpaces,
    PeopleTracks, Trajectory,
};
pub use interactions::{GATHERED_RADIUS, InteractionObject, STILL_SPEED, interactions};
pub use motion::MotionMetrics;
pub use objects::ObjectMetrics;
pub use papers::PaperMetrics;
pub use people_cost::{PeopleCostMetrics, RobotFreeTracks};
pub use proximity::{ClearanceMetrics, ProximityMetrics};
pub use recorder::{EpisodeRecorder, EpisodeReport, Outcome, RecorderSetup, SceneLog, Snapshot};
pub use recovery::RecoveryMetrics;
pub use registry::{Better, METRICS, MetricInfo, Per, metric_info};
pub use snqi::SnqiMetrics;

/// Contact bit of [`EvalContext::collision_steps`] and of the world's physics contacts: the robot
/// touched a person.
pub const CONTACT_PERSON: u8 = 1;
/// Contact bit: the robot touched walls or furniture.
pub const CONTACT_STATIC: u8 = 2;
/// Contact bit: the robot touched another robot.
pub const CONTACT_ROBOT: u8 = 4;

/// Every metric of one episode, one struct per family, flattened when serialised (one key per
/// metric, in this order). `None` means undefined (reason in each field's doc).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FullMetrics {
    /// The outcome and the collisions.
    #[serde(flatten)]
    pub collisions: CollisionMetrics,
    /// Path efficiency.
    #[serde(flatten)]
    pub efficiency: EfficiencyMetrics,
    /// Motion quality.
    #[serde(flatten)]
    pub motion: MotionMetrics,
    /// Proximity to people.
    #[serde(flatten)]
    pub proximity: ProximityMetrics,
    /// Who approached whom: zone time and entries (body gaps), robot-caused and person-caused.
    #[serde(flatten)]
    pub approach: ApproachMetrics,
    /// Groups and interactions.
    #[serde(flatten)]
    pub groups: GroupMetrics,
    /// Object spaces.
    #[serde(flatten)]
    pub objects: ObjectMetrics,
    /// Time to collision, clearance to the static geometry, social force.
    #[serde(flatten)]
    pub clearance: ClearanceMetrics,
    /// The seed papers' own metrics.
    #[serde(flatten)]
    pub papers: PaperMetrics,
    /// The SNQI inputs not given by the other families.
    #[serde(flatten)]
    pub snqi: SnqiMetrics,
    /// Who hit whom: the contact events by fault.
    #[serde(flatten)]
    pub fault: FaultMetrics,
    /// The robot's cost to people, against the robot-free run.
    #[serde(flatten)]
    pub people_cost: PeopleCostMetrics,
}

/// The robot's samples, shared by the families.
pub(crate) struct Samples {
    /// Samples `N`.
    pub n: usize,
    /// Steps `T = N - 1` (0 for an empty trajectory).
    pub steps: usize,
    /// Robot centres (m), `N` entries.
    pub pos: Vec<Vec2>,
    /// Robot yaws (rad), `N` entries.
    pub yaw: Vec<f64>,
    /// Forward-difference velocities `(p_{t+1} - p_t) / dt` (m/s), `T` entries.
    pub vel: Vec<Vec2>,
}

impl Samples {
    fn new(traj: &Trajectory) -> Self {
        let n = traj.robot.len();
        let pos: Vec<Vec2> = traj.robot.iter().map(|r| Vec2::new(r[0], r[1])).collect();
        let yaw = traj.robot.iter().map(|r| r[2]).collect();
        let vel = pos.windows(2).map(|w| (w[1] - w[0]) / traj.dt).collect();
        Samples { n, steps: n.saturating_sub(1), pos, yaw, vel }
    }

    /// Sum of the distances between consecutive centres (m).
    pub fn path_length(&self) -> f64 {
        self.pos.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }
}

/// Evaluates one recorded episode (see the module documentation for conventions).
///
/// # Errors
/// [`crate::error::CoreError::Input`] when an array has the wrong length, a value is not finite
/// (except an infinite `geodesic_length`), a radius or threshold is negative, or the zones
/// decrease.
pub fn evaluate(
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<FullMetrics> {
    input::validate(traj, people, groups, objects, ctx)?;
    let s = Samples::new(traj);
    let touches = fault::touches(&s, traj, people, ctx.collision_steps);
    let collisions = collisions::evaluate(&s, traj, people, ctx.collision_steps, &touches);
    let efficiency = efficiency::evaluate(&s, traj, ctx, collisions.success);
    let path_length = efficiency.path_length;
    Ok(FullMetrics {
        motion: motion::evaluate(&s, traj, &ctx.params, path_length),
        proximity: proximity::evaluate(&s, traj, people, ctx),
        groups: groups::evaluate(&s, traj.dt, groups, &ctx.zones),
        objects: objects::evaluate(&s, objects),
        clearance: proximity::evaluate_clearance(&s, traj, people, ctx),
        papers: papers::evaluate(&s, traj.dt, ctx, collisions.success, path_length),
        snqi: snqi::evaluate(&s, traj, people, |t, i| {
            proximity::force_on_person(&s, traj, people, &ctx.params, t, i)
        }),
        fault: fault::evaluate(s.steps, people.count, &touches, ctx.collision_steps),
        approach: approach::evaluate(&s, traj, people, ctx),
        people_cost: people_cost::evaluate(
            s.n,
            people.count,
            traj.dt,
            people.positions,
            people.present,
            ctx.robot_free.as_ref(),
        ),
        collisions,
        efficiency,
    })
}

/// Min, mean and max of a sequence; `None` when empty.
fn min_avg_max(values: impl Iterator<Item = f64>) -> Option<(f64, f64, f64)> {
    let mut count = 0usize;
    let (mut lo, mut sum, mut hi) = (f64::INFINITY, 0.0, f64::NEG_INFINITY);
    for v in values {
        count += 1;
        lo = lo.min(v);
        hi = hi.max(v);
        sum += v;
    }
    (count > 0).then(|| (lo, sum / count as f64, hi))
}

/// `100 * count / n`; `None` when `n` is 0.
fn pct(count: usize, n: usize) -> Option<f64> {
    (n > 0).then(|| 100.0 * count as f64 / n as f64)
}

/// `count / n`; `None` when `n` is 0.
fn frac(count: usize, n: usize) -> Option<f64> {
    (n > 0).then(|| count as f64 / n as f64)
}

/// Zone index of a centre distance: 0 intimate, 1 personal, 2 social, 3 public.
fn zone_of(d: f64, zones: &[f64; 3]) -> usize {
    zones.iter().position(|&z| d < z).unwrap_or(3)
}
