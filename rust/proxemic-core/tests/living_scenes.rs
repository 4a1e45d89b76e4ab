//! Living scenes: the scripted behaviours of the museum and the care center over long seeded
//! runs (people never enter walls or furniture, visitors face exhibits, conversations form and
//! break up on schedule, the tour stops and gathers, residents arrive before their activities,
//! groups stay together, same seed same people), and the bad-input errors of the people.
//!
//! The robot stands at its start (its aware neighbours see it); the people are stepped through
//! `World::step` exactly as in an episode.

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::{Behaviour, Scenario};
use proxemic_core::world::World;

mod common;
use common::{Drive, env_scenario as scenario, scenario_error};

/// Per step (after it): positions and headings of the people.
struct Trace {
    dt: f64,
    pos: Vec<Vec<Vec2>>,
    heading: Vec<Vec<f64>>,
}

/// `steps` control steps with the robots held still at their starts; `check` sees the world after
/// each step.
fn run(s: &Scenario, seed: u64, steps: usize, mut check: impl FnMut(&World, usize)) -> Trace {
    let mut d = Drive::start(s.clone(), seed);
    let mut trace = Trace { dt: d.dt, pos: Vec::with_capacity(steps), heading: Vec::with_capacity(steps) };
    for k in 0..steps {
        d.step_free();
        check(&d.world, k);
        trace.pos.push(d.world.crowd().pos.clone());
        trace.heading.push(d.world.crowd().heading.clone());
    }
    trace
}

fn index(s: &Scenario, name: &str) -> usize {
    s.persons.iter().position(|p| p.name == name).unwrap_or_else(|| panic!("no person {name}"))
}

fn angle_between(heading: f64, from: Vec2, to: Vec2) -> f64 {
    let d = to - from;
    let a = d.y.atan2(d.x) - heading;
    a.sin().atan2(a.cos()).abs()
}

#[test]
fn the_scenes_build() {
    for name in ["museum", "care_center"] {
        let s = scenario(name);
        World::new(s).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}

#[test]
fn nobody_enters_walls_or_furniture_over_long_runs() {
    for (name, seed) in [("museum", 1), ("care_center", 2)] {
        let s = scenario(name);
        let seated: Vec<bool> = s.persons.iter().map(|p| p.behaviour == Behaviour::Seated).collect();
        let mut checked = 0usize;
        run(&s, seed, 3000, |world, k| {
            let c = world.crowd();
            for (i, q) in c.pos.iter().enumerate().filter(|(i, _)| !seated[*i]) {
                let g = world.geometry();
                assert!(
                    !g.contains(*q),
                    "{name}: {} inside a wall or object at {q:?}, step {k}",
                    s.persons[i].name
                );
                // the hard constraint keeps centres at least half a radius off the geometry
                assert!(g.distance(*q) >= 0.5 * c.radius[i] - 1e-9, "{name}: {} at {q:?}", s.persons[i].name);
                checked += 1;
            }
        });
        assert!(checked >= 3000 * 15, "{name}: {checked}");
    }
}

#[test]
fn same_seed_same_people_bit_for_bit() {
    for name in ["museum", "care_center"] {
        let s = scenario(name);
        let bits = |seed| {
            let t = run(&s, seed, 600, |_, _| {});
            let last = t.pos.last().expect("steps").clone();
            let h = t.heading.last().expect("steps").clone();
            last.iter()
                .flat_map(|p| [p.x.to_bits(), p.y.to_bits()])
                .chain(h.iter().map(|a| a.to_bits()))
                .collect::<Vec<u64>>()
        };
        assert_eq!(bits(3), bits(3), "{name}");
        assert_ne!(bits(3), bits(4), "{name}");
    }
}

/// Steps (indices) at which person `i` has not moved for the previous `n` steps.
fn still_for(t: &Trace, i: usize, n: usize) -> Vec<usize> {
    (n..t.pos.len()).filter(|&k| (k - n..k).all(|j| t.pos[j][i] == t.pos[k][i])).collect()
}

#[test]
fn visitors_dwell_facing_their_exhibits() {
    let s = scenario("museum");
    let t = run(&s, 5, 3000, |_, _| {});
    let visitors: Vec<usize> =
        (0..s.persons.len()).filter(|&i| s.persons[i].behaviour == Behaviour::Visitor).collect();
    assert!(visitors.len() >= 5);
    for &i in &visitors {
        let p = &s.persons[i];
        let still = still_for(&t, i, 30);
        assert!(still.len() > 100, "{} never dwelt", p.name);
        // The exhibits it stood at: facing each (within 0.3 rad once turned, after 3 s still).
        let mut seen = std::collections::BTreeSet::new();
        for &k in &still {
            let q = t.pos[k][i];
            let (o, d) = p
                .exhibits
                .iter()
                .map(|&o| (o, (Vec2::new(s.objects[o].pose[0], s.objects[o].pose[1]) - q).norm()))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("exhibits");
            assert!(d < 4.0, "{} stands still {d:.1} m from its nearest exhibit at {q:?}", p.name);
            let c = Vec2::new(s.objects[o].pose[0], s.objects[o].pose[1]);
            let off = angle_between(t.heading[k][i], q, c);
            assert!(off < 0.3, "{} at {q:?} looks {off:.2} rad away from {}", p.name, s.objects[o].name);
            seen.insert(o);
        }
        assert!(seen.len() >= 2, "{} dwelt at {} exhibit(s) in 300 s", p.name, seen.len());
    }
}

#[test]
fn conversations_form_and_break_up_on_schedule() {
    let s = scenario("museum");
    let t = run(&s, 6, 2000, |_, _| {});
    let at = |time: f64| ((time / t.dt).round() as usize).saturating_sub(1);
    // (group, start, end) in seconds into the episode; group 13 is given in time of day.
    for (g, start, end) in [(11u32, -10.0, 60.0), (12, 20.0, 120.0), (13, 30.0, 150.0)] {
        let members: Vec<usize> = (0..s.persons.len()).filter(|&i| s.persons[i].group == Some(g)).collect();
        let spot = Vec2::from(s.persons[members[0]].spot.expect("spot"));
        let r = 0.4 + 0.1 * members.len() as f64;
        let formed = |k: usize| {
            members.iter().all(|&i| {
                let q = t.pos[k][i];
                ((q - spot).norm() - r).abs() < 0.45 && angle_between(t.heading[k][i], q, spot) < 0.3
            })
        };
        if start > 0.0 {
            // waiting at home before the start, formed before the end, not formed before the start
            let k = at(start - 1.0);
            for &i in &members {
                let home = Vec2::from(s.persons[i].home.expect("home"));
                assert!((t.pos[k][i] - home).norm() < 1e-9, "{} left home early", s.persons[i].name);
            }
            assert!(!formed(k), "group {g} formed before its start");
        }
        let k = at(end - 1.0);
        let state: Vec<(Vec2, f64, f64)> = members
            .iter()
            .map(|&i| {
                (t.pos[k][i], (t.pos[k][i] - spot).norm(), angle_between(t.heading[k][i], t.pos[k][i], spot))
            })
            .collect();
        assert!(formed(k), "group {g} not formed at {} s: {state:?}", end - 1.0);
        // broken up: 40 s after the end every member has walked away from the spot
        let k = at(end + 40.0);
        for &i in &members {
            assert!((t.pos[k][i] - spot).norm() > r + 1.0, "{} still at the conversation", s.persons[i].name);
        }
    }
}

#[test]
fn the_tour_stops_and_gathers_facing_the_guide() {
    let s = scenario("museum");
    let g = index(&s, "tour_guide");
    let followers: Vec<usize> = (0..s.persons.len()).filter(|&i| s.persons[i].guide == Some(g)).collect();
    assert_eq!(followers.len(), 4);
    let radius = s.persons[followers[0]].gather_radius;
    let t = run(&s, 7, 3000, |world, k| {
        // the group stays together all along
        let c = world.crowd();
        for &i in &followers {
            let d = (c.pos[i] - c.pos[g]).norm();
            assert!(d < 6.0, "follower {i} {d:.1} m from the guide at step {k}");
        }
    });
    // The guide stands still at its stops for 25 s; 20 s into a stop the group has gathered.
    let still = still_for(&t, g, 200);
    let stops: std::collections::BTreeSet<[u64; 2]> =
        still.iter().map(|&k| [t.pos[k][g].x.to_bits(), t.pos[k][g].y.to_bits()]).collect();
    assert!(stops.len() >= 3, "the guide stopped at {} places", stops.len());
    for &k in &still {
        let pg = t.pos[k][g];
        let centroid = followers.iter().fold(Vec2::zeros(), |a, &i| a + t.pos[k][i]) / followers.len() as f64;
        assert!(angle_between(t.heading[k][g], pg, centroid) < 0.3, "the guide does not face the group");
        for &i in &followers {
            let q = t.pos[k][i];
            let d = (q - pg).norm();
            assert!(
                (d - radius).abs() < 0.6,
                "follower {} {d:.2} m from the guide at a stop",
                s.persons[i].name
            );
            assert!(
                angle_between(t.heading[k][i], q, pg) < 0.3,
                "follower {} does not face the guide",
                s.persons[i].name
            );
        }
    }
}

#[test]
fn residents_and_staff_arrive_before_their_activities_and_leave_after() {
    let s = scenario("care_center");
    let t = run(&s, 8, 3000, |_, _| {});
    let at = |time: f64| ((time / t.dt).round() as usize).saturating_sub(1);
    let mut checked = 0;
    for act in &s.activities {
        let (t0, t1) = (act.start - s.scene.start_time, act.end - s.scene.start_time);
        let o = s.objects.iter().position(|o| o.name == act.object).expect("object");
        let obj = &s.objects[o];
        let c = Vec2::new(obj.pose[0], obj.pose[1]);
        let reach = obj
            .interaction
            .as_ref()
            .expect("space")
            .polygon
            .iter()
            .map(|v| (Vec2::from(*v) - c).norm())
            .fold(0.0, f64::max);
        let participants: Vec<usize> =
            (0..s.persons.len()).filter(|&i| s.persons[i].attends.contains(&o)).collect();
        // arrived (standing in the object's space, still) when the activity starts
        if t0 > 0.0 && t0 < 300.0 {
            let k = at(t0);
            for &i in &participants {
                let q = t.pos[k][i];
                assert!((q - c).norm() <= reach, "{} not at {} when it starts", s.persons[i].name, obj.name);
                assert!(
                    t.pos[k - 10][i] == q,
                    "{} still walking when {} starts",
                    s.persons[i].name,
                    obj.name
                );
                checked += 1;
            }
            // a therapist faces the residents
            let residents: Vec<usize> = participants
                .iter()
                .copied()
                .filter(|&i| s.persons[i].behaviour == Behaviour::Resident)
                .collect();
            let mean = residents.iter().fold(Vec2::zeros(), |a, &i| a + t.pos[k][i]) / residents.len() as f64;
            for &i in participants.iter().filter(|&&i| s.persons[i].behaviour == Behaviour::Staff) {
                assert!(
                    angle_between(t.heading[k][i], t.pos[k][i], mean) < 0.4,
                    "{} does not face the residents",
                    s.persons[i].name
                );
            }
        }
        // left 60 s after it ends
        if t1 > 0.0 && t1 + 60.0 < 300.0 {
            let k = at(t1 + 60.0);
            for &i in &participants {
                assert!(
                    (t.pos[k][i] - c).norm() > reach,
                    "{} still at {} after it ended",
                    s.persons[i].name,
                    obj.name
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 8, "{checked}");
}

/// A 10 x 8 m room split by a wall at x = 5 (doorway y 3.3 - 4.7), with a table and a bench.
const ROOM: &str = r#"
[scene]
name = "room"
bounds = [0, 0, 10, 8]

[[wall]]
from = [0, 0]
to = [10, 0]
[[wall]]
from = [10, 0]
to = [10, 8]
[[wall]]
from = [10, 8]
to = [0, 8]
[[wall]]
from = [0, 8]
to = [0, 0]
[[wall]]
from = [5, 0]
to = [5, 3.2]
[[wall]]
from = [5, 4.8]
to = [5, 8]

[[object]]
name = "table"
kind = "table"
pose = [2.5, 6.0, 0.0]
size = [1.2, 0.8]
interaction = { shape = "rectangle", margin = 0.8 }

[[object]]
name = "bench"
kind = "bench"
pose = [8.0, 1.0, 1.5707963267948966]
size = [0.5, 1.8]

[[activity]]
object = "table"
start = "09:01"
end = "09:30"

[[robot]]
start = [1, 1, 0]
goal = [9, 7]
"#;

/// The error of ROOM plus `people`, from parsing or building the world.
fn room_error(people: &str) -> (String, String, String) {
    let text = format!("{ROOM}\n{people}");
    let (file, field, expected, found) =
        scenario_error(Scenario::from_toml_str(&text, "room.toml").and_then(World::new));
    assert_eq!(file, "room.toml");
    (field, expected, found)
}

#[test]
fn the_room_is_valid_with_every_behaviour() {
    let people = r#"
[[person]]
behaviour = "visitor"
exhibits = ["table", 0]
dwell = 2.0
[[person]]
behaviour = "seated"
seat = "bench"
place = 1
[[person]]
behaviour = "resident"
home = [8.0, 6.0]
attends = ["table"]
speed = "elderly"
[[person]]
behaviour = "staff"
home = [8.5, 7.0]
attends = ["table"]
[[person]]
behaviour = "conversation"
group = 1
home = [7.0, 3.0]
spot = [7.5, 5.0]
start = 5.0
end = "09:02"
[[person]]
behaviour = "conversation"
group = 1
home = [9.0, 3.0]
spot = [7.5, 5.0]
start = 5.0
end = "09:02"
[[person]]
behaviour = "guide"
route = [[2.5, 2.0], [4.0, 4.0], [7.0, 4.0], [4.0, 3.9]]
stops = [0, 2]
dwell = 5.0
[[person]]
behaviour = "follower"
guide = "person_6"
"#;
    let s = Scenario::from_toml_str(&format!("{ROOM}\n{people}"), "room.toml").expect("valid");
    assert_eq!(s.persons[4].schedule, Some([5.0, 120.0]));
    // the seated person sits on the bench, at its middle place, facing its front
    assert_eq!(s.persons[1].pose, [8.0, 1.0, std::f64::consts::FRAC_PI_2]);
    World::new(s).expect("valid world");
}

#[test]
fn a_route_through_a_wall_is_named() {
    let (field, expected, found) =
        room_error("[[person]]\nbehaviour = \"guide\"\nroute = [[2.0, 2.0], [8.0, 2.0]]\n");
    assert_eq!(field, "person[0].route[0]");
    assert!(expected.contains("does not cross walls"), "{expected}");
    assert!(found.contains("[2, 2] to [8, 2]"), "{found}");
}

#[test]
fn a_group_with_one_member_is_named() {
    let (field, expected, found) = room_error(
        "[[person]]\nbehaviour = \"standing\"\npose = [8, 6, 0]\ngroup = 4\n[[person]]\nbehaviour = \"standing\"\npose = [8, 7, 0]\n",
    );
    assert_eq!(field, "person[0].group");
    assert!(expected.contains("at least 2"), "{expected}");
    assert_eq!(found, "group 4 with 1 member");
}

#[test]
fn an_activity_or_exhibit_on_a_missing_object_is_named() {
    let text = ROOM.replace("object = \"table\"\nstart", "object = \"stretcher\"\nstart");
    match Scenario::from_toml_str(&text, "room.toml") {
        Err(CoreError::Scenario { field, found, .. }) => {
            assert_eq!(field, "activity[0].object");
            assert_eq!(found, "\"stretcher\"");
        }
        other => panic!("{other:?}"),
    }
    let (field, _, found) =
        room_error("[[person]]\nbehaviour = \"visitor\"\nexhibits = [\"table\", \"tv\"]\n");
    assert_eq!((field.as_str(), found.as_str()), ("person[0].exhibits[1]", "\"tv\""));
    let (field, expected, _) =
        room_error("[[person]]\nbehaviour = \"resident\"\nhome = [8, 6]\nattends = [\"bench\"]\n");
    assert_eq!(field, "person[0].attends[0]");
    assert!(expected.contains("interaction space"), "{expected}");
    let (field, _, found) = room_error("[[person]]\nbehaviour = \"seated\"\nseat = \"sofa\"\n");
    assert_eq!((field.as_str(), found.as_str()), ("person[0].seat", "\"sofa\""));
    let (field, expected, _) =
        room_error("[[person]]\nbehaviour = \"seated\"\nseat = \"bench\"\nplace = 3\n");
    assert_eq!(field, "person[0].place");
    assert!(expected.contains("below 3"), "{expected}");
}

#[test]
fn a_person_inside_furniture_is_named() {
    let (field, expected, found) = room_error("[[person]]\nbehaviour = \"standing\"\npose = [2.5, 6.0, 0]\n");
    assert_eq!(field, "person[0].pose");
    assert!(expected.contains("from walls and furniture"), "{expected}");
    assert_eq!(found, "[2.5, 6]");
    let (field, _, _) =
        room_error("[[person]]\nbehaviour = \"resident\"\nhome = [2.5, 6.2]\nattends = [\"table\"]\n");
    assert_eq!(field, "person[0].home");
    // a conversation whose circle runs into the wall
    let conv = "[[person]]\nbehaviour = \"conversation\"\ngroup = 1\nhome = [7, 2]\nspot = [5.5, 6]\nstart = 1\nend = 9\n";
    let (field, expected, _) = room_error(&format!("{conv}{}", conv.replace("[7, 2]", "[8, 2]")));
    assert_eq!(field, "person[1].spot"); // the member whose place is in the wall
    assert!(expected.contains("o-space"), "{expected}");
}

#[test]
fn fields_of_another_behaviour_and_bad_times_are_named() {
    let (field, expected, _) =
        room_error("[[person]]\nbehaviour = \"standing\"\npose = [8, 6, 0]\nseat = \"bench\"\n");
    assert_eq!(field, "person[0].seat");
    assert!(expected.contains("Standing"), "{expected}");
    let conv = "[[person]]\nbehaviour = \"conversation\"\ngroup = 1\nhome = [7, 2]\nspot = [7.5, 5]\nstart = \"9h\"\nend = 9\n";
    let (field, expected, found) = room_error(&format!("{conv}{conv}"));
    assert_eq!(field, "person[0].start");
    assert!(expected.contains("HH:MM"), "{expected}");
    assert_eq!(found, "\"9h\"");
    let (field, _, _) = room_error("[[person]]\nbehaviour = \"follower\"\nguide = \"nobody\"\n");
    assert_eq!(field, "person[0].guide");
}
