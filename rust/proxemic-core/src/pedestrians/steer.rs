//! Each person's motion for a substep, from its script: walkers and guides on their routes,
//! followers of a guide, programs (visitors, conversations, residents, staff).

use super::Crowd;
use super::scripts::{Face, Program, Script, Task, Until};
use crate::math::Vec2;

/// The velocity toward `q` from `pos` at `speed` (zero at `q`).
pub(super) fn toward(pos: Vec2, q: Vec2, speed: f64) -> Vec2 {
    let d = q - pos;
    let n = d.norm();
    if n > 1e-9 { d * (speed / n) } else { Vec2::zeros() }
}

/// The direction of `q` seen from `pos` (radians; `None` at `q`).
pub(super) fn bearing(pos: Vec2, q: Vec2) -> Option<f64> {
    let d = q - pos;
    (d.norm() > 1e-6).then(|| d.y.atan2(d.x))
}

impl Crowd {
    /// Advances person `i`'s script by `h` seconds and sets its motion for this substep:
    /// `moving`, `desired` (velocity) and `face_want`; `robots` (centre, radius, velocity) are
    /// what replayed people react to.
    pub(super) fn plan_step(&mut self, i: usize, h: f64, robots: &[(Vec2, f64, Vec2)]) {
        self.moving[i] = true;
        self.face_want[i] = None;
        self.desired[i] = Vec2::zeros();
        // Taken out for the match (the arms update the other per-person arrays), put back below.
        let script = std::mem::replace(&mut self.script[i], Script::Still);
        match &script {
            Script::Still => self.moving[i] = false,
            Script::Walker => self.walker_step(i, h),
            Script::Guide { stops, followers } => self.guide_step(i, h, stops, followers),
            Script::Follower { guide, slots } => self.follower_step(i, *guide, slots),
            Script::RobotFollower { robot, start, places } => {
                self.robot_follower_step(i, h, *robot, *start, places)
            }
            Script::Program(prog) => self.program_step(i, h, prog),
            Script::Replay { track, react_radius } => self.replay_step(i, h, track, *react_radius, robots),
        }
        self.script[i] = script;
    }

    /// Person `i`'s walk along its closed route over `h` seconds: counts its dwell down, or, on
    /// arrival at its target waypoint `k`, moves the target on and starts a dwell of `dwell(k)`
    /// seconds (0 for no stop there).
    fn advance_route(&mut self, i: usize, h: f64, dwell: impl Fn(&Self, usize) -> f64) {
        if self.dwell_left[i] > 0.0 {
            self.dwell_left[i] = (self.dwell_left[i] - h).max(0.0);
        } else if (self.routes[i][self.target[i]] - self.pos[i]).norm() <= self.params.arrival {
            let k = self.target[i];
            self.target[i] = (k + 1) % self.routes[i].len();
            self.dwell_left[i] = dwell(self, k);
        }
    }

    /// A walker: along its closed route, dwelling at its stops facing the next waypoint.
    fn walker_step(&mut self, i: usize, h: f64) {
        let pos = self.pos[i];
        self.advance_route(
            i,
            h,
            |c, k| if c.stops[i].get(k).copied().unwrap_or(true) { c.dwell[i] } else { 0.0 },
        );
        let next = self.routes[i][self.target[i]];
        if self.dwell_left[i] > 0.0 {
            self.face_want[i] = bearing(pos, next);
        } else {
            self.desired[i] = toward(pos, next, self.speed[i]);
        }
    }

    /// A tour guide: along its route, standing at its stops facing its followers.
    fn guide_step(&mut self, i: usize, h: f64, stops: &[bool], followers: &[usize]) {
        let pos = self.pos[i];
        self.advance_route(i, h, |c, k| if stops[k] { c.dwell[i].max(h) } else { 0.0 });
        if self.dwell_left[i] > 0.0 {
            // At a stop: stand facing the followers.
            self.moving[i] = false;
            if !followers.is_empty() {
                let c = followers.iter().fold(Vec2::zeros(), |a, &k| a + self.pos[k]);
                self.face_want[i] = bearing(pos, c / followers.len() as f64);
            }
        } else {
            self.desired[i] = toward(pos, self.routes[i][self.target[i]], self.speed[i]);
        }
    }

    /// A follower of guide `g`: behind it along its route, gathered at `slots` at its stops.
    fn follower_step(&mut self, i: usize, g: usize, slots: &[Option<Vec2>]) {
        let (pos, arrival) = (self.pos[i], self.params.arrival);
        let n = slots.len();
        // The guide's place in its route: the stop it dwells at, or the waypoint it
        // walks to.
        let (at_stop, gk) = if self.dwell_left[g] > 0.0 {
            (true, (self.target[g] + n - 1) % n)
        } else {
            (false, self.target[g])
        };
        let f = self.target[i];
        if at_stop && (f == gk || self.gathered[i] == Some(gk)) {
            let slot = slots[gk].unwrap_or(self.pos[g]);
            if self.gathered[i] == Some(gk) || (slot - pos).norm() <= arrival {
                // Gathered: stand facing the guide.
                self.gathered[i] = Some(gk);
                self.target[i] = (gk + 1) % n;
                self.moving[i] = false;
                self.face_want[i] = bearing(pos, self.pos[g]);
            } else {
                self.desired[i] = toward(pos, slot, self.speed[i]);
            }
        } else if f == gk {
            // Right behind the guide: follow it, waiting within a metre of it.
            if (self.pos[g] - pos).norm() > 1.0 {
                self.desired[i] = toward(pos, self.pos[g], self.speed[i]);
            }
            self.face_want[i] = bearing(pos, self.pos[g]);
        } else {
            // Behind: walk the guide's route (its waypoints are clear of walls).
            let q = self.routes[g][f];
            if (q - pos).norm() <= 2.0 * arrival {
                self.target[i] = (f + 1) % n;
            }
            self.desired[i] = toward(pos, self.routes[g][self.target[i]], self.speed[i]);
        }
    }

    /// A program: walks and stays, one task after another.
    fn program_step(&mut self, i: usize, h: f64, prog: &Program) {
        let (pos, arrival) = (self.pos[i], self.params.arrival);
        let len = prog.tasks.len();
        // Finished tasks are skipped within the substep (bounded by one pass).
        for _ in 0..=len {
            match &prog.tasks[self.task[i]] {
                Task::Walk(path) => {
                    let leg = self.leg[i];
                    let q = path[leg];
                    let d = (q - pos).norm();
                    let last = leg + 1 == path.len();
                    // A destination taken by someone else counts as reached after 2 s
                    // of standing within a metre of it.
                    if last && d < 1.0 && self.vel[i].norm() < 0.1 {
                        self.stuck[i] += h;
                    } else {
                        self.stuck[i] = 0.0;
                    }
                    if d <= arrival || (last && self.stuck[i] > 2.0) {
                        self.leg[i] += 1;
                        if last {
                            self.advance(i, len, prog.cyclic);
                            continue;
                        }
                    }
                    self.desired[i] = toward(pos, path[self.leg[i]], self.speed[i]);
                }
                Task::Stay { face, until } => {
                    let done = match until {
                        Until::For(d) => self.clock[i] >= *d,
                        Until::At(t) => self.time >= *t,
                        Until::Forever => false,
                    };
                    if done {
                        self.advance(i, len, prog.cyclic);
                        continue;
                    }
                    self.clock[i] += h;
                    self.moving[i] = false;
                    if let Face::Point(q) = face {
                        self.face_want[i] = bearing(pos, *q);
                    }
                }
            }
            break;
        }
    }

    /// Moves person `i` to the next task of its program (`len` tasks).
    fn advance(&mut self, i: usize, len: usize, cyclic: bool) {
        self.leg[i] = 0;
        self.clock[i] = 0.0;
        self.stuck[i] = 0.0;
        self.task[i] = if self.task[i] + 1 < len {
            self.task[i] + 1
        } else if cyclic {
            0
        } else {
            self.task[i]
        };
    }
}
