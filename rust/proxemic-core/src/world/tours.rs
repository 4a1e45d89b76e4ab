//! Robot tours: a robot that reaches its current waypoint stands there for its `dwell` seconds,
//! then heads for the next target of its route.

use super::World;
use super::planners::plan_path;
use crate::control::eband::ElasticBand;
use crate::control::{FollowerParams, PathFollower};
use crate::math::Vec2;
use crate::metrics::Outcome;
use crate::scenario::PlannerKind;

impl World {
    /// Tours: a robot that reaches its current waypoint stands there for its `dwell` seconds,
    /// then heads for the next target (re-planning its path); progress is measured toward the
    /// new target from then on.
    pub(super) fn advance_tours(&mut self, dt: f64) {
        let radius = self.scenario.episode.success_radius;
        let mut next = Vec::new();
        for (i, (rb, st)) in self.robots.iter_mut().zip(&self.statics).enumerate() {
            if rb.outcome != Outcome::Running || rb.leg + 1 >= st.route.len() {
                continue;
            }
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            if !rb.dwelling && (p - st.route[rb.leg]).norm() <= radius {
                rb.dwelling = true;
                rb.dwell_left = st.dwell;
            }
            if rb.dwelling {
                if rb.dwell_left <= 1e-9 {
                    rb.dwelling = false;
                    rb.dwell_left = 0.0;
                    rb.leg += 1;
                    rb.geodesic = st.fields[rb.leg].distance(p);
                    next.push(i);
                } else {
                    rb.dwell_left -= dt;
                }
            }
        }
        for i in next {
            self.start_leg(i);
        }
    }

    /// Plans robot `i`'s path to its (new) current target with its planner.
    fn start_leg(&mut self, i: usize) {
        let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
        let st = &self.statics[i];
        let target = st.route[self.robots[i].leg];
        let grid = &self.grids[st.grid_index].grid;
        let path = plan_path(&mut self.planner, grid, p, target).unwrap_or_else(|| vec![p, target]);
        let rb = &mut self.robots[i];
        rb.follower = PathFollower::new(path, FollowerParams::default());
        rb.social_path = None;
        if st.planner == PlannerKind::Eband {
            rb.band = ElasticBand::new(rb.follower.path(), st.eband).ok();
        }
        if self.planning[i] && st.planner.social_global() && self.perceive().is_ok() {
            let tod = self.time_of_day();
            self.social_plan(i, p, tod);
        }
    }
}
