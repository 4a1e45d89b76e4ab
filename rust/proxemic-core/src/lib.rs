//! # proxemic-core
//!
//! The pure-Rust core of proxemic. Every per-step computation of the gym lives here; the Python
//! package only moves arrays in and out and steps MuJoCo.
//!
//! One control step is one call from Python (the binding's `World.step`), in which the binding
//! runs [`world::World::command`] (the policies' actions become limited commands), calls back
//! into Python for the physics (MuJoCo, the only part with the GIL held), then runs
//! [`world::World::step`], which in order:
//! 1. ingests the robots' poses, velocities and contact flags read from the physics;
//! 2. advances the scripted people ([`pedestrians`]) to the same instant and logs the scene's
//!    ground truth (groups, interactions, object activities), then advances the robots' tours;
//! 3. records each running robot's metrics ([`metrics`]), its outcome and reward terms;
//! 4. builds the observations;
//! 5. runs each robot's built-in planner ([`plan`], [`control`]) for its next command;
//! 6. writes the people's poses and the physics' contact hints.
//!
//! Outputs go into caller-owned buffers (no output array is allocated per step); the core still
//! allocates small working vectors during a step.
//!
//! Modules:
//! - [`scenario`]: parse and validate scenario TOML once; errors name the file and field.
//! - [`geom`]: the 2D geometry primitives (cross product, point-segment distance, point in
//!   polygon or triangle), one definition each.
//! - [`map`]: static geometry, occupancy grid, distance field, 2D ray casting.
//! - [`perception`]: from people and robots to the individuals of the social map (groups,
//!   socialization features).
//! - [`social_cost_map`]: the social cost map (layers of zones, groups and object spaces).
//! - [`plan`]: 8-connected A* (plain and cost-aware), Dijkstra oracle, path smoothing, and the
//!   social global planner ([`plan::social`]).
//! - [`control`]: command limits, the path follower, the local planners and the mode switch.
//! - [`pedestrians`]: scripted people.
//! - [`groups`]: group detection (Delaunay, density, F-formation), groups as individuals.
//! - [`metrics`]: per-step accumulation and episode summaries.
//! - [`world`]: ties these together: construction, reset, `command` and `step`, with the
//!   output layout, rewards, observations, tours and the built-in planners' dispatch.

pub mod chronemics;
pub mod control;
pub mod error;
pub mod geom;
pub mod groups;
pub mod map;
pub mod math;
pub mod metrics;
pub mod pedestrians;
pub mod perception;
pub mod plan;
pub mod proxemics;
pub mod scenario;
pub mod social_cost_map;
pub mod world;

pub use error::{CoreError, Result};
