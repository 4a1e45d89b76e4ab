//! Followers of a robot's tour: they walk the robot's trail (see [`Crowd::set_guides`]) and
//! gather on an arc around it at its stops.

use super::Crowd;
use super::scripts::Script;
use super::steer::{bearing, toward};
use crate::math::Vec2;

/// How close (metres, centre to centre) a follower walks behind its robot guide.
pub const FOLLOW_GAP: f64 = 1.2;

/// How near (metres) a follower of a robot gets to its place on a gathering arc (places are
/// 0.75 m apart, so followers in place never overlap).
pub const SLOT_REACHED: f64 = 0.1;

/// Within this distance (metres) of a robot standing at a stop, its followers walk straight to
/// their places on the arc instead of along its trail.
pub const GATHER_REACH: f64 = 3.0;

/// Centre distance (metres) a follower keeps from its robot guide: closer, it steps back.
pub const ROBOT_SPACE: f64 = 1.0;

/// Spacing (metres) of the points of a robot's trail, which its followers walk.
pub const TRAIL_SPACING: f64 = 0.3;

/// How near (metres) a follower passes a trail point before heading for the next.
pub const TRAIL_REACHED: f64 = 0.4;

impl Crowd {
    /// A follower of robot `robot`'s tour (starting at `start`, gathering at `places` at each
    /// tour point): along the robot's trail up to [`FOLLOW_GAP`] from it, then on a place of its
    /// arc while it stands at a stop.
    pub(super) fn robot_follower_step(
        &mut self,
        i: usize,
        h: f64,
        robot: Option<usize>,
        start: Vec2,
        places: &[Vec<Vec2>],
    ) {
        let pos = self.pos[i];
        let n = places.len();
        let guide = robot.filter(|&j| j < self.trails.len()).and_then(|j| Some((j, *self.guides.get(j)?)));
        let Some((j, g)) = guide else {
            // No robot to follow: wait at the place, facing the tour's start.
            self.moving[i] = false;
            self.face_want[i] = bearing(pos, start);
            return;
        };
        // Taken out for the borrow checker, put back below.
        let trail = std::mem::take(&mut self.trails[j]);
        let gk = g.target.min(n - 1);
        // Along the robot's trail, up to FOLLOW_GAP from it.
        let mut k = self.leg[i];
        while k < trail.len() && (trail[k] - pos).norm() <= TRAIL_REACHED {
            k += 1;
        }
        // Caught up: the trail ahead ends at the robot, or it is this near (at a
        // stop, within GATHER_REACH: the place on the arc is in reach).
        let reach = if g.dwelling { GATHER_REACH } else { FOLLOW_GAP };
        let caught_up =
            k >= trail.len() || (trail[k] - g.pos).norm() <= FOLLOW_GAP || (pos - g.pos).norm() <= reach;
        // A place on the arc is claimed on arriving near the robot at a stop.
        let slot = if g.dwelling && caught_up {
            self.choose_place(i, robot, &places[gk])
        } else {
            if !g.dwelling {
                self.target[i] = usize::MAX; // walking: no place claimed
            }
            None
        };
        if self.gathered[i] == Some(gk) && g.dwelling {
            // Gathered: stand facing the robot until it moves on.
            self.moving[i] = false;
            self.face_want[i] = bearing(pos, g.pos);
        } else if let (Some(slot), true) = (slot, caught_up) {
            // The robot stands at a stop: take the place on its arc.
            if self.take_place(i, h, g.pos, gk, slot) {
                k = trail.len(); // the way to here is behind
            }
        } else if caught_up {
            let away = pos - g.pos;
            if away.norm() < ROBOT_SPACE && away.norm() > 1e-9 {
                self.desired[i] = away * (0.5 * self.speed[i] / away.norm()); // step back
            }
            self.face_want[i] = bearing(pos, g.pos);
        } else {
            self.desired[i] = toward(pos, trail[k], self.speed[i]);
        }
        self.leg[i] = k;
        self.trails[j] = trail;
    }

    /// Follower `i` heads for `slot`, its place on the arc of the robot (at `robot_pos`) standing
    /// at tour point `gk`: it takes the place on arriving, or as near as the others let it get
    /// after 2 s within 1.5 m of it (but not within [`ROBOT_SPACE`] of the robot: from there it
    /// first steps out). Returns whether it has gathered.
    fn take_place(&mut self, i: usize, h: f64, robot_pos: Vec2, gk: usize, slot: Vec2) -> bool {
        let pos = self.pos[i];
        let d = (slot - pos).norm();
        let away = pos - robot_pos;
        let near_robot = away.norm() < ROBOT_SPACE;
        if d < 1.5 && self.vel[i].norm() < 0.1 && !near_robot {
            self.stuck[i] += h;
        } else {
            self.stuck[i] = 0.0;
        }
        if d <= SLOT_REACHED || self.stuck[i] > 2.0 {
            self.stuck[i] = 0.0;
            self.gathered[i] = Some(gk);
            self.moving[i] = false;
            self.face_want[i] = bearing(pos, robot_pos);
            true
        } else {
            let mut dir = (slot - pos) / d;
            if away.norm() < FOLLOW_GAP && away.norm() > 1e-9 {
                dir += away / away.norm(); // round the robot, not past it
            }
            self.desired[i] = toward(pos, pos + dir, self.speed[i]);
            false
        }
    }

    /// Follower `i`'s place on `places` (a robot's gathering arc at a tour stop): the one it
    /// claimed before, else one no other follower of the robot has claimed, the arc's ends first
    /// (the claim, an index into `places`, is kept in `target` while the robot stands there).
    fn choose_place(&mut self, i: usize, robot: Option<usize>, places: &[Vec2]) -> Option<Vec2> {
        if let Some(&q) = places.get(self.target[i]) {
            return Some(q);
        }
        let claimed = |c: &Crowd, place: usize| {
            (0..c.len()).any(|k| {
                k != i
                    && c.target[k] == place
                    && matches!(&c.script[k], Script::RobotFollower { robot: r, .. } if *r == robot)
            })
        };
        // The ends of the arc first (whoever comes later finds the places nearest the way in,
        // in the middle, free), the nearer of equal ones.
        let pos = self.pos[i];
        let mid = 0.5 * (places.len() as f64 - 1.0);
        let best = (0..places.len()).filter(|&k| !claimed(self, k)).min_by(|&a, &b| {
            let end = |k: usize| -(k as f64 - mid).abs();
            end(a).total_cmp(&end(b)).then((places[a] - pos).norm().total_cmp(&(places[b] - pos).norm()))
        });
        self.target[i] = best.unwrap_or(usize::MAX);
        best.map(|k| places[k])
    }
}
