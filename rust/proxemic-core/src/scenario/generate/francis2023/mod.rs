//! The scenario archetypes of Francis et al. 2023 ("Principles and guidelines for evaluating
//! social robot navigation algorithms", §V "Scenarios" and its figure of scenario diagrams) as
//! seeded, parametric scene families.
//!
//! Each archetype (`archetypes.rs`, one function per archetype) draws its free parameters
//! (widths, lengths, speeds, angles, offsets) from the seed, within ranges written beside it,
//! lays out walls, people and robots, and writes a scenario file; the file loads like any other.
//! The spec naming a scene is `francis2023/<archetype>` (seed 0) or
//! `francis2023/<archetype>?seed=N&max_time=T&drive=D` ([`parse_spec`]); same spec, same text, bit
//! for bit. `drive=differential` makes every robot a differential-drive base (the scene's draws
//! are the same).
//!
//! Conventions shared by every archetype: the robot drives from west to east unless the archetype
//! says otherwise; people's walks are one way (`walker` with a stop of an hour at the end of the
//! route), so each person does what the archetype says once and then stands where they arrived;
//! the episode randomises nothing (no walker phase, no speed jitter, no start jitter): the scene's
//! seed is the only source of variation, so `proxemic eval --suite francis2023` runs episode `k`
//! on the scene of seed `k`.

mod archetypes;

use std::fmt::Write as _;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::Generated;
use super::layout::round2;
use super::params::{each_parameter, parse_drive, perr};
use crate::control::Drive;
use crate::error::Result;
use crate::scenario::Scenario;

/// The prefix of a Francis et al. 2023 scene's spec.
pub const PREFIX: &str = "francis2023/";

/// The archetypes, in the order the suite runs them: the 25 panels (a)-(y) of the paper's Fig. 7
/// in its order, panel (f) "Intersection No Gesture" twice (`crossing_90`, and `crossing_45` with
/// the paths at 45 deg).
pub const ARCHETYPES: [&str; 26] = [
    "frontal_approach",
    "pedestrian_obstruction",
    "pedestrian_overtaking",
    "robot_overtaking",
    "down_path",
    "crossing_90",
    "crossing_45",
    "intersection_wait",
    "intersection_proceed",
    "blind_corner",
    "narrow_hallway",
    "narrow_doorway",
    "entering_room",
    "exiting_room",
    "entering_elevator",
    "exiting_elevator",
    "joining_group",
    "leaving_group",
    "following_person",
    "leading_person",
    "accompanying_person",
    "dense_crowd",
    "parallel_traffic",
    "perpendicular_traffic",
    "circular_crossing",
    "robot_crowding",
];

/// Wall thickness (m) of every archetype's walls.
pub(crate) const WALL: f64 = 0.2;
/// Half the wall thickness (m).
const H: f64 = WALL / 2.0;
/// The robot's default top speed (m/s), used to time people's walks so they meet the robot.
pub(crate) const ROBOT_SPEED: f64 = 0.55;
/// A one-way walk's dwell at its end (s): the person stays there for the rest of the episode.
const STAY: f64 = 3600.0;

/// A parsed spec: the archetype, the seed and the episode length override.
#[derive(Clone, Debug, PartialEq)]
pub struct Spec {
    /// One of [`ARCHETYPES`].
    pub archetype: String,
    /// The scene seed (default 0).
    pub seed: u64,
    /// Episode length (s), in [5, 600]; default: the archetype's own (long enough for its task).
    pub max_time: Option<f64>,
    /// Every robot's drive; default holonomic.
    pub drive: Drive,
}

impl Spec {
    /// The canonical spec text: `francis2023/<archetype>` plus `?seed=N&max_time=T&drive=D` for
    /// the values that differ from the defaults.
    pub fn text(&self) -> String {
        let mut pairs = Vec::new();
        if self.seed != 0 {
            pairs.push(format!("seed={}", self.seed));
        }
        if let Some(t) = self.max_time {
            pairs.push(format!("max_time={t}"));
        }
        if !self.drive.is_holonomic() {
            pairs.push(format!("drive={}", self.drive.name()));
        }
        let q = if pairs.is_empty() { String::new() } else { format!("?{}", pairs.join("&")) };
        format!("{PREFIX}{}{q}", self.archetype)
    }
}

/// Parses `francis2023/<archetype>[?seed=N&max_time=T&drive=D]`. Errors are [`crate::CoreError::Scenario`] naming
/// the spec and the part that is wrong (an unknown archetype lists them all).
pub fn parse_spec(spec: &str) -> Result<Spec> {
    let rest = spec.strip_prefix(PREFIX).ok_or_else(|| {
        perr(spec, "<spec>", "francis2023/<archetype>[?seed=N&max_time=T&drive=D]", format!("{spec:?}"))
    })?;
    let (name, query) = match rest.split_once('?') {
        Some((n, q)) => (n, Some(q)),
        None => (rest, None),
    };
    if !ARCHETYPES.contains(&name) {
        return Err(perr(spec, "archetype", format!("one of {ARCHETYPES:?}"), format!("{name:?}")));
    }
    let mut out = Spec { archetype: name.to_string(), seed: 0, max_time: None, drive: Drive::Holonomic };
    each_parameter(spec, query.unwrap_or(""), |k, v| {
        match k {
            "seed" => {
                out.seed = v
                    .trim()
                    .parse::<u64>()
                    .map_err(|_| perr(spec, "seed", "a non-negative integer seed", format!("{v:?}")))?;
            }
            "max_time" => {
                let t = v.trim().parse::<f64>().ok().filter(|t| t.is_finite() && (5.0..=600.0).contains(t));
                out.max_time = Some(t.ok_or_else(|| {
                    perr(spec, "max_time", "a number of seconds in [5, 600]", format!("{v:?}"))
                })?);
            }
            "drive" => out.drive = parse_drive(spec, v)?,
            _ => {
                return Err(perr(
                    spec,
                    k,
                    "a parameter among [\"seed\", \"max_time\", \"drive\"]",
                    format!("{k:?}"),
                ));
            }
        }
        Ok(())
    })?;
    Ok(out)
}

/// Generates the scene of a spec `francis2023/<archetype>[?seed=N&max_time=T&drive=D]`.
pub fn generate(spec: &str) -> Result<Generated> {
    let s = parse_spec(spec)?;
    build(&s)
}

/// Generates the scene of a parsed spec.
pub fn build(s: &Spec) -> Result<Generated> {
    let source = s.text();
    // Each archetype its own stream: the same seed draws unrelated values in two archetypes.
    let salt = s
        .archetype
        .bytes()
        .fold(0xcbf2_9ce4_8422_2325u64, |h, b| (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3));
    let mut d = Draft::new(ChaCha8Rng::seed_from_u64(s.seed ^ salt));
    archetypes::lay_out(&s.archetype, &mut d);
    if let Some(t) = s.max_time {
        d.max_time = t;
    }
    let toml = d.render(s);
    let scenario = Scenario::from_toml_str(&toml, &source)?;
    Ok(Generated { toml, scenario })
}

/// What a person does in an archetype.
pub(crate) enum Ped {
    /// Walks the way-points once at `speed` (m/s) and stays at the last.
    Walk { route: Vec<[f64; 2]>, speed: f64 },
    /// Walks the closed route over and over (milling in a crowd).
    Loop { route: Vec<[f64; 2]>, speed: f64 },
    /// Stands at `pose` ([x, y, theta]), a member of ground-truth group `group` if given.
    Stand { pose: [f64; 3], group: Option<u32> },
    /// Follows robot 0 (the `follower` script with `guide = "robot:robot_0"`): starts
    /// `gather` metres behind the robot's start, walks its trail up to the follow gap behind it
    /// and gathers `gather` metres behind it where it stops.
    FollowRobot { speed: f64, gather: f64 },
}

/// A robot's task: a goal point, or joining a conversation group (an approach task).
pub(crate) enum Goal {
    Point([f64; 2]),
    Group(u32),
}

/// A scene being laid out: the seed's random stream, walls (centre lines), people, robots.
pub(crate) struct Draft {
    rng: ChaCha8Rng,
    /// Wall centre lines (thickness [`WALL`]).
    pub(crate) walls: Vec<([f64; 2], [f64; 2])>,
    pub(crate) people: Vec<Ped>,
    /// Start pose and task of every robot.
    pub(crate) robots: Vec<([f64; 3], Goal)>,
    /// Episode length (s).
    pub(crate) max_time: f64,
    /// The drawn parameters, `(name, value, unit)`, written into the scene's description.
    pub(crate) params: Vec<(&'static str, f64, &'static str)>,
    /// One sentence on the layout, for the description.
    pub(crate) what: String,
}

impl Draft {
    fn new(rng: ChaCha8Rng) -> Self {
        Draft {
            rng,
            walls: Vec::new(),
            people: Vec::new(),
            robots: Vec::new(),
            max_time: 60.0,
            params: Vec::new(),
            what: String::new(),
        }
    }

    /// A parameter drawn uniformly in [lo, hi] and rounded to centimetres (hundredths), recorded
    /// under `name` for the description.
    pub(crate) fn draw(&mut self, name: &'static str, lo: f64, hi: f64, unit: &'static str) -> f64 {
        let v = round2(self.rng.random_range(lo..=hi));
        self.params.push((name, v, unit));
        v
    }

    /// An integer drawn uniformly in [lo, hi], recorded under `name`.
    pub(crate) fn draw_int(&mut self, name: &'static str, lo: usize, hi: usize) -> usize {
        let v = self.rng.random_range(lo..=hi);
        self.params.push((name, v as f64, ""));
        v
    }

    /// A side, -1 or +1, recorded under `name`.
    pub(crate) fn side(&mut self, name: &'static str) -> f64 {
        let v = if self.rng.random_bool(0.5) { 1.0 } else { -1.0 };
        self.params.push((name, v, ""));
        v
    }

    /// An unrecorded small jitter in [-a, a] (centimetres), e.g. of crowd members' places.
    pub(crate) fn jitter(&mut self, a: f64) -> f64 {
        round2(self.rng.random_range(-a..=a))
    }

    /// A wall of thickness [`WALL`] along the centre line `a`-`b` (its polygon runs half a
    /// thickness past both ends, closing corners).
    pub(crate) fn wall(&mut self, a: [f64; 2], b: [f64; 2]) {
        self.walls.push(([round2(a[0]), round2(a[1])], [round2(b[0]), round2(b[1])]));
    }

    /// The walls round the clear rectangle [x0, x1] x [y0, y1] (their inner faces on its edges).
    pub(crate) fn room(&mut self, x0: f64, y0: f64, x1: f64, y1: f64) {
        self.wall([x0, y0 - H], [x1, y0 - H]);
        self.wall([x0, y1 + H], [x1, y1 + H]);
        self.wall([x0 - H, y0], [x0 - H, y1]);
        self.wall([x1 + H, y0], [x1 + H, y1]);
    }

    /// A wall whose face runs from `a` to `b` exactly (no overhang past its ends: for a door's
    /// jambs and convex corners), its body on the side of the unit normal `out`.
    pub(crate) fn face(&mut self, a: [f64; 2], b: [f64; 2], out: [f64; 2]) {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt().max(1e-9);
        let t = [dx / len * H, dy / len * H];
        let o = [out[0] * H, out[1] * H];
        self.wall([a[0] + o[0] + t[0], a[1] + o[1] + t[1]], [b[0] + o[0] - t[0], b[1] + o[1] - t[1]]);
    }

    pub(crate) fn person(&mut self, p: Ped) {
        self.people.push(p);
    }

    /// A robot at `start` facing `goal`, driving there.
    pub(crate) fn robot_to(&mut self, start: [f64; 2], goal: [f64; 2]) {
        let theta = (goal[1] - start[1]).atan2(goal[0] - start[0]);
        self.robots.push(([round2(start[0]), round2(start[1]), round2(theta)], Goal::Point(pt2(goal))));
    }

    /// Episode length for a robot trip of `length` metres: three times the time at top speed,
    /// at least 30 s, rounded up to 5 s.
    pub(crate) fn time_for(&mut self, length: f64) {
        self.max_time = ((3.0 * length / ROBOT_SPEED).max(30.0) / 5.0).ceil() * 5.0;
    }

    /// The scene's bounds: the walls' extent.
    fn bounds(&self) -> [f64; 4] {
        let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for (p, q) in &self.walls {
            for r in [p, q] {
                b = [b[0].min(r[0]), b[1].min(r[1]), b[2].max(r[0]), b[3].max(r[1])];
            }
        }
        [round2(b[0] - WALL), round2(b[1] - WALL), round2(b[2] + WALL), round2(b[3] + WALL)]
    }

    fn render(&self, s: &Spec) -> String {
        let mut t = String::new();
        let arch = &s.archetype;
        let b = self.bounds();
        let params: Vec<String> = self
            .params
            .iter()
            .map(|(k, v, u)| if u.is_empty() { format!("{k} = {v}") } else { format!("{k} = {v} {u}") })
            .collect();
        let _ = writeln!(t, "# Generated by proxemic (Francis et al. 2023 archetype), {}.\n", s.text());
        let _ = writeln!(t, "[scene]\nname = \"francis2023_{arch}\"");
        let _ = writeln!(t, "bounds = [{:?}, {:?}, {:?}, {:?}]", b[0], b[1], b[2], b[3]);
        let _ = writeln!(
            t,
            "description = \"Francis et al. 2023, {}: {} (seed {}: {}).\"\n",
            arch.replace('_', " "),
            self.what,
            s.seed,
            params.join(", ")
        );
        for (a, c) in &self.walls {
            let _ = writeln!(t, "[[wall]]\nfrom = {}\nto = {}\nthickness = {WALL:?}\n", pt(*a), pt(*c));
        }
        for (k, p) in self.people.iter().enumerate() {
            let _ = writeln!(t, "[[person]]\nname = \"person_{k}\"");
            match p {
                Ped::Walk { route, speed } | Ped::Loop { route, speed } => {
                    // A walk of more than one leg goes back the way it came after its stay (the
                    // route is closed: its last leg must not cut through walls).
                    let mut route = route.clone();
                    let end = route.len() - 1;
                    if matches!(p, Ped::Walk { .. }) && end > 1 {
                        route.extend(route[1..end].iter().rev().copied().collect::<Vec<_>>());
                    }
                    let pts: Vec<String> = route.iter().map(|q| pt(pt2(*q))).collect();
                    let _ = writeln!(
                        t,
                        "behaviour = \"walker\"\nroute = [{}]\nspeed = {:?}",
                        pts.join(", "),
                        round2(*speed)
                    );
                    if matches!(p, Ped::Walk { .. }) {
                        let _ = writeln!(t, "stops = [{end}]\ndwell = {STAY:?}");
                    }
                }
                Ped::Stand { pose, group } => {
                    let _ = writeln!(
                        t,
                        "behaviour = \"standing\"\npose = [{:?}, {:?}, {:?}]",
                        round2(pose[0]),
                        round2(pose[1]),
                        round2(pose[2])
                    );
                    if let Some(g) = group {
                        let _ = writeln!(t, "group = {g}");
                    }
                }
                Ped::FollowRobot { speed, gather } => {
                    let _ = writeln!(
                        t,
                        "behaviour = \"follower\"\nguide = \"robot:robot_0\"\nspeed = {:?}\ngather_radius = {:?}",
                        round2(*speed),
                        round2(*gather)
                    );
                }
            }
            t.push('\n');
        }
        for (k, (start, goal)) in self.robots.iter().enumerate() {
            let _ = writeln!(
                t,
                "[[robot]]\nname = \"robot_{k}\"\nstart = [{:?}, {:?}, {:?}]\nplanner = \"astar\"",
                start[0], start[1], start[2]
            );
            t.push_str(&super::drive_line(s.drive));
            match goal {
                Goal::Point(g) => {
                    let _ = writeln!(t, "goal = {}\n", pt(*g));
                }
                Goal::Group(g) => {
                    let _ = writeln!(t, "approach = {{ group = {g} }}\n");
                }
            }
        }
        let _ = writeln!(t, "[episode]\nmax_time = {:?}\nsuccess_radius = 0.3\n", self.max_time);
        let _ = writeln!(
            t,
            "[episode.randomize]\nperson_phase = false\nspeed_jitter = 0.0\nrobot_start_jitter = 0.0"
        );
        t
    }
}

/// A point rounded to centimetres.
pub(crate) fn pt2(p: [f64; 2]) -> [f64; 2] {
    [round2(p[0]), round2(p[1])]
}

fn pt(p: [f64; 2]) -> String {
    format!("[{:?}, {:?}]", p[0], p[1])
}

#[cfg(test)]
mod tests;
