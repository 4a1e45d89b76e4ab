//! Scripted pedestrians driven by a social force model.
//!
//! Every walker follows its closed route of waypoints, pausing `dwell` seconds at each; its
//! motion comes from the social force model, integrated with a fixed time step
//! ([`SocialForceParams::dt`], 0.1 s by default) in a Jacobi (snapshot) update so that the result does not
//! depend on the order of the people:
//! - **driving force** toward the current waypoint, `(v0 e - v) / tau` (Helbing & Molnar 1995);
//! - **interaction with other people** (and with the robots, for people who do not `ignore` them) after
//!   Moussaid et al. 2009: an exponential repulsion along the interaction direction
//!   `t = D / |D|`, `D = lambda (v_i - v_j) + e_ij`, and a lateral term that makes people pass
//!   each other; at exact symmetry the lateral term takes the project's passing convention
//!   (pass on the right, [`PASS_ON_RIGHT`]);
//! - **walls and furniture**: `F_o exp(-d / sigma_o)` along the gradient of the static
//!   distance field, with `d` the gap between the body and the nearest obstacle (pedsim's
//!   parameters), plus a hard constraint checked on the exact geometry: a step that would bring
//!   a person's centre closer than half its radius to it is cancelled;
//! - **walking groups** (people with the same group id): gaze, coherence and repulsion terms
//!   of Moussaid et al. 2010.
//!
//! Other behaviours ([`Behaviour`](crate::scenario::Behaviour): exhibit visitors, conversations, tour guides and followers,
//! seated people, care-center residents and staff) run [`scripts::Script`]s planned once when
//! the world is built ([`scripts::plan_scripts`]): they walk with the same forces and hard
//! constraints, and while they stay somewhere (dwelling at an exhibit, talking, sitting, taking
//! part in an activity, gathered at a tour stop) they stand still like standing people, turned
//! toward what they attend to.
//!
//! Standing people stay where they are (other people and the robot go around them), but turn
//! toward a robot inside their intimate zone and shift aside within what their behaviour allows.
//! How each person sees the robots is its [`Reaction`](crate::scenario::Reaction) (`react.rs`,
//! [`ReactionParams`]): `ignore` (the robot is invisible), `aware` (the default), `yield`,
//! `curious`, `cautious`; all but `ignore` never step to within a hard gap of a robot's body.
//!
//! ORCA people (`orca.rs`, [`orca::OrcaPeople`]) are the other pedestrian model: CrowdNav's, each
//! person running ORCA toward its goal; the CrowdNav protocol's scenes use it
//! ([`crate::world::crowdnav`]).
//!
//! Recorded people (`[[replay]]` tracks) follow their tracks exactly, present only between their
//! first and last samples, and walk with the same forces once a robot comes near
//! ([`replay`]).
//!
//! Every random draw (initial route phase, speed jitter) comes from the episode's seeded
//!
//! The files: `force.rs` (the parameters, the interaction and group forces), `crowd.rs` (the
//! crowd's arrays and the substep: plan, forces, integration), `react.rs` (the reactions to
//! robots), `spawn.rs` (a new episode's
//! crowd), `steer.rs` (each script's motion for a substep), `follow.rs` (followers of a robot's
//! tour), `replay.rs` (recorded people), `scripts.rs` (the scripts, planned once when the world is built),
//! `counterfactual.rs` (the episode's people replayed without the robots, for the robot's cost to
//! people), `validation.rs` (the model against recorded crowds: closed-loop re-enactment and
//! open-loop prediction) and `rimea.rs` (the RiMEA known-answer tests).

mod counterfactual;
mod crowd;
mod follow;
mod force;
pub mod orca;
mod react;
pub mod replay;
pub mod rimea;
pub mod scripts;
mod spawn;
mod steer;
#[cfg(test)]
mod tests;
pub mod validation;

pub use counterfactual::{RobotFree, Stages};
pub use crowd::{Crowd, GuideState};
pub use follow::{FOLLOW_GAP, GATHER_REACH, ROBOT_SPACE, SLOT_REACHED, TRAIL_REACHED, TRAIL_SPACING};
pub use force::{SocialForceParams, interaction_force};
pub use react::ReactionParams;
pub use spawn::SPAWN_TRIES;

/// Maximum rate at which people turn their body toward their walking direction (rad/s).
pub const TURN_RATE: f64 = 4.0;

pub use crate::control::PASS_ON_RIGHT;
