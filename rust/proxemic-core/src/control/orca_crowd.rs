//! ORCA as the robots run it among people: one batched [`Orca::compute`] per control step for
//! the robots in ORCA mode. Every robot is an agent; the robots computing ORCA this step take
//! their share of the avoidance (reciprocal), the others and the people do not (a person does
//! not run ORCA, so the robot takes the whole avoidance: van den Berg et al. 2011 with
//! alpha = 1). The static geometry comes in as obstacle edges ([`ObstacleSet`]).

use crate::control::orca::nonholonomic::{NhParams, TrackableSet};
use crate::control::orca::{Line, ObstacleSet, Orca, OrcaAgent};
use crate::math::Vec2;

/// NH-ORCA's constants for the differential-drive robots ([`crate::control::orca::nonholonomic`]):
/// a tracking error `E` of 0.02 m (chosen on the tuning split, see docs/choices.md) and a settle
/// time `T` of 0.4 s, the time constant of the heading policy (1 /
/// [`crate::control::FollowerParams::heading_gain`], 2.5 /s).
pub const NH_PARAMS: NhParams = NhParams { tracking_error: 0.02, settle_time: 0.4 };

/// A differential-drive robot's state as NH-ORCA needs it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Unicycle<'a> {
    /// Heading (rad).
    pub heading: f64,
    /// The velocities it can track (made once per robot with [`NH_PARAMS`]).
    pub set: &'a TrackableSet,
}

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
pub struct OrcaRobot<'a> {
    /// Position (m).
    pub pos: Vec2,
    /// The command it executed last (world frame, m/s).
    pub vel: Vec2,
    /// Radius (m).
    pub radius: f64,
    /// Maximum speed (m/s).
    pub max_speed: f64,
    /// `Some` for a robot running NH-ORCA (a differential-drive `astar_orca` robot, [`NH_PARAMS`]):
    /// its radius enlarged by the tracking error and, when it computes ORCA, its velocity kept
    /// within those it can track.
    pub unicycle: Option<Unicycle<'a>>,
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
/// deterministic perturbation. If ORCA reports an input error, `desired` is left unchanged. A
/// robot with [`OrcaRobot::unicycle`] set runs NH-ORCA: its ORCA velocity is one it can track
/// within [`NH_PARAMS`]'s error, which its caller turns into a command with
/// [`crate::control::orca::nonholonomic::track`].
#[allow(clippy::too_many_arguments)]
pub fn orca_among_people(
    orca: &mut Orca,
    obstacles: &ObstacleSet,
    robots: &[OrcaRobot<'_>],
    people: OrcaPeople<'_>,
    active: &[usize],
    partial_goals: &[Vec2],
    desired: &mut [Vec2],
    dt: f64,
    step: u64,
) {
    let mut agents: Vec<OrcaAgent> = Vec::with_capacity(robots.len() + people.pos.len());
    let mut within: Vec<Vec<Line>> = Vec::new();
    for (j, rb) in robots.iter().enumerate() {
        if let (Some(u), true) = (rb.unicycle, active.contains(&j)) {
            within.resize(j + 1, Vec::new());
            u.set.lines(u.heading, &mut within[j]);
        }
        let enlarged = if rb.unicycle.is_some() { NH_PARAMS.tracking_error } else { 0.0 };
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
            radius: rb.radius + ORCA_MARGIN + enlarged,
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
    if orca.compute_within(&agents, active, obstacles, dt, step, &within, &mut out).is_ok() {
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
        let robot = |x: f64| OrcaRobot {
            pos: Vec2::new(x, 0.0),
            vel: Vec2::zeros(),
            radius: 0.24,
            max_speed: 0.55,
            unicycle: None,
        };
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

    /// ORCA for robot 0 among `robots`, no people, no walls.
    fn robot_0_among_robots(orca: &mut Orca, robots: &[OrcaRobot<'_>], goals: &[Vec2], desired: &mut [Vec2]) {
        let none = OrcaPeople { pos: &[], vel: &[], radius: &[], intimate: 0.0 };
        orca_among_people(orca, &ObstacleSet::empty(), robots, none, &[0], goals, desired, 0.1, 0);
    }

    #[test]
    fn a_differential_robot_gets_a_velocity_it_can_track_and_a_body_enlarged_by_the_error() {
        let set = TrackableSet::new(0.55, 2.0, NH_PARAMS);
        use crate::control::orca::nonholonomic::max_tracked_speed;
        let params = OrcaParams { perturbation: 0.0, ..OrcaParams::default() };
        let mut orca = Orca::new(params).expect("valid params");
        // Facing +x, its goal straight to its left: the holonomic robot goes left at full speed,
        // the differential one only as fast as it can track a quarter turn within E.
        let goals = [Vec2::new(0.0, 3.0)];
        let mut speeds = Vec::new();
        for unicycle in [None, Some(Unicycle { heading: 0.0, set: &set })] {
            let robots = [OrcaRobot {
                pos: Vec2::zeros(),
                vel: Vec2::zeros(),
                radius: 0.24,
                max_speed: 0.55,
                unicycle,
            }];
            let mut desired = [Vec2::new(0.0, 0.55)];
            robot_0_among_robots(&mut orca, &robots, &goals, &mut desired);
            speeds.push(desired[0]);
        }
        assert!((speeds[0].norm() - 0.55).abs() < 1e-9, "holonomic: {:?}", speeds[0]);
        let u = speeds[1];
        let angle = u.y.atan2(u.x);
        assert!(u.norm() <= max_tracked_speed(angle, 0.55, 2.0, NH_PARAMS) + 1e-9, "untrackable {u:?}");
        assert!(u.norm() < 0.45 && u.y > 0.0, "slower, still toward the goal: {u:?}");
        // The other robot sees the differential one enlarged by E: a holonomic robot 0.7 m away,
        // heading at it, is stopped sooner than by a holonomic neighbour.
        let pair = |unicycle| {
            let robots = [
                OrcaRobot {
                    pos: Vec2::zeros(),
                    vel: Vec2::zeros(),
                    radius: 0.24,
                    max_speed: 0.55,
                    unicycle: None,
                },
                OrcaRobot {
                    pos: Vec2::new(0.7, 0.0),
                    vel: Vec2::zeros(),
                    radius: 0.24,
                    max_speed: 0.55,
                    unicycle,
                },
            ];
            let mut desired = [Vec2::new(0.55, 0.0), Vec2::zeros()];
            let goals = [Vec2::new(5.0, 0.0), Vec2::new(0.7, 0.0)];
            let mut orca =
                Orca::new(OrcaParams { perturbation: 0.0, ..OrcaParams::default() }).expect("valid");
            robot_0_among_robots(&mut orca, &robots, &goals, &mut desired);
            desired[0].x
        };
        assert!(pair(Some(Unicycle { heading: 0.0, set: &set })) < pair(None));
    }
}
