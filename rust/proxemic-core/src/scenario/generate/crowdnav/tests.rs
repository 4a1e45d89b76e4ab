use super::*;
use crate::control::Drive;

#[test]
fn specs_round_trip_and_bad_parameters_are_named() {
    let s = parse_spec("crowdnav/circle_crossing?humans=20&visible=true&seed=7").expect("ok");
    assert_eq!((s.humans, s.visible, s.seed), (20, true, 7));
    assert_eq!(parse_spec(&s.text()).expect("ok"), s);
    assert_eq!(parse_spec("crowdnav/square_crossing").expect("ok").text(), "crowdnav/square_crossing");
    for (bad, field) in [
        ("crowdnav/triangle", "family"),
        ("crowdnav/circle_crossing?humans=0", "humans"),
        ("crowdnav/circle_crossing?humans=21", "humans"),
        ("crowdnav/circle_crossing?visible=yes", "visible"),
        ("crowdnav/circle_crossing?seed=-1", "seed"),
        ("crowdnav/circle_crossing?speed=2", "speed"),
    ] {
        let e = parse_spec(bad).expect_err("an error").to_string();
        assert!(e.contains(field), "{bad}: {e}");
    }
}

#[test]
fn people_follow_crowdnavs_rules() {
    let min = 2.0 * RADIUS + DISCOMFORT_DIST - 0.011; // centimetre rounding of both points
    for family in FAMILIES {
        for seed in 0..30 {
            let s = Spec {
                family: family.to_string(),
                humans: 20,
                visible: false,
                seed,
                drive: Drive::Holonomic,
            };
            let people = draw_people(&s).expect("ok");
            assert_eq!(people.len(), 20);
            let d = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
            for (k, (start, goal)) in people.iter().enumerate() {
                if family == "circle_crossing" {
                    assert_eq!(*goal, [-start[0], -start[1]]);
                    let r = start[0].hypot(start[1]);
                    assert!((CIRCLE_RADIUS - 0.72..=CIRCLE_RADIUS + 0.72).contains(&r), "{r}");
                } else {
                    assert!(start[0] * goal[0] <= 0.0 && start[0].abs() <= 5.0 && goal[1].abs() <= 5.0);
                }
                assert!(d(*start, ROBOT_START) >= min);
                for (s2, g2) in &people[..k] {
                    assert!(d(*start, *s2) >= min);
                    if family == "circle_crossing" {
                        assert!(d(*start, *g2) >= min);
                    } else {
                        assert!(d(*goal, *g2) >= min);
                    }
                }
            }
        }
    }
}

#[test]
fn scenes_load_with_the_protocols_settings() {
    let g = generate("crowdnav/square_crossing?humans=3&seed=4").expect("ok");
    let sc = &g.scenario;
    assert_eq!(sc.persons.len(), 3);
    assert_eq!(sc.control_dt(), TIME_STEP);
    assert_eq!(sc.episode.max_time, TIME_LIMIT);
    assert_eq!(sc.robots[0].radius, RADIUS);
    assert_eq!(g.toml, generate("crowdnav/square_crossing?humans=3&seed=4").expect("ok").toml);
    assert_ne!(g.toml, generate("crowdnav/square_crossing?humans=3&seed=5").expect("ok").toml);
}
