//! The robot's cost to people by counterfactual: a robot standing in a corridor too
//! narrow to pass delays the person walking it; a robot far from everyone costs nobody anything,
//! exactly (the robot-free replay is the episode's own crowd, bit for bit). The robots are
//! simulated kinematically (their commands integrated exactly; no MuJoCo).

use proxemic_core::metrics::EpisodeReport;
use proxemic_core::scenario::Scenario;

mod common;
use common::Drive;

/// A 20 x 10 m hall with a corridor 1.1 m wide along its south wall (y 0 to 1.1) and a person
/// walking it west to east and back; the robot starts at `robot` (x, y) and is held still.
fn corridor(robot: (f64, f64)) -> Scenario {
    let (x, y) = robot;
    let text = format!(
        r#"
[scene]
name = "corridor"
bounds = [0, 0, 20, 10]

[[wall]]
from = [0, 0]
to = [20, 0]
[[wall]]
from = [20, 0]
to = [20, 10]
[[wall]]
from = [20, 10]
to = [0, 10]
[[wall]]
from = [0, 10]
to = [0, 0]
[[wall]]
from = [0, 1.1]
to = [19.0, 1.1]

[[robot]]
start = [{x}, {y}, 0]
goal = [15.0, {gy}]

[[person]]
name = "walker"
behaviour = "walker"
route = [[1.0, 0.55], [18.0, 0.55]]
speed = 1.2
dwell = 1.0

[[person]]
name = "bystander"
behaviour = "standing"
pose = [3.0, 8.0, 0.0]

[episode]
max_time = 60.0

[episode.randomize]
person_phase = false
speed_jitter = 0.0
"#,
        gy = if y < 1.1 { 0.55 } else { 8.0 },
    );
    Scenario::from_toml_str(&text, "corridor.toml").expect("valid scenario")
}

/// `steps` control steps with robot 0 held still (zero command, integrated kinematically).
fn run(s: Scenario, steps: usize) -> EpisodeReport {
    let mut d = Drive::start(s, 0);
    for _ in 0..steps {
        d.command(&[0.0, 0.0, 0.0]);
        d.hold();
        d.step_free();
    }
    d.world.episode_metrics().expect("metrics").remove(0)
}

#[test]
fn a_robot_blocking_a_corridor_delays_the_person_in_it() {
    // Without the robot the walker reaches the corridor's east end after about 14 s; with the
    // robot standing across it at x = 10, never within the 40 s.
    let m = run(corridor((10.0, 0.55)), 400).metrics.people_cost;
    let max = m.ped_delay_s_max.expect("people");
    assert!(max > 15.0, "{m:?}");
    // the bystander is never late: the mean is half the walker's delay
    assert!((m.ped_delay_s_mean.expect("people") - max / 2.0).abs() < 1e-9, "{m:?}");
}

#[test]
fn a_robot_far_from_everyone_costs_nothing_exactly() {
    // The robot stands in the hall, more than 4 m (the interaction cutoff) from the walker.
    let m = run(corridor((10.0, 7.0)), 400).metrics.people_cost;
    for v in [
        m.ped_delay_s_mean,
        m.ped_delay_s_max,
        m.ped_extra_distance_m_mean,
        m.ped_extra_distance_m_max,
        m.ped_path_deviation_m_mean,
        m.ped_path_deviation_m_max,
    ] {
        assert_eq!(v, Some(0.0), "{m:?}");
    }
}
