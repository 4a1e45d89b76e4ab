//! `Scenario::with_start_time`: the same validated scenario as a file whose `scene.start_time`
//! says that time, and a typed error for a time outside a day.

use proxemic_core::CoreError;
use proxemic_core::scenario::{Scenario, parse_time_of_day};

const ENVS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs");

#[test]
fn start_time_builder_matches_the_edited_file() {
    let text = std::fs::read_to_string(format!("{ENVS}/calderita_exp1.toml")).expect("scene file");
    assert!(text.contains("start_time = \"10:05\""), "the scene's start time moved");
    let edited = text.replace("start_time = \"10:05\"", "start_time = \"09:05\"");
    let from_file = Scenario::from_toml_str(&edited, "exp1").expect("valid");
    let base = Scenario::from_toml_str(&text, "exp1").expect("valid");
    let nine_five = parse_time_of_day("09:05").expect("a time");
    let built = base.with_start_time(nine_five).expect("a time in the day");
    assert_eq!(built.scene.start_time, nine_five);
    assert_ne!(base.to_json().expect("json"), built.to_json().expect("json"));
    assert_eq!(built.to_json().expect("json"), from_file.to_json().expect("json"));
}

#[test]
fn start_time_outside_a_day_is_a_scenario_error() {
    let base = Scenario::from_file(format!("{ENVS}/calderita_exp1.toml")).expect("valid");
    for bad in [-1.0, 86400.0, f64::NAN] {
        match base.with_start_time(bad) {
            Err(CoreError::Scenario { field, .. }) => assert_eq!(field, "scene.start_time"),
            other => panic!("expected a scenario error for {bad}, got {other:?}"),
        }
    }
}
