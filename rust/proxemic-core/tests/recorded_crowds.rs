//! Recorded crowds: `[[replay]]` tracks become people who are where the file
//! says (linear interpolation at the control instants), appear at their first sample and leave
//! after their last (absent people count in no observation or metric), react to a robot within
//! `react_radius`, and bad files are refused naming the file, the line and the column.
//!
//! The robot stands at its start; the people are stepped through `World::step` exactly as in an
//! episode.

use std::path::PathBuf;

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::metrics::Outcome;
use proxemic_core::scenario::{Behaviour, Scenario};
use proxemic_core::world::{PERSON_OUT, World};

mod common;
use common::{Drive, scenario_error};

/// A fresh directory for one test's files.
fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("proxemic-replay-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// A 20 m x 20 m empty room with one robot standing at `robot` (its goal far away) and the
/// `[[replay]]` table `replay`; the track file `csv` is written beside it as `tracks.csv`.
fn scene(name: &str, csv: &str, robot: [f64; 2], replay: &str) -> Result<Scenario, CoreError> {
    let d = dir(name);
    std::fs::write(d.join("tracks.csv"), csv).expect("write csv");
    let text = format!(
        r#"
[scene]
name = "replay test"
bounds = [-10, -10, 10, 10]

[[robot]]
start = [{}, {}, 0]
goal = [9, 9]

[episode]
max_time = 30

[[replay]]
file = "tracks.csv"
{replay}
"#,
        robot[0], robot[1]
    );
    let path = d.join("scene.toml");
    std::fs::write(&path, text).expect("write scenario");
    Scenario::from_file(&path)
}

/// Linear interpolation of `track` (`[t, x, y]`) at `t`.
fn lerp(track: &[[f64; 3]], t: f64) -> Option<Vec2> {
    let k = track.windows(2).position(|w| t >= w[0][0] - 1e-9 && t <= w[1][0] + 1e-9)?;
    let (a, b) = (track[k], track[k + 1]);
    let u = ((t - a[0]) / (b[0] - a[0])).clamp(0.0, 1.0);
    Some(Vec2::new(a[1] + (b[1] - a[1]) * u, a[2] + (b[2] - a[2]) * u))
}

/// Per control instant (0 = after reset): each person's position, presence and the people
/// buffer the physics gets; and the world at the end.
struct Run {
    pos: Vec<Vec<Vec2>>,
    present: Vec<Vec<bool>>,
    buffer: Vec<Vec<f64>>,
    masks: Vec<Vec<f64>>,
    world: World,
}

fn run(s: &Scenario, steps: usize) -> Run {
    let mut d = Drive::start(s.clone(), 3);
    let lay = *d.world.layout();
    let mask = |o: &[f64]| o[lay.obs_people_mask.range()].to_vec();
    let (mut pos, mut present, mut buffer, mut masks) = (vec![], vec![], vec![], vec![]);
    for k in 0..=steps {
        if k > 0 {
            d.step_free();
        }
        pos.push(d.world.crowd().pos.clone());
        present.push(d.world.crowd().present.clone());
        buffer.push(d.people.clone());
        masks.push(mask(&d.out));
    }
    Run { pos, present, buffer, masks, world: d.world }
}

/// Two tracks sampled every 0.4 s (ETH's rate), in a frame rotated and moved into the scene.
const TWO_TRACKS: &str = "t,id,x,y
0.0,1,0.0,0.0
0.0,ped 2,2.0,1.0
0.4,1,0.5,0.1
0.4,ped 2,2.0,1.5
0.8,1,1.1,0.1
1.2,1,1.5,0.3
0.8,ped 2,2.2,2.1
1.6,1,2.0,0.6
2.0,1,2.6,0.5
";

#[test]
fn a_replayed_person_is_where_the_file_says_at_every_sample_and_in_between() {
    let s = scene("exact", TWO_TRACKS, [-8.0, -8.0], "offset = [1.0, -2.0]\nrotate = 0.5").expect("valid");
    assert_eq!(s.persons.len(), 2);
    assert!(s.persons.iter().all(|p| p.behaviour == Behaviour::Replay));
    assert_eq!(s.persons[1].name, "replay0:ped 2");
    let (sin, cos) = 0.5f64.sin_cos();
    let scene_xy = |x: f64, y: f64| Vec2::new(cos * x - sin * y + 1.0, sin * x + cos * y - 2.0);
    let r = run(&s, 25);
    let dt = s.control_dt();
    // Every sample of the file, at its instant (samples fall on control instants).
    let num = |v: &str| -> f64 { v.parse().expect("a number") };
    let mut checked = 0;
    for line in TWO_TRACKS.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (t, x, y): (f64, f64, f64) = (num(f[0]), num(f[2]), num(f[3]));
        let i = usize::from(f[1] != "1");
        let k = (t / dt).round() as usize;
        let want = scene_xy(x, y);
        assert!((r.pos[k][i] - want).norm() < 1e-9, "{line}: at {:?}, file says {want:?}", r.pos[k][i]);
        let b = &r.buffer[k][i * PERSON_OUT..];
        assert!((Vec2::new(b[0], b[1]) - want).norm() < 1e-9, "{line}: the physics gets {:?}", &b[..2]);
        checked += 1;
    }
    assert_eq!(checked, 9);
    // Between samples: the linear interpolation, at every control instant the track covers.
    for (i, p) in s.persons.iter().enumerate() {
        for (k, pos) in r.pos.iter().enumerate() {
            if let Some(want) = lerp(&p.track, k as f64 * dt) {
                assert!((pos[i] - want).norm() < 1e-9, "person {i} at step {k}: {:?} vs {want:?}", pos[i]);
                assert!(r.present[k][i]);
            }
        }
    }
}

#[test]
fn people_appear_at_their_first_sample_leave_after_their_last_and_count_for_nothing_meanwhile() {
    // Appears at t = 1.0 s 0.71 m from the robot, on the line from where absent people are
    // parked (far to +x, -y): were the jump from there swept like motion, it would cross the
    // robot. It walks away and leaves at 2.0 s.
    let csv = "t,id,x,y\n1.0,a,0.0,0.0\n1.5,a,-0.5,0.5\n2.0,a,-1.0,1.0\n";
    let s = scene("appear", csv, [0.5, -0.5], "").expect("valid");
    let r = run(&s, 30);
    for (k, present) in r.present.iter().enumerate() {
        let t = k as f64 * s.control_dt();
        let here = (1.0 - 1e-9..=2.0 + 1e-9).contains(&t);
        assert_eq!(present[0], here, "presence at {t} s");
        let b = &r.buffer[k];
        let far = Vec2::new(b[0], b[1]).norm() > 1000.0;
        assert_eq!(far, !here, "the physics' body at {t} s: {:?}", &b[..2]);
        assert_eq!(r.masks[k][0] == 1.0, here, "the robot's observation at {t} s");
    }
    let report = &r.world.episode_metrics().expect("metrics")[0];
    assert_eq!(report.outcome, Outcome::Running, "an absent person's jump is no collision");
    assert_eq!(report.metrics.collisions.hc_count, 0);
    let closest = (10..=20)
        .filter_map(|k| lerp(&s.persons[0].track, k as f64 * 0.1))
        .map(|q| (q - Vec2::new(0.5, -0.5)).norm())
        .fold(f64::INFINITY, f64::min);
    let got = report.metrics.proximity.dist_person_min.expect("someone was present");
    assert!((got - closest).abs() < 1e-9, "closest distance {got} vs {closest} while present");
}

#[test]
fn a_person_who_never_appears_has_no_distance() {
    let csv = "t,id,x,y\n100.0,late,0.0,0.0\n101.0,late,1.0,0.0\n";
    let s = scene("never", csv, [0.5, -0.5], "").expect("valid");
    let r = run(&s, 20);
    assert!(r.present.iter().all(|p| !p[0]));
    let report = &r.world.episode_metrics().expect("metrics")[0];
    assert_eq!(report.metrics.proximity.dist_person_min, None);
    assert_eq!(report.metrics.proximity.d_min, vec![None]);
}

/// A person walking along y = 0 from x = -4 to x = 4 in 8 s, through the robot at the origin.
const THROUGH: &str = "t,id,x,y\n0,w,-4,0\n2,w,-2,0\n4,w,0,0\n6,w,2,0\n8,w,4,0\n";

#[test]
fn a_person_reacts_to_a_robot_within_react_radius_and_otherwise_walks_through_it() {
    let dt = 0.1;
    let gap_min = |r: &Run| r.pos.iter().map(|p| p[0].norm() - 0.2 - 0.24).fold(f64::INFINITY, f64::min);
    let deviation = |r: &Run, s: &Scenario| {
        (0..r.pos.len())
            .filter_map(|k| lerp(&s.persons[0].track, k as f64 * dt).map(|q| (r.pos[k][0] - q).norm()))
            .fold(0.0, f64::max)
    };
    // No reaction (the default): exactly the file, through the robot.
    let blind = scene("blind", THROUGH, [0.0, 0.0], "").expect("valid");
    let b = run(&blind, 80);
    assert!(deviation(&b, &blind) < 1e-9);
    assert!(gap_min(&b) < 0.0);
    // Reacting within 1.5 m: it leaves the file's line and never touches the robot.
    let aware = scene("aware", THROUGH, [0.0, 0.0], "react_radius = 1.5").expect("valid");
    let a = run(&aware, 80);
    let dev = deviation(&a, &aware);
    assert!(dev > 0.3, "the reacting person deviates from its track (by {dev} m)");
    assert!(gap_min(&a) > 0.0, "the reacting person keeps off the robot (gap {})", gap_min(&a));
    // Before the robot is within reach, it was exactly on its track.
    for k in 0..=15 {
        let q = lerp(&aware.persons[0].track, k as f64 * dt).expect("on track");
        assert!((a.pos[k][0] - q).norm() < 1e-9, "step {k}");
    }
    // It still heads on along its track: past the robot by the end.
    assert!(a.pos[80][0].x > 1.0, "at the end: {:?}", a.pos[80][0]);
}

#[test]
fn same_file_same_replay_bit_for_bit() {
    let s = scene("determinism", THROUGH, [0.0, 0.0], "react_radius = 1.5").expect("valid");
    let (a, b) = (run(&s, 60), run(&s, 60));
    assert_eq!(a.buffer, b.buffer);
}

/// The error for the track file `csv` (its file, field, expected, found).
fn file_error(name: &str, csv: &str) -> (String, String, String, String) {
    scenario_error(scene(name, csv, [-8.0, -8.0], ""))
}

#[test]
fn bad_track_files_are_refused_naming_the_file_line_and_column() {
    let cases: [(&str, &str, &str, &str); 8] = [
        (
            "unsorted",
            "t,id,x,y\n0,a,0,0\n1,a,1,0\n0.5,a,2,0\n",
            "line 4, column 1 (t)",
            "each track's times increase",
        ),
        ("wrongheader", "time,id,x,y\n0,a,0,0\n1,a,1,0\n", "line 1, column 1 (header)", "t,id,x,y"),
        ("missingcol", "t,id,x\n0,a,0\n1,a,1\n", "line 1, column 7 (header)", "t,id,x,y"),
        ("shortrow", "t,id,x,y\n0,a,0,0\n1,a,1\n", "line 3, column 6", "4 comma-separated values"),
        ("nan", "t,id,x,y\n0,a,0,0\n1,a,NaN,0\n", "line 3, column 5 (x)", "finite coordinate"),
        ("text", "t,id,x,y\n0,a,0,0\none,a,1,0\n", "line 3, column 1 (t)", "finite time"),
        (
            "onesample",
            "t,id,x,y\n0,a,0,0\n1,a,1,0\n# b stays\n2,b,1,1\n",
            "line 5, column 1 (t)",
            "at least 2 samples",
        ),
        ("outside", "t,id,x,y\n0,a,0,0\n1,a,50,0\n", "line 3", "inside scene.bounds"),
    ];
    for (name, csv, field, expected) in cases {
        let (file, f, e, found) = file_error(name, csv);
        assert!(file.ends_with("tracks.csv"), "{name}: the error names the track file, not {file}");
        assert_eq!(f, format!("replay[0].file {field}"), "{name}: {e} / {found}");
        assert!(e.contains(expected), "{name}: expected {expected:?} in {e:?}");
    }
    // A missing file names the scenario's field and the path tried.
    let d = dir("missing");
    let path = d.join("scene.toml");
    let text = "[scene]\nname = \"m\"\nbounds = [0, 0, 5, 5]\n[[robot]]\nstart = [1, 1, 0]\ngoal = [4, 4]\n[[replay]]\nfile = \"nowhere.csv\"\n";
    std::fs::write(&path, text).expect("write");
    match Scenario::from_file(&path) {
        Err(CoreError::Scenario { file, field, found, .. }) => {
            assert!(file.ends_with("scene.toml"));
            assert_eq!(field, "replay[0].file");
            assert!(found.contains("nowhere.csv"), "{found}");
        }
        other => panic!("expected a scenario error, got {:?}", other.err()),
    }
    // `behaviour = "replay"` belongs to [[replay]] files only.
    let bad = "[scene]\nname = \"m\"\nbounds = [0, 0, 5, 5]\n[[robot]]\nstart = [1, 1, 0]\ngoal = [4, 4]\n[[person]]\nbehaviour = \"replay\"\n";
    match Scenario::from_toml_str(bad, "inline.toml") {
        Err(CoreError::Scenario { field, .. }) => assert_eq!(field, "person[0].behaviour"),
        other => panic!("expected a scenario error, got {:?}", other.err()),
    }
}
