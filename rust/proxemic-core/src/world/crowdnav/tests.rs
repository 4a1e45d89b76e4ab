use super::*;

const FAR: ([f64; 2], [f64; 2]) = ([100.0, 100.0], [100.0, 100.0]);

/// The episode with CrowdNav's ORCA robot (`astar_orca`'s driver).
fn simulate(spec: String, people: &[([f64; 2], [f64; 2])], visible: bool) -> Result<CrowdNavEpisode> {
    let mut orca = OrcaPeople::new()?;
    super::simulate(spec, people, visible, |now| {
        let mut bodies = vec![*now.robot];
        bodies.extend_from_slice(now.humans);
        Ok(Motion::holonomic(orca.velocities(&bodies, &[0], TIME_STEP)?[0], 0.0))
    })
}

/// The episode with `astar_orca`'s unicycle.
fn simulate_unicycle(people: &[([f64; 2], [f64; 2])], visible: bool) -> Result<CrowdNavEpisode> {
    let mut orca = OrcaPeople::new()?;
    super::simulate("t".into(), people, visible, |now| {
        let mut bodies = vec![*now.robot];
        bodies.extend_from_slice(now.humans);
        let (v, r) = unicycle_step(orca.velocities(&bodies, &[0], TIME_STEP)?[0], now.theta);
        Ok(Motion::unicycle(v, r, now.theta))
    })
}

#[test]
fn an_unobstructed_robot_arrives_on_crowdnavs_step() {
    // 1 m/s until the goal is 1 m away (28 steps of 0.25 m), then the preferred velocity is the
    // vector to the goal: the distance left goes 1, 0.75, 0.5625, 0.4219, 0.3164 and the 33rd
    // step ends 0.2373 m from the goal (< 0.3 m), at t = 33 x 0.25 s.
    let e = simulate("t".into(), &[FAR], false).expect("ok");
    assert_eq!(e.outcome, CrowdNavOutcome::Success);
    assert_eq!(e.time, 33.0 * TIME_STEP);
    assert_eq!(e.discomfort_steps, 0);
}

#[test]
fn a_collision_is_checked_before_the_goal_and_a_visible_person_is_passed_clear() {
    // Overlapping bodies at the start: a collision on the first step, at t = 0.25 s.
    let e = simulate("t".into(), &[([0.0, -3.8], [0.0, -3.8])], false).expect("ok");
    assert_eq!((e.outcome, e.time), (CrowdNavOutcome::Collision, TIME_STEP), "{e:?}");
    // Exactly head on with a person who sees the robot: both run ORCA, so nobody touches; without
    // a perturbation (CrowdNav has it commented out) the symmetric pair stalls face to face.
    let head_on = [([0.0, 4.0], [0.0, -4.0])];
    let seen = simulate("t".into(), &head_on, true).expect("ok");
    assert_eq!(seen.outcome, CrowdNavOutcome::Timeout, "{seen:?}");
    assert!(seen.min_dist >= 0.0);
    // Slightly off the line, the pair passes and the robot arrives.
    let off = simulate("t".into(), &[([0.05, 4.0], [0.05, -4.0])], true).expect("ok");
    assert_eq!(off.outcome, CrowdNavOutcome::Success, "{off:?}");
    assert!(off.min_dist >= 0.0);
}

#[test]
fn a_person_standing_on_the_goal_makes_a_timeout_at_crowdnavs_limit() {
    let e = simulate("t".into(), &[([0.0, 4.0], [0.0, 4.0])], false).expect("ok");
    assert_eq!(e.outcome, CrowdNavOutcome::Timeout, "{e:?}");
    assert_eq!(e.time, TIME_LIMIT);
    assert!(e.discomfort_steps > 0);
}

#[test]
fn the_summary_counts_as_crowdnavs_explorer() {
    let rec = |outcome, time, steps: usize, sum: f64| CrowdNavEpisode {
        spec: String::new(),
        outcome,
        time,
        discomfort_steps: steps,
        discomfort_dist_sum: sum,
        min_dist: 0.0,
    };
    let s = summarize(&[
        rec(CrowdNavOutcome::Success, 10.0, 2, 0.2),
        rec(CrowdNavOutcome::Collision, 5.0, 0, 0.0),
        rec(CrowdNavOutcome::Timeout, 25.0, 2, 0.2),
    ]);
    assert_eq!((s.success, s.collision, s.timeout), (1, 1, 1));
    assert_eq!(s.mean_nav_time, 10.0);
    assert_eq!(s.discomfort_frequency, 4.0 / (40.0 / TIME_STEP));
    assert!((s.mean_min_dist_in_discomfort - 0.1).abs() < 1e-12);
    assert_eq!(summarize(&[rec(CrowdNavOutcome::Timeout, 25.0, 0, 0.0)]).mean_nav_time, TIME_LIMIT);
}

#[test]
fn unknown_planners_and_bad_specs_are_named() {
    let e = run_episode("crowdnav/circle_crossing", "nobody").expect_err("an error").to_string();
    assert!(e.contains("planner"), "{e}");
    let e = run_episode("crowdnav/circle_crossing?humans=x", "astar_orca").expect_err("an error").to_string();
    assert!(e.contains("humans"), "{e}");
}

#[test]
fn episodes_are_deterministic() {
    let a = run_episode("crowdnav/circle_crossing?humans=20&seed=3", "astar_orca").expect("ok");
    let b = run_episode("crowdnav/circle_crossing?humans=20&seed=3", "astar_orca").expect("ok");
    assert_eq!(a, b);
}

#[test]
fn every_built_in_planner_drives_a_deterministic_episode() {
    let spec = "crowdnav/circle_crossing?humans=5&seed=10003";
    for planner in PLANNERS {
        let a = run_episode(spec, planner).unwrap_or_else(|e| panic!("{planner}: {e}"));
        let b = run_episode(spec, planner).unwrap_or_else(|e| panic!("{planner}: {e}"));
        assert_eq!(a, b, "{planner}");
        assert!(a.time > 0.0 && a.time <= TIME_LIMIT, "{planner}: {a:?}");
    }
}

#[test]
fn an_unobstructed_planner_arrives_at_crowdnavs_speed() {
    // Alone, the path follower drives the 8 m at up to 1 m/s (its own slowing into the goal):
    // it arrives, no sooner than 7.75 s (8 m less the 0.3 m radius, in whole 0.25 s steps).
    let s = crowdnav::parse_spec("crowdnav/circle_crossing?humans=1&seed=0").expect("spec");
    let mut d = WorldDriver::new(&s, PlannerKind::Astar, true).expect("world");
    let e = super::simulate(s.text(), &[FAR], false, |now| d.drive(&now, None::<&mut NoPolicy>)).expect("ok");
    assert_eq!(e.outcome, CrowdNavOutcome::Success, "{e:?}");
    assert!(e.time >= 7.75 && e.time < 12.0, "{e:?}");
}

#[test]
fn a_policy_drives_through_the_observation_every_step() {
    // The policy is asked once per step, with the robot's observation row; the same policy gives
    // the same episode.
    let spec = "crowdnav/circle_crossing?humans=3&seed=10000";
    let run = || {
        let mut calls = 0usize;
        let e = run_policy_episode(spec, |row: &[f64]| {
            calls += 1;
            assert!(row.iter().all(|v| v.is_finite()));
            Ok::<_, CoreError>([1.0, 0.2, 0.0])
        })
        .expect("ok");
        (e, calls)
    };
    let (e, calls) = run();
    let steps =
        if e.outcome == CrowdNavOutcome::Timeout { 97 } else { (e.time / TIME_STEP).round() as usize };
    assert_eq!(calls, steps, "{e:?}");
    assert_eq!(run().0, e);
    let bad = run_policy_episode(spec, |_: &[f64]| Ok::<_, CoreError>([f64::NAN, 0.0, 0.0]));
    assert!(bad.expect_err("an error").to_string().contains("action"));
}

#[test]
fn the_kinematic_world_names_bad_states() {
    let s = crowdnav::parse_spec("crowdnav/circle_crossing?humans=2&seed=10000").expect("spec");
    let scenario = crowdnav::build(&s).expect("scene").scenario;
    let mut fresh = World::new(scenario).expect("world");
    let robot = KinematicRobot { pose: [0.0, -4.0, 1.57], velocity: Vec2::zeros(), wz: 0.0 };
    let mut out = vec![0.0; fresh.layout().stride];
    let people = [(Vec2::new(1.0, 1.0), Vec2::zeros()); 2];
    let e = fresh.kinematic_observe(robot, &people, false, &mut out).expect_err("before reset");
    assert!(e.to_string().contains("reset"), "{e}");
    let mut d = WorldDriver::new(&s, PlannerKind::Social, true).expect("world");
    let w = &mut d.world;
    let e = w.kinematic_observe(robot, &people[..1], true, &mut out).expect_err("one person short");
    assert!(e.to_string().contains("people"), "{e}");
    let nan = KinematicRobot { velocity: Vec2::new(f64::NAN, 0.0), ..robot };
    let e = w.kinematic_observe(nan, &people, true, &mut out).expect_err("not finite");
    assert!(e.to_string().contains("robot"), "{e}");
    let e = w.kinematic_observe(robot, &people, true, &mut out[1..]).expect_err("short buffer");
    assert!(e.to_string().contains("out"), "{e}");
    w.kinematic_observe(robot, &people, true, &mut out).expect("ok");
    let e = w.kinematic_command(Some([f64::INFINITY, 0.0, 0.0]), &mut out).expect_err("not finite");
    assert!(e.to_string().contains("action"), "{e}");
    let (v, _) = w.kinematic_command(Some([1.0, 1.0, 0.0]), &mut out).expect("ok");
    assert!(v.norm() <= V_PREF + 1e-12, "{v:?}");
}

#[test]
fn the_unicycle_turns_at_most_a_quarter_turn_then_moves_along_its_new_heading() {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4};
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12;
    // Straight ahead: no turn, full speed.
    let (v, r) = unicycle_step(Vec2::new(1.0, 0.0), 0.0);
    assert!(close(v, 1.0) && close(r, 0.0), "{v} {r}");
    // 30 degrees left: turns all of it and goes at full speed.
    let a = std::f64::consts::FRAC_PI_6;
    let (v, r) = unicycle_step(Vec2::new(a.cos(), a.sin()) * 0.8, 0.0);
    assert!(close(v, 0.8) && close(r, a), "{v} {r}");
    // Square to the right: a quarter turn only, at cos(π/4) of the speed.
    let (v, r) = unicycle_step(Vec2::new(0.0, -1.0), 0.0);
    assert!(close(v, FRAC_PI_4.cos()) && close(r, -FRAC_PI_4), "{v} {r}");
    // Behind: turns, does not move (never reverses); nothing asked, nothing done.
    let (v, r) = unicycle_step(Vec2::new(-1.0, -0.1), FRAC_PI_2 - 1.0);
    assert_eq!(v, 0.0);
    assert!(close(r.abs(), FRAC_PI_4), "{r}");
    assert_eq!(unicycle_step(Vec2::zeros(), 1.0), (0.0, 0.0));
    // Turn, then move: the velocity is along the heading after the turn (CrowdNav's agent.py).
    let m = Motion::unicycle(0.5, FRAC_PI_4, 0.0);
    assert!(close(m.vel.x, 0.5 * FRAC_PI_4.cos()) && close(m.vel.y, 0.5 * FRAC_PI_4.sin()), "{m:?}");
    assert!(close(m.turn, FRAC_PI_4));
}

#[test]
fn an_unobstructed_unicycle_arrives_with_the_holonomic_robot_and_a_visible_person_is_passed_clear() {
    // Facing its goal from the start, the unicycle's ORCA velocity is along its heading: the same
    // 33 steps as the holonomic robot (up to the start heading's 0.0008 rad, written 1.57).
    let e = simulate_unicycle(&[FAR], false).expect("ok");
    assert_eq!((e.outcome, e.time), (CrowdNavOutcome::Success, 33.0 * TIME_STEP), "{e:?}");
    // A person crossing square to its path, who sees it: it turns away and still arrives, clear.
    let e = simulate_unicycle(&[([-3.0, 0.0], [3.0, 0.0])], true).expect("ok");
    assert_eq!(e.outcome, CrowdNavOutcome::Success, "{e:?}");
    assert!(e.min_dist >= 0.0, "{e:?}");
}

#[test]
fn every_planner_drives_the_unicycle_by_its_kinematics() {
    // Every step of every planner on crowded scenes: the turn within a quarter turn, the
    // velocity along the heading after the turn, at most 1 m/s. Three scenes, so that a planner
    // whose episode ends early in one (the `learned` policy collides within 3 steps on seed 3)
    // is still checked over many steps.
    for &name in PLANNERS {
        let kind = PlannerKind::parse(name).expect("a planner");
        let mut steps = 0;
        for seed in [3, 4, 5] {
            let s = crowdnav::parse_spec(&format!(
                "crowdnav/circle_crossing?humans=10&seed={seed}&drive=differential"
            ))
            .expect("spec");
            let people = crowdnav::draw_people(&s).expect("people");
            let mut check = |now: &Instant<'_>, m: Motion| {
                steps += 1;
                assert!(m.turn.abs() <= MAX_TURN + 1e-12, "{name}: turn {}", m.turn);
                let h = Vec2::new((now.theta + m.turn).cos(), (now.theta + m.turn).sin());
                assert!(
                    (h.x * m.vel.y - h.y * m.vel.x).abs() < 1e-9,
                    "{name}: sideways {m:?} at {}",
                    now.theta
                );
                assert!(m.vel.norm() <= V_PREF + 1e-12, "{name}: {m:?}");
            };
            if kind == PlannerKind::AstarOrca {
                let mut orca = OrcaPeople::new().expect("orca");
                super::simulate(s.text(), &people, s.visible, |now| {
                    let mut bodies = vec![*now.robot];
                    bodies.extend_from_slice(now.humans);
                    let (v, r) = unicycle_step(orca.velocities(&bodies, &[0], TIME_STEP)?[0], now.theta);
                    let m = Motion::unicycle(v, r, now.theta);
                    check(&now, m);
                    Ok::<_, CoreError>(m)
                })
                .expect("episode");
            } else {
                let mut driver = WorldDriver::new(&s, kind, true).expect("world");
                super::simulate(s.text(), &people, s.visible, |now| {
                    let m = driver.drive(&now, None::<&mut NoPolicy>)?;
                    check(&now, m);
                    Ok::<_, CoreError>(m)
                })
                .expect("episode");
            }
        }
        assert!(steps > 12, "{name}: {steps} steps");
    }
}
