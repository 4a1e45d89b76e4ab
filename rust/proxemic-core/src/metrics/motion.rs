//! Motion quality (`docs/metrics.md`, Motion quality): stalled time, speed, acceleration and jerk
//! by finite differences, the cumulative heading change (body yaw, = Calderita et al.'s CHC; and
//! motion direction) and the path irregularity (Guzzi et al. 2013).

use serde::Serialize;

use super::{MetricParams, Samples, Trajectory, min_avg_max};
use crate::math::{EPS, wrap_angle};

/// The motion quality metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionMetrics {
    /// Stalled time ST (s, `docs/metrics.md`, Motion quality, HuNav/SEAN): `dt` times the steps with finite-difference
    /// speed < `stall_linear` and yaw rate < `stall_angular`.
    pub stalled_time: f64,
    /// Min speed (m/s, `docs/metrics.md`, Motion quality) of `v_t = (p_{t+1} - p_t)/dt`; `None` without a step.
    pub vel_min: Option<f64>,
    /// Mean speed (m/s) over the steps.
    pub vel_avg: Option<f64>,
    /// Max speed (m/s).
    pub vel_max: Option<f64>,
    /// Min `|a_t|`, `a_t = (p_{t+1} - 2 p_t + p_{t-1})/dt²` (m/s², `docs/metrics.md`, Motion quality); `None`
    /// with fewer than 3 samples.
    pub acc_min: Option<f64>,
    /// Mean `|a_t|` (m/s²).
    pub acc_avg: Option<f64>,
    /// Max `|a_t|` (m/s²).
    pub acc_max: Option<f64>,
    /// Min `|j_t|`, `j_t = (p_{t+2} - 3p_{t+1} + 3p_t - p_{t-1})/dt³` (m/s³, `docs/metrics.md`, Motion quality);
    /// `None` with fewer than 4 samples.
    pub jerk_min: Option<f64>,
    /// Mean `|j_t|` (m/s³).
    pub jerk_avg: Option<f64>,
    /// Max `|j_t|` (m/s³).
    pub jerk_max: Option<f64>,
    /// Cumulative heading change of the body yaw, `sum |wrap(theta_{t+1} - theta_t)|` (rad;
    /// `docs/metrics.md`, Motion quality, Pérez-Higueras 2018, HuNav; Calderita et al.'s CHC / H of eq. 18).
    pub chc: f64,
    /// Cumulative change of the motion direction `atan2(v_t)` (rad, `docs/metrics.md`, Motion quality), over
    /// consecutive steps with speed >= `v_eps` (slower steps are skipped).
    pub chc_motion: f64,
    /// Path irregularity PI (rad/m, Guzzi et al. 2013; `docs/metrics.md`, Motion quality):
    /// `(chc - |wrap(atan2(g - p_0) - theta_0)|) / PL`; may be negative (a holonomic robot need
    /// not turn towards the goal); `None` when PL < 1e-9 m.
    pub path_irregularity: Option<f64>,
}

/// The motion quality of the recording `s`, whose path is `path_length` m long.
pub(crate) fn evaluate(s: &Samples, traj: &Trajectory, q: &MetricParams, path_length: f64) -> MotionMetrics {
    let dt = traj.dt;
    let (pos, yaw, vel) = (&s.pos, &s.yaw, &s.vel);
    let stalled_time = dt
        * (0..s.steps)
            .filter(|&k| {
                vel[k].norm() < q.stall_linear
                    && (wrap_angle(yaw[k + 1] - yaw[k]) / dt).abs() < q.stall_angular
            })
            .count() as f64;
    let v_stats = min_avg_max(vel.iter().map(|v| v.norm()));
    let a_stats = min_avg_max(pos.windows(3).map(|w| ((w[2] - w[1] * 2.0 + w[0]) / (dt * dt)).norm()));
    let j_stats = min_avg_max(
        pos.windows(4).map(|w| ((w[3] - w[2] * 3.0 + w[1] * 3.0 - w[0]) / (dt * dt * dt)).norm()),
    );
    let chc: f64 = yaw.windows(2).map(|w| wrap_angle(w[1] - w[0]).abs()).sum();
    let path_irregularity = match (pos.first(), yaw.first()) {
        (Some(p0), Some(&th0)) if path_length > EPS => {
            let to_goal = traj.goal - p0;
            let initial = wrap_angle(to_goal.y.atan2(to_goal.x) - th0).abs();
            Some((chc - initial) / path_length)
        }
        _ => None,
    };
    MotionMetrics {
        stalled_time,
        vel_min: v_stats.map(|s| s.0),
        vel_avg: v_stats.map(|s| s.1),
        vel_max: v_stats.map(|s| s.2),
        acc_min: a_stats.map(|s| s.0),
        acc_avg: a_stats.map(|s| s.1),
        acc_max: a_stats.map(|s| s.2),
        jerk_min: j_stats.map(|s| s.0),
        jerk_avg: j_stats.map(|s| s.1),
        jerk_max: j_stats.map(|s| s.2),
        chc,
        chc_motion: motion_heading_change(s, q.v_eps),
        path_irregularity,
    }
}

/// Cumulative change of the motion direction (rad) over consecutive steps with speed >= `v_eps`.
fn motion_heading_change(s: &Samples, v_eps: f64) -> f64 {
    let mut chc_motion = 0.0;
    let mut last_dir: Option<f64> = None;
    for v in &s.vel {
        if v.norm() >= v_eps && v.norm() > 0.0 {
            let h = v.y.atan2(v.x);
            if let Some(prev) = last_dir {
                chc_motion += wrap_angle(h - prev).abs();
            }
            last_dir = Some(h);
        }
    }
    chc_motion
}
