//! Local control: command limits and the path follower of the plain A* planner.
//!
//! Commands to the holonomic base are `(vx, vy, wz)` in the robot frame (metres per second and
//! radians per second). Every command, from a built-in planner or from a user's action, passes
//! through [`Limits::apply`], which enforces Pepper's limits (NAOqi `ALMotion` maxima): the norm of
//! the linear velocity at most `max_speed` (0.55 m/s), the change of the world-frame linear
//! velocity per control step at most `max_accel * dt` (0.55 m/s^2), `|wz|` at most
//! `max_angular_speed` (2.0 rad/s), and the change of `wz` at most `max_angular_accel * dt`
//! (3.0 rad/s^2). Acceleration is limited relative to the previous *command*, so the limit holds
//! on what the base is asked to do whatever the physics did.
//!
//! Submodules: [`mode_switch`] (the mode switch of Daza 2021 Algorithm 1 as the `social` planner
//! runs it, and each local planner's choice of mode), [`daza2021`] (Algorithm 1 as published, for
//! the `daza2021` and `sousa2022` planners), [`orca`], [`social_momentum`] and [`eband`] (the local planners),
//! [`orca_crowd`] (ORCA as the robots run it among people), [`progress`] (the progress monitor
//! and recovery every built-in planner runs), [`stop_and_wait`] (the `astar_stop` baseline's
//! rule: stop for whoever is in the way, re-plan around them after a wait), [`learned`] (the
//! `learned` planner's policy network, read from its array file) and [`yielding`]
//! (predictive yielding: rollouts against the people's predicted motion with a hard body gap,
//! the `social` planner's last word on its commands, `crate::world`'s yield step).
//!
//! Heading policy of the built-in follower: face the direction of motion (turn toward the
//! velocity's direction with a proportional gain); when nearly stopped, keep the heading.
//!
//! A differential-drive robot ([`Drive::Differential`]) is commanded `(v, wz)`: a forward speed
//! along its heading and a turn rate, never a sideways velocity. Every built-in planner still
//! computes a holonomic world-frame velocity `u` and the heading policy's turn rate; one rule
//! ([`Limits::unicycle_from_holonomic`]) turns them into the unicycle's command: the turn rate is
//! the heading policy's (a proportional turn toward `u`'s direction, gain
//! [`FollowerParams::heading_gain`]), the forward speed is `u`'s projection on the heading,
//! `v = max(0, u . h) = |u| max(0, cos e)` with `e` the heading error (the usual
//! holonomic-to-unicycle tracking: full speed when facing `u`, none when `u` is at or behind the
//! robot's side, which then turns in place). Then [`Limits::apply_unicycle`] limits `v` and `wz`
//! (speed, acceleration, angular speed, angular acceleration). The exception is the `astar_orca`
//! baseline, whose robot runs NH-ORCA ([`orca::nonholonomic`]): ORCA's velocity is one it can
//! track, and the command is the tracking manoeuvre's.

pub mod daza2021;
pub mod eband;
pub mod learned;
pub mod mode_switch;
pub mod orca;
pub mod orca_crowd;
pub mod progress;
pub mod social_momentum;
pub mod stop_and_wait;
pub mod yielding;

use crate::math::{Vec2, rotate, wrap_angle};

/// The project's one passing convention, shared by ORCA, Social Momentum and the pedestrians'
/// social force: in a perfectly symmetric encounter both parties pass on their own right
/// (right-hand traffic), so head-on meetings resolve the same way every time.
pub const PASS_ON_RIGHT: bool = true;

/// How a robot base moves: the robot's `drive` in a scenario's `[[robot]]`.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// Omnidirectional (Pepper): any velocity `(vx, vy)` in the plane and a turn rate `wz`.
    #[default]
    Holonomic,
    /// Differential drive (unicycle kinematics: TurtleBot, Jackal, a wheelchair): a forward
    /// speed `v` along the heading (negative: reverse) and a turn rate `wz`; no sideways motion.
    Differential,
}

impl Drive {
    /// The names accepted in scenario files and in scene names' `drive=` key.
    pub const NAMES: [&'static str; 2] = ["holonomic", "differential"];

    /// Whether this is [`Drive::Holonomic`] (the default, left out of a serialised robot).
    pub fn is_holonomic(&self) -> bool {
        *self == Drive::Holonomic
    }

    /// Parses a name of [`Drive::NAMES`].
    pub fn parse(name: &str) -> Option<Self> {
        match name {
            "holonomic" => Some(Drive::Holonomic),
            "differential" => Some(Drive::Differential),
            _ => None,
        }
    }

    /// The drive's name (as in [`Drive::NAMES`]).
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Motion limits of a robot base.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Maximum linear speed, norm of (vx, vy) (m/s). Pepper: 0.55.
    pub max_speed: f64,
    /// Maximum angular speed (rad/s). Pepper: 2.0.
    pub max_angular_speed: f64,
    /// Maximum linear acceleration (m/s^2). Pepper: 0.55.
    pub max_accel: f64,
    /// Maximum angular acceleration (rad/s^2). Pepper (NAOqi `MaxAccTheta`): 3.0.
    pub max_angular_accel: f64,
}

impl Limits {
    /// Pepper's limits.
    pub const PEPPER: Limits =
        Limits { max_speed: 0.55, max_angular_speed: 2.0, max_accel: 0.55, max_angular_accel: 3.0 };

    /// Limits a desired world-frame command `(v, wz)` given the previous world-frame command,
    /// over a control period `dt`. Non-finite desired values are treated as a request to stop.
    pub fn apply(
        &self,
        desired_v: Vec2,
        desired_wz: f64,
        prev_v: Vec2,
        prev_wz: f64,
        dt: f64,
    ) -> (Vec2, f64) {
        let desired_v =
            if desired_v.x.is_finite() && desired_v.y.is_finite() { desired_v } else { Vec2::zeros() };
        let v = clamp_norm(desired_v, self.max_speed);
        let dv = clamp_norm(v - prev_v, self.max_accel * dt);
        let v = clamp_norm(prev_v + dv, self.max_speed);
        (v, self.limit_turn(desired_wz, prev_wz, dt))
    }

    /// Limits a unicycle's desired command, forward speed `desired_v` (m/s, negative: reverse)
    /// and turn rate `desired_wz` (rad/s), given the previous command `(prev_v, prev_wz)`, over
    /// `dt`: `|v| <= max_speed`, `|v - prev_v| <= max_accel * dt`, and `wz` as [`Limits::apply`]
    /// limits it. Non-finite desired values are a request to stop.
    pub fn apply_unicycle(
        &self,
        desired_v: f64,
        desired_wz: f64,
        prev_v: f64,
        prev_wz: f64,
        dt: f64,
    ) -> (f64, f64) {
        let desired_v = if desired_v.is_finite() { desired_v } else { 0.0 };
        let v = desired_v.clamp(-self.max_speed, self.max_speed);
        let dv = (v - prev_v).clamp(-self.max_accel * dt, self.max_accel * dt);
        let v = (prev_v + dv).clamp(-self.max_speed, self.max_speed);
        (v, self.limit_turn(desired_wz, prev_wz, dt))
    }

    /// The turn rate (rad/s) both drives execute for a desired `desired_wz` after `prev_wz`
    /// over `dt`: within `max_angular_speed`, changed by at most `max_angular_accel * dt`; a
    /// non-finite request is a request to stop turning.
    fn limit_turn(&self, desired_wz: f64, prev_wz: f64, dt: f64) -> f64 {
        let desired_wz = if desired_wz.is_finite() { desired_wz } else { 0.0 };
        let wz = desired_wz.clamp(-self.max_angular_speed, self.max_angular_speed);
        let dw = (wz - prev_wz).clamp(-self.max_angular_accel * dt, self.max_angular_accel * dt);
        (prev_wz + dw).clamp(-self.max_angular_speed, self.max_angular_speed)
    }

    /// The one rule turning a built-in planner's holonomic command into a differential-drive
    /// robot's (see the module docs): world-frame velocity `u` (m/s) and the heading policy's
    /// turn rate `wz` (rad/s) for a robot with heading `theta` (rad) whose previous world-frame
    /// command was `(prev_v, prev_wz)`; returns the limited world-frame command, which is always
    /// along the heading (`v = s (cos theta, sin theta)`, `s` the limited forward speed).
    pub fn unicycle_from_holonomic(
        &self,
        u: Vec2,
        wz: f64,
        theta: f64,
        prev_v: Vec2,
        prev_wz: f64,
        dt: f64,
    ) -> (Vec2, f64) {
        let h = Vec2::new(theta.cos(), theta.sin());
        let u = if u.x.is_finite() && u.y.is_finite() { u } else { Vec2::zeros() };
        self.unicycle_world(u.dot(&h).max(0.0), wz, theta, prev_v, prev_wz, dt)
    }

    /// A unicycle's limited command as a world-frame command: forward speed `s` (m/s) and turn
    /// rate `wz` (rad/s) limited by [`Limits::apply_unicycle`] against the previous world-frame
    /// command `(prev_v, prev_wz)` (its forward speed: its norm, negative when it pointed behind
    /// the heading `theta`), returned as `(s (cos theta, sin theta), wz)`.
    pub fn unicycle_world(
        &self,
        s: f64,
        wz: f64,
        theta: f64,
        prev_v: Vec2,
        prev_wz: f64,
        dt: f64,
    ) -> (Vec2, f64) {
        let h = Vec2::new(theta.cos(), theta.sin());
        let prev_s = if prev_v.dot(&h) < 0.0 { -prev_v.norm() } else { prev_v.norm() };
        let (s, wz) = self.apply_unicycle(s, wz, prev_s, prev_wz, dt);
        (h * s, wz)
    }
}

/// Scales `v` down to norm `max` if it is longer.
pub fn clamp_norm(v: Vec2, max: f64) -> Vec2 {
    let n = v.norm();
    if n > max && n > 0.0 { v * (max / n) } else { v }
}

/// World-frame velocity to robot-frame velocity for a robot with heading `theta`.
pub fn world_to_body(v: Vec2, theta: f64) -> Vec2 {
    rotate(v, -theta)
}

/// The robot-frame command `(vx, vy)` the base executes for a world-frame command `v` at heading
/// `theta`: [`world_to_body`]; for a differential drive (whose commands are along the heading
/// by construction) `vy` is exactly 0, not the rotation's rounding.
pub fn body_command(drive: Drive, v: Vec2, theta: f64) -> Vec2 {
    let b = world_to_body(v, theta);
    match drive {
        Drive::Holonomic => b,
        Drive::Differential => Vec2::new(b.x, 0.0),
    }
}

/// Robot-frame velocity to world-frame velocity.
pub fn body_to_world(v: Vec2, theta: f64) -> Vec2 {
    rotate(v, theta)
}

/// Parameters of the pure-pursuit path follower.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowerParams {
    /// Look-ahead distance along the path (metres); default 0.8.
    pub lookahead: f64,
    /// Proportional gain from heading error to angular velocity (1/s); default 2.5.
    pub heading_gain: f64,
    /// Distance from the path beyond which the path is re-planned (metres); default 1.0.
    pub replan_distance: f64,
    /// Below this speed (m/s) the heading is held rather than turned toward the motion; default 0.05.
    pub min_turn_speed: f64,
}

impl Default for FollowerParams {
    fn default() -> Self {
        FollowerParams { lookahead: 0.8, heading_gain: 2.5, replan_distance: 1.0, min_turn_speed: 0.05 }
    }
}

/// On an approach task the robot turns to face the person within this distance of the goal (m).
pub const APPROACH_FACING_DISTANCE: f64 = 1.0;

/// The built-in planners' heading policy: the angular velocity (rad/s, before limits) of a robot
/// at `pos` with heading `theta` (rad) moving at `desired` (world frame, m/s). It faces the
/// direction of motion, or holds its heading below `params.min_turn_speed`; on an approach task
/// (`face`, the person approached) it faces the person within [`APPROACH_FACING_DISTANCE`] of
/// `goal`.
pub fn heading_rate(
    pos: Vec2,
    theta: f64,
    desired: Vec2,
    face: Option<Vec2>,
    goal: Vec2,
    params: &FollowerParams,
) -> f64 {
    let gain = params.heading_gain;
    match face {
        Some(q) if (goal - pos).norm() < APPROACH_FACING_DISTANCE => {
            let to = q - pos;
            gain * wrap_angle(to.y.atan2(to.x) - theta)
        }
        _ if desired.norm() > params.min_turn_speed => gain * wrap_angle(desired.y.atan2(desired.x) - theta),
        _ => 0.0,
    }
}

/// Tracks a polyline path: finds the closest point ahead of the last one (progress never goes
/// backwards), aims at a look-ahead point, and slows down to stop at the end.
#[derive(Clone, Debug, Default)]
pub struct PathFollower {
    path: Vec<Vec2>,
    /// Cumulative arc length at each waypoint.
    arc: Vec<f64>,
    /// Arc-length position of the robot's projection on the path.
    progress: f64,
    params: FollowerParams,
}

/// What the follower asks for this step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FollowerOutput {
    /// Desired world-frame velocity (m/s), before limits.
    pub velocity: Vec2,
    /// Desired angular velocity (rad/s), before limits.
    pub wz: f64,
    /// Distance from the robot to its projection on the path (metres).
    pub cross_track: f64,
}

impl PathFollower {
    /// A follower for `path` (world-frame waypoints, at least one).
    pub fn new(path: Vec<Vec2>, params: FollowerParams) -> Self {
        let mut arc = Vec::with_capacity(path.len());
        let mut s = 0.0;
        for (k, p) in path.iter().enumerate() {
            if k > 0 {
                s += (p - path[k - 1]).norm();
            }
            arc.push(s);
        }
        PathFollower { path, arc, progress: 0.0, params }
    }

    /// The path being followed.
    pub fn path(&self) -> &[Vec2] {
        &self.path
    }

    /// Total path length (metres).
    pub fn length(&self) -> f64 {
        self.arc.last().copied().unwrap_or(0.0)
    }

    /// The follower's parameters.
    pub fn params(&self) -> &FollowerParams {
        &self.params
    }

    /// Point at arc length `s` (clamped to the path).
    fn point_at(&self, s: f64) -> Vec2 {
        if self.path.len() < 2 {
            return self.path.first().copied().unwrap_or_else(Vec2::zeros);
        }
        let s = s.clamp(0.0, self.length());
        let k = match self.arc.binary_search_by(|a| a.total_cmp(&s)) {
            Ok(k) => return self.path[k],
            Err(k) => k.clamp(1, self.path.len() - 1),
        };
        let (a, b) = (self.path[k - 1], self.path[k]);
        let seg = self.arc[k] - self.arc[k - 1];
        if seg <= 0.0 { b } else { a + (b - a) * ((s - self.arc[k - 1]) / seg) }
    }

    /// Projects `p` on the path, searching segments from the current progress up to
    /// `window` metres ahead; returns (arc length, distance).
    fn project(&self, p: Vec2, window: f64) -> (f64, f64) {
        let mut best = (self.progress, (p - self.point_at(self.progress)).norm());
        for k in 1..self.path.len() {
            if self.arc[k] < self.progress {
                continue;
            }
            if self.arc[k - 1] > self.progress + window {
                break;
            }
            let (a, b) = (self.path[k - 1], self.path[k]);
            let ab = b - a;
            let len2 = ab.norm_squared();
            let t = if len2 > 0.0 { ((p - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
            let s = (self.arc[k - 1] + t * len2.sqrt()).max(self.progress);
            let d = (p - self.point_at(s)).norm();
            if d < best.1 - 1e-12 {
                best = (s, d);
            }
        }
        best
    }

    /// The point `d` metres ahead of the current progress along the path (its end beyond it):
    /// the partial goal of the local planners.
    pub fn point_ahead(&self, d: f64) -> Vec2 {
        self.point_at(self.progress + d)
    }

    /// Distance from `p` to the path ahead of the current progress (metres), without advancing.
    pub fn step_preview_cross_track(&self, p: Vec2) -> f64 {
        self.project(p, 2.0 * self.params.lookahead + 1.0).1
    }

    /// One control step of `dt` seconds: robot at `p` with heading `theta`, with a maximum speed
    /// and acceleration used to plan the stop at the end of the path.
    pub fn step(&mut self, p: Vec2, theta: f64, max_speed: f64, max_accel: f64, dt: f64) -> FollowerOutput {
        self.step_visible(p, theta, max_speed, max_accel, dt, &|_, _| true)
    }

    /// [`PathFollower::step`] that never aims across an obstacle: when the straight line to the
    /// look-ahead point is not `visible`, the look-ahead is halved (down to 5 cm), so the robot
    /// does not cut inside corners such as doorways; it then heads along the path's direction
    /// with a cross-track correction (closing the gap over one look-ahead length) rather than
    /// straight at the nearby point.
    pub fn step_visible(
        &mut self,
        p: Vec2,
        theta: f64,
        max_speed: f64,
        max_accel: f64,
        dt: f64,
        visible: &dyn Fn(Vec2, Vec2) -> bool,
    ) -> FollowerOutput {
        let (s, cross) = self.project(p, 2.0 * self.params.lookahead + 1.0);
        self.progress = s;
        let mut ahead = self.params.lookahead;
        let mut target = self.point_at(s + ahead);
        while ahead > 0.05 && !visible(p, target) {
            ahead *= 0.5;
            target = self.point_at(s + ahead);
        }
        let remaining = (self.length() - s) + cross;
        let mut to_target = target - p;
        if ahead < self.params.lookahead {
            // The look-ahead point was hidden: rather than head straight for a point beside the
            // robot (which, off the path by SM or a push, aims square at the path and overshoots
            // it toward the wall it runs along), go along the path's direction here and close
            // the cross-track error over one look-ahead length.
            let here = self.point_at(s);
            let tangent = self.point_at(s + 0.05) - here;
            if tangent.norm() > 1e-9 {
                let dir = tangent / tangent.norm() + (here - p) / self.params.lookahead;
                to_target = dir * ahead.min(to_target.norm().max(1e-3)) / dir.norm().max(1e-9);
            }
        }
        let dist = to_target.norm();
        // Brake so as to stop at the end: v^2 = 2 a d, with 10% margin on the deceleration.
        // and never ask for more than the remaining distance in one step (no overshoot).
        let speed = max_speed.min((2.0 * 0.9 * max_accel * remaining).sqrt()).min(remaining / dt.max(1e-6));
        let velocity = if dist > 1e-6 { to_target * (speed / dist) } else { Vec2::zeros() };
        let wz = if velocity.norm() > self.params.min_turn_speed {
            self.params.heading_gain * wrap_angle(velocity.y.atan2(velocity.x) - theta)
        } else {
            0.0
        };
        FollowerOutput { velocity, wz, cross_track: cross }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_clamp_speed_norm_not_box() {
        let l = Limits::PEPPER;
        let (v, _) = l.apply(Vec2::new(1.0, 1.0), 0.0, Vec2::new(0.5, 0.2), 0.0, 10.0);
        assert!((v.norm() - 0.55).abs() < 1e-12);
        assert!((v.x - v.y).abs() < 1e-12);
    }

    #[test]
    fn limits_bound_acceleration() {
        let l = Limits::PEPPER;
        let (v, wz) = l.apply(Vec2::new(0.55, 0.0), 2.0, Vec2::zeros(), 0.0, 0.1);
        assert!((v.norm() - 0.055).abs() < 1e-12);
        assert!((wz - 0.3).abs() < 1e-12);
        // reversing direction: change bounded by a*dt
        let (v2, _) = l.apply(Vec2::new(-0.55, 0.0), 0.0, v, wz, 0.1);
        assert!(((v2 - v).norm() - 0.055).abs() < 1e-12);
    }

    #[test]
    fn limits_treat_nan_as_stop() {
        let l = Limits::PEPPER;
        let (v, wz) = l.apply(Vec2::new(f64::NAN, 0.0), f64::INFINITY, Vec2::new(0.3, 0.0), 1.0, 0.1);
        assert!(v.x.is_finite() && wz.is_finite());
        assert!(v.norm() < 0.3);
        assert!(wz < 1.0);
    }

    #[test]
    fn frames_round_trip() {
        let v = Vec2::new(0.3, -0.2);
        let w = body_to_world(world_to_body(v, 1.1), 1.1);
        assert!((v - w).norm() < 1e-12);
        // facing +y, forward in the body is +y in the world
        let f = body_to_world(Vec2::new(1.0, 0.0), std::f64::consts::FRAC_PI_2);
        assert!((f - Vec2::new(0.0, 1.0)).norm() < 1e-12);
    }

    fn drive(path: Vec<Vec2>, start: Vec2, steps: usize) -> (Vec2, f64, f64) {
        let mut f = PathFollower::new(path, FollowerParams::default());
        let l = Limits::PEPPER;
        let (mut p, mut th, mut v, mut w) = (start, 0.0, Vec2::zeros(), 0.0);
        let mut max_cross: f64 = 0.0;
        for _ in 0..steps {
            let out = f.step(p, th, l.max_speed, l.max_accel, 0.1);
            max_cross = max_cross.max(out.cross_track);
            (v, w) = l.apply(out.velocity, out.wz, v, w, 0.1);
            p += v * 0.1;
            th = wrap_angle(th + w * 0.1);
        }
        (p, v.norm(), max_cross)
    }

    #[test]
    fn follower_reaches_the_end_and_stops() {
        let path = vec![Vec2::new(0.0, 0.0), Vec2::new(4.0, 0.0), Vec2::new(4.0, 3.0)];
        let (p, speed, max_cross) = drive(path, Vec2::zeros(), 400);
        assert!((p - Vec2::new(4.0, 3.0)).norm() < 0.05, "{p:?}");
        assert!(speed < 0.02);
        assert!(max_cross < 0.5, "cut the corner by {max_cross}");
    }

    #[test]
    fn follower_with_an_empty_or_one_point_path_is_defined() {
        let mut empty = PathFollower::new(vec![], FollowerParams::default());
        let o = empty.step(Vec2::new(1.0, 1.0), 0.0, 0.55, 0.55, 0.1);
        assert!(o.velocity.x.is_finite() && o.velocity.y.is_finite() && o.wz.is_finite());
        let mut single = PathFollower::new(vec![Vec2::new(3.0, 0.0)], FollowerParams::default());
        let o = single.step(Vec2::zeros(), 0.0, 0.55, 0.55, 0.1);
        assert!(o.velocity.x > 0.0 && o.velocity.y.abs() < 1e-12, "{o:?}");
        let mut nan = PathFollower::new(vec![Vec2::zeros(), Vec2::new(2.0, 0.0)], FollowerParams::default());
        let o = nan.step(Vec2::new(f64::NAN, 0.0), 0.0, 0.55, 0.55, 0.1);
        let (v, w) = Limits::PEPPER.apply(o.velocity, o.wz, Vec2::zeros(), 0.0, 0.1);
        assert!(v.x.is_finite() && v.y.is_finite() && w.is_finite());
    }

    #[test]
    fn follower_does_not_aim_across_obstacles() {
        // An L-shaped path around a corner at (2, 0): the look-ahead point beyond the corner is
        // hidden behind the block x > 1.8, y < -0.2, so the follower aims at the corner instead.
        let path = vec![Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), Vec2::new(2.0, -3.0)];
        let mut f = PathFollower::new(path, FollowerParams::default());
        let blocked = |a: Vec2, b: Vec2| {
            (0..=20).all(|k| {
                let q = a + (b - a) * (k as f64 / 20.0);
                !(q.x > 1.8 && q.y < -0.2)
            })
        };
        let free = f.clone().step(Vec2::new(1.7, 0.0), 0.0, 0.55, 0.55, 0.1);
        let out = f.step_visible(Vec2::new(1.7, 0.0), 0.0, 0.55, 0.55, 0.1, &blocked);
        // Free: aims at (2, -0.5) through the block (slope -5/3); checked: along the path toward
        // the corner (slope 0: the robot is on the path, so no cross-track correction).
        assert!(free.velocity.y / free.velocity.x < -1.5, "{free:?}");
        let slope = out.velocity.y / out.velocity.x;
        assert!(slope > -0.5 && slope <= 0.0, "{out:?}");
    }

    #[test]
    fn follower_rejoins_a_path_by_a_wall_at_a_shallow_angle() {
        // A straight path 0.35 m from a wall (y < -0.35 blocked); the robot, pushed 0.3 m off
        // toward the open side, cannot see its look-ahead point past the wall's inflation (as in
        // a corridor whose path hugs a wall). It heads along the path, closing the gap over one
        // look-ahead length, not square at the wall.
        let path = vec![Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)];
        let mut f = PathFollower::new(path, FollowerParams::default());
        let hidden = |a: Vec2, b: Vec2| (0..=20).all(|k| (a + (b - a) * (k as f64 / 20.0)).y > 0.05);
        let out = f.step_visible(Vec2::new(2.0, 0.3), 0.0, 0.55, 0.55, 0.1, &hidden);
        let slope = out.velocity.y / out.velocity.x;
        let expected = -0.3 / FollowerParams::default().lookahead;
        assert!((slope - expected).abs() < 1e-9, "{out:?}");
    }

    #[test]
    fn follower_progress_never_goes_backwards() {
        // A path that doubles back: the follower must not jump to the later, closer segment.
        let path = vec![Vec2::new(0.0, 0.0), Vec2::new(5.0, 0.0), Vec2::new(5.0, 0.6), Vec2::new(0.0, 0.6)];
        let mut f = PathFollower::new(path, FollowerParams::default());
        let out = f.step(Vec2::new(0.5, 0.25), 0.0, 0.55, 0.55, 0.1);
        assert!(out.velocity.x > 0.0, "{out:?}");
    }

    #[test]
    fn unicycle_rule_moves_along_the_heading_only() {
        let l = Limits::PEPPER;
        let th: f64 = 0.3;
        let h = Vec2::new(th.cos(), th.sin());
        // Asked to go 45 degrees off the heading at full speed: forward at |u| cos(45 deg), within
        // the acceleration limit from rest (0.055 m/s in 0.1 s), along the heading.
        let u = rotate(Vec2::new(0.55, 0.0), th + std::f64::consts::FRAC_PI_4);
        let (v, w) = l.unicycle_from_holonomic(u, 1.0, th, Vec2::zeros(), 0.0, 0.1);
        assert!((v.norm() - 0.055).abs() < 1e-12 && (v.dot(&h) - 0.055).abs() < 1e-12, "{v:?}");
        assert!((w - 0.3).abs() < 1e-12, "{w}"); // angular acceleration 3 rad/s^2 * 0.1 s
        // Already at 0.35 m/s forward: 0.55 cos 45 = 0.389 is within reach.
        let (v, _) = l.unicycle_from_holonomic(u, 1.0, th, h * 0.35, 0.0, 0.1);
        assert!((v.dot(&h) - 0.55 * std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-12, "{v:?}");
        // Asked to go backwards: no reverse, it slows down (and turns, by the given rate).
        let (v, _) = l.unicycle_from_holonomic(-u, 1.0, th, h * 0.3, 0.0, 0.1);
        assert!((v.dot(&h) - 0.245).abs() < 1e-12, "{v:?}");
        // The robot-frame command of a differential drive has no sideways part at all.
        assert_eq!(body_command(Drive::Differential, v, th).y, 0.0);
    }

    #[test]
    fn unicycle_limits_reverse_and_speed() {
        let l = Limits::PEPPER;
        let (s, _) = l.apply_unicycle(-5.0, 0.0, -0.5, 0.0, 0.1);
        assert_eq!(s, -0.55);
        let th: f64 = 1.0;
        let h = Vec2::new(th.cos(), th.sin());
        // A previous command pointing behind the heading counts as reverse speed.
        let (v, _) = l.unicycle_world(0.0, 0.0, th, h * -0.2, 0.0, 0.1);
        assert!((v.dot(&h) + 0.145).abs() < 1e-12, "{v:?}");
    }
}
