//! ORCA cost per agent-step on navground's `Cross` scenario, for `benches/orca_vs_navground.py`.
//!
//! usage: `cargo run --release --example orca_agents -- N STEPS [REPS [SEED0]]`
//!
//! The world mirrors navground's `Cross` scenario: N agents placed at
//! random without overlap in a square of side `2 sqrt(N)` m (4 m^2 per agent), agent `k` shuttling
//! between the mid-points of two opposite sides (four groups: +x, -x, +y, -y, switching target within
//! 0.5 m), radius 0.25 m + 0.1 m safety margin, maximum speed 1.5 m/s, preferred speed 1.0 m/s,
//! neighbours within 5 m (navground's `Bounded` range; `ORCA_NEIGHBOR_DIST` in the environment
//! overrides it, to match neighbour counts) with no count limit (navground's ORCA default is 1000),
//! time horizons 10 s, dt = 0.1 s, holonomic Euler integration.
//!
//! Per repetition (seeds `SEED0..SEED0 + REPS`, default 0): 20 warm-up steps, then `STEPS` timed
//! steps (ORCA for every agent + integration + target switching). Prints one JSON line with the
//! median wall and thread-CPU microseconds per agent-step and the mean number of neighbours.

#![allow(missing_docs)]

use proxemic_core::control::orca::{ObstacleSet, Orca, OrcaAgent, OrcaParams};
use proxemic_core::math::Vec2;

mod common;
use common::{cross_agents, median, time_per};

const RADIUS: f64 = 0.35;
const MAX_SPEED: f64 = 1.5;
const PREF_SPEED: f64 = 1.0;
const DT: f64 = 0.1;
const WARMUP: usize = 20;

struct World {
    agents: Vec<OrcaAgent>,
    targets: Vec<[Vec2; 2]>,
    current: Vec<usize>,
}

fn make_world(n: usize, seed: u64) -> World {
    let (agents, targets) = cross_agents(n, seed, RADIUS, MAX_SPEED);
    World { agents, targets, current: vec![0; n] }
}

fn step(w: &mut World, orca: &mut Orca, obstacles: &ObstacleSet, active: &[usize], out: &mut [Vec2], k: u64) {
    for (i, a) in w.agents.iter_mut().enumerate() {
        let mut goal = w.targets[i][w.current[i]];
        if (goal - a.pos).norm() < 0.5 {
            w.current[i] ^= 1;
            goal = w.targets[i][w.current[i]];
        }
        let d = goal - a.pos;
        let dist = d.norm();
        a.pref_vel = if dist > 1e-9 { d * (PREF_SPEED / dist) } else { Vec2::zeros() };
    }
    if let Err(e) = orca.compute(&w.agents, active, obstacles, DT, k, out) {
        eprintln!("orca: {e}");
        std::process::exit(1);
    }
    for (a, v) in w.agents.iter_mut().zip(out.iter()) {
        a.vel = *v;
        a.pos += *v * DT;
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let parse = |i: usize, default: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default);
    let n = parse(1, 200);
    let steps = parse(2, 100);
    let reps = parse(3, 5).max(1);
    let seed0 = parse(4, 0) as u64;
    let params = OrcaParams {
        time_horizon: 10.0,
        time_horizon_obst: 10.0,
        neighbor_dist: std::env::var("ORCA_NEIGHBOR_DIST").ok().and_then(|s| s.parse().ok()).unwrap_or(5.0),
        max_neighbors: 1000,
        ..OrcaParams::default()
    };
    let obstacles = ObstacleSet::empty();
    let mut wall = Vec::new();
    let mut cpu = Vec::new();
    let mut neighbors = Vec::new();
    let mut overlaps = 0usize;
    for seed in seed0..seed0 + reps as u64 {
        let mut w = make_world(n, seed);
        let mut orca = match Orca::new(params) {
            Ok(o) => o,
            Err(e) => {
                eprintln!("orca: {e}");
                std::process::exit(1);
            }
        };
        let active: Vec<usize> = (0..n).collect();
        let mut out = vec![Vec2::zeros(); n];
        for k in 0..WARMUP {
            step(&mut w, &mut orca, &obstacles, &active, &mut out, k as u64);
        }
        let mut nb = 0usize;
        let (w_us, c_us) = time_per(steps * n, || {
            for k in 0..steps {
                step(&mut w, &mut orca, &obstacles, &active, &mut out, (WARMUP + k) as u64);
                nb += orca.stats().neighbors;
            }
        });
        wall.push(w_us);
        cpu.extend(c_us);
        neighbors.push(nb as f64 / (steps * n) as f64);
        for i in 0..n {
            for j in i + 1..n {
                if (w.agents[i].pos - w.agents[j].pos).norm() < 2.0 * RADIUS - 1e-6 {
                    overlaps += 1;
                }
            }
        }
    }
    let cpu_med = if cpu.is_empty() { f64::NAN } else { median(cpu) };
    println!(
        "{{\"impl\": \"proxemic\", \"n\": {n}, \"steps\": {steps}, \"reps\": {reps}, \
         \"us_per_agent_step_median\": {:.4}, \"cpu_us_per_agent_step_median\": {:.4}, \
         \"mean_neighbors\": {:.2}, \"overlaps_last_step\": {:.2}}}",
        median(wall),
        cpu_med,
        neighbors.iter().sum::<f64>() / neighbors.len() as f64,
        overlaps as f64 / reps as f64
    );
}
