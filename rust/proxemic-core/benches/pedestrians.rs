//! Pedestrian update cost per person-step at 50, 200 and 1000 people, at the museum's density
//! (29 people on 864 m^2), in a square hall with walls and pillars.
#![allow(missing_docs)] // criterion_group! generates an undocumented public function

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use proxemic_core::map::geometry::{Bounds, StaticGeometry};
use proxemic_core::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use proxemic_core::math::Vec2;
use proxemic_core::pedestrians::{Crowd, SocialForceParams};
use proxemic_core::scenario::{Behaviour, Person, Randomize};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

fn hall(side: f64) -> StaticGeometry {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
    };
    let mut polys = vec![
        rect(-0.2, -0.2, side + 0.2, 0.0),
        rect(-0.2, side, side + 0.2, side + 0.2),
        rect(-0.2, 0.0, 0.0, side),
        rect(side, 0.0, side + 0.2, side),
    ];
    // a pillar every 8 m
    let mut x = 8.0;
    while x < side - 4.0 {
        let mut y = 8.0;
        while y < side - 4.0 {
            polys.push(rect(x - 0.3, y - 0.3, x + 0.3, y + 0.3));
            y += 8.0;
        }
        x += 8.0;
    }
    StaticGeometry::new(polys, Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(side + 1.0, side + 1.0) })
        .expect("valid hall")
}

fn crowd(n: usize, side: f64, rng: &mut ChaCha8Rng) -> Vec<Person> {
    let mut pt = || Vec2::new(rng.random_range(1.0..side - 1.0), rng.random_range(1.0..side - 1.0));
    (0..n)
        .map(|k| {
            let (a, b, c) = (pt(), pt(), pt());
            Person {
                name: format!("p{k}"),
                behaviour: Behaviour::Walker,
                pose: [a.x, a.y, 0.0],
                route: vec![[a.x, a.y], [b.x, b.y], [c.x, c.y]],
                speed: 1.2,
                dwell: 2.0,
                radius: 0.2,
                height: 1.7,
                group: if k % 10 < 2 { Some((k / 10) as u32) } else { None },
                aware: true,
                features: vec![],
                ..Person::default()
            }
        })
        .collect()
}

/// Criterion's `time:` line is the cost per person-step (one 0.1 s step of the whole crowd divided by
/// the number of people), its `thrpt:` line person-steps per second.
fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("pedestrians/per_person_step_0.1s");
    for n in [50usize, 200, 1000] {
        let side = (n as f64 * 864.0 / 29.0).sqrt();
        let geom = hall(side);
        let spec = GridSpec::covering(geom.bounds(), 0.1).expect("valid grid");
        let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
        let mut rng = ChaCha8Rng::seed_from_u64(1);
        let persons = crowd(n, side, &mut rng);
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
