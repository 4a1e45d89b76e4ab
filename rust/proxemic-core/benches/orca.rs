//! ORCA cost per agent-step at N = 10, 200 and 1000 agents.
//!
//! The crossing of navground's `Cross` scenario at constant density (4 m^2 per agent, side
//! `2 sqrt(N)` m): agents shuttle between the mid-points of two opposite sides; r = 0.35 m,
//! V = 1.5 m/s, preferred speed 1 m/s, neighbours within 5 m (no count limit), tau = tau_o = 10 s,
//! dt = 0.1 s. Two variants: `all_neighbors` (as navground) and `max10` (the default
//! `max_neighbors = 10`). The world is warmed up for 40 steps, then one iteration is one
//! [`Orca::compute`] over all agents on that frozen snapshot (throughput = N agent-steps).
//!
//! Run with `cargo bench --bench orca` (add `-- --quick` for a short run). The side-by-side with
//! navground is `benches/orca_vs_navground.py` at the repository root.

#![allow(missing_docs)]

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use proxemic_core::control::orca::{ObstacleSet, Orca, OrcaAgent, OrcaParams};
use proxemic_core::math::Vec2;
use std::hint::black_box;
use std::time::Duration;

#[path = "../examples/common/mod.rs"]
mod common;
use common::cross_agents;

const RADIUS: f64 = 0.35;
const DT: f64 = 0.1;

/// Agents and their two shuttle targets (the example `orca_agents`'s crossing).
fn world(n: usize, seed: u64) -> (Vec<OrcaAgent>, Vec<[Vec2; 2]>) {
    cross_agents(n, seed, RADIUS, 1.5)
}

/// A snapshot of the crossing after `warmup` steps.
fn warmed(n: usize, params: OrcaParams, warmup: usize) -> Vec<OrcaAgent> {
    let (mut agents, targets) = world(n, 0);
    let mut current = vec![0usize; n];
    let mut orca = Orca::new(params).expect("params");
    let active: Vec<usize> = (0..n).collect();
    let mut out = vec![Vec2::zeros(); n];
    for k in 0..warmup {
        for (i, a) in agents.iter_mut().enumerate() {
            if (targets[i][current[i]] - a.pos).norm() < 0.5 {
                current[i] ^= 1;
            }
            let d = targets[i][current[i]] - a.pos;
            a.pref_vel = d / d.norm().max(1e-9);
        }
        orca.compute(&agents, &active, &ObstacleSet::empty(), DT, k as u64, &mut out).expect("compute");
        for (a, v) in agents.iter_mut().zip(&out) {
            a.vel = *v;
            a.pos += *v * DT;
        }
    }
    agents
}

fn orca(c: &mut Criterion) {
    let mut g = c.benchmark_group("orca_agent_step");
    let base = OrcaParams {
        time_horizon: 10.0,
        time_horizon_obst: 10.0,
        neighbor_dist: 5.0,
        ..OrcaParams::default()
    };
    for (name, max_neighbors) in [("all_neighbors", 1000), ("max10", 10)] {
        let params = OrcaParams { max_neighbors, ..base };
        for n in [10usize, 200, 1000] {
            let agents = warmed(n, params, 40);
            let active: Vec<usize> = (0..n).collect();
            let mut solver = Orca::new(params).expect("params");
            let mut out = vec![Vec2::zeros(); n];
            let obstacles = ObstacleSet::empty();
            g.throughput(Throughput::Elements(n as u64));
            g.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| {
                    solver
                        .compute(black_box(&agents), &active, &obstacles, DT, 7, &mut out)
                        .expect("compute");
                    black_box(&out);
                })
            });
        }
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(30)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = orca
}
criterion_main!(benches);
