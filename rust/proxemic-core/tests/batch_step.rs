//! `world::batch`: several worlds stepped in threads give, bit for bit, what stepping them one by
//! one gives; a bad world's input is refused before any world changes. The robots are simulated
//! kinematically (their commands integrated exactly; no MuJoCo).

use proxemic_core::world::batch::{command_batch, step_batch};
use proxemic_core::world::{PERSON_OUT, World};

mod common;
use common::{env_scenario, kinematics};

/// Worlds of `name` reset with `seeds`, their buffers end to end.
fn worlds(name: &str, seeds: &[u64]) -> (Vec<World>, Vec<f64>, Vec<f64>) {
    let s = env_scenario(name);
    let mut ws = Vec::new();
    let mut out = Vec::new();
    let mut people = Vec::new();
    for &seed in seeds {
        let mut w = World::new(s.clone()).expect("valid world");
        let mut o = vec![0.0; w.layout().stride * w.num_robots()];
        let mut p = vec![0.0; w.num_people() * PERSON_OUT];
        w.reset(seed, &mut o, &mut p).expect("reset");
        out.extend(o);
        people.extend(p);
        ws.push(w);
    }
    (ws, out, people)
}

/// `steps` steps of every world with fixed actions, batched over `threads` threads (0: one by one
/// through `World::command` / `World::step`); the outputs after every step.
fn run(name: &str, seeds: &[u64], steps: usize, threads: usize) -> Vec<(Vec<f64>, Vec<f64>)> {
    let (mut ws, mut out, mut people) = worlds(name, seeds);
    let dt = env_scenario(name).control_dt();
    let n = ws[0].num_robots();
    let (width, pwidth) = (out.len() / ws.len(), people.len() / ws.len());
    // World k's robot 0 driven by an action, other robots on their planners.
    let mut actions = vec![f64::NAN; 3 * n * ws.len()];
    for k in 0..ws.len() {
        actions[3 * n * k..3 * n * k + 3].copy_from_slice(&[0.6, 0.1 * k as f64, -0.2]);
    }
    let mut state = vec![0.0; 6 * n * ws.len()];
    let contacts = vec![0u8; n * ws.len()];
    let mut trace = Vec::new();
    for _ in 0..steps {
        if threads == 0 {
            for (k, w) in ws.iter_mut().enumerate() {
                let o = &mut out[k * width..(k + 1) * width];
                w.command(&actions[3 * n * k..3 * n * (k + 1)], o).expect("command");
                kinematics(w, o, &mut state[6 * n * k..6 * n * (k + 1)], dt);
                let p = &mut people[k * pwidth..(k + 1) * pwidth];
                w.step(&state[6 * n * k..6 * n * (k + 1)], &contacts[n * k..n * (k + 1)], o, p)
                    .expect("step");
            }
        } else {
            let mut refs: Vec<&mut World> = ws.iter_mut().collect();
            command_batch(&mut refs, &actions, &mut out).expect("command_batch");
            for (k, w) in refs.iter().enumerate() {
                kinematics(w, &out[k * width..(k + 1) * width], &mut state[6 * n * k..6 * n * (k + 1)], dt);
            }
            step_batch(&mut refs, &state, &contacts, &mut out, &mut people, threads).expect("step_batch");
        }
        trace.push((out.clone(), people.clone()));
    }
    trace
}

#[test]
fn batched_steps_in_threads_equal_one_by_one_steps() {
    for name in ["museum", "museum_multi"] {
        let seeds = [3, 4, 5];
        let serial = run(name, &seeds, 30, 0);
        for threads in [1, 2, 3, 8] {
            let batched = run(name, &seeds, 30, threads);
            for (t, (a, b)) in serial.iter().zip(&batched).enumerate() {
                // bit for bit (NaN-free outputs: == on every value)
                assert!(a.0 == b.0 && a.1 == b.1, "{name}, {threads} threads: step {t} differs");
            }
        }
        // the worlds' episodes differ (seeds and actions): the batch does not mix them up
        let last = &serial[29].0;
        let width = last.len() / seeds.len();
        assert!(last[..width] != last[width..2 * width]);
    }
}

#[test]
fn a_bad_world_is_refused_before_any_world_changes() {
    let (mut ws, mut out, mut people) = worlds("museum", &[1, 2]);
    let before = (out.clone(), people.clone(), ws[0].steps());
    let mut refs: Vec<&mut World> = ws.iter_mut().collect();
    // world 1's action is half NaN
    let bad = [0.1, 0.0, 0.0, f64::NAN, 0.0, 0.0];
    let err = command_batch(&mut refs, &bad, &mut out).expect_err("refused");
    assert!(err.to_string().starts_with("worlds[1].action[0]"), "{err}");
    assert_eq!(out, before.0);
    // world 1's state is not finite
    let mut state = vec![0.0; 12];
    state[6] = f64::INFINITY;
    let err = step_batch(&mut refs, &state, &[0, 0], &mut out, &mut people, 2).expect_err("refused");
    assert!(err.to_string().starts_with("worlds[1].state[0][0]"), "{err}");
    assert_eq!((out, people, refs[0].steps()), before);
    // buffers of the wrong total size
    let err = step_batch(&mut refs, &state[..6], &[0, 0], &mut [0.0; 3], &mut [], 2).expect_err("refused");
    assert!(err.to_string().starts_with("state: expected 12 values"), "{err}");
}
