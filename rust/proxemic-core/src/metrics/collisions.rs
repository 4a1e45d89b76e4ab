//! The outcome and the collisions (`docs/metrics.md`, Outcome and collisions): success, collision, timeout,
//! time to goal, and the steps with a collision by kind. A step collides with a person when the
//! physics says so or when the swept relative motion of the two discs overlaps (CrowdNav's test;
//! people present over the step only),
//! with the static geometry or another robot when the physics says so. A person contact ends the
//! episode (a collision, failing success) only when it is the robot's fault ([`super::fault`]).

use serde::Serialize;

use super::fault::Touch;
use super::{CONTACT_PERSON, CONTACT_ROBOT, CONTACT_STATIC, PeopleTracks, Samples, Trajectory};
use crate::geom::distance_point_segment;
use crate::math::{EPS, Vec2};

/// The outcome and collision metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CollisionMetrics {
    /// Number of control steps `T` (samples minus one, 0 for an empty trajectory).
    pub steps: usize,
    /// Success S (`docs/metrics.md`, Outcome and collisions): the robot centre came within `success_radius` of the goal at
    /// some instant with no collision (static, robot, or a person contact that is the robot's
    /// fault) in any step ending at or before it; a person walking into the robot does not fail it.
    pub success: bool,
    /// A collision that ends the episode (`docs/metrics.md`, Outcome and collisions): with walls or furniture, with
    /// another robot, or with a person by the robot's fault ([`super::fault`]).
    pub collision: bool,
    /// Timeout TO (`docs/metrics.md`, Outcome and collisions): neither success nor any collision in the recording.
    pub timeout: bool,
    /// Time to goal (s, `docs/metrics.md`, Outcome and collisions): first goal instant times `dt`; `None` without success.
    pub time_to_goal: Option<f64>,
    /// Steps with a collision with a person, HC (`docs/metrics.md`, Outcome and collisions): a
    /// negative surface gap anywhere on the swept relative motion over the step (both bodies
    /// moving linearly between the instants, CrowdNav's test), or the physics' person bit; only
    /// people present over the whole step count ([`super::fault`]: a physics contact with a
    /// replayed person appearing or leaving in the step is none).
    pub hc_count: usize,
    /// Steps with a collision with walls or furniture, WC (physics' static bit).
    pub wc_count: usize,
    /// Steps with a collision with another robot, AC (physics' robot bit).
    pub ac_count: usize,
    /// `hc_count > 0`.
    pub hc: bool,
    /// `wc_count > 0`.
    pub wc: bool,
    /// `ac_count > 0`.
    pub ac: bool,
}

/// Surface gap (m; negative = overlap) of the robot moving linearly from `p0` to `p1` (radius
/// `rr`) and a person moving linearly from `q0` to `q1` (radius `r`) over the same step, at their
/// closest: the distance from the origin to the segment of their relative positions, minus both
/// radii. A relative motion shorter than [`EPS`] counts as none (the gap at the start).
pub(crate) fn swept_gap(p0: Vec2, p1: Vec2, q0: Vec2, q1: Vec2, rr: f64, r: f64) -> f64 {
    let (a, b) = (q0 - p0, q1 - p1);
    let d = if (b - a).norm_squared() <= EPS * EPS {
        a.norm()
    } else {
        distance_point_segment(Vec2::zeros(), a, b)
    };
    d - rr - r
}

/// The outcome and collisions of the recording `s` among `people`, with the physics' `CONTACT_*`
/// bits `contacts` per step (or none) and each step's person `touches` ([`super::fault::touches`]).
pub(crate) fn evaluate(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    contacts: &[u8],
    touches: &[Touch],
) -> CollisionMetrics {
    let np = people.count;
    // Per step k, attributed to instant k + 1.
    let (mut hc_count, mut wc_count, mut ac_count) = (0usize, 0usize, 0usize);
    let mut first_collision_instant: Option<usize> = None;
    for k in 0..s.steps {
        let bits = contacts.get(k).copied().unwrap_or(0);
        // A person contact is a step touching someone ([`super::fault::classify_step`]: the swept
        // discs of a person present over the step, or the physics' person contact with a person
        // present over it; a physics contact with a replayed person appearing or leaving is
        // none), or the physics' person contact with no person in the tracks to attribute it to.
        let row = touches.get(k * np..(k + 1) * np).unwrap_or(&[]);
        let nobody = (0..np).all(|i| !people.is_present(k, i) && !people.is_present(k + 1, i));
        let hit_person = row.iter().any(|&t| t != Touch::None) || (bits & CONTACT_PERSON != 0 && nobody);
        let hit_static = bits & CONTACT_STATIC != 0;
        let hit_robot = bits & CONTACT_ROBOT != 0;
        hc_count += usize::from(hit_person);
        wc_count += usize::from(hit_static);
        ac_count += usize::from(hit_robot);
        let robot_fault = row.contains(&Touch::RobotFault);
        if (robot_fault || hit_static || hit_robot) && first_collision_instant.is_none() {
            first_collision_instant = Some(k + 1);
        }
    }
    let collision = first_collision_instant.is_some();
    let goal_instant = s.pos.iter().position(|p| (p - traj.goal).norm() <= traj.success_radius);
    let success = match (goal_instant, first_collision_instant) {
        (Some(g), Some(c)) => g < c,
        (Some(_), None) => true,
        _ => false,
    };
    CollisionMetrics {
        steps: s.steps,
        success,
        collision,
        timeout: s.n > 0 && !success && !collision,
        time_to_goal: if success { goal_instant.map(|g| g as f64 * traj.dt) } else { None },
        hc_count,
        wc_count,
        ac_count,
        hc: hc_count > 0,
        wc: wc_count > 0,
        ac: ac_count > 0,
    }
}
