//! Tests of Social Momentum (the disc model and its steps).

use super::collision::segment_segment_distance;
use super::*;
use crate::control::clamp_norm;
use crate::control::orca::nonholonomic::TrackingBound;
use crate::map::Bounds;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const DT: f64 = 0.1;
const R: f64 = 0.3;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

fn person(pos: Vec2, vel: Vec2) -> Agent {
    Agent { pos, vel, radius: 0.3, weight: 1.0, comfort: 0.0 }
}

fn step(pos: Vec2, vel: Vec2, goal: Vec2, others: &[Agent], params: &SocialMomentumParams) -> Option<Vec2> {
    social_momentum(pos, vel, R, goal, others, None, &Limits::PEPPER, DT, params)
}

fn check_limits(out: Vec2, vel: Vec2, l: &Limits, dt: f64) {
    assert!(out.norm() <= l.max_speed + 1e-12, "speed {} > {}", out.norm(), l.max_speed);
    assert!((out - vel).norm() <= l.max_accel * dt + 1e-12, "accel {:?} from {:?}", out, vel);
}

#[test]
fn angular_momentum_known_answers() {
    let l = angular_momentum(v(0.0, 0.0), v(1.0, 0.0), v(4.0, 1.0), v(-1.0, 0.0));
    assert!((l - 1.0).abs() < 1e-12, "{l}");
    assert_eq!(angular_momentum(v(0.0, 0.0), v(1.0, 0.0), v(4.0, 0.0), v(-1.0, 0.0)), 0.0);
    // Midpoint form of design §2.2 gives the same value.
    let (pr, vr, pi, vi) = (v(0.3, -1.2), v(0.4, 0.1), v(2.5, 0.7), v(-0.8, 0.3));
    let c = (pr + pi) * 0.5;
    let mid = cross(pr - c, vr) + cross(pi - c, vi);
    assert!((angular_momentum(pr, vr, pi, vi) - mid).abs() < 1e-12);
    // Translation invariance.
    let s = v(10.0, -7.0);
    assert!((angular_momentum(pr + s, vr, pi + s, vi) - mid).abs() < 1e-12);
    // Mirroring across x flips the sign.
    let m = |a: Vec2| v(a.x, -a.y);
    assert!((angular_momentum(m(pr), m(vr), m(pi), m(vi)) + mid).abs() < 1e-12);
}

#[test]
fn alone_it_heads_straight_to_the_goal_at_max_speed() {
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let goal = v(20.0, 5.0);
    let dir = goal.normalize();
    let (mut pos, mut vel) = (Vec2::zeros(), Vec2::zeros());
    for k in 0..40 {
        let out = step(pos, vel, goal, &[], &p).expect("free space");
        check_limits(out, vel, &l, DT);
        let expected = (l.max_accel * DT * (k + 1) as f64).min(l.max_speed);
        assert!((out.norm() - expected).abs() < 1e-9, "step {k}: {} vs {expected}", out.norm());
        assert!((out.normalize() - dir).norm() < 1e-9, "step {k}: direction {out:?}");
        vel = out;
        pos += vel * DT;
    }
    assert!((vel.norm() - l.max_speed).abs() < 1e-12);
}

/// Head-on encounter with a scripted person walking straight at the robot; returns the robot's
/// trajectory and the minimum centre distance.
fn head_on(params: &SocialMomentumParams, mirror: bool) -> (Vec<Vec2>, f64) {
    let sy = if mirror { -1.0 } else { 1.0 };
    let (mut pos, mut vel) = (Vec2::zeros(), v(0.55, 0.0));
    let mut ped = v(8.0, 0.0);
    let ped_vel = v(-1.0, 0.0);
    let mut traj = vec![pos];
    let mut min_d = f64::INFINITY;
    for _ in 0..120 {
        // Partial goal: 2 m ahead on the global path y = 0.
        let goal = v(pos.x + 2.0, 0.0);
        let others = [person(v(ped.x, sy * ped.y), ped_vel)];
        // None: stop, through the limits like any command.
        let out = step(pos, vel, goal, &others, params)
            .unwrap_or_else(|| Limits::PEPPER.apply(Vec2::zeros(), 0.0, vel, 0.0, DT).0);
        check_limits(out, vel, &Limits::PEPPER, DT);
        vel = out;
        pos += vel * DT;
        ped += ped_vel * DT;
        min_d = min_d.min((pos - ped).norm());
        traj.push(pos);
    }
    (traj, min_d)
}

#[test]
fn inside_a_persons_bound_it_backs_out_instead_of_waiting() {
    // A person standing 0.5 m ahead, between the robot and its goal: closer than the bound
    // (0.3 + 0.3 + 0.1 = 0.7 m). The robot opens the gap rather than stopping there.
    let p = SocialMomentumParams::default();
    let ped = person(v(0.5, 0.0), Vec2::zeros());
    let mut pos = Vec2::zeros();
    let mut vel = Vec2::zeros();
    for _ in 0..30 {
        let out = step(pos, vel, v(5.0, 0.0), &[ped], &p).expect("a way out");
        check_limits(out, vel, &Limits::PEPPER, DT);
        vel = out;
        pos += vel * DT;
    }
    assert!((pos - ped.pos).norm() >= 0.7, "still inside the bound at {pos:?}");
}

#[test]
fn head_on_it_passes_on_the_right_deterministically() {
    let p = SocialMomentumParams::default();
    let (traj, min_d) = head_on(&p, false);
    let (traj2, _) = head_on(&p, false);
    assert_eq!(traj, traj2, "not deterministic");
    let min_y = traj.iter().map(|q| q.y).fold(f64::INFINITY, f64::min);
    let max_y = traj.iter().map(|q| q.y).fold(f64::NEG_INFINITY, f64::max);
    assert!(min_y < -0.2, "did not move right: min y {min_y}");
    assert!(max_y < 1e-9, "moved left: max y {max_y}");
    assert!(min_d >= 0.6 - 1e-9, "collided: {min_d}");
    // It kept going: the robot is past the person and back near the path.
    let end = traj[traj.len() - 1];
    assert!(end.x > 4.0, "stalled at {end:?}");
}

#[test]
fn mirrored_scene_gives_mirrored_action() {
    let m = |a: Vec2| v(a.x, -a.y);
    let p = SocialMomentumParams::default();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut compared = 0;
    for _ in 0..100 {
        let vel = v(rng.random_range(-0.4..0.55), rng.random_range(-0.3..0.3));
        let goal = v(rng.random_range(2.0..5.0), rng.random_range(-2.0..2.0));
        let others: Vec<Agent> = (0..3)
            .map(|_| {
                person(
                    v(rng.random_range(1.0..4.0), rng.random_range(-2.0..2.0)),
                    v(rng.random_range(-1.0..0.5), rng.random_range(-0.5..0.5)),
                )
            })
            .collect();
        let mirrored: Vec<Agent> =
            others.iter().map(|a| Agent { pos: m(a.pos), vel: m(a.vel), ..*a }).collect();
        // Skip scenes where a person's rotation sense is undecided (the convention breaks the
        // mirror symmetry there on purpose).
        if others.iter().any(|a| angular_momentum(Vec2::zeros(), vel, a.pos, a.vel).abs() < 0.1) {
            continue;
        }
        let a = step(Vec2::zeros(), vel, goal, &others, &p);
        let b = step(Vec2::zeros(), m(vel), m(goal), &mirrored, &p);
        match (a, b) {
            (Some(a), Some(b)) => {
                assert!((m(a) - b).norm() < 1e-9, "{a:?} vs mirrored {b:?}");
                compared += 1;
            }
            (None, None) => {}
            _ => panic!("one side stopped: {a:?} {b:?}"),
        }
    }
    assert!(compared > 20, "{compared}");
}

#[test]
fn crossing_from_the_left_keeps_its_rotation_sense_and_arrives() {
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let goal = v(8.0, 0.0);
    let (mut pos, mut vel) = (Vec2::zeros(), Vec2::zeros());
    let mut ped = v(3.5, 3.5);
    let ped_vel = v(0.0, -0.8);
    let mut sign = 0.0;
    let mut min_d = f64::INFINITY;
    for _ in 0..400 {
        let partial = pos + clamp_norm(goal - pos, 2.0);
        let others = [person(ped, ped_vel)];
        let out = step(pos, vel, partial, &others, &p)
            .unwrap_or_else(|| l.apply(Vec2::zeros(), 0.0, vel, 0.0, DT).0);
        check_limits(out, vel, &l, DT);
        let lm = angular_momentum(pos, out, ped, ped_vel);
        let ahead = (ped - pos).dot(&out) > 0.0 && (ped - pos).norm() < p.sensing_range;
        if ahead && lm.abs() >= p.min_momentum {
            if sign == 0.0 {
                sign = lm.signum();
            }
            assert_eq!(lm.signum(), sign, "switched sides at {pos:?}, person {ped:?}");
        }
        vel = out;
        pos += vel * DT;
        ped += ped_vel * DT;
        min_d = min_d.min((pos - ped).norm());
    }
    assert!(sign != 0.0);
    assert!(min_d >= 0.6, "collided: {min_d}");
    assert!((pos - goal).norm() < 0.1, "did not arrive: {pos:?}");
}

#[test]
fn passing_side_follows_rotation_already_under_way() {
    // The person is offset to the robot's right (y = -0.5) and the pass is already clockwise
    // (L < 0, robot passing on the left): Social Momentum keeps that sense rather than
    // crossing in front of the person.
    let p = SocialMomentumParams::default();
    let pos = Vec2::zeros();
    let vel = v(0.55, 0.0);
    let others = [person(v(3.0, -0.5), v(-1.0, 0.0))];
    let l = angular_momentum(pos, vel, others[0].pos, others[0].vel);
    assert!(l < -p.min_momentum, "{l}");
    let out = step(pos, vel, v(5.0, 0.0), &others, &p).expect("free");
    assert!(angular_momentum(pos, out, others[0].pos, others[0].vel) < 0.0);
    assert!(out.y >= 0.0, "{out:?}");
}

#[test]
fn lambda_increases_the_momentum_terms_influence() {
    let pos = Vec2::zeros();
    let vel = v(0.5, 0.0);
    let goal = v(5.0, 0.0);
    let others = [person(v(3.0, 0.4), v(-0.8, 0.0))];
    let sm_of = |out: Vec2| angular_momentum(pos, out, others[0].pos, others[0].vel);
    let mut last: Option<(Vec2, f64)> = None;
    for lambda in [0.0, 0.3, 3.0] {
        let p = SocialMomentumParams { lambda, ..Default::default() };
        let out = step(pos, vel, goal, &others, &p).expect("free");
        let sm = sm_of(out);
        if let Some((prev, prev_sm)) = last {
            assert!(sm >= prev_sm - 1e-12, "lambda {lambda}: {sm} < {prev_sm}");
            if lambda == 3.0 {
                assert!((out - prev).norm() > 1e-3, "no measurable change: {out:?} vs {prev:?}");
            }
        }
        last = Some((out, sm));
    }
    // λ = 0 is the pure-efficiency choice: straight at the goal.
    let p0 = SocialMomentumParams { lambda: 0.0, ..Default::default() };
    let out0 = step(pos, vel, goal, &others, &p0).expect("free");
    assert!((out0 - v(0.55, 0.0)).norm() < 1e-12, "{out0:?}");
}

#[test]
fn never_exceeds_speed_or_acceleration() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let p = SocialMomentumParams::default();
    for _ in 0..300 {
        let l = Limits {
            max_speed: rng.random_range(0.1..1.5),
            max_angular_speed: 2.0,
            max_accel: rng.random_range(0.1..3.0),
            max_angular_accel: 3.0,
        };
        let dt = rng.random_range(0.02..0.5);
        let speed = rng.random_range(0.0..l.max_speed);
        let ang: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let vel = v(ang.cos(), ang.sin()) * speed;
        let goal = v(rng.random_range(-5.0..5.0), rng.random_range(-5.0..5.0));
        let others: Vec<Agent> = (0..rng.random_range(0..6))
            .map(|_| {
                person(
                    v(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0)),
                    v(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)),
                )
            })
            .collect();
        if let Some(out) = social_momentum(Vec2::zeros(), vel, R, goal, &others, None, &l, dt, &p) {
            check_limits(out, vel, &l, dt);
        }
    }
    // A current velocity above the limit: the speed bound wins, decelerating at most a*dt.
    let l = Limits::PEPPER;
    let out =
        social_momentum(Vec2::zeros(), v(0.6, 0.0), R, v(5.0, 0.0), &[], None, &l, DT, &p).expect("free");
    check_limits(out, v(0.6, 0.0), &l, DT);
    let out =
        social_momentum(Vec2::zeros(), v(2.0, 0.0), R, v(5.0, 0.0), &[], None, &l, DT, &p).expect("free");
    assert!(out.norm() <= l.max_speed + 1e-12, "{out:?}");
}

#[test]
fn boxed_in_returns_none() {
    // Eight people on a 1.2 m ring walking straight at the robot.
    let others: Vec<Agent> = (0..8)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 8.0;
            let u = v(a.cos(), a.sin());
            person(u * 1.2, -u * 1.0)
        })
        .collect();
    let p = SocialMomentumParams::default();
    assert_eq!(step(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &others, &p), None);
    // One person farther away leaves room to side-step.
    let one = [person(v(2.5, 0.0), v(-1.0, 0.0))];
    assert!(step(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &one, &p).is_some());
}

fn room() -> StaticGeometry {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| vec![v(x0, y0), v(x1, y0), v(x1, y1), v(x0, y1)];
    let polys = vec![
        rect(-5.0, -5.0, 5.0, -4.8),
        rect(-5.0, 4.8, 5.0, 5.0),
        rect(-5.0, -5.0, -4.8, 5.0),
        rect(4.8, -5.0, 5.0, 5.0),
        rect(1.0, -1.0, 1.5, 3.0),
        rect(-2.0, -3.0, 0.0, -2.5),
    ];
    let bounds = Bounds { min: v(-5.0, -5.0), max: v(5.0, 5.0) };
    match StaticGeometry::new(polys, bounds) {
        Ok(g) => g,
        Err(e) => panic!("{e}"),
    }
}

/// Six people at random in the room (walking up to 1.2 m/s each way), those within `bound` plus
/// their radius of `pos` left out.
fn six_people_clear_of(rng: &mut ChaCha8Rng, pos: Vec2, bound: f64) -> Vec<Agent> {
    (0..6)
        .map(|_| {
            person(
                v(rng.random_range(-4.5..4.5), rng.random_range(-4.5..4.5)),
                v(rng.random_range(-1.2..1.2), rng.random_range(-1.2..1.2)),
            )
        })
        .filter(|a| (a.pos - pos).norm() >= bound + a.radius)
        .collect()
}

/// Moving at `out` from `pos` over `horizon` keeps `bound` (the robot's radius and margin) plus
/// each person's radius from everyone and `bound` from the walls: dense time sampling,
/// independent of the filter's closed form.
fn assert_clear_over_horizon(
    pos: Vec2,
    out: Vec2,
    others: &[Agent],
    geom: &StaticGeometry,
    bound: f64,
    horizon: f64,
) {
    for k in 0..=400 {
        let t = horizon * k as f64 / 400.0;
        let q = pos + out * t;
        for a in others {
            let d = (q - (a.pos + a.vel * t)).norm();
            assert!(d >= bound + a.radius - 1e-9, "person within {d} m at t={t}");
        }
        assert!(geom.distance(q) >= bound - 1e-9, "wall at t={t}");
    }
}

#[test]
fn chosen_samples_never_collide_within_the_horizon() {
    let geom = room();
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut checked = 0;
    let mut stopped = 0;
    for _ in 0..400 {
        let pos = v(rng.random_range(-4.3..4.3), rng.random_range(-4.3..4.3));
        if geom.distance(pos) < R + p.safety_margin || geom.contains(pos) {
            continue;
        }
        let ang: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let vel = v(ang.cos(), ang.sin()) * rng.random_range(0.0..0.55);
        let goal = v(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0));
        let others = six_people_clear_of(&mut rng, pos, R + p.safety_margin);
        match social_momentum(pos, vel, R, goal, &others, Some(&geom), &l, DT, &p) {
            None => stopped += 1,
            Some(out) => {
                checked += 1;
                assert_clear_over_horizon(pos, out, &others, &geom, R + p.safety_margin, p.horizon);
            }
        }
    }
    assert!(checked > 100, "only {checked} checked ({stopped} stopped)");
}

#[test]
fn inside_a_margin_it_can_back_away() {
    let geom = room();
    let p = SocialMomentumParams::default();
    // 0.32 m from the wall face at x = 1.0 (bound 0.4), goal straight through the wall.
    let pos = v(0.68, 1.0);
    let out = social_momentum(pos, Vec2::zeros(), R, v(3.0, 1.0), &[], Some(&geom), &Limits::PEPPER, DT, &p)
        .expect("can move away or along");
    assert!(out.x <= 1e-12, "{out:?}");
}

#[test]
fn nan_inputs_stop_the_robot() {
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let nan = f64::NAN;
    let ok = person(v(3.0, 0.0), v(-1.0, 0.0));
    let call =
        |pos: Vec2,
         vel: Vec2,
         goal: Vec2,
         others: &[Agent],
         l: &Limits,
         dt: f64,
         p: &SocialMomentumParams| { social_momentum(pos, vel, R, goal, others, None, l, dt, p) };
    assert!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, DT, &p).is_some());
    assert_eq!(call(v(nan, 0.0), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, DT, &p), None);
    assert_eq!(call(Vec2::zeros(), v(0.0, nan), v(5.0, 0.0), &[ok], &l, DT, &p), None);
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(f64::INFINITY, 0.0), &[ok], &l, DT, &p), None);
    let bad = Agent { pos: v(nan, 1.0), ..ok };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok, bad], &l, DT, &p), None);
    let bad = Agent { vel: v(1.0, f64::INFINITY), ..ok };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[bad], &l, DT, &p), None);
    let bad = Agent { radius: nan, ..ok };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[bad], &l, DT, &p), None);
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, nan, &p), None);
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, 0.0, &p), None);
    let bl = Limits { max_speed: nan, ..l };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &bl, DT, &p), None);
    let bp = SocialMomentumParams { lambda: nan, ..p };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, DT, &bp), None);
    let bp = SocialMomentumParams { horizon: f64::INFINITY, ..p };
    assert_eq!(call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[ok], &l, DT, &bp), None);
    assert_eq!(
        social_momentum(Vec2::zeros(), Vec2::zeros(), nan, v(5.0, 0.0), &[ok], None, &l, DT, &p),
        None
    );
    // An infinite acceleration limit is allowed and stays finite.
    let il = Limits { max_accel: f64::INFINITY, ..l };
    let out = call(Vec2::zeros(), Vec2::zeros(), v(5.0, 0.0), &[], &il, DT, &p).expect("free");
    assert!((out - v(0.55, 0.0)).norm() < 1e-12, "{out:?}");
    // A goal on the robot, and degenerate action sets, still give finite answers.
    let g0 = SocialMomentumParams { n_speeds: 0, n_headings: 0, ..p };
    let out = call(Vec2::zeros(), v(0.2, 0.0), Vec2::zeros(), &[ok], &l, DT, &g0).expect("free");
    assert!(out.x.is_finite() && out.y.is_finite());
}

#[test]
fn inside_an_obstacle_stops() {
    let geom = room();
    let p = SocialMomentumParams::default();
    let out = social_momentum(
        v(1.2, 0.0),
        Vec2::zeros(),
        R,
        v(3.0, 0.0),
        &[],
        Some(&geom),
        &Limits::PEPPER,
        DT,
        &p,
    );
    assert_eq!(out, None);
}

/// Random people around the origin (some standing, some walking, comfort zones of 0-1.5 m).
fn random_crowd(rng: &mut ChaCha8Rng, n: usize) -> Vec<Agent> {
    (0..n)
        .map(|_| Agent {
            pos: v(rng.random_range(-8.0..8.0), rng.random_range(-8.0..8.0)),
            vel: v(rng.random_range(-1.3..1.3), rng.random_range(-1.3..1.3)),
            radius: rng.random_range(0.0..0.4),
            weight: 1.0,
            comfort: if rng.random_bool(0.2) { 0.0 } else { rng.random_range(0.3..1.5) },
        })
        .collect()
}

#[test]
fn the_comfort_candidates_give_the_full_sum_bit_for_bit() {
    // The straightforward intrusion: every agent of the comfort term at every instant, no term
    // skipped. The per-instant candidate lists must leave the sum unchanged, bit for bit.
    let reference = |c: &Comfort, v: Vec2| -> f64 {
        let dv0 = v - c.vel;
        let turn = if dv0.norm() > 1e-9 { dv0 / dv0.norm() } else { Vec2::zeros() };
        let h = c.horizon / COMFORT_SAMPLES as f64;
        let (mut q, mut sum) = (Vec2::zeros(), 0.0);
        for k in 0..COMFORT_SAMPLES {
            let t = (k as f64 + 1.0) * h;
            let mut w = clamp_norm(v + turn * c.accel * (t - c.dt).max(0.0), c.vmax);
            w -= c.goal_dir * w.dot(&c.goal_dir).min(0.0);
            q += w * h;
            for a in &c.agents {
                sum += (a.r - (a.d0 + q - a.vel * t).norm()).max(0.0);
            }
        }
        sum / COMFORT_SAMPLES as f64
    };
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    let (mut nonzero, mut skipped) = (0, 0);
    for _ in 0..300 {
        let vel = v(rng.random_range(-0.4..0.4), rng.random_range(-0.4..0.4));
        let goal_dir = {
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            v(a.cos(), a.sin())
        };
        let n = rng.random_range(0..40);
        let others = random_crowd(&mut rng, n);
        let c = Comfort::new(Vec2::zeros(), vel, goal_dir, &others, &l, DT, &p);
        skipped += c.agents.len() * COMFORT_SAMPLES - c.candidates.iter().map(Vec::len).sum::<usize>();
        for s in action_set(vel, goal_dir * 2.0, goal_dir, l.max_accel * DT, l.max_speed, &p) {
            let (fast, slow) = (c.intrusion(s), reference(&c, s));
            assert_eq!(fast.to_bits(), slow.to_bits(), "sample {s:?}: {fast} vs {slow}");
            nonzero += usize::from(slow > 0.0);
        }
    }
    // The check means something: intrusions happen, and terms are skipped.
    assert!(nonzero > 1000 && skipped > 1000, "{nonzero} non-zero intrusions, {skipped} terms skipped");
}

#[test]
fn the_collision_prefilters_change_no_verdict() {
    // The straightforward collision filter: every near agent's disc and exact Gaussian minimum,
    // every nearby wall edge, no distance pre-check.
    let reference = |scene: &Scene, v: Vec2, horizon: f64| -> bool {
        let pos = scene.pos;
        let person = scene.near.iter().any(|a| {
            let (d0, dv) = (pos - a.pos, v - a.vel);
            let dd = dv.norm_squared();
            let t = if dd > 0.0 { (-d0.dot(&dv) / dd).clamp(0.0, horizon) } else { 0.0 };
            (t > 0.0 && (d0 + dv * t).norm_squared() < a.bound2)
                || a.gaussian.is_some_and(|(g, level)| {
                    let (q, t) = g.min_along(d0, dv, horizon);
                    t > 0.0 && q < level
                })
        });
        let end = pos + v * horizon;
        person
            || scene.edges.iter().any(|&(a, b, d_now)| {
                let d = segment_segment_distance(pos, end, a, b);
                d < scene.wall_bound && d < d_now
            })
    };
    let geom = room();
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let mut rng = ChaCha8Rng::seed_from_u64(32);
    let (mut hits, mut total) = (0, 0);
    for _ in 0..300 {
        let pos = v(rng.random_range(-4.5..4.5), rng.random_range(-4.5..4.5));
        if geom.contains(pos) {
            continue;
        }
        let vel = v(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5));
        let n = rng.random_range(0..30);
        let others: Vec<Agent> =
            random_crowd(&mut rng, n).into_iter().map(|a| Agent { pos: a.pos * 0.6, ..a }).collect();
        let shapes: Vec<AgentShape> = (0..n)
            .map(|_| {
                if rng.random_bool(0.5) {
                    return AgentShape::Disc;
                }
                let sides = crate::proxemics::Asymmetric {
                    front: rng.random_range(0.3..2.5),
                    rear: rng.random_range(0.3..2.5),
                    right: rng.random_range(0.3..2.5),
                    left: rng.random_range(0.3..2.5),
                };
                let g = GaussianSpace::new(rng.random_range(-3.2..3.2), sides, 1.0, 0.5).expect("valid");
                AgentShape::Gaussian(g)
            })
            .collect();
        let wall_bound = R + p.safety_margin;
        let edges = nearby_edges(pos, Some(&geom), l.max_speed * p.horizon + wall_bound).expect("outside");
        let (near, _) = people_sets(pos, vel, R, None, &others, &shapes, l.max_speed, &p);
        let scene = Scene { pos, partial_goal: pos, wall_bound, edges: &edges, near: &near, reactive: &[] };
        for s in action_set(vel, v(1.0, 0.0), v(1.0, 0.0), l.max_accel * DT, l.max_speed, &p) {
            let fast = collides(&scene, s, p.horizon);
            assert_eq!(fast, reference(&scene, s, p.horizon), "sample {s:?} at {pos:?}");
            hits += usize::from(fast);
            total += 1;
        }
    }
    assert!(hits > 1000 && total - hits > 1000, "{hits} of {total} samples collide");
}

/// A differential-drive robot's tracking bound (Pepper's limits, NH-ORCA's `T`) at `heading`.
fn unicycle(heading: f64, e: f64) -> TrackingBound {
    use crate::control::orca::nonholonomic::NhParams;
    let l = Limits::PEPPER;
    TrackingBound {
        heading,
        max_speed: l.max_speed,
        max_turn: l.max_angular_speed,
        params: NhParams { tracking_error: e, settle_time: 0.4 },
    }
}

#[test]
fn a_unicycle_chooses_only_velocities_it_can_track_and_keeps_clear_by_its_tracking_error() {
    use crate::control::orca::nonholonomic::max_tracked_speed;
    let geom = room();
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let e = 0.05;
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let (mut checked, mut slowed) = (0, 0);
    for _ in 0..400 {
        let pos = v(rng.random_range(-4.3..4.3), rng.random_range(-4.3..4.3));
        if geom.distance(pos) < R + e + p.safety_margin || geom.contains(pos) {
            continue;
        }
        let heading: f64 = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
        // A unicycle moves along its heading.
        let vel = v(heading.cos(), heading.sin()) * rng.random_range(0.0..0.55);
        let goal = v(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0));
        let others = six_people_clear_of(&mut rng, pos, R + e + p.safety_margin);
        let u = unicycle(heading, e);
        let Some(out) =
            social_momentum_shaped(pos, vel, R, goal, &others, &[], Some(&geom), &l, DT, &p, Some(u))
        else {
            continue;
        };
        checked += 1;
        let cap = max_tracked_speed(out.y.atan2(out.x) - heading, l.max_speed, l.max_angular_speed, u.params);
        assert!(out.norm() <= cap + 1e-12, "untrackable {out:?} at heading {heading}");
        let free = social_momentum(pos, vel, R, goal, &others, Some(&geom), &l, DT, &p);
        if free.is_some_and(|f| f.norm() > out.norm() + 1e-9) {
            slowed += 1;
        }
        // The body enlarged by the tracking error stays clear of everyone over the horizon.
        assert_clear_over_horizon(pos, out, &others, &geom, R + e + p.safety_margin, p.horizon);
    }
    assert!(checked > 100, "only {checked} checked");
    // The constraint bites: in some scenes (mostly a slow robot, whose window reaches every
    // direction) the holonomic choice was faster.
    assert!(slowed > 0, "none of {checked} slowed by the constraint");
}

#[test]
fn a_unicycle_facing_away_from_its_goal_turns_before_it_goes() {
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    let goal = v(5.0, 0.0);
    let go = |u: Option<TrackingBound>| {
        social_momentum_shaped(Vec2::zeros(), Vec2::zeros(), R, goal, &[], &[], None, &l, DT, &p, u)
            .expect("free space")
    };
    // Standing, facing away from the goal: the holonomic robot sets off toward it, the unicycle
    // may only creep (the tracking command then turns it on the spot).
    let holonomic = go(None);
    let away = go(Some(unicycle(std::f64::consts::PI, 0.02)));
    assert!(away.norm() < 0.5 * holonomic.norm(), "{away:?} against {holonomic:?}");
    // Facing the goal it goes as the holonomic robot does.
    assert_eq!(go(Some(unicycle(0.0, 0.02))), holonomic);
}

#[test]
fn a_bad_tracking_bound_stops_the_robot() {
    let p = SocialMomentumParams::default();
    let l = Limits::PEPPER;
    for u in [
        unicycle(f64::NAN, 0.02),
        unicycle(0.0, 0.0),
        TrackingBound { max_turn: -1.0, ..unicycle(0.0, 0.02) },
    ] {
        let out = social_momentum_shaped(
            Vec2::zeros(),
            Vec2::zeros(),
            R,
            v(5.0, 0.0),
            &[],
            &[],
            None,
            &l,
            DT,
            &p,
            Some(u),
        );
        assert_eq!(out, None, "{u:?}");
    }
}
