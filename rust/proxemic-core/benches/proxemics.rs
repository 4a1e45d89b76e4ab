//! Personal-space and agenda evaluation costs: one person's function over a 100 x 100 grid at
//! 0.1 m (10 000 evaluations, the window a cost map fills around one person), and R(t) lookups.
//!
//! Run with `cargo bench --bench proxemics` (add `-- --quick` for a short run).

#![allow(missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use proxemic_core::chronemics::{Activity, Agenda, AgendaParams};
use proxemic_core::math::Vec2;
use proxemic_core::proxemics::{Asymmetric, PersonalSpace, Pose};
use std::hint::black_box;

fn grid_sum(sp: &PersonalSpace, person: Pose) -> f64 {
    let mut s = 0.0;
    for j in 0..100 {
        for i in 0..100 {
            let p = Vec2::new(person.x - 5.0 + 0.1 * i as f64, person.y - 5.0 + 0.1 * j as f64);
            s += sp.value(person, p);
        }
    }
    s
}

fn placed_sum(sp: &PersonalSpace, person: Pose) -> f64 {
    let placed = sp.at(person);
    let mut s = 0.0;
    for j in 0..100 {
        for i in 0..100 {
            s += placed.value(Vec2::new(person.x - 5.0 + 0.1 * i as f64, person.y - 5.0 + 0.1 * j as f64));
        }
    }
    s
}

fn personal_space(c: &mut Criterion) {
    let mut g = c.benchmark_group("personal_space_100x100");
    g.throughput(Throughput::Elements(10_000));
    let person = Pose::new(3.0, 4.0, 0.7);
    let spaces = [
        ("symmetric", PersonalSpace::DAZA2021),
        ("kirby", PersonalSpace::CALDERITA),
        (
            "asymmetric",
            PersonalSpace::Asymmetric(Asymmetric { front: 1.7, rear: 0.6, right: 0.9, left: 1.3 }),
        ),
    ];
    for (name, sp) in spaces {
        g.bench_function(name, |b| b.iter(|| grid_sum(black_box(&sp), black_box(person))));
        g.bench_function(format!("{name}_placed"), |b| {
            b.iter(|| placed_sum(black_box(&sp), black_box(person)))
        });
    }
    g.finish();
}

fn agenda(c: &mut Criterion) {
    // 10 objects with 4 activities each.
    let mut acts = Vec::new();
    for o in 0..10 {
        for k in 0..4 {
            let start = 3600.0 * (7.0 + 3.0 * k as f64) + 300.0 * o as f64;
            acts.push(Activity::new(format!("object{o}"), start, start + 3600.0));
        }
    }
    let names: Vec<String> = (0..10).map(|o| format!("object{o}")).collect();
    let Ok(ag) = Agenda::new(acts.clone(), AgendaParams::CALDERITA) else { return };
    let mut g = c.benchmark_group("agenda");
    g.throughput(Throughput::Elements(10));
    g.bench_function("cost_10_objects", |b| {
        b.iter(|| names.iter().map(|n| ag.cost(n, black_box(40_000.0))).sum::<f64>())
    });
    g.bench_function("next_change", |b| b.iter(|| ag.next_change(black_box(40_000.0))));
    g.bench_function("build_40_activities", |b| {
        b.iter(|| Agenda::new(black_box(acts.clone()), AgendaParams::CALDERITA).is_ok())
    });
    g.finish();
}

criterion_group!(benches, personal_space, agenda);
criterion_main!(benches);
