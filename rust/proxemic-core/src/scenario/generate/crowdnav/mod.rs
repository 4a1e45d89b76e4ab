//! CrowdNav's test scenes (Chen, Liu, Kreiss, Alahi, "Crowd-robot interaction: crowd-aware robot
//! navigation with attention-based deep reinforcement learning", ICRA 2019, and its simulator
//! `crowd_sim`) as seeded scene families: `crowdnav/circle_crossing` and
//! `crowdnav/square_crossing`.
//!
//! As CrowdNav's `env.config` and `crowd_sim.py` set them (read, not copied; `docs/crowdnav.md`):
//! - the robot, of radius 0.3 m and preferred speed 1 m/s, drives from (0, -4) to (0, 4);
//! - circle crossing: each person starts at angle `a` ~ U[0, 2 pi) on the circle of radius 4 m,
//!   plus a noise U[-0.5, 0.5] m on each axis, and walks to the opposite point (its start
//!   mirrored through the origin);
//! - square crossing: each person starts on a random side (x ~ U[0, 5] m with that side's sign,
//!   y ~ U[-5, 5] m) of the 10 m square and walks to a point on the other side;
//! - a draw is rejected and drawn again while it is closer than 0.8 m (two radii plus the 0.2 m
//!   discomfort distance) to an agent already placed: for circle crossing to its start or its goal,
//!   for square crossing the start to the starts and the goal to the goals;
//! - people of radius 0.3 m and preferred speed 1 m/s, time step 0.25 s (`control_hz = 4`),
//!   time limit 25 s.
//!
//! CrowdNav draws with numpy's generator; these scenes draw the same distributions from the
//! scene's seed (ChaCha8), so the scenes are CrowdNav's in distribution, not one for one. The
//! people are written as one-way walkers (they stay at their goal); the CrowdNav protocol's own
//! kinematic episodes ([`crate::world::crowdnav`]) run them with ORCA as CrowdNav does.
//!
//! Spec: `crowdnav/<family>[?humans=N&visible=true|false&seed=S&drive=D]`, defaults 5 humans,
//! robot invisible (the people ignore it, `reaction = "ignore"`), seed 0, holonomic robot
//! (`drive=differential`: CrowdNav's unicycle robot, [`crate::world::crowdnav`]).

use std::fmt::Write as _;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::Generated;
use super::layout::round2;
use super::params::{each_parameter, parse_drive, perr};
use crate::control::Drive;
use crate::error::Result;
use crate::scenario::Scenario;

/// The prefix of a CrowdNav scene's spec.
pub const PREFIX: &str = "crowdnav/";

/// The families, in the order the suite runs them.
pub const FAMILIES: [&str; 2] = ["circle_crossing", "square_crossing"];

/// Radius of the circle of circle crossing (m; CrowdNav's `circle_radius`).
pub const CIRCLE_RADIUS: f64 = 4.0;
/// Side of the square of square crossing (m; CrowdNav's `square_width`).
pub const SQUARE_WIDTH: f64 = 10.0;
/// Radius of every person and of the robot (m).
pub const RADIUS: f64 = 0.3;
/// Preferred speed of every person and of the robot (m/s).
pub const V_PREF: f64 = 1.0;
/// CrowdNav's discomfort distance (m, body edge to body edge): a step closer is a discomfort step.
pub const DISCOMFORT_DIST: f64 = 0.2;
/// Time step (s).
pub const TIME_STEP: f64 = 0.25;
/// Time limit (s).
pub const TIME_LIMIT: f64 = 25.0;
/// Most people a scene may have (rejection sampling must find room for them).
pub const MAX_HUMANS: usize = 20;
/// Draws tried per person before the scene is refused (CrowdNav retries for ever).
const TRIES: usize = 100_000;
/// Whole-scene redraws before the scene is refused.
const RESTARTS: usize = 100;

/// A parsed spec.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// One of [`FAMILIES`].
    pub family: String,
    /// Number of people, in [1, [`MAX_HUMANS`]]; default 5.
    pub humans: usize,
    /// Whether the people see the robot (CrowdNav's `robot.visible`); default false.
    pub visible: bool,
    /// The scene seed; default 0.
    pub seed: u64,
    /// The robot's drive: holonomic (default) or differential (CrowdNav's `unicycle` kinematics).
    pub drive: Drive,
}

impl Spec {
    /// The canonical spec text (parameters that differ from the defaults, in the order humans,
    /// visible, seed, drive).
    pub fn text(&self) -> String {
        let mut pairs = Vec::new();
        if self.humans != 5 {
            pairs.push(format!("humans={}", self.humans));
        }
        if self.visible {
            pairs.push("visible=true".to_string());
        }
        if self.seed != 0 {
            pairs.push(format!("seed={}", self.seed));
        }
        if !self.drive.is_holonomic() {
            pairs.push(format!("drive={}", self.drive.name()));
        }
        let q = if pairs.is_empty() { String::new() } else { format!("?{}", pairs.join("&")) };
        format!("{PREFIX}{}{q}", self.family)
    }
}

/// Parses `crowdnav/<family>[?humans=N&visible=B&seed=S&drive=D]`. Errors are
/// [`crate::CoreError::Scenario`] naming the spec and the part that is wrong.
pub fn parse_spec(spec: &str) -> Result<Spec> {
    let rest = spec.strip_prefix(PREFIX).ok_or_else(|| {
        perr(
            spec,
            "<spec>",
            "crowdnav/<family>[?humans=N&visible=true|false&seed=S&drive=D]",
            format!("{spec:?}"),
        )
    })?;
    let (name, query) = rest.split_once('?').map_or((rest, None), |(n, q)| (n, Some(q)));
    if !FAMILIES.contains(&name) {
        return Err(perr(spec, "family", format!("one of {FAMILIES:?}"), format!("{name:?}")));
    }
    let mut out =
        Spec { family: name.to_string(), humans: 5, visible: false, seed: 0, drive: Drive::Holonomic };
    each_parameter(spec, query.unwrap_or(""), |k, v| {
        match k {
            "humans" => {
                let n = v.trim().parse::<usize>().ok().filter(|n| (1..=MAX_HUMANS).contains(n));
                out.humans = n.ok_or_else(|| {
                    perr(spec, "humans", format!("an integer in [1, {MAX_HUMANS}]"), format!("{v:?}"))
                })?;
            }
            "visible" => {
                out.visible = match v.trim() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(perr(spec, "visible", "true or false", format!("{v:?}"))),
                };
            }
            "seed" => {
                out.seed = v
                    .trim()
                    .parse::<u64>()
                    .map_err(|_| perr(spec, "seed", "a non-negative integer seed", format!("{v:?}")))?;
            }
            "drive" => out.drive = parse_drive(spec, v)?,
            _ => {
                return Err(perr(
                    spec,
                    k,
                    "a parameter among [\"humans\", \"visible\", \"seed\", \"drive\"]",
                    format!("{k:?}"),
                ));
            }
        }
        Ok(())
    })?;
    Ok(out)
}

/// Generates the scene of a spec `crowdnav/<family>[?...]`.
pub fn generate(spec: &str) -> Result<Generated> {
    build(&parse_spec(spec)?)
}

/// The robot's start and goal (m).
pub const ROBOT_START: [f64; 2] = [0.0, -CIRCLE_RADIUS];
/// The robot's goal (m).
pub const ROBOT_GOAL: [f64; 2] = [0.0, CIRCLE_RADIUS];

/// The robot's start heading (rad): toward its goal, π/2 written to two decimals as the scene file
/// writes it.
pub const ROBOT_HEADING: f64 = 1.57;

/// The people's starts and goals of a parsed spec, `(start, goal)` per person, rounded to
/// centimetres. Errors: no room for a person after many draws.
pub fn draw_people(s: &Spec) -> Result<Vec<([f64; 2], [f64; 2])>> {
    let salt = s
        .family
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    let mut rng = ChaCha8Rng::seed_from_u64(s.seed ^ salt);
    let min_dist = 2.0 * RADIUS + DISCOMFORT_DIST;
    // Every agent placed so far, robot first: (start, goal).
    let mut agents: Vec<([f64; 2], [f64; 2])> = vec![(ROBOT_START, ROBOT_GOAL)];
    let far = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) >= min_dist;
    let no_room =
        || perr(&s.text(), "humans", "few enough people to place them 0.8 m apart", s.humans.to_string());
    // CrowdNav redraws a person for ever; a draw that finds no room in `TRIES` draws (0.3% of
    // 20-person circle crossings, some of which have no room at all) redraws the whole scene from
    // the same stream, up to `RESTARTS` times.
    for _ in 0..RESTARTS {
        agents.truncate(1);
        let mut full = true;
        for _ in 0..s.humans {
            let placed = if s.family == "circle_crossing" {
                (0..TRIES).find_map(|_| {
                    let a = rng.random::<f64>() * std::f64::consts::TAU;
                    let nx = (rng.random::<f64>() - 0.5) * V_PREF;
                    let ny = (rng.random::<f64>() - 0.5) * V_PREF;
                    let p = [round2(CIRCLE_RADIUS * a.cos() + nx), round2(CIRCLE_RADIUS * a.sin() + ny)];
                    agents.iter().all(|(st, g)| far(p, *st) && far(p, *g)).then_some((p, [-p[0], -p[1]]))
                })
            } else {
                let sign = if rng.random::<f64>() > 0.5 { -1.0 } else { 1.0 };
                let half = SQUARE_WIDTH * 0.5;
                let mut side = |sign: f64| {
                    [
                        round2(rng.random::<f64>() * half * sign),
                        round2((rng.random::<f64>() - 0.5) * SQUARE_WIDTH),
                    ]
                };
                let start =
                    (0..TRIES).map(|_| side(sign)).find(|p| agents.iter().all(|(st, _)| far(*p, *st)));
                let goal = (0..TRIES).map(|_| side(-sign)).find(|p| agents.iter().all(|(_, g)| far(*p, *g)));
                start.zip(goal)
            };
            match placed {
                Some(a) => agents.push(a),
                None => {
                    full = false;
                    break;
                }
            }
        }
        if full {
            return Ok(agents.split_off(1));
        }
    }
    Err(no_room())
}

/// Generates the scene of a parsed spec.
pub fn build(s: &Spec) -> Result<Generated> {
    let source = s.text();
    let people = draw_people(s)?;
    let mut t = String::new();
    let _ = writeln!(t, "# Generated by proxemic (CrowdNav protocol), {source}.\n");
    let _ = writeln!(t, "[scene]\nname = \"crowdnav_{}\"", s.family);
    let _ = writeln!(t, "bounds = [-8.0, -8.0, 8.0, 8.0]\ncontrol_hz = {:?}", 1.0 / TIME_STEP);
    let _ = writeln!(t, "reaction = \"{}\"", if s.visible { "aware" } else { "ignore" });
    let _ = writeln!(
        t,
        "description = \"CrowdNav {}: {} people (radius {RADIUS} m, {V_PREF} m/s) cross while the robot drives from (0, -4) to (0, 4); the people {} the robot (seed {}).\"\n",
        s.family.replace('_', " "),
        s.humans,
        if s.visible { "see" } else { "do not see" },
        s.seed
    );
    for (k, (start, goal)) in people.iter().enumerate() {
        let _ = writeln!(
            t,
            "[[person]]\nname = \"person_{k}\"\nbehaviour = \"walker\"\nroute = [[{:?}, {:?}], [{:?}, {:?}]]\nspeed = {V_PREF:?}\nradius = {RADIUS:?}\nstops = [1]\ndwell = 3600.0\n",
            start[0], start[1], goal[0], goal[1]
        );
    }
    let _ = writeln!(
        t,
        "[[robot]]\nname = \"robot_0\"\nstart = [{:?}, {:?}, {:?}]\ngoal = [{:?}, {:?}]\nradius = {RADIUS:?}\nmax_speed = {V_PREF:?}\nplanner = \"astar_orca\"\n{}",
        ROBOT_START[0],
        ROBOT_START[1],
        ROBOT_HEADING,
        ROBOT_GOAL[0],
        ROBOT_GOAL[1],
        super::drive_line(s.drive)
    );
    let _ = writeln!(t, "[episode]\nmax_time = {TIME_LIMIT:?}\nsuccess_radius = {RADIUS:?}\n");
    let _ = writeln!(
        t,
        "[episode.randomize]\nperson_phase = false\nspeed_jitter = 0.0\nrobot_start_jitter = 0.0"
    );
    let scenario = Scenario::from_toml_str(&t, &source)?;
    Ok(Generated { toml: t, scenario })
}

#[cfg(test)]
mod tests;
