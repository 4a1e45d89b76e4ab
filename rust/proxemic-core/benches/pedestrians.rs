//! Pedestrian update cost per person-step at 50, 200 and 1000 people, at the museum's density
//! (29 people on 864 m^2), in a square hall with walls and pillars.
#![allow(missing_docs)] // criterion_group! generates an undocumented public function

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use proxemic_core::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use proxemic_core::math::Vec2;
use proxemic_core::pedestrians::{Crowd, SocialForceParams};
use proxemic_core::scenario::Randomize;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

#[path = "../examples/common/mod.rs"]
mod common;
use common::{hall, walkers};

/// Criterion's `time:` line is the cost per person-step (one 0.1 s step of the whole crowd divided by
/// the number of people), its `thrpt:` line person-steps per second.
fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("pedestrians/per_person_step_0.1s");
    for n in [50usize, 200, 1000] {
        let side = (n as f64 * 864.0 / 29.0).sqrt();
        let geom = hall(side).expect("valid hall");
        let spec = GridSpec::covering(geom.bounds(), 0.1).expect("valid grid");
        let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let persons = walkers(n, side, &mut rng);
        let mut crowd = Crowd::spawn(&persons, &Randomize::default(), SocialForceParams::default(), &mut rng);
        let robots = [(Vec2::new(side / 2.0, side / 2.0), 0.24, Vec2::zeros())];
        for _ in 0..50 {
            crowd.step(0.1, &robots, &geom, &field);
        }
        group.throughput(Throughput::Elements(1));
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter_custom(|iters| {
                let t0 = Instant::now();
                for _ in 0..iters {
                    crowd.step(0.1, &robots, &geom, &field);
                }
                t0.elapsed() / n as u32
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
