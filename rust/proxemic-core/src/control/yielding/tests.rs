//! Tests of predictive yielding.

use super::*;
use crate::map::Bounds;
use proptest::prelude::*;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// Pepper's radius in the scenes (m) and a person's.
const ROBOT_R: f64 = 0.3;
const PERSON_R: f64 = 0.22;
const DT: f64 = 0.1;

/// A corridor 3.2 m wide along x (walls at y = ±1.6), from x = -10 to 20: room for a 0.6 m robot
/// and a 0.44 m person to pass with 0.45 m between them and 0.05 m to the walls, with 0.46 m to
/// spare.
fn corridor() -> StaticGeometry {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| vec![v(x0, y0), v(x1, y0), v(x1, y1), v(x0, y1)];
    let polys = vec![rect(-10.0, -1.8, 20.0, -1.6), rect(-10.0, 1.6, 20.0, 1.8)];
    match StaticGeometry::new(polys, Bounds { min: v(-10.0, -1.8), max: v(20.0, 1.8) }) {
        Ok(g) => g,
        Err(e) => panic!("{e}"),
    }
}

/// Hall's personal zone (1.2 m) and social zone (3.6 m) round a person moving at constant
/// velocity, centre distance, with the social map's default factors (4 and 2).
struct Zones(Mover);

impl CostField for Zones {
    fn factor(&self, p: Vec2, t: f64) -> f64 {
        let d = (p - (self.0.pos + self.0.vel * t)).norm();
        if d < 1.2 {
            4.0
        } else if d < 3.6 {
            2.0
        } else {
            1.0
        }
    }
    fn max_factor(&self) -> f64 {
        5.0
    }
}

fn person(pos: Vec2, vel: Vec2) -> Mover {
    Mover { pos, vel, radius: PERSON_R, gap: 0.45 }
}

/// Runs the robot from the origin toward +x at full reference speed for `steps` control steps
/// among people walking at constant velocity; returns (smallest body gap, smallest speed after
/// the start, largest |y|, final position).
fn head_on(steps: usize) -> (f64, f64, f64, Vec2) {
    let geom = corridor();
    let limits = Limits::PEPPER;
    let params = YieldParams::default();
    let (mut p, mut vel) = (v(0.0, 0.0), v(0.0, 0.0));
    let walker = person(v(8.0, 0.0), v(-1.0, 0.0));
    let (mut min_gap, mut min_speed, mut max_y) = (f64::INFINITY, f64::INFINITY, 0.0f64);
    for k in 0..steps {
        let t = k as f64 * DT;
        let now = Mover { pos: walker.pos + walker.vel * t, ..walker };
        let robot = Robot { pos: p, vel, radius: ROBOT_R };
        let out = plan(&robot, v(limits.max_speed, 0.0), &[now], &Zones(now), Some(&geom), &limits, &params);
        (vel, _) = limits.apply(out.velocity, 0.0, vel, 0.0, DT);
        p += vel * DT;
        let q = walker.pos + walker.vel * (t + DT);
        min_gap = min_gap.min((q - p).norm() - ROBOT_R - PERSON_R);
        if k > 20 {
            min_speed = min_speed.min(vel.norm());
        }
        max_y = max_y.max(p.y.abs());
    }
    (min_gap, min_speed, max_y, p)
}

#[test]
fn a_robot_steps_aside_for_a_person_walking_head_on_in_a_corridor() {
    let (min_gap, min_speed, max_y, end) = head_on(150);
    assert!(min_gap >= 0.45, "body gap fell to {min_gap:.3} m");
    // It gave way: off the person's line by more than half the needed 0.97 m, or slowed down.
    assert!(max_y > 0.5 || min_speed < 0.3, "max |y| {max_y:.2}, min speed {min_speed:.2}");
    // And it went on afterwards.
    assert!(end.x > 5.0, "stalled at {end:?}");
}

#[test]
fn the_same_input_gives_the_same_command_bit_for_bit() {
    let a = head_on(120);
    let b = head_on(120);
    assert_eq!(a.0.to_bits(), b.0.to_bits());
    assert_eq!(a.3.x.to_bits(), b.3.x.to_bits());
    assert_eq!(a.3.y.to_bits(), b.3.y.to_bits());
}

#[test]
fn with_no_way_out_the_robot_stops() {
    // Running at full speed straight at a person 0.5 m ahead: every rollout approaches them
    // inside the gap, so the command is the stop.
    let robot = Robot { pos: v(0.0, 0.0), vel: v(0.55, 0.0), radius: ROBOT_R };
    let wall = person(v(1.05, 0.0), v(-0.5, 0.0));
    let out = plan(&robot, v(0.55, 0.0), &[wall], &NoCost, None, &Limits::PEPPER, &YieldParams::default());
    assert!(out.stopped);
    assert_eq!(out.velocity, Vec2::zeros());
}

#[test]
fn a_person_walking_into_a_standing_robot_does_not_freeze_it() {
    // The person will come within the gap of the robot where it stands; standing or stepping
    // back does not approach them, so some rollout is admissible.
    let robot = Robot { pos: v(0.0, 0.0), vel: Vec2::zeros(), radius: ROBOT_R };
    let walker = person(v(1.5, 0.0), v(-0.6, 0.0));
    let out = plan(&robot, v(0.55, 0.0), &[walker], &NoCost, None, &Limits::PEPPER, &YieldParams::default());
    assert!(!out.stopped, "{out:?}");
    let params = YieldParams::default();
    let pts = rollout(&robot, out.velocity, &Limits::PEPPER, &params);
    assert!(!violates(&pts, &robot, &[walker], &params), "{out:?}");
}

#[test]
fn social_cost_steers_the_choice() {
    // A cost field that charges the half-plane y > 0.2 ahead: the robot keeps to y <= 0.2.
    struct Band;
    impl CostField for Band {
        fn factor(&self, p: Vec2, _t: f64) -> f64 {
            if p.y > 0.2 { 4.0 } else { 1.0 }
        }
        fn max_factor(&self) -> f64 {
            4.0
        }
    }
    let robot = Robot { pos: v(0.0, 0.1), vel: v(0.3, 0.3), radius: ROBOT_R };
    let free = plan(&robot, v(0.55, 0.0), &[], &NoCost, None, &Limits::PEPPER, &YieldParams::default());
    let costed = plan(&robot, v(0.55, 0.0), &[], &Band, None, &Limits::PEPPER, &YieldParams::default());
    assert!(costed.velocity.y < free.velocity.y, "{free:?} {costed:?}");
}

#[test]
fn an_infinite_cost_is_a_hard_constraint() {
    struct Keep;
    impl CostField for Keep {
        fn factor(&self, p: Vec2, _t: f64) -> f64 {
            if p.x > 0.5 { f64::INFINITY } else { 1.0 }
        }
        fn max_factor(&self) -> f64 {
            4.0
        }
    }
    let params = YieldParams::default();
    let robot = Robot { pos: Vec2::zeros(), vel: Vec2::zeros(), radius: ROBOT_R };
    let out = plan(&robot, v(0.55, 0.0), &[], &Keep, None, &Limits::PEPPER, &params);
    let end = rollout(&robot, out.velocity, &Limits::PEPPER, &params);
    assert!(end.iter().all(|q| q.pos.x <= 0.5), "{out:?}");
}

#[test]
fn bad_input_is_a_stop() {
    let robot = Robot { pos: v(f64::NAN, 0.0), vel: Vec2::zeros(), radius: ROBOT_R };
    let out = plan(&robot, v(0.5, 0.0), &[], &NoCost, None, &Limits::PEPPER, &YieldParams::default());
    assert!(out.stopped && out.velocity == Vec2::zeros());
    let ok = Robot { pos: Vec2::zeros(), ..robot };
    let bad = person(v(1.0, f64::INFINITY), Vec2::zeros());
    let out = plan(&ok, v(0.5, 0.0), &[bad], &NoCost, None, &Limits::PEPPER, &YieldParams::default());
    assert!(out.stopped && out.velocity == Vec2::zeros());
    let params = YieldParams { step: 0.0, ..YieldParams::default() };
    let out = plan(&ok, v(0.5, 0.0), &[], &NoCost, None, &Limits::PEPPER, &params);
    assert!(out.stopped);
}

#[test]
fn every_rollout_ends_stopped_within_the_horizon() {
    let params = YieldParams::default();
    let robot = Robot { pos: Vec2::zeros(), vel: v(0.55, 0.0), radius: ROBOT_R };
    for c in [v(0.55, 0.0), v(0.0, 0.55), v(-0.2, 0.1)] {
        let pts = rollout(&robot, c, &Limits::PEPPER, &params);
        assert!(pts.last().is_some_and(|q| q.vel.norm() < 1e-12), "{c:?}");
        // and the acceleration limit holds along it
        let mut prev = robot.vel;
        for q in &pts {
            assert!((q.vel - prev).norm() <= Limits::PEPPER.max_accel * params.step + 1e-12);
            prev = q.vel;
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// Whatever the people (constant velocity), the command's rollout never brings the robot
    /// inside a person's gap while approaching them; when no such command exists the robot is
    /// told to stop.
    #[test]
    fn the_command_never_violates_the_constraint(
        vx in -0.55f64..0.55, vy in -0.55f64..0.55,
        people in proptest::collection::vec((-4.0f64..4.0, -4.0f64..4.0, -1.3f64..1.3, -1.3f64..1.3), 0..8),
        rx in -0.55f64..0.55, ry in -0.55f64..0.55,
    ) {
        let limits = Limits::PEPPER;
        let params = YieldParams::default();
        let robot = Robot { pos: Vec2::zeros(), vel: clamp_norm(v(vx, vy), 0.55), radius: ROBOT_R };
        let movers: Vec<Mover> =
            people.iter().map(|&(x, y, ux, uy)| person(v(x, y), v(ux, uy))).collect();
        let out = plan(&robot, v(rx, ry), &movers, &NoCost, None, &limits, &params);
        if out.stopped {
            prop_assert_eq!(out.velocity, Vec2::zeros());
        } else {
            let pts = rollout(&robot, out.velocity, &limits, &params);
            prop_assert!(!violates(&pts, &robot, &movers, &params), "{:?}", out);
        }
    }
}

/// The rollout as step 2 of the module docs states it, every step updated: [`rollout`] skips the
/// updates that cannot change anything (a velocity already at its target's fixed point, the
/// stopped tail) and must give the same points bit for bit.
fn rollout_by_the_book(
    robot: &Robot,
    command: Vec2,
    limits: &Limits,
    params: &YieldParams,
) -> Vec<RolloutPoint> {
    let h = params.step;
    let n = (params.horizon / h).ceil() as usize;
    let dv = limits.max_accel * h;
    let command = clamp_norm(command, limits.max_speed);
    let (mut p, mut v) = (robot.pos, robot.vel);
    (1..=n)
        .map(|k| {
            let t0 = (k - 1) as f64 * h;
            let target = if t0 < params.commit - 1e-9 { command } else { Vec2::zeros() };
            v = clamp_norm(v + clamp_norm(target - v, dv), limits.max_speed);
            p += v * h;
            RolloutPoint { t: k as f64 * h, pos: p, vel: v }
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// The skipped updates change nothing: the same points, bit for bit, from any state, command
    /// and limits (including a robot already at the command's velocity and one at rest).
    #[test]
    fn rollout_equals_the_step_by_step_update(
        pos in (-5.0f64..5.0, -5.0f64..5.0),
        vel in (-0.8f64..0.8, -0.8f64..0.8),
        cmd in (-0.8f64..0.8, -0.8f64..0.8),
        at_command in 0usize..3,
        accel in 0.1f64..2.0,
        commit in 0.0f64..3.0,
    ) {
        let command = v(cmd.0, cmd.1);
        let limits = Limits { max_accel: accel, ..Limits::PEPPER };
        let vel = match at_command {
            0 => v(vel.0, vel.1),
            1 => clamp_norm(command, limits.max_speed),
            _ => Vec2::zeros(),
        };
        let robot = Robot { pos: v(pos.0, pos.1), vel, radius: ROBOT_R };
        let params = YieldParams { commit, ..YieldParams::default() };
        let bits = |pts: &[RolloutPoint]| -> Vec<[u64; 5]> {
            pts.iter()
                .map(|q| [q.t.to_bits(), q.pos.x.to_bits(), q.pos.y.to_bits(), q.vel.x.to_bits(), q.vel.y.to_bits()])
                .collect()
        };
        prop_assert_eq!(
            bits(&rollout(&robot, command, &limits, &params)),
            bits(&rollout_by_the_book(&robot, command, &limits, &params))
        );
    }
}
