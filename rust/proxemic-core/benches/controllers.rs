//! Local controller benchmarks: a Social Momentum step with 10, 50 and 200 people (median and 99th
//! percentile of single calls, target <= 20 us median at 50 people), the same step as the
//! `daza2021` planner runs it (Daza et al. 2021: intimate discs and group o-spaces, no comfort
//! term) and as `sousa2022` runs it (Sousa et al. 2022: the individuals' fully asymmetric
//! Gaussians, built in the step) at 50 people (target <= 20 us too), and an elastic-band update
//! on a 20 m path. `benches/criterion_targets.py` checks the medians against the targets.
//!
//! Run with `cargo bench --bench controllers` (add `-- --quick` for a short run).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use proxemic_core::control::Limits;
use proxemic_core::control::daza2021::{
    Daza2021Params, MobileObject, PeopleSpaces, RobotState, daza2021_decide, daza2021_social_momentum,
};
use proxemic_core::control::eband::{EbandParams, ElasticBand};
use proxemic_core::control::social_momentum::{Agent, SocialMomentumParams, social_momentum};
use proxemic_core::groups::PersonState;
use proxemic_core::map::{Bounds, DistanceField, GridSpec, OccupancyGrid, StaticGeometry};
use proxemic_core::math::Vec2;
use proxemic_core::perception::{Individual, ProxemicsConfig, perceive};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::time::{Duration, Instant};

const DT: f64 = 0.1;
const ROBOT_RADIUS: f64 = 0.3;

fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Vec2> {
    vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
}

/// A 24 x 12 m hall: outer walls and six display cases.
fn hall() -> StaticGeometry {
    let (w, h, t) = (24.0, 12.0, 0.2);
    let mut p =
        vec![rect(0.0, 0.0, w, t), rect(0.0, h - t, w, h), rect(0.0, 0.0, t, h), rect(w - t, 0.0, w, h)];
    for (x, y) in [(4.0, 2.0), (9.0, 8.5), (12.5, 3.0), (16.0, 8.0), (19.0, 2.5), (6.5, 6.8)] {
        p.push(rect(x, y, x + 1.6, y + 0.8));
    }
    StaticGeometry::new(p, Bounds { min: Vec2::new(0.0, 0.0), max: Vec2::new(w, h) }).expect("valid hall")
}

struct Scene {
    pos: Vec2,
    vel: Vec2,
    goal: Vec2,
    people: Vec<Agent>,
}

/// `count` scenes with `n` people each, spread over the hall (at least `min_dist` m from the
/// robot) and walking at up to 1.3 m/s; the robot is near the middle, moving, with a partial goal
/// 2 m ahead.
fn scenes(geom: &StaticGeometry, n: usize, count: usize, seed: u64, min_dist: f64) -> Vec<Scene> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::with_capacity(count);
    while out.len() < count {
        let pos = Vec2::new(rng.random_range(9.0..15.0), rng.random_range(4.5..7.5));
        if geom.distance(pos) < ROBOT_RADIUS + 0.2 {
            continue;
        }
        let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let dir = Vec2::new(a.cos(), a.sin());
        let mut people = Vec::with_capacity(n);
        while people.len() < n {
            let p = Vec2::new(rng.random_range(0.5..23.5), rng.random_range(0.5..11.5));
            if (p - pos).norm() < min_dist || geom.contains(p) {
                continue;
            }
            let b: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let s = rng.random_range(0.0..1.3);
            people.push(Agent {
                pos: p,
                vel: Vec2::new(b.cos(), b.sin()) * s,
                radius: 0.3,
                weight: 1.0,
                comfort: 1.2,
            });
        }
        out.push(Scene { pos, vel: dir * 0.4, goal: pos + dir * 2.0, people });
    }
    out
}

/// A scene as Daza et al. 2021's Algorithm 1 sees it, with the perception's groups and individuals.
struct PaperScene {
    robot: RobotState,
    /// The line-1 path the partial goal lies on.
    path: [Vec2; 2],
    vel: Vec2,
    objects: Vec<MobileObject>,
    groups: Vec<Vec<usize>>,
    decision: proxemic_core::control::daza2021::Daza2021Decision,
    individuals: Vec<Individual>,
}

fn sm_step(s: &Scene, geom: &StaticGeometry, params: &SocialMomentumParams) -> Option<Vec2> {
    social_momentum(s.pos, s.vel, ROBOT_RADIUS, s.goal, &s.people, Some(geom), &Limits::PEPPER, DT, params)
}

/// Median and 99th percentile (microseconds) of `reps` single calls cycling over the scenes.
fn percentiles(
    scenes: &[Scene],
    geom: &StaticGeometry,
    params: &SocialMomentumParams,
    reps: usize,
) -> (f64, f64) {
    let mut t = Vec::with_capacity(reps);
    for k in 0..reps {
        let s = &scenes[k % scenes.len()];
        let t0 = Instant::now();
        black_box(sm_step(black_box(s), geom, params));
        t.push(t0.elapsed().as_secs_f64() * 1e6);
    }
    t.sort_by(f64::total_cmp);
    (t[reps / 2], t[(reps * 99) / 100])
}

fn benches(c: &mut Criterion) {
    let geom = hall();
    let params = SocialMomentumParams::default();

    for n in [10usize, 50, 200] {
        // Stopping scenes (every sample collides) exit early, so also report scenes where nobody
        // is within 2 m (few stops).
        for min_dist in [2.0, 0.8] {
            let sc = scenes(&geom, n, 64, 42 + n as u64, min_dist);
            let stops = sc.iter().filter(|s| sm_step(s, &geom, &params).is_none()).count();
            // Warm up, then report single-call percentiles (criterion reports means of batches).
            percentiles(&sc, &geom, &params, 2000);
            let (med, p99) = percentiles(&sc, &geom, &params, 20000);
            eprintln!(
                "social_momentum step, {n} people (>= {min_dist} m away): median {med:.2} us, \
                 p99 {p99:.2} us ({stops}/64 scenes stop)"
            );
        }
        let sc = scenes(&geom, n, 64, 42 + n as u64, 0.8);
        let mut k = 0usize;
        c.bench_function(&format!("sm/step_{n}_people"), |b| {
            b.iter(|| {
                k = (k + 1) % sc.len();
                black_box(sm_step(black_box(&sc[k]), &geom, &params))
            })
        });
    }

    // The paper planners' Social Momentum at 50 people: Algorithm 1's agents (and, for sousa2022,
    // the Gaussians of the perceived individuals) are built in the timed step, as the world does
    // every step; the perception (groups) is shared by every robot and done once per step.
    let params = Daza2021Params::default();
    let cfg = ProxemicsConfig::default();
    let paper: Vec<PaperScene> = scenes(&geom, 50, 64, 92, 0.8)
        .into_iter()
        .map(|s| {
            let objects: Vec<MobileObject> = s
                .people
                .iter()
                .map(|a| MobileObject { pos: a.pos, vel: a.vel, radius: 0.2, id: None })
                .collect();
            let states: Vec<PersonState> = s
                .people
                .iter()
                .map(|a| PersonState { pos: a.pos, heading: a.vel.y.atan2(a.vel.x), vel: a.vel })
                .collect();
            let per = perceive(&cfg, &states, &vec![Vec::new(); states.len()], &[]).expect("perception");
            let groups: Vec<Vec<usize>> = per.groups.multi().cloned().collect();
            let robot = RobotState { pos: s.pos, pref_vel: s.vel, radius: ROBOT_RADIUS };
            let path = [s.pos, s.goal + (s.goal - s.pos) * 3.0];
            let decision = daza2021_decide(&robot, &path, &objects, &groups, &params).expect("decision");
            PaperScene { robot, path, vel: s.vel, objects, groups, decision, individuals: per.individuals }
        })
        .collect();
    for (name, gaussians) in [("daza2021", false), ("sousa2022", true)] {
        let mut k = 0usize;
        c.bench_function(&format!("sm/{name}_step_50_people"), |b| {
            b.iter(|| {
                k = (k + 1) % paper.len();
                let s = &paper[k];
                let spaces =
                    if gaussians { PeopleSpaces::Gaussians(&s.individuals) } else { PeopleSpaces::Intimate };
                black_box(daza2021_social_momentum(
                    &s.robot,
                    &s.path,
                    s.vel,
                    &s.objects,
                    &s.groups,
                    &s.decision,
                    spaces,
                    Some(&geom),
                    &Limits::PEPPER,
                    DT,
                    &params,
                    None,
                ))
            })
        });
    }

    // Elastic band on a 20 m path across the hall, clearance from a 0.05 m distance field, five
    // people as personal-space Gaussians.
    let spec = GridSpec::covering(geom.bounds(), 0.05).expect("valid grid");
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
    let clearance = |p: Vec2| field.at(p) - ROBOT_RADIUS;
    let people = [Vec2::new(6.0, 5.8), Vec2::new(10.0, 6.3), Vec2::new(13.0, 5.5), Vec2::new(17.5, 6.0)];
    let cost =
        |p: Vec2| people.iter().map(|c| (-(p - c).norm_squared() / (2.0 * 0.45 * 0.45)).exp()).sum::<f64>();
    let path: Vec<Vec2> = (0..=80).map(|k| Vec2::new(2.0 + 0.25 * k as f64, 6.0)).collect();
    let fresh = ElasticBand::new(&path, EbandParams::default()).expect("valid band");
    let mut warm = fresh.clone();
    for _ in 0..50 {
        warm.update(&clearance, Some(&cost));
    }
    eprintln!(
        "eband: 20 m path, {} bubbles after convergence, connected {}, length {:.2} m",
        warm.points().len(),
        warm.is_connected(),
        warm.length()
    );
    c.bench_function("eband/update_20m_fresh", |b| {
        b.iter(|| {
            let mut band = fresh.clone();
            band.update(&clearance, Some(&cost));
            black_box(band.points().len())
        })
    });
    c.bench_function("eband/update_20m_converged", |b| {
        b.iter(|| {
            let mut band = warm.clone();
            band.update(&clearance, Some(&cost));
            black_box(band.points().len())
        })
    });
}

criterion_group! {
    name = controllers;
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = benches
}
criterion_main!(controllers);
