//! The progress monitor in the per-robot step: [`crate::control::progress`] decides when a robot
//! is stalled; here the world carries out its recovery with the robot's grid, the people and the
//! path planner. The same for every built-in planner (the hook is in [`World::plan_all`], before
//! the planner's own step).

use super::World;
use super::planners::{plan_path, segment_clear};
use crate::control::eband::ElasticBand;
use crate::control::mode_switch::Mode;
use crate::control::orca_crowd::{ORCA_MARGIN, person_disc};
use crate::control::progress::{BACKOFF_DISTANCE, blocking_people, clearest_point, mark_discs};
use crate::control::{FollowerParams, PathFollower};
use crate::geom::distance_squared_point_segment;
use crate::math::Vec2;
use crate::scenario::PlannerKind;

/// Points of the path ahead (every this many metres) the blocking test looks at.
const AHEAD_SAMPLE: f64 = 0.5;
/// The way back is taken when its end has at least this much more clearance (m) than the
/// robot's place (it leads out of a doorway or a dead end).
const BACKOFF_GAIN: f64 = 0.05;

impl World {
    /// Robot `i`'s progress monitor this step (a running robot whose built-in planner runs):
    /// paused while the robot stands at a tour stop, restarted for each new target; on a stall,
    /// the recovery ([`World::recover`]). When the hold of a recovery path ends, the `eband`
    /// planner gets its band back on a fresh plain path.
    pub(super) fn watch_progress(&mut self, i: usize, dt: f64) {
        let rb = &mut self.robots[i];
        if rb.dwelling {
            rb.progress.restart(rb.geodesic);
            return;
        }
        let p = Vec2::new(rb.pose[0], rb.pose[1]);
        let held = rb.progress.holds_path();
        if rb.progress.update(rb.leg, rb.geodesic, p, dt) {
            self.recover(i, p);
            self.robots[i].progress.recovered();
        } else if held && !rb.progress.holds_path() && self.statics[i].planner == PlannerKind::Eband {
            let st = &self.statics[i];
            let grid = &self.grids[st.grid_index].grid;
            if let Some(path) = plan_path(&mut self.planner, grid, p, st.route[rb.leg]) {
                rb.follower = PathFollower::new(path, FollowerParams::default());
            }
            rb.band = ElasticBand::new(rb.follower.path(), st.eband).ok();
        }
    }

    /// Robot `i`'s recovery from `p`: a new path that backs out along the way it came when that
    /// leads to more clearance (else to the clearest point within reach), then goes on to its target by a plain A* path planned with
    /// the blocking people as temporary obstacles (discs of their radius plus the robot's
    /// inflated radius, for `astar_orca` the larger discs ORCA keeps its centre out of; without a
    /// way round them, on the static grid). The local control state
    /// goes with the old path: the partial goal (on the new path), the mode, the social path
    /// and the elastic band (the `eband` planner gets a new one when the hold ends; the social
    /// planners plan a new social path then).
    fn recover(&mut self, i: usize, p: Vec2) {
        let st = &self.statics[i];
        let target = st.route[self.robots[i].leg];
        let grid = &self.grids[st.grid_index].grid;
        let rb = &self.robots[i];
        let field = &self.field;
        let steps = (crate::control::progress::BLOCKING_PATH_AHEAD / AHEAD_SAMPLE).ceil() as usize;
        let ahead: Vec<Vec2> =
            (0..=steps).map(|k| rb.follower.point_ahead(k as f64 * AHEAD_SAMPLE)).collect();
        let inflated = st.radius + self.scenario.robots[i].inflation_margin;
        let c = &self.crowd;
        let blocking = blocking_people(p, &ahead, &c.pos);
        // `astar_orca` follows every path with ORCA, which keeps its centre further from a
        // person than the inflated disc does, and does not pass between people closer than that:
        // its recovery keeps to ORCA's discs (the re-plan's obstacles, rasterised so that no cell
        // within them stays free) and counts the blocking people's bodies as obstacles when it
        // looks for room to back out to. With the plain rule, a robot ORCA held in the gap of a
        // conversing pair 1.2 m apart backed out through the gap (more room from the walls
        // there) and re-planned through the 0.2 m channel the inflated discs left.
        let orca_follows = st.planner == PlannerKind::AstarOrca;
        let keep_off = |k: usize| {
            let inflated_disc = c.radius[k] + inflated;
            if orca_follows {
                let orca = person_disc(c.radius[k], 0.0) + st.radius + ORCA_MARGIN;
                inflated_disc.max(orca + grid.spec.resolution * std::f64::consts::FRAC_1_SQRT_2)
            } else {
                inflated_disc
            }
        };
        let discs: Vec<(Vec2, f64)> = blocking.iter().map(|&k| (c.pos[k], keep_off(k))).collect();
        let bodies: Vec<(Vec2, f64)> = if orca_follows {
            blocking.iter().map(|&k| (c.pos[k], c.radius[k])).collect()
        } else {
            Vec::new()
        };
        // Room at a point (m): its clearance from the walls, and for `astar_orca` from the
        // blocking people's bodies.
        let room = |q: Vec2| bodies.iter().fold(field.at(q), |m, &(o, r)| m.min((q - o).norm() - r));
        let back = rb.progress.way_back(p);
        let mut path = vec![p];
        match back.last() {
            // Back along the way it came when that leads to more room (out of a doorway or a
            // dead end)...
            Some(&end) if back.len() >= 2 && room(end) > room(p) + BACKOFF_GAIN => path = back,
            // ...else to the clearest point within reach, if any has more room than here (for
            // `astar_orca`, in a straight line that goes no deeper into ORCA's discs).
            _ => {
                let visible = |a: Vec2, b: Vec2| {
                    segment_clear(grid, a, b)
                        && (!orca_follows
                            || discs.iter().all(|&(o, r)| {
                                let limit = r.min((a - o).norm());
                                distance_squared_point_segment(o, a, b) >= limit * limit - 1e-9
                            }))
                };
                if let Some(q) = clearest_point(p, BACKOFF_DISTANCE, &room, &visible) {
                    path.push(q);
                }
            }
        }
        let from = *path.last().unwrap_or(&p);
        let onward = if discs.is_empty() {
            None
        } else {
            let mut blocked = grid.clone();
            mark_discs(&mut blocked, &discs);
            plan_path(&mut self.planner, &blocked, from, target)
        }
        .or_else(|| plan_path(&mut self.planner, grid, from, target));
        match onward {
            Some(rest) => path.extend(rest.into_iter().skip(1)),
            None => path.push(target),
        }
        let rb = &mut self.robots[i];
        rb.follower = PathFollower::new(path, FollowerParams::default());
        rb.mode = Mode::FollowPath;
        rb.social_path = None;
        rb.band = None;
        rb.last_plan_step = self.steps;
    }
}
