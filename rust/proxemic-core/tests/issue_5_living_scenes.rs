//! Living scenes: the scripted behaviours of the museum and the care center over long seeded
//! runs (people never enter walls or furniture, visitors face exhibits, conversations form and
//! break up on schedule, the tour stops and gathers, residents arrive before their activities,
//! groups stay together, same seed same people), and the bad-input errors of the people.
//!
//! The robot stands at its start (its aware neighbours see it); the people are stepped through
//! `World::step` exactly as in an episode.

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::{Behaviour, Scenario};
use proxemic_core::world::World;

const ENVS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs");

fn scenario(name: &str) -> Scenario {
    Scenario::from_file(format!("{ENVS}/{name}.toml")).expect("valid scenario")
}

/// Per step (after it): positions and headings of the people.
struct Trace {
    dt: f64,
    pos: Vec<Vec<Vec2>>,
    heading: Vec<Vec<f64>>,
}

impl Trace {
    fn time(&self, step: usize) -> f64 {
        (step + 1) as f64 * self.dt
    }
}

fn run(s: &Scenario, seed: u64, steps: usize, mut check: impl FnMut(&World, usize)) -> Trace {
    let dt = s.control_dt();
    let mut world = World::new(s.clone()).expect("valid world");
    let n = world.num_robots();
    let stride = world.layout().stride;
    let pose_off = world.layout().section("pose").expect("pose").offset;
    let mut out = vec![0.0; stride * n];
    let mut people = vec![0.0; world.num_people() * 3];
    world.reset(seed, &mut out, &mut people).expect("reset");
    let state: Vec<f64> = (0..n)
        .flat_map(|i| {
            let r = &out[i * stride + pose_off..i * stride + pose_off + 3];
            [r[0], r[1], r[2], 0.0, 0.0, 0.0]
        })
        .collect();
    let contacts = vec![0u8; n];
    let mut trace = Trace { dt, pos: Vec::with_capacity(steps), heading: Vec::with_capacity(steps) };
    for k in 0..steps {
        world.step(&state, &contacts, &mut out, &mut people).expect("step");
        check(&world, k);
        trace.pos.push(world.crowd().pos.clone());
        trace.heading.push(world.crowd().heading.clone());
    }
    trace
}

fn index(s: &Scenario, name: &str) -> usize {
    s.persons.iter().position(|p| p.name == name).unwrap_or_else(|| panic!("no person {name}"))
}

fn angle_between(heading: f64, from: Vec2, to: Vec2) -> f64 {
    let d = to - from;
    let a = d.y.atan2(d.x) - heading;
    a.sin().atan2(a.cos()).abs()
}

#[test]
fn the_scenes_build() {
    for name in ["museum", "care_center"] {
        let s = scenario(name);
        World::new(s).unwrap_or_else(|e| panic!("{name}: {e}"));
    }
}
