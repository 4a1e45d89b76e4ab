//! Social Momentum: a sampling-based local controller that prefers legible, momentum-preserving
//! passes around people.
//!
//! After Mavrogiannis, Thomason and Knepper, "Social Momentum: A Framework for Legible Navigation in
//! Dynamic Multi-Agent Environments" (HRI 2018), and Mavrogiannis, Alves-Oliveira, Thomason and
//! Knepper, "Social Momentum: Design and Evaluation of a Framework for Socially Competent Robot
//! Navigation" (ACM THRI 2022); used near people and groups, with a partial goal on the global path,
//! by Daza et al. 2021 (Algorithm 1, lines 14-19). No official code exists; this follows the spec in
//! `docs/algorithms.md` §8. The paper's weight λ and action set are unverified, so every parameter
//! is in [`SocialMomentumParams`].
//!
//! # One step
//! 1. **Action set.** The dynamic window `W = {|v| <= max_speed} ∩ {|v - vel| <= max_accel * dt}`
//!    is sampled on a polar grid centred on the current velocity: `n_speeds` rings (radii
//!    `k/n_speeds * max_accel * dt`, `k = 1..=n_speeds`) times `n_headings` rays, the first ray
//!    pointing at the partial goal. Every sample is projected onto `W` (exact closest point).
//!    Three more samples come first: the goal-seeking one (the point of `W` closest to
//!    `(partial_goal - pos) / projection_time`, i.e. the efficiency optimum), the current velocity
//!    (coast) and the maximum-braking one (the point of `W` closest to zero).
//! 2. **Collision filter.** Each sample is held constant over `horizon` seconds, as are the people's
//!    velocities. A sample is rejected if the minimum centre distance to a person,
//!    `|d0 + t* dv|` with `t* = clamp(-(d0·dv)/|dv|², 0, horizon)`, is below
//!    `radius + r_i + safety_margin`, or if the swept segment `pos → pos + v * horizon` comes within
//!    `radius + safety_margin` of a wall edge (exact segment-segment distance). A pair that is
//!    *already* closer than its bound does not reject a sample that does not bring it closer (the
//!    minimum over the horizon is at `t = 0`), so a robot inside a margin can always back away.
//!    With [`social_momentum_shaped`] an agent may instead be an [`AgentShape::Gaussian`]
//!    (Sousa et al. 2022 §4.5): its fully asymmetric Gaussian's keep-out region is tested the same
//!    way, exactly (see [`GaussianSpace`] and the `gaussian` submodule's docs for the choices
//!    where the paper is silent).
//! 3. **Score.** Efficiency `E(v) = -|pos + v * projection_time - partial_goal|`. For each person
//!    in the reactive set (within `sensing_range` and within `field_of_view` about the robot's
//!    heading), the pairwise angular momentum about the pair's midpoint with unit masses is
//!    `L_i = ½ det(pos - p_i, vel - v_i)` now and `L̂_i(v) = ½ det(pos - p_i, v - v_i)` for the
//!    action (the midpoint form `det(p̂_R - ĉ, v) + det(p̂_i - ĉ, v_i)` reduces exactly to this for
//!    any projection time; see [`angular_momentum`]). The momentum term is
//!    `SM(v) = Σ w_i |L̂_i(v)|` when `sign(L̂_i(v)) = s_i` for every reactive person, else 0
//!    (all-or-nothing, the 2022 form; `per_agent_mask` switches to a per-person mask), with
//!    `w_i ∝ weight_i / |pos - p_i|` normalised to sum 1. `E` is normalised to `[0, 1]` and `SM` to
//!    `[0, 1]` over the collision-free samples; the chosen velocity maximises `E + λ SM` (the
//!    first sample wins a tie, so the result is deterministic).
//! 4. **Comfort** (our addition; the papers' robot only keeps out of the intimate zone, which
//!    the collision filter enforces, while Daza et al. 2021 §3 ask it to respect personal zones
//!    too). For every agent with a comfort radius `R_i` (Hall's personal zone), the intrusion of a
//!    sample is the mean over the comfort horizon `T` of `max(0, R_i − |d0 + dv t|)`, sampled at
//!    [`COMFORT_SAMPLES`] instants; `C(v)` sums it over the agents. It is normalised as
//!    `(C − C_min) / max(C_max − C_min, COMFORT_SCALE)` over the collision-free samples (so a
//!    difference of a few millimetres barely counts) and the score becomes `E + λ SM − μ C`.
//!    The robot thus sidesteps early for a person walking at it, lets a person beside it walk on,
//!    and passes standing people wide where there is room; where there is none it still moves
//!    (the term only ranks samples, it rejects none). The part of a sample that backs away from
//!    the partial goal is left out of its intrusion (it counts as standing still), so comfort
//!    makes the robot slow down or step aside, never retreat along its way.
//!
//! 5. **Escape.** When the robot is already inside a person's bound (`radius + r_i +
//!    safety_margin`: someone walked up to it, or it was pushed), it takes the collision-free
//!    sample that opens the smallest such gap most over the projection time, whatever the goal:
//!    standing still there deadlocks with a person who waits for the robot to make way.
//!
//! # Passing convention (right-hand traffic)
//! The world frame is REP-103 (x forward, y left, counter-clockwise positive). A robot at the
//! origin moving along +x meets a person at `(4, 0)` moving along -x. Passing on the right means
//! each keeps to its own right: the robot moves to `y = -a`, the person to `y = +a`. Then
//! `pos - p_i = (-dx, -2a)`, `vel - v_i = (s, 0)` with `s > 0`, and
//! `L = ½ det((-dx, -2a), (s, 0)) = ½ (0 - (-2a) s) = a s > 0`: right-hand passing is a
//! counter-clockwise (positive) joint rotation, and the same sign holds for a standing person the
//! robot passes with the person on its left. So the required sign `s_i` of a person is
//! `sign(L_i)` when `|L_i| >= min_momentum` (respect the rotation already under way), and
//! [`PASSING_MOMENTUM_SIGN`] = +1 otherwise (exact head-on, slow or ambiguous encounters resolve to
//! the right, the same way every time).
//!
//! # Bad input
//! Any non-finite position, velocity, radius, weight, goal, limit, `dt` or parameter, a negative
//! radius, weight, gain or limit, `dt <= 0`, or a robot whose centre is inside a static polygon:
//! the function returns `None` (stop). It never panics and never returns a non-finite velocity.

use crate::control::Limits;
use crate::control::orca::nonholonomic::{NhParams, TrackingBound};
use crate::geom::cross;
use crate::map::StaticGeometry;
use crate::math::Vec2;

mod collision;
mod comfort;
pub mod gaussian;
mod window;

use collision::{Edge, Near, collides, nearby_edges};
use comfort::Comfort;
pub use gaussian::{AgentShape, GaussianSpace};
use window::action_set;

/// Sign of the pairwise angular momentum `L` that corresponds to passing on the right
/// (right-hand traffic) in the REP-103 world frame: +1 (counter-clockwise). See the module docs for
/// the derivation.
pub const PASSING_MOMENTUM_SIGN: f64 = if crate::control::PASS_ON_RIGHT { 1.0 } else { -1.0 };

/// The NH-ORCA constants with which a differential-drive robot's Social Momentum keeps to the
/// velocities it can track ([`social_momentum_shaped`]'s `unicycle`): a tracking error `E` of
/// 0.15 m and the settle time `T` of 0.4 s (the heading policy's time constant, as
/// [`crate::control::orca_crowd::NH_PARAMS`]'s). `E` was chosen on the differential robot's tuning
/// split (docs/choices.md): 0.02 m, NH-ORCA's, confined a robot dodging CrowdNav's 1 m/s walkers
/// to within 6° of its heading at full speed, and it was run into.
pub const UNICYCLE_TRACKING: NhParams = NhParams { tracking_error: 0.15, settle_time: 0.4 };

/// Instants at which a sample's comfort intrusion is evaluated over the comfort horizon.
pub const COMFORT_SAMPLES: usize = 6;
/// Smallest spread of the comfort intrusion (m) that the normalisation stretches to the full
/// weight: differences below it count in proportion.
pub const COMFORT_SCALE: f64 = 0.05;

/// Parameters of [`social_momentum`]. All lengths in metres, times in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SocialMomentumParams {
    /// Weight λ of the normalised momentum term against the normalised efficiency term
    /// (dimensionless, `>= 0`); default 2.0. The paper's value is unverified. The values usually
    /// swept (0.1, 0.3, 1) turn too late with the action set confined to the one-step
    /// acceleration window: a Pepper-limited robot
    /// (0.55 m/s, 0.55 m/s², dt = 0.1 s) meeting a non-reactive person walking head-on at 1 m/s
    /// from 8 m was run over for λ <= 1 and cleared the person for λ >= 2 (horizon 1.5 s).
    /// With the comfort term on, λ = 2 also took less time than 3 in the comparison suites'
    /// museum and care center (1.16x and 1.28x plain A*'s time to goal over 60 seeds, against
    /// 1.23x and 1.35x). 0 gives the pure-efficiency choice.
    pub lambda: f64,
    /// Number of rings of the polar action grid inside the acceleration window (`>= 0`); default 5.
    pub n_speeds: usize,
    /// Number of rays of the polar action grid, the first toward the partial goal (`>= 0`);
    /// default 24 (every 15°).
    pub n_headings: usize,
    /// Collision horizon `T_c` over which samples and people move at constant velocity
    /// (s, `>= 0`); default 1.5. The action set lies inside the acceleration window, so a long
    /// horizon leaves no feasible sample sooner against a person walking straight at the robot,
    /// and a short one reacts late (1.0-1.25 s failed the head-on test at λ = 2).
    pub horizon: f64,
    /// Extra clearance added to every radius sum and to the robot's radius against walls
    /// (m, `>= 0`); default 0.1.
    pub safety_margin: f64,
    /// Time over which a sample is projected to score efficiency (s, `> 0`); default 1.0.
    pub projection_time: f64,
    /// People farther than this do not enter the momentum term (m, `>= 0`, may be infinite);
    /// default 5.0. Every person is still considered by the collision filter.
    pub sensing_range: f64,
    /// Full angle of the cone about the robot's heading (its velocity, or the goal direction when
    /// nearly stopped) inside which people enter the momentum term (rad, in `[0, 2π]`); default π
    /// (people in front, ±90°).
    pub field_of_view: f64,
    /// Below this `|L_i|` (m²/s, `>= 0`) a person's current rotation sense is treated as
    /// undecided and the preferred sign is [`PASSING_MOMENTUM_SIGN`]; default 0.05.
    pub min_momentum: f64,
    /// `false` (default): the momentum term is zero for a sample that flips the rotation sense of
    /// any reactive person (the 2022 all-or-nothing form). `true`: only the flipped persons'
    /// terms are dropped.
    pub per_agent_mask: bool,
    /// Weight μ of the normalised comfort term (dimensionless, `>= 0`): the intrusion of a sample
    /// into the agents' comfort zones ([`Agent::comfort`]) is subtracted, `E + λ SM − μ C`;
    /// default 3.0. 0 gives the plain Social Momentum of the papers (which only keeps out of the
    /// intimate zone, through the collision filter).
    pub comfort_weight: f64,
    /// Horizon over which the comfort intrusion is integrated (s, `>= 0`); default 3.0: long
    /// enough to see a person walking at the robot from beyond their personal zone (a closing
    /// speed of 1.5 m/s covers 4.5 m).
    pub comfort_horizon: f64,
}

impl Default for SocialMomentumParams {
    fn default() -> Self {
        SocialMomentumParams {
            lambda: 2.0,
            n_speeds: 5,
            n_headings: 24,
            horizon: 1.5,
            safety_margin: 0.1,
            projection_time: 1.0,
            sensing_range: 5.0,
            field_of_view: std::f64::consts::PI,
            min_momentum: 0.05,
            per_agent_mask: false,
            comfort_weight: 3.0,
            comfort_horizon: 3.0,
        }
    }
}

impl SocialMomentumParams {
    fn is_valid(&self) -> bool {
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        nonneg(self.lambda)
            && nonneg(self.horizon)
            && nonneg(self.safety_margin)
            && self.projection_time.is_finite()
            && self.projection_time > 0.0
            && !self.sensing_range.is_nan()
            && self.sensing_range >= 0.0
            && nonneg(self.field_of_view)
            && self.field_of_view <= std::f64::consts::TAU
            && nonneg(self.min_momentum)
            && nonneg(self.comfort_weight)
            && nonneg(self.comfort_horizon)
    }
}

/// Another moving body the robot reasons about: a person, or a member of a group given as an
/// individual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Agent {
    /// Position in the world frame (m).
    pub pos: Vec2,
    /// Estimated velocity in the world frame (m/s), assumed constant over the horizon.
    pub vel: Vec2,
    /// Body radius (m, `>= 0`).
    pub radius: f64,
    /// Importance in the momentum term (dimensionless, `>= 0`; 1 for an individual, heavier for
    /// group members, 0 to ignore the person in the momentum term but not in the collision filter).
    pub weight: f64,
    /// Radius of the agent's comfort zone (m, centre distance to the robot's centre, `>= 0`): the
    /// robot prefers samples that keep it outside (Hall's personal zone for a person, 1.2 m by
    /// default); 0 for none (other robots).
    pub comfort: f64,
}

impl Agent {
    fn is_valid(&self) -> bool {
        finite2(self.pos)
            && finite2(self.vel)
            && self.radius.is_finite()
            && self.radius >= 0.0
            && self.weight.is_finite()
            && self.weight >= 0.0
            && self.comfort.is_finite()
            && self.comfort >= 0.0
    }
}

/// Pairwise angular momentum (m²/s) of the robot `(p_r, v_r)` and a person `(p_i, v_i)` about
/// their midpoint with unit masses, z component: `det(p_r - c, v_r) + det(p_i - c, v_i)` with
/// `c = (p_r + p_i)/2`, which equals `½ det(p_r - p_i, v_r - v_i)`. Positive (counter-clockwise)
/// for a pass on the right; translation invariant. Example: robot at the origin moving at (1, 0),
/// person at (4, 1) moving at (-1, 0): `L = 1.0`; exact head-on: `L = 0`.
pub fn angular_momentum(p_r: Vec2, v_r: Vec2, p_i: Vec2, v_i: Vec2) -> f64 {
    0.5 * cross(p_r - p_i, v_r - v_i)
}

/// Chooses the robot's velocity with Social Momentum (see the module docs for the algorithm).
///
/// - `pos`, `vel`: the robot's position (m) and current velocity command (m/s), world frame;
/// - `radius`: the robot's radius (m, `>= 0`);
/// - `partial_goal`: the point on the global path to head for (m);
/// - `others`: the people, group members given as individuals;
/// - `geom`: static geometry; samples whose straight motion over the horizon would bring the
///   robot within `radius + safety_margin` of a wall are rejected;
/// - `limits`: `max_speed` (m/s) and `max_accel` (m/s², may be infinite) bound the action set:
///   every returned velocity has norm `<= max_speed` and lies within `max_accel * dt` of `vel`
///   (when `|vel| > max_speed + max_accel * dt` both cannot hold; the speed bound wins, as in
///   [`Limits::apply`]);
/// - `dt`: the control period (s, `> 0`).
///
/// Returns `None` (stop) when every sample collides, and for any bad input (module docs).
#[allow(clippy::too_many_arguments)]
pub fn social_momentum(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    partial_goal: Vec2,
    others: &[Agent],
    geom: Option<&StaticGeometry>,
    limits: &Limits,
    dt: f64,
    params: &SocialMomentumParams,
) -> Option<Vec2> {
    social_momentum_shaped(pos, vel, radius, partial_goal, others, &[], geom, limits, dt, params, None)
}

/// [`social_momentum`] with a keep-out shape per agent: `shapes[i]` is the shape of `others[i]`
/// ([`AgentShape::Disc`], or [`AgentShape::Gaussian`] for Sousa et al. 2022 §4.5: the people's
/// and groups' fully asymmetric Gaussians with their socialization features, a group as one
/// individual; see [`GaussianSpace`] for how a Gaussian enters the collision
/// filter). An empty `shapes` means every agent is a disc, which is exactly
/// [`social_momentum`]. Returns `None` (stop) also when `shapes` is neither empty nor as long as
/// `others`.
///
/// `unicycle` is `Some` for a differential-drive robot (Social Momentum under its kinematic
/// constraint; our extension, after NH-ORCA, Alonso-Mora et al. 2010, see
/// [`crate::control::orca::nonholonomic`]): every sample of the action set is shortened to a
/// velocity the robot can track within the error `E` ([`TrackingBound::clip`]), and the robot's
/// radius is enlarged by `E` against people and walls, so that the collision filter's straight
/// motion holds for the robot tracking the chosen velocity. A shortened sample may lie outside
/// the acceleration window; the command's limits ([`Limits::apply_unicycle`]) bound it.
#[allow(clippy::too_many_arguments)]
pub fn social_momentum_shaped(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    partial_goal: Vec2,
    others: &[Agent],
    shapes: &[AgentShape],
    geom: Option<&StaticGeometry>,
    limits: &Limits,
    dt: f64,
    params: &SocialMomentumParams,
    unicycle: Option<TrackingBound>,
) -> Option<Vec2> {
    if !inputs_valid(pos, vel, radius, partial_goal, others, limits, dt, params)
        || !(shapes.is_empty() || shapes.len() == others.len())
        || unicycle.is_some_and(|u| !tracking_valid(&u))
    {
        return None;
    }
    let radius = radius + unicycle.map_or(0.0, |u| u.params.tracking_error);
    let vmax = limits.max_speed;
    // Beyond |vel| + vmax the acceleration disc contains the whole speed disc: cap it there so an
    // infinite acceleration limit stays finite.
    let reach = (limits.max_accel * dt).min(vel.norm() + vmax);
    let wall_bound = radius + params.safety_margin;
    let edges = nearby_edges(pos, geom, vmax * params.horizon + wall_bound)?;
    let to_goal = partial_goal - pos;
    let heading = if vel.norm() > 1e-6 {
        Some(vel / vel.norm())
    } else if to_goal.norm() > 1e-9 {
        Some(to_goal / to_goal.norm())
    } else {
        None
    };
    let (near, reactive) = people_sets(pos, vel, radius, heading, others, shapes, vmax, params);
    let goal_dir = if to_goal.norm() > 1e-9 {
        to_goal / to_goal.norm()
    } else {
        heading.unwrap_or_else(|| Vec2::new(1.0, 0.0))
    };
    let mut samples = action_set(vel, to_goal, goal_dir, reach, vmax, params);
    if let Some(u) = unicycle {
        for v in &mut samples {
            *v = u.clip(*v);
        }
    }
    let comfort = Comfort::new(pos, vel, goal_dir, others, limits, dt, params);
    let scene = Scene { pos, partial_goal, wall_bound, edges: &edges, near: &near, reactive: &reactive };
    let feasible = feasible_samples(&scene, &samples, &comfort, params);
    if feasible.is_empty() {
        return None;
    }
    // Inside someone's keep-out bound already (they came up to the robot, or the robot was
    // pushed): get out first. Waiting there deadlocks with a person who yields to the robot.
    let intruded: Vec<&Near> = near.iter().filter(|a| a.contains(pos - a.pos)).collect();
    if !intruded.is_empty() {
        return escape(pos, &intruded, &feasible, params.projection_time);
    }
    best_score(&feasible, params)
}

/// Step 0 of [`social_momentum`]: anything non-finite or out of range stops the robot.
#[allow(clippy::too_many_arguments)]
fn inputs_valid(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    partial_goal: Vec2,
    others: &[Agent],
    limits: &Limits,
    dt: f64,
    params: &SocialMomentumParams,
) -> bool {
    finite2(pos)
        && finite2(vel)
        && finite2(partial_goal)
        && radius.is_finite()
        && radius >= 0.0
        && dt.is_finite()
        && dt > 0.0
        && limits.max_speed.is_finite()
        && limits.max_speed >= 0.0
        && limits.max_accel >= 0.0 // false for NaN; +inf allowed
        && params.is_valid()
        && others.iter().all(Agent::is_valid)
}

/// A [`TrackingBound`] [`social_momentum_shaped`] accepts: finite, non-negative limits and
/// positive NH-ORCA constants.
fn tracking_valid(u: &TrackingBound) -> bool {
    u.heading.is_finite()
        && u.max_speed.is_finite()
        && u.max_speed >= 0.0
        && u.max_turn.is_finite()
        && u.max_turn >= 0.0
        && u.params.tracking_error.is_finite()
        && u.params.tracking_error > 0.0
        && u.params.settle_time.is_finite()
        && u.params.settle_time > 0.0
}

/// A person in the momentum term.
struct Reactive {
    /// pos - p_i
    d0: Vec2,
    /// ½ det(d0, v_i)
    k: f64,
    /// Required rotation sense (±1).
    sign: f64,
    /// Normalised weight.
    w: f64,
}

/// The people that could be met within the horizon (collision filter) and the reactive set
/// (momentum term, with normalised inverse-distance weights and required rotation senses).
#[allow(clippy::too_many_arguments)]
fn people_sets(
    pos: Vec2,
    vel: Vec2,
    radius: f64,
    heading: Option<Vec2>,
    others: &[Agent],
    shapes: &[AgentShape],
    vmax: f64,
    params: &SocialMomentumParams,
) -> (Vec<Near>, Vec<Reactive>) {
    let horizon = params.horizon;
    let mut near: Vec<Near> = Vec::new();
    let mut reactive: Vec<Reactive> = Vec::new();
    let cos_half_fov = (0.5 * params.field_of_view).cos();
    let mut weight_sum = 0.0;
    for (i, a) in others.iter().enumerate() {
        let d0 = pos - a.pos;
        let dist = d0.norm();
        let bound = radius + a.radius + params.safety_margin;
        let gaussian = match shapes.get(i) {
            Some(AgentShape::Gaussian(g)) => Some((*g, g.level(params.safety_margin))),
            _ => None,
        };
        let g_reach = gaussian.map_or(0.0, |(g, _)| g.reach(params.safety_margin));
        let reach = bound.max(g_reach);
        if dist - reach <= (vmax + a.vel.norm()) * horizon {
            let gaussian_reach = g_reach * (1.0 + 1e-9) + 1e-9;
            near.push(Near { pos: a.pos, vel: a.vel, bound2: bound * bound, gaussian, gaussian_reach });
        }
        let in_fov = match heading {
            Some(h) => params.field_of_view >= std::f64::consts::TAU || (-d0).dot(&h) >= dist * cos_half_fov,
            None => true,
        };
        if dist <= params.sensing_range && in_fov && a.weight > 0.0 {
            let l_now = 0.5 * cross(d0, vel - a.vel);
            let sign =
                if l_now.abs() >= params.min_momentum { l_now.signum() } else { PASSING_MOMENTUM_SIGN };
            // Inverse distance, guarded against coincident centres.
            let w = a.weight / dist.max(1e-6);
            weight_sum += w;
            reactive.push(Reactive { d0, k: 0.5 * cross(d0, a.vel), sign, w });
        }
    }
    if weight_sum > 0.0 {
        for r in &mut reactive {
            r.w /= weight_sum;
        }
    }
    (near, reactive)
}

/// What the collision filter and the scores of one step look at.
struct Scene<'a> {
    pos: Vec2,
    partial_goal: Vec2,
    /// `radius + safety_margin` (m).
    wall_bound: f64,
    edges: &'a [Edge],
    near: &'a [Near],
    reactive: &'a [Reactive],
}

/// A collision-free sample with its raw efficiency, momentum and comfort terms.
#[derive(Clone, Copy)]
struct Scored {
    v: Vec2,
    e: f64,
    sm: f64,
    c: f64,
}

/// Steps 2-4 of [`social_momentum`]: the collision-free samples with their raw scores.
fn feasible_samples(
    scene: &Scene,
    samples: &[Vec2],
    comfort: &Comfort,
    params: &SocialMomentumParams,
) -> Vec<Scored> {
    let mut feasible: Vec<Scored> = Vec::with_capacity(samples.len());
    for &v in samples {
        if !finite2(v) || collides(scene, v, params.horizon) {
            continue;
        }
        let e = -(scene.pos + v * params.projection_time - scene.partial_goal).norm();
        let mut sm = 0.0;
        let mut all_kept = true;
        for r in scene.reactive {
            let l = 0.5 * cross(r.d0, v) - r.k;
            if l * r.sign > 0.0 {
                sm += r.w * l.abs();
            } else {
                all_kept = false;
                if !params.per_agent_mask {
                    // All or nothing: the term is 0 whatever the others give.
                    break;
                }
            }
        }
        if !params.per_agent_mask && !all_kept {
            sm = 0.0;
        }
        feasible.push(Scored { v, e, sm, c: 0.0 });
    }
    comfort.intrusions(&mut feasible);
    feasible
}

/// Step 5 of [`social_momentum`]: the feasible sample that opens the smallest gap to the intruded
/// people most over the projection time `tau` (s); `None` if it would stand still.
fn escape(pos: Vec2, intruded: &[&Near], feasible: &[Scored], tau: f64) -> Option<Vec2> {
    let gap = |v: Vec2| intruded.iter().map(|a| a.gap(pos + v * tau, tau)).fold(f64::INFINITY, f64::min);
    let mut best: Option<(Vec2, f64)> = None;
    for s in feasible {
        let g = gap(s.v);
        if best.is_none_or(|(_, b)| g > b) {
            best = Some((s.v, g));
        }
    }
    best.map(|(v, _)| v).filter(|v| finite2(*v) && v.norm() > 1e-9)
}

/// Step 3 of [`social_momentum`]: normalise the terms over the feasible samples and take the
/// sample maximising `E + λ SM − μ C` (the first wins a tie).
fn best_score(feasible: &[Scored], params: &SocialMomentumParams) -> Option<Vec2> {
    let (mut e_min, mut e_max, mut sm_max) = (f64::INFINITY, f64::NEG_INFINITY, 0.0f64);
    let (mut c_min, mut c_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for s in feasible {
        e_min = e_min.min(s.e);
        e_max = e_max.max(s.e);
        sm_max = sm_max.max(s.sm);
        c_min = c_min.min(s.c);
        c_max = c_max.max(s.c);
    }
    let e_range = e_max - e_min;
    let c_range = (c_max - c_min).max(COMFORT_SCALE);
    let mut best: Option<(Vec2, f64)> = None;
    for s in feasible {
        let e_n = if e_range > 1e-12 { (s.e - e_min) / e_range } else { 1.0 };
        let sm_n = if sm_max > 1e-12 { s.sm / sm_max } else { 0.0 };
        let c_n = (s.c - c_min) / c_range;
        let score = e_n + params.lambda * sm_n - params.comfort_weight * c_n;
        if best.is_none_or(|(_, sc)| score > sc) {
            best = Some((s.v, score));
        }
    }
    best.map(|(v, _)| v).filter(|v| finite2(*v))
}

#[inline]
fn finite2(v: Vec2) -> bool {
    v.x.is_finite() && v.y.is_finite()
}

#[cfg(test)]
mod tests;
