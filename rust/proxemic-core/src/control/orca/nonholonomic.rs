//! NH-ORCA: ORCA for differential-drive robots, after J. Alonso-Mora, A. Breitenmoser, M. Rufli,
//! P. Beardsley and R. Siegwart, "Optimal Reciprocal Collision Avoidance for Multiple
//! Non-Holonomic Robots", Distributed Autonomous Robotic Systems (DARS 2010), Springer STAR 83,
//! 2013, pp. 203-216.
//!
//! A differential-drive robot cannot move along an arbitrary holonomic velocity `u`, but it can
//! track one within a bounded error. The paper's construction, as used here:
//! 1. **Tracking.** To follow `u` (speed `V`, at angle `θ` from the heading) the robot drives an
//!    arc of constant forward speed `v` and turn rate `ω = θ / T` until it faces `u` after the
//!    time `T`, then goes straight at `u`. Choosing `v` to minimise the distance at `T` between the
//!    robot and the point moving at `u` gives (our derivation of the paper's closed form):
//!    `v = V (θ/2) cot(θ/2)` (`v = V` at `θ = 0`), and that distance, the largest tracking error
//!    of the manoeuvre, is `ε(V, θ) = V T |sin(θ/2)|` (after `T` the robot moves parallel to the
//!    point, so the error stays).
//! 2. **The velocities it can track.** With a tracking error bound `E`, the allowed holonomic
//!    velocities are those with `V ≤ E / (T |sin(θ/2)|)`, within the ORCA speed disc. The
//!    paper's `T` is a constant; a robot turning at most `ω_max` cannot turn by `θ` in `T` when
//!    `|θ| > ω_max T`, so here `T` becomes `T_θ = max(T, |θ| / ω_max)` for such angles (our choice:
//!    the paper's wheel-speed bound has no separate turn-rate limit). The region is approximated
//!    from inside by a convex polygon ([`TrackableSet`]), whose edges enter ORCA's linear
//!    program as hard constraints (beside the obstacles').
//! 3. **The enlarged body.** The robot is seen by everyone, and sees itself, with its radius
//!    enlarged by `E`, so that avoidance planned for the holonomic point holds for the tracking
//!    robot.
//!
//! Units: metres, seconds, radians; world frame. Parameters: [`NhParams`].

use crate::control::orca::Line;
use crate::math::{Vec2, wrap_angle};

/// NH-ORCA's two constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NhParams {
    /// `E`, the tracking error allowed (m, > 0): added to the robot's radius, and the bound on
    /// the error of the tracking manoeuvre.
    pub tracking_error: f64,
    /// `T`, the time to turn to the holonomic velocity's direction (s, > 0).
    pub settle_time: f64,
}

/// Vertices of the polygon approximating the allowed velocities ([`TrackableSet`]).
const POLYGON_VERTICES: usize = 24;

/// Directions at which the polygon is checked to lie inside the allowed set.
const CHECK_DIRECTIONS: usize = 360;

/// The largest holonomic speed (m/s) a robot with forward speed limit `max_speed` (m/s) and turn
/// rate limit `max_turn` (rad/s) can track within `p.tracking_error` at the angle `theta` (rad)
/// from its heading: `min(max_speed, E / (T_θ |sin(θ/2)|))`, `T_θ = max(T, |θ| / max_turn)`.
pub fn max_tracked_speed(theta: f64, max_speed: f64, max_turn: f64, p: NhParams) -> f64 {
    let a = wrap_angle(theta).abs();
    let settle = if max_turn > 0.0 { p.settle_time.max(a / max_turn) } else { p.settle_time };
    let s = (a / 2.0).sin();
    if s * settle * max_speed <= p.tracking_error { max_speed } else { p.tracking_error / (settle * s) }
}

/// The tracking command `(v, ω)` (m/s, rad/s) of step 1 for the holonomic velocity `u` (m/s,
/// world frame) from heading `theta` (rad): turn rate `θ / T_θ` and forward speed
/// `|u| (θ/2) cot(θ/2)`, never negative (`θ` the angle from the heading to `u`). A zero `u` is a
/// stop with no turn.
pub fn track(u: Vec2, theta: f64, max_turn: f64, p: NhParams) -> (f64, f64) {
    let speed = u.norm();
    if !(speed.is_finite() && speed > 1e-9) {
        return (0.0, 0.0);
    }
    let th = wrap_angle(u.y.atan2(u.x) - theta);
    let a = th.abs();
    let settle = if max_turn > 0.0 { p.settle_time.max(a / max_turn) } else { p.settle_time };
    let v = if a < 1e-9 { speed } else { speed * (a / 2.0) / (a / 2.0).tan() };
    (v.max(0.0), th / settle)
}

/// A differential-drive robot as a sampling local planner (Social Momentum) sees it: the
/// velocities it can track from its `heading` are [`max_tracked_speed`]'s, exactly (no polygon:
/// the planner's samples are shortened one by one, [`TrackingBound::clip`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackingBound {
    /// Heading (rad).
    pub heading: f64,
    /// Forward speed limit (m/s, `>= 0`).
    pub max_speed: f64,
    /// Turn rate limit (rad/s, `>= 0`; 0 means no separate limit).
    pub max_turn: f64,
    /// The tracking error `E` and settle time `T`.
    pub params: NhParams,
}

impl TrackingBound {
    /// `v` (world frame, m/s) shortened along its own direction to the largest speed the robot
    /// can track there ([`max_tracked_speed`] at `v`'s angle from the heading); a zero or
    /// non-finite `v` is returned as it is.
    pub fn clip(&self, v: Vec2) -> Vec2 {
        let n = v.norm();
        if !(n.is_finite() && n > 0.0) {
            return v;
        }
        let cap =
            max_tracked_speed(v.y.atan2(v.x) - self.heading, self.max_speed, self.max_turn, self.params);
        if n > cap { v * (cap / n) } else { v }
    }
}

/// The velocities [`max_tracked_speed`] allows a robot, as a convex polygon inside them in the
/// robot's own frame (x along the heading): made once per robot, turned to its heading each step
/// ([`TrackableSet::lines`]). The polygon: 24 points on the set's boundary at evenly spaced angles,
/// their convex hull, shrunk about the origin until it lies inside the set at 360 directions (the
/// set need not be convex, the hull must be inside it: our choice, the paper approximates it by a
/// polygon without saying how).
#[derive(Clone, Debug, PartialEq)]
pub struct TrackableSet {
    /// Counter-clockwise hull of the boundary points, robot frame (m/s), before `scale`.
    hull: Vec<Vec2>,
    /// The shrink factor that puts the hull inside the set (<= 1).
    scale: f64,
}

impl TrackableSet {
    /// The set of a robot with forward speed limit `max_speed` (m/s) and turn rate limit
    /// `max_turn` (rad/s) for the tracking error and settle time of `p`.
    pub fn new(max_speed: f64, max_turn: f64, p: NhParams) -> Self {
        let boundary = |a: f64| {
            let r = max_tracked_speed(a, max_speed, max_turn, p);
            Vec2::new(a.cos(), a.sin()) * r
        };
        let pts: Vec<Vec2> = (0..POLYGON_VERTICES)
            .map(|k| {
                boundary(-std::f64::consts::PI + std::f64::consts::TAU * k as f64 / POLYGON_VERTICES as f64)
            })
            .collect();
        let hull = convex_hull(pts);
        // The hull's reach along each direction against the set's: the smallest ratio shrinks it.
        let mut scale: f64 = 1.0;
        if hull.len() >= 3 {
            for k in 0..CHECK_DIRECTIONS {
                let a = -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / CHECK_DIRECTIONS as f64;
                let d = Vec2::new(a.cos(), a.sin());
                let reach = ray_reach(&hull, d);
                if reach > 0.0 {
                    scale = scale.min(max_tracked_speed(a, max_speed, max_turn, p) / reach);
                }
            }
        }
        TrackableSet { hull, scale }
    }

    /// Appends to `out` the polygon's half-planes (feasible side on the left of each [`Line`],
    /// ORCA's convention) for the robot at heading `theta` (rad), in the world frame; none when
    /// the polygon is degenerate.
    pub fn lines(&self, theta: f64, out: &mut Vec<Line>) {
        let hull = &self.hull;
        if hull.len() < 3 {
            return;
        }
        let (s, c) = theta.sin_cos();
        let world = |q: Vec2| Vec2::new(c * q.x - s * q.y, s * q.x + c * q.y) * self.scale;
        for k in 0..hull.len() {
            let a = world(hull[k]);
            let b = world(hull[(k + 1) % hull.len()]);
            let e = b - a;
            let n = e.norm();
            if n > 1e-12 {
                out.push(Line { point: a, dir: e / n });
            }
        }
    }
}

/// Counter-clockwise convex hull of `pts` (Andrew's monotone chain), collinear points dropped.
fn convex_hull(mut pts: Vec<Vec2>) -> Vec<Vec2> {
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let turn = |o: Vec2, a: Vec2, b: Vec2| (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    let mut hull: Vec<Vec2> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Vec2>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &q in iter {
            while hull.len() >= start + 2 && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0 {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// How far from the origin the ray along the unit `d` leaves the convex polygon `hull` (which
/// contains the origin); 0 when it does not contain it.
fn ray_reach(hull: &[Vec2], d: Vec2) -> f64 {
    let mut best = f64::INFINITY;
    for k in 0..hull.len() {
        let a = hull[k];
        let e = hull[(k + 1) % hull.len()] - a;
        // Solve t d = a + s e for t >= 0, s in [0, 1].
        let den = d.x * e.y - d.y * e.x;
        if den.abs() < 1e-15 {
            continue;
        }
        let t = (a.x * e.y - a.y * e.x) / den;
        let s = (a.x * d.y - a.y * d.x) / den;
        if t >= 0.0 && (-1e-12..=1.0 + 1e-12).contains(&s) {
            best = best.min(t);
        }
    }
    if best.is_finite() { best } else { 0.0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: NhParams = NhParams { tracking_error: 0.1, settle_time: 0.4 };

    /// The manoeuvre of step 1 integrated in small steps: the largest distance to the point
    /// moving at `u` over `[0, T_θ + 1 s]`.
    fn simulated_error(u: Vec2, max_turn: f64) -> f64 {
        let (v, w) = track(u, 0.0, max_turn, P);
        let th = u.y.atan2(u.x);
        let settle = P.settle_time.max(th.abs() / max_turn);
        let (mut x, mut y, mut h, dt) = (0.0, 0.0, 0.0_f64, 1e-4);
        let mut worst: f64 = 0.0;
        let mut t = 0.0;
        while t < settle + 1.0 {
            let (vv, ww) = if t < settle { (v, w) } else { (u.norm(), 0.0) };
            x += vv * h.cos() * dt;
            y += vv * h.sin() * dt;
            h += ww * dt;
            t += dt;
            worst = worst.max(((x - u.x * t).powi(2) + (y - u.y * t).powi(2)).sqrt());
        }
        worst
    }

    #[test]
    fn the_tracking_error_is_the_closed_form_and_at_most_the_bound_on_the_allowed_set() {
        for deg in [10.0_f64, 45.0, 90.0, 135.0, 170.0] {
            let th = deg.to_radians();
            let speed = max_tracked_speed(th, 0.55, 2.0, P);
            let u = Vec2::new(th.cos(), th.sin()) * speed;
            let err = simulated_error(u, 2.0);
            assert!(err <= P.tracking_error + 2e-3, "{deg} deg: error {err} at {speed} m/s");
            let settle = P.settle_time.max(th / 2.0);
            let closed = speed * settle * (th / 2.0).sin();
            assert!((err - closed).abs() < 2e-3, "{deg} deg: simulated {err}, closed form {closed}");
        }
        // Straight ahead: the full speed, no error; the cap never exceeds the speed limit.
        assert_eq!(max_tracked_speed(0.0, 0.55, 2.0, P), 0.55);
        assert!(max_tracked_speed(3.0, 0.55, 2.0, P) < 0.1);
    }

    #[test]
    fn the_polygon_lies_inside_the_allowed_set_and_turns_with_the_heading() {
        for heading in [0.0, 1.0, -2.5] {
            let mut lines = Vec::new();
            TrackableSet::new(0.55, 2.0, P).lines(heading, &mut lines);
            assert!(lines.len() >= 3);
            let inside = |q: Vec2| lines.iter().all(|l| crate::geom::cross(l.dir, q - l.point) >= -1e-12);
            assert!(inside(Vec2::zeros()));
            for k in 0..720 {
                let a = k as f64 * std::f64::consts::TAU / 720.0;
                let d = Vec2::new((heading + a).cos(), (heading + a).sin());
                let cap = max_tracked_speed(a, 0.55, 2.0, P);
                assert!(!inside(d * (cap * 1.001 + 1e-9)), "beyond the set at {a} rad is inside the polygon");
            }
            // Forward at nearly full speed is allowed; sideways much less; backwards hardly.
            let fwd = Vec2::new(heading.cos(), heading.sin());
            let side = Vec2::new(-heading.sin(), heading.cos());
            assert!(inside(fwd * 0.5));
            assert!(!inside(side * 0.3));
            assert!(!inside(-fwd * 0.1));
        }
    }

    #[test]
    fn a_clipped_velocity_keeps_its_direction_at_the_largest_trackable_speed() {
        for heading in [0.0, 1.0, -2.5] {
            let b = TrackingBound { heading, max_speed: 0.55, max_turn: 2.0, params: P };
            for k in 0..72 {
                let a = k as f64 * std::f64::consts::TAU / 72.0;
                let d = Vec2::new((heading + a).cos(), (heading + a).sin());
                let cap = max_tracked_speed(a, 0.55, 2.0, P);
                let out = b.clip(d * 2.0);
                assert!(
                    (out.norm() - cap).abs() < 1e-12 && (out.normalize() - d).norm() < 1e-9,
                    "{a}: {out:?}"
                );
                // Already trackable: unchanged.
                assert_eq!(b.clip(d * (0.5 * cap)), d * (0.5 * cap));
            }
            assert_eq!(b.clip(Vec2::zeros()), Vec2::zeros());
        }
    }

    #[test]
    fn tracking_turns_first_and_never_reverses() {
        let (v, w) = track(Vec2::new(0.5, 0.0), 0.0, 2.0, P);
        assert!((v - 0.5).abs() < 1e-12 && w == 0.0);
        let (v, w) = track(Vec2::new(0.0, 0.3), 0.0, 2.0, P);
        assert!(v > 0.0 && v < 0.3 && (w - 2.0).abs() < 1e-9, "quarter turn at the turn limit: {v} {w}");
        let (v, w) = track(Vec2::new(-0.3, 1e-12), 0.0, 2.0, P);
        assert!(v.abs() < 1e-6 && w > 0.0 && w <= 2.0 + 1e-12);
        assert_eq!(track(Vec2::zeros(), 1.0, 2.0, P), (0.0, 0.0));
    }
}
