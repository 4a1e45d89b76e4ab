//! Tests of the social force model, the crowd and its scripts.

use super::scripts::Script;
use super::*;
use crate::map::geometry::Bounds;
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::map::grid::{GridSpec, OccupancyGrid};
use crate::math::Vec2;
use crate::scenario::{Behaviour, Reaction};
use crate::scenario::{Person, Randomize};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn walker(route: &[[f64; 2]], speed: f64, dwell: f64) -> Person {
    Person {
        name: "p".into(),
        behaviour: Behaviour::Walker,
        pose: [route[0][0], route[0][1], 0.0],
        route: route.to_vec(),
        speed,
        dwell,
        radius: 0.2,
        height: 1.7,
        group: None,
        reaction: Reaction::Aware,
        features: vec![],
        ..Person::default()
    }
}

#[test]
fn walkers_never_start_in_a_robot_start_area() {
    // A 10 m out-and-back route; the robot's start area covers its first 3 m (plus the
    // person's radius). Over many seeds no walker starts inside it, and without the area
    // some do (the check can fail).
    let persons = vec![walker(&[[0.0, 0.0], [10.0, 0.0]], 1.2, 0.0); 8];
    let scripts: Vec<Script> = persons.iter().map(Script::basic).collect();
    let random = Randomize { person_phase: true, speed_jitter: 0.0, robot_start_jitter: 0.0 };
    let area = [(Vec2::new(0.0, 0.0), 3.0)];
    let inside = |c: &Crowd| c.pos.iter().filter(|q| q.norm() < 3.0 + 0.2).count();
    let (mut with_area, mut without) = (0, 0);
    for seed in 0..50 {
        let spawn = |clear: &[(Vec2, f64)]| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let params = SocialForceParams::default();
            Crowd::spawn_scripted(&persons, &scripts, &random, params, clear, &mut rng)
        };
        with_area += inside(&spawn(&area));
        without += inside(&spawn(&[]));
    }
    assert_eq!(with_area, 0);
    assert!(without > 50, "{without}");
}

fn fixed() -> Randomize {
    Randomize { person_phase: false, speed_jitter: 0.0, robot_start_jitter: 0.0 }
}

fn room() -> StaticGeometry {
    // 20 x 10 m room with 0.2 m walls.
    let b = Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(21.0, 11.0) };
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
    };
    StaticGeometry::new(
        vec![
            rect(-0.2, -0.2, 20.2, 0.0),
            rect(-0.2, 10.0, 20.2, 10.2),
            rect(-0.2, 0.0, 0.0, 10.0),
            rect(20.0, 0.0, 20.2, 10.0),
        ],
        b,
    )
    .expect("valid room")
}

struct Room {
    geom: StaticGeometry,
    field: DistanceField,
}

impl Room {
    fn step(&self, c: &mut Crowd, dt: f64, robots: &[(Vec2, f64, Vec2)]) {
        c.step(dt, robots, &self.geom, &self.field);
    }
}

fn room_with_field() -> Room {
    let geom = room();
    let spec = GridSpec::covering(geom.bounds(), 0.1).expect("valid grid");
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
    Room { geom, field }
}

fn spawn(persons: &[Person]) -> Crowd {
    Crowd::spawn(persons, &fixed(), SocialForceParams::default(), &mut ChaCha8Rng::seed_from_u64(0))
}

#[test]
fn moussaid_known_answers() {
    // Moussaid et al. 2009's interaction force with A = 4.5, the worked example of the social
    // force model in `docs/algorithms.md`.
    // The published parameters (the defaults are calibrated on recordings).
    let p = SocialForceParams {
        cutoff: 10.0,
        strength: 4.5,
        gamma: 0.35,
        lambda: 2.0,
        n: 2.0,
        n_prime: 3.0,
        ..SocialForceParams::default()
    };
    let f =
        interaction_force(Vec2::zeros(), Vec2::new(1.3, 0.0), Vec2::new(2.0, 0.0), Vec2::new(-1.3, 0.0), &p);
    assert!((f.x + 1.7904).abs() < 1e-4, "{f:?}");
    // exact symmetry: the passing convention adds a push to the right (negative y)
    assert!(f.y < 0.0);
    let f =
        interaction_force(Vec2::zeros(), Vec2::new(1.3, 0.0), Vec2::new(2.0, 0.3), Vec2::new(-1.3, 0.0), &p);
    assert!((f.x + 0.8832).abs() < 1e-4 && (f.y + 1.3415).abs() < 1e-4, "{f:?}");
    let f = interaction_force(Vec2::zeros(), Vec2::new(1.3, 0.0), Vec2::new(1.0, 0.0), Vec2::zeros(), &p);
    assert!((f.x + 2.0349).abs() < 1e-4, "{f:?}");
}

#[test]
fn lone_walker_relaxes_to_its_speed() {
    let room = room_with_field();
    let mut c = spawn(&[walker(&[[2.0, 5.0], [18.0, 5.0]], 1.2, 0.0)]);
    room.step(&mut c, 0.5, &[]);
    let v = c.vel[0].norm();
    // v(t) = v0 (1 - exp(-t / tau)) up to the Euler discretisation
    let want = 1.2 * (1.0 - (-1.0f64).exp());
    assert!((v - want).abs() < 0.05, "{v} vs {want}");
    room.step(&mut c, 3.0, &[]);
    assert!((c.vel[0].norm() - 1.2).abs() < 0.01);
    assert!((c.heading[0]).abs() < 1e-6);
}

#[test]
fn walkers_follow_their_routes_and_dwell() {
    let room = room_with_field();
    let mut c = spawn(&[walker(&[[2.0, 2.0], [8.0, 2.0], [8.0, 8.0]], 1.0, 3.0)]);
    let mut reached_second = false;
    let mut dwelt = 0;
    for _ in 0..400 {
        room.step(&mut c, 0.1, &[]);
        if (c.pos[0] - Vec2::new(8.0, 2.0)).norm() < 0.35 {
            reached_second = true;
            if c.vel[0].norm() < 1e-9 {
                dwelt += 1;
            }
        }
    }
    assert!(reached_second);
    assert!(dwelt >= 20, "dwelt {dwelt} steps");
}

#[test]
fn walkers_dwell_only_at_their_stops() {
    let room = room_with_field();
    let mut w = walker(&[[2.0, 2.0], [8.0, 2.0], [8.0, 8.0]], 1.0, 3.0);
    w.stops = vec![false, false, true];
    let mut c = spawn(&[w]);
    let (mut still_at_corner, mut still_at_stop) = (0, 0);
    for _ in 0..400 {
        room.step(&mut c, 0.1, &[]);
        let still = c.vel[0].norm() < 1e-9;
        if still && (c.pos[0] - Vec2::new(8.0, 2.0)).norm() < 0.35 {
            still_at_corner += 1;
        }
        if still && (c.pos[0] - Vec2::new(8.0, 8.0)).norm() < 0.35 {
            still_at_stop += 1;
        }
    }
    assert_eq!(still_at_corner, 0, "dwelt at a waypoint that is not a stop");
    assert!(still_at_stop >= 20, "dwelt {still_at_stop} steps at the stop");
}

#[test]
fn nobody_enters_the_walls_in_a_crowded_long_run() {
    let room = room_with_field();
    let mut persons = Vec::new();
    for k in 0..30 {
        let y = 0.5 + (k % 10) as f64 * 0.9;
        let (a, b) = if k % 2 == 0 { ([1.0, y], [19.0, 9.5 - y]) } else { ([19.0, y], [1.0, 9.5 - y]) };
        persons.push(walker(&[a, b], 1.0 + 0.01 * k as f64, 0.0));
    }
    let mut c = Crowd::spawn(
        &persons,
        &Randomize::default(),
        SocialForceParams::default(),
        &mut ChaCha8Rng::seed_from_u64(3),
    );
    for _ in 0..1200 {
        room.step(&mut c, 0.1, &[]);
        for (i, q) in c.pos.iter().enumerate() {
            assert!(!room.geom.contains(*q), "person {i} inside the walls at {q:?}");
            assert!(room.geom.distance(*q) >= 0.5 * c.radius[i] - 1e-9);
        }
    }
}

/// Known failure under the calibrated defaults (strength 2.0, gamma 0.27, n' 4.5, fitted on the
/// UCY recordings): the two walkers' centres come to 0.392 m, 0.008 m inside the sum of their
/// radii (0.4 m), though they still pass on their right. Kept as a strict expected failure:
/// `should_panic` fails the moment they stop touching.
#[test]
#[should_panic(expected = "they collided")]
fn head_on_walkers_pass_on_their_right() {
    let room = room_with_field();
    let mut c =
        spawn(&[walker(&[[2.0, 5.0], [18.0, 5.0]], 1.2, 0.0), walker(&[[18.0, 5.0], [2.0, 5.0]], 1.2, 0.0)]);
    let mut min_d = f64::INFINITY;
    for _ in 0..80 {
        room.step(&mut c, 0.1, &[]);
        min_d = min_d.min((c.pos[0] - c.pos[1]).norm());
    }
    assert!(min_d > 0.4, "they collided: {min_d}");
    // walker 0 heads +x: its right is -y; walker 1 heads -x: its right is +y.
    assert!(c.pos[0].y < 5.0 && c.pos[1].y > 5.0, "{:?}", c.pos);
}

#[test]
fn aware_walker_goes_around_a_standing_robot_and_oblivious_does_not_avoid_it() {
    let room = room_with_field();
    let robot = [(Vec2::new(8.0, 5.0), 0.24, Vec2::zeros())];
    let mut p = walker(&[[2.0, 5.0], [16.0, 5.0]], 1.0, 0.0);
    let mut c = spawn(std::slice::from_ref(&p));
    let mut min_gap = f64::INFINITY;
    for _ in 0..200 {
        room.step(&mut c, 0.1, &robot);
        min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
    }
    assert!(min_gap >= ReactionParams::default().hard_gap - 1e-9, "gap {min_gap}");
    assert!(c.pos[0].x > 10.0, "stuck behind the robot at {:?}", c.pos[0]);
    p.reaction = Reaction::Ignore;
    let mut c = spawn(&[p]);
    let mut min_gap = f64::INFINITY;
    for _ in 0..200 {
        room.step(&mut c, 0.1, &robot);
        min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
    }
    assert!(min_gap < 0.0);
}

#[test]
fn walking_group_stays_together() {
    let room = room_with_field();
    let mut a = walker(&[[2.0, 4.5], [18.0, 4.5]], 1.0, 0.0);
    let mut b = walker(&[[2.0, 5.5], [18.0, 5.5]], 1.2, 0.0);
    a.group = Some(1);
    b.group = Some(1);
    let mut c = spawn(&[a, b]);
    for _ in 0..100 {
        room.step(&mut c, 0.1, &[]);
        assert!((c.pos[0] - c.pos[1]).norm() < 2.0);
    }
}

#[test]
fn same_seed_same_crowd_bit_for_bit() {
    let room = room_with_field();
    let persons: Vec<Person> =
        (0..12).map(|k| walker(&[[1.0 + k as f64, 1.0], [18.0 - k as f64, 9.0]], 1.0, 1.0)).collect();
    let run = |seed| {
        let mut c = Crowd::spawn(
            &persons,
            &Randomize::default(),
            SocialForceParams::default(),
            &mut ChaCha8Rng::seed_from_u64(seed),
        );
        for _ in 0..300 {
            room.step(&mut c, 0.1, &[]);
        }
        c.pos.iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect::<Vec<u64>>()
    };
    assert_eq!(run(4), run(4));
    assert_ne!(run(4), run(5));
}

#[test]
fn standing_person_stays() {
    let room = room_with_field();
    let p = Person {
        name: "s".into(),
        behaviour: Behaviour::Standing,
        pose: [3.0, 2.0, 1.0],
        route: vec![],
        speed: 1.0,
        dwell: 0.0,
        radius: 0.2,
        height: 1.7,
        group: None,
        reaction: Reaction::Aware,
        features: vec![],
        ..Person::default()
    };
    let mut c = spawn(&[p]);
    room.step(&mut c, 1.0, &[]);
    assert_eq!(c.pos[0], Vec2::new(3.0, 2.0));
    assert_eq!(c.heading[0], 1.0);
}

/// A standing person of radius 0.2 m at `at`, facing +x, aware of robots.
fn standing_aware(at: Vec2) -> Person {
    Person {
        name: "s".into(),
        behaviour: Behaviour::Standing,
        pose: [at.x, at.y, 0.0],
        radius: 0.2,
        reaction: Reaction::Aware,
        ..Person::default()
    }
}

#[test]
fn a_standing_person_steps_aside_for_a_passing_robot_in_the_open_but_stays_put_in_a_corner() {
    // A robot passes 0.65 m below a standing person at 0.5 m/s, along x. In the open the person
    // shifts up, out of its way; 0.45 m from two walls (the back corner of an elevator car) a
    // shift would be pushed back off the walls, toward the robot, so the person stays put.
    let room = room_with_field();
    let pass = |at: Vec2| {
        let mut c = spawn(&[standing_aware(at)]);
        let v = Vec2::new(0.5, 0.0);
        let mut robot = [(Vec2::new(at.x - 2.5, at.y - 0.65), 0.24, v)];
        let (mut min_gap, mut still_gap) = (f64::INFINITY, f64::INFINITY);
        for _ in 0..60 {
            room.step(&mut c, 0.1, &robot);
            robot[0].0 += v * 0.1;
            min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
            still_gap = still_gap.min((at - robot[0].0).norm() - 0.44);
        }
        (c.pos[0], min_gap, still_gap)
    };
    let (_, min_gap, still_gap) = pass(Vec2::new(10.0, 5.0));
    assert!(min_gap > still_gap + 0.05, "shifted aside: gap {min_gap} against {still_gap} standing");
    let corner = Vec2::new(20.0 - 0.45, 10.0 - 0.45);
    let (end, min_gap, still_gap) = pass(corner);
    assert!((end - corner).norm() < 1e-9, "moved from the corner to {end:?}");
    assert!(min_gap >= still_gap - 1e-9, "gap {min_gap} against {still_gap} standing");
}

#[test]
fn a_standing_person_makes_room_for_a_robot_waiting_at_the_edge_of_their_intimate_zone() {
    // A robot that keeps out of people's intimate zones (0.45 m body gap) stops at its edge when
    // a standing person blocks its way. Standing still 0.5 m from the person (inside
    // `waiting_gap`, outside the intimate zone) it is stepped away from, to about that gap (the
    // person goes back toward its place once the robot is out of reach); at 0.6 m it is not.
    let room = room_with_field();
    let wait = |gap: f64| {
        let mut c = spawn(&[standing_aware(Vec2::new(10.0, 5.0))]);
        let robot = [(Vec2::new(10.0 - 0.44 - gap, 5.0), 0.24, Vec2::zeros())];
        for _ in 0..20 {
            room.step(&mut c, 0.1, &robot);
        }
        c.pos[0].x - 10.0
    };
    let rp = ReactionParams::default();
    assert!(rp.hard_gap < 0.5 && 0.5 < rp.waiting_gap && rp.waiting_gap < 0.6);
    let moved = wait(0.5);
    assert!(
        moved > 0.03 && 0.5 + moved > rp.waiting_gap - 0.02,
        "stepped back {moved} m from a robot waiting 0.5 m away"
    );
    assert_eq!(wait(0.6), 0.0);
}

#[test]
fn a_walker_dwelling_at_a_stop_makes_room_as_standing_people_do() {
    // A walker stops 1 m down its route for a long dwell (a script plans that as a walk at zero
    // speed); a robot then waits 0.5 m behind it. Dwelling, it stands still, and steps back
    // from the robot as a standing person does (it once stayed put: Francis `robot_overtaking`
    // timed out in the narrowest halls).
    let room = room_with_field();
    let p = walker(&[[9.0, 5.0], [10.0, 5.0]], 0.5, 600.0);
    let mut c = spawn(&[p]);
    for _ in 0..60 {
        room.step(&mut c, 0.1, &[]);
    }
    let stop = c.pos[0];
    assert!((stop - Vec2::new(10.0, 5.0)).norm() < 0.2, "not at its stop: {stop:?}");
    assert!(c.dwell_left[0] > 0.0);
    let robot = [(stop - Vec2::new(0.44 + 0.5, 0.0), 0.24, Vec2::zeros())];
    for _ in 0..20 {
        room.step(&mut c, 0.1, &robot);
    }
    let moved = c.pos[0].x - stop.x;
    assert!(moved > 0.03, "stepped back {moved} m from a robot waiting 0.5 m behind it");
}

#[test]
fn random_phase_is_on_the_route_and_seeded() {
    let p = walker(&[[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]], 1.0, 0.0);
    let r = Randomize::default();
    let sp = SocialForceParams::default();
    let a = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(7));
    let b = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(7));
    let c = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(8));
    assert_eq!(a.pos, b.pos);
    assert_ne!(a.pos, c.pos);
    let q = a.pos[0];
    let on = (q.y.abs() < 1e-9 && (0.0..=4.0).contains(&q.x))
        || ((q.x - 4.0).abs() < 1e-9 && (0.0..=3.0).contains(&q.y))
        || ((q.y - 0.75 * q.x).abs() < 1e-9);
    assert!(on, "{q:?}");
}

/// A hallway 12 m long and `width` wide (0.2 m walls), with its distance field.
fn hallway(width: f64) -> Room {
    let b = Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(13.0, width + 1.0) };
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
    };
    let geom = StaticGeometry::new(
        vec![
            rect(-0.2, -0.2, 12.2, 0.0),
            rect(-0.2, width, 12.2, width + 0.2),
            rect(-0.2, 0.0, 0.0, width),
            rect(12.0, 0.0, 12.2, width),
        ],
        b,
    )
    .expect("valid hallway");
    let spec = GridSpec::covering(geom.bounds(), 0.1).expect("valid grid");
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
    Room { geom, field }
}

#[test]
fn a_walker_squeezes_past_a_robot_waiting_at_the_wall_of_a_narrow_hallway_but_not_one_coming_on() {
    // 1.3 m wide: beside a robot 5 cm off the wall there are 0.77 m, 0.185 m on each side of a
    // 0.4 m body, so no way at the hard gap (0.45 m).
    let room = hallway(1.3);
    let rp = ReactionParams::default();
    let c0 = Vec2::new(6.0, 1.3 - 0.05 - 0.24);
    let walk = |v: Vec2, steps: usize| {
        let mut c = spawn(&[walker(&[[1.0, 0.65], [11.0, 0.65]], 1.0, 0.0)]);
        let (mut min_gap, mut far) = (f64::INFINITY, 0.0_f64);
        let mut robot = [(c0, 0.24, v)];
        for _ in 0..steps {
            room.step(&mut c, 0.1, &robot);
            robot[0].0 += v * 0.1;
            min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
            far = far.max(c.pos[0].x);
        }
        (far, min_gap)
    };
    // It walks to x = 11 and back: how far it got is what counts.
    let (far, min_gap) = walk(Vec2::zeros(), 200);
    assert!(far > 10.0, "stuck behind the robot at x = {far}");
    let half = 0.5 * (0.5 * (0.77 - 0.4));
    assert!(min_gap < rp.hard_gap && min_gap >= half - 1e-9, "gap {min_gap}");
    // The robot creeping toward the person (0.1 m/s, above `squeeze_approach`): the person
    // keeps its hard gap and does not get past.
    let (far, min_gap) = walk(Vec2::new(-0.1, 0.0), 60);
    assert!(min_gap >= rp.hard_gap - 1e-9, "gap {min_gap}");
    assert!(far < 6.0, "got past to x = {far}");
}
