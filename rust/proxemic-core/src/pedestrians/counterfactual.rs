//! The robot-free run of an episode: the same people from the same spawn, stepped with no robot
//! as an obstacle, for the robot's cost to people (`ped_*` metrics of `docs/metrics.md`).
//!
//! The people's stepping draws no random number (every draw is made once, at the spawn), so the
//! crowd cloned right after the spawn and stepped with the same control period is the episode's
//! crowd without the robots. The robots stay the *guides* of their tours: followers of a robot's
//! tour still walk the trail the robot walked (the guide states are recorded per step), only the
//! robots' bodies are gone (no force on people, no keep-out, no reactions). It is stepped lazily, when
//! the metrics are asked for, over the steps recorded since the last call, so an episode's
//! counterfactual costs one crowd stepping without robots, at most once per step.

use std::time::{Duration, Instant};

use super::{Crowd, GuideState};
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::math::Vec2;
use crate::metrics::RobotFreeTracks;

/// The instants at which each person's script moves on (a way-point reached, a walk's leg done,
/// a task finished), per person, in order: a person's progress through their script.
#[derive(Clone, Debug, Default)]
pub struct Stages {
    key: Vec<(usize, usize, usize)>,
    /// Per person, the control instants of their stage changes.
    pub events: Vec<Vec<usize>>,
}

impl Stages {
    /// The stages of `crowd` at instant 0 (no event yet).
    pub fn new(crowd: &Crowd) -> Self {
        let n = crowd.len();
        Stages { key: (0..n).map(|i| stage_key(crowd, i)).collect(), events: vec![Vec::new(); n] }
    }

    /// Notes the stage changes of `crowd` at control instant `instant`.
    pub fn observe(&mut self, crowd: &Crowd, instant: usize) {
        for (i, (key, events)) in self.key.iter_mut().zip(&mut self.events).enumerate() {
            let now = stage_key(crowd, i);
            if now != *key {
                *key = now;
                events.push(instant);
            }
        }
    }
}

/// Where person `i` is in their script: the way-point they walk to, the task and the leg of a
/// program's walk.
fn stage_key(crowd: &Crowd, i: usize) -> (usize, usize, usize) {
    (crowd.target[i], crowd.task[i], crowd.leg[i])
}

/// The robot-free run of the current episode (see the module documentation).
#[derive(Clone, Debug, Default)]
pub struct RobotFree {
    crowd: Crowd,
    dt: f64,
    robots: usize,
    /// Guide states recorded per control step (`robots` each).
    guides: Vec<GuideState>,
    /// Control steps recorded, and stepped so far in the robot-free crowd.
    recorded: usize,
    stepped: usize,
    /// The robot-free people's centres per instant (row-major, instant 0 first).
    positions: Vec<Vec2>,
    stages: Stages,
    real_stages: Stages,
    elapsed: Duration,
}

impl RobotFree {
    /// The robot-free run of an episode whose people were just spawned as `crowd`, with `robots`
    /// robots and a control period of `dt` seconds.
    pub fn new(crowd: &Crowd, robots: usize, dt: f64) -> Self {
        RobotFree {
            crowd: crowd.clone(),
            dt,
            robots,
            guides: Vec::new(),
            recorded: 0,
            stepped: 0,
            positions: crowd.pos.clone(),
            stages: Stages::new(crowd),
            real_stages: Stages::new(crowd),
            elapsed: Duration::ZERO,
        }
    }

    /// Records one control step of the episode: the robots as guides during it (`robots`
    /// entries) and the episode's crowd after it (for its stage changes).
    pub fn record(&mut self, guides: &[GuideState], real: &Crowd) {
        self.guides.extend((0..self.robots).map(|k| guides.get(k).copied().unwrap_or_default()));
        self.recorded += 1;
        self.real_stages.observe(real, self.recorded);
    }

    /// Steps the robot-free crowd over the recorded steps it has not made yet.
    pub fn advance(&mut self, geometry: &StaticGeometry, field: &DistanceField) {
        if self.stepped == self.recorded {
            return;
        }
        let start = Instant::now();
        while self.stepped < self.recorded {
            let k = self.stepped;
            self.crowd.set_guides(&self.guides[k * self.robots..(k + 1) * self.robots]);
            self.crowd.step(self.dt, &[], geometry, field);
            self.stepped += 1;
            self.positions.extend_from_slice(&self.crowd.pos);
            self.stages.observe(&self.crowd, self.stepped);
        }
        self.elapsed += start.elapsed();
    }

    /// The robot-free tracks over the instants stepped so far.
    pub fn tracks(&self) -> RobotFreeTracks<'_> {
        RobotFreeTracks {
            positions: &self.positions,
            instants: self.stepped + 1,
            stages: &self.stages.events,
            real_stages: &self.real_stages.events,
        }
    }

    /// Wall-clock time spent stepping the robot-free crowd this episode (for benchmarks).
    pub fn elapsed(&self) -> Duration {
        self.elapsed
    }
}
