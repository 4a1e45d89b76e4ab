//! ORCA as the robots run it among people: one batched [`Orca::compute`] per control step for
//! the robots in ORCA mode. Every robot is an agent; the robots computing ORCA this step take
//! their share of the avoidance (reciprocal), the others and the people do not (a person does
//! not run ORCA, so the robot takes the whole avoidance: van den Berg et al. 2011 with
//! alpha = 1). The static geometry comes in as obstacle edges ([`ObstacleSet`]).

use crate::control::orca::{ObstacleSet, Orca, OrcaAgent};
use crate::math::Vec2;

/// Added to every radius ORCA sees (metres): ORCA lets bodies touch, the physics counts a touch.
pub const ORCA_MARGIN: f64 = 0.08;

/// Speed bound of a person as an ORCA agent (m/s).
const PERSON_MAX_SPEED: f64 = 2.5;

/// The radius (m) of a person's disc as ORCA sees it: the body `radius`, at least `intimate`
/// minus a robot's typical radius (0.24 m) so that the robot stays out of the intimate zone (0 for
/// the body alone), plus [`ORCA_MARGIN`]. A robot's centre is kept this far plus its own radius
/// plus [`ORCA_MARGIN`] from the person's centre.
pub fn person_disc(radius: f64, intimate: f64) -> f64 {
    radius.max(intimate - 0.24) + ORCA_MARGIN
}

/// Agent ids of the people start here (robots are numbered by index below it).
const PERSON_ID_BASE: u64 = 1_000_000;

/// A robot as ORCA sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrcaRobot {
    /// Position (m).
    pub pos: Vec2,
    /// The command it executed last (world frame, m/s).
    pub vel: Vec2,
    /// Radius (m).
    pub radius: f64,
    /// Maximum speed (m/s).
    pub max_speed: f64,
}

/// The people as ORCA sees them: positions (m), velocities (m/s) and radii (m), one entry per
/// person.
#[derive(Clone, Copy, Debug)]
pub struct OrcaPeople<'a> {
    /// Positions (m).
    pub pos: &'a [Vec2],
    /// Velocities (m/s).
    pub vel: &'a [Vec2],
    /// Radii (m).
    pub radius: &'a [f64],
    /// Radius of the intimate zone (m): a person's disc is at least this minus a robot's
    /// typical radius (0.24 m), so the robot stays out of the zone; 0 for the body radius alone
    /// (the non-social `astar_orca` baseline).
    pub intimate: f64,
}

/// ORCA for the robots in `active` (indices into `robots`). Each active robot heads for its
/// `partial_goals` entry at the speed in its `desired` entry (what the path follower wanted, so
/// it brakes at the end of the path), and its `desired` entry is replaced by ORCA's velocity;
/// robots not active keep their executed command as preferred velocity. `step` seeds ORCA's
/// deterministic perturbation. If ORCA reports an input error, `desired` is left unchanged.
#[allow(clippy::too_many_arguments)]
pub fn orca_among_people(
    orca: &mut Orca,
    obstacles: &ObstacleSet,
    robots: &[OrcaRobot],
    people: OrcaPeople<'_>,
    active: &[usize],
    partial_goals: &[Vec2],
    desired: &mut [Vec2],
    dt: f64,
    step: u64,
) {
    let mut agents: Vec<OrcaAgent> = Vec::with_capacity(robots.len() + people.pos.len());
    for (j, rb) in robots.iter().enumerate() {
        let pref = if active.contains(&j) {
            let to = partial_goals[j] - rb.pos;
            let speed = desired[j].norm().min(rb.max_speed);
            if to.norm() > 1e-9 { to * (speed / to.norm()) } else { Vec2::zeros() }
        } else {
            rb.vel
        };
        agents.push(OrcaAgent {
            pos: rb.pos,
            vel: rb.vel,
            pref_vel: pref,
            radius: rb.radius + ORCA_MARGIN,
            max_speed: rb.max_speed,
            // Only robots computing ORCA this step take their share of the avoidance.
            reciprocal: active.contains(&j),
            id: j as u64,
        });
    }
    for k in 0..people.pos.len() {
        agents.push(OrcaAgent {
            pos: people.pos[k],
            vel: people.vel[k],
            pref_vel: people.vel[k],
            radius: person_disc(people.radius[k], people.intimate),
            max_speed: PERSON_MAX_SPEED,
            reciprocal: false,
            id: PERSON_ID_BASE + k as u64,
        });
    }
    let mut out = vec![Vec2::zeros(); agents.len()];
    if orca.compute(&agents, active, obstacles, dt, step, &mut out).is_ok() {
        for &i in active {
            desired[i] = out[i];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::orca::OrcaParams;

    #[test]
    fn a_robot_heading_at_a_person_turns_aside_and_others_are_untouched() {
        let mut orca = Orca::new(OrcaParams::default()).expect("valid params");
        let robot =
            |x: f64| OrcaRobot { pos: Vec2::new(x, 0.0), vel: Vec2::zeros(), radius: 0.24, max_speed: 0.55 };
        let robots = [robot(0.0), robot(-5.0)];
        let people =
            OrcaPeople { pos: &[Vec2::new(1.0, 0.0)], vel: &[Vec2::zeros()], radius: &[0.2], intimate: 0.45 };
        let goals = [Vec2::new(3.0, 0.0), Vec2::new(-8.0, 0.0)];
        let mut desired = [Vec2::new(0.55, 0.0), Vec2::new(0.3, 0.0)];
        orca_among_people(
            &mut orca,
            &ObstacleSet::empty(),
            &robots,
            people,
            &[0],
            &goals,
            &mut desired,
            0.1,
            0,
        );
        assert!(desired[0].norm() <= 0.55 + 1e-12);
        assert!(desired[0].x < 0.55, "the robot does not drive on into the person: {:?}", desired[0]);
        assert_eq!(desired[1], Vec2::new(0.3, 0.0));
    }
}
