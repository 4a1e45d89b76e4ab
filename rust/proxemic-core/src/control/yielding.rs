//! Predictive yielding: the `social` planner's local control near people.
//!
//! Each control step the robot rolls out a small set of candidate holonomic commands over a few
//! seconds against the people's predicted motion, throws out every rollout that would bring its
//! body too close to someone or from which it could not stop in time, and takes the best of the
//! rest by the social cost map's cost, progress along the global path and comfort. Yielding
//! (slowing, stopping, stepping aside to let people pass) is what comes out of it: no rule asks for
//! it.
//!
//! # One step
//! 1. **Candidates.** The reference is the path follower's desired velocity `u` (it already holds
//!    the global path's direction, the right-hand lane and the stop at the end). Candidates are
//!    the command `0` (brake) and, for each speed `f |u|` (`f` in
//!    [`YieldParams::speed_fractions`]) and each heading offset in [`HEADINGS_DEG`] (around `u`'s
//!    direction, out to ±90°: side steps), the command of that speed and heading; three backward
//!    headings ([`BACK_HEADINGS_DEG`]) at the smallest speed let the robot back off from someone
//!    walking into it. The current velocity (coast) comes last, unless the reference is a stop;
//!    [`plan_with`] adds a caller's candidates (the `social` planner's Social Momentum command).
//! 2. **Rollout.** A candidate `c` is held for [`YieldParams::commit`] seconds, then the robot
//!    brakes to a stop and stands until the horizon [`YieldParams::horizon`]; its velocity moves
//!    toward the target at the acceleration limit (`|Δv| <= max_accel h` per integration step
//!    `h`, as [`crate::control::Limits::apply`] limits the command), its position is integrated
//!    every `h`. Every rollout thus ends stopped: a rollout that passes the check below is one the
//!    robot can still stop from in time (the braking tail is checked, after Fraichard and Asama,
//!    "Inevitable collision states", Autonomous Robots 2004: a state is safe if some manoeuvre
//!    from it never collides; braking is the manoeuvre tried).
//! 3. **Hard constraints.** People move at constant velocity (their position and velocity now).
//!    A rollout is rejected if at any integration instant the robot's body gap (edge to edge,
//!    `|p - q| - r - r_i`) to a mover is below the mover's required gap (for a person
//!    [`YieldParams::body_gap`], Hall's intimate zone from body edge to body edge, plus
//!    [`YieldParams::speed_margin`] times their speed; 0 for a group's o-space disc) *and*
//!    either the robot moves toward the mover faster than
//!    [`YieldParams::approach_tolerance`] (0.05 m/s, the rule `collisions_robot_fault` uses) or
//!    it is closer to the mover than it would be had it stood still where it is now: the robot
//!    never brings itself into someone's intimate zone, nor stops in the way of someone walking
//!    at it, but a person who walks up to a standing robot does not freeze it. A rollout
//!    is also rejected if it comes within `radius + wall_margin` of a wall closer than the robot is
//!    now, or through a point where the cost field is infinite (a hard cost: the recovery's
//!    active object spaces).
//! 4. **Score** of an admissible rollout, maximised (the first wins a tie, so the choice is
//!    deterministic): `w_p P + w_c K − w_s S − w_a A − w_h H` with
//!    - progress `P`: the rollout's displacement along `u`'s direction at the horizon, over the
//!      reference command's (`c = u`) own, so the reference scores 1;
//!    - social cost `S`: the mean, over instants every [`YieldParams::cost_period`], of the cost
//!      field's traversal factor at the robot's predicted position and time, as
//!      `(f − 1)/(f_max − 1)` in `[0, 1]` (the social cost map's factors: personal and social
//!      zones of the people, moved along their velocity, groups' o-spaces, object spaces at R(t));
//!    - clearance `K`: the rollout's smallest body gap beyond the required one, over
//!      [`YieldParams::clearance_scale`], clamped to `[0, 1]` (the dynamic window approach's
//!      clearance term): with someone walking at it the robot takes the side step that leaves
//!      the most room, not just enough;
//!    - acceleration `A = |c − v| / (2 v_max)` and heading change `H = angle(c, v)/π` (comfort:
//!      no jerky changes of speed or direction without a reason).
//!
//!    This is the dynamic window approach's form (Fox, Burgard and Thrun, "The dynamic window
//!    approach to collision avoidance", IEEE RAM 1997: admissible velocities scored by a weighted
//!    sum of heading, clearance and velocity) with rollouts over a horizon against predicted
//!    people instead of a one-step window against a static map.
//! 5. **No admissible rollout:** the command is `0`, the safest stop (the robot brakes at its
//!    acceleration limit), and the outcome says so.
//!
//! # Bad input
//! A non-finite position, velocity or radius of the robot or a mover, non-finite limits or
//! parameters: the command is a stop, flagged as such. Nothing panics.

use crate::control::Limits;
use crate::control::clamp_norm;
use crate::map::StaticGeometry;
use crate::math::{Vec2, rotate};

/// Heading offsets of the candidates about the reference direction (degrees), the reference
/// first; ±90° are the side steps.
pub const HEADINGS_DEG: [f64; 11] = [0.0, 15.0, -15.0, 30.0, -30.0, 45.0, -45.0, 70.0, -70.0, 90.0, -90.0];
/// Backward heading offsets (degrees), tried at the smallest speed fraction only.
pub const BACK_HEADINGS_DEG: [f64; 3] = [180.0, 135.0, -135.0];

/// Parameters of [`plan`]; lengths in metres, times in seconds, speeds in m/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YieldParams {
    /// Prediction horizon (s, `> 0`); default 3.0.
    pub horizon: f64,
    /// Integration step of a rollout (s, `> 0`); default 0.1 (the scenes' control period).
    pub step: f64,
    /// How long a candidate command is held before the rollout brakes (s, `>= 0`); default 1.0.
    pub commit: f64,
    /// Body gap (edge to edge) the robot keeps from a person (m); default 0.45, Hall's intimate
    /// zone.
    pub body_gap: f64,
    /// Growth of a person's required gap with their speed (s: metres per m/s); default 0.4. A
    /// walking person's path is the least certain (they steer, slow, turn), so the gap the
    /// robot keeps from them is `body_gap + speed_margin |v|`: 0.45 m from someone standing,
    /// 0.85 m from someone walking at 1 m/s. Chosen on the tuning split (0, 0.2 and 0.4 tried,
    /// `docs/planners.md`).
    pub speed_margin: f64,
    /// Body gap kept from another robot's body (m); default 0.1.
    pub robot_gap: f64,
    /// Speed toward a mover (m/s) above which the robot counts as approaching it; default 0.05,
    /// the rule of `collisions_robot_fault`.
    pub approach_tolerance: f64,
    /// Clearance kept from walls beyond the robot's radius (m); default 0.05.
    pub wall_margin: f64,
    /// Speeds of the candidates as fractions of the reference speed, largest first; default
    /// `[1, 2/3, 1/3]`.
    pub speed_fractions: [f64; 3],
    /// The cost field is read every this many seconds along a rollout (s, `> 0`); default 0.3.
    pub cost_period: f64,
    /// Weight of progress (dimensionless); default 1.0.
    pub w_progress: f64,
    /// Weight of the social cost (dimensionless); default 1.0.
    pub w_social: f64,
    /// Weight of the clearance (dimensionless); default 1.0.
    pub w_clearance: f64,
    /// Body gap beyond the required one (m, `> 0`) at which the clearance term is full;
    /// default 1.0.
    pub clearance_scale: f64,
    /// Weight of the acceleration (dimensionless); default 0.2.
    pub w_accel: f64,
    /// Weight of the heading change (dimensionless); default 0.1.
    pub w_turn: f64,
}

impl Default for YieldParams {
    fn default() -> Self {
        YieldParams {
            horizon: 3.0,
            step: 0.1,
            commit: 1.0,
            body_gap: 0.45,
            speed_margin: 0.4,
            robot_gap: 0.1,
            approach_tolerance: 0.05,
            wall_margin: 0.05,
            speed_fractions: [1.0, 2.0 / 3.0, 1.0 / 3.0],
            cost_period: 0.3,
            w_progress: 1.0,
            w_social: 1.0,
            w_clearance: 1.0,
            clearance_scale: 1.0,
            w_accel: 0.2,
            w_turn: 0.1,
        }
    }
}

impl YieldParams {
    fn is_valid(&self) -> bool {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        pos(self.horizon)
            && pos(self.step)
            && pos(self.cost_period)
            && pos(self.clearance_scale)
            && nonneg(self.commit)
            && nonneg(self.body_gap)
            && nonneg(self.speed_margin)
            && nonneg(self.robot_gap)
            && nonneg(self.approach_tolerance)
            && nonneg(self.wall_margin)
            && self.speed_fractions.iter().all(|&f| nonneg(f))
            && [self.w_progress, self.w_social, self.w_clearance, self.w_accel, self.w_turn]
                .iter()
                .all(|&w| nonneg(w))
            && self.horizon / self.step <= 1e4
    }
}

/// A moving disc the robot keeps its body gap from: a person, a group's o-space, another robot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mover {
    /// Position now (m, world frame).
    pub pos: Vec2,
    /// Velocity, assumed constant over the horizon (m/s).
    pub vel: Vec2,
    /// Radius of the disc (m, `>= 0`): a person's body, a group's o-space.
    pub radius: f64,
    /// Body gap the robot keeps from the disc's edge (m, `>= 0`).
    pub gap: f64,
}

impl Mover {
    fn is_valid(&self) -> bool {
        self.pos.x.is_finite()
            && self.pos.y.is_finite()
            && self.vel.x.is_finite()
            && self.vel.y.is_finite()
            && self.radius.is_finite()
            && self.radius >= 0.0
            && self.gap.is_finite()
            && self.gap >= 0.0
    }
}

/// The robot as the planner sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Robot {
    /// Position (m).
    pub pos: Vec2,
    /// Velocity now (m/s, the executed command).
    pub vel: Vec2,
    /// Body radius (m).
    pub radius: f64,
}

/// The social cost the rollouts are scored on: the traversal factor (`>= 1`; infinite where the
/// robot must not go) at a point `t` seconds from now, and the largest finite factor.
pub trait CostField {
    /// Traversal factor at `p` (m) `t` seconds from now (`>= 1`, infinite for a hard cost).
    fn factor(&self, p: Vec2, t: f64) -> f64;
    /// The largest finite factor (`> 1`): a factor at or above it scores 1.
    fn max_factor(&self) -> f64;
}

/// A cost field that is 1 everywhere (no social cost).
#[derive(Clone, Copy, Debug, Default)]
pub struct NoCost;

impl CostField for NoCost {
    fn factor(&self, _p: Vec2, _t: f64) -> f64 {
        1.0
    }
    fn max_factor(&self) -> f64 {
        2.0
    }
}

/// What [`plan`] decided.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct YieldOutcome {
    /// Desired world-frame velocity (m/s), before [`Limits::apply`].
    pub velocity: Vec2,
    /// `true` when no rollout was admissible (or the input was bad): the command is the stop.
    pub stopped: bool,
}

/// One instant of a rollout.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RolloutPoint {
    /// Time from now (s).
    pub t: f64,
    /// Predicted position (m).
    pub pos: Vec2,
    /// Predicted velocity (m/s).
    pub vel: Vec2,
}

/// The rollout of command `command` (m/s, world frame) for `robot`: the points at every
/// integration step up to the horizon (step 2 of the module docs).
pub fn rollout(robot: &Robot, command: Vec2, limits: &Limits, params: &YieldParams) -> Vec<RolloutPoint> {
    let mut out = Vec::new();
    rollout_into(robot, command, limits, params, &mut out);
    out
}

/// [`rollout`] into `out` (cleared first): one buffer for every candidate of a step.
fn rollout_into(
    robot: &Robot,
    command: Vec2,
    limits: &Limits,
    params: &YieldParams,
    out: &mut Vec<RolloutPoint>,
) {
    let h = params.step;
    let n = (params.horizon / h).ceil() as usize;
    let dv = limits.max_accel * h;
    let command = clamp_norm(command, limits.max_speed);
    let (mut p, mut v) = (robot.pos, robot.vel);
    let same = |a: Vec2, b: Vec2| a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits();
    // The target for which `v` is a fixed point of the update (bit for bit): while the target
    // stays, the update would give `v` again, and is skipped.
    let mut steady: Option<Vec2> = None;
    out.clear();
    out.reserve(n);
    for k in 1..=n {
        let t0 = (k - 1) as f64 * h;
        let braking = t0 >= params.commit - 1e-9;
        if braking && v.x == 0.0 && v.y == 0.0 {
            // Stopped while braking: every later step leaves `v` zero and `p` where it is (the
            // same values the update below would compute), so the rest is the stop's.
            out.extend((k..=n).map(|j| RolloutPoint { t: j as f64 * h, pos: p, vel: v }));
            break;
        }
        let target = if braking { Vec2::zeros() } else { command };
        if !steady.is_some_and(|s| same(s, target)) {
            let next = clamp_norm(v + clamp_norm(target - v, dv), limits.max_speed);
            steady = same(next, v).then_some(target);
            v = next;
        }
        p += v * h;
        out.push(RolloutPoint { t: k as f64 * h, pos: p, vel: v });
    }
}

/// Whether the rollout `points` of `robot` breaks a hard constraint against `movers` (step 3 of
/// the module docs; walls and hard costs are checked by [`plan`]).
pub fn violates(points: &[RolloutPoint], robot: &Robot, movers: &[Mover], params: &YieldParams) -> bool {
    clearance(points, robot, movers, params).is_none()
}

/// The smallest body gap beyond the required one (m) to `movers` along `points`, `None` when the
/// rollout breaks a hard constraint ([`violates`]); infinite without movers.
fn clearance(points: &[RolloutPoint], robot: &Robot, movers: &[Mover], params: &YieldParams) -> Option<f64> {
    let mut least = f64::INFINITY;
    for pt in points {
        for m in movers {
            let q = m.pos + m.vel * pt.t;
            let d = q - pt.pos;
            let dist = d.norm();
            let edge = dist - robot.radius - m.radius;
            if edge < m.gap && intrudes(pt, robot, q, d, dist, params.approach_tolerance) {
                return None;
            }
            least = least.min(edge - m.gap);
        }
    }
    Some(least)
}

/// Whether the robot at `pt`, inside a mover's required gap (the mover at `q`, `d = q − pt.pos`,
/// `dist = |d|`), approaches it, or is closer than it would be had it stood where it is now.
#[inline]
fn intrudes(pt: &RolloutPoint, robot: &Robot, q: Vec2, d: Vec2, dist: f64, tolerance: f64) -> bool {
    let toward = if dist > 1e-9 { pt.vel.dot(&d) / dist } else { pt.vel.norm() };
    toward > tolerance || dist < (q - robot.pos).norm() - 1e-9
}

/// One control step of predictive yielding (see the module docs).
///
/// - `robot`: position, executed velocity and radius;
/// - `reference`: the path follower's desired velocity (m/s): direction and speed of the
///   candidates;
/// - `movers`: people (gap [`YieldParams::body_gap`]), groups' o-space discs, other robots;
/// - `cost`: the social cost field;
/// - `geometry`: the static geometry (walls), if any;
/// - `limits`: the robot's speed and acceleration limits.
#[allow(clippy::too_many_arguments)]
pub fn plan(
    robot: &Robot,
    reference: Vec2,
    movers: &[Mover],
    cost: &dyn CostField,
    geometry: Option<&StaticGeometry>,
    limits: &Limits,
    params: &YieldParams,
) -> YieldOutcome {
    plan_with(robot, reference, &[], movers, cost, geometry, limits, params)
}

/// [`plan`] with `extra` candidate commands (m/s, world frame) tried after the module's own:
/// another local planner's proposal, kept when it scores best.
#[allow(clippy::too_many_arguments)]
pub fn plan_with(
    robot: &Robot,
    reference: Vec2,
    extra: &[Vec2],
    movers: &[Mover],
    cost: &dyn CostField,
    geometry: Option<&StaticGeometry>,
    limits: &Limits,
    params: &YieldParams,
) -> YieldOutcome {
    let stop = YieldOutcome { velocity: Vec2::zeros(), stopped: true };
    let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
    if !(finite(robot.pos) && finite(robot.vel) && finite(reference) && robot.radius.is_finite())
        || robot.radius < 0.0
        || !(limits.max_speed.is_finite() && limits.max_speed >= 0.0)
        || !(limits.max_accel.is_finite() && limits.max_accel > 0.0)
        || !params.is_valid()
        || !movers.iter().all(Mover::is_valid)
    {
        return stop;
    }
    let speed = reference.norm().min(limits.max_speed);
    let dir = if speed > 1e-9 { reference / reference.norm() } else { Vec2::zeros() };
    let mut candidates = candidates(robot.vel, dir, speed, params);
    candidates.extend(extra.iter().copied().filter(|c| c.x.is_finite() && c.y.is_finite()));
    // Only the movers a rollout could reach matter: the robot covers at most v_max T, a mover
    // |v_i| T.
    let reach = limits.max_speed.max(robot.vel.norm()) * params.horizon;
    let near: Vec<Mover> = movers
        .iter()
        .filter(|m| {
            (m.pos - robot.pos).norm() - m.vel.norm() * params.horizon - reach - robot.radius - m.radius
                < m.gap + 1e-9
        })
        .copied()
        .collect();
    let wall_bound = robot.radius + params.wall_margin;
    let wall_now = geometry.map_or(f64::INFINITY, |g| g.boundary_distance_within(robot.pos, wall_bound));
    // The walls within reach of any rollout point: a point within `open` of the robot's position
    // (outside the geometry) can neither be inside it nor within `wall_bound` of a wall, and
    // skips the checks (the same decisions, for less work).
    let look = limits.max_speed.max(robot.vel.norm()) * params.horizon + wall_bound + 0.1;
    let open = geometry.map_or(f64::INFINITY, |g| {
        if g.contains(robot.pos) {
            0.0
        } else {
            g.boundary_distance_within(robot.pos, look) - wall_bound - 1e-6
        }
    });
    let hard_now = cost.factor(robot.pos, 0.0).is_infinite();
    let max_factor = cost.max_factor().max(1.0 + 1e-9);
    let every = ((params.cost_period / params.step).round() as usize).max(1);
    let progress_of = |pts: &[RolloutPoint]| pts.last().map_or(0.0, |q| (q.pos - robot.pos).dot(&dir));
    let mut pts = Vec::new();
    rollout_into(robot, dir * speed, limits, params, &mut pts);
    let reference_progress = progress_of(&pts);
    let v_scale = 2.0 * limits.max_speed.max(1e-9);
    let mut best: Option<(Vec2, f64)> = None;
    for c in candidates {
        rollout_into(robot, c, limits, params, &mut pts);
        let progress = if reference_progress > 1e-9 { progress_of(&pts) / reference_progress } else { 0.0 };
        let accel = (c - robot.vel).norm() / v_scale;
        let turn = if c.norm() > params.approach_tolerance && robot.vel.norm() > params.approach_tolerance {
            let cos = (c.dot(&robot.vel) / (c.norm() * robot.vel.norm())).clamp(-1.0, 1.0);
            cos.acos() / std::f64::consts::PI
        } else {
            0.0
        };
        let score_of = |clear: f64, social: f64| {
            params.w_progress * progress + params.w_clearance * clear
                - params.w_social * social
                - params.w_accel * accel
                - params.w_turn * turn
        };
        // Upper bounds of the score (the clearance term at most its full weight, the cost term at
        // least 0; rounding is monotonic): a candidate whose bound does not beat the best so far
        // cannot be chosen, and what the bound leaves out is not computed (the same choice).
        let beaten = |bound: f64| {
            best.is_some_and(|(_, s)| bound.partial_cmp(&s) != Some(std::cmp::Ordering::Greater))
        };
        if beaten(score_of(1.0, 0.0)) {
            continue;
        }
        let Some(gap) = clearance(&pts, robot, &near, params) else { continue };
        let clear = (gap / params.clearance_scale).clamp(0.0, 1.0);
        let score_with = |social: f64| score_of(clear, social);
        // Then with the clearance known: the walls and costs are looked at only for a candidate
        // that can still win.
        if beaten(score_with(0.0)) {
            continue;
        }
        if let Some(g) = geometry {
            // A point where the previous one was (the rollout stopped) has the previous one's
            // answer, which was no hit: it is not tested again.
            let mut last: Option<Vec2> = None;
            let hits = pts.iter().any(|pt| {
                if last == Some(pt.pos) {
                    return false;
                }
                last = Some(pt.pos);
                (pt.pos - robot.pos).norm() >= open
                    && (g.contains(pt.pos) || {
                        let d = g.boundary_distance_within(pt.pos, wall_bound);
                        d < robot.radius.max(wall_bound.min(wall_now)) - 1e-9
                    })
            });
            if hits {
                continue;
            }
        }
        let mut social = 0.0;
        let mut samples = 0usize;
        let mut hard = false;
        for pt in pts.iter().skip(every - 1).step_by(every) {
            let f = cost.factor(pt.pos, pt.t);
            if f.is_infinite() && !hard_now {
                hard = true;
                break;
            }
            social += ((f.min(max_factor) - 1.0) / (max_factor - 1.0)).clamp(0.0, 1.0);
            samples += 1;
        }
        if hard {
            continue;
        }
        let social = if samples > 0 { social / samples as f64 } else { 0.0 };
        let score = score_with(social);
        if score.is_finite() && best.is_none_or(|(_, s)| score > s) {
            best = Some((c, score));
        }
    }
    match best {
        Some((v, _)) => YieldOutcome { velocity: v, stopped: false },
        None => stop,
    }
}

/// The candidate commands of one step (step 1 of the module docs): the brake, the grid of
/// speeds and headings about `dir`, the backward ones, the current velocity.
fn candidates(vel: Vec2, dir: Vec2, speed: f64, params: &YieldParams) -> Vec<Vec2> {
    let mut out = Vec::with_capacity(2 + HEADINGS_DEG.len() * 3 + BACK_HEADINGS_DEG.len());
    out.push(Vec2::zeros());
    if speed > 1e-9 {
        for &f in &params.speed_fractions {
            for &a in &HEADINGS_DEG {
                out.push(rotate(dir, a.to_radians()) * (f * speed));
            }
        }
        let slow = params.speed_fractions.iter().copied().fold(f64::INFINITY, f64::min) * speed;
        for &a in &BACK_HEADINGS_DEG {
            out.push(rotate(dir, a.to_radians()) * slow);
        }
    }
    if speed > 1e-9 {
        out.push(vel);
    }
    out
}

#[cfg(test)]
mod tests;
