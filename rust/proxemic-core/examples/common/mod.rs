//! Shared by the speed examples and the pedestrian and ORCA criterion benches (included there by
//! path): the crowd world and the ORCA crossing they time, the robots' kinematics without MuJoCo
//! (the integration tests' own, `tests/common/kinematics.rs`, included by path), and the timer,
//! thread-CPU clock and median they report with.
#![allow(dead_code)] // each includer uses its part

use proxemic_core::control::orca::OrcaAgent;
use proxemic_core::map::geometry::{Bounds, StaticGeometry};
use proxemic_core::math::Vec2;
use proxemic_core::scenario::{Behaviour, Person, Reaction};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

#[path = "../../tests/common/kinematics.rs"]
mod kinematics;
#[allow(unused_imports)] // the examples that drive robots use it
pub use kinematics::kinematics;

/// Square metres per person in the first museum (864 m^2, 29 people): the crowd's density.
pub const AREA_PER_PERSON: f64 = 864.0 / 29.0;

/// A square hall of `side` metres with 0.2 m walls and a 0.6 m pillar every 8 m.
pub fn hall(side: f64) -> Result<StaticGeometry, String> {
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
    };
    let mut polys = vec![
        rect(-0.2, -0.2, side + 0.2, 0.0),
        rect(-0.2, side, side + 0.2, side + 0.2),
        rect(-0.2, 0.0, 0.0, side),
        rect(side, 0.0, side + 0.2, side),
    ];
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
        .map_err(|e| e.to_string())
}

/// `n` walkers, each on a route through three random points of the hall at 1.2 m/s, one in five
/// in a group of two.
pub fn walkers(n: usize, side: f64, rng: &mut ChaCha8Rng) -> Vec<Person> {
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
                reaction: Reaction::Aware,
                features: vec![],
                ..Person::default()
            }
        })
        .collect()
}

/// navground's `Cross` scenario at 4 m^2 per agent: `n` agents of `radius` (m) placed at random
/// (seeded by `seed`) without overlap, 0.1 m apart at least, in a square of side `2 sqrt(n)` m
/// centred on the origin, at rest, reciprocal, at most `max_speed` (m/s); agent `k` shuttles
/// between the mid-points of two opposite sides (four groups: +x, -x, +y, -y), its two targets
/// returned beside it.
pub fn cross_agents(n: usize, seed: u64, radius: f64, max_speed: f64) -> (Vec<OrcaAgent>, Vec<[Vec2; 2]>) {
    let h = (n as f64).sqrt();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pos: Vec<Vec2> = Vec::with_capacity(n);
    while pos.len() < n {
        let p = Vec2::new(rng.random_range(-h..h), rng.random_range(-h..h));
        if pos.iter().all(|q| (p - q).norm() >= 2.0 * radius + 0.1) {
            pos.push(p);
        }
    }
    let targets = (0..n)
        .map(|k| match k % 4 {
            0 => [Vec2::new(h, 0.0), Vec2::new(-h, 0.0)],
            1 => [Vec2::new(-h, 0.0), Vec2::new(h, 0.0)],
            2 => [Vec2::new(0.0, h), Vec2::new(0.0, -h)],
            _ => [Vec2::new(0.0, -h), Vec2::new(0.0, h)],
        })
        .collect();
    let agents = pos
        .iter()
        .enumerate()
        .map(|(k, &p)| OrcaAgent {
            pos: p,
            vel: Vec2::zeros(),
            pref_vel: Vec2::zeros(),
            radius,
            max_speed,
            reciprocal: true,
            id: k as u64,
        })
        .collect();
    (agents, targets)
}

/// Runs `f` once and returns its wall time and this thread's CPU time per unit of `units`
/// (microseconds); the CPU time is `None` where the thread clock is unavailable.
pub fn time_per(units: usize, f: impl FnOnce()) -> (f64, Option<f64>) {
    let c0 = thread_cpu_ns();
    let t0 = Instant::now();
    f();
    let el = t0.elapsed().as_secs_f64();
    let c1 = thread_cpu_ns();
    let per = units as f64;
    (el / per * 1e6, c0.zip(c1).map(|(a, b)| (b - a) as f64 / per * 1e-3))
}

/// Nanoseconds this thread has spent on a CPU (Linux `schedstat`), if available.
pub fn thread_cpu_ns() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    s.split_whitespace().next()?.parse().ok()
}

/// The median (NaN for no values).
pub fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.is_empty() {
        f64::NAN
    } else if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}
