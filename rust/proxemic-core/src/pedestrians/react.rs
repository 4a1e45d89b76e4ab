//! The robot as seen by people: each person's [`Reaction`] reshapes its planned motion for the
//! substep (after its script, before the forces) when a robot is within
//! [`ReactionParams::notice`]; beyond it nothing is computed (the crowd's hot loop is untouched).
//!
//! - walking people (`aware`, `yield`, `cautious`, and `curious` ones once their curiosity is
//!   spent) steer round a keep-out disc around the robot's body, of body gap
//!   [`ReactionParams::keep_gap`] (`cautious_gap` for `cautious`) plus
//!   [`ReactionParams::speed_gain`] times the robot's speed, passing on the side they are
//!   already on (at exact symmetry, on the right);
//! - a walking person who cannot pass a robot at its hard gap, because the free width between
//!   the robot and the walls on the side it passes is too narrow (a narrow hallway, a doorway),
//!   squeezes through the middle of that width if the robot is not coming toward it (its
//!   velocity toward the person at most [`ReactionParams::squeeze_approach`]) and the width
//!   leaves at least [`ReactionParams::squeeze_gap`] on each side: it walks along its way, drawn
//!   across it to the middle of the gap, the robot's body repels it across its way as a wall
//!   does (instead of the robot's social force), and its hard gap to that robot is half that
//!   gap; a follower of a robot's tour follows it and never squeezes past it;
//! - `yield`: a person ahead of a moving robot, within its lane, steps aside out of the lane,
//!   and waits at its edge while the robot comes on;
//! - `curious`: walks to [`ReactionParams::curious_distance`] of the robot's centre and follows it,
//!   facing it, for [`ReactionParams::curious_time`] seconds in all, then goes on with its script;
//! - `cautious`: a larger keep-out, and slows down (to at least
//!   [`ReactionParams::cautious_min_speed`] of its speed) within
//!   [`ReactionParams::cautious_slow_range`] of it;
//! - people standing still (standing, seated, in a conversation, dwelling at a stop, gathered,
//!   taking part in an activity) who see the robot turn toward it once its body is inside their
//!   intimate zone, or, when it stands still, within [`ReactionParams::waiting_gap`] of them (a
//!   robot that keeps out of their intimate zone waits at its edge), and shift aside (out of its
//!   way, or away from it when it stands still) by at most what their behaviour allows
//!   ([`shift_allowed`]: nothing when seated), going back to their place once it has left.
//!
//! The hard constraint of [`Crowd`]'s integration keeps every reacting person from stepping to
//! within [`ReactionParams::hard_gap`] of a robot's body (`cautious_hard_gap`, `curious_hard_gap`)
//! or closer to a robot it is already that near. `ignore` skips all of this.

use super::Crowd;
use super::scripts::Script;
use super::steer::{bearing, toward};
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;
use crate::scenario::{Behaviour, Reaction};

/// Parameters of the people's reactions to robots (metres, seconds, m/s). The distances are
/// Hall's zones (intimate 0.45 m, personal 1.2 m) as body gaps; the values were chosen on the
/// tuning split (`docs/people.md`, `tests/parked_robot.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReactionParams {
    /// Reactions are computed only for people whose centre is within this distance of a
    /// robot's centre (m); default 5.0.
    pub notice: f64,
    /// Body gap of the keep-out an `aware` or `yield` person steers round (m); default 0.7.
    pub keep_gap: f64,
    /// Growth of the keep-out with the robot's speed (s: metres per m/s); default 0.5.
    pub speed_gain: f64,
    /// Body gap a reacting person never steps within (nor closer once within; m); default 0.45,
    /// Hall's intimate zone.
    pub hard_gap: f64,
    /// `cautious`: keep-out body gap (m); default 1.2, Hall's personal zone.
    pub cautious_gap: f64,
    /// `cautious`: hard gap (m); default 0.8.
    pub cautious_hard_gap: f64,
    /// `cautious`: it slows down within this body gap beyond its keep-out (m); default 2.0.
    pub cautious_slow_range: f64,
    /// `cautious`: slowest speed near a robot, as a fraction of its own; default 0.5.
    pub cautious_min_speed: f64,
    /// `curious`: centre distance it approaches to (m); default 1.0.
    pub curious_distance: f64,
    /// `curious`: hard gap (m); default 0.3.
    pub curious_hard_gap: f64,
    /// `curious`: seconds it spends approaching and following robots, per episode; default 30.
    pub curious_time: f64,
    /// `yield`: half-width of a moving robot's lane beyond both bodies (m); default 0.5.
    pub yield_lane: f64,
    /// `yield`: how far ahead of a moving robot people yield (seconds of its motion); default 4.
    pub yield_ahead: f64,
    /// A robot slower than this counts as still (m/s); default 0.1.
    pub still_speed: f64,
    /// Speed at which people standing still shift aside and back (m/s); default 0.4.
    pub shift_speed: f64,
    /// Narrowest body gap at which a walking person squeezes past a robot that leaves it
    /// no way at its hard gap (m); default 0.05 (the module's docs say when).
    pub squeeze_gap: f64,
    /// A robot whose velocity toward a person is at most this is squeezed past (m/s); default
    /// 0.05, the rule by which the metrics call an approach the robot's.
    pub squeeze_approach: f64,
    /// Body gap within which people standing still make room for a robot standing still (m);
    /// default 0.55. A robot that keeps out of people's intimate zones (0.45 m) stops at its
    /// edge when a standing person blocks its way; people who moved only for a robot inside that
    /// zone would never see it waiting there, and robot and person would wait for each other
    /// for good. Chosen on the tuning split (Francis `robot_crowding`, `docs/people.md`).
    pub waiting_gap: f64,
}

impl Default for ReactionParams {
    fn default() -> Self {
        ReactionParams {
            notice: 5.0,
            keep_gap: 0.7,
            speed_gain: 0.5,
            hard_gap: 0.45,
            cautious_gap: 1.2,
            cautious_hard_gap: 0.8,
            cautious_slow_range: 2.0,
            cautious_min_speed: 0.5,
            curious_distance: 1.0,
            curious_hard_gap: 0.3,
            curious_time: 30.0,
            yield_lane: 0.5,
            yield_ahead: 4.0,
            still_speed: 0.1,
            shift_speed: 0.4,
            squeeze_gap: 0.05,
            waiting_gap: 0.55,
            squeeze_approach: 0.05,
        }
    }
}

/// How far (m) a person standing still may shift aside from its place for a robot, by
/// behaviour: nothing seated or replayed (a replayed person follows its track), 0.3 m in a
/// conversation, an activity or at a tour stop (guide), 0.5 m otherwise.
pub(super) fn shift_allowed(b: Behaviour) -> f64 {
    match b {
        Behaviour::Seated | Behaviour::Replay => 0.0,
        Behaviour::Conversation | Behaviour::Resident | Behaviour::Staff | Behaviour::Guide => 0.3,
        Behaviour::Walker | Behaviour::Standing | Behaviour::Visitor | Behaviour::Follower => 0.5,
    }
}

impl ReactionParams {
    /// The hard gap of `r` (m; `None` for `ignore`).
    pub(super) fn hard(&self, r: Reaction) -> Option<f64> {
        match r {
            Reaction::Ignore => None,
            Reaction::Aware | Reaction::Yield => Some(self.hard_gap),
            Reaction::Cautious => Some(self.cautious_hard_gap),
            Reaction::Curious => Some(self.curious_hard_gap),
        }
    }
}

impl Crowd {
    /// Reshapes person `i`'s planned motion (`moving`, `desired`, `face_want`) for its reaction
    /// to the nearest robot within [`ReactionParams::notice`]; `robots` are (centre, radius,
    /// velocity); `geometry` is the static world. Does nothing for `ignore` or with no robot near.
    pub(super) fn react(
        &mut self,
        i: usize,
        h: f64,
        robots: &[(Vec2, f64, Vec2)],
        geometry: &StaticGeometry,
    ) {
        self.squeeze[i] = None;
        let reaction = self.reaction[i];
        if reaction == Reaction::Ignore || !self.present[i] {
            return;
        }
        let rp = self.react_params;
        let pos = self.pos[i];
        let near = robots
            .iter()
            .enumerate()
            .map(|(k, &(c, r, v))| ((c - pos).norm_squared(), c, r, v, k))
            .filter(|q| q.0 < rp.notice * rp.notice)
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let Some((d2, c, rr, v, k)) = near else {
            self.return_to_place(i);
            return;
        };
        let d = d2.sqrt();
        let gap = d - self.radius[i] - rr;
        let speed = v.norm();
        // Standing still: no script motion this substep, or dwelling (a walker at a stop, a guide
        // at a tour stop), which a script plans as a walk at zero speed.
        let dwelling = self.dwell_left[i] > 0.0 && self.desired[i] == Vec2::zeros();
        if !self.moving[i] || dwelling {
            if !matches!(self.script[i], Script::Replay { .. }) {
                self.stand_aside(i, (c, gap, v), geometry);
            }
            return;
        }
        self.anchor[i] = None;
        if reaction == Reaction::Curious && self.curious_left[i] > 0.0 {
            self.curious_left[i] -= h;
            let spot = c + (pos - c) * (rp.curious_distance / d.max(1e-9));
            let dist = (spot - pos).norm();
            self.desired[i] =
                if dist > 0.1 { toward(pos, spot, self.speed[i].min(dist / 0.5)) } else { Vec2::zeros() };
            self.face_want[i] = bearing(pos, c);
            return;
        }
        let base = if reaction == Reaction::Cautious { rp.cautious_gap } else { rp.keep_gap };
        let keep = self.radius[i] + rr + base + rp.speed_gain * speed;
        if reaction == Reaction::Yield && speed > rp.still_speed && self.yield_to(i, c, rr, v) {
            return;
        }
        let want = self.desired[i];
        let s = want.norm();
        if s < 1e-9 {
            return;
        }
        // A robot not coming toward the person (by the metrics' rule of who approached whom); a
        // follower of a robot's tour follows it and never squeezes past.
        if v.dot(&(c - pos)) >= -rp.squeeze_approach * d
            && !matches!(self.script[i], Script::RobotFollower { .. })
            && let Some(hard) = rp.hard(reaction)
            && let Some(g) =
                self.passage_gap(i, want / s, (c, rr), (keep - self.radius[i] - rr, hard), geometry)
        {
            // Along its way, drawn across it to the middle of the gap beside the robot.
            let u = want / s;
            let side = if u.x * (c - pos).y - u.y * (c - pos).x >= 0.0 {
                Vec2::new(u.y, -u.x)
            } else {
                Vec2::new(-u.y, u.x)
            };
            let off = (c + side * (rr + g + self.radius[i]) - pos).dot(&side);
            self.squeeze[i] = Some((k, 0.5 * g));
            self.desired[i] = (u + side * (off / 0.3).clamp(-1.0, 1.0)).normalize() * s;
            return;
        }
        let dir = steer_round(pos, want / s, c, keep);
        let mut s_new = s;
        if reaction == Reaction::Cautious {
            let over = (gap - rp.cautious_gap) / rp.cautious_slow_range;
            s_new *= over.clamp(rp.cautious_min_speed, 1.0);
        }
        let dir = if dir.norm() < 1e-9 { want / s } else { dir };
        self.desired[i] = dir * s_new;
    }

    /// The body gap at which walking person `i`, going along `dir` (unit), squeezes past a robot
    /// at `c` (radius `rr`) that is not coming toward it: the middle of the free width between
    /// the robot's body and the static geometry on the side it passes (the side `steer_round`
    /// takes), when that middle is nearer the robot than `hard` (its hard gap; so it could not
    /// pass otherwise) but not nearer than [`ReactionParams::squeeze_gap`], and the middle line
    /// of that gap is clear of the static geometry from the person to a body length past the
    /// robot. `None` when its way misses the keep-out disc of body gap `keep_gap` or the robot is
    /// a body length behind it, or there is no such way.
    fn passage_gap(
        &self,
        i: usize,
        dir: Vec2,
        (c, rr): (Vec2, f64),
        (keep_gap, hard): (f64, f64),
        geometry: &StaticGeometry,
    ) -> Option<f64> {
        let rp = self.react_params;
        let r = self.radius[i];
        let to = c - self.pos[i];
        let cross = dir.x * to.y - dir.y * to.x;
        // Until the robot is a body length behind: a person beside it is still squeezing past.
        if to.dot(&dir) <= -(r + rr) || cross.abs() >= r + rr + keep_gap {
            return None;
        }
        let side = if cross >= 0.0 { Vec2::new(dir.y, -dir.x) } else { Vec2::new(-dir.y, dir.x) };
        // Sphere tracing from the robot's edge on the exact geometry: the distance to the nearest
        // boundary is free way ahead.
        let limit = 2.0 * (r + hard);
        let mut w = 0.0;
        while w < limit {
            let clear = geometry.boundary_distance_within(c + side * (rr + w), 0.5);
            if clear < 0.005 {
                break;
            }
            w += clear;
        }
        let g = 0.5 * (w - 2.0 * r);
        if g >= hard || g < rp.squeeze_gap {
            return None;
        }
        // The way through: the middle line of the gap, from where the person is (at most 2 m
        // back) to a body length past the robot, clear of the static geometry every 10 cm.
        let mid = c + side * (rr + g + r);
        let from = (-to.dot(&dir)).max(-2.0);
        let steps = ((r + rr - from) / 0.1).ceil().max(0.0) as usize;
        let clear = (0..=steps).all(|k| {
            let a = (from + 0.1 * k as f64).min(r + rr);
            geometry.boundary_distance_within(mid + dir * a, r + 0.05) > r + 0.02
        });
        clear.then_some(g)
    }

    /// `yield`: if person `i` is ahead of the moving robot at `c` (velocity `v`) within its
    /// lane, steps out of the lane (or waits at its edge) and returns true.
    fn yield_to(&mut self, i: usize, c: Vec2, rr: f64, v: Vec2) -> bool {
        let rp = self.react_params;
        let pos = self.pos[i];
        let speed = v.norm();
        let u = v / speed;
        let rel = pos - c;
        let ahead = rel.dot(&u);
        let lat = u.x * rel.y - u.y * rel.x;
        let half = self.radius[i] + rr + rp.yield_lane;
        if ahead <= 0.0 || ahead > speed * rp.yield_ahead + half || lat.abs() >= half + 0.3 {
            return false;
        }
        if lat.abs() < half {
            // Out of the lane: to the side it is on (the right of the robot's way at a tie).
            let side = if lat > 0.0 { Vec2::new(-u.y, u.x) } else { Vec2::new(u.y, -u.x) };
            self.desired[i] = side * self.speed[i];
        } else {
            self.desired[i] = Vec2::zeros();
        }
        self.face_want[i] = bearing(pos, c);
        true
    }

    /// A person standing still: turns toward a robot (at `c`, body gap `gap`, velocity `v`) whose
    /// body is inside its intimate zone (or, standing still, within
    /// [`ReactionParams::waiting_gap`]) and shifts aside within [`shift_allowed`] of its place;
    /// else goes back to its place. Aside is [`aside_from`]: out of a moving robot's way, away
    /// from a still one. A person whose step aside would end where the walls push harder than the
    /// shift drives (within 0.5 m of a wall, body edge) stays put: once moving, the walls would
    /// push it off them, out of a corner toward the robot.
    fn stand_aside(&mut self, i: usize, (c, gap, v): (Vec2, f64, Vec2), geometry: &StaticGeometry) {
        let rp = self.react_params;
        let pos = self.pos[i];
        let speed = v.norm();
        // A moving robot is made room for once inside the intimate zone (grown with its speed), a
        // still one already at the zone's edge, where a robot that keeps out of it waits.
        let mut reach = rp.hard_gap + rp.speed_gain * speed;
        if speed <= rp.still_speed {
            reach = reach.max(rp.waiting_gap);
        }
        if gap >= reach {
            self.return_to_place(i);
            return;
        }
        self.face_want[i] = bearing(pos, c);
        let place = *self.anchor[i].get_or_insert(pos);
        let away = aside_from(pos, c, v, rp.still_speed);
        let next = pos + away * (rp.shift_speed * self.params.dt);
        // The body-edge distance within which the walls' push (F_o exp(-x / sigma_o)) outweighs
        // the shift's drive (shift speed / tau): a shift there is pushed off the wall instead.
        let fp = &self.params;
        let reach = fp.wall_range * (fp.wall_strength * fp.tau / rp.shift_speed.max(1e-9)).max(1.0).ln();
        let wall_bound = self.radius[i] + reach;
        if self.shift[i] > 0.0
            && (next - place).norm() <= self.shift[i]
            && geometry.boundary_distance_within(next, wall_bound) >= wall_bound
        {
            self.moving[i] = true;
            self.desired[i] = away * rp.shift_speed;
        }
    }

    /// A person standing still that shifted aside walks back to its place (then forgets it).
    fn return_to_place(&mut self, i: usize) {
        let Some(place) = self.anchor[i] else {
            return;
        };
        if self.moving[i] || (place - self.pos[i]).norm() < 0.05 {
            self.anchor[i] = None;
            return;
        }
        self.moving[i] = true;
        self.desired[i] = toward(self.pos[i], place, self.react_params.shift_speed);
    }
}

/// The unit direction in which a person standing at `pos` steps aside for a robot at `c` moving
/// at `v`: a robot slower than `still_speed` (m/s) is stepped away from (along the line from
/// its centre); a moving one is stepped out of the way of, perpendicular to its heading, to the
/// side the person is on (the robot's right at a tie). Stepping straight away from a robot that
/// comes head-on would back the person along the robot's own way, into it.
fn aside_from(pos: Vec2, c: Vec2, v: Vec2, still_speed: f64) -> Vec2 {
    let speed = v.norm();
    if speed <= still_speed {
        return toward(c, pos, 1.0);
    }
    let u = v / speed;
    let rel = pos - c;
    let left = Vec2::new(-u.y, u.x);
    if rel.dot(&left) > 0.0 { left } else { -left }
}

/// The walking direction of a person at `pos` wanting to go along `dir` (unit) that passes a
/// disc of radius `keep` round `c`: `dir` if its way misses the disc (or leads away), else the
/// tangent to the disc on the side the person is on (the right at exact symmetry); inside the
/// disc, `dir` without its component toward `c`, plus a unit step outward.
fn steer_round(pos: Vec2, dir: Vec2, c: Vec2, keep: f64) -> Vec2 {
    let to = c - pos;
    let d = to.norm();
    let along = to.dot(&dir);
    if d < 1e-9 {
        return dir;
    }
    let cross = dir.x * to.y - dir.y * to.x;
    if d <= keep {
        let out = -to / d;
        let tangential = dir - (to / d) * along.max(0.0) / d;
        return (tangential + out).normalize();
    }
    // The way misses the disc, or the disc is behind.
    if along <= 0.0 || cross.abs() >= keep {
        return dir;
    }
    let phi = to.y.atan2(to.x);
    let alpha = (keep / d).asin();
    let a = if cross >= 0.0 { phi - alpha } else { phi + alpha };
    Vec2::new(a.cos(), a.sin())
}
