//! The `with_*` builders: copies of a validated scenario with one setting replaced (planner,
//! robots, elastic-band gains, goal, the subgoal sensor), checked like the file values.

use super::check::{Checker, err, is_time_of_day};
use super::model::{EbandGains, PlannerKind, Scenario};
use crate::error::Result;

/// Most robots [`Scenario::with_robots`] makes when it samples extra ones.
pub const MAX_ROBOTS: usize = 8;

/// Seed of the extra robots' sampled tasks in [`Scenario::with_robots`] (fixed: the same extra
/// robots in every episode and run).
pub const EXTRA_ROBOTS_SEED: u64 = 0x00AB_0075;

impl Scenario {
    /// A copy with every robot's planner replaced by `name` (one of [`PlannerKind::NAMES`]).
    pub fn with_planner(&self, name: &str) -> Result<Self> {
        let kind = PlannerKind::parse(name).ok_or_else(|| {
            err(&self.source, "planner", format!("one of {:?}", PlannerKind::NAMES), format!("{name:?}"))
        })?;
        let mut s = self.clone();
        for r in &mut s.robots {
            r.planner = kind;
        }
        Ok(s)
    }

    /// A copy with every robot's drive replaced by `name` (one of
    /// [`Drive::NAMES`](crate::control::Drive::NAMES)): `"differential"` makes every robot a
    /// unicycle base, `"holonomic"` every robot a holonomic one. Errors name the field `drive`.
    pub fn with_drive(&self, name: &str) -> Result<Self> {
        use crate::control::Drive;
        let drive = Drive::parse(name).ok_or_else(|| {
            err(&self.source, "drive", format!("one of {:?}", Drive::NAMES), format!("{name:?}"))
        })?;
        let mut s = self.clone();
        for r in &mut s.robots {
            r.drive = drive;
        }
        Ok(s)
    }

    /// A copy with robot `index`'s planner replaced by `name` (one of [`PlannerKind::NAMES`]).
    pub fn with_robot_planner(&self, index: usize, name: &str) -> Result<Self> {
        let field = format!("robot[{index}].planner");
        if index >= self.robots.len() {
            return Err(err(
                &self.source,
                format!("robot[{index}]"),
                format!("a robot index below {}", self.robots.len()),
                index.to_string(),
            ));
        }
        let kind = PlannerKind::parse(name).ok_or_else(|| {
            err(&self.source, field, format!("one of {:?}", PlannerKind::NAMES), format!("{name:?}"))
        })?;
        let mut s = self.clone();
        s.robots[index].planner = kind;
        Ok(s)
    }

    /// A copy with `n` robots (1 <= `n` <= [`MAX_ROBOTS`]): the first `n` robots of the file, and
    /// if `n` is more than the file has, extra robots shaped like robot 0 (radius, limits,
    /// planner) whose starts and goals are sampled free and reachable the way generated scenes'
    /// are ([`generate::sample_tasks`](super::generate::sample_tasks), seed [`EXTRA_ROBOTS_SEED`]),
    /// named `robot_<index>`. Followers of a robot that is left out stay at their place at its
    /// tour's start. Errors name `robots`: a count out of range, or no room for the extra robots.
    pub fn with_robots(&self, n: usize) -> Result<Self> {
        if n == 0 || n > MAX_ROBOTS.max(self.robots.len()) {
            return Err(err(
                &self.source,
                "robots",
                format!(
                    "a number of robots in [1, {}] (the file's {} [[robot]] entries, then sampled ones)",
                    MAX_ROBOTS.max(self.robots.len()),
                    self.robots.len()
                ),
                n.to_string(),
            ));
        }
        let mut s = self.clone();
        if n > self.robots.len() {
            let tasks = super::generate::sample_tasks(
                self,
                self.robots.len(),
                n - self.robots.len(),
                EXTRA_ROBOTS_SEED,
            )?;
            for (k, (start, goal)) in tasks.into_iter().enumerate() {
                let mut r = self.robots[0].clone();
                let index = self.robots.len() + k;
                r.name = format!("robot_{index}");
                while s.robots.iter().any(|q| q.name == r.name) {
                    r.name.push('_');
                }
                r.start = start;
                r.goal = goal;
                r.approach = None;
                r.waypoints.clear();
                r.dwell = 0.0;
                s.robots.push(r);
            }
            return Ok(s);
        }
        s.robots.truncate(n);
        for p in &mut s.persons {
            if p.guide_robot.is_some_and(|j| j >= n) {
                p.guide_robot = None; // the tour waits at its start for a guide that is not there
            }
        }
        Ok(s)
    }

    /// A copy with every robot's elastic-band gains replaced by `gains` (name, value): each name
    /// one of [`EbandGains::NAMES`], each value a number in `[0, EbandGains::MAX]`. Errors name
    /// the field `eband.<gain>` (an unknown name first, then a value out of range).
    pub fn with_eband_gains(&self, gains: &[(&str, f64)]) -> Result<Self> {
        let values = EbandGains::by_name(&self.source, "eband", gains)?;
        let mut s = self.clone();
        for r in &mut s.robots {
            r.eband = r.eband.merged(&self.source, "eband", values)?;
        }
        Ok(s)
    }

    /// A copy whose episode starts at `time` (seconds after midnight, in [0, 86400)) instead of
    /// the file's `scene.start_time`: the agenda's activities (times of day) then fall at another
    /// point of the episode. Times the validated scenario holds as seconds into the episode keep
    /// their value, including a conversation's `start` and `end` written as times of day (they
    /// were converted with the file's start time). Errors name the field `scene.start_time`.
    pub fn with_start_time(&self, time: f64) -> Result<Self> {
        if !is_time_of_day(time) {
            return Err(err(
                &self.source,
                "scene.start_time",
                "seconds after midnight in [0, 86400)",
                time.to_string(),
            ));
        }
        let mut s = self.clone();
        s.scene.start_time = time;
        Ok(s)
    }

    /// A copy whose observation has the `subgoal` key with look-ahead `lookahead` (metres, in
    /// [0, 10]; 0 leaves the key out): see [`Sensors::subgoal`](super::model::Sensors::subgoal).
    /// Errors name the field `sensors.subgoal`.
    pub fn with_subgoal(&self, lookahead: f64) -> Result<Self> {
        Checker { file: &self.source }.range("sensors.subgoal", lookahead, 0.0, 10.0, false)?;
        let mut s = self.clone();
        s.sensors.subgoal = lookahead;
        Ok(s)
    }

    /// A copy whose robot `robot` goes to `goal` (world frame, metres; inside `scene.bounds`)
    /// instead of its file goal or approach task. Whether the goal is free space is checked when
    /// a world is built from the scenario.
    pub fn with_goal(&self, robot: usize, goal: [f64; 2]) -> Result<Self> {
        let field = format!("robot[{robot}].goal");
        if robot >= self.robots.len() {
            return Err(err(
                &self.source,
                field,
                format!("a robot index below {}", self.robots.len()),
                format!("{robot}"),
            ));
        }
        Checker { file: &self.source }.inside(&field, goal, self.scene.bounds)?;
        let mut s = self.clone();
        s.robots[robot].goal = goal;
        s.robots[robot].approach = None;
        Ok(s)
    }
}
