//! Whole-world control steps: `World::command` plus `World::step` for the robots of
//! `museum_multi` (the museum's 56 people), with the physics replaced by exact integration of the
//! commands (no contacts), so what is timed is the core's share of a parallel env step. Three
//! settings per robot count (4 and 11): policies only (built-in planners off, every robot turning
//! in place, so all stay live and every scan changes, as in `benches/parallel_bench.py`), every
//! robot planning with plain A* (`astar`) and with the full social planner (`social`). Episodes
//! are reset (untimed) when every robot has finished.
//!
//! Also `World::episode_metrics` at the end of a museum episode.
//!
//! Run with `cargo bench --bench world` (add `-- --quick` for a short run; `--profile-time 10`
//! runs one setting for a profiler).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use proxemic_core::control::body_to_world;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::Scenario;
use proxemic_core::world::{PERSON_OUT, World};
use std::time::{Duration, Instant};

const ENVS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs");

struct Sim {
    world: World,
    out: Vec<f64>,
    people: Vec<f64>,
    state: Vec<f64>,
    actions: Vec<f64>,
    seed: u64,
}

impl Sim {
    fn new(robots: usize, planner: Option<&str>) -> Self {
        let mut s = Scenario::from_file(format!("{ENVS}/museum_multi.toml"))
            .expect("museum_multi")
            .with_robots(robots)
            .expect("robots");
        if let Some(p) = planner {
            s = s.with_planner(p).expect("planner");
        }
        let mut world = World::new(s).expect("world");
        let n = world.num_robots();
        let mut actions = vec![f64::NAN; 3 * n];
        if planner.is_none() {
            world.set_planning(&vec![false; n]).expect("planning");
            for a in actions.chunks_exact_mut(3) {
                a.copy_from_slice(&[0.0, 0.0, 0.5]);
            }
        }
        let out = vec![0.0; world.layout().stride * n];
        let people = vec![0.0; world.num_people() * PERSON_OUT];
        let mut sim = Sim { world, out, people, state: vec![0.0; 6 * n], actions, seed: 0 };
        sim.reset();
        sim
    }

    fn reset(&mut self) {
        self.seed += 1;
        self.world.reset(self.seed, &mut self.out, &mut self.people).expect("reset");
        let (stride, pose) = (self.world.layout().stride, self.world.layout().pose.offset);
        for i in 0..self.world.num_robots() {
            self.state[6 * i..6 * i + 3].copy_from_slice(&self.out[i * stride + pose..i * stride + pose + 3]);
            self.state[6 * i + 3..6 * i + 6].fill(0.0);
        }
    }

    /// One control step; returns whether every robot has finished.
    fn step(&mut self) -> bool {
        let lay = self.world.layout();
        let (stride, cmd, flags) = (lay.stride, lay.command.offset, lay.flags.offset);
        let n = self.world.num_robots();
        let dt = 0.1;
        self.world.command(&self.actions, &mut self.out).expect("command");
        for i in 0..n {
            let c = &self.out[i * stride + cmd..i * stride + cmd + 3];
            let th = self.state[6 * i + 2];
            let v = body_to_world(Vec2::new(c[0], c[1]), th);
            self.state[6 * i] += v.x * dt;
            self.state[6 * i + 1] += v.y * dt;
            self.state[6 * i + 2] = th + c[2] * dt;
            self.state[6 * i + 3] = v.x;
            self.state[6 * i + 4] = v.y;
            self.state[6 * i + 5] = c[2];
        }
        let contacts = vec![0u8; n];
        self.world.step(&self.state, &contacts, &mut self.out, &mut self.people).expect("step");
        (0..n).all(|i| self.out[i * stride + flags] > 0.5 || self.out[i * stride + flags + 1] > 0.5)
    }
}

fn world_steps(c: &mut Criterion) {
    let mut group = c.benchmark_group("world_step");
    group.measurement_time(Duration::from_secs(3));
    for robots in [4, 11] {
        for (label, planner) in [("policies", None), ("astar", Some("astar")), ("social", Some("social"))] {
            let mut sim = Sim::new(robots, planner);
            group.bench_function(format!("{robots}_robots/{label}"), |b| {
                b.iter_custom(|iters| {
                    let mut total = Duration::ZERO;
                    for _ in 0..iters {
                        let t0 = Instant::now();
                        let done = sim.step();
                        total += t0.elapsed();
                        if done {
                            sim.reset();
                        }
                    }
                    total
                });
            });
        }
    }
    group.finish();
}

/// The lidar alone: 72 rays, 8 m, from 200 free points of the museum (no discs).
fn museum_scans(c: &mut Criterion) {
    use proxemic_core::map::scan;
    use rand::{Rng, SeedableRng};
    let s = Scenario::from_file(format!("{ENVS}/museum.toml")).expect("museum");
    let world = World::new(s).expect("world");
    let geom = world.geometry();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let b = world.scenario().scene.bounds;
    let mut points = Vec::new();
    while points.len() < 200 {
        let p = Vec2::new(rng.random_range(b[0]..b[2]), rng.random_range(b[1]..b[3]));
        if !geom.contains(p) && geom.distance(p) > 0.3 {
            points.push((p, rng.random_range(-3.0..3.0)));
        }
    }
    let mut out = vec![0.0; 72];
    c.bench_function("lidar/museum_72_rays_200_points", |bch| {
        bch.iter(|| {
            for &(p, h) in &points {
                scan(geom, &[], std::hint::black_box(p), h, 8.0, &mut out).expect("scan");
            }
        });
    });
}

/// `World::episode_metrics` (the post-hoc evaluator, once per episode end) of one robot of
/// `museum_multi` planning with A*, after its episode ran to the end (capped at 3000 steps).
fn episode_metrics(c: &mut Criterion) {
    let mut sim = Sim::new(1, Some("astar"));
    for _ in 0..3000 {
        if sim.step() {
            break;
        }
    }
    c.bench_function("episode_metrics/museum_multi_1_robot_astar", |b| {
        b.iter(|| sim.world.episode_metrics().expect("metrics"));
    });
}

criterion_group!(benches, world_steps, museum_scans, episode_metrics);
criterion_main!(benches);
