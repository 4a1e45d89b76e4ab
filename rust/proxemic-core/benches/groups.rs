//! Group-detection benchmarks: Delaunay for 200 standing + moving people in a 36 x 24 m area
//! (target <= 200 us), from scratch and from one control step to the next with the detector's
//! memory (informational), density and F-formation for 50.
//!
//! Run with `cargo bench --bench groups` (add `-- --quick` for a short run).

#![allow(missing_docs)]

use criterion::{Criterion, criterion_group, criterion_main};
use proxemic_core::groups::{
    DelaunayParams, DensityParams, DetectorMemory, FFormationParams, PersonState, detect, detect_with,
};
use proxemic_core::math::Vec2;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spade::Triangulation;
use std::f64::consts::{PI, TAU};
use std::hint::black_box;
use std::time::Duration;

/// Standing circles facing their centre, walking pairs, and loners (half standing, half walking).
fn scene(n: usize, w: f64, h: f64, seed: u64) -> Vec<PersonState> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut p = Vec::with_capacity(n);
    while p.len() < n {
        let c = Vec2::new(rng.random_range(1.0..w - 1.0), rng.random_range(1.0..h - 1.0));
        match rng.random_range(0..3) {
            0 => {
                let k = rng.random_range(2..6usize).min(n - p.len());
                let r = rng.random_range(0.5..0.9);
                for j in 0..k {
                    let a = j as f64 * TAU / k as f64 + rng.random_range(-0.2..0.2);
                    p.push(PersonState::standing(c + Vec2::new(a.cos(), a.sin()) * r, a + PI));
                }
            }
            1 => {
                let a: f64 = rng.random_range(-PI..PI);
                let v = Vec2::new(a.cos(), a.sin()) * rng.random_range(0.8..1.5);
                for j in 0..2.min(n - p.len()) {
                    let off = Vec2::new(-a.sin(), a.cos()) * (0.7 * j as f64);
                    p.push(PersonState::walking(c + off, v));
                }
            }
            _ => {
                let a: f64 = rng.random_range(-PI..PI);
                let speed = if rng.random_bool(0.5) { 0.0 } else { 1.2 };
                p.push(PersonState { pos: c, heading: a, vel: Vec2::new(a.cos(), a.sin()) * speed });
            }
        }
    }
    p
}

fn bench_groups(c: &mut Criterion) {
    let crowd = scene(200, 36.0, 24.0, 1);
    let fifty = scene(50, 36.0, 24.0, 2);
    let delaunay = DelaunayParams::default().method();
    let density = DensityParams::default().method();
    let fformation = FFormationParams::default().method();
    let mut g = c.benchmark_group("groups");
    g.warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(3));
    g.bench_function("delaunay_200", |b| b.iter(|| detect(black_box(&crowd), &delaunay)));
    // A control step later (0.1 s): each call moves everyone from one state to the other and
    // back, so the detector's memory repairs the previous triangulation every time.
    let later: Vec<PersonState> =
        crowd.iter().map(|p| PersonState { pos: p.pos + p.vel * 0.1, ..*p }).collect();
    let mut memory = DetectorMemory::default();
    let mut flip = false;
    g.bench_function("delaunay_200_next_step", |b| {
        b.iter(|| {
            flip = !flip;
            detect_with(black_box(if flip { &later } else { &crowd }), &delaunay, &mut memory)
        })
    });
    g.bench_function("delaunay_distance_only_200", |b| {
        b.iter(|| detect(black_box(&crowd), &DelaunayParams::distance_only(1.5).method()))
    });
    // The triangulation alone, for the share of the detector's time spent in spade.
    let pts: Vec<spade::Point2<f64>> = crowd.iter().map(|p| spade::Point2::new(p.pos.x, p.pos.y)).collect();
    g.bench_function("spade_bulk_load_200", |b| {
        b.iter(|| spade::DelaunayTriangulation::<spade::Point2<f64>>::bulk_load(black_box(pts.clone())))
    });
    g.bench_function("density_50", |b| b.iter(|| detect(black_box(&fifty), &density)));
    g.bench_function("fformation_50", |b| b.iter(|| detect(black_box(&fifty), &fformation)));
    g.finish();
}

criterion_group!(benches, bench_groups);
criterion_main!(benches);
