//! A new episode's crowd: each person's start (route phase, first task, place at the tour's
//! start) and speed drawn from the episode's seeded generator, and the walking groups.

use rand::Rng;

use super::react::shift_allowed;
use super::replay::{parked_at, track_at};
use super::scripts::{Face, Script, Task, Until};
use super::{Crowd, SocialForceParams};
use crate::math::Vec2;
use crate::scenario::{Person, Randomize};

impl Crowd {
    /// Builds a crowd of walkers and standing people for a new episode, drawing the randomised
    /// parts from `rng`; people of other behaviours stand still at their pose (use
    /// [`Crowd::spawn_scripted`] with [`super::scripts::plan_scripts`] for them).
    pub fn spawn<R: Rng>(
        persons: &[Person],
        randomize: &Randomize,
        params: SocialForceParams,
        rng: &mut R,
    ) -> Self {
        let scripts: Vec<Script> = persons.iter().map(Script::basic).collect();
        Self::spawn_scripted(persons, &scripts, randomize, params, &[], rng)
    }

    /// Builds the crowd for a new episode with one planned script per person, drawing the
    /// randomised parts (walkers' route phase, visitors' first exhibit and dwell phase, speed
    /// jitter of everyone who walks) from `rng`. A walker's random start on its route is drawn
    /// again (up to [`SPAWN_TRIES`] times) while it lies within `keep_clear`'s discs (centre,
    /// radius in m) widened by the person's radius: the robots' start areas, so that no episode
    /// begins with a person on top of a robot.
    pub fn spawn_scripted<R: Rng>(
        persons: &[Person],
        scripts: &[Script],
        randomize: &Randomize,
        params: SocialForceParams,
        keep_clear: &[(Vec2, f64)],
        rng: &mut R,
    ) -> Self {
        let mut c = Crowd { params, ..Crowd::default() };
        for (p, script) in persons.iter().zip(scripts) {
            let route: Vec<Vec2> = p.route.iter().map(|w| Vec2::new(w[0], w[1])).collect();
            let walker = *script == Script::Walker;
            let jitter = randomize.speed_jitter;
            let replay = matches!(script, Script::Replay { .. });
            let speed = if *script != Script::Still && !replay && jitter > 0.0 {
                p.speed * rng.random_range(1.0 - jitter..=1.0 + jitter)
            } else {
                p.speed
            };
            let (pos, target, heading, task, clock) =
                initial_state(p, script, &route, randomize, keep_clear, rng);
            // A replayed person is in the scene if its track has begun at t = 0.
            let present = match script {
                Script::Replay { track, .. } => track_at(track, 0.0).is_some(),
                _ => true,
            };
            let (pos, vel) = match script {
                Script::Replay { track, .. } => {
                    track_at(track, 0.0).unwrap_or((parked_at(c.len()), Vec2::zeros()))
                }
                _ => (pos, Vec2::zeros()),
            };
            c.present.push(present);
            c.reacting.push(false);
            c.script.push(script.clone());
            c.task.push(task);
            c.leg.push(0);
            c.clock.push(clock);
            c.stuck.push(0.0);
            c.gathered.push(matches!(script, Script::RobotFollower { .. }).then_some(0));
            c.pos.push(pos);
            c.vel.push(vel);
            c.heading.push(heading);
            c.radius.push(p.radius);
            c.group.push(p.group);
            c.speed.push(speed);
            c.target.push(target);
            c.dwell_left.push(0.0);
            c.routes.push(route);
            c.dwell.push(p.dwell);
            c.stops.push(if walker { p.stops.clone() } else { Vec::new() });
            c.walker.push(walker);
            c.reaction.push(p.reaction);
            c.shift.push(shift_allowed(p.behaviour));
        }
        let mut ids: Vec<u32> = c.group.iter().flatten().copied().collect();
        ids.sort_unstable();
        ids.dedup();
        c.group_slot = vec![None; c.len()];
        let n = c.len();
        c.moving = vec![false; n];
        c.anchor = vec![None; n];
        c.squeeze = vec![None; n];
        c.curious_left = vec![c.react_params.curious_time; n];
        c.desired = vec![Vec2::zeros(); n];
        c.face_want = vec![None; n];
        for id in ids {
            // Walking groups: walkers. (Conversation members walk to their places at the same
            // time but without the group terms, whose coherence would pull them into the
            // o-space.)
            let members: Vec<usize> = (0..n).filter(|&k| c.group[k] == Some(id) && c.walker[k]).collect();
            if members.len() >= 2 {
                for &k in &members {
                    c.group_slot[k] = Some(c.groups.len());
                }
                c.groups.push(members);
            }
        }
        c
    }
}

/// Where person `p` starts with `script` (on its `route` for a walker): position, target
/// waypoint, heading, program task and time already spent in it; randomised parts from `rng`.
fn initial_state<R: Rng>(
    p: &Person,
    script: &Script,
    route: &[Vec2],
    randomize: &Randomize,
    keep_clear: &[(Vec2, f64)],
    rng: &mut R,
) -> (Vec2, usize, f64, usize, f64) {
    let (mut task, mut clock) = (0, 0.0);
    let (pos, target, heading) = match script {
        Script::Walker if randomize.person_phase => {
            let blocked = |q: Vec2| keep_clear.iter().any(|(c, r)| (q - c).norm() < r + p.radius);
            let (mut pos, mut target) = point_at_fraction(route, rng.random::<f64>());
            for _ in 1..SPAWN_TRIES {
                if !blocked(pos) {
                    break;
                }
                (pos, target) = point_at_fraction(route, rng.random::<f64>());
            }
            let d = route[target] - pos;
            (pos, target, d.y.atan2(d.x))
        }
        Script::Walker => (route[0], 1, p.pose[2]),
        Script::Program(prog) => {
            let k = if randomize.person_phase && prog.starts.len() > 1 {
                rng.random_range(0..prog.starts.len())
            } else {
                0
            };
            let (t, at) = prog.starts[k];
            task = t;
            let mut heading = p.pose[2];
            if let Some(Task::Stay { face, until }) = prog.tasks.get(t) {
                if let (Until::For(d), true) = (until, randomize.person_phase) {
                    clock = rng.random::<f64>() * d;
                }
                if let Face::Point(q) = face {
                    heading = (q.y - at.y).atan2(q.x - at.x);
                }
            }
            (at, 0, heading)
        }
        Script::Follower { slots, .. } => {
            let at = slots.first().copied().flatten().unwrap_or(Vec2::new(p.pose[0], p.pose[1]));
            (at, 0, p.pose[2])
        }
        Script::RobotFollower { places, start, .. } => {
            // Gathered behind the robot at its start, facing it.
            let at = places.first().and_then(|p| p.first()).copied().unwrap_or(*start);
            let d = start - at;
            (at, usize::MAX, d.y.atan2(d.x))
        }
        Script::Guide { .. } => (route[0], 0, p.pose[2]),
        // Placed by the caller (on its track at t = 0, or parked), facing along its first segment.
        Script::Replay { .. } => (Vec2::new(p.pose[0], p.pose[1]), 0, p.pose[2]),
        Script::Still => (Vec2::new(p.pose[0], p.pose[1]), 0, p.pose[2]),
    };
    (pos, target, heading, task, clock)
}

/// Draws of a walker's start on its route before the last one is kept even if it is not clear
/// of the robots' start areas (see [`Crowd::spawn_scripted`]).
pub const SPAWN_TRIES: usize = 32;

/// The point at `frac` (in [0, 1)) of a closed route's length, and the index of the waypoint
/// that follows it.
fn point_at_fraction(route: &[Vec2], frac: f64) -> (Vec2, usize) {
    let n = route.len();
    let lens: Vec<f64> = (0..n).map(|k| (route[(k + 1) % n] - route[k]).norm()).collect();
    let total: f64 = lens.iter().sum();
    let mut s = frac.clamp(0.0, 1.0) * total;
    for k in 0..n {
        if s < lens[k] || k == n - 1 {
            let t = (s / lens[k].max(1e-12)).min(1.0);
            return (route[k] + (route[(k + 1) % n] - route[k]) * t, (k + 1) % n);
        }
        s -= lens[k];
    }
    (route[0], 1 % n)
}
