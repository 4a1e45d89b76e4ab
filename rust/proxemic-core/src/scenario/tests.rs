//! Tests of loading, validating and overriding scenarios.

use super::build::polygons::{circle_polygon, signed_area};
use super::*;
use crate::error::{CoreError, Result};

const MINIMAL: &str = r#"
[scene]
name = "room"
bounds = [0, 0, 10, 8]

[[wall]]
from = [0, 0]
to = [10, 0]

[[object]]
name = "painting"
kind = "painting"
pose = [5, 7.8, -1.5707963267948966]
size = [0.1, 1.5]
interaction = { shape = "trapezoid", length = 2.0, near_width = 1.5, far_width = 3.0 }

[[person]]
route = [[1, 1], [8, 1], [8, 6]]
speed = 1.2

[[person]]
behaviour = "standing"
pose = [3, 3, 0]

[[robot]]
start = [1, 4, 0]
goal = [9, 4]
"#;

fn parse(text: &str) -> Result<Scenario> {
    Scenario::from_toml_str(text, "test.toml")
}

fn scenario_err(text: &str) -> (String, String, String, String) {
    match parse(text) {
        Err(CoreError::Scenario { file, field, expected, found }) => (file, field, expected, found),
        other => panic!("expected a scenario error, got {other:?}"),
    }
}

#[test]
fn minimal_scenario_fills_defaults() {
    let s = parse(MINIMAL).expect("valid");
    assert_eq!(s.scene.resolution, 0.1);
    assert_eq!(s.scene.start_time, 9.0 * 3600.0);
    assert_eq!(s.frame_skip(), 10);
    assert_eq!(s.max_steps(), 1800);
    assert_eq!(s.persons[0].name, "person_0");
    assert_eq!(s.robots[0].max_speed, 0.55);
    assert_eq!(s.robots[0].radius, 0.24);
    // walker starts at its first waypoint, facing the second
    assert_eq!(s.persons[0].pose, [1.0, 1.0, 0.0]);
    assert_eq!(s.static_polygons().len(), 2);
}

#[test]
fn painting_trapezoid_faces_into_the_room() {
    let s = parse(MINIMAL).expect("valid");
    let poly = &s.objects[0].interaction.as_ref().expect("has space").polygon;
    // facing -y: the far side is 2 m below the painting's front face at y = 7.75
    let ys: Vec<f64> = poly.iter().map(|p| p[1]).collect();
    let min_y = ys.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!((min_y - (7.8 - 0.05 - 2.0)).abs() < 1e-9, "{ys:?}");
    assert!(signed_area(poly) > 0.0);
    // far width 3.0
    let xs: Vec<f64> = poly.iter().map(|p| p[0]).collect();
    let span = xs.iter().cloned().fold(f64::MIN, f64::max) - xs.iter().cloned().fold(f64::MAX, f64::min);
    assert!((span - 3.0).abs() < 1e-9);
}

#[test]
fn wall_polygon_covers_the_end_caps() {
    let s = parse(MINIMAL).expect("valid");
    let xs: Vec<f64> = s.walls[0].polygon.iter().map(|p| p[0]).collect();
    assert!((xs.iter().cloned().fold(f64::MAX, f64::min) + 0.1).abs() < 1e-9);
    assert!((xs.iter().cloned().fold(f64::MIN, f64::max) - 10.1).abs() < 1e-9);
}

#[test]
fn unknown_field_is_named() {
    let text = MINIMAL.replace("speed = 1.2", "speed = 1.2\nsped = 3");
    let (file, field, expected, found) = scenario_err(&text);
    assert_eq!(file, "test.toml");
    assert!(field.starts_with("person[0]"), "{field}");
    assert!(found.contains("sped"), "{found}");
    assert!(expected.contains("speed"), "{expected}");
}

#[test]
fn missing_field_is_named() {
    let text = MINIMAL.replace("goal = [9, 4]\n", "");
    let (_, field, expected, _) = scenario_err(&text);
    assert!(field.starts_with("robot[0]"), "{field}");
    assert!(expected.contains("goal"), "{expected}");
}

#[test]
fn wrong_type_is_named() {
    let text = MINIMAL.replace("speed = 1.2", "speed = \"sprint\"");
    let (_, field, expected, found) = scenario_err(&text);
    assert!(field.starts_with("person[0].speed"), "{field}");
    assert!(expected.contains("number") && expected.contains("elderly"), "{expected}");
    assert!(found.contains("sprint"), "{found}");
    // a preset name is a speed
    let s = parse(&MINIMAL.replace("speed = 1.2", "speed = \"elderly\"")).expect("valid");
    assert_eq!(s.persons[0].speed, 0.6);
}

#[test]
fn malformed_toml_gives_line() {
    let (_, field, expected, _) = scenario_err("[scene\nname = 1");
    assert!(field.contains("line 1"), "{field}");
    assert_eq!(expected, "valid TOML");
}

#[test]
fn nan_is_rejected_with_field() {
    let text = MINIMAL.replace("speed = 1.2", "speed = nan");
    let (_, field, expected, found) = scenario_err(&text);
    assert_eq!(field, "person[0].speed");
    assert!(expected.contains("(0, 2.5]"));
    assert_eq!(found, "NaN");
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, nan]");
    let (_, field, _, _) = scenario_err(&text);
    assert_eq!(field, "robot[0].goal");
}

#[test]
fn overlapping_robot_starts_are_rejected() {
    let two = format!("{MINIMAL}\n[[robot]]\nstart = [1.3, 4.1, 0]\ngoal = [9, 6]\n");
    let (file, field, expected, found) = scenario_err(&two);
    assert_eq!(file, "test.toml");
    assert_eq!(field, "robot[1].start");
    assert!(expected.contains("0.48 m") && expected.contains("robot[0]"), "{expected}");
    assert!(found.contains("overlapping"), "{found}");
    // Just clear of each other: accepted.
    let ok = two.replace("start = [1.3, 4.1, 0]", "start = [1.5, 4, 0]");
    assert_eq!(parse(&ok).expect("valid").robots.len(), 2);
}

#[test]
fn extends_overrides_scene_keys_and_replaces_tables() {
    let dir = std::env::temp_dir().join(format!("proxemic-extends-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    std::fs::write(dir.join("base.toml"), MINIMAL).expect("write base");
    let child = "extends = \"base.toml\"\n[scene]\nname = \"two\"\n\n\
                 [[robot]]\nstart = [1, 4, 0]\ngoal = [9, 4]\n[[robot]]\nstart = [1, 6, 0]\ngoal = [9, 6]\n";
    std::fs::write(dir.join("child.toml"), child).expect("write child");
    let s = Scenario::from_file(dir.join("child.toml")).expect("valid");
    assert_eq!(s.scene.name, "two");
    assert_eq!(s.scene.bounds, [0.0, 0.0, 10.0, 8.0]); // kept from the base
    assert_eq!(s.persons.len(), 2); // the base's people
    assert_eq!(s.robots.len(), 2); // the child's robots replace the base's
    std::fs::write(dir.join("bad.toml"), "extends = \"nowhere.toml\"\n").expect("write bad");
    match Scenario::from_file(dir.join("bad.toml")) {
        Err(CoreError::Scenario { file, field, found, .. }) => {
            assert!(file.ends_with("bad.toml"), "{file}");
            assert_eq!(field, "extends");
            assert!(found.contains("nowhere.toml"), "{found}");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
    std::fs::write(dir.join("loop.toml"), "extends = \"loop.toml\"\n").expect("write loop");
    match Scenario::from_file(dir.join("loop.toml")) {
        Err(CoreError::Scenario { field, expected, .. }) => {
            assert_eq!(field, "extends");
            assert!(expected.contains("chained"), "{expected}");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn robot_subsets_and_per_robot_planners() {
    let two = format!("{MINIMAL}\n[[robot]]\nstart = [1, 6, 0]\ngoal = [9, 6]\n");
    let s = parse(&two).expect("valid");
    assert_eq!(s.with_robots(1).expect("one").robots.len(), 1);
    assert_eq!(s.with_robots(2).expect("two").robots.len(), 2);
    for bad in [0, 9] {
        match s.with_robots(bad) {
            Err(CoreError::Scenario { field, expected, found, .. }) => {
                assert_eq!(field, "robots");
                assert!(expected.contains("[1, 8]"), "{expected}");
                assert_eq!(found, bad.to_string());
            }
            other => panic!("expected a scenario error, got {other:?}"),
        }
    }
    let m = s.with_robot_planner(1, "astar_orca").expect("known planner");
    assert_eq!(m.robots[1].planner, PlannerKind::AstarOrca);
    assert_eq!(m.robots[0].planner, s.robots[0].planner);
    match s.with_robot_planner(1, "teleport") {
        Err(CoreError::Scenario { field, found, .. }) => {
            assert_eq!(field, "robot[1].planner");
            assert_eq!(found, "\"teleport\"");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
    assert!(s.with_robot_planner(2, "astar_orca").is_err());
}

#[test]
fn with_drive_sets_every_robot_and_names_the_field() {
    use crate::control::Drive;
    let two = format!("{MINIMAL}\n[[robot]]\nstart = [1, 6, 0]\ngoal = [9, 6]\n");
    let s = parse(&two).expect("valid");
    assert!(s.robots.iter().all(|r| r.drive == Drive::Holonomic));
    let d = s.with_drive("differential").expect("known drive");
    assert!(d.robots.iter().all(|r| r.drive == Drive::Differential));
    let back = d.with_drive("holonomic").expect("known drive");
    assert!(back.robots.iter().all(|r| r.drive == Drive::Holonomic));
    // The description the Python side reads says it.
    assert!(d.to_json().expect("serialises").contains("differential"));
    assert!(!s.to_json().expect("serialises").contains("differential"));
    match s.with_drive("tank") {
        Err(CoreError::Scenario { field, expected, found, .. }) => {
            assert_eq!(field, "drive");
            assert_eq!(expected, format!("one of {:?}", Drive::NAMES));
            assert_eq!(found, "\"tank\"");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
}

#[test]
fn out_of_bounds_goal_is_rejected() {
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [19, 4]");
    let (_, field, expected, found) = scenario_err(&text);
    assert_eq!(field, "robot[0].goal");
    assert!(expected.contains("inside scene.bounds"));
    assert_eq!(found, "[19, 4]");
}

#[test]
fn bad_time_of_day() {
    let text = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nstart_time = \"25:00\"");
    let (_, field, _, found) = scenario_err(&text);
    assert_eq!(field, "scene.start_time");
    assert_eq!(found, "\"25:00\"");
    assert_eq!(parse_time_of_day("10:30:15"), Some(37815.0));
}

#[test]
fn physics_rate_must_be_a_multiple() {
    let text = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nphysics_hz = 105");
    let (_, field, _, _) = scenario_err(&text);
    assert_eq!(field, "scene.physics_hz");
}

#[test]
fn walker_needs_two_waypoints_and_standing_needs_a_pose() {
    let text = MINIMAL.replace("route = [[1, 1], [8, 1], [8, 6]]", "route = [[1, 1]]");
    assert_eq!(scenario_err(&text).1, "person[0].route");
    let text = MINIMAL.replace("pose = [3, 3, 0]", "");
    assert_eq!(scenario_err(&text).1, "person[1].pose");
}

#[test]
fn duplicate_names_rejected() {
    let text = format!("{MINIMAL}\n[[robot]]\nname = \"robot_0\"\nstart = [2, 4, 0]\ngoal = [8, 4]\n");
    let (_, field, expected, _) = scenario_err(&text);
    assert_eq!(field, "robot[1].name");
    assert!(expected.contains("robot[0]"));
}

#[test]
fn unknown_planner_lists_the_known_ones() {
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\nplanner = \"teleport\"");
    let (_, field, expected, found) = scenario_err(&text);
    assert!(field.starts_with("robot[0].planner"), "{field}");
    assert!(expected.contains("astar"), "{expected}");
    assert!(found.contains("teleport"), "{found}");
}

#[test]
fn eband_gains_from_the_file_and_by_override_are_checked() {
    let s = parse(MINIMAL).expect("valid");
    assert_eq!(s.robots[0].eband, EbandGains::default());
    assert_eq!((s.robots[0].eband.contraction_gain, s.robots[0].eband.repulsion_gain), (1.0, 0.5));
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { repulsion_gain = 2.0 }");
    let g = parse(&text).expect("valid").robots[0].eband;
    assert_eq!((g.contraction_gain, g.repulsion_gain, g.social_gain), (1.0, 2.0, 0.5));
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { social_gain = -1.0 }");
    let (_, field, expected, found) = scenario_err(&text);
    assert_eq!(field, "robot[0].eband.social_gain");
    assert!(expected.contains("[0, 100]"), "{expected}");
    assert_eq!(found, "-1");
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\neband = { kc = 1.0 }");
    assert!(scenario_err(&text).1.starts_with("robot[0].eband"));

    let t = s.with_eband_gains(&[("contraction_gain", 3.0), ("social_gain", 0.0)]).expect("valid gains");
    assert_eq!(t.robots[0].eband.contraction_gain, 3.0);
    assert_eq!(t.robots[0].eband.repulsion_gain, 0.5);
    assert_eq!(t.robots[0].eband.params().social_gain, 0.0);
    match s.with_eband_gains(&[("repulsion_gain", f64::NAN)]) {
        Err(CoreError::Scenario { field, found, .. }) => {
            assert_eq!(field, "eband.repulsion_gain");
            assert_eq!(found, "NaN");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
    // An unknown name is named (the first in lexicographic order), before any value is checked.
    match s.with_eband_gains(&[("spring", 1.0), ("repulsion_gain", -1.0), ("kc", 1.0)]) {
        Err(CoreError::Scenario { field, expected, found, .. }) => {
            assert_eq!(field, "eband.kc");
            assert!(expected.contains("social_gain"), "{expected}");
            assert_eq!(found, "\"kc\"");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
}

#[test]
fn goal_override_is_checked() {
    let s = parse(MINIMAL).expect("valid");
    assert_eq!(s.with_goal(0, [5.0, 2.0]).expect("inside").robots[0].goal, [5.0, 2.0]);
    match s.with_goal(0, [50.0, 2.0]) {
        Err(CoreError::Scenario { field, expected, .. }) => {
            assert_eq!(field, "robot[0].goal");
            assert!(expected.contains("inside scene.bounds"), "{expected}");
        }
        other => panic!("expected a scenario error, got {other:?}"),
    }
    assert!(matches!(s.with_goal(3, [5.0, 2.0]), Err(CoreError::Scenario { .. })));
}

#[test]
fn no_robot_is_an_error() {
    let text = MINIMAL.split("[[robot]]").next().expect("has a robot table").to_string();
    assert_eq!(scenario_err(&text).1, "robot");
}

#[test]
fn json_round_trip_has_polygons() {
    let s = parse(MINIMAL).expect("valid");
    let v: serde_json::Value = serde_json::from_str(&s.to_json().expect("json")).expect("json");
    assert_eq!(v["walls"][0]["polygon"].as_array().map(|a| a.len()), Some(4));
    assert_eq!(v["objects"][0]["interaction"]["shape"], "trapezoid");
    assert_eq!(v["robots"][0]["planner"], "astar");
}

#[test]
fn circle_polygon_contains_the_disc() {
    let poly = circle_polygon([0.0, 0.0], 1.0);
    // the inscribed radius of the polygon equals the circle's radius
    for i in 0..poly.len() {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        let mid = [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
        assert!((mid[0].hypot(mid[1]) - 1.0).abs() < 1e-9);
    }
    assert!(signed_area(&poly) > 0.0);
}

const SOCIAL: &str = r#"
[proxemics]
space = "sousa2022"
features = ["emotional_state", "food_need"]
groups = "delaunay"
d_max = 1.2

[proxemics.influence]
front = [0.9, 0.0]
left = [0.5, 0.5]

[[activity]]
object = "painting"
start = "10:00"
end = "11:00"
name = "guided talk"
"#;

fn social_scenario(extra_person: &str) -> String {
    let text = MINIMAL.replace("speed = 1.2", &format!("speed = 1.2\n{extra_person}"));
    format!("{text}{SOCIAL}")
}

#[test]
fn proxemics_and_agenda_parse() {
    let s = parse(&social_scenario("emotional_state = \"happy\"")).expect("valid");
    assert_eq!(s.persons[0].features, vec![0.98, 0.5]);
    assert_eq!(s.persons[1].features, vec![0.70, 0.5]);
    assert_eq!(s.proxemics.influence[0], vec![0.9, 0.0]);
    assert_eq!(s.proxemics.influence[1], vec![0.0, 0.0]);
    let cfg = s.proxemics_config();
    assert_eq!(cfg.features.len(), 2);
    assert!(matches!(cfg.groups, Some(crate::groups::GroupMethod::Delaunay(p)) if p.d_max == 1.2));
    let agenda = s.agenda().expect("valid agenda");
    assert_eq!(agenda.cost("painting", 10.5 * 3600.0), 3.5);
    assert_eq!(agenda.cost("painting", 8.0 * 3600.0), 1.5);
    assert_eq!(s.activities[0].name, "guided talk");
}

#[test]
fn social_bad_input_names_the_field() {
    let (_, f, e, _) = scenario_err(&social_scenario("emotional_state = \"grumpy\""));
    assert_eq!(f, "person[0].emotional_state");
    assert!(e.contains("happy"));
    let (_, f, _, _) = scenario_err(&social_scenario("features = [0.5]"));
    assert_eq!(f, "person[0].features");
    let (_, f, _, found) = scenario_err(&social_scenario("features = [0.0, 0.5]"));
    assert_eq!((f.as_str(), found.as_str()), ("person[0].features[0]", "0"));
    let (_, f, _, _) = scenario_err(&social_scenario("").replace("front = [0.9, 0.0]", "front = [1.5, 0.0]"));
    assert_eq!(f, "proxemics.influence.front[0]");
    let (_, f, _, _) = scenario_err(&social_scenario("").replace("front = [0.9, 0.0]", "front = [0.9]"));
    assert_eq!(f, "proxemics.influence.front");
    let (_, f, _, _) = scenario_err(&social_scenario("").replace("\"sousa2022\"", "\"hall\""));
    assert_eq!(f, "proxemics.space");
}

#[test]
fn agenda_bad_input_names_the_activity() {
    let (_, f, _, found) =
        scenario_err(&social_scenario("").replace("object = \"painting\"", "object = \"tv\""));
    assert_eq!((f.as_str(), found.as_str()), ("activity[0].object", "\"tv\""));
    let (_, f, _, _) = scenario_err(&social_scenario("").replace("end = \"11:00\"", "end = \"09:00\""));
    assert_eq!(f, "activity[0].end");
    let overlap = format!(
        "{}\n[[activity]]\nobject = \"painting\"\nstart = \"10:30\"\nend = \"12:00\"\n",
        social_scenario("")
    );
    let (_, f, _, _) = scenario_err(&overlap);
    assert!(f.contains("activity[0]") && f.contains("activity[1]"), "{f}");
    let text = MINIMAL.replace(
        "interaction = { shape = \"trapezoid\", length = 2.0, near_width = 1.5, far_width = 3.0 }\n",
        "",
    );
    let no_space =
        format!("{text}\n[[activity]]\nobject = \"painting\"\nstart = \"10:00\"\nend = \"11:00\"\n");
    let (_, f, e, _) = scenario_err(&no_space);
    assert_eq!(f, "activity[0].object");
    assert!(e.contains("interaction space"));
}

/// Sousa 2022 Table 2: a waiter robot serves food from the person's left and drinks from
/// their right. With `auto`, the side the person's needs make most welcoming is chosen.
fn waiter(food: f64, drink: f64, side: &str) -> Scenario {
    let text = format!(
        r#"
[scene]
name = "dinner"
bounds = [0, 0, 10, 10]
[proxemics]
space = "sousa2022"
features = ["food_need", "beverage_need"]
[proxemics.influence]
left = [0.5, 0.0]
right = [0.0, 0.5]
[[person]]
name = "guest"
behaviour = "standing"
pose = [5, 5, 1.5707963267948966]
features = [{food}, {drink}]
[[robot]]
start = [1, 1, 0]
approach = {{ person = "guest", side = "{side}" }}
"#
    );
    parse(&text).expect("valid waiter scene")
}

#[test]
fn approach_goals_follow_the_person_s_needs() {
    // The guest faces +y: their left is -x, their right +x.
    let food = waiter(0.9, 0.1, "auto");
    let a = food.robots[0].approach.as_ref().expect("approach");
    assert_eq!(a.side, "left");
    assert!(food.robots[0].goal[0] < 5.0 && (food.robots[0].goal[1] - 5.0).abs() < 1e-9);
    let drink = waiter(0.1, 0.9, "auto");
    assert_eq!(drink.robots[0].approach.as_ref().expect("approach").side, "right");
    assert!(drink.robots[0].goal[0] > 5.0);
    // The needed side lets the robot come closer than the side without need.
    let near = 5.0 - food.robots[0].goal[0];
    let far = 5.0 - waiter(0.1, 0.9, "left").robots[0].goal[0];
    assert!(near < far, "{near} vs {far}");
    assert_eq!(food.robots[0].approach.as_ref().expect("approach").face, [5.0, 5.0]);
}

#[test]
fn approach_bad_input() {
    let text = MINIMAL.replace("goal = [9, 4]", "approach = { person = \"nobody\" }");
    assert_eq!(scenario_err(&text).1, "robot[0].approach.person");
    let text = MINIMAL.replace("goal = [9, 4]", "approach = { person = \"person_0\" }");
    let (_, f, e, _) = scenario_err(&text);
    assert_eq!(f, "robot[0].approach.person");
    assert!(e.contains("standing"));
    let text = MINIMAL.replace("goal = [9, 4]", "approach = { person = \"person_1\", side = \"behind\" }");
    assert_eq!(scenario_err(&text).1, "robot[0].approach.side");
    let text = MINIMAL.replace("goal = [9, 4]", "goal = [9, 4]\napproach = { person = \"person_1\" }");
    assert_eq!(scenario_err(&text).1, "robot[0].approach");
}

#[test]
fn grid_too_large_names_bounds_and_resolution() {
    // 1000 x 1000 m at 0.1 m: 1e8 cells, which aborted on an 800 MB allocation.
    let big = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 1000, 1000]");
    assert!(big.contains("1000, 1000"), "the test's scenario changed");
    let (_, field, expected, found) = scenario_err(&big);
    assert_eq!(field, "scene.resolution", "{expected}");
    assert!(expected.contains("scene.bounds [0.0, 0.0, 1000.0, 1000.0]"), "{expected}");
    assert!(found.contains("0.1 m (100000000 cells)"), "{found}");
    // A thin strip passes the area check but not the grid size at 0.01 m.
    let fine = MINIMAL
        .replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 900, 60]")
        .replace("[scene]", "[scene]\nresolution = 0.01");
    let (_, field, expected, found2) = scenario_err(&fine);
    assert_eq!(field, "scene.resolution");
    assert!(expected.contains("scene.bounds") && expected.contains("a resolution of at least"), "{expected}");
    assert!(found2.contains("0.01 m"), "{found2}");
    // A side longer than the limit, whatever the area.
    let long = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 100000000, 0.001]");
    let (_, field, expected, _) = scenario_err(&long);
    assert_eq!(field, "scene.bounds");
    assert!(expected.contains("at most 1000 m"), "{expected}");
}

#[test]
fn wall_far_outside_the_bounds_is_named() {
    // Found by the fuzzer: a wall end at -9.2e18 m made the static geometry's bucket grid
    // overflow its capacity (a panic).
    let text = MINIMAL.replace("from = [0, 0]", "from = [-9223372036854775808, 0]");
    assert!(text.contains("-9223372036854775808"), "the test's scenario changed");
    let (_, field, expected, _) = scenario_err(&text);
    assert_eq!(field, "wall[0].from");
    assert!(expected.contains("inside scene.bounds"), "{expected}");
}

#[test]
fn starts_goals_jitter_and_standing_people_are_checked() {
    // The goal on the start: the episode would be won at once.
    let (_, field, ..) = scenario_err(&MINIMAL.replace("goal = [9, 4]", "goal = [1.1, 4]"));
    assert_eq!(field, "robot[0].goal");
    // A standing person on the robot's start.
    let (_, field, ..) = scenario_err(&MINIMAL.replace("pose = [3, 3, 0]", "pose = [1.2, 4.1, 0]"));
    assert_eq!(field, "person[1].pose");
    // Two standing people at the same place.
    let twin = format!("{MINIMAL}\n[[person]]\nbehaviour = \"standing\"\npose = [3.1, 3, 0]\n");
    let (_, field, ..) = scenario_err(&twin);
    assert_eq!(field, "person[2].pose");
    // A jitter that can put the robot outside the bounds (its start is 1 m from the edge).
    let out = format!("{MINIMAL}\n[episode.randomize]\nrobot_start_jitter = 1.5\n");
    let (_, field, expected, _) = scenario_err(&out);
    assert_eq!(field, "episode.randomize.robot_start_jitter");
    assert!(expected.contains("inside scene.bounds"), "{expected}");
    // A jitter under which two robots could overlap.
    let two = format!(
        "{MINIMAL}\n[[robot]]\nstart = [2, 4, 0]\ngoal = [9, 6]\n[episode.randomize]\nrobot_start_jitter = 0.3\n"
    );
    let (_, field, expected, _) = scenario_err(&two);
    assert_eq!(field, "episode.randomize.robot_start_jitter");
    assert!(expected.contains("cannot overlap"), "{expected}");
    // The same scenes without the fault are valid.
    assert!(parse(&format!("{MINIMAL}\n[episode.randomize]\nrobot_start_jitter = 0.5\n")).is_ok());
}

#[test]
fn rates_spaces_and_polygons_are_checked() {
    // 1 Hz control: the robot (0.55 m/s) would move 0.55 m between two looks of the core.
    let slow = MINIMAL.replace("[scene]", "[scene]\ncontrol_hz = 1\nphysics_hz = 100");
    let (_, field, ..) = scenario_err(&slow);
    assert_eq!(field, "scene.control_hz");
    // 10 Hz physics: 0.055 m per physics step, more than a quarter of a wall.
    let coarse = MINIMAL.replace("[scene]", "[scene]\ncontrol_hz = 10\nphysics_hz = 10");
    let (_, field, ..) = scenario_err(&coarse);
    assert_eq!(field, "scene.physics_hz");
    // The painting at the top wall (y = 7.8) turned to face the wall: its viewers would stand
    // outside the room.
    let backwards =
        MINIMAL.replace("pose = [5, 7.8, -1.5707963267948966]", "pose = [5, 7.8, 1.5707963267948966]");
    let (_, field, _, found) = scenario_err(&backwards);
    assert_eq!(field, "object[0].pose");
    assert!(found.contains("outside scene.bounds"), "{found}");
    // A self-intersecting (bow-tie) polygon and a spiked one.
    let space = r#"interaction = { shape = "trapezoid", length = 2.0, near_width = 1.5, far_width = 3.0 }"#;
    let bow = MINIMAL
        .replace(space, r#"interaction = { shape = "polygon", points = [[4, 5], [7, 7], [7, 5], [4, 6]] }"#);
    let (_, field, _, found) = scenario_err(&bow);
    assert_eq!(field, "object[0].interaction.points");
    assert!(found.contains("cross"), "{found}");
    let spike = MINIMAL.replace(
        space,
        r#"interaction = { shape = "polygon", points = [[4, 5], [6, 5], [6, 7], [6, 5.5], [4, 7]] }"#,
    );
    let (_, field, _, found) = scenario_err(&spike);
    assert_eq!(field, "object[0].interaction.points");
    assert!(found.contains("spike"), "{found}");
    // A fine simple polygon passes.
    let fine = MINIMAL
        .replace(space, r#"interaction = { shape = "polygon", points = [[4, 5], [6, 5], [6, 7], [4, 7]] }"#);
    assert!(parse(&fine).is_ok());
}

#[test]
fn every_bundled_scenario_validates() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../python/proxemic/data/envs");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("the bundled scenarios") {
        let path = entry.expect("a directory entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            if let Err(e) = Scenario::from_file(&path) {
                panic!("{}: {e}", path.display());
            }
            n += 1;
        }
    }
    assert!(n >= 12, "{n} scenarios");
}

#[test]
fn every_planner_name_parses_to_its_own_kind_and_the_papers_planners_are_listed() {
    let kinds: Vec<PlannerKind> = PlannerKind::NAMES.iter().filter_map(|n| PlannerKind::parse(n)).collect();
    assert_eq!(kinds.len(), PlannerKind::NAMES.len());
    for (k, a) in kinds.iter().enumerate() {
        assert!(kinds[k + 1..].iter().all(|b| b != a), "{a:?} twice");
    }
    assert_eq!(PlannerKind::parse("daza2021"), Some(PlannerKind::Daza2021));
    assert_eq!(PlannerKind::parse("sousa2022"), Some(PlannerKind::Sousa2022));
    assert!(PlannerKind::Daza2021.daza2021_family() && PlannerKind::Sousa2022.daza2021_family());
    assert!(!PlannerKind::Social.daza2021_family());
    // Daza 2021 line 1: plain A*; Sousa 2022 §3.1: the path on the Gaussians' cost map.
    assert!(!PlannerKind::Daza2021.social_global() && PlannerKind::Sousa2022.social_global());
    // §4.5's pairing: Sousa's Gaussians in Social Momentum on the plain A* path.
    assert_eq!(PlannerKind::parse("sousa2022_astar"), Some(PlannerKind::Sousa2022Astar));
    let pairing = PlannerKind::Sousa2022Astar;
    assert!(pairing.daza2021_family() && pairing.sousa2022_gaussians() && !pairing.social_global());
    assert!(!PlannerKind::Daza2021.sousa2022_gaussians());
    assert_eq!(PlannerKind::parse("daza"), None);
}

/// serde's own words (Rust type names, toml internals) never reach the user: each bad shape gets
/// the field and what it accepts; fixed-length arrays are checked for their length.
#[test]
fn file_format_errors_name_the_field_and_the_accepted_shapes() {
    let room = "[scene]\nname = \"r\"\nbounds = [0, 0, 10, 8]\n[[robot]]\nstart = [1, 1, 0]\ngoal = [8, 4]\n";
    let table = "[[object]]\nname = \"t\"\nkind = \"table\"\npose = [5, 2, 0]\nsize = [1, 1]\n";
    let cases: [(String, &str, &[&str]); 9] = [
        (
            format!("{room}[[wall]]\nfrom = [0, 0]\nto = [8, 0, 1]\n"),
            "wall[0].to",
            &["exactly 2 numbers", "3 numbers"],
        ),
        (
            format!("{room}[[robot]]\nstart = [1, 2]\ngoal = [8, 4]\n"),
            "robot[1].start",
            &["exactly 3 numbers"],
        ),
        (
            format!("{room}{table}interaction = \"circle\"\n"),
            "object[0].interaction",
            &["shape = \"circle\" with `radius`", "polygon"],
        ),
        (
            format!("{room}{table}interaction = {{ radius = 2 }}\n"),
            "object[0].interaction",
            &["`shape`", "trapezoid"],
        ),
        (
            format!(
                "{room}{table}interaction = {{ shape = \"polygon\", points = [[1, 2], [3, 4, 5], [1, 1]] }}\n"
            ),
            "object[0].interaction",
            &["points entry 1 has 3 numbers"],
        ),
        (
            format!("{room}[[object]]\nname = \"t\"\nkind = 3\npose = [5, 2, 0]\n"),
            "object[0].kind",
            &["`round_table`", "another type"],
        ),
        (format!("{room}[[person]]\nbehaviour = 2\n"), "person[0].behaviour", &["`conversation`"]),
        (format!("{room}[episode]\nrandomize = 3\n"), "episode.randomize", &["`speed_jitter`"]),
        ("[scene]\nname = \"r\"\nbounds = [0, 0, 10]\n".to_string(), "scene.bounds", &["exactly 4 numbers"]),
    ];
    for (text, field, words) in cases {
        let msg = Scenario::from_toml_str(&text, "x").err().map(|e| e.to_string()).unwrap_or_default();
        assert!(msg.contains(field), "{field}: {msg}");
        for w in words {
            assert!(msg.contains(w), "{field}: {w:?} not in {msg}");
        }
        for rust in ["Raw", "struct", "internally tagged", "wanted string"] {
            assert!(!msg.contains(rust), "{field}: Rust internals in {msg}");
        }
    }
}

#[test]
fn the_json_schema_covers_every_table_and_refuses_unknown_fields() {
    let schema = super::json_schema();
    let props = schema["properties"].as_object().expect("properties");
    for table in [
        "scene",
        "wall",
        "object",
        "person",
        "robot",
        "episode",
        "sensors",
        "reward",
        "proxemics",
        "agenda",
        "activity",
        "extends",
        "append",
    ] {
        assert!(props.contains_key(table), "{table}");
    }
    assert_eq!(schema["additionalProperties"], serde_json::json!(false));
    let wall = &schema["$defs"]["RawWall"];
    assert_eq!(wall["properties"]["to"]["minItems"], serde_json::json!(2));
    assert_eq!(wall["properties"]["to"]["maxItems"], serde_json::json!(2));
    assert_eq!(schema["$defs"]["RawScene"]["properties"]["control_hz"]["default"], serde_json::json!(10.0));
}

#[test]
fn reactions_come_from_the_person_its_group_or_the_scene_and_bad_ones_are_named() {
    let text = MINIMAL
        .replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nreaction = \"cautious\"")
        .replace("speed = 1.2", "speed = 1.2\ngroup = 7")
        .replace("pose = [3, 3, 0]", "pose = [3, 3, 0]\nreaction = \"curious\"")
        + "\n[[person]]\nbehaviour = \"standing\"\npose = [6, 3, 0]\n\n[[person]]\nbehaviour = \"standing\"\npose = [3, 6, 0]\naware = false\n\n[[person]]\nroute = [[1, 1.5], [8, 1.5], [8, 6.5]]\nspeed = 1.2\ngroup = 7\n\n[[group]]\nid = 7\nreaction = \"yield\"\n";
    let s = parse(&text).expect("valid");
    let got: Vec<Reaction> = s.persons.iter().map(|p| p.reaction).collect();
    assert_eq!(
        got,
        [Reaction::Yield, Reaction::Curious, Reaction::Cautious, Reaction::Ignore, Reaction::Yield]
    );
    assert_eq!(parse(MINIMAL).expect("valid").persons[1].reaction, Reaction::Aware);

    let bad = MINIMAL.replace("pose = [3, 3, 0]", "pose = [3, 3, 0]\nreaction = \"shy\"");
    let (file, field, expected, found) = scenario_err(&bad);
    assert_eq!(file, "test.toml");
    assert!(field.starts_with("person[1].reaction"), "{field}");
    assert!(expected.contains("ignore") && expected.contains("cautious"), "{expected}");
    assert!(found.contains("shy"), "{found}");

    let bad = MINIMAL.replace("bounds = [0, 0, 10, 8]", "bounds = [0, 0, 10, 8]\nreaction = 3");
    let (_, field, _, _) = scenario_err(&bad);
    assert!(field.starts_with("scene.reaction"), "{field}");

    let bad = MINIMAL.to_string() + "\n[[group]]\nid = 9\nreaction = \"yield\"\n";
    let (_, field, expected, found) = scenario_err(&bad);
    assert_eq!((field.as_str(), found.as_str()), ("group[0].id", "9"), "{expected}");

    let bad = MINIMAL.replace("pose = [3, 3, 0]", "pose = [3, 3, 0]\naware = false\nreaction = \"yield\"");
    let (_, field, _, found) = scenario_err(&bad);
    assert_eq!(field, "person[1].reaction");
    assert!(found.contains("yield"), "{found}");
}
