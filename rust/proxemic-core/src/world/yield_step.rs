//! The `social` planner's last word on every command: predictive yielding
//! ([`crate::control::yielding`]) against the people, the groups' o-spaces and the other robots,
//! scored on the social cost of the people's spaces moved along their velocities and of the
//! objects' spaces at the agenda's hour. While a recovery path is held the same step runs on it,
//! with the active object spaces as hard costs: only the path (the search's goal) changes.

use super::World;
use crate::control::yielding::{CostField, Mover, Robot, plan_with};
use crate::math::Vec2;
use crate::perception::Individual;
use crate::social_cost_map::{SocialCosts, SpaceFunction};

/// The social cost field of one robot's step ([`CostField`]): each perceived individual's
/// traversal factor on its space function, the individual moved along its members' mean velocity
/// (`t` seconds ahead, the point is moved back instead: the space function is a function of the
/// offset from the individual), capped at the map's largest factor (the intimate zone is the body
/// gap's hard constraint, not a cost), less the robot's target's own factor for a standing
/// individual whose personal zone holds the target (the target is reached through that space:
/// the free corner of an elevator car beside the person in it); the objects' factors at the
/// agenda's hour, infinite for an active space during a recovery.
struct SocialField<'a> {
    world: &'a World,
    costs: &'a SocialCosts,
    /// Each individual with its mean velocity and, for a standing individual whose personal zone
    /// holds the robot's current target, the target's excess factor (`factor - 1`, capped; 0
    /// otherwise): the cost the target itself must incur.
    individuals: Vec<(&'a Individual, Vec2, f64)>,
    object_factors: Vec<f64>,
}

impl CostField for SocialField<'_> {
    fn factor(&self, p: Vec2, t: f64) -> f64 {
        let mut f = self.world.social.object_factor_at(p, &self.object_factors);
        let cap = self.costs.max_factor;
        for &(ind, vel, floor) in &self.individuals {
            let q = p - vel * t;
            let [x0, y0, x1, y1] = ind.bounds();
            if q.x < x0 || q.x > x1 || q.y < y0 || q.y > y1 {
                continue;
            }
            // Only the cost beyond the target's own counts: a target inside someone's space
            // (the free corner of an elevator car with a person in it) is reached through it.
            f = f.max((self.costs.factor(ind, q).min(cap) - floor).max(1.0));
        }
        f
    }

    fn max_factor(&self) -> f64 {
        self.costs.max_factor
    }
}

impl World {
    /// Robot `i`'s desired velocity `desired` (m/s, from the path follower or Social Momentum)
    /// made safe and polite by predictive yielding; `true` when no rollout was admissible and
    /// the robot brakes. `recovering`: a recovery path is held (active object spaces are hard).
    pub(super) fn yield_step(&self, i: usize, reference: Vec2, desired: &mut Vec2, recovering: bool) -> bool {
        let st = &self.statics[i];
        let rb = &self.robots[i];
        let params = &self.control.yielding;
        let robot = Robot { pos: Vec2::new(rb.pose[0], rb.pose[1]), vel: rb.exec_v, radius: st.radius };
        let c = &self.crowd;
        let mut movers: Vec<Mover> = Vec::with_capacity(c.len() + self.robots.len() + 4);
        movers.extend((0..c.len()).map(|k| Mover {
            pos: c.pos[k],
            vel: c.vel[k],
            radius: c.radius[k],
            gap: params.body_gap + params.speed_margin * c.vel[k].norm(),
        }));
        let tod = self.time_of_day();
        let mut object_factors = self.social.object_factors(tod);
        if recovering {
            let mut active = Vec::new();
            self.social.object_activity(tod, &mut active);
            for (f, on) in object_factors.iter_mut().zip(active) {
                if on {
                    *f = f64::INFINITY;
                }
            }
        }
        // The cost field is read at the robot's position now and along its rollouts, at most
        // `t_end` seconds ahead (the rollouts' last instant) and `reach` metres away (their speed
        // is clamped to the limit): an individual whose bounds, moved along its velocity over
        // that time, stay farther than `reach` from the robot never holds a point the field is
        // read at, and is left out of the field (it would add nothing to a maximum). With
        // thousands of people this is most of them. Non-finite bounds or limits leave no one out.
        let t_end = (params.horizon / params.step).ceil() * params.step;
        let reach = st.limits.max_speed * t_end;
        let out_of_reach = |ind: &Individual, vel: Vec2| {
            let lim = (reach + vel.norm() * t_end) * (1.0 + 1e-9) + 1e-6;
            let [x0, y0, x1, y1] = ind.bounds();
            x0 - robot.pos.x > lim
                || robot.pos.x - x1 > lim
                || y0 - robot.pos.y > lim
                || robot.pos.y - y1 > lim
        };
        let mut individuals = Vec::new();
        let target = st.route[rb.leg];
        let costs = &self.social.config().costs;
        if let Some(per) = self.social.perception() {
            for ind in &per.individuals {
                if ind.members.is_empty() || ind.robots.contains(&i) {
                    continue;
                }
                let vel =
                    ind.members.iter().fold(Vec2::zeros(), |a, &k| a + c.vel[k]) / ind.members.len() as f64;
                if !out_of_reach(ind, vel) {
                    let [x0, y0, x1, y1] = ind.bounds();
                    // A standing individual only (a walker's space moves on from the target),
                    // and a target in its personal zone: a target merely in someone's social
                    // zone is reached round them.
                    let inside = vel.norm() <= params.approach_tolerance
                        && (x0..=x1).contains(&target.x)
                        && (y0..=y1).contains(&target.y)
                        && costs.in_personal_zone(ind, target);
                    let floor =
                        if inside { costs.factor(ind, target).min(costs.max_factor) - 1.0 } else { 0.0 };
                    individuals.push((ind, vel, floor));
                }
                if ind.members.len() + ind.robots.len() >= 2 {
                    // A group's o-space: the mean distance of its members from its centre, kept
                    // clear by the robot's body (gap 0).
                    let ospace = ind.members.iter().map(|&k| (c.pos[k] - ind.centre).norm()).sum::<f64>()
                        / ind.members.len() as f64;
                    movers.push(Mover { pos: ind.centre, vel, radius: ospace, gap: 0.0 });
                }
            }
        }
        for (j, (o, s)) in self.robots.iter().zip(&self.statics).enumerate() {
            if j != i {
                movers.push(Mover {
                    pos: Vec2::new(o.pose[0], o.pose[1]),
                    vel: o.velocity,
                    radius: s.radius,
                    gap: params.robot_gap,
                });
            }
        }
        let field = SocialField { world: self, costs, individuals, object_factors };
        let extra = [*desired];
        let out =
            plan_with(&robot, reference, &extra, &movers, &field, Some(&self.geometry), &st.limits, params);
        *desired = out.velocity;
        out.stopped
    }
}
