//! Step 1 of Social Momentum, the action set: samples of the dynamic window (the speed disc
//! intersected with the one-step acceleration disc), each projected onto it exactly.

use super::SocialMomentumParams;
use crate::control::clamp_norm;
use crate::math::Vec2;

/// Step 1 of [`social_momentum`]: the goal-seeking, coasting and braking samples, then the polar
/// grid, each projected onto the dynamic window.
pub(super) fn action_set(
    vel: Vec2,
    to_goal: Vec2,
    goal_dir: Vec2,
    reach: f64,
    vmax: f64,
    params: &SocialMomentumParams,
) -> Vec<Vec2> {
    let tau = params.projection_time;
    let project = |w: Vec2| project_window(w, vel, reach, vmax);
    let mut samples: Vec<Vec2> = Vec::with_capacity(3 + params.n_speeds * params.n_headings);
    samples.push(project(to_goal / tau));
    samples.push(project(vel));
    samples.push(project(Vec2::zeros()));
    if params.n_headings > 0 {
        let step = std::f64::consts::TAU / params.n_headings as f64;
        let dirs: Vec<Vec2> =
            (0..params.n_headings).map(|h| crate::math::rotate(goal_dir, step * h as f64)).collect();
        for s in 1..=params.n_speeds {
            let r = reach * s as f64 / params.n_speeds as f64;
            for d in &dirs {
                samples.push(project(vel + d * r));
            }
        }
    }
    samples
}

#[inline]
/// The point of `{|v| <= vmax} ∩ {|v - c| <= r}` closest to `w` (exact). When the two discs are
/// disjoint the speed bound wins: the point of the speed disc closest to the acceleration disc.
pub(super) fn project_window(w: Vec2, c: Vec2, r: f64, vmax: f64) -> Vec2 {
    let in_speed = |v: Vec2| v.norm() <= vmax;
    let in_reach = |v: Vec2| (v - c).norm() <= r;
    if in_speed(w) && in_reach(w) {
        return w;
    }
    let p1 = clamp_norm(w, vmax);
    if in_reach(p1) {
        return p1;
    }
    let p2 = c + clamp_norm(w - c, r);
    if in_speed(p2) {
        return p2;
    }
    // The closest point is one of the two corners where the circles cross.
    let dc = c.norm();
    if dc > 0.0 {
        let a = (vmax * vmax - r * r + dc * dc) / (2.0 * dc);
        let h2 = vmax * vmax - a * a;
        if h2 >= 0.0 {
            let u = c / dc;
            let perp = Vec2::new(-u.y, u.x);
            let h = h2.sqrt();
            let q1 = u * a + perp * h;
            let q2 = u * a - perp * h;
            let q = if (q1 - w).norm_squared() <= (q2 - w).norm_squared() { q1 } else { q2 };
            return clamp_norm(q, vmax);
        }
    }
    clamp_norm(p2, vmax)
}
