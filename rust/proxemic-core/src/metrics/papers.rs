//! The seed papers' own metrics under their names: Daza et al. 2021's `L_ratio` (eq. 1) and
//! `Smooth` (eq. 2, in rad² as written and its root in rad) against the plain A* path, and Calderita et al.'s `d_t` (distance travelled)
//! and `tau` (navigation time). Calderita et al.'s other metrics are the same numbers as metrics
//! of the other families and are recorded there once: `d_min` per person and Ψ per Hall zone in
//! [`super::ProximityMetrics`] (`d_min`, `psi_*`), CHC (H of eq. 18) in
//! [`super::MotionMetrics::chc`], Ψ per object and Ψ(Objects) in [`super::ObjectMetrics`].

use serde::Serialize;

use super::{EvalContext, Samples};
use crate::math::{EPS, Vec2, wrap_angle};

/// The papers' own metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PaperMetrics {
    /// Daza et al. 2021 eq. 1: `L_ratio = D_A* / D_SN`, the A* polyline length (start to goal)
    /// over the social path's length to the goal: the executed path plus the straight rest from
    /// its last point (inside the success radius) to the goal, so both lengths end at the goal as
    /// in the paper, where `L_ratio <= 1` by construction. `None` without success, with fewer than
    /// 2 A* points, or `D_SN` < 1e-9 m.
    pub l_ratio: Option<f64>,
    /// Daza et al. 2021 eq. 2 as written (rad²): `Smooth = 1/(k-1) sum_i theta_i²` over the `k`
    /// angles (rad) between the executed step direction and the A* direction where the path
    /// leaves (last instant within `astar_tolerance` of the A* polyline, then outside) and
    /// rejoins it; 0 for `k = 0` and `theta_1²` for `k = 1`; `None` with fewer than 2 A* points.
    pub smooth_rad2: Option<f64>,
    /// The root of eq. 2 (rad): `sqrt(smooth_rad2)`, a root-mean-square leave/rejoin angle (with
    /// eq. 2's `k - 1` divisor). Daza et al. print Table 2's Smooth in rad and read its values as
    /// angles (0.08 rad = 4.6°, 0.43 rad = 25°), and only the root of eq. 2 is an angle, so this
    /// is the one compared with the table (`docs/metrics.md`). `None` when `smooth_rad2` is.
    pub smooth_rad: Option<f64>,
    /// Number `k` of leave/rejoin angles in `smooth_rad2`.
    pub smooth_k: usize,
    /// Calderita's d_t (m): distance travelled, equal to `path_length`.
    pub d_t: f64,
    /// Calderita's tau (s): navigation time of the recording, `T * dt`.
    pub tau: f64,
}

/// The papers' metrics of the recording `s` (control period `dt`, s; path `path_length` m long;
/// `success` from the outcome).
pub(crate) fn evaluate(
    s: &Samples,
    dt: f64,
    ctx: &EvalContext,
    success: bool,
    path_length: f64,
) -> PaperMetrics {
    let astar_ok = ctx.astar_path.len() >= 2;
    // D_SN runs to the goal (the A* path's last point), like D_A*: the executed path ends inside
    // the success radius, so the straight rest to the goal is added.
    let to_goal = match (s.pos.last(), ctx.astar_path.last()) {
        (Some(p), Some(g)) => (g - p).norm(),
        _ => 0.0,
    };
    let d_sn = path_length + to_goal;
    let l_ratio = (astar_ok && success && d_sn > EPS).then(|| polyline_length(ctx.astar_path) / d_sn);
    let angles = if astar_ok {
        leave_rejoin_angles(&s.pos, ctx.astar_path, ctx.params.astar_tolerance)
    } else {
        Vec::new()
    };
    let smooth_k = angles.len();
    let smooth_rad2 = astar_ok.then(|| {
        let sq = angles.iter().fold(0.0, |acc, a| acc + a * a);
        sq / (smooth_k.saturating_sub(1).max(1)) as f64
    });
    let smooth_rad = smooth_rad2.map(f64::sqrt);
    PaperMetrics { l_ratio, smooth_rad2, smooth_rad, smooth_k, d_t: path_length, tau: s.steps as f64 * dt }
}

/// Closest point of a polyline (with at least one point) to `pt`: (distance, unit direction of
/// the segment holding it, or `None` when every segment is degenerate). Segments shorter than
/// [`EPS`] count as their first point.
fn polyline_nearest(pt: Vec2, line: &[Vec2]) -> (f64, Option<Vec2>) {
    let mut best = (f64::INFINITY, None);
    if line.len() == 1 {
        return ((pt - line[0]).norm(), None);
    }
    for w in line.windows(2) {
        let d = w[1] - w[0];
        let len = d.norm();
        if len <= EPS {
            let dist = (pt - w[0]).norm();
            if dist < best.0 {
                best = (dist, best.1);
            }
            continue;
        }
        let s = ((pt - w[0]).dot(&d) / (len * len)).clamp(0.0, 1.0);
        let dist = (pt - (w[0] + d * s)).norm();
        if dist < best.0 || best.1.is_none() && dist <= best.0 {
            best = (dist, Some(d / len));
        }
    }
    best
}

/// Length of a polyline (m).
fn polyline_length(line: &[Vec2]) -> f64 {
    line.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
}

/// Unsigned angle (rad, in [0, pi]) between two non-zero vectors.
fn angle_between(a: Vec2, b: Vec2) -> f64 {
    wrap_angle(a.y.atan2(a.x) - b.y.atan2(b.x)).abs()
}

/// Daza et al. 2021 eq. 2 angles where the path leaves and rejoins the A* polyline.
fn leave_rejoin_angles(pos: &[Vec2], astar: &[Vec2], tol: f64) -> Vec<f64> {
    let mut angles = Vec::new();
    let near: Vec<(bool, Option<Vec2>)> = pos
        .iter()
        .map(|&p| {
            let (d, dir) = polyline_nearest(p, astar);
            (d <= tol, dir)
        })
        .collect();
    for t in 0..pos.len().saturating_sub(1) {
        let (on0, dir0) = near[t];
        let (on1, dir1) = near[t + 1];
        let step = pos[t + 1] - pos[t];
        if step.norm() <= EPS {
            continue;
        }
        let tangent = match (on0, on1) {
            (true, false) => dir0,
            (false, true) => dir1,
            _ => None,
        };
        if let Some(tan) = tangent {
            angles.push(angle_between(step, tan));
        }
    }
    angles
}
