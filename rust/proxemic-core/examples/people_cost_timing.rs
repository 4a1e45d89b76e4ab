//! What the robot's cost to people costs: per episode, the wall-clock time the world spends
//! stepping the people, and the time the robot-free replay of those people takes when the metrics
//! are asked for at the end (`World::people_step_times`). The robots drive on their built-in
//! planners, simulated kinematically (their commands integrated exactly; no MuJoCo).
//!
//! Run: `cargo run --release -p proxemic-core --example people_cost_timing [-- scenario ...]`
//! (default: museum and care_center, seeds 0-2).

mod common;

use proxemic_core::scenario::Scenario;
use proxemic_core::world::{PERSON_OUT, World};

const ENVS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs");

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let names: Vec<&str> = if args.is_empty() {
        vec!["museum", "care_center"]
    } else {
        args.iter().map(String::as_str).collect()
    };
    for name in names {
        let Ok(s) = Scenario::from_file(format!("{ENVS}/{name}.toml")) else {
            eprintln!("{name}: no such scenario");
            continue;
        };
        let dt = s.control_dt();
        let Ok(mut w) = World::new(s) else { continue };
        let lay = *w.layout();
        let n = w.num_robots();
        let (mut total_crowd, mut total_free) = (0.0, 0.0);
        for seed in 0..3u64 {
            let mut out = vec![0.0; lay.stride * n];
            let mut people = vec![0.0; w.num_people() * PERSON_OUT];
            if w.reset(seed, &mut out, &mut people).is_err() {
                continue;
            }
            let mut state = vec![0.0; 6 * n];
            let contacts = vec![0u8; n];
            let actions = vec![f64::NAN; 3 * n];
            let mut steps = 0;
            loop {
                if w.command(&actions, &mut out).is_err() {
                    break;
                }
                common::kinematics(&w, &out, &mut state, dt);
                if w.step(&state, &contacts, &mut out, &mut people).is_err() {
                    break;
                }
                steps += 1;
                let flags = &out[lay.flags.offset..lay.flags.offset + 2];
                if flags[0] > 0.0 || flags[1] > 0.0 {
                    break;
                }
            }
            let Ok(reports) = w.episode_metrics() else { continue };
            let (crowd, free) = w.people_step_times();
            let (crowd, free) = (crowd.as_secs_f64() * 1e3, free.as_secs_f64() * 1e3);
            total_crowd += crowd;
            total_free += free;
            let m = &reports[0].metrics.people_cost;
            println!(
                "{name} seed {seed}: {steps} steps, {} people; people stepped in {crowd:.1} ms, robot-free \
                 replay {free:.1} ms (ratio {:.2}); delay mean/max {:?}/{:?} s, extra distance mean {:?} m, \
                 deviation mean/max {:?}/{:?} m",
                w.num_people(),
                free / crowd,
                m.ped_delay_s_mean,
                m.ped_delay_s_max,
                m.ped_extra_distance_m_mean,
                m.ped_path_deviation_m_mean,
                m.ped_path_deviation_m_max,
            );
        }
        println!("{name}: robot-free replay / people stepping = {:.2}", total_free / total_crowd);
    }
}
