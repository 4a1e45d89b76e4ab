//! Shared by the integration suites (`mod common;`): the kinematic driver that steps a
//! [`World`] without MuJoCo (the robots' commands integrated exactly, contacts as the suite says),
//! and the scenario helpers the suites build their scenes with.
#![allow(dead_code)] // each suite uses its part

mod kinematics;

pub use kinematics::kinematics;

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::{Reaction, Scenario};
use proxemic_core::world::{PERSON_OUT, World};

/// The shipped scenario files.
pub const ENVS: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../python/proxemic/data/envs");

/// The shipped scenario `name` (`python/proxemic/data/envs/<name>.toml`).
pub fn env_scenario(name: &str) -> Scenario {
    Scenario::from_file(format!("{ENVS}/{name}.toml")).unwrap_or_else(|e| panic!("scenario {name}: {e}"))
}

/// `scenario` with every person reacting to robots with `reaction`.
pub fn with_reaction(mut scenario: Scenario, reaction: Reaction) -> Scenario {
    for p in &mut scenario.persons {
        p.reaction = reaction;
    }
    scenario
}

/// The scenario error of `result` as (file, field, expected, found); panics on success or on
/// another error.
pub fn scenario_error<T>(result: Result<T, CoreError>) -> (String, String, String, String) {
    match result {
        Err(CoreError::Scenario { file, field, expected, found }) => (file, field, expected, found),
        Err(other) => panic!("expected a scenario error, got {other}"),
        Ok(_) => panic!("expected a scenario error, got a valid result"),
    }
}

/// A world driven without MuJoCo: its output buffers and the physics state the suite hands to
/// [`World::step`] (x, y, yaw, vx, vy, wz per robot).
pub struct Drive {
    /// The world.
    pub world: World,
    /// The robots' output rows ([`World::layout`]).
    pub out: Vec<f64>,
    /// The people's output ([`PERSON_OUT`] values per person).
    pub people: Vec<f64>,
    /// The physics state handed to the next [`World::step`].
    pub state: Vec<f64>,
    /// The control period (s).
    pub dt: f64,
}

impl Drive {
    /// A world of `scenario` with its buffers, not yet reset.
    pub fn new(scenario: Scenario) -> Self {
        let dt = scenario.control_dt();
        let world = World::new(scenario).expect("valid world");
        let n = world.num_robots();
        let out = vec![0.0; world.layout().stride * n];
        let people = vec![0.0; world.num_people() * PERSON_OUT];
        Self { world, out, people, state: vec![0.0; 6 * n], dt }
    }

    /// A world of `scenario` reset with `seed`.
    pub fn start(scenario: Scenario, seed: u64) -> Self {
        let mut d = Self::new(scenario);
        d.reset(seed);
        d
    }

    /// Starts an episode from `seed`; every robot at rest at its start pose ([`Drive::hold`]).
    pub fn reset(&mut self, seed: u64) {
        self.world.reset(seed, &mut self.out, &mut self.people).expect("reset");
        self.hold();
    }

    /// Every robot at rest at its pose in `out`: the state the next step holds it still with.
    pub fn hold(&mut self) {
        let lay = *self.world.layout();
        for (i, row) in self.out.chunks_exact(lay.stride).enumerate() {
            let pose = &row[lay.pose.offset..lay.pose.offset + 3];
            self.state[6 * i..6 * i + 6].copy_from_slice(&[pose[0], pose[1], pose[2], 0.0, 0.0, 0.0]);
        }
    }

    /// The first half of a step: `actions` (3 per robot, NaN for the built-in planner).
    pub fn command(&mut self, actions: &[f64]) {
        self.world.command(actions, &mut self.out).expect("command");
    }

    /// The physics: every robot's command in `out` integrated over one control period into `state`.
    pub fn integrate(&mut self) {
        kinematics(&self.world, &self.out, &mut self.state, self.dt);
    }

    /// The second half of a step with the contact bits `contacts` (one per robot).
    pub fn step(&mut self, contacts: &[u8]) {
        self.world.step(&self.state, contacts, &mut self.out, &mut self.people).expect("step");
    }

    /// The second half of a step without contacts.
    pub fn step_free(&mut self) {
        let contacts = vec![0u8; self.world.num_robots()];
        self.step(&contacts);
    }

    /// One whole step on the built-in planners: command, integrate, step without contacts.
    pub fn drive(&mut self) {
        let nan = vec![f64::NAN; 3 * self.world.num_robots()];
        self.command(&nan);
        self.integrate();
        self.step_free();
    }

    /// Robot `i`'s output row.
    pub fn row(&self, i: usize) -> &[f64] {
        let stride = self.world.layout().stride;
        &self.out[i * stride..(i + 1) * stride]
    }

    /// Robot `i`'s position in the state last handed to the physics.
    pub fn robot(&self, i: usize) -> Vec2 {
        Vec2::new(self.state[6 * i], self.state[6 * i + 1])
    }
}
