//! The `daza2021` and `sousa2022` planners' per-step bookkeeping: what robot `i` sees this step,
//! handed to [`crate::control::daza2021`] (Daza et al. 2021 Algorithm 1, with Sousa et al. 2022's
//! Gaussians for `sousa2022`), which decides the mode and runs Social Momentum. ORCA's velocity
//! comes later, in one batch among the robots only ([`World::plan_all`]).

use super::World;
use crate::control::daza2021::{
    Daza2021Mode, Daza2021Params, MobileObject, PeopleSpaces, RobotState, daza2021_decide,
    daza2021_social_momentum,
};
use crate::control::mode_switch::Mode;
use crate::math::Vec2;

impl World {
    /// Robot `i`'s local step with the `daza2021` or `sousa2022` planner: its mode, with Social
    /// Momentum the new `desired` velocity, and the partial goal on its global path (written to
    /// `partial_goal`, for ORCA).
    ///
    /// - Line 1's path is the follower's path: plain A* for `daza2021` (re-planned with plain A*
    ///   only when the robot is pushed off it, as for every plain-A* planner); for `sousa2022`
    ///   the path on the social map of Sousa's Gaussians (Sousa 2022 §3.1, Fig. 3; re-planned on
    ///   the social planners' triggers, see [`crate::scenario::PlannerKind::Sousa2022`]).
    /// - Line 3's mobile objects: every person (no identity) and every other robot (its index as
    ///   identity), at their current positions and velocities; the robot's own preferred
    ///   velocity for the collision cone is the path follower's `desired`.
    /// - Line 13's groups: the perception's groups of two or more
    ///   ([`crate::perception::perceive`], the scenario's detector; by default Delaunay with the
    ///   orientation rule and Daza 2021's movement rule (DILMO) for moving groups, i.e. Daza's
    ///   Movement-and-Orientation detector).
    /// - Parameters: [`Daza2021Params::default`] (Hall radii 0.5 / 1 / 4 m, Daza's), whatever
    ///   the scene's own zones: the planner is Daza's system.
    ///
    /// - The mode is decided afresh every step, with no hysteresis (the paper gives none; the
    ///   `social` planner keeps ORCA while a robot is near, this one does not).
    /// - ORCA (line 8) is proxemic's ([`crate::control::orca`], its defaults and
    ///   [`crate::control::orca_crowd::ORCA_MARGIN`]): the paper gives no ORCA parameters.
    ///
    /// A bad input (it cannot happen with a valid world) makes the robot follow its path.
    pub(super) fn daza_step(&self, i: usize, partial_goal: &mut Vec2, desired: &mut Vec2, dt: f64) -> Mode {
        let st = &self.statics[i];
        let rb = &self.robots[i];
        let params = Daza2021Params::default();
        let robot =
            RobotState { pos: Vec2::new(rb.pose[0], rb.pose[1]), pref_vel: *desired, radius: st.radius };
        let c = &self.crowd;
        let mut objects: Vec<MobileObject> = (0..c.pos.len())
            .map(|k| MobileObject { pos: c.pos[k], vel: c.vel[k], radius: c.radius[k], id: None })
            .collect();
        objects.extend((0..self.robots.len()).filter(|&j| j != i).map(|j| MobileObject {
            pos: Vec2::new(self.robots[j].pose[0], self.robots[j].pose[1]),
            vel: self.robots[j].velocity,
            radius: self.statics[j].radius,
            id: Some(j as u64),
        }));
        let per = self.social.perception();
        let groups: Vec<Vec<usize>> = per.map(|p| p.groups.multi().cloned().collect()).unwrap_or_default();
        let Ok(decision) = daza2021_decide(&robot, rb.follower.path(), &objects, &groups, &params) else {
            return Mode::FollowPath;
        };
        *partial_goal = decision.partial_goal;
        match decision.mode {
            Daza2021Mode::FollowPath => Mode::FollowPath,
            Daza2021Mode::Orca => Mode::Orca,
            Daza2021Mode::SocialMomentum => {
                let spaces = match per {
                    Some(p) if st.planner.sousa2022_gaussians() => PeopleSpaces::Gaussians(&p.individuals),
                    _ => PeopleSpaces::Intimate,
                };
                let v = daza2021_social_momentum(
                    &robot,
                    rb.follower.path(),
                    rb.exec_v,
                    &objects,
                    &groups,
                    &decision,
                    spaces,
                    Some(&self.geometry),
                    &st.limits,
                    dt,
                    &params,
                    self.sm_unicycle(i),
                );
                match v {
                    Some(v) => {
                        *desired = v;
                        Mode::SocialMomentum
                    }
                    None => {
                        *desired = Vec2::zeros();
                        Mode::Wait
                    }
                }
            }
        }
    }
}
