//! Each archetype is built as Francis et al. 2023 describe it, for many seeds: the people and the
//! robot start where the archetype puts them, and the passages are as narrow as drawn.

use super::*;
use crate::error::CoreError;
use crate::map::geometry::{Bounds, StaticGeometry};
use crate::math::Vec2;
use crate::scenario::Behaviour;
use crate::world::World;

const SEEDS: u64 = 12;

/// Tolerance of positions (m): every value is written rounded to centimetres.
const CM: f64 = 0.011;

fn scene(arch: &str, seed: u64) -> Scenario {
    generate(&format!("{PREFIX}{arch}?seed={seed}"))
        .unwrap_or_else(|e| panic!("{arch} seed {seed}: {e}"))
        .scenario
}

fn geometry(s: &Scenario) -> StaticGeometry {
    let b = s.scene.bounds;
    let bounds = Bounds { min: Vec2::new(b[0], b[1]), max: Vec2::new(b[2], b[3]) };
    let polygons = s
        .static_polygons()
        .into_iter()
        .map(|p| p.into_iter().map(|q| Vec2::new(q[0], q[1])).collect())
        .collect();
    StaticGeometry::new(polygons, bounds).expect("geometry")
}

fn v(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

/// The robot's start, unit direction to its goal, and the distance to it.
fn robot_line(s: &Scenario, i: usize) -> (Vec2, Vec2, f64) {
    let r = &s.robots[i];
    let (a, b) = (Vec2::new(r.start[0], r.start[1]), v(r.goal));
    let d = b - a;
    (a, d * (1.0 / d.norm()), d.norm())
}

/// Along-track and signed cross-track coordinates of `p` in the frame (origin `o`, unit `u`).
fn frame(o: Vec2, u: Vec2, p: Vec2) -> (f64, f64) {
    let d = p - o;
    (d.x * u.x + d.y * u.y, u.x * d.y - u.y * d.x)
}

/// Clear width through `p` across the unit direction `u` (rays both ways to the walls).
fn width_across(g: &StaticGeometry, p: Vec2, u: Vec2) -> f64 {
    let n = Vec2::new(-u.y, u.x);
    g.cast_ray(p, n, 50.0) + g.cast_ray(p, n * -1.0, 50.0)
}

fn unit(a: Vec2, b: Vec2) -> Vec2 {
    let d = b - a;
    d * (1.0 / d.norm())
}

fn dot(a: Vec2, b: Vec2) -> f64 {
    a.x * b.x + a.y * b.y
}

/// Where the first person's one-way walk ends (its stop).
fn walk_end(s: &Scenario) -> Vec2 {
    let p = &s.persons[0];
    let k = p.stops.iter().position(|&x| x).expect("a walk's stop");
    v(p.route[k])
}

/// The first person's first leg: start and unit direction.
fn first_leg(s: &Scenario, k: usize) -> (Vec2, Vec2) {
    let r = &s.persons[k].route;
    (v(r[0]), unit(v(r[0]), v(r[1])))
}

#[test]
fn every_archetype_builds_a_world_round_trips_and_is_deterministic() {
    for arch in ARCHETYPES {
        for seed in 0..SEEDS {
            let spec = format!("{PREFIX}{arch}?seed={seed}");
            let g = generate(&spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
            World::new(g.scenario.clone()).unwrap_or_else(|e| panic!("{spec}: {e}"));
            let back = Scenario::from_toml_str(&g.toml, &g.scenario.source).expect("reload");
            assert_eq!(
                back.to_json().expect("json"),
                g.scenario.to_json().expect("json"),
                "{spec}: the text does not load back the same"
            );
            assert_eq!(generate(&spec).expect("again").toml, g.toml, "{spec}: not deterministic");
        }
        let a = generate(&format!("{PREFIX}{arch}")).expect("seed 0").toml;
        assert_ne!(
            a,
            generate(&format!("{PREFIX}{arch}?seed=1")).expect("seed 1").toml,
            "{arch}: seed ignored"
        );
        assert_eq!(a, generate(&format!("{PREFIX}{arch}?seed=0")).expect("seed=0").toml);
    }
}

#[test]
fn specs_parse_and_bad_specs_name_the_field() {
    let s = parse_spec("francis2023/crossing_90?seed=4&max_time=12").expect("spec");
    assert_eq!((s.archetype.as_str(), s.seed, s.max_time), ("crossing_90", 4, Some(12.0)));
    assert_eq!(s.text(), "francis2023/crossing_90?seed=4&max_time=12");
    assert_eq!(generate("francis2023/crossing_90?max_time=12").expect("t").scenario.episode.max_time, 12.0);
    for (bad, field) in [
        ("francis2023/frontal", "archetype"),
        ("francis2023/crossing_90?seed=-1", "seed"),
        ("francis2023/crossing_90?max_time=1", "max_time"),
        ("francis2023/crossing_90?width=3", "width"),
        ("francis2023/crossing_90?seed", "<spec>"),
    ] {
        match parse_spec(bad) {
            Err(CoreError::Scenario { field: f, .. }) => assert_eq!(f, field, "{bad}"),
            other => panic!("{bad}: {other:?}"),
        }
    }
}

#[test]
fn frontal_approach_person_ahead_on_the_line_walking_toward_the_robot() {
    for seed in 0..SEEDS {
        let s = scene("frontal_approach", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, across) = frame(o, u, p);
        assert!((6.0 - CM..=9.0 + CM).contains(&along), "seed {seed}: person {along} m ahead");
        assert!(across.abs() <= 0.2 + CM, "seed {seed}: {across} m off the robot's line");
        assert!(dot(dir, u) < -0.999, "seed {seed}: the person does not walk toward the robot");
    }
}

#[test]
fn pedestrian_obstruction_person_stands_in_the_way_with_room_to_pass() {
    for seed in 0..SEEDS {
        let s = scene("pedestrian_obstruction", seed);
        let (o, u, len) = robot_line(&s, 0);
        let p = &s.persons[0];
        assert_eq!(p.behaviour, Behaviour::Standing);
        let (along, across) = frame(o, u, Vec2::new(p.pose[0], p.pose[1]));
        assert!((4.0 - CM..=6.0 + CM).contains(&along) && along < len, "seed {seed}: {along} m ahead");
        assert!(across.abs() <= 0.3 + CM, "seed {seed}: not in the robot's way ({across} m)");
        let w = width_across(&geometry(&s), Vec2::new(p.pose[0], p.pose[1]), u);
        assert!((2.4 - 1e-6..=3.2 + 1e-6).contains(&w), "seed {seed}: hall {w} m wide");
        // Room for the robot's inflated footprint on one side of the person at least.
        let r = &s.robots[0];
        assert!(w / 2.0 + across.abs() - p.radius >= 2.0 * (r.radius + r.inflation_margin), "seed {seed}");
    }
}

#[test]
fn overtaking_slow_person_ahead_and_fast_person_behind_walk_the_robot_s_way() {
    for seed in 0..SEEDS {
        let s = scene("robot_overtaking", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, across) = frame(o, u, p);
        assert!((2.0 - CM..=3.5 + CM).contains(&along) && across.abs() <= 0.2 + CM, "seed {seed}");
        assert!(dot(dir, u) > 0.999 && s.persons[0].speed < s.robots[0].max_speed, "seed {seed}");

        let s = scene("pedestrian_overtaking", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, _) = frame(o, u, p);
        assert!(
            (-3.0 - CM..=-1.5 + CM).contains(&along),
            "seed {seed}: the person starts {along} m from the robot"
        );
        assert!(dot(dir, u) > 0.999 && s.persons[0].speed > s.robots[0].max_speed, "seed {seed}");
        // The person's walk ends past the robot's goal: it has to overtake.
        let end = walk_end(&s);
        assert!(frame(o, u, end).0 > frame(o, u, v(s.robots[0].goal)).0, "seed {seed}");
    }
}

#[test]
fn crossings_cross_the_robot_s_path_at_their_angle_at_about_the_same_time() {
    for (arch, angle) in [("crossing_90", 90.0f64), ("crossing_45", 45.0)] {
        for seed in 0..SEEDS {
            let s = scene(arch, seed);
            let (o, u, len) = robot_line(&s, 0);
            let (p, dir) = first_leg(&s, 0);
            let between = dot(dir, u).abs().min(1.0).acos().to_degrees();
            assert!((between - angle).abs() < 1.0, "{arch} seed {seed}: paths at {between} deg");
            // Where the person's line meets the robot's, within both walks.
            let (pa, pc) = frame(o, u, p);
            let (da, dc) = (dot(dir, u), u.x * dir.y - u.y * dir.x);
            let t = -pc / dc;
            let meet = pa + t * da;
            let leg = (v(s.persons[0].route[1]) - p).norm();
            assert!(meet > 0.0 && meet < len && t > 0.0 && t < leg, "{arch} seed {seed}: no crossing");
            let ratio = (t / s.persons[0].speed) / (meet / s.robots[0].max_speed);
            assert!((0.85..=1.25).contains(&ratio), "{arch} seed {seed}: arrival ratio {ratio}");
        }
    }
}

#[test]
fn narrow_hallway_is_as_narrow_as_drawn_and_the_person_comes_the_other_way() {
    for seed in 0..SEEDS {
        let s = scene("narrow_hallway", seed);
        let (o, u, len) = robot_line(&s, 0);
        let g = geometry(&s);
        for k in 0..=10 {
            let w = width_across(&g, o + u * (len * k as f64 / 10.0), u);
            assert!((1.2 - 1e-6..=1.6 + 1e-6).contains(&w), "seed {seed}: {w} m wide");
        }
        let (p, dir) = first_leg(&s, 0);
        assert!(frame(o, u, p).0 > len && dot(dir, u) < -0.999, "seed {seed}");
    }
}

#[test]
fn narrow_doorway_robot_and_person_cross_one_narrow_door_in_opposite_directions() {
    for seed in 0..SEEDS {
        let s = scene("narrow_doorway", seed);
        let (o, u, len) = robot_line(&s, 0);
        let g = geometry(&s);
        let narrowest = (0..=200)
            .map(|k| width_across(&g, o + u * (len * k as f64 / 200.0), u))
            .fold(f64::INFINITY, f64::min);
        assert!((0.9 - 1e-6..=1.2 + 1e-6).contains(&narrowest), "seed {seed}: door {narrowest} m");
        let (p, _) = first_leg(&s, 0);
        let end = walk_end(&s);
        // The person starts beyond the door (between it and the robot's goal) and ends on the robot's side.
        let wall_x = (o + u * len).x - 2.5 - WALL;
        assert!(p.x > wall_x + WALL && end.x < wall_x && o.x < wall_x, "seed {seed}");
    }
}

#[test]
fn blind_corner_walls_hide_the_person_from_the_robot() {
    for seed in 0..SEEDS {
        let s = scene("blind_corner", seed);
        let r = &s.robots[0];
        let start = Vec2::new(r.start[0], r.start[1]);
        let (p, dir) = first_leg(&s, 0);
        let g = geometry(&s);
        assert!(g.segment_hits(start, p), "seed {seed}: the robot sees the person at the start");
        // The robot's leg runs east, the person's south, toward the robot's leg: perpendicular.
        assert!(r.start[2].abs() < 1e-9 && dot(dir, Vec2::new(0.0, -1.0)) > 0.999, "seed {seed}");
        let w = width_across(&g, start, Vec2::new(1.0, 0.0));
        assert!((1.6 - 1e-6..=2.4 + 1e-6).contains(&w), "seed {seed}: corridor {w} m");
        // The straight line to the goal crosses the corner's walls: the robot must turn.
        assert!(g.segment_hits(start, v(r.goal)), "seed {seed}");
        let end = walk_end(&s);
        assert!(
            (end.y - start.y).abs() < CM && end.x < start.x,
            "seed {seed}: the person ends behind the robot"
        );
    }
}

#[test]
fn entering_and_exiting_room_go_through_the_doorway_past_a_person() {
    for (arch, entering) in [("entering_room", true), ("exiting_room", false)] {
        for seed in 0..SEEDS {
            let s = scene(arch, seed);
            let r = &s.robots[0];
            let (start, goal) = (Vec2::new(r.start[0], r.start[1]), v(r.goal));
            let g = geometry(&s);
            // The corridor is below y = its width; the room above the dividing wall.
            let cw = width_across(&g, Vec2::new(0.5, 0.5), Vec2::new(1.0, 0.0));
            assert!((1.8 - 1e-6..=2.4 + 1e-6).contains(&cw), "{arch} seed {seed}: corridor {cw}");
            let (in_room, in_corridor) = if entering { (goal, start) } else { (start, goal) };
            assert!(in_room.y > cw + WALL && in_corridor.y < cw, "{arch} seed {seed}");
            // The doorway: the gap in the dividing wall, on x = 6 (the corridor's middle).
            let door = width_across(&g, Vec2::new(6.0, cw + WALL / 2.0), Vec2::new(0.0, 1.0));
            assert!((0.9 - 1e-6..=1.2 + 1e-6).contains(&door), "{arch} seed {seed}: door {door}");
            let route = &s.persons[0].route;
            let (p0, p1) = (v(route[0]), walk_end(&s));
            if entering {
                assert!(p0.y > cw + WALL && p1.y < cw, "{arch} seed {seed}: the person does not come out");
            } else {
                // Along the corridor, past the doorway, from the side the robot turns to.
                assert!(p0.y < cw && (p0.y - p1.y).abs() < 1e-9, "{arch} seed {seed}");
                assert!(
                    (p0.x - 6.0) * (p1.x - 6.0) < 0.0 && (p0.x - 6.0) * (goal.x - 6.0) > 0.0,
                    "{arch} seed {seed}"
                );
            }
        }
    }
}

/// The centre of the people's places (a group's o-space centre).
fn centre(s: &Scenario) -> Vec2 {
    let n = s.persons.len() as f64;
    let sum = s.persons.iter().fold(Vec2::new(0.0, 0.0), |acc, p| acc + Vec2::new(p.pose[0], p.pose[1]));
    sum * (1.0 / n)
}

#[test]
fn joining_and_leaving_a_conversation_group() {
    for seed in 0..SEEDS {
        let s = scene("joining_group", seed);
        let members: Vec<_> = s.persons.iter().filter(|p| p.behaviour == Behaviour::Standing).collect();
        assert!((2..=4).contains(&members.len()) && members.len() == s.persons.len(), "seed {seed}");
        assert!(members.iter().all(|p| p.group == Some(1)), "seed {seed}: not one group");
        let spot = centre(&s);
        for p in &members {
            // Facing the o-space centre.
            let to = spot - Vec2::new(p.pose[0], p.pose[1]);
            let facing = Vec2::new(p.pose[2].cos(), p.pose[2].sin());
            assert!(dot(to * (1.0 / to.norm()), facing) > 0.999, "seed {seed}: a member faces away");
        }
        let r = &s.robots[0];
        assert!(r.approach.is_some(), "seed {seed}: joining is an approach task");
        let d0 = (Vec2::new(r.start[0], r.start[1]) - spot).norm();
        assert!((5.0 - 1e-2..=7.0 + 1e-2).contains(&d0), "seed {seed}: starts {d0} m away");
        assert!((v(r.goal) - spot).norm() < 2.5, "seed {seed}: its goal is not at the group");

        let s = scene("leaving_group", seed);
        let spot = centre(&s);
        let r = &s.robots[0];
        let start = Vec2::new(r.start[0], r.start[1]);
        let ring = 0.4 + 0.1 * s.persons.len() as f64;
        assert!((start - spot).norm() <= ring + 0.3, "seed {seed}: the robot is not in the group");
        for p in &s.persons {
            let at = Vec2::new(p.pose[0], p.pose[1]);
            assert!((at - start).norm() > p.radius + r.radius, "seed {seed}: the robot overlaps a member");
        }
        let d1 = (v(r.goal) - spot).norm();
        assert!((5.0 - 1e-2..=7.0 + 1e-2).contains(&d1), "seed {seed}: goal {d1} m away");
    }
}

#[test]
fn following_and_accompanying_a_person() {
    for seed in 0..SEEDS {
        let s = scene("following_person", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, across) = frame(o, u, p);
        assert!(
            (1.5 - CM..=2.5 + CM).contains(&along) && across.abs() < CM && dot(dir, u) > 0.999,
            "seed {seed}"
        );
        assert!(s.persons[0].speed < s.robots[0].max_speed, "seed {seed}: the robot cannot keep up");
        let end = walk_end(&s);
        let gap = frame(v(s.robots[0].goal), u, end).0;
        assert!((1.2 - CM..=1.6 + CM).contains(&gap), "seed {seed}: goal {gap} m behind the person's end");

        let s = scene("accompanying_person", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, across) = frame(o, u, p);
        assert!(along.abs() < CM && (0.8 - CM..=1.2 + CM).contains(&across.abs()), "seed {seed}");
        assert!(dot(dir, u) > 0.999, "seed {seed}: not the same way");
        let end = walk_end(&s);
        let (ga, gc) = frame(v(s.robots[0].goal), u, end);
        assert!(
            ga.abs() < CM && (gc - across).abs() < CM,
            "seed {seed}: the goal is not beside the person's end"
        );
    }
}

#[test]
fn dense_crowd_has_at_least_one_person_per_square_metre_where_the_robot_passes() {
    const WINDOW: f64 = 3.0; // a 3 m stretch of the hall, its whole width
    for seed in 0..SEEDS {
        let s = scene("dense_crowd", seed);
        let (o, u, len) = robot_line(&s, 0);
        let g = geometry(&s);
        let w = width_across(&g, o, u);
        let starts: Vec<f64> = s.persons.iter().map(|p| frame(o, u, v(p.route[0])).0).collect();
        let best = (0..=((len - WINDOW) / 0.05) as usize)
            .map(|k| {
                let a = k as f64 * 0.05;
                (a, starts.iter().filter(|&&x| x >= a && x <= a + WINDOW).count())
            })
            .max_by_key(|c| c.1)
            .expect("windows");
        let density = best.1 as f64 / (WINDOW * w);
        assert!(density >= 1.0, "seed {seed}: {density:.2} people/m^2 at best");
        assert!(best.0 > 0.0 && best.0 + WINDOW < len, "seed {seed}: the crowd is not on the robot's way");
        // The crowd stays in its stretch: every route within 1 m of the densest window.
        for p in &s.persons {
            for q in &p.route {
                let x = frame(o, u, v(*q)).0;
                assert!(
                    x > best.0 - 1.5 && x < best.0 + WINDOW + 1.5,
                    "seed {seed}: a crowd member wanders off"
                );
            }
        }
    }
}

#[test]
fn robot_crowding_surrounds_the_robot_with_people_with_a_way_out() {
    for seed in 0..SEEDS {
        let s = scene("robot_crowding", seed);
        assert_eq!(s.robots.len(), 1, "seed {seed}");
        assert!((5..=7).contains(&s.persons.len()), "seed {seed}: {} people", s.persons.len());
        let r = &s.robots[0];
        let c = Vec2::new(r.start[0], r.start[1]);
        let mut bearings = Vec::new();
        for p in &s.persons {
            assert_eq!(p.behaviour, Behaviour::Standing, "seed {seed}");
            let at = Vec2::new(p.pose[0], p.pose[1]);
            let d = (at - c).norm();
            assert!((1.3 - CM..=1.7 + CM).contains(&d), "seed {seed}: a person {d} m from the robot");
            // Facing the robot.
            let facing = Vec2::new(p.pose[2].cos(), p.pose[2].sin());
            assert!(dot(unit(at, c), facing) > 0.99, "seed {seed}: a person faces away");
            bearings.push((at.y - c.y).atan2(at.x - c.x));
        }
        // A way out: every gap between neighbours round the ring lets the robot's body through.
        bearings.sort_by(f64::total_cmp);
        let ring = (Vec2::new(s.persons[0].pose[0], s.persons[0].pose[1]) - c).norm();
        for k in 0..bearings.len() {
            let next =
                if k + 1 < bearings.len() { bearings[k + 1] } else { bearings[0] + std::f64::consts::TAU };
            let chord = 2.0 * ring * ((next - bearings[k]) / 2.0).sin();
            assert!(chord - 2.0 * s.persons[0].radius > 2.0 * r.radius, "seed {seed}: gap {chord} m");
        }
        let far = (v(r.goal) - c).norm();
        assert!((4.0 - CM..=6.0 + CM).contains(&far), "seed {seed}: goal {far} m away");
    }
}

#[test]
fn down_path_person_walks_the_robot_s_way_four_metres_aside() {
    for seed in 0..SEEDS {
        let s = scene("down_path", seed);
        let (o, u, _) = robot_line(&s, 0);
        let (p, dir) = first_leg(&s, 0);
        let (along, across) = frame(o, u, p);
        assert!((3.5 - CM..=4.5 + CM).contains(&across.abs()), "seed {seed}: {across} m aside");
        assert!((-1.0 - CM..=2.0 + CM).contains(&along), "seed {seed}: {along} m ahead");
        assert!(dot(dir, u) > 0.999, "seed {seed}: not the robot's way");
        let sp = s.persons[0].speed;
        assert!((0.45 - CM..=0.65 + CM).contains(&sp), "seed {seed}: {sp} m/s");
    }
}

#[test]
fn intersections_person_crosses_first_or_waits_at_the_edge() {
    for seed in 0..SEEDS {
        for wait in [true, false] {
            let arch = if wait { "intersection_wait" } else { "intersection_proceed" };
            let s = scene(arch, seed);
            let (o, u, len) = robot_line(&s, 0);
            let g = geometry(&s);
            let cw = width_across(&g, o, u);
            assert!((2.0 - 1e-6..=3.0 + 1e-6).contains(&cw), "{arch} seed {seed}: corridor {cw} m");
            let p = &s.persons[0];
            if wait {
                let (a, dir) = first_leg(&s, 0);
                assert!(dot(dir, u).abs() < 1e-6, "{arch} seed {seed}: not across the robot's way");
                let (pa, pc) = frame(o, u, a);
                // The person reaches the robot's line first: 0.5-0.8 of the robot's time.
                let ratio = (pc.abs() / p.speed) / (pa / s.robots[0].max_speed);
                assert!((0.45..=0.85).contains(&ratio), "{arch} seed {seed}: arrival ratio {ratio}");
                let (_, ec) = frame(o, u, walk_end(&s));
                assert!(ec * pc < 0.0 && pa < len, "{arch} seed {seed}: the person does not cross");
                // The crossing corridor is open across the robot's: the person's walk is clear.
                assert!(!g.segment_hits(a, walk_end(&s)), "{arch} seed {seed}");
            } else {
                assert_eq!(p.behaviour, Behaviour::Standing);
                let at = Vec2::new(p.pose[0], p.pose[1]);
                let (pa, pc) = frame(o, u, at);
                assert!(pa > 0.0 && pa < len, "{arch} seed {seed}");
                let edge = pc.abs() - cw / 2.0;
                assert!((0.4 - CM..=0.8 + CM).contains(&edge), "{arch} seed {seed}: {edge} m from the edge");
                let facing = Vec2::new(p.pose[2].cos(), p.pose[2].sin());
                assert!(
                    facing.x.abs() < 1e-3 && facing.y * pc < 0.0,
                    "{arch} seed {seed}: not facing the crossing"
                );
            }
            // The crossing corridor's width, in its arm where the person starts.
            let at = v(s.persons[0].route.first().copied().unwrap_or([p.pose[0], p.pose[1]]));
            assert!(
                frame(o, u, at).1.abs() > cw / 2.0,
                "{arch} seed {seed}: the person starts in the robot's corridor"
            );
            let across = width_across(&g, at, Vec2::new(0.0, 1.0));
            assert!((2.0 - 1e-6..=3.0 + 1e-6).contains(&across), "{arch} seed {seed}: {across}");
        }
    }
}

#[test]
fn elevators_robot_enters_past_a_person_or_leaves_after_one() {
    for (arch, entering) in [("entering_elevator", true), ("exiting_elevator", false)] {
        for seed in 0..SEEDS {
            let s = scene(arch, seed);
            let g = geometry(&s);
            let r = &s.robots[0];
            let (start, goal) = (Vec2::new(r.start[0], r.start[1]), v(r.goal));
            let (car, lobby) = if entering { (goal, start) } else { (start, goal) };
            // The car is beyond the lobby's east wall, through a door 0.9-1.1 m wide.
            assert!(car.x > lobby.x + 2.0, "{arch} seed {seed}");
            // The wall east of the lobby, on two rows 1.5 m either side of the robot's lobby end
            // (one of them misses the door; the nearer wall is the lobby's).
            let wall_x = [-1.5, 1.5]
                .iter()
                .filter_map(|dy| {
                    (0..400)
                        .map(|k| lobby.x + k as f64 * 0.02)
                        .find(|&x| g.cast_ray(Vec2::new(x, lobby.y + dy), Vec2::new(1.0, 0.0), 50.0) < 0.05)
                })
                .fold(f64::NAN, f64::min);
            assert!(
                wall_x.is_finite() && car.x > wall_x,
                "{arch} seed {seed}: the car is not beyond the wall"
            );
            let narrowest = (0..200)
                .map(|k| {
                    let y = car.y - 2.0 + 0.02 * k as f64;
                    (
                        g.cast_ray(Vec2::new(wall_x + 0.1, y), Vec2::new(0.0, 1.0), 50.0)
                            + g.cast_ray(Vec2::new(wall_x + 0.1, y), Vec2::new(0.0, -1.0), 50.0),
                        y,
                    )
                })
                .filter(|(w, y)| {
                    g.cast_ray(Vec2::new(wall_x - 0.5, *y), Vec2::new(1.0, 0.0), 50.0) > 1.0 && *w < 5.0
                })
                .map(|(w, _)| w)
                .fold(f64::INFINITY, f64::min);
            assert!((0.9 - 1e-6..=1.1 + 1e-6).contains(&narrowest), "{arch} seed {seed}: door {narrowest} m");
            let p = &s.persons[0];
            if entering {
                assert_eq!(p.behaviour, Behaviour::Standing, "{arch} seed {seed}");
                let at = Vec2::new(p.pose[0], p.pose[1]);
                assert!(
                    at.x > wall_x && (at - goal).norm() > 0.8,
                    "{arch} seed {seed}: the person is not in the car"
                );
            } else {
                let (a, end) = (v(p.route[0]), walk_end(&s));
                assert!(
                    a.x > wall_x && end.x < wall_x,
                    "{arch} seed {seed}: the person does not leave the car"
                );
                assert!((a - start).norm() < (v(p.route[0]) - goal).norm(), "{arch} seed {seed}");
            }
        }
    }
}

#[test]
fn leading_person_follows_the_robot() {
    for seed in 0..SEEDS {
        let s = scene("leading_person", seed);
        let p = &s.persons[0];
        assert_eq!(p.behaviour, Behaviour::Follower, "seed {seed}");
        assert_eq!(p.guide_robot, Some(0), "seed {seed}: not the robot's follower");
        assert!((1.2 - CM..=1.8 + CM).contains(&p.gather_radius), "seed {seed}");
        assert!(p.speed > s.robots[0].max_speed, "seed {seed}: the person cannot keep up");
    }
}

/// Every person of the traffic archetypes walks along (parallel) or across (perpendicular) the
/// robot's line, both ways in each lane.
fn lanes(arch: &str, seed: u64, along: bool) {
    let s = scene(arch, seed);
    let (o, u, len) = robot_line(&s, 0);
    assert!(s.persons.len() >= 6, "{arch} seed {seed}");
    for p in &s.persons {
        let (a, dir) = first_leg(&s, s.persons.iter().position(|q| std::ptr::eq(q, p)).unwrap_or(0));
        let c = dot(dir, u).abs();
        assert!(if along { c > 0.999 } else { c < 1e-3 }, "{arch} seed {seed}: lane direction");
        let (pa, pc) = frame(o, u, a);
        if along {
            assert!((1.0 - CM..=1.4 + CM).contains(&pc.abs()), "{arch} seed {seed}: lane {pc} m aside");
        } else {
            assert!(pa > 1.0 && pa < len, "{arch} seed {seed}: lane off the robot's way");
        }
    }
}

#[test]
fn traffic_lanes_run_along_or_across_the_robot_s_way() {
    for seed in 0..SEEDS {
        lanes("parallel_traffic", seed, true);
        lanes("perpendicular_traffic", seed, false);
    }
}

#[test]
fn circular_crossing_people_cross_the_circle_through_the_robot_s_path() {
    for seed in 0..SEEDS {
        let s = scene("circular_crossing", seed);
        let (o, u, len) = robot_line(&s, 0);
        let centre = o + u * (len / 2.0);
        assert!((4..=6).contains(&s.persons.len()), "seed {seed}");
        for (k, p) in s.persons.iter().enumerate() {
            let (a, b) = (v(p.route[0]), walk_end(&s_person(&s, k)));
            let (ra, rb) = ((a - centre).norm(), (b - centre).norm());
            assert!((3.0 - CM..=4.0 + CM).contains(&ra) && (ra - rb).abs() < 2.0 * CM, "seed {seed}");
            assert!(((a + b) * 0.5 - centre).norm() < 2.0 * CM, "seed {seed}: not across the centre");
            let (_, pc) = frame(o, u, a);
            assert!(pc.abs() > 0.3, "seed {seed}: a person starts on the robot's line");
        }
    }
}

/// A scene with only person `k` (for [`walk_end`], which reads the first person).
fn s_person(s: &Scenario, k: usize) -> Scenario {
    let mut t = s.clone();
    t.persons = vec![s.persons[k].clone()];
    t
}
