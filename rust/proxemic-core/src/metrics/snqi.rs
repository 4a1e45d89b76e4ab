//! The per-episode inputs of the Social Navigation Quality Index (SNQI) of the robot-sf benchmark
//! (Ll7 et al., `robot_sf.benchmark.snqi`; `docs/metrics.md`), which the other families do not
//! already give: near misses, force-exceed events and the comfort exposure. The index itself is
//! a function of a whole evaluation (its normalisation takes the median and 95th percentile of a
//! baseline planner's episodes), so it is computed over the records in Python
//! (`proxemic.snqi`); its collision count is `hc_count`, its jerk `jerk_avg`.
//!
//! robot-sf counts a near miss at a step whose closest person's surface clearance is in
//! `[0, 0.5)` m, and a force-exceed event at each (step, person) whose social force exceeds
//! 2.0 m/s². robot-sf's force is the total social-force of its pedestrian simulator on the
//! person; ours is the robot's own social force on the person (`social_force_on_people`, the
//! Helbing-style force with A = 2.1 m/s², B = 0.3 m, λ = 0.5), so that the exposure measures the
//! robot's effect and not the crowd's own pushing (docs: choices.md).

use serde::Serialize;

use super::{PeopleTracks, Samples, Trajectory, frac};
use crate::math::Vec2;

/// robot-sf's near-miss clearance (m, surface gap): a step is a near miss when the closest
/// person's gap is in `[0, SNQI_NEAR_MISS_GAP)`.
pub const SNQI_NEAR_MISS_GAP: f64 = 0.5;
/// robot-sf's comfort force threshold (m/s²): a (step, person) is a force-exceed event when the
/// robot's social force on the person is above it.
pub const SNQI_FORCE_THRESHOLD: f64 = 2.0;

/// The SNQI inputs of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SnqiMetrics {
    /// Instants at which the closest person's surface gap is in `[0, 0.5)` m (robot-sf's
    /// `near_misses`; an instant in contact, gap < 0, is a collision, not a near miss).
    pub near_misses: usize,
    /// (instant, person) pairs at which the robot's social force on the person is above
    /// 2.0 m/s² (robot-sf's `force_exceed_events`).
    pub force_exceed_events: usize,
    /// `force_exceed_events / (K N)` over the `K` people and `N` instants (robot-sf's
    /// `comfort_exposure`, in [0, 1]); 0 without people; `None` without samples.
    pub comfort_exposure: Option<f64>,
}

/// The SNQI inputs of the recording `s` among `people`; `force` is the magnitude of the robot's
/// social force on person `i` at instant `t` (m/s²).
pub(crate) fn evaluate(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    force: impl Fn(usize, usize) -> f64,
) -> SnqiMetrics {
    let (np, rr) = (people.count, traj.robot_radius);
    let mut near_misses = 0usize;
    let mut exceed = 0usize;
    for t in 0..s.n {
        let mut closest = f64::INFINITY;
        for i in (0..np).filter(|&i| people.is_present(t, i)) {
            let q: Vec2 = people.positions[t * np + i];
            closest = closest.min((q - s.pos[t]).norm() - rr - people.radii[i]);
            exceed += usize::from(force(t, i) > SNQI_FORCE_THRESHOLD);
        }
        near_misses += usize::from((0.0..SNQI_NEAR_MISS_GAP).contains(&closest));
    }
    let comfort_exposure = if np == 0 { (s.n > 0).then_some(0.0) } else { frac(exceed, np * s.n) };
    SnqiMetrics { near_misses, force_exceed_events: exceed, comfort_exposure }
}
