//! The CrowdNav protocol's episodes: CrowdNav's kinematic simulation of its scenes
//! ([`crate::scenario::generate::crowdnav`]) and its counting of outcomes, as its code does them
//! (`crowd_sim.py`'s `step` and `crowd_nav/utils/explorer.py`, read, not copied;
//! `docs/crowdnav.md`).
//!
//! One step of `dt` (0.25 s), from the state at time `t`:
//! 1. every person's velocity for the step: ORCA toward its goal ([`OrcaPeople`]), seeing the
//!    other people and, when the robot is visible, the robot;
//! 2. the robot's velocity for the step, from the same instant: `astar_orca` is CrowdNav's ORCA
//!    robot (ORCA toward the goal with CrowdNav's robot parameters, holonomic, preferred velocity
//!    capped at 1 m/s; in these open scenes the A* path is the straight line to the goal); every
//!    other built-in planner, and a user's policy, drives through the core's [`World`], set to the
//!    instant's robot and people ([`World::kinematic_observe`]): its command (or the policy's
//!    action on the env's observation), limited by the robot's limits with the acceleration
//!    [`INSTANT_ACCEL`], cut to 1 m/s, applied at once (holonomic, as CrowdNav's robot);
//!    with `drive=differential` the robot is CrowdNav's unicycle (below);
//! 3. the swept closest distance to each person: the distance from the robot to the segment the
//!    person sweeps relative to the robot over the step, using the person's velocity *of the last
//!    step* and the robot's new one, minus both radii; below 0 is a collision (the scan stops at
//!    the first), and `dmin` is the least over the people scanned;
//! 4. the robot reaches its goal when its position after the step is within its radius of it;
//! 5. the step's outcome, first that holds: timeout when `t >= time_limit - 1 s` (CrowdNav
//!    compares with `time_limit - 1`), collision, goal reached, discomfort when `dmin` < 0.2 m
//!    (counted, the episode goes on); people's contacts with each other are not counted;
//! 6. everyone moves by its velocity times `dt`, and `t += dt` (also on the last step).
//!
//! **The unicycle robot** (`drive=differential`, CrowdNav's `kinematics = 'unicycle'`): its action
//! is a speed `v` and a rotation `r` for the step; it turns first, then moves `v dt` along its new
//! heading (`agent.py`'s `compute_position` and `step`), and the swept distance of step 3 uses that
//! post-turn velocity (`crowd_sim.py`'s unicycle branch). CrowdNav's simulator takes any `r`; its
//! unicycle policies choose `r` in `[-π/4, π/4]` (`cadrl.py`'s action space), and so does the
//! robot here ([`MAX_TURN`]). CrowdNav's ORCA robot is holonomic only (`orca.py` has no unicycle
//! mode); `astar_orca`'s unicycle turns toward ORCA's velocity `u` by at most [`MAX_TURN`], then
//! moves at `u`'s projection on its new heading, never backwards ([`unicycle_step`]). The world's
//! planners and a user's policy drive a differential robot of the world (the robot's turn rate at
//! most `MAX_TURN / dt`, reached in one step): their forward speed and turn rate become `v` and
//! `r = wz dt`.
//!
//! The summary ([`CrowdNavSummary`]) counts as CrowdNav's explorer does: rates over episodes, the
//! mean navigation time over successes (the time limit when there is none), and the discomfort
//! frequency: discomfort steps over `sum(episode times) / dt`, where a timeout's time is the time
//! limit.

use serde::Serialize;

use super::World;
use super::kinematic::KinematicRobot;
use crate::control::{Drive, clamp_norm};
use crate::error::{CoreError, Result};
use crate::geom::distance_point_segment;
use crate::math::{Vec2, wrap_angle};
use crate::pedestrians::orca::{OrcaBody, OrcaPeople};
use crate::scenario::PlannerKind;
use crate::scenario::generate::crowdnav::{self, DISCOMFORT_DIST, Spec, TIME_LIMIT, TIME_STEP, V_PREF};
use crate::world::PERSON_OUT;

/// The planners the protocol's kinematic episodes run: every built-in planner. `astar_orca` is
/// CrowdNav's ORCA robot (its own solver call, as CrowdNav's `ORCA` policy); the others drive
/// through the core's [`World`] set kinematically every step ([`super::kinematic`]).
pub const PLANNERS: &[&str] = PlannerKind::NAMES;

/// The robot's linear acceleration limit in the protocol's worlds (m/s²): any velocity within
/// the 1 m/s cap is reached in one step of 0.25 s (`2 × 1 m/s / 0.25 s`), so a planner's desired
/// velocity is applied at once, as CrowdNav applies its robot's action (holonomic, no dynamics).
pub const INSTANT_ACCEL: f64 = 2.0 * V_PREF / TIME_STEP;

/// The unicycle robot's largest turn in one step (rad): π/4, the bound of CrowdNav's unicycle
/// policies' rotations (`cadrl.py`'s action space; its simulator sets none).
pub const MAX_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// The unicycle robot's angular acceleration limit in the world (rad/s²): any turn rate within
/// `MAX_TURN / dt` is reached in one step (`2 × (MAX_TURN / dt) / dt`), as CrowdNav applies its
/// robot's rotation.
pub const INSTANT_ANGULAR_ACCEL: f64 = 2.0 * MAX_TURN / (TIME_STEP * TIME_STEP);

/// The robot's motion over one step: the velocity it moves at (m/s, world frame) and its turn
/// (rad), taken before it moves (CrowdNav's unicycle turns, then moves; a holonomic robot's
/// motion does not depend on its heading).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Motion {
    vel: Vec2,
    turn: f64,
}

impl Motion {
    /// A holonomic robot's motion: velocity `vel`, turning at `wz` (rad/s).
    fn holonomic(vel: Vec2, wz: f64) -> Self {
        Motion { vel, turn: wz * TIME_STEP }
    }

    /// The unicycle's motion from heading `theta` (rad): turn `r` (rad), then forward speed `v`
    /// (m/s; negative: reverse) along the new heading.
    fn unicycle(v: f64, r: f64, theta: f64) -> Self {
        let heading = theta + r;
        Motion { vel: Vec2::new(heading.cos(), heading.sin()) * v, turn: r }
    }
}

/// `astar_orca`'s unicycle step from heading `theta` (rad) toward ORCA's holonomic velocity `u`
/// (m/s): the turn toward `u`'s direction, at most [`MAX_TURN`] either way (none when `u` is 0),
/// then the forward speed `max(0, u · h')` with `h'` the new heading; returns `(v, r)`.
pub fn unicycle_step(u: Vec2, theta: f64) -> (f64, f64) {
    if !(u.x.is_finite() && u.y.is_finite()) || u.norm() < 1e-12 {
        return (0.0, 0.0);
    }
    let r = wrap_angle(u.y.atan2(u.x) - theta).clamp(-MAX_TURN, MAX_TURN);
    let heading = theta + r;
    (u.dot(&Vec2::new(heading.cos(), heading.sin())).max(0.0), r)
}

/// How a CrowdNav episode ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CrowdNavOutcome {
    /// The robot reached its goal (CrowdNav's `ReachGoal`).
    Success,
    /// The swept distance to a person fell below 0 (`Collision`).
    Collision,
    /// The time ran out (`Timeout`).
    Timeout,
}

/// One episode's record.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CrowdNavEpisode {
    /// The scene's spec.
    pub spec: String,
    /// How it ended.
    pub outcome: CrowdNavOutcome,
    /// The time at the end (s): after the last step for a success or collision, the time limit for
    /// a timeout (as the explorer records it).
    pub time: f64,
    /// Steps that ended in discomfort (`dmin` < 0.2 m, not the last step).
    pub discomfort_steps: usize,
    /// Sum of `dmin` over those steps (m).
    pub discomfort_dist_sum: f64,
    /// Least swept distance over the episode (m, body edge to body edge; negative at a collision).
    pub min_dist: f64,
}

/// The state of an episode at the start of a step, as the robot's driver sees it.
struct Instant<'a> {
    /// Steps taken so far.
    step: usize,
    /// The robot (its velocity is its last action).
    robot: &'a OrcaBody,
    /// Its heading (rad) and angular velocity (rad/s).
    theta: f64,
    wz: f64,
    /// The people (each one's velocity is its last action).
    humans: &'a [OrcaBody],
}

/// Runs the episode of a `crowdnav/...` spec with the built-in `planner` (one of [`PLANNERS`]).
/// Errors: [`CoreError::Scenario`] for a bad spec, [`CoreError::Input`] naming `planner` when it
/// is not one of [`PLANNERS`], the world's errors for a scene it cannot build.
pub fn run_episode(spec: &str, planner: &str) -> Result<CrowdNavEpisode> {
    let kind = PlannerKind::parse(planner)
        .ok_or_else(|| CoreError::input("planner", format!("one of {PLANNERS:?}"), format!("{planner:?}")))?;
    let s: Spec = crowdnav::parse_spec(spec)?;
    let people = crowdnav::draw_people(&s)?;
    if kind == PlannerKind::AstarOrca {
        let mut orca = OrcaPeople::new()?;
        let mut bodies: Vec<OrcaBody> = Vec::with_capacity(people.len() + 1);
        return simulate(s.text(), &people, s.visible, |now| {
            // CrowdNav's ORCA robot: every person a reciprocal neighbour.
            bodies.clear();
            bodies.push(*now.robot);
            bodies.extend_from_slice(now.humans);
            let u = orca.velocities(&bodies, &[0], TIME_STEP)?[0];
            Ok(match s.drive {
                Drive::Holonomic => Motion::holonomic(u, 0.0),
                Drive::Differential => {
                    let (v, r) = unicycle_step(u, now.theta);
                    Motion::unicycle(v, r, now.theta)
                }
            })
        });
    }
    let mut driver = WorldDriver::new(&s, kind, true)?;
    simulate(s.text(), &people, s.visible, |now| driver.drive(&now, None::<&mut NoPolicy>))
}

/// No user policy (the built-in planner drives).
type NoPolicy = fn(&[f64]) -> Result<[f64; 3]>;

/// Runs the episode of a `crowdnav/...` spec driven by a user's policy: `act` gets the robot's
/// row of the world's output ([`super::Layout`]; the observation in its `obs_*` sections, as the
/// env builds it) and returns a normalised action (vx, vy, wz in [-1, 1], robot frame), limited
/// as the env limits it. Errors: as [`run_episode`], and `act`'s.
pub fn run_policy_episode<E: From<CoreError>>(
    spec: &str,
    mut act: impl FnMut(&[f64]) -> std::result::Result<[f64; 3], E>,
) -> std::result::Result<CrowdNavEpisode, E> {
    let s: Spec = crowdnav::parse_spec(spec)?;
    let people = crowdnav::draw_people(&s)?;
    let mut driver = WorldDriver::new(&s, PlannerKind::Astar, false)?;
    simulate(s.text(), &people, s.visible, |now| driver.drive(&now, Some(&mut act)))
}

/// A world of the scene whose robot is driven kinematically ([`World::kinematic_observe`]).
struct WorldDriver {
    world: World,
    drive: Drive,
    out: Vec<f64>,
    people: Vec<(Vec2, Vec2)>,
}

impl WorldDriver {
    /// The world of spec `s` with the robot on `planner` (its planner off without `planning`: a
    /// user's policy drives), the acceleration limit [`INSTANT_ACCEL`] (a unicycle's turn rate at
    /// most [`MAX_TURN`] per step, reached at once), reset with the scene's seed.
    fn new(s: &Spec, planner: PlannerKind, planning: bool) -> Result<Self> {
        let mut scenario = crowdnav::build(s)?.scenario;
        for r in &mut scenario.robots {
            r.planner = planner;
            r.max_accel = INSTANT_ACCEL;
            if s.drive == Drive::Differential {
                r.max_angular_speed = MAX_TURN / TIME_STEP;
                r.max_angular_accel = INSTANT_ANGULAR_ACCEL;
            }
        }
        let mut world = World::new(scenario)?;
        if !planning {
            world.set_planning(&[false])?;
        }
        let mut out = vec![0.0; world.layout().stride];
        let mut people_out = vec![0.0; world.num_people() * PERSON_OUT];
        world.reset(s.seed, &mut out, &mut people_out)?;
        Ok(WorldDriver { world, drive: s.drive, out, people: Vec::new() })
    }

    /// The robot's motion for the step from `now`: the world set to `now`, then its planner's
    /// command or `act`'s action on the observation, the speed cut to CrowdNav's 1 m/s; a
    /// unicycle's forward speed and turn rate `wz` become its speed and its turn `wz dt`.
    fn drive<E: From<CoreError>>(
        &mut self,
        now: &Instant<'_>,
        act: Option<&mut impl FnMut(&[f64]) -> std::result::Result<[f64; 3], E>>,
    ) -> std::result::Result<Motion, E> {
        self.people.clear();
        self.people.extend(now.humans.iter().map(|h| (h.pos, h.vel)));
        let robot = KinematicRobot {
            pose: [now.robot.pos.x, now.robot.pos.y, now.theta],
            velocity: now.robot.vel,
            wz: now.wz,
        };
        self.world.kinematic_observe(robot, &self.people, now.step > 0, &mut self.out)?;
        let action = match act {
            Some(act) => Some(act(&self.out)?),
            None => None,
        };
        let (v, wz) = self.world.kinematic_command(action, &mut self.out)?;
        Ok(match self.drive {
            Drive::Holonomic => Motion::holonomic(clamp_norm(v, V_PREF), wz),
            Drive::Differential => {
                // The world's unicycle command is along the heading: its signed forward speed.
                let speed = v.dot(&Vec2::new(now.theta.cos(), now.theta.sin())).clamp(-V_PREF, V_PREF);
                Motion::unicycle(speed, (wz * TIME_STEP).clamp(-MAX_TURN, MAX_TURN), now.theta)
            }
        })
    }
}

/// The episode of the people `(start, goal)` and the robot from CrowdNav's start to its goal;
/// `visible`: the people see the robot. `drive` gives the robot's motion for each step.
fn simulate<E: From<CoreError>>(
    spec: String,
    people: &[([f64; 2], [f64; 2])],
    visible: bool,
    mut drive: impl FnMut(Instant<'_>) -> std::result::Result<Motion, E>,
) -> std::result::Result<CrowdNavEpisode, E> {
    let body = |pos: [f64; 2], goal: [f64; 2]| OrcaBody {
        pos: Vec2::new(pos[0], pos[1]),
        vel: Vec2::zeros(),
        goal: Vec2::new(goal[0], goal[1]),
        radius: crowdnav::RADIUS,
        v_pref: crowdnav::V_PREF,
    };
    let mut robot = body(crowdnav::ROBOT_START, crowdnav::ROBOT_GOAL);
    let mut theta = crowdnav::ROBOT_HEADING;
    let mut wz = 0.0;
    let mut humans: Vec<OrcaBody> = people.iter().map(|(p, g)| body(*p, *g)).collect();
    let mut orca = OrcaPeople::new()?;
    let n = humans.len();
    let everyone: Vec<usize> = (0..n).collect();
    let mut bodies: Vec<OrcaBody> = Vec::with_capacity(n + 1);
    let dt = TIME_STEP;
    let mut t = 0.0;
    let mut rec = CrowdNavEpisode {
        spec,
        outcome: CrowdNavOutcome::Timeout,
        time: TIME_LIMIT,
        discomfort_steps: 0,
        discomfort_dist_sum: 0.0,
        min_dist: f64::INFINITY,
    };
    for step in 0.. {
        // 1. The people's velocities: each sees the others and, if visible, the robot.
        bodies.clear();
        bodies.extend_from_slice(&humans);
        if visible {
            bodies.push(robot);
        }
        let human_vel = orca.velocities(&bodies, &everyone, dt)?;
        // 2. The robot's velocity, from the same instant.
        let Motion { vel: action, turn } =
            drive(Instant { step, robot: &robot, theta, wz, humans: &humans })?;
        // 3. Swept closest distance, with each person's velocity of the last step and the
        //    robot's velocity of this one (a unicycle's after its turn).
        let mut dmin = f64::INFINITY;
        let mut collision = false;
        for h in &humans {
            let p = h.pos - robot.pos;
            let e = p + (h.vel - action) * dt;
            let d = distance_point_segment(Vec2::zeros(), p, e) - h.radius - robot.radius;
            rec.min_dist = rec.min_dist.min(d);
            if d < 0.0 {
                collision = true;
                break;
            }
            dmin = dmin.min(d);
        }
        // 4-5. Goal, then the outcome in CrowdNav's order.
        let reached = (robot.pos + action * dt - robot.goal).norm() < robot.radius;
        let done = if t >= TIME_LIMIT - 1.0 {
            Some(CrowdNavOutcome::Timeout)
        } else if collision {
            Some(CrowdNavOutcome::Collision)
        } else if reached {
            Some(CrowdNavOutcome::Success)
        } else {
            if dmin < DISCOMFORT_DIST {
                rec.discomfort_steps += 1;
                rec.discomfort_dist_sum += dmin;
            }
            None
        };
        // 6. Move.
        robot.pos += action * dt;
        robot.vel = action;
        theta = wrap_angle(theta + turn);
        wz = turn / dt;
        for (h, v) in humans.iter_mut().zip(&human_vel) {
            h.pos += *v * dt;
            h.vel = *v;
        }
        t += dt;
        if let Some(outcome) = done {
            rec.outcome = outcome;
            rec.time = if outcome == CrowdNavOutcome::Timeout { TIME_LIMIT } else { t };
            return Ok(rec);
        }
    }
    unreachable!("the time limit ends every episode")
}

/// The figures CrowdNav's explorer prints, over a set of episodes.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CrowdNavSummary {
    /// Episodes.
    pub episodes: usize,
    /// Successes, collisions and timeouts.
    pub success: usize,
    /// Collisions.
    pub collision: usize,
    /// Timeouts.
    pub timeout: usize,
    /// Mean time of the successes (s); the time limit when there is none (CrowdNav's rule).
    pub mean_nav_time: f64,
    /// Discomfort steps over `sum(episode times) / dt` (a timeout counts the time limit).
    pub discomfort_frequency: f64,
    /// Mean `dmin` over the discomfort steps (m; 0 when there is none).
    pub mean_min_dist_in_discomfort: f64,
}

/// Summarises episodes as CrowdNav's explorer does.
pub fn summarize(episodes: &[CrowdNavEpisode]) -> CrowdNavSummary {
    let count = |o| episodes.iter().filter(|e| e.outcome == o).count();
    let success = count(CrowdNavOutcome::Success);
    let times: f64 = episodes.iter().filter(|e| e.outcome == CrowdNavOutcome::Success).map(|e| e.time).sum();
    let steps: f64 = episodes.iter().map(|e| e.time).sum::<f64>() / TIME_STEP;
    let danger: usize = episodes.iter().map(|e| e.discomfort_steps).sum();
    let danger_sum: f64 = episodes.iter().map(|e| e.discomfort_dist_sum).sum();
    CrowdNavSummary {
        episodes: episodes.len(),
        success,
        collision: count(CrowdNavOutcome::Collision),
        timeout: count(CrowdNavOutcome::Timeout),
        mean_nav_time: if success > 0 { times / success as f64 } else { TIME_LIMIT },
        discomfort_frequency: if steps > 0.0 { danger as f64 / steps } else { 0.0 },
        mean_min_dist_in_discomfort: if danger > 0 { danger_sum / danger as f64 } else { 0.0 },
    }
}

#[cfg(test)]
mod tests;
