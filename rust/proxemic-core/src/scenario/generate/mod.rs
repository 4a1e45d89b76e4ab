//! Generated scenes: a seeded random floor plan with furniture, people and robots, written as a
//! scenario file and loaded like any other.
//!
//! [`generate`] draws, from a seed and [`GenParams`]:
//! - the floor plan (`layout.rs`): an east-west corridor with rooms 5-9 m wide on both sides, a
//!   doorway from every room to the corridor, and doorways between neighbouring rooms at random;
//! - the furniture (`furnish.rs`): paintings on the rooms' back walls (trapezoidal viewing
//!   spaces), exhibits (circular ones), plinths (rectangular ones) and benches, kept clear of the
//!   doorways and of each other by a passage; the agenda makes about half of the objects with an
//!   interaction space busy for the whole episode (an `[[activity]]`), the others idle;
//! - the people: conversation groups (F-formations of 2-6, already talking), people standing and
//!   seated (on the benches), walkers on closed routes through the doorways;
//! - the robots (`robots.rs`): starts and goals sampled free and reachable.
//!
//! Room to pass: nobody stands or talks in the corridor or in a doorway's approach (a disc of the
//! door's half-width plus 1.4 m), and every person standing still keeps 1 m of free floor round
//! them, so a robot can always pass a person standing still at the intimate zone's 0.45 m from body
//! edge to body edge. Walkers are not held to this.
//!
//! The result is the text of a scenario file ([`Generated::toml`]) and the scenario it loads as:
//! writing the text out and reading it back gives the same scenario. Every value is rounded to
//! centimetres (angles to hundredths of a radian) before it is written, so the text holds exactly
//! the numbers drawn. Same seed and parameters, same text, bit for bit.

pub mod crowdnav;
pub mod francis2023;
mod furnish;
mod layout;
mod params;
mod robots;

use std::fmt::Write as _;

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

pub use params::{GenParams, PARAM_NAMES, parse_spec};
pub use robots::{Task, sample_tasks};

use self::furnish::{GObject, GPerson, Keep};
use self::layout::Plan;
use super::model::{Reaction, Scenario};
use crate::error::Result;
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;

/// A generated scene: its scenario file text and the validated scenario.
#[derive(Clone, Debug)]
pub struct Generated {
    /// The scenario file (TOML).
    pub toml: String,
    /// The scenario it loads as (source: the spec, `generated/<seed>?...`).
    pub scenario: Scenario,
}

/// The spec naming a generated scene: `generated/<seed>`, followed by `?key=value&...` for the
/// parameters that differ from the defaults (in [`PARAM_NAMES`] order).
pub fn spec(seed: u64, p: &GenParams) -> String {
    let d = GenParams::default();
    let mut pairs = Vec::new();
    let mut num = |k: &str, v: f64, dv: f64| {
        if v != dv {
            pairs.push(format!("{k}={v}"));
        }
    };
    num("width", p.width, d.width);
    num("height", p.height, d.height);
    num("corridor_width", p.corridor_width, d.corridor_width);
    num("door_width", p.door_width, d.door_width);
    num("density", p.density, d.density);
    num("group_share", p.group_share, d.group_share);
    num("walker_share", p.walker_share, d.walker_share);
    num("seated_share", p.seated_share, d.seated_share);
    if p.objects_per_room != d.objects_per_room {
        pairs.push(format!("objects_per_room={}", p.objects_per_room));
    }
    if p.robots != d.robots {
        pairs.push(format!("robots={}", p.robots));
    }
    if p.max_time != d.max_time {
        pairs.push(format!("max_time={}", p.max_time));
    }
    if p.encounters != d.encounters {
        pairs.push(format!("encounters={}", p.encounters));
    }
    if p.reaction != d.reaction {
        pairs.push(format!("reaction={}", p.reaction.name()));
    }
    if p.drive != d.drive {
        pairs.push(format!("drive={}", p.drive.name()));
    }
    if pairs.is_empty() {
        format!("generated/{seed}")
    } else {
        format!("generated/{seed}?{}", pairs.join("&"))
    }
}

/// The scene of any generator spec: `generated/<seed>[?...]` ([`parse_spec`], [`generate`]) or
/// `francis2023/<archetype>[?seed=N&max_time=T]` ([`francis2023::generate`]) or
/// `crowdnav/<family>[?humans=N&visible=B&seed=S]` ([`crowdnav::generate`]).
pub fn generate_spec(spec: &str) -> Result<Generated> {
    if spec.starts_with(crowdnav::PREFIX) {
        return crowdnav::generate(spec);
    }
    if spec.starts_with(francis2023::PREFIX) {
        return francis2023::generate(spec);
    }
    let (seed, params) = parse_spec(spec)?;
    generate(seed, &params)
}

/// Start of the generated scenes' day (the agenda's activities are times of day).
const START_TIME: f64 = 10.0 * 3600.0;

/// Generates the scene of `seed` with parameters `p` (checked first). Errors: a parameter out of
/// range ([`GenParams::check`]), or no room for the robots' tasks; both
/// [`CoreError::Scenario`](crate::error::CoreError::Scenario) naming the parameter.
pub fn generate(seed: u64, p: &GenParams) -> Result<Generated> {
    let source = spec(seed, p);
    p.check(&source)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let plan = layout::plan(&mut rng, p, &source)?;
    let mut keep = Keep::new(&plan);
    let mut objects = furnish::objects(&mut rng, &plan, p, &mut keep);
    let geometry = static_geometry(&plan, &objects, p, &source)?;
    let mut people = furnish::people(&mut rng, &plan, p, &geometry, &mut objects, &mut keep);
    let activities = agenda(&mut rng, &objects, p);
    // The scene without its robots, with a placeholder in the bounds' corner (inside the outer
    // wall, where nobody is) to make it a loadable scenario for the robot sampler.
    let corner = [[0.15, 0.15, 0.0], [round2(p.width) - 0.15, round2(p.height) - 0.15, 0.0]];
    let draft =
        render(seed, p, &plan, &objects, &people, &activities, &[(corner[0], [corner[1][0], corner[1][1]])]);
    let draft = Scenario::from_toml_str(&draft, &source)?;
    let tasks = sample_tasks(&draft, 0, p.robots, seed ^ 0x05EE_D0F0_B075)?;
    if p.encounters > 0 {
        let ends: Vec<Vec2> =
            tasks.iter().flat_map(|(s, g)| [Vec2::new(s[0], s[1]), Vec2::new(g[0], g[1])]).collect();
        let mut group = 900u32;
        for (start, goal) in &tasks {
            let path = shortest_way(&draft, Vec2::new(start[0], start[1]), Vec2::new(goal[0], goal[1]))?;
            if let Some(members) =
                furnish::encounter(&mut rng, &path, &geometry, &mut keep, &ends, group, p.max_time + 60.0)
            {
                people.extend(members);
                group += 1;
            }
        }
    }
    let toml = render(seed, p, &plan, &objects, &people, &activities, &tasks);
    let scenario = Scenario::from_toml_str(&toml, &source)?;
    Ok(Generated { toml, scenario })
}

/// The cells of the robot's shortest way on its inflated grid from `start` to `goal` (steepest
/// descent of the geodesic distance to the goal), as cell centres.
fn shortest_way(s: &Scenario, start: Vec2, goal: Vec2) -> Result<Vec<Vec2>> {
    use crate::map::CostGrid;
    use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
    use crate::plan::geodesic::GoalField;
    let geometry = s.static_geometry()?;
    let spec = GridSpec::covering(geometry.bounds(), s.scene.resolution)?;
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geometry, spec));
    let r = &s.robots[0];
    let grid = CostGrid::inflated(&field, r.radius + r.inflation_margin);
    let mut path = Vec::new();
    let (Some(gc), Some(mut c)) = (spec.cell_of(goal), spec.cell_of(start)) else {
        return Ok(path);
    };
    let to_goal = GoalField::compute(&grid, gc);
    let dist = |x: usize, y: usize| to_goal.cell_distance(spec.center(x, y));
    for _ in 0..spec.len() {
        path.push(spec.center(c.0, c.1));
        let mut best = (dist(c.0, c.1), c);
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)] {
            let (x, y) = (c.0 as isize + dx, c.1 as isize + dy);
            if x < 0 || y < 0 || x as usize >= spec.width || y as usize >= spec.height {
                continue;
            }
            let d = dist(x as usize, y as usize);
            if d < best.0 {
                best = (d, (x as usize, y as usize));
            }
        }
        if best.1 == c {
            break;
        }
        c = best.1;
    }
    Ok(path)
}

fn round2(v: f64) -> f64 {
    layout::round2(v)
}

/// The walls and solid object footprints as the loaded scenario will have them.
fn static_geometry(plan: &Plan, objects: &[GObject], p: &GenParams, source: &str) -> Result<StaticGeometry> {
    let text = render(0, p, plan, objects, &[], &[], &[([0.15, 0.15, 0.0], [1.0, 1.0])]);
    Scenario::from_toml_str(&text, source)?.static_geometry()
}

/// An activity of the agenda: object name, start and end (`"HH:MM"`).
type Activity = (String, String, String);

/// About half of the objects with an interaction space busy from 10 minutes before the start to
/// 10 minutes after the episode's end.
fn agenda(rng: &mut ChaCha8Rng, objects: &[GObject], p: &GenParams) -> Vec<Activity> {
    use rand::Rng;
    let hhmm = |t: f64| {
        let m = (t / 60.0).round() as i64;
        format!("{:02}:{:02}", (m / 60).min(23), m % 60)
    };
    objects
        .iter()
        .filter(|o| o.interaction.is_some())
        .filter(|_| rng.random_bool(0.5))
        .map(|o| (o.name.clone(), hhmm(START_TIME - 600.0), hhmm(START_TIME + p.max_time + 600.0)))
        .collect()
}

/// A robot's `drive = "..."` line (with its newline), empty for the default holonomic drive (so
/// a holonomic scene's text is unchanged).
pub(crate) fn drive_line(drive: crate::control::Drive) -> String {
    if drive.is_holonomic() { String::new() } else { format!("drive = \"{}\"\n", drive.name()) }
}

fn pt(p: [f64; 2]) -> String {
    format!("[{:?}, {:?}]", p[0], p[1])
}

/// The scenario file text.
#[allow(clippy::too_many_arguments)]
fn render(
    seed: u64,
    p: &GenParams,
    plan: &Plan,
    objects: &[GObject],
    people: &[GPerson],
    activities: &[Activity],
    robots: &[Task],
) -> String {
    let mut t = String::new();
    let (w, h) = (round2(p.width), round2(p.height));
    let _ = writeln!(t, "# Generated by proxemic (core generator), {}.\n", spec(seed, p));
    let _ = writeln!(t, "[scene]\nname = \"generated_{seed}\"\nbounds = [0.0, 0.0, {w:?}, {h:?}]");
    let _ = writeln!(t, "start_time = \"10:00\"");
    if p.reaction != Reaction::default() {
        let _ = writeln!(t, "reaction = \"{}\"", p.reaction.name());
    }
    let _ = writeln!(
        t,
        "description = \"A generated floor: a corridor with {} rooms, {} objects, {} people, {} robots (seed {seed}).\"\n",
        plan.rooms.len() - 1,
        objects.len(),
        people.len(),
        robots.len()
    );
    for wall in &plan.walls {
        let _ = writeln!(
            t,
            "[[wall]]\nfrom = [{:?}, {:?}]\nto = [{:?}, {:?}]\nthickness = {:?}\n",
            round2(wall.from.x),
            round2(wall.from.y),
            round2(wall.to.x),
            round2(wall.to.y),
            wall.thickness
        );
    }
    for o in objects {
        let _ = writeln!(t, "[[object]]\nname = \"{}\"\nkind = \"{}\"", o.name, o.kind);
        let _ = writeln!(t, "pose = [{:?}, {:?}, {:?}]", o.pose[0], o.pose[1], o.pose[2]);
        if let Some(s) = o.size {
            let _ = writeln!(t, "size = {}", pt(s));
        }
        if let Some(r) = o.radius {
            let _ = writeln!(t, "radius = {r:?}");
        }
        if let Some(i) = &o.interaction {
            let _ = writeln!(t, "interaction = {i}");
        }
        t.push('\n');
    }
    for (k, (object, start, end)) in activities.iter().enumerate() {
        let _ = writeln!(
            t,
            "[[activity]]\nname = \"activity_{k}\"\nobject = \"{object}\"\nstart = \"{start}\"\nend = \"{end}\"\n"
        );
    }
    for (k, person) in people.iter().enumerate() {
        let _ = writeln!(t, "[[person]]\nname = \"person_{k}\"");
        match person {
            GPerson::Standing { pose } => {
                let _ = writeln!(
                    t,
                    "behaviour = \"standing\"\npose = [{:?}, {:?}, {:?}]",
                    pose[0], pose[1], pose[2]
                );
            }
            GPerson::Seated { seat, place } => {
                let _ =
                    writeln!(t, "behaviour = \"seated\"\nseat = \"{seat}\"\nplace = {place}\nheight = 1.25");
            }
            GPerson::Walker { route, speed, dwell } => {
                let pts: Vec<String> = route.iter().map(|q| pt(*q)).collect();
                let _ = writeln!(
                    t,
                    "behaviour = \"walker\"\nroute = [{}]\nspeed = {speed:?}\ndwell = {dwell:?}",
                    pts.join(", ")
                );
            }
            GPerson::Conversation { group, home, spot, end } => {
                let _ = writeln!(
                    t,
                    "behaviour = \"conversation\"\ngroup = {group}\nhome = {}\nspot = {}\nstart = -5.0\nend = {end:?}",
                    pt(*home),
                    pt(*spot)
                );
            }
        }
        t.push('\n');
    }
    for (k, (start, goal)) in robots.iter().enumerate() {
        let _ = writeln!(
            t,
            "[[robot]]\nname = \"robot_{k}\"\nstart = [{:?}, {:?}, {:?}]\ngoal = {}\nplanner = \"astar\"\n{}",
            start[0],
            start[1],
            start[2],
            pt(*goal),
            drive_line(p.drive)
        );
    }
    let _ = writeln!(t, "[episode]\nmax_time = {:?}\nsuccess_radius = 0.3\n", p.max_time);
    let _ =
        writeln!(t, "[episode.randomize]\nperson_phase = true\nspeed_jitter = 0.1\nrobot_start_jitter = 0.1");
    t
}

#[cfg(test)]
mod tests;
