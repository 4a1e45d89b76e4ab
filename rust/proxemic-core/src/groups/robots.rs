//! Robots taking part in human interactions (Daza et al. 2021, §4.3).
//!
//! Daza 2021: a secondary robot interacts with humans when it "invades the personal proxemic zone
//! of the humans"; such a robot is then given a proxemic zone (the intimate one) and the planning
//! robot treats the humans and the robot as one group. Rule as implemented: a robot joins the
//! group of person `i` when
//! - it is stationary: speed `<= stationary_speed`, and
//! - it is inside `i`'s personal zone: the distance from `i`'s position to the nearest point of the
//!   robot's disc, `max(0, |p_i - c| - radius)`, is below `personal_radius` (Daza: 1 m).
//!
//! When several people qualify, the nearest one (by that distance; ties: lowest index) decides.

use super::{Groups, PersonState, validate_people};
use crate::error::{CoreError, Result};
use crate::math::{Real, Vec2};

/// A robot as a disc with a velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotDisc {
    /// Centre of the disc (m, world frame, finite).
    pub pos: Vec2,
    /// Disc radius (m, >= 0, finite).
    pub radius: Real,
    /// Velocity (m/s, finite).
    pub vel: Vec2,
}

/// Parameters of [`robot_joins_interaction`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JoinParams {
    /// Outer radius of a person's personal zone (m, > 0, default 1.0, Daza 2021 §2).
    pub personal_radius: Real,
    /// A robot at or below this speed is stationary (m/s, >= 0, default 0.05).
    pub stationary_speed: Real,
}

impl Default for JoinParams {
    fn default() -> Self {
        Self { personal_radius: 1.0, stationary_speed: 0.05 }
    }
}

/// For each robot, the index into `groups.members` of the group it joins, or `None`.
///
/// `groups` must be the result of a detector on the same `people` (a person alone has its own
/// singleton group, so a robot talking to a lone person joins that person's group).
/// Errors: invalid people (`people[i]...`), invalid robots (`robots[k].pos`, `.radius`, `.vel`),
/// `groups.labels` not one per person (`groups.labels`), or invalid parameters
/// (`join.personal_radius`, `join.stationary_speed`).
pub fn robot_joins_interaction(
    people: &[PersonState],
    groups: &Groups,
    robots: &[RobotDisc],
    params: &JoinParams,
) -> Result<Vec<Option<usize>>> {
    validate_people(people)?;
    super::check_positive("join.personal_radius", params.personal_radius, 1e6)?;
    super::check_range("join.stationary_speed", params.stationary_speed, 0.0, 1e9)?;
    if groups.labels.len() != people.len() || groups.labels.iter().any(|&l| l >= groups.members.len()) {
        return Err(CoreError::input(
            "groups.labels",
            format!("{} labels below {}", people.len(), groups.members.len()),
            format!("{} labels", groups.labels.len()),
        ));
    }
    let mut out = Vec::with_capacity(robots.len());
    for (k, r) in robots.iter().enumerate() {
        if !(r.pos.x.is_finite() && r.pos.y.is_finite()) {
            return Err(CoreError::input(
                format!("robots[{k}].pos"),
                "finite coordinates",
                format!("{:?}", r.pos),
            ));
        }
        if !(r.radius.is_finite() && r.radius >= 0.0) {
            return Err(CoreError::input(
                format!("robots[{k}].radius"),
                "a finite value >= 0",
                r.radius.to_string(),
            ));
        }
        if !(r.vel.x.is_finite() && r.vel.y.is_finite()) {
            return Err(CoreError::input(
                format!("robots[{k}].vel"),
                "a finite velocity",
                format!("{:?}", r.vel),
            ));
        }
        if r.vel.norm() > params.stationary_speed {
            out.push(None);
            continue;
        }
        let mut best: Option<(Real, usize)> = None;
        for (i, p) in people.iter().enumerate() {
            let gap = ((p.pos - r.pos).norm() - r.radius).max(0.0);
            if gap < params.personal_radius && best.is_none_or(|(g, _)| gap < g) {
                best = Some((gap, i));
            }
        }
        out.push(best.map(|(_, i)| groups.labels[i]));
    }
    Ok(out)
}
