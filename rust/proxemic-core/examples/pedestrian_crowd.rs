//! Pedestrian update cost per person-step, for `benches/pedestrians_vs_navground.py`.
//!
//! usage: `cargo run --release --example pedestrian_crowd -- N STEPS [REPS [SEED0]]`
//!
//! The world is the criterion bench's (`benches/pedestrians.rs`): N walkers at the museum's density
//! (864 m^2 for 29 people) in a square hall with walls and a pillar every 8 m, each walking a route
//! through three random points at 1.2 m/s, one in five in a group of two, one robot standing in the
//! middle; the social force model with its default parameters, one 0.1 s step per control step.
//!
//! Per repetition (seeds `SEED0..SEED0 + REPS`, default 0): 20 warm-up steps, then `STEPS` timed
//! steps. Prints one JSON line with the median wall and thread-CPU microseconds per person-step.
#![allow(missing_docs)]

use proxemic_core::map::grid::{DistanceField, GridSpec, OccupancyGrid};
use proxemic_core::math::Vec2;
use proxemic_core::pedestrians::{Crowd, SocialForceParams};
use proxemic_core::scenario::Randomize;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

mod common;
use common::{AREA_PER_PERSON, hall, median, time_per, walkers};

const DT: f64 = 0.1;
const WARMUP: usize = 20;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let parse = |i: usize, default: usize| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default);
    let n = parse(1, 200).max(1);
    let steps = parse(2, 100).max(1);
    let reps = parse(3, 5).max(1);
    let seed0 = parse(4, 0) as u64;
    let side = (n as f64 * AREA_PER_PERSON).sqrt();
    let geom = match hall(side) {
        Ok(g) => g,
        Err(e) => {
            eprintln!("pedestrian_crowd: hall: {e}");
            std::process::exit(1);
        }
    };
    let Ok(spec) = GridSpec::covering(geom.bounds(), 0.1) else {
        eprintln!("pedestrian_crowd: the hall's grid is too large");
        std::process::exit(1);
    };
    let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
    let robots = [(Vec2::new(side / 2.0, side / 2.0), 0.24, Vec2::zeros())];
    let (mut wall, mut cpu) = (Vec::new(), Vec::new());
    let mut speed = 0.0;
    for seed in seed0..seed0 + reps as u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let people = walkers(n, side, &mut rng);
        let mut crowd = Crowd::spawn(&people, &Randomize::default(), SocialForceParams::default(), &mut rng);
        for _ in 0..WARMUP {
            crowd.step(DT, &robots, &geom, &field);
        }
        let (w_us, c_us) = time_per(steps * n, || {
            for _ in 0..steps {
                crowd.step(DT, &robots, &geom, &field);
            }
        });
        wall.push(w_us);
        cpu.extend(c_us);
        speed += crowd.vel.iter().map(|v| v.norm()).sum::<f64>() / n as f64 / reps as f64;
    }
    println!(
        "{{\"impl\": \"proxemic\", \"n\": {n}, \"steps\": {steps}, \"reps\": {reps}, \"side_m\": {side:.2}, \
         \"us_per_person_step_median\": {:.4}, \"cpu_us_per_person_step_median\": {:.4}, \
         \"mean_speed\": {speed:.3}}}",
        median(wall),
        median(cpu),
    );
}
