//! Recorded people ([`Script::Replay`], from a scenario's `[[replay]]` files).
//!
//! A replayed person is where its track says: the linear interpolation of the two samples
//! around the crowd's clock, with the segment's slope as its velocity and its direction as the
//! heading (kept while the track stands still). It is present from its first sample to its last
//! and absent before and after: an absent person stands parked far outside every scene
//! ([`parked_at`]: rows from [`PARK_ORIGIN`], [`PARK_SPACING`] apart, farther than any
//! interaction reaches), is flagged in [`Crowd::present`] and is left out of the neighbour search, the
//! robots' observations and lidar, and the metrics.
//!
//! A person whose replay has a `react_radius` reacts once a robot's centre comes within it while
//! present: from then until the track ends it walks with the crowd's social force model (the
//! driving force, other people, the robots, walls, and the hard constraints of
//! [`crate::pedestrians`]) toward where its track goes [`REACT_LOOKAHEAD`] seconds ahead, at the
//! speed that would take it there in that time (at most [`REACT_MAX_SPEED`]). It does not snap
//! back onto its track afterwards (that would be a jump); it leaves at the track's end.

use super::Crowd;
use super::scripts::Script;
use super::steer::toward;
use crate::math::Vec2;

/// Where the first absent person is parked (metres, world frame): ten kilometres from the origin,
/// beyond every scene's bounds.
pub const PARK_ORIGIN: [f64; 2] = [1.0e4, -1.0e4];

/// Distance (metres) between parked people: more than every interaction's range (the social
/// force cut-off, group detection's distances), so that parked people never interact.
pub const PARK_SPACING: f64 = 20.0;

/// Parked people stand in rows of this many, every other one a metre off the row: never all on
/// one line, the degenerate case of the perception's Delaunay triangulation (slow there).
pub const PARK_ROW: usize = 32;

/// How far ahead on its track (seconds) a reacting person heads.
pub const REACT_LOOKAHEAD: f64 = 1.0;

/// Preferred speed cap of a reacting person (m/s).
pub const REACT_MAX_SPEED: f64 = 2.0;

/// Where person `i` stands while absent.
pub fn parked_at(i: usize) -> Vec2 {
    let (col, row) = (i % PARK_ROW, i / PARK_ROW);
    let zigzag = if col % 2 == 1 { 1.0 } else { 0.0 };
    Vec2::new(PARK_ORIGIN[0] + PARK_SPACING * col as f64, PARK_ORIGIN[1] - PARK_SPACING * row as f64 - zigzag)
}

/// Position and velocity of `track` (`[t, x, y]` samples in strictly increasing time) at time
/// `t` by linear interpolation; `None` before its first sample or after its last (with a
/// nanosecond of slack for the clock's rounding).
pub fn track_at(track: &[[f64; 3]], t: f64) -> Option<(Vec2, Vec2)> {
    const SLACK: f64 = 1e-9;
    let (first, last) = (track.first()?, track.last()?);
    if track.len() < 2 || t < first[0] - SLACK || t > last[0] + SLACK {
        return None;
    }
    // The segment [k - 1, k] holding t: k is the first sample after t (at most the last one).
    let k = track.partition_point(|s| s[0] <= t).clamp(1, track.len() - 1);
    let (a, b) = (track[k - 1], track[k]);
    let span = b[0] - a[0];
    let u = ((t - a[0]) / span).clamp(0.0, 1.0);
    let (pa, pb) = (Vec2::new(a[1], a[2]), Vec2::new(b[1], b[2]));
    Some((pa + (pb - pa) * u, (pb - pa) / span))
}

/// Clearance (metres, surface to surface) a reacting person keeps when walking around a robot.
pub const DETOUR_CLEARANCE: f64 = 0.3;

/// Where a reacting person at `pos` (radius `r`) heads for `target`: the target itself, or, when
/// the straight way passes within [`DETOUR_CLEARANCE`] of the nearest robot in the way, a point
/// beside that robot on the person's side of the way (on its right when exactly head-on, the
/// passing convention), so that a robot standing on the track is walked around instead of
/// waited for.
fn detour(pos: Vec2, target: Vec2, r: f64, robots: &[(Vec2, f64, Vec2)]) -> Vec2 {
    let way = target - pos;
    let len = way.norm();
    if len < 1e-9 {
        return target;
    }
    let dir = way / len;
    let left = Vec2::new(-dir.y, dir.x);
    let blocking = robots
        .iter()
        .filter_map(|&(c, rr, _)| {
            let along = (c - pos).dot(&dir);
            let side = (c - pos).dot(&left);
            let reach = r + rr + DETOUR_CLEARANCE;
            (along > 0.0 && along < len + rr && side.abs() < reach).then_some((along, c, side, reach))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let Some((_, c, side, reach)) = blocking else { return target };
    // The robot is to the person's left (side > 0): pass it on the right, and vice versa.
    let sign = if side > 0.0 || (side == 0.0 && super::PASS_ON_RIGHT) { -1.0 } else { 1.0 };
    c + left * (sign * reach)
}

impl Crowd {
    /// Replayed person `i` for the substep of `h` seconds (before the clock moves): absent, on
    /// its track (placed after the integration by [`Crowd::place_replays`]), or reacting to a
    /// robot of `robots` (centre, radius, velocity) within `react_radius`: walking toward its
    /// track with the forces.
    pub(super) fn replay_step(
        &mut self,
        i: usize,
        h: f64,
        track: &[[f64; 3]],
        react_radius: f64,
        robots: &[(Vec2, f64, Vec2)],
    ) {
        let t = self.time + h;
        let pos = self.pos[i];
        let present = self.present[i] && track_at(track, t).is_some();
        if present && !self.reacting[i] && react_radius > 0.0 {
            self.reacting[i] = robots.iter().any(|&(c, _, _)| (c - pos).norm() <= react_radius);
        }
        if !(present && self.reacting[i]) {
            self.moving[i] = false;
            return;
        }
        let ahead = track.last().map_or(t, |s| (t + REACT_LOOKAHEAD).min(s[0]));
        let target = track_at(track, ahead).map_or(pos, |(q, _)| q);
        let speed = ((target - pos).norm() / REACT_LOOKAHEAD).min(REACT_MAX_SPEED);
        let aim = detour(pos, target, self.radius[i], robots);
        self.speed[i] = speed.max(1e-3);
        self.desired[i] = toward(pos, aim, speed);
    }

    /// After a substep's integration: every replayed person not reacting is put where its track
    /// is at the crowd's clock, or parked while absent (a reacting person whose track has ended
    /// leaves too).
    pub(super) fn place_replays(&mut self) {
        for i in 0..self.len() {
            let Script::Replay { track, .. } = &self.script[i] else { continue };
            match track_at(track, self.time) {
                Some(_) if self.reacting[i] && self.present[i] => {}
                Some((q, v)) => {
                    self.present[i] = true;
                    self.pos[i] = q;
                    self.vel[i] = v;
                    if v.norm() > 1e-6 {
                        self.heading[i] = v.y.atan2(v.x);
                    }
                }
                None => {
                    self.present[i] = false;
                    self.reacting[i] = false;
                    self.pos[i] = parked_at(i);
                    self.vel[i] = Vec2::zeros();
                }
            }
        }
    }
}
