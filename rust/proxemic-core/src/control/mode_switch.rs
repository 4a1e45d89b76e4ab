//! The mode switch of Daza et al. 2021, Algorithm 1, and the local planners a robot can run.
//!
//! Every control step a robot on the `social` planner looks at the mobile objects around it:
//! robots broadcast identities, people have none (Algorithm 1, lines 3-4).
//! - Only robots around, and one of them in the robot's collision cone (a collision within the
//!   cone's time horizon at the current velocities): **ORCA** toward a partial goal on the global
//!   path (lines 5-11); robots reciprocate.
//! - People around (or a robot that joined a human group, which counts as a person, lines 17-19):
//!   **Social Momentum** toward a partial goal on the global path (lines 12-19), with each person
//!   as an agent whose radius keeps the robot out of their intimate zone, and each group as one
//!   heavier individual covering its o-space, so the robot neither crosses a conversation nor
//!   brushes a member. When every sample collides the robot stops and waits.
//! - Otherwise: follow the global path (lines 10, 21, 24); the path is retaken as soon as
//!   nothing is in the way.
//!
//! Whatever the mode, the command then goes through [`crate::control::Limits::apply`], so a mode
//! switch never makes the command jump beyond the acceleration limits.

use crate::control::orca::nonholonomic::TrackingBound;
use crate::control::social_momentum::{Agent, SocialMomentumParams, social_momentum_shaped};
use crate::control::yielding::YieldParams;
use crate::control::{Limits, clamp_norm};
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;

/// What the mode switch decided for one step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Follow the global path.
    FollowPath,
    /// ORCA among robots (Algorithm 1 lines 5-8).
    Orca,
    /// Social Momentum near people and groups (lines 12-19).
    SocialMomentum,
    /// Every Social Momentum sample collided: stop and wait.
    Wait,
}

impl Mode {
    /// A small integer code (for observations and logs): 0 follow, 1 ORCA, 2 SM, 3 wait.
    pub fn code(self) -> u8 {
        match self {
            Mode::FollowPath => 0,
            Mode::Orca => 1,
            Mode::SocialMomentum => 2,
            Mode::Wait => 3,
        }
    }
}

/// Parameters of the mode switch (every value documented with its default).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeSwitchParams {
    /// People within this centre distance switch to Social Momentum (m); default 3.5: with the
    /// comfort term's 3 s horizon, a person walking at the robot is seen before their personal
    /// zone is reached (3.0 left it too late in the museum's corridor).
    pub people_range: f64,
    /// Robots within this distance are checked against the collision cone (m); default 4.0.
    pub robot_range: f64,
    /// Time horizon of the collision cone (s); default 3.0.
    pub cone_horizon: f64,
    /// Distance along the global path to the partial goal (m); default 1.5.
    pub partial_goal: f64,
    /// Weight of a group member in the momentum term (1 for a person alone); default 2.0.
    pub group_weight: f64,
    /// Social Momentum parameters.
    pub sm: SocialMomentumParams,
    /// Predictive yielding, the `social` planner's last word on every command
    /// ([`crate::control::yielding`]).
    pub yielding: YieldParams,
}

impl Default for ModeSwitchParams {
    fn default() -> Self {
        ModeSwitchParams {
            people_range: 3.5,
            robot_range: 4.0,
            cone_horizon: 3.0,
            partial_goal: 1.5,
            group_weight: 2.0,
            sm: SocialMomentumParams::default(),
            yielding: YieldParams::default(),
        }
    }
}

/// A person (or a robot taking part in a human interaction) as the controller sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Person {
    /// Position (m).
    pub pos: Vec2,
    /// Velocity (m/s).
    pub vel: Vec2,
    /// Radius the robot must keep its centre clear of (m): the person's intimate radius minus
    /// the robot's own radius, or the body radius, whichever is larger.
    pub keep_out: f64,
    /// Momentum weight (1 alone, heavier in a group).
    pub weight: f64,
    /// Radius of the comfort zone the robot's centre prefers to stay out of (m, centre
    /// distance): Hall's personal zone for a person, 0 for none (see
    /// [`crate::control::social_momentum::Agent::comfort`]).
    pub comfort: f64,
}

/// Another robot as the controller sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OtherRobot {
    /// Position (m).
    pub pos: Vec2,
    /// Velocity (m/s).
    pub vel: Vec2,
    /// Radius (m).
    pub radius: f64,
}

/// Whether two discs moving at constant velocities touch within `horizon` seconds (the
/// collision cone of the relative velocity).
pub fn in_collision_cone(p: Vec2, v: Vec2, r: f64, q: Vec2, u: Vec2, s: f64, horizon: f64) -> bool {
    let d = q - p;
    let w = v - u;
    let rr = r + s;
    if d.norm_squared() <= rr * rr {
        return true;
    }
    let ww = w.norm_squared();
    if ww < 1e-12 {
        return false;
    }
    let t = (d.dot(&w) / ww).clamp(0.0, horizon);
    (d - w * t).norm_squared() <= rr * rr
}

/// Algorithm 1's choice for one robot: the mode, given who is around.
pub fn choose_mode(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    people: &[Person],
    robots: &[OtherRobot],
    params: &ModeSwitchParams,
) -> Mode {
    let near = |q: Vec2, range: f64| (q - pos).norm() <= range;
    if people.iter().any(|p| near(p.pos, params.people_range)) {
        return Mode::SocialMomentum;
    }
    let cone = robots.iter().any(|o| {
        near(o.pos, params.robot_range)
            && in_collision_cone(pos, vel, radius, o.pos, o.vel, o.radius, params.cone_horizon)
    });
    if cone { Mode::Orca } else { Mode::FollowPath }
}

/// Social Momentum toward `partial_goal` among `people` (and the other robots, as obstacles that
/// do not take part in the momentum term). Returns the desired world velocity and the mode
/// (`SocialMomentum`, or `Wait` with a zero velocity when every sample collides or stopping is
/// the only safe choice). `unicycle` is `Some` for a differential-drive robot: Social Momentum
/// under its kinematic constraint ([`social_momentum_shaped`]).
#[allow(clippy::too_many_arguments)]
pub fn social_momentum_step(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    partial_goal: Vec2,
    people: &[Person],
    robots: &[OtherRobot],
    geometry: Option<&StaticGeometry>,
    limits: &Limits,
    dt: f64,
    params: &ModeSwitchParams,
    unicycle: Option<TrackingBound>,
) -> (Vec2, Mode) {
    let mut agents: Vec<Agent> = Vec::with_capacity(people.len() + robots.len());
    for p in people {
        agents.push(Agent {
            pos: p.pos,
            vel: p.vel,
            radius: p.keep_out,
            weight: p.weight,
            comfort: p.comfort,
        });
    }
    for o in robots {
        agents.push(Agent { pos: o.pos, vel: o.vel, radius: o.radius, weight: 0.0, comfort: 0.0 });
    }
    match social_momentum_shaped(
        pos,
        vel,
        radius,
        partial_goal,
        &agents,
        &[],
        geometry,
        limits,
        dt,
        &params.sm,
        unicycle,
    ) {
        // Standing still as the only safe choice is waiting, too.
        Some(v) if v.norm() > 1e-6 => (clamp_norm(v, limits.max_speed), Mode::SocialMomentum),
        _ => (Vec2::zeros(), Mode::Wait),
    }
}

/// The local planner a built-in planner runs on top of its global path.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LocalPlanner {
    /// Algorithm 1's switch ([`choose_mode`]): Social Momentum among people, ORCA against a
    /// robot in the collision cone, else the global path (the `social` planner).
    ModeSwitch,
    /// Social Momentum while people are within [`ModeSwitchParams::people_range`], else the
    /// global path (the `social_momentum` planner).
    SocialMomentum,
    /// ORCA every step (the `astar_orca` planner).
    Orca,
}

/// What `planner` does this step for a robot at `pos` moving at `vel` (m/s) whose mode was
/// `previous`, among `people` and the other `robots`. With [`LocalPlanner::ModeSwitch`], a
/// robot avoiding robots keeps ORCA while any robot is still within
/// [`ModeSwitchParams::robot_range`] (hysteresis: leaving ORCA on a clear cone would steer
/// straight back into the conflict).
#[allow(clippy::too_many_arguments)]
pub fn select_mode(
    planner: LocalPlanner,
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    previous: Mode,
    people: &[Person],
    robots: &[OtherRobot],
    params: &ModeSwitchParams,
) -> Mode {
    match planner {
        LocalPlanner::Orca => Mode::Orca,
        LocalPlanner::SocialMomentum => {
            let near = people.iter().any(|q| (q.pos - pos).norm() <= params.people_range);
            if near { Mode::SocialMomentum } else { Mode::FollowPath }
        }
        LocalPlanner::ModeSwitch => {
            let m = choose_mode(pos, vel, radius, people, robots, params);
            let robots_near = robots.iter().any(|o| (o.pos - pos).norm() <= params.robot_range);
            if m == Mode::FollowPath && previous == Mode::Orca && robots_near { Mode::Orca } else { m }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collision_cone_head_on_and_parallel() {
        let (p, q) = (Vec2::zeros(), Vec2::new(4.0, 0.0));
        assert!(in_collision_cone(p, Vec2::new(0.5, 0.0), 0.24, q, Vec2::new(-0.5, 0.0), 0.24, 5.0));
        // too far ahead in time
        assert!(!in_collision_cone(p, Vec2::new(0.1, 0.0), 0.24, q, Vec2::zeros(), 0.24, 5.0));
        // parallel, 1 m apart
        assert!(!in_collision_cone(
            p,
            Vec2::new(0.5, 0.0),
            0.24,
            Vec2::new(0.0, 1.0),
            Vec2::new(0.5, 0.0),
            0.24,
            5.0
        ));
    }

    #[test]
    fn mode_switch_follows_algorithm_1() {
        let params = ModeSwitchParams::default();
        let v = Vec2::new(0.5, 0.0);
        let person = Person {
            pos: Vec2::new(2.0, 0.5),
            vel: Vec2::zeros(),
            keep_out: 0.21,
            weight: 1.0,
            comfort: 0.0,
        };
        let robot = OtherRobot { pos: Vec2::new(3.0, 0.0), vel: Vec2::new(-0.5, 0.0), radius: 0.24 };
        let far_robot = OtherRobot { pos: Vec2::new(3.0, 3.0), vel: Vec2::new(0.5, 0.0), radius: 0.24 };
        assert_eq!(choose_mode(Vec2::zeros(), v, 0.24, &[person], &[robot], &params), Mode::SocialMomentum);
        assert_eq!(choose_mode(Vec2::zeros(), v, 0.24, &[], &[robot], &params), Mode::Orca);
        assert_eq!(choose_mode(Vec2::zeros(), v, 0.24, &[], &[far_robot], &params), Mode::FollowPath);
        assert_eq!(choose_mode(Vec2::zeros(), v, 0.24, &[], &[], &params), Mode::FollowPath);
    }

    #[test]
    fn mode_switch_keeps_orca_while_a_robot_is_near() {
        let params = ModeSwitchParams::default();
        let v = Vec2::new(0.5, 0.0);
        // Moving away from a robot 2 m behind: not in the cone, but within range.
        let behind = OtherRobot { pos: Vec2::new(-2.0, 0.0), vel: Vec2::zeros(), radius: 0.24 };
        let sel = |prev| {
            select_mode(LocalPlanner::ModeSwitch, Vec2::zeros(), v, 0.24, prev, &[], &[behind], &params)
        };
        assert_eq!(sel(Mode::FollowPath), Mode::FollowPath);
        assert_eq!(sel(Mode::Orca), Mode::Orca);
        let far = OtherRobot { pos: Vec2::new(-9.0, 0.0), ..behind };
        let sel_far =
            select_mode(LocalPlanner::ModeSwitch, Vec2::zeros(), v, 0.24, Mode::Orca, &[], &[far], &params);
        assert_eq!(sel_far, Mode::FollowPath);
        let alone =
            select_mode(LocalPlanner::SocialMomentum, Vec2::zeros(), v, 0.24, Mode::Orca, &[], &[], &params);
        assert_eq!(alone, Mode::FollowPath);
    }

    #[test]
    fn boxed_in_the_robot_waits() {
        let params = ModeSwitchParams::default();
        let ring: Vec<Person> = (0..8)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 8.0;
                Person {
                    pos: Vec2::new(a.cos(), a.sin()) * 0.56,
                    vel: Vec2::zeros(),
                    keep_out: 0.21,
                    weight: 1.0,
                    comfort: 0.0,
                }
            })
            .collect();
        let (v, mode) = social_momentum_step(
            Vec2::zeros(),
            Vec2::zeros(),
            0.24,
            Vec2::new(5.0, 0.0),
            &ring,
            &[],
            None,
            &Limits::PEPPER,
            0.1,
            &params,
            None,
        );
        assert_eq!(mode, Mode::Wait);
        assert_eq!(v, Vec2::zeros());
    }
}
