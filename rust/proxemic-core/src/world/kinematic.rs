//! The world driven kinematically from outside, without physics or the social force: the
//! CrowdNav protocol ([`super::crowdnav`]) sets the robot's and the people's states every step and
//! asks for the robot's command, so every built-in planner, the `learned` policy and a user's
//! policy (through the env's observation) drive the robot in CrowdNav's kinematic episodes.
//!
//! A step is two calls: [`World::kinematic_observe`] takes the states of the instant, builds the
//! observation and runs the built-in planners; [`World::kinematic_command`] returns the robot's
//! command, the planner's or (given an action) a user's, limited as [`World::command`] limits it.
//! Nothing is recorded: the robots' outcomes stay running and the metrics are the caller's.

use super::World;
use crate::error::{CoreError, Result};
use crate::math::{Vec2, wrap_angle};

/// A robot's state set from outside: pose `(x, y, theta)` (m, rad) and world-frame velocity
/// (m/s, rad/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KinematicRobot {
    /// Position and heading (m, m, rad).
    pub pose: [f64; 3],
    /// World-frame linear velocity (m/s).
    pub velocity: Vec2,
    /// Angular velocity (rad/s).
    pub wz: f64,
}

impl World {
    /// Sets the one robot's state and every person's `(position, velocity)` (scenario order) at
    /// the next instant (`advance`: one control step after the last call; false right after
    /// [`World::reset`], the same instant), then builds the observation and runs the built-in
    /// planners into `out` (one row of [`super::Layout::stride`] values). The robot's executed
    /// command becomes its velocity (the command is applied instantly). A person's heading turns
    /// to its velocity when it moves.
    ///
    /// # Errors
    /// [`CoreError::Input`] before the first reset, for a world of more than one robot, for a
    /// number of people other than the scenario's, for non-finite states or an `out` of the
    /// wrong size.
    pub fn kinematic_observe(
        &mut self,
        robot: KinematicRobot,
        people: &[(Vec2, Vec2)],
        advance: bool,
        out: &mut [f64],
    ) -> Result<()> {
        if !self.started {
            return Err(CoreError::input(
                "kinematic step",
                "a call after reset()",
                "a call before the first reset()",
            ));
        }
        if self.robots.len() != 1 {
            return Err(CoreError::input(
                "robots",
                "one robot (the kinematic protocol drives one)",
                format!("{} robots", self.robots.len()),
            ));
        }
        if out.len() != self.layout.stride {
            return Err(CoreError::input(
                "out",
                format!("{} values", self.layout.stride),
                format!("{} values", out.len()),
            ));
        }
        if people.len() != self.crowd.len() {
            return Err(CoreError::input(
                "people",
                format!("{} people (the scenario's)", self.crowd.len()),
                format!("{} people", people.len()),
            ));
        }
        let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
        if !robot.pose.iter().all(|v| v.is_finite()) || !finite(robot.velocity) || !robot.wz.is_finite() {
            return Err(CoreError::input("robot", "a finite pose and velocity", format!("{robot:?}")));
        }
        if let Some(k) = people.iter().position(|(p, v)| !finite(*p) || !finite(*v)) {
            return Err(CoreError::input(
                format!("people[{k}]"),
                "a finite position and velocity",
                format!("{:?}", people[k]),
            ));
        }
        let rb = &mut self.robots[0];
        rb.pose = [robot.pose[0], robot.pose[1], wrap_angle(robot.pose[2])];
        rb.velocity = robot.velocity;
        rb.wz = robot.wz;
        rb.exec_v = robot.velocity;
        rb.exec_wz = robot.wz;
        rb.user_command = false;
        for (k, &(p, v)) in people.iter().enumerate() {
            self.crowd.pos[k] = p;
            self.crowd.vel[k] = v;
            if v.norm() > 1e-9 {
                self.crowd.heading[k] = v.y.atan2(v.x);
            }
        }
        if advance {
            self.steps += 1;
        }
        self.observe_all(out);
        self.plan_all(out);
        Ok(())
    }

    /// The robot's world-frame command `(v, wz)` (m/s, rad/s) after [`World::kinematic_observe`]:
    /// its built-in planner's, or with `action` (3 normalised robot-frame values in [-1, 1], as
    /// the env's action space) a user's, limited as [`World::command`] limits it.
    ///
    /// # Errors
    /// [`CoreError::Input`] for an action that is not 3 finite numbers, or before a reset.
    pub fn kinematic_command(&mut self, action: Option<[f64; 3]>, out: &mut [f64]) -> Result<(Vec2, f64)> {
        if let Some(a) = action {
            if !a.iter().all(|v| v.is_finite()) {
                return Err(CoreError::input(
                    "action",
                    "3 finite numbers in [-1, 1] (vx, vy, wz normalised)",
                    format!("{a:?}"),
                ));
            }
            self.command(&a, out)?;
        }
        let rb = self.robots.first().ok_or_else(|| {
            CoreError::input("kinematic step", "a call after reset()", "a call before the first reset()")
        })?;
        Ok((rb.proposed_v, rb.proposed_wz))
    }
}
