//! Path efficiency (`docs/metrics.md`, Efficiency): path length, its ratio to the geodesic
//! start-goal length, SPL (Anderson et al. 2018) and the failures to progress.

use serde::Serialize;

use super::{EvalContext, MetricParams, Samples, Trajectory};
use crate::math::EPS;

/// The path efficiency metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EfficiencyMetrics {
    /// Path length PL (m, `docs/metrics.md`, Efficiency): sum of distances between consecutive robot centres.
    pub path_length: f64,
    /// Path length ratio PLR = PL / `l*` (`docs/metrics.md`, Efficiency, geodesic `l*`); `None` when `l*` is not
    /// finite or below 1e-9 m.
    pub path_length_ratio: Option<f64>,
    /// SPL = S * `l*` / max(PL, `l*`) (Anderson et al. 2018; `docs/metrics.md`, Efficiency); 1 on success with
    /// PL and `l*` both ~0; `None` when `l*` is not finite.
    pub spl: Option<f64>,
    /// Failure to progress FP (`docs/metrics.md`, Efficiency): consecutive, non-overlapping windows of
    /// `progress_window` s in which the straight-line centre-to-goal distance decreased by less
    /// than `progress_delta` (an incomplete final window is not counted).
    pub failure_to_progress: usize,
}

/// The efficiency of the recording `s` towards `traj.goal`, `success` from the outcome.
pub(crate) fn evaluate(
    s: &Samples,
    traj: &Trajectory,
    ctx: &EvalContext,
    success: bool,
) -> EfficiencyMetrics {
    let path_length = s.path_length();
    let l_star = ctx.geodesic_length;
    let path_length_ratio = (l_star.is_finite() && l_star > EPS).then(|| path_length / l_star);
    let spl = l_star.is_finite().then(|| {
        if !success {
            0.0
        } else {
            let denom = path_length.max(l_star);
            if denom <= EPS { 1.0 } else { l_star / denom }
        }
    });
    EfficiencyMetrics {
        path_length,
        path_length_ratio,
        spl,
        failure_to_progress: failures_to_progress(s, traj, &ctx.params),
    }
}

/// Consecutive, non-overlapping windows of `progress_window` s in which the straight-line
/// centre-to-goal distance decreased by less than `progress_delta`.
fn failures_to_progress(s: &Samples, traj: &Trajectory, q: &MetricParams) -> usize {
    let goal_dist: Vec<f64> = s.pos.iter().map(|p| (p - traj.goal).norm()).collect();
    let window = ((q.progress_window / traj.dt).round() as usize).max(1);
    (0..s.steps / window)
        .filter(|w| goal_dist[w * window] - goal_dist[(w + 1) * window] < q.progress_delta)
        .count()
}
