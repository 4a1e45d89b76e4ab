//! # proxemic-core
//!
//! The pure-Rust core of proxemic. Every per-step computation of the gym lives here; the Python
//! package only moves arrays in and out and steps MuJoCo.
//!
//! One control step of [`world::World`] does, in order:
//! 1. ingest the robots' poses, velocities and contact flags read from the physics;
//! 2. accumulate the step's metrics ([`metrics`]) and reward terms, and build the observations;
//! 3. advance the scripted pedestrians ([`pedestrians`]) to the next control instant;
//! 4. run each robot's built-in planner ([`plan`], [`control`]) to get its next command.
//!
//! Modules:
//! - [`scenario`]: parse and validate scenario TOML once; errors name the file and field.
//! - [`geom`]: the 2D geometry primitives (cross product, point-segment distance, point in
//!   polygon or triangle), one definition each.
//! - [`map`]: static geometry, occupancy grid, distance field, 2D ray casting.
//! - [`perception`]: from people and robots to the individuals of the social map (groups,
//!   socialization features).
//! - [`socialmap`]: the social cost map (layers of zones, groups and object spaces).
//! - [`plan`]: 8-connected A* (plain and cost-aware), Dijkstra oracle, path smoothing, and the
//!   social global planner ([`plan::social`]).
//! - [`control`]: command limits, the path follower, the local planners and the mode switch.
//! - [`pedestrians`]: scripted people.
//! - [`groups`]: group detection (Delaunay, density, F-formation), groups as individuals.
//! - [`metrics`]: per-step accumulation and episode summaries.
//! - [`world`]: ties these together behind one `step`.

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
pub mod socialmap;
pub mod world;

pub use error::{CoreError, Result};
