//! Tests of ORCA: known-answer cases (hand-worked geometry of van den Berg et al. 2011's half-planes,
//! restated in `docs/algorithms.md`), properties, and scenarios.

use super::*;
use proptest::prelude::*;

fn v(x: f64, y: f64) -> Vec2 {
    Vec2::new(x, y)
}

/// An agent with the KAT defaults (r = 0.5, V = 1, reciprocal) whose preferred velocity is `vel`.
fn kat_agent(pos: Vec2, vel: Vec2, id: u64) -> OrcaAgent {
    OrcaAgent { pos, vel, pref_vel: vel, radius: 0.5, max_speed: 1.0, reciprocal: true, id }
}

/// The KAT parameters: tau = tau_o = 5, no perturbation.
fn kat_params() -> OrcaParams {
    OrcaParams {
        time_horizon: 5.0,
        time_horizon_obst: 5.0,
        neighbor_dist: 10.0,
        max_neighbors: 10,
        perturbation: 0.0,
        pass_tilt: 0.0,
    }
}

fn solve(params: OrcaParams, agents: &[OrcaAgent], obstacles: &ObstacleSet, dt: f64) -> Vec<Vec2> {
    let mut orca = Orca::new(params).expect("valid params");
    let mut out = vec![Vec2::zeros(); agents.len()];
    let active: Vec<usize> = (0..agents.len()).collect();
    orca.compute(agents, &active, obstacles, dt, 0, &mut out).expect("compute");
    out
}

fn assert_close(a: Vec2, b: Vec2, tol: f64) {
    assert!((a - b).norm() <= tol, "{a:?} != {b:?} (tol {tol})");
}

// ---------------------------------------------------------------- known answers

#[test]
fn kat1_exact_head_on_takes_the_right_leg() {
    let agents = [kat_agent(v(0.0, 0.0), v(1.0, 0.0), 0), kat_agent(v(4.0, 0.0), v(-1.0, 0.0), 1)];
    let out = solve(kat_params(), &agents, &ObstacleSet::empty(), 0.25);
    assert_close(out[0], v(0.937500, -0.242061), 1e-6);
    assert_close(out[1], v(-0.937500, 0.242061), 1e-6);
    // A's line.
    let mut orca = Orca::new(kat_params()).expect("params");
    let mut o = vec![Vec2::zeros(); 2];
    orca.compute(&agents, &[0], &ObstacleSet::empty(), 0.25, 0, &mut o).expect("compute");
    let lines = orca.last_lines();
    assert_eq!(lines.len(), 1);
    assert_close(lines[0].point, v(0.9375, -0.242061), 1e-6);
    assert_close(lines[0].dir, v(-0.968246, 0.25), 1e-6);
    // Right-hand traffic: A (heading +x) veers to -y, B (heading -x) to +y.
    assert!(PASS_ON_RIGHT && out[0].y < 0.0 && out[1].y > 0.0);
}

#[test]
fn kat2_offset_encounter() {
    let agents = [kat_agent(v(0.0, 0.0), v(1.0, 0.0), 0), kat_agent(v(4.0, 0.2), v(-1.0, 0.0), 1)];
    let out = solve(kat_params(), &agents, &ObstacleSet::empty(), 0.25);
    assert_close(out[0], v(0.959591, -0.196917), 1e-6);
    assert_close(out[1], v(-0.959591, 0.196917), 1e-6);
}

#[test]
fn kat3_overlapping_agents_separate_in_one_step() {
    let agents = [kat_agent(v(0.0, 0.0), v(0.0, 0.0), 0), kat_agent(v(0.8, 0.0), v(0.0, 0.0), 1)];
    let dt = 0.25;
    let out = solve(kat_params(), &agents, &ObstacleSet::empty(), dt);
    assert_close(out[0], v(-0.4, 0.0), 1e-12);
    assert_close(out[1], v(0.4, 0.0), 1e-12);
    let sep = (agents[1].pos + out[1] * dt - agents[0].pos - out[0] * dt).norm();
    assert!((sep - 1.0).abs() < 1e-12, "separation {sep}");
}

fn kat4_wall() -> ObstacleSet {
    // Occupies x in [2, 3], y in [-5, 5]; counter-clockwise.
    ObstacleSet::new(&[vec![v(2.0, -5.0), v(3.0, -5.0), v(3.0, 5.0), v(2.0, 5.0)]]).expect("wall")
}

#[test]
fn kat4_wall_line_and_settling_point() {
    let wall = kat4_wall();
    let params = OrcaParams { time_horizon_obst: 2.0, ..kat_params() };
    let mut orca = Orca::new(params).expect("params");
    let mut a = [kat_agent(v(0.0, 0.0), v(1.0, 0.0), 0)];
    let mut out = vec![Vec2::zeros(); 1];
    orca.compute(&a, &[0], &wall, 0.25, 0, &mut out).expect("compute");
    let lines = orca.last_lines();
    assert_eq!(lines.len(), 1, "{lines:?}");
    assert_close(lines[0].point, v(0.75, 2.5), 1e-12);
    assert_close(lines[0].dir, v(0.0, 1.0), 1e-12);
    assert_close(out[0], v(0.75, 0.0), 1e-12);
    // Integrate: v_x = (1.5 - x) / tau_o, so x_k = 1.5 (1 - (7/8)^k) with dt = 0.25: the agent creeps
    // towards the wall, is at 1.494 after 42 steps (RVO2's measured value) and never reaches 2 - r.
    for step in 0..400 {
        orca.compute(&a, &[0], &wall, 0.25, step, &mut out).expect("compute");
        a[0].vel = out[0];
        a[0].pos += out[0] * 0.25;
        let k = step as i32 + 1;
        assert!((a[0].pos.x - 1.5 * (1.0 - 0.875f64.powi(k))).abs() < 1e-9, "step {k}: {:?}", a[0].pos);
        assert!(a[0].pos.x < 1.5 && a[0].pos.y == 0.0, "penetrated at step {k}: {:?}", a[0].pos);
        if k == 42 {
            assert!((a[0].pos.x - 1.494).abs() < 1e-3, "x_42 = {}", a[0].pos.x);
        }
    }
}

#[test]
fn kat_non_reciprocal_neighbour_gets_full_responsibility() {
    // KAT1 against a person (alpha = 1): u = (-0.125, -0.484123), so A's new velocity is vA + u.
    let mut person = kat_agent(v(4.0, 0.0), v(-1.0, 0.0), 1);
    person.reciprocal = false;
    let agents = [kat_agent(v(0.0, 0.0), v(1.0, 0.0), 0), person];
    let mut orca = Orca::new(kat_params()).expect("params");
    let mut out = vec![Vec2::zeros(); 2];
    orca.compute(&agents, &[0], &ObstacleSet::empty(), 0.25, 0, &mut out).expect("compute");
    assert_close(out[0], v(0.875, -0.484123), 1e-6);
    assert_eq!(out[1], Vec2::zeros(), "inactive entries are left untouched");
}

// ---------------------------------------------------------------- LP properties

/// Brute force over a dense polar grid of the speed disk: the feasible point closest to `opt`.
fn brute_lp(lines: &[Line], speed: f64, opt: Vec2) -> Option<f64> {
    let mut best: Option<f64> = None;
    let (nr, na) = (400, 720);
    for ir in 0..=nr {
        let rr = speed * ir as f64 / nr as f64;
        for ia in 0..na {
            let th = std::f64::consts::TAU * ia as f64 / na as f64;
            let x = v(rr * th.cos(), rr * th.sin());
            if lines.iter().all(|l| cross(l.dir, l.point - x) <= 1e-9) {
                let d = (x - opt).norm();
                best = Some(best.map_or(d, |b: f64| b.min(d)));
            }
        }
    }
    best
}

fn arb_line() -> impl Strategy<Value = Line> {
    (-1.5f64..1.5, -1.5f64..1.5, 0.0f64..std::f64::consts::TAU)
        .prop_map(|(x, y, a)| Line { point: v(x, y), dir: v(a.cos(), a.sin()) })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn lp2_is_feasible_and_optimal(lines in prop::collection::vec(arb_line(), 0..6),
                                    ox in -1.5f64..1.5, oy in -1.5f64..1.5) {
        let opt = v(ox, oy);
        let mut x = Vec2::zeros();
        let fail = lp2(&lines, 1.0, opt, false, &mut x);
        let brute = brute_lp(&lines, 1.0, opt);
        if fail == lines.len() {
            prop_assert!(x.norm() <= 1.0 + 1e-9);
            for l in &lines {
                prop_assert!(cross(l.dir, l.point - x) <= 1e-9, "violates {:?}", l);
            }
            if let Some(b) = brute {
                // Dense sampling resolution is about 2.5e-3 at the rim.
                prop_assert!((x - opt).norm() <= b + 1e-9, "lp {} brute {}", (x - opt).norm(), b);
                // The sampler only approximates the optimum from above (coarse inside the disc).
                prop_assert!((x - opt).norm() >= b - 3e-2, "lp {} brute {}", (x - opt).norm(), b);
            }
        } else {
            // Infeasible: the sampler must not find a clearly feasible point either.
            let shrunk: Vec<Line> = lines.iter()
                .map(|l| Line { point: l.point + left_normal(l.dir) * 1e-2, dir: l.dir }).collect();
            prop_assert!(brute_lp(&shrunk, 1.0, opt).is_none());
        }
    }

    #[test]
    fn lp3_keeps_obstacle_lines_and_minimises_max_violation(
        obst in prop::collection::vec(arb_line(), 0..2),
        agent in prop::collection::vec(arb_line(), 1..6),
        ox in -1.0f64..1.0, oy in -1.0f64..1.0,
    ) {
        let speed = 1.0;
        let mut lines = obst.clone();
        lines.extend(agent.iter().copied());
        let n_obst = obst.len();
        // Only meaningful when the obstacle lines alone are feasible with some margin.
        let mut tmp = Vec2::zeros();
        let obst_shrunk: Vec<Line> = obst.iter()
            .map(|l| Line { point: l.point + left_normal(l.dir) * 0.05, dir: l.dir }).collect();
        prop_assume!(lp2(&obst_shrunk, speed, Vec2::zeros(), false, &mut tmp) == obst_shrunk.len());
        let mut x = Vec2::zeros();
        let fail = lp2(&lines, speed, v(ox, oy), false, &mut x);
        prop_assume!(fail < lines.len());
        let mut proj = Vec::new();
        lp3(&lines, n_obst, fail, speed, &mut x, &mut proj);
        prop_assert!(x.norm() <= speed + 1e-9);
        for l in &obst {
            prop_assert!(cross(l.dir, l.point - x) <= 1e-7, "obstacle line violated");
        }
        let max_viol = |x: Vec2| agent.iter().map(|l| cross(l.dir, l.point - x)).fold(0.0f64, f64::max);
        // Brute-force minimax over feasible points of the obstacle lines.
        let mut best = f64::INFINITY;
        for ir in 0..=200 {
            let rr = speed * ir as f64 / 200.0;
            for ia in 0..360 {
                let th = std::f64::consts::TAU * ia as f64 / 360.0;
                let y = v(rr * th.cos(), rr * th.sin());
                if obst.iter().all(|l| cross(l.dir, l.point - y) <= 0.0) {
                    best = best.min(max_viol(y));
                }
            }
        }
        prop_assert!(max_viol(x) <= best + 1e-6, "lp3 {} brute {}", max_viol(x), best);
    }
}

// ---------------------------------------------------------------- symmetry properties

fn random_scene(seed: u64, n: usize) -> Vec<OrcaAgent> {
    let mut s = seed;
    let mut rnd = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64)
    };
    (0..n)
        .map(|k| OrcaAgent {
            pos: v(rnd() * 8.0, rnd() * 8.0),
            vel: v(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0) * 0.7,
            pref_vel: v(rnd() * 2.0 - 1.0, rnd() * 2.0 - 1.0) * 0.7,
            radius: 0.2 + 0.2 * rnd(),
            max_speed: 0.5 + rnd(),
            reciprocal: k % 3 != 0,
            id: k as u64,
        })
        .collect()
}

#[test]
fn translation_invariance_and_mirror_symmetry() {
    // Both the perturbation and the passing-side tilt are chiral by design: switch them off.
    let params = OrcaParams { perturbation: 0.0, pass_tilt: 0.0, ..OrcaParams::default() };
    let walls = vec![vec![v(-1.0, -1.0), v(9.0, -1.0), v(9.0, -0.8), v(-1.0, -0.8)]];
    for seed in 0..20 {
        let agents = random_scene(seed, 12);
        let base = solve(params, &agents, &ObstacleSet::new(&walls).expect("walls"), 0.1);
        let shift = v(3.25, -1.5);
        let moved: Vec<OrcaAgent> = agents.iter().map(|a| OrcaAgent { pos: a.pos + shift, ..*a }).collect();
        let walls_moved: Vec<Vec<Vec2>> =
            walls.iter().map(|p| p.iter().map(|q| q + shift).collect()).collect();
        let out = solve(params, &moved, &ObstacleSet::new(&walls_moved).expect("walls"), 0.1);
        for (a, b) in base.iter().zip(&out) {
            assert_close(*a, *b, 1e-9);
        }
        // Mirror in y (polygons re-oriented by ObstacleSet::new).
        let flip = |p: Vec2| v(p.x, -p.y);
        let mirrored: Vec<OrcaAgent> = agents
            .iter()
            .map(|a| OrcaAgent { pos: flip(a.pos), vel: flip(a.vel), pref_vel: flip(a.pref_vel), ..*a })
            .collect();
        let walls_m: Vec<Vec<Vec2>> = walls.iter().map(|p| p.iter().map(|&q| flip(q)).collect()).collect();
        let out = solve(params, &mirrored, &ObstacleSet::new(&walls_m).expect("walls"), 0.1);
        for (a, b) in base.iter().zip(&out) {
            assert_close(flip(*a), *b, 1e-9);
        }
    }
}

// ---------------------------------------------------------------- neighbour search

fn brute_neighbors(agents: &[OrcaAgent], i: usize, params: &OrcaParams) -> Vec<(f64, u64, usize)> {
    let r2 = params.neighbor_dist * params.neighbor_dist;
    let mut all: Vec<(f64, u64, usize)> = agents
        .iter()
        .enumerate()
        .filter(|&(k, a)| k != i && a.is_valid())
        .map(|(k, a)| ((a.pos - agents[i].pos).norm_squared(), a.id, k))
        .filter(|&(d2, _, _)| d2 < r2)
        .collect();
    all.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    all.truncate(params.max_neighbors);
    all
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn kd_tree_equals_brute_force(
        pts in prop::collection::vec((0i32..40, 0i32..40, 0u64..50, any::<bool>()), 1..300),
        nd in 0.0f64..20.0, k in 0usize..40, scale in 0.05f64..1.0,
    ) {
        // Integer lattice positions make exact distance ties (and coincident agents) common; the
        // duplicated ids exercise the index tie-break; some agents are invalid.
        let agents: Vec<OrcaAgent> = pts.iter().map(|&(x, y, id, ok)| OrcaAgent {
            pos: v(x as f64 * scale, y as f64 * scale),
            vel: Vec2::zeros(),
            pref_vel: Vec2::zeros(),
            radius: if ok || id % 7 != 0 { 0.1 } else { f64::NAN },
            max_speed: 1.0,
            reciprocal: true,
            id,
        }).collect();
        let params = OrcaParams { neighbor_dist: nd, max_neighbors: k, ..OrcaParams::default() };
        let mut orca = Orca::new(params).expect("params");
        orca.build_tree(&agents);
        for i in 0..agents.len() {
            orca.query_neighbors(agents[i].pos, i);
            let fast: Vec<(f64, u64, usize)> =
                orca.neighbors.iter().map(|n| (n.d2, n.id, n.idx as usize)).collect();
            prop_assert_eq!(fast, brute_neighbors(&agents, i, &params));
        }
    }

    #[test]
    fn obstacle_grid_equals_linear_scan(
        boxes in prop::collection::vec((0.0f64..50.0, 0.0f64..50.0, 0.1f64..3.0, 0.1f64..3.0), 12..40),
        queries in prop::collection::vec((-5.0f64..55.0, -5.0f64..55.0, 0.1f64..6.0), 1..30),
    ) {
        let polys: Vec<Vec<Vec2>> = boxes.iter()
            .map(|&(x, y, w, h)| vec![v(x, y), v(x + w, y), v(x + w, y + h), v(x, y + h)]).collect();
        let set = ObstacleSet::new(&polys).expect("boxes");
        prop_assert!(!set.cell_start.is_empty(), "grid in use");
        let mut stamps = Stamps::default();
        for &(x, y, r) in &queries {
            let p = v(x, y);
            let mut fast = Vec::new();
            set.query(p, r * r, &mut fast, &mut stamps);
            let mut slow: Vec<(f64, u32)> = (0..set.num_edges()).filter_map(|e| {
                let a = set.vertices[e].point;
                let b = set.vertices[set.vertices[e].next as usize].point;
                let d2 = distance_squared_point_segment(p, a, b);
                (cross(b - a, p - a) <= 0.0 && d2 < r * r).then_some((d2, e as u32))
            }).collect();
            slow.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            prop_assert_eq!(fast, slow);
        }
    }
}

// ---------------------------------------------------------------- safety properties

fn arb_agent() -> impl Strategy<Value = OrcaAgent> {
    (
        (-20.0f64..20.0, -20.0f64..20.0),
        (-3.0f64..3.0, -3.0f64..3.0),
        (-3.0f64..3.0, -3.0f64..3.0),
        0.0f64..1.0,
        0.0f64..2.0,
        any::<bool>(),
        0u64..1000,
    )
        .prop_map(|(p, vel, pref, radius, max_speed, reciprocal, id)| OrcaAgent {
            pos: v(p.0, p.1),
            vel: v(vel.0, vel.1),
            pref_vel: v(pref.0, pref.1),
            radius,
            max_speed,
            reciprocal,
            id,
        })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn output_is_finite_and_within_max_speed(
        agents in prop::collection::vec(arb_agent(), 1..40),
        boxes in prop::collection::vec((-20.0f64..20.0, -20.0f64..20.0, 0.0f64..4.0, 0.0f64..4.0), 0..6),
        dt in 0.01f64..1.0, step in any::<u64>(), tau in 0.1f64..10.0, tau_o in 0.1f64..10.0,
        k in 0usize..20, pert in 0.0f64..1.0, tilt in 0.0f64..0.5,
    ) {
        // Includes degenerate boxes (zero width or height) and agents inside obstacles.
        let polys: Vec<Vec<Vec2>> = boxes.iter()
            .map(|&(x, y, w, h)| vec![v(x, y), v(x + w, y), v(x + w, y + h), v(x, y + h)])
            .filter(|p| (p[2] - p[0]).norm() > 0.0)
            .collect();
        let set = ObstacleSet::new(&polys).expect("boxes");
        let params = OrcaParams { time_horizon: tau, time_horizon_obst: tau_o, neighbor_dist: 10.0,
                                  max_neighbors: k, perturbation: pert, pass_tilt: tilt };
        let mut orca = Orca::new(params).expect("params");
        let mut out = vec![v(f64::NAN, f64::NAN); agents.len()];
        let active: Vec<usize> = (0..agents.len()).collect();
        orca.compute(&agents, &active, &set, dt, step, &mut out).expect("compute");
        for (a, o) in agents.iter().zip(&out) {
            prop_assert!(o.x.is_finite() && o.y.is_finite(), "{:?}", o);
            prop_assert!(o.norm() <= a.max_speed, "{} > {}", o.norm(), a.max_speed);
        }
    }
}

#[test]
fn coincident_agents_move_apart_without_nan() {
    let agents = [kat_agent(v(1.0, 1.0), v(0.0, 0.0), 3), kat_agent(v(1.0, 1.0), v(0.0, 0.0), 7)];
    let out = solve(kat_params(), &agents, &ObstacleSet::empty(), 0.25);
    assert!(out.iter().all(|o| o.x.is_finite() && o.y.is_finite()));
    assert!(out[0].x < 0.0 && out[1].x > 0.0, "{out:?}");
    // Relative velocity exactly p / dt in the overlapping case.
    let agents = [kat_agent(v(0.0, 0.0), v(0.0, 0.0), 0), kat_agent(v(0.2, 0.0), v(-0.8, 0.0), 1)];
    let out = solve(kat_params(), &agents, &ObstacleSet::empty(), 0.25);
    assert!(out.iter().all(|o| o.x.is_finite() && o.y.is_finite()));
    assert!(out[0].x < 0.0, "{out:?}");
}

#[test]
fn agent_exactly_on_an_obstacle_vertex_gets_a_finite_velocity() {
    let wall = kat4_wall();
    let a = [kat_agent(v(2.0, 5.0), v(0.5, 0.5), 0), kat_agent(v(2.0, 0.0), v(1.0, 0.0), 1)];
    let out = solve(kat_params(), &a, &wall, 0.1);
    assert!(out.iter().all(|o| o.x.is_finite() && o.y.is_finite() && o.norm() <= 1.0));
    // On the left edge, moving into the wall: the edge line forbids any +x component.
    assert!(out[1].x <= 1e-12, "{:?}", out[1]);
}

#[test]
fn nan_agent_stops_and_is_invisible_to_others() {
    let mut bad = kat_agent(v(f64::NAN, 0.0), v(1.0, 0.0), 5);
    let good = kat_agent(v(0.0, 0.0), v(1.0, 0.0), 6);
    let out = solve(kat_params(), &[bad, good], &ObstacleSet::empty(), 0.1);
    assert_eq!(out[0], Vec2::zeros());
    assert_close(out[1], v(1.0, 0.0), 1e-12);
    for field in 0..4 {
        bad = kat_agent(v(0.0, 0.0), v(1.0, 0.0), 5);
        match field {
            0 => bad.vel.y = f64::INFINITY,
            1 => bad.pref_vel.x = f64::NAN,
            2 => bad.radius = -1.0,
            _ => bad.max_speed = f64::NAN,
        }
        let mut orca = Orca::new(kat_params()).expect("params");
        let mut out = vec![v(9.0, 9.0); 2];
        orca.compute(&[bad, good], &[0, 1], &ObstacleSet::empty(), 0.1, 0, &mut out).expect("compute");
        assert_eq!(out[0], Vec2::zeros());
        assert_eq!(orca.stats().invalid_agents, 1);
        assert_eq!(orca.stats().neighbors, 0, "the invalid agent is nobody's neighbour");
    }
}

#[test]
fn bad_arguments_are_errors() {
    assert!(Orca::new(OrcaParams { time_horizon: 0.0, ..OrcaParams::default() }).is_err());
    assert!(Orca::new(OrcaParams { time_horizon_obst: f64::NAN, ..OrcaParams::default() }).is_err());
    assert!(Orca::new(OrcaParams { neighbor_dist: -1.0, ..OrcaParams::default() }).is_err());
    assert!(Orca::new(OrcaParams { perturbation: 2.0, ..OrcaParams::default() }).is_err());
    let mut orca = Orca::new(OrcaParams::default()).expect("params");
    let a = [kat_agent(v(0.0, 0.0), v(1.0, 0.0), 0)];
    let e = ObstacleSet::empty();
    let mut out = vec![Vec2::zeros(); 1];
    assert!(orca.compute(&a, &[0], &e, 0.0, 0, &mut out).is_err());
    assert!(orca.compute(&a, &[0], &e, f64::NAN, 0, &mut out).is_err());
    assert!(orca.compute(&a, &[1], &e, 0.1, 0, &mut out).is_err());
    assert!(orca.compute(&a, &[0], &e, 0.1, 0, &mut []).is_err());
    assert!(ObstacleSet::new(&[vec![v(0.0, 0.0)]]).is_err());
    assert!(ObstacleSet::new(&[vec![v(0.0, 0.0), v(0.0, 0.0)]]).is_err());
    assert!(ObstacleSet::new(&[vec![v(0.0, 0.0), v(f64::NAN, 1.0)]]).is_err());
}

#[test]
fn obstacle_set_orientation_and_convexity() {
    // A clockwise L-shape is reversed; its reflex corner is non-convex.
    let cw = vec![v(0.0, 0.0), v(0.0, 2.0), v(1.0, 2.0), v(1.0, 1.0), v(2.0, 1.0), v(2.0, 0.0), v(0.0, 0.0)];
    let set = ObstacleSet::new(&[cw]).expect("L");
    assert_eq!(set.num_edges(), 6, "closing vertex dropped");
    let area2: f64 = (0..6).map(|i| cross(set.vertices[i].point, set.vertices[(i + 1) % 6].point)).sum();
    assert!(area2 > 0.0);
    let reflex: Vec<Vec2> = set.vertices.iter().filter(|x| !x.convex).map(|x| x.point).collect();
    assert_eq!(reflex, vec![v(1.0, 1.0)]);
    let wall = ObstacleSet::new(&[vec![v(0.0, 0.0), v(1.0, 0.0)]]).expect("thin wall");
    assert!(wall.vertices.iter().all(|x| x.convex));
}

// ---------------------------------------------------------------- scenarios

/// Preferred velocity towards `goal` at `speed`, slowing down to arrive within one step.
fn pref_towards(pos: Vec2, goal: Vec2, speed: f64, dt: f64) -> Vec2 {
    let d = goal - pos;
    let dist = d.norm();
    if dist < 1e-9 { Vec2::zeros() } else { d * (speed.min(dist / dt) / dist) }
}

struct Run {
    /// Positions after every step.
    traj: Vec<Vec<Vec2>>,
    /// Steps until all agents were within `tol` of their goals (None if never).
    arrived_at: Option<usize>,
    min_sep_margin: f64,
    lp3_steps: usize,
}

/// Euler simulation of every agent running ORCA towards its goal.
fn run(
    mut agents: Vec<OrcaAgent>,
    goals: &[Vec2],
    params: OrcaParams,
    obstacles: &ObstacleSet,
    dt: f64,
    steps: usize,
) -> Run {
    let mut orca = Orca::new(params).expect("params");
    let n = agents.len();
    let active: Vec<usize> = (0..n).collect();
    let mut out = vec![Vec2::zeros(); n];
    let mut r = Run { traj: Vec::new(), arrived_at: None, min_sep_margin: f64::INFINITY, lp3_steps: 0 };
    for step in 0..steps {
        for (a, g) in agents.iter_mut().zip(goals) {
            a.pref_vel = pref_towards(a.pos, *g, a.max_speed, dt);
        }
        orca.compute(&agents, &active, obstacles, dt, step as u64, &mut out).expect("compute");
        if orca.last_lp3_fallbacks() > 0 {
            r.lp3_steps += 1;
        }
        for (a, o) in agents.iter_mut().zip(&out) {
            a.vel = *o;
            a.pos += *o * dt;
        }
        for i in 0..n {
            for j in i + 1..n {
                let m = (agents[i].pos - agents[j].pos).norm() - (agents[i].radius + agents[j].radius);
                r.min_sep_margin = r.min_sep_margin.min(m);
            }
        }
        r.traj.push(agents.iter().map(|a| a.pos).collect());
        if r.arrived_at.is_none() && agents.iter().zip(goals).all(|(a, g)| (a.pos - g).norm() < 0.05) {
            r.arrived_at = Some(step + 1);
            break;
        }
    }
    r
}

fn circle(n: usize, radius: f64, agent_radius: f64, speed: f64) -> (Vec<OrcaAgent>, Vec<Vec2>) {
    let agents: Vec<OrcaAgent> = (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            OrcaAgent {
                pos: v(a.cos(), a.sin()) * radius,
                vel: Vec2::zeros(),
                pref_vel: Vec2::zeros(),
                radius: agent_radius,
                max_speed: speed,
                reciprocal: true,
                id: 100 + k as u64,
            }
        })
        .collect();
    let goals = agents.iter().map(|a| -a.pos).collect();
    (agents, goals)
}

#[test]
fn four_robots_cross_through_a_common_centre() {
    // Daza 2021 Fig. 15: four robots on a 4 m circle swap to the opposite sides.
    let (agents, goals) = circle(4, 2.0, 0.3, 0.55);
    let params = OrcaParams::default();
    let r1 = run(agents.clone(), &goals, params, &ObstacleSet::empty(), 0.1, 600);
    assert!(r1.min_sep_margin >= -1e-6, "collision: margin {}", r1.min_sep_margin);
    let t = r1.arrived_at.expect("all four arrive");
    eprintln!("four robots: arrived after {t} steps, min margin {:.4} m", r1.min_sep_margin);
    assert!(t <= 150, "arrived after {t} steps (4 m at 0.55 m/s needs 73)");
    let r2 = run(agents, &goals, params, &ObstacleSet::empty(), 0.1, 600);
    assert_eq!(r1.traj.len(), r2.traj.len());
    for (a, b) in r1.traj.iter().zip(&r2.traj) {
        for (p, q) in a.iter().zip(b) {
            assert_eq!(p.x.to_bits(), q.x.to_bits());
            assert_eq!(p.y.to_bits(), q.y.to_bits());
        }
    }
}

#[test]
fn four_robots_without_the_passing_tilt_deadlock() {
    // The optimum sits at the vertex of two mirror-image half-planes, which the perturbation of the
    // preferred velocity cannot move: the passing-side tilt is what resolves Fig. 15.
    let (agents, goals) = circle(4, 2.0, 0.3, 0.55);
    let params = OrcaParams { pass_tilt: 0.0, ..OrcaParams::default() };
    let r = run(agents, &goals, params, &ObstacleSet::empty(), 0.1, 600);
    assert!(r.arrived_at.is_none());
    assert!(r.min_sep_margin >= -1e-6);
}

#[test]
fn twenty_agents_antipodal_swap_all_arrive() {
    let (agents, goals) = circle(20, 10.0, 0.5, 1.0);
    let params = OrcaParams { time_horizon_obst: 5.0, ..OrcaParams::default() };
    let r1 = run(agents.clone(), &goals, params, &ObstacleSet::empty(), 0.25, 2000);
    let t = r1.arrived_at.expect("all twenty arrive");
    eprintln!(
        "twenty: arrived after {t} steps, LP3 steps {}, min margin {:.4}",
        r1.lp3_steps, r1.min_sep_margin
    );
    assert!(t < 600, "arrived after {t} steps");
    if r1.lp3_steps == 0 {
        assert!(r1.min_sep_margin >= -1e-3, "margin {}", r1.min_sep_margin);
    }
    let r2 = run(agents.clone(), &goals, params, &ObstacleSet::empty(), 0.25, 2000);
    assert_eq!(r1.traj, r2.traj, "deterministic");
    // With the passing-side tilt alone the ring stays feasible throughout, and then no pair overlaps.
    let tilt_only = OrcaParams { perturbation: 0.0, ..params };
    let r = run(agents, &goals, tilt_only, &ObstacleSet::empty(), 0.25, 2000);
    assert!(r.arrived_at.is_some_and(|t| t < 600));
    assert_eq!(r.lp3_steps, 0);
    assert!(r.min_sep_margin >= -1e-3, "margin {}", r.min_sep_margin);
}

#[test]
fn twenty_agents_without_perturbation_deadlock() {
    // The perturbation is what resolves the symmetric ring (pins that the test above can fail).
    let (agents, goals) = circle(20, 10.0, 0.5, 1.0);
    let params =
        OrcaParams { time_horizon_obst: 5.0, perturbation: 0.0, pass_tilt: 0.0, ..OrcaParams::default() };
    let r = run(agents, &goals, params, &ObstacleSet::empty(), 0.25, 600);
    assert!(r.arrived_at.is_none());
}

#[test]
fn robot_avoids_a_non_reciprocating_person_beside_a_wall() {
    // Corridor wall along y = -1 on the robot's right; a person walks straight at constant velocity.
    let wall =
        ObstacleSet::new(&[vec![v(-5.0, -1.5), v(15.0, -1.5), v(15.0, -1.0), v(-5.0, -1.0)]]).expect("wall");
    let dt = 0.1;
    let mut robot = OrcaAgent {
        pos: v(0.0, -0.2),
        vel: Vec2::zeros(),
        pref_vel: Vec2::zeros(),
        radius: 0.3,
        max_speed: 0.55,
        reciprocal: true,
        id: 1,
    };
    let person_vel = v(-1.0, 0.0);
    let mut person = OrcaAgent {
        pos: v(8.0, 0.25),
        vel: person_vel,
        pref_vel: person_vel,
        radius: 0.3,
        max_speed: 1.5,
        reciprocal: false,
        id: 2,
    };
    let goal = v(10.0, -0.2);
    let mut orca = Orca::new(OrcaParams::default()).expect("params");
    let mut out = vec![Vec2::zeros(); 2];
    let mut min_person = f64::INFINITY;
    let mut min_wall = f64::INFINITY;
    let mut arrived = false;
    for step in 0..400u64 {
        robot.pref_vel = pref_towards(robot.pos, goal, robot.max_speed, dt);
        orca.compute(&[robot, person], &[0], &wall, dt, step, &mut out).expect("compute");
        robot.vel = out[0];
        robot.pos += out[0] * dt;
        person.pos += person_vel * dt;
        min_person = min_person.min((robot.pos - person.pos).norm());
        min_wall = min_wall.min(robot.pos.y - (-1.0));
        if (robot.pos - goal).norm() < 0.05 {
            arrived = true;
            break;
        }
    }
    assert!(min_person >= 0.6 - 1e-6, "robot touched the person: {min_person}");
    assert!(min_wall >= 0.3 - 1e-6, "robot entered the wall: clearance {min_wall}");
    assert!(arrived, "robot did not reach its goal");
}

#[test]
fn robot_alone_avoids_a_person_that_does_not_reciprocate() {
    // Head-on with a person who keeps walking: with alpha = 1 the robot's own avoidance suffices,
    // with alpha = 1/2 (treating the person as reciprocal) it would not.
    let sim = |reciprocal: bool| {
        let dt = 0.1;
        let mut robot = OrcaAgent {
            pos: v(0.0, 0.0),
            vel: v(0.55, 0.0),
            pref_vel: v(0.55, 0.0),
            radius: 0.3,
            max_speed: 0.55,
            reciprocal: true,
            id: 1,
        };
        let pv = v(-1.0, 0.0);
        let mut person = OrcaAgent {
            pos: v(6.0, 0.05),
            vel: pv,
            pref_vel: pv,
            radius: 0.3,
            max_speed: 1.0,
            reciprocal,
            id: 2,
        };
        let params = OrcaParams { time_horizon: 3.0, ..OrcaParams::default() };
        let mut orca = Orca::new(params).expect("params");
        let mut out = vec![Vec2::zeros(); 2];
        let mut min_d = f64::INFINITY;
        for step in 0..100u64 {
            robot.pref_vel = v(0.55, 0.0);
            orca.compute(&[robot, person], &[0], &ObstacleSet::empty(), dt, step, &mut out).expect("c");
            robot.vel = out[0];
            robot.pos += out[0] * dt;
            person.pos += pv * dt;
            min_d = min_d.min((robot.pos - person.pos).norm());
        }
        min_d
    };
    assert!(sim(false) >= 0.6 - 1e-6, "alpha = 1: min distance {}", sim(false));
}

/// Index of the first step at which A (heading +x) is abreast of B (heading -x), and their
/// positions then.
fn abreast(r: &Run) -> (Vec2, Vec2) {
    let k = r.traj.iter().position(|p| p[0].x >= p[1].x).expect("they pass");
    (r.traj[k][0], r.traj[k][1])
}

#[test]
fn head_on_symmetric_encounter_both_pass_on_their_right() {
    let mk = |x: f64, speed: f64, id: u64| OrcaAgent {
        pos: v(x, 0.0),
        vel: v(speed, 0.0),
        pref_vel: Vec2::zeros(),
        radius: 0.3,
        max_speed: 0.55,
        reciprocal: true,
        id,
    };
    // Starting at rest far apart: the approach stays in the cut-off-disk case (no side of its own);
    // the passing-side perturbation resolves it to the right.
    let agents = vec![mk(0.0, 0.0, 1), mk(8.0, 0.0, 2)];
    let goals = [v(8.0, 0.0), v(0.0, 0.0)];
    let r = run(agents.clone(), &goals, OrcaParams::default(), &ObstacleSet::empty(), 0.1, 1000);
    assert!(r.arrived_at.is_some());
    assert!(r.min_sep_margin >= -1e-6);
    let (a, b) = abreast(&r);
    assert!(a.y < -0.05 && b.y > 0.05, "A {a:?}, B {b:?}");
    // The passing-side tilt alone also resolves it to the right.
    let tilt_only = OrcaParams { perturbation: 0.0, ..OrcaParams::default() };
    let r = run(agents.clone(), &goals, tilt_only, &ObstacleSet::empty(), 0.1, 1000);
    assert!(r.arrived_at.is_some());
    assert!(r.min_sep_margin >= -1e-6);
    let (a, b) = abreast(&r);
    assert!(a.y < -0.05 && b.y > 0.05, "A {a:?}, B {b:?}");
    // Plain RVO2 (neither) never resolves this approach (pins the cases above).
    let params0 = OrcaParams { perturbation: 0.0, pass_tilt: 0.0, ..OrcaParams::default() };
    let r0 = run(agents, &goals, params0, &ObstacleSet::empty(), 0.1, 1000);
    assert!(r0.arrived_at.is_none());
    // Already at speed and close (closing speed above distance / tau): the velocity-obstacle legs
    // apply and the exact tie takes the right leg, even without any perturbation.
    let agents = vec![mk(0.0, 0.55, 1), mk(2.0, -0.55, 2)];
    let goals = [v(6.0, 0.0), v(-4.0, 0.0)];
    let r = run(agents, &goals, params0, &ObstacleSet::empty(), 0.1, 1000);
    assert!(r.arrived_at.is_some());
    assert!(r.min_sep_margin >= -1e-6);
    let (a, b) = abreast(&r);
    assert!(a.y < -0.05 && b.y > 0.05, "A {a:?}, B {b:?}");
}

#[test]
fn perturbation_is_deterministic_and_points_to_the_passing_side() {
    let h = v(0.6, 0.8);
    assert_eq!(perturbation(3, 17, h), perturbation(3, 17, h));
    assert_ne!(perturbation(3, 17, h), perturbation(3, 18, h));
    assert_ne!(perturbation(3, 17, h), perturbation(4, 17, h));
    let right = v(h.y, -h.x);
    let n = 10_000u64;
    let mut mean = Vec2::zeros();
    for s in 0..n {
        let p = perturbation(7, s, h);
        assert!((p.norm() - 1.0).abs() < 1e-12);
        assert!(p.dot(&right) >= 0.0, "always towards the right of the heading");
        mean += p / n as f64;
    }
    // Uniform angle in [-pi/2, pi/2] from the right normal: mean 2/pi to the right, 0 along.
    assert!((mean.dot(&right) - 2.0 / std::f64::consts::PI).abs() < 0.02, "{mean:?}");
    assert!(mean.dot(&h).abs() < 0.02, "{mean:?}");
}

/// Signed clearance of a disc centre from a set of polygons: the distance to the nearest edge, negative
/// when inside a polygon (or on its boundary).
fn clearance(p: Vec2, polys: &[Vec<Vec2>]) -> f64 {
    let mut best = f64::INFINITY;
    for poly in polys {
        let n = poly.len();
        let mut inside = n >= 3;
        let mut d = f64::INFINITY;
        for i in 0..n {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            d = d.min(distance_squared_point_segment(p, a, b).sqrt());
            if n >= 3 && cross(b - a, p - a) < 0.0 {
                inside = false; // CCW convex polygons only: right of an edge means outside
            }
        }
        best = best.min(if inside { -d } else { d });
    }
    best
}

#[test]
fn pairwise_random_crossings_never_overlap_when_feasible() {
    // Collision-free property: two agents crossing at random angles and offsets, 1000 steps in all.
    let mut s = 12345u64;
    let mut rnd = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64)
    };
    let mut violations = 0;
    let mut steps_total = 0;
    while steps_total < 1000 {
        let th = rnd() * std::f64::consts::TAU;
        let off = rnd() - 0.5;
        let a0 = v(-4.0, off);
        let b0 = v(4.0 * th.cos(), 4.0 * th.sin());
        let agents = vec![kat_agent(a0, Vec2::zeros(), 1), kat_agent(b0, Vec2::zeros(), 2)];
        let goals = [-a0, -b0];
        let r = run(agents, &goals, kat_params(), &ObstacleSet::empty(), 0.25, 100);
        steps_total += r.traj.len();
        if r.lp3_steps == 0 && r.min_sep_margin < -1e-9 {
            violations += 1;
        }
    }
    assert_eq!(violations, 0);
}

#[test]
fn walls_are_never_penetrated() {
    // Agents criss-cross a field of boxes, a thin wall and a non-convex L; no centre ever comes closer
    // than its radius to an obstacle (within 1e-6 m).
    let polys = vec![
        vec![v(-1.0, -1.0), v(1.0, -1.0), v(1.0, 1.0), v(-1.0, 1.0)],
        vec![v(3.0, 2.0), v(4.0, 2.0), v(4.0, 5.0), v(3.0, 5.0)],
        vec![v(-4.0, -4.5), v(-2.5, -4.5), v(-2.5, -3.0), v(-4.0, -3.0)],
    ];
    let thin = vec![v(-3.0, 3.0), v(-1.0, 4.5)];
    let ell = vec![v(2.0, -5.0), v(5.0, -5.0), v(5.0, -4.0), v(3.0, -4.0), v(3.0, -2.0), v(2.0, -2.0)];
    let mut all = polys.clone();
    all.push(thin.clone());
    all.push(ell.clone());
    let set = ObstacleSet::new(&all).expect("obstacles");
    // The L split into two convex pieces for the clearance check.
    let mut convex = polys.clone();
    convex.push(vec![v(2.0, -5.0), v(5.0, -5.0), v(5.0, -4.0), v(2.0, -4.0)]);
    convex.push(vec![v(2.0, -4.0), v(3.0, -4.0), v(3.0, -2.0), v(2.0, -2.0)]);
    let thin_clear = |p: Vec2| distance_squared_point_segment(p, thin[0], thin[1]).sqrt();
    for seed in 0..6u64 {
        let (mut agents, _) = circle(12, 8.0, 0.3, 1.0);
        for (k, a) in agents.iter_mut().enumerate() {
            let ang = (seed as f64) * 0.37 + k as f64 * 0.1;
            a.pos = rotate_vec(a.pos, ang);
        }
        let goals: Vec<Vec2> = agents.iter().map(|a| -a.pos).collect();
        let params = OrcaParams { time_horizon_obst: 2.0, ..OrcaParams::default() };
        let mut orca = Orca::new(params).expect("params");
        let active: Vec<usize> = (0..agents.len()).collect();
        let mut out = vec![Vec2::zeros(); agents.len()];
        assert!(agents.iter().all(|a| clearance(a.pos, &convex).min(thin_clear(a.pos)) > 0.5));
        for step in 0..600u64 {
            for (a, g) in agents.iter_mut().zip(&goals) {
                a.pref_vel = pref_towards(a.pos, *g, a.max_speed, 0.1);
            }
            orca.compute(&agents, &active, &set, 0.1, step, &mut out).expect("compute");
            for (a, o) in agents.iter_mut().zip(&out) {
                a.vel = *o;
                a.pos += *o * 0.1;
                let c = clearance(a.pos, &convex).min(thin_clear(a.pos));
                assert!(c >= a.radius - 1e-6, "seed {seed} step {step}: agent {} clearance {c}", a.id);
            }
        }
        let far = agents.iter().zip(&goals).filter(|(a, g)| (a.pos - *g).norm() > 0.5).count();
        assert!(far <= 2, "seed {seed}: {far} agents far from their goals");
    }
}

fn rotate_vec(p: Vec2, a: f64) -> Vec2 {
    let (s, c) = a.sin_cos();
    v(c * p.x - s * p.y, s * p.x + c * p.y)
}
