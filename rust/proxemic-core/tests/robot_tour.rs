//! A tour guided by a robot: people whose `guide = "robot:<name>"` walk behind the robot, and
//! gather on an arc behind it, facing it, at every waypoint where it dwells and at its goal; the
//! robot visits its waypoints in order, stands its `dwell` seconds at each, and succeeds at its
//! goal. Same seed, same tour, bit for bit. Bad input names the file and the field.
//!
//! The robot runs plain A* and is simulated kinematically (its commands integrated exactly); the
//! people are stepped through `World::step` as in an episode.

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::Scenario;
use proxemic_core::world::World;

mod common;
use common::Drive;

/// A 24 x 12 m hall with a display case between the first two stops; the guide starts in the
/// west, stops twice for 20 s and ends in the south-east; three followers, and two walkers
/// walking along the east and north walls (out of the plain A* robot's way).
fn hall(guide: &str, extra: &str) -> String {
    format!(
        r#"
[scene]
name = "robot_tour"
bounds = [0, 0, 24, 12]

[[wall]]
from = [0, 0]
to = [24, 0]
[[wall]]
from = [24, 0]
to = [24, 12]
[[wall]]
from = [24, 12]
to = [0, 12]
[[wall]]
from = [0, 12]
to = [0, 0]

[[object]]
name = "case"
kind = "cabinet"
pose = [7.5, 6.0, 0.0]
size = [1.0, 1.0]

[[robot]]
name = "guide"
start = [3.0, 6.0, 0.0]
waypoints = [[11.0, 6.0], [17.0, 8.5]]
dwell = 20.0
goal = [21.0, 3.5]
planner = "astar"
{extra}
[[person]]
name = "visitor_1"
behaviour = "follower"
guide = "{guide}"
group = 1

[[person]]
name = "visitor_2"
behaviour = "follower"
guide = "{guide}"
group = 1

[[person]]
name = "visitor_3"
behaviour = "follower"
guide = "{guide}"
group = 1
speed = "slow"

[[person]]
name = "walker_1"
route = [[23.0, 1.5], [23.0, 10.5]]

[[person]]
name = "walker_2"
route = [[2.0, 10.5], [22.0, 10.5]]

[episode]
max_time = 200.0
success_radius = 0.3

[episode.randomize]
person_phase = true
speed_jitter = 0.1
robot_start_jitter = 0.0
"#
    )
}

fn scenario(text: &str) -> Scenario {
    Scenario::from_toml_str(text, "robot_tour.toml").expect("valid scenario")
}

/// One control step's record: the robots' poses, whether each stands at a tour stop (its
/// planner's mode is "wait"), its outcome flags, and the people's positions and headings.
struct Step {
    robots: Vec<Vec2>,
    dwelling: Vec<bool>,
    success: Vec<bool>,
    people: Vec<Vec2>,
    headings: Vec<f64>,
}

/// Runs `steps` control steps (or until the people have stood 10 s at the end of the tour).
fn run(s: &Scenario, seed: u64, steps: usize) -> Vec<Step> {
    let mut d = Drive::start(s.clone(), seed);
    let n = d.world.num_robots();
    let lay = *d.world.layout();
    let (mode, flags) = (lay.mode.offset, lay.flags.offset);
    let mut trace = Vec::with_capacity(steps);
    let mut after_end = 0;
    for _ in 0..steps {
        d.drive();
        let step = Step {
            robots: (0..n).map(|i| d.robot(i)).collect(),
            dwelling: (0..n).map(|i| d.row(i)[mode] == 3.0).collect(),
            success: (0..n).map(|i| d.row(i)[flags + 2] > 0.5).collect(),
            people: d.world.crowd().pos.clone(),
            headings: d.world.crowd().heading.clone(),
        };
        let done = step.success[0];
        trace.push(step);
        if done {
            after_end += 1;
            if after_end as f64 * d.dt >= 10.0 {
                break;
            }
        }
    }
    trace
}

fn angle_to(heading: f64, from: Vec2, to: Vec2) -> f64 {
    let d = to - from;
    let a = d.y.atan2(d.x) - heading;
    a.sin().atan2(a.cos()).abs()
}

/// The stops of a trace: runs of steps where the robot dwells, as (first, last) step indices.
fn dwell_runs(trace: &[Step]) -> Vec<(usize, usize)> {
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (k, s) in trace.iter().enumerate() {
        if s.dwelling[0] {
            match runs.last_mut() {
                Some(r) if r.1 + 1 == k => r.1 = k,
                _ => runs.push((k, k)),
            }
        }
    }
    runs
}

#[test]
fn followers_stay_with_the_robot_and_gather_at_its_stops() {
    let s = scenario(&hall("robot:guide", ""));
    for seed in 0..8 {
        check_tour(&s, seed);
    }
}

fn check_tour(s: &Scenario, seed: u64) {
    let dt = s.control_dt();
    let followers = [0, 1, 2];
    let trace = run(s, seed, 2000);
    let end = trace
        .iter()
        .position(|t| t.success[0])
        .unwrap_or_else(|| panic!("seed {seed}: the tour does not reach its goal ({} steps)", trace.len()));

    // The robot stands at each waypoint, in order, for its dwell time.
    let runs = dwell_runs(&trace);
    assert_eq!(runs.len(), 2, "seed {seed}: two stops: {runs:?}");
    for (&(a, b), w) in runs.iter().zip([Vec2::new(11.0, 6.0), Vec2::new(17.0, 8.5)]) {
        assert!((trace[a].robots[0] - w).norm() <= 0.3 + 1e-9, "stop at {w:?}");
        let secs = (b - a + 1) as f64 * dt;
        assert!((secs - 20.0).abs() <= 2.0 * dt, "dwelt {secs} s, not 20 s");
    }
    assert!(end > runs[1].1, "the goal comes after the stops");

    // They stay with it: never more than 5 m from the robot while it walks between stops.
    for (k, t) in trace.iter().enumerate().take(end).skip(1) {
        for &f in &followers {
            let d = (t.people[f] - t.robots[0]).norm();
            assert!(d <= 5.0, "seed {seed}, step {k}: follower {f} is {d:.2} m from the robot");
        }
    }

    // At each stop and at the goal (its last 3 s), they stand gathered behind the robot, on an
    // arc 1-2.2 m from it, facing it, out of its intimate zone.
    let settled = (3.0 / dt) as usize;
    let ends = [runs[0].1, runs[1].1, trace.len() - 1];
    for (stop, &last) in ends.iter().enumerate() {
        for k in last + 1 - settled..=last {
            let t = &trace[k];
            let r = t.robots[0];
            for &f in &followers {
                let d = (t.people[f] - r).norm();
                assert!(
                    (1.0..=2.2).contains(&d),
                    "seed {seed}, stop {stop}, step {k}: follower {f} at {d:.2} m"
                );
                let a = angle_to(t.headings[f], t.people[f], r);
                assert!(
                    a < 0.35,
                    "seed {seed}, stop {stop}, step {k}: follower {f} looks {a:.2} rad off the robot"
                );
            }
            // still: the same place one step later
            if k < last {
                for &f in &followers {
                    assert!((trace[k + 1].people[f] - t.people[f]).norm() < 1e-9, "follower {f} moves");
                }
            }
        }
    }
    // Each in its own place (no two bodies overlap), on the side the robot came from.
    for (stop, &last) in ends.iter().enumerate() {
        let t = &trace[last];
        let came_from = trace[ends[stop].saturating_sub(if stop < 2 { 300 } else { 150 })].robots[0];
        for (i, &f) in followers.iter().enumerate() {
            for &g in &followers[i + 1..] {
                let gap = (t.people[f] - t.people[g]).norm();
                assert!(
                    gap > 0.4,
                    "stop {stop}: followers {f} and {g} overlap ({gap:.2} m apart): {:?} {:?} robot {:?}",
                    t.people[f],
                    t.people[g],
                    t.robots[0]
                );
            }
            let (to_person, to_before) = (t.people[f] - t.robots[0], came_from - t.robots[0]);
            assert!(to_person.dot(&to_before) > 0.0, "stop {stop}: follower {f} is not behind the robot");
        }
    }
}

#[test]
fn same_seed_same_tour_bit_for_bit() {
    let s = scenario(&hall("robot:guide", ""));
    let (a, b, c) = (run(&s, 11, 600), run(&s, 11, 600), run(&s, 12, 600));
    let bits = |tr: &[Step]| -> Vec<u64> {
        tr.iter()
            .flat_map(|t| t.people.iter().chain(&t.robots).flat_map(|p| [p.x.to_bits(), p.y.to_bits()]))
            .collect()
    };
    assert_eq!(bits(&a), bits(&b));
    assert_ne!(bits(&a), bits(&c), "another seed draws other walking speeds");
}

#[test]
fn without_its_robot_the_group_waits_at_the_start() {
    // Two robots, the guide second; with_robots(1) leaves it out.
    let extra = r#"
[[robot]]
name = "courier"
start = [3.0, 2.0, 0.0]
goal = [21.0, 2.0]
planner = "astar"
"#;
    let text = hall("robot:guide", "")
        .replace("[[robot]]\nname = \"guide\"", &format!("{extra}\n[[robot]]\nname = \"guide\""));
    let s = scenario(&text).with_robots(1).expect("one robot");
    assert!(s.persons[..3].iter().all(|p| p.guide_robot.is_none() && !p.tour.is_empty()));
    let trace = run(&s, 5, 100);
    for f in 0..3 {
        let first = trace[0].people[f];
        assert!(trace.iter().all(|t| t.people[f] == first), "follower {f} moved without its guide");
        assert!((first - Vec2::new(3.0, 6.0)).norm() > 1.0 && (first - Vec2::new(3.0, 6.0)).norm() < 2.0);
    }
}

fn scenario_error(text: &str) -> (String, String, String, String) {
    common::scenario_error(Scenario::from_toml_str(text, "robot_tour.toml"))
}

#[test]
fn bad_tours_are_clear_errors() {
    // An unknown robot: file, field, what was expected (the robots' names), what arrived.
    let (file, field, expected, found) = scenario_error(&hall("robot:gide", ""));
    assert_eq!(file, "robot_tour.toml");
    assert_eq!(field, "person[0].guide");
    assert!(expected.contains("robot:<name>") && expected.contains("\"guide\""), "{expected}");
    assert_eq!(found, "\"robot:gide\"");
    // A person guide name that is neither a guide person nor a robot.
    let (_, field, expected, _) = scenario_error(&hall("nobody", ""));
    assert_eq!(field, "person[0].guide");
    assert!(expected.contains("robot:<name>"), "{expected}");
    // A dwell without waypoints.
    let text = hall("robot:guide", "").replace("waypoints = [[11.0, 6.0], [17.0, 8.5]]\n", "");
    let (_, field, _, found) = scenario_error(&text);
    assert_eq!(field, "robot[0].dwell");
    assert!(found.contains("without waypoints"), "{found}");
    // A waypoint outside the scene, and a negative dwell.
    let text = hall("robot:guide", "").replace("[17.0, 8.5]", "[17.0, 30.0]");
    assert_eq!(scenario_error(&text).1, "robot[0].waypoints[1]");
    let text = hall("robot:guide", "").replace("dwell = 20.0", "dwell = -1.0");
    assert_eq!(scenario_error(&text).1, "robot[0].dwell");
    // A waypoint inside the display case, refused when the world is built.
    let s = scenario(&hall("robot:guide", "").replace("[11.0, 6.0]", "[7.5, 6.0]"));
    match World::new(s) {
        Err(CoreError::Scenario { field, found, .. }) => {
            assert_eq!(field, "robot[0].waypoints[0]");
            assert!(found.contains("inside a wall or object"), "{found}");
        }
        other => panic!("expected a scenario error, got {:?}", other.err()),
    }
    // A tour that passes its goal before its last waypoint.
    let s = scenario(&hall("robot:guide", "").replace("[[11.0, 6.0],", "[[21.0, 3.0],"));
    match World::new(s) {
        Err(CoreError::Scenario { field, found, .. }) => {
            assert_eq!(field, "robot[0].waypoints[0]");
            assert!(found.contains("passes the goal"), "{found}");
        }
        other => panic!("expected a scenario error, got {:?}", other.err()),
    }
}

#[test]
fn a_scene_extending_another_can_append_people() {
    let dir = std::env::temp_dir().join(format!("proxemic-append-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("base.toml"), hall("robot:guide", "")).expect("write base");
    let child = "extends = \"base.toml\"\nappend = [\"person\"]\n\n[[person]]\nname = \"late_visitor\"\nbehaviour = \"follower\"\nguide = \"robot:guide\"\n";
    std::fs::write(dir.join("child.toml"), child).expect("write child");
    let s = Scenario::from_file(dir.join("child.toml")).expect("valid child");
    assert_eq!(s.persons.len(), 6);
    assert_eq!(s.persons[5].name, "late_visitor");
    assert_eq!(s.persons[5].guide_robot, Some(0));
    // Without `append`, the child's people replace the base's.
    std::fs::write(dir.join("child2.toml"), child.replace("append = [\"person\"]\n", "")).expect("write");
    assert_eq!(Scenario::from_file(dir.join("child2.toml")).expect("valid").persons.len(), 1);
    // Only arrays of tables can be appended.
    std::fs::write(dir.join("bad.toml"), child.replace("[\"person\"]", "[\"scene\"]")).expect("write");
    match Scenario::from_file(dir.join("bad.toml")) {
        Err(CoreError::Scenario { field, expected, .. }) => {
            assert_eq!(field, "append");
            assert!(expected.contains("person"), "{expected}");
        }
        other => panic!("expected a scenario error, got {:?}", other.map(|s| s.scene.name)),
    }
    std::fs::remove_dir_all(&dir).ok();
}
