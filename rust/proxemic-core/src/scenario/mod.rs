//! Scenario files: parse and validate once.
//!
//! A scenario is a TOML file (`envs/*.toml`) describing the static scene (walls, objects with
//! interaction spaces), the people, the robots and the episode settings. [`Scenario::from_file`]
//! and [`Scenario::from_toml_str`] parse it with serde (unknown fields are rejected), fill in the
//! defaults, check every value, and compute world-frame polygons for walls, object footprints and
//! interaction spaces. The result serialises to JSON ([`Scenario::to_json`]) for the Python side,
//! which never parses the TOML itself.
//!
//! Every error is a [`CoreError::Scenario`](crate::error::CoreError::Scenario) naming the file,
//! the dotted field path (`person[3].route[1]`), what was expected and what arrived.
//!
//! Conventions: SI units, angles in radians counter-clockwise from +x, poses `[x, y, theta]` in the
//! world frame, times of day as `"HH:MM"` or `"HH:MM:SS"` strings.
//!
//! The files, in the order a scenario goes through them:
//! - `raw.rs`: the file representation, serde structs mirroring the TOML tables, and the default
//!   of every optional field;
//! - `load.rs`: reading files, `extends` chains ([`APPENDABLE`], [`MAX_EXTENDS`]), and serde errors
//!   mapped to scenario errors with the dotted field path, line and column;
//! - `build/`: the raw tables checked and turned into the validated model, one file per thing
//!   built: `scene.rs` (scene settings and walls), `objects.rs` (objects, interaction spaces, the
//!   agenda), `people.rs` (people, one function per behaviour, and the links between them),
//!   `proxemics.rs` (the social model and people's features), `robots.rs` (robots and approach
//!   tasks), `polygons.rs` (world-frame rectangles and circles); `mod.rs` runs them in order;
//! - `check.rs`: the error constructor and the value checks (finite, range, inside the bounds,
//!   unique names, times of day) shared by the others;
//! - `schema.rs`: the JSON Schema of the file format ([`json_schema`], from the raw types), the
//!   scenario reference of the docs and `proxemic schema`;
//! - `model/`: the validated types ([`Scenario`] and its parts) and their accessors (`people.rs`
//!   the people's, `robot.rs` the robots');
//! - `overrides.rs`: the `with_*` builders, copies of a scenario with one setting replaced;
//! - `generate/`: generated scenes (a seeded floor plan, furniture, people and robots written as a
//!   scenario file), and robot tasks sampled free and reachable in any scenario.

mod build;
mod check;
pub mod generate;
mod load;
mod model;
mod overrides;
mod raw;
mod schema;
#[cfg(test)]
mod tests;

pub use build::people::ROBOT_GUIDE;
pub use build::replay::read_track_file;
pub use check::{TimeOfDay, check_time_of_day, is_time_of_day, parse_time_of_day};
pub use load::{APPENDABLE, MAX_EXTENDS};
pub use model::{
    ActivitySpec, AgendaSpec, Approach, Behaviour, CIRCLE_VERTICES, EbandGains, Episode, Interaction,
    InteractionShape, Object, ObjectKind, Person, PlannerKind, Proxemics, Randomize, Reaction, RewardWeights,
    Robot, SEAT_SPACING, SPEED_PRESETS, Scenario, Scene, Sensors, Wall,
};
pub use overrides::{EXTRA_ROBOTS_SEED, MAX_ROBOTS};
pub use schema::json_schema;
