//! The core's share of an env step in a large crowd: `World::command` plus `World::step` of a
//! scenario file (e.g. the crowd bench's halls, written by
//! `python benches/crowd_bench.py --write DIR`), the robots on their built-in planners and
//! simulated kinematically (their commands integrated exactly; no MuJoCo, no contacts). Prints
//! the wall time per step (mean, median, and the steps over 5 times the median: the social
//! planner's re-plans; run it on a quiet machine) and a digest of every output of every step, so
//! that a change meant to change nothing can be checked on a large crowd (the same digest before
//! and after).
//!
//! Run: `cargo run --release -p proxemic-core --example crowd_world_timing -- FILE [STEPS]`
//! (100 steps by default).

mod common;

use common::median;
use proxemic_core::scenario::Scenario;
use proxemic_core::world::{PERSON_OUT, World};
use std::time::Instant;

/// FNV-1a over the bits of `values`, folded into `h`.
fn fold(mut h: u64, values: &[f64]) -> u64 {
    for v in values {
        for b in v.to_bits().to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
    h
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: crowd_world_timing FILE [STEPS]");
        std::process::exit(2);
    };
    let steps: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let s = match Scenario::from_file(path) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let dt = s.control_dt();
    let mut w = match World::new(s) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("{path}: {e}");
            std::process::exit(1);
        }
    };
    let lay = *w.layout();
    let n = w.num_robots();
    let mut out = vec![0.0; lay.stride * n];
    let mut people = vec![0.0; w.num_people() * PERSON_OUT];
    if let Err(e) = w.reset(0, &mut out, &mut people) {
        eprintln!("reset: {e}");
        std::process::exit(1);
    }
    let mut digest = fold(fold(0xcbf2_9ce4_8422_2325, &out), &people);
    let mut state = vec![0.0; 6 * n];
    let contacts = vec![0u8; n];
    let actions = vec![f64::NAN; 3 * n];
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t0 = Instant::now();
        if w.command(&actions, &mut out).is_err() {
            break;
        }
        common::kinematics(&w, &out, &mut state, dt);
        if let Err(e) = w.step(&state, &contacts, &mut out, &mut people) {
            eprintln!("step: {e}");
            break;
        }
        times.push(t0.elapsed().as_secs_f64() * 1e6);
        digest = fold(fold(digest, &out), &people);
    }
    let med = median(times.clone());
    let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
    let spikes: Vec<(usize, f64)> =
        times.iter().copied().enumerate().filter(|&(_, t)| t > 5.0 * med).collect();
    let spike_share = spikes.iter().map(|s| s.1).sum::<f64>() / times.len().max(1) as f64;
    println!("{path}: {} people, {} steps", w.num_people(), times.len());
    println!(
        "core step, wall [us]: mean {mean:.0}, median {med:.0}, spikes {} ({spike_share:.0} us of the mean)",
        spikes.len()
    );
    for (k, t) in spikes {
        println!("  step {k}: {t:.0} us");
    }
    println!("digest {digest:016x}");
}
