//! The built-in planner's recoveries: how often its progress monitor ([`crate::control::progress`])
//! recovered and how long it considered the robot stalled (not computed from the trajectory: the
//! world copies the monitor's counts into the report, [`crate::world::World::episode_metrics`]),
//! and what the robot did while it followed a recovery path: its time on it and its entries into
//! groups' o-spaces and active object spaces on the way (computed from the steps the recorder
//! marked as recovering).

use serde::Serialize;

use super::{Groups, ObjectSpaces, Trajectory};
use crate::math::Vec2;

/// The built-in planner's recoveries in an episode. Zero for a robot whose built-in planner did
/// not run (see [`crate::world::World::set_planning`]) or whose monitor is off.
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
    /// Seconds of steps whose command followed a held recovery path (s, >= 0): those steps times
    /// the control period.
    pub recovery_time: f64,
    /// Entries into groups' o-spaces during recovery (count): recovery steps that end with the
    /// robot centre inside an o-space present at that instant after starting outside every
    /// o-space present at the step's start.
    pub recovery_ospace_entries: usize,
    /// Entries into active object spaces during recovery (count): recovery steps that end with
    /// the robot centre inside the interaction polygon of an object whose activity is on after
    /// starting outside every active one.
    pub recovery_object_entries: usize,
}

/// The recovery metrics computed from the recording (the monitor's own counts left at zero):
/// `recovering[k]` says whether step `k` (instant `k` to `k + 1`) followed a recovery path.
pub(crate) fn evaluate(
    traj: &Trajectory,
    recovering: &[bool],
    groups: &Groups,
    objects: &ObjectSpaces,
) -> RecoveryMetrics {
    let at = |t: usize| Vec2::new(traj.robot[t][0], traj.robot[t][1]);
    let steps = traj.robot.len().saturating_sub(1);
    let mut m = RecoveryMetrics::default();
    let mut recovery_steps = 0usize;
    for k in (0..steps.min(recovering.len())).filter(|&k| recovering[k]) {
        recovery_steps += 1;
        let (p0, p1) = (at(k), at(k + 1));
        m.recovery_ospace_entries += usize::from(groups.in_ospace(k + 1, p1) && !groups.in_ospace(k, p0));
        m.recovery_object_entries +=
            usize::from(objects.in_active_space(k + 1, p1) && !objects.in_active_space(k, p0));
    }
    m.recovery_time = recovery_steps as f64 * traj.dt;
    m
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::OSpace;

    #[test]
    fn counts_only_recovery_steps_that_enter() {
        // The robot walks along x from 0 to 4 m in 1 m steps; an o-space of radius 0.5 m at
        // (2, 0) at every instant; an object polygon around (4, 0) active from instant 3 on.
        let robot: Vec<[f64; 3]> = (0..=4).map(|x| [x as f64, 0.0, 0.0]).collect();
        let traj = Trajectory {
            dt: 0.5,
            robot: &robot,
            robot_radius: 0.3,
            goal: Vec2::new(4.0, 0.0),
            success_radius: 0.1,
        };
        let ospaces = [OSpace { centre: Vec2::new(2.0, 0.0), radius: 0.5 }; 5];
        let offsets: Vec<usize> = (0..=5).collect();
        let groups = Groups { ospace_offsets: &offsets, ospaces: &ospaces, link_offsets: &[], links: &[] };
        let square =
            vec![vec![Vec2::new(3.5, -0.5), Vec2::new(4.5, -0.5), Vec2::new(4.5, 0.5), Vec2::new(3.5, 0.5)]];
        let active = [false, false, false, true, true];
        let objects = ObjectSpaces { polygons: &square, active: &active };
        // Steps 1 (1 -> 2 m, into the o-space) and 3 (3 -> 4 m, into the active space) recovering.
        let m = evaluate(&traj, &[false, true, false, true], &groups, &objects);
        assert_eq!((m.recovery_ospace_entries, m.recovery_object_entries), (1, 1));
        assert!((m.recovery_time - 1.0).abs() < 1e-12);
        // The same entries outside recovery count nothing.
        let m = evaluate(&traj, &[true, false, true, false], &groups, &objects);
        assert_eq!((m.recovery_ospace_entries, m.recovery_object_entries), (0, 0));
        // The object's space while idle is no entry.
        let idle = [false; 5];
        let m = evaluate(&traj, &[true; 4], &groups, &ObjectSpaces { polygons: &square, active: &idle });
        assert_eq!((m.recovery_ospace_entries, m.recovery_object_entries), (1, 0));
        assert_eq!(m.recoveries, 0);
    }
}
