//! The `astar_stop` planner's step: the rule of [`crate::control::stop_and_wait`] on the robot's
//! plain A* path, among the people and the other robots, and its re-plan around the blockers.

use super::World;
use super::planners::plan_path;
use crate::control::mode_switch::Mode;
use crate::control::stop_and_wait::{
    Body, Robot, StopDecision, StopParams, max_reach, with_temporary_obstacles,
};
use crate::control::{FollowerParams, PathFollower};
use crate::math::Vec2;

impl World {
    /// Robot `i`'s stop-and-wait step: keeps the follower's `desired` velocity while the corridor
    /// ahead is clear ([`Mode::FollowPath`]), or sets it to zero while someone is in the way
    /// ([`Mode::Wait`]), re-planning the plain A* path around them after the wait.
    pub(super) fn stop_step(&mut self, i: usize, desired: &mut Vec2, dt: f64) -> Mode {
        let params = StopParams::default();
        let st = &self.statics[i];
        let rb = &self.robots[i];
        let p = Vec2::new(rb.pose[0], rb.pose[1]);
        let robot = Robot {
            radius: st.radius,
            speed: rb.exec_v.norm(),
            max_speed: st.limits.max_speed,
            max_decel: st.limits.max_accel,
        };
        let c = &self.crowd;
        // People always count where they are about to be; a robot only when it has the right of
        // way over this one (a lower index).
        let mut others: Vec<Body> = (0..c.len())
            .map(|k| Body { pos: c.pos[k], radius: c.radius[k], vel: c.vel[k], predicted: true })
            .collect();
        for (j, (o, s)) in self.robots.iter().zip(&self.statics).enumerate() {
            if j != i {
                let pos = Vec2::new(o.pose[0], o.pose[1]);
                others.push(Body { pos, radius: s.radius, vel: o.velocity, predicted: j < i });
            }
        }
        let length = max_reach(&robot, robot.max_speed, &others, dt, &params);
        let samples = (length / params.sample).ceil().max(1.0) as usize;
        let mut ahead = Vec::with_capacity(samples + 1);
        ahead.push(p);
        ahead.extend((1..=samples).map(|k| rb.follower.point_ahead(k as f64 * params.sample)));
        // The path ends within the reach: its end is the robot's current target.
        let ends_at_goal = rb.follower.point_ahead(length + params.sample) == rb.follower.point_ahead(length);
        // The straight line along the robot's velocity, as long as the path's corridor.
        let heading =
            if robot.speed > 1e-3 { vec![p, p + rb.exec_v * (length / robot.speed)] } else { Vec::new() };
        let corridors: [(&[Vec2], bool); 2] = [(&ahead, ends_at_goal), (&heading, false)];
        let decision = self.robots[i].stop.update(&corridors, &robot, &others, dt, &params);
        match decision {
            StopDecision::Go => Mode::FollowPath,
            StopDecision::Stop => {
                *desired = Vec2::zeros();
                Mode::Wait
            }
            StopDecision::Replan(blocking) => {
                let around: Vec<(Body, f64)> = blocking
                    .iter()
                    .filter_map(|&k| others.get(k))
                    .map(|&b| (b, robot.radius + b.radius + params.margin))
                    .collect();
                let st = &self.statics[i];
                let grid = with_temporary_obstacles(&self.grids[st.grid_index].grid, &around);
                let goal = st.route[self.robots[i].leg];
                if let Some(path) = plan_path(&mut self.planner, &grid, p, goal) {
                    self.robots[i].follower = PathFollower::new(path, FollowerParams::default());
                }
                *desired = Vec2::zeros();
                Mode::Wait
            }
        }
    }
}
