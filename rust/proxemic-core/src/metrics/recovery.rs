//! The built-in planner's progress monitor ([`crate::control::progress`]): how often it
//! recovered and how long it considered the robot stalled. Not computed from the trajectory: the
//! world copies the monitor's counts into the report ([`crate::world::World::episode_metrics`]).

use serde::Serialize;

/// The progress monitor's record of an episode. Zero for a robot whose built-in planner did not
/// run (see [`crate::world::World::set_planning`]) or whose monitor is off.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RecoveryMetrics {
    /// Recoveries (count): windows of [`crate::control::progress::ProgressParams::window`]
    /// seconds (default 15) in which the geodesic distance to the current target fell by less than
    /// [`crate::control::progress::ProgressParams::distance`] (default 0.5 m), each followed by a
    /// recovery (back out, re-plan round the blocking people).
    pub recoveries: usize,
    /// Seconds the monitor considered the robot stalled (s, >= 0): from the start of each window
    /// that ended in a recovery to the progress that ended the stall (or the episode's end).
    pub monitor_stalled_time: f64,
}
