//! The robot's cost to the people around it, by counterfactual (the `ped_*` keys of
//! `docs/metrics.md`): each person in the episode against the same person in the same episode
//! replayed without the robots ([`crate::pedestrians::RobotFree`]).
//!
//! Per person `i`, over the robot's episode (instants `0..=T`):
//! - **delay**: the robot-free run's stage changes (way-point reached, a walk's leg done, a task
//!   finished) at instants `c_1 < c_2 < ...` within the episode, the episode's own at
//!   `r_1 < r_2 < ...`; the `k`-th is late by `(r_k - c_k) dt`, or by `(T - c_k) dt` when the
//!   person has not made it yet by the end (at least that late). The person's delay is the
//!   largest of these, floored at 0; 0 for a person whose robot-free run makes no stage change
//!   (standing, talking, sitting through the episode): they have no way-point to be late for.
//! - **extra distance**: at the last stage change both runs made, the distance the person walked
//!   to it in the episode minus the distance walked to it without the robot, floored at 0; 0
//!   without such a stage change.
//! - **path deviation**: the largest distance from the person's position at an instant of the
//!   episode to their robot-free path (the polyline of their robot-free positions over the
//!   episode): how far from their own way the robot pushed them, independent of the delay.
//!   Exactly 0 when the two tracks are identical.
//!
//! Each is reported as its mean and max over all people of the scene (everyone counts, a
//! bystander the robot never disturbed with 0); `None` without people. Katyal et al. 2022
//! ("Learning a Group-Aware Policy for Robot Navigation") measure the people's side by their
//! average velocity; comparing each person with themself in a robot-free replay of the same seed
//! is ours, exact here because the people's model is deterministic.

use serde::Serialize;

use crate::geom::distance_point_segment;
use crate::math::Vec2;

/// The robot-free run as the metrics read it ([`crate::pedestrians::RobotFree::tracks`]).
#[derive(Clone, Copy, Debug)]
pub struct RobotFreeTracks<'a> {
    /// The robot-free people's centres (m), row-major per instant (`instants * P` entries).
    pub positions: &'a [Vec2],
    /// Instants available (steps + 1).
    pub instants: usize,
    /// Per person, the instants of their stage changes in the robot-free run.
    pub stages: &'a [Vec<usize>],
    /// Per person, the instants of their stage changes in the episode.
    pub real_stages: &'a [Vec<usize>],
}

/// The robot's cost to people: delay, extra distance and path deviation, mean and max over
/// people (`None` without people, or without a robot-free run).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct PeopleCostMetrics {
    /// Mean over people of each person's delay (s).
    pub ped_delay_s_mean: Option<f64>,
    /// Largest person's delay (s).
    pub ped_delay_s_max: Option<f64>,
    /// Mean over people of each person's extra distance walked (m).
    pub ped_extra_distance_m_mean: Option<f64>,
    /// Largest person's extra distance walked (m).
    pub ped_extra_distance_m_max: Option<f64>,
    /// Mean over people of each person's path deviation (m).
    pub ped_path_deviation_m_mean: Option<f64>,
    /// Largest person's path deviation (m).
    pub ped_path_deviation_m_max: Option<f64>,
}

/// The cost of the episode's first `n` instants (`n >= 1`) with the people's `real` centres
/// (row-major, at least `n * np`) against the robot-free run `free`, control period `dt`. Only
/// the instants at which a person is `present` (row-major like `real`; empty: always) count in
/// their distances: a replayed person's parked positions before they appear and after they leave
/// are no part of their way.
pub(crate) fn evaluate(
    n: usize,
    np: usize,
    dt: f64,
    real: &[Vec2],
    present: &[bool],
    free: Option<&RobotFreeTracks>,
) -> PeopleCostMetrics {
    let Some(free) = free else { return PeopleCostMetrics::default() };
    let n = n.min(free.instants);
    if np == 0 || n == 0 || real.len() < n * np || free.positions.len() < n * np {
        return PeopleCostMetrics::default();
    }
    let last = n - 1;
    let no_events: Vec<usize> = Vec::new();
    let (mut delay, mut extra, mut dev) = (Vec::new(), Vec::new(), Vec::new());
    for i in 0..np {
        let here = |t: usize| present.get(t * np + i).copied().unwrap_or(true);
        let track =
            |pos: &[Vec2]| -> Vec<Vec2> { (0..n).filter(|&t| here(t)).map(|t| pos[t * np + i]).collect() };
        let cf = free.stages.get(i).unwrap_or(&no_events);
        let re = free.real_stages.get(i).unwrap_or(&no_events);
        // Delay: the robot-free run's stage changes within the episode.
        let mut d = 0.0f64;
        let mut common: Option<(usize, usize)> = None;
        for (k, &c) in cf.iter().enumerate().take_while(|&(_, &c)| c <= last) {
            match re.get(k).filter(|&&r| r <= last) {
                Some(&r) => {
                    d = d.max((r as f64 - c as f64) * dt);
                    common = Some((r, c));
                }
                None => d = d.max((last - c) as f64 * dt),
            }
        }
        delay.push(d);
        // Extra distance to the last stage change both runs made.
        let (a, b) = (track(real), track(free.positions));
        // The distance walked to instant `upto`, over the steps with the person there at both ends.
        let walked = |pos: &[Vec2], upto: usize| -> f64 {
            (0..upto)
                .filter(|&t| here(t) && here(t + 1))
                .map(|t| (pos[(t + 1) * np + i] - pos[t * np + i]).norm())
                .sum()
        };
        extra.push(common.map_or(0.0, |(r, c)| (walked(real, r) - walked(free.positions, c)).max(0.0)));
        // Path deviation from the robot-free path.
        dev.push(if a == b { 0.0 } else { deviation(&a, &b) });
    }
    let mean = |v: &[f64]| Some(v.iter().sum::<f64>() / v.len() as f64);
    let max = |v: &[f64]| Some(v.iter().copied().fold(0.0, f64::max));
    PeopleCostMetrics {
        ped_delay_s_mean: mean(&delay),
        ped_delay_s_max: max(&delay),
        ped_extra_distance_m_mean: mean(&extra),
        ped_extra_distance_m_max: max(&extra),
        ped_path_deviation_m_mean: mean(&dev),
        ped_path_deviation_m_max: max(&dev),
    }
}

/// Largest distance from a point of `track` to the polyline `path` (m).
///
/// Each point tries the segments outwards from its own instant's (the two tracks run in step,
/// so the nearest segment comes early), one forwards and one backwards in turn, and stops as
/// soon as one is within the largest distance found so far: such a point cannot raise it.
///
/// Segments that cannot be nearer than the nearest one found so far are skipped by arc length:
/// if segment `j` is at distance `d` from the point `p`, any point `q` of the path reachable
/// from a vertex `v` of segment `j` along the path within arc length `a` is at distance
/// `|p - q| >= |p - v| - |v - q| >= d - a` (triangle inequality, `|p - v| >= d` because `v` is on
/// segment `j`, `|v - q| <= a` because the straight line is no longer than the path). So going
/// forwards from `v = path[j + 1]`, segment `m > j` (whose far end `path[m + 1]` is at arc
/// `arc[m + 1] - arc[j + 1]`) is farther than `near` when `arc[m + 1] - arc[j + 1] < d - near`,
/// and backwards from `v = path[j]`, segment `m < j` when `arc[j] - arc[m] < d - near`; a margin
/// of `1e-9 (1 + total length + d + near)` m, far above the rounding of the sums and distances,
/// keeps the test conservative. Only segments whose computed distance exceeds the minimum are
/// skipped, so each point's minimum, and the maximum over points, is the same computed value as
/// trying every segment, bit for bit, at a cost that grows with the path's length over the
/// point's distance instead of with its number of segments.
///
/// A person standing still repeats one vertex over many instants: the same zero-length segment
/// over and over, all at one distance from a point, so the arc length bound (no arc between
/// them) skips none of them and a point near that spot would try them all. Such a run is kept
/// as one zero-length segment (the third and later copies of a vertex, equal bit for bit, are
/// dropped), which leaves the set of segments, so each point's minimum, unchanged.
fn deviation(track: &[Vec2], path: &[Vec2]) -> f64 {
    if path.len() < 2 {
        let to_path = |p: Vec2| path.first().map_or(f64::INFINITY, |&q| (p - q).norm());
        return track.iter().map(|&p| to_path(p)).fold(0.0, f64::max);
    }
    let same = |a: Vec2, b: Vec2| a.x.to_bits() == b.x.to_bits() && a.y.to_bits() == b.y.to_bits();
    // kept[j]: how many of path[..=j] are kept, so path[j] is (or repeats) the kept vertex
    // kept[j] - 1.
    let mut vertices: Vec<Vec2> = Vec::with_capacity(path.len());
    let mut kept = Vec::with_capacity(path.len());
    for (k, &v) in path.iter().enumerate() {
        if k < 2 || !(same(v, path[k - 1]) && same(v, path[k - 2])) {
            vertices.push(v);
        }
        kept.push(vertices.len());
    }
    let path = &vertices[..];
    let segments = path.len() - 1;
    // The segment of the collapsed path that instant t's segment is, or repeats (where the search
    // starts: any start gives the same minimum).
    let own = |t: usize| (kept[t.min(kept.len() - 2)] - 1).min(segments - 1);
    // arc[k]: the path's length from path[0] to path[k] (m), non-decreasing.
    let mut arc = Vec::with_capacity(path.len());
    let mut total = 0.0f64;
    arc.push(total);
    for w in path.windows(2) {
        total += (w[1] - w[0]).norm();
        arc.push(total);
    }
    let margin = |d: f64, near: f64| 1e-9 * (1.0 + total + d + near);
    let distance = |p: Vec2, j: usize| distance_point_segment(p, path[j], path[j + 1]);
    let mut worst = 0.0f64;
    // The points farthest from their own instant's segment first, so `worst` rises early and
    // the others stop sooner (the maximum of exact minima does not depend on the order).
    let mut order: Vec<(f64, usize)> =
        track.iter().enumerate().map(|(t, &p)| (distance(p, own(t)), t)).collect();
    order.sort_unstable_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    for (first, t) in order {
        let p = track[t];
        let start = own(t);
        let mut near = first;
        // Forwards: segments `fwd..segments` are left, measured from the vertex at arc `fwd_arc`
        // of a segment at distance `fwd_d`; backwards: segments `0..bwd` are left.
        let (mut fwd, mut fwd_arc, mut fwd_d) = (start + 1, arc[start + 1], near);
        let (mut bwd, mut bwd_arc, mut bwd_d) = (start, arc[start], near);
        while near > worst && (fwd < segments || bwd > 0) {
            if fwd < segments {
                // Skip the segments whose far end is within arc `fwd_d - near` of the vertex.
                let reach = fwd_arc + (fwd_d - near - margin(fwd_d, near));
                // (The next segment is usually not skipped: test it before searching.)
                let m = if arc[fwd + 1] < reach {
                    fwd + 1 + arc[fwd + 2..].partition_point(|&a| a < reach)
                } else {
                    fwd
                };
                if m < segments {
                    fwd_d = distance(p, m);
                    near = near.min(fwd_d);
                    fwd_arc = arc[m + 1];
                }
                fwd = m + 1;
            }
            if bwd > 0 && near > worst {
                let floor = bwd_arc - (bwd_d - near - margin(bwd_d, near));
                // (No skip if `floor` is NaN: the comparison below is false.)
                let left =
                    if arc[bwd - 1] > floor { arc[..bwd - 1].partition_point(|&a| a <= floor) } else { bwd };
                if left > 0 {
                    let m = left - 1;
                    bwd_d = distance(p, m);
                    near = near.min(bwd_d);
                    bwd_arc = arc[m];
                }
                bwd = left.saturating_sub(1);
            }
        }
        worst = worst.max(near);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every point against every segment: the definition.
    fn deviation_brute(track: &[Vec2], path: &[Vec2]) -> f64 {
        let to_path = |p: Vec2| -> f64 {
            if path.len() == 1 {
                return (p - path[0]).norm();
            }
            path.windows(2).map(|w| distance_point_segment(p, w[0], w[1])).fold(f64::INFINITY, f64::min)
        };
        track.iter().map(|&p| to_path(p)).fold(0.0, f64::max)
    }

    #[test]
    fn deviation_is_the_largest_distance_to_the_path_bit_for_bit() {
        // A deterministic wander (a linear congruential sequence) of tracks of several lengths,
        // the path drifting away from the track and back, with detours at random instants.
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for len in [0usize, 1, 2, 3, 7, 50, 301] {
            for _ in 0..20 {
                let track: Vec<Vec2> =
                    (0..len).map(|t| Vec2::new(0.05 * t as f64 + next(), 2.0 * next())).collect();
                let path: Vec<Vec2> =
                    track.iter().map(|&p| p + Vec2::new(3.0 * next(), 3.0 * next())).collect();
                for path_len in [0, 1, path.len()].into_iter().filter(|&k| k <= path.len()) {
                    let (a, b) =
                        (deviation(&track, &path[..path_len]), deviation_brute(&track, &path[..path_len]));
                    assert_eq!(a.to_bits(), b.to_bits(), "len {len}, path {path_len}: {a} vs {b}");
                }
            }
        }
        // Long tracks against paths that leave far and come back, loop round the same circle
        // (segments far along the path but near in space), stand still (zero-length segments),
        // run backwards in time, or stand for long runs of instants at a few spots (one vertex
        // repeated bit for bit) with the track a hair away from them (a seated person the
        // robot barely moved: the runs collapse to one segment).
        for len in [2000usize, 2001] {
            for shape in 0..6 {
                let track: Vec<Vec2> = (0..len)
                    .map(|t| {
                        let a = t as f64 * 0.031;
                        Vec2::new(5.0 * a.cos() + 0.3 * next(), 5.0 * a.sin() + 0.3 * next())
                    })
                    .collect();
                let path: Vec<Vec2> = match shape {
                    0 => track
                        .iter()
                        .enumerate()
                        .map(|(t, &p)| p + Vec2::new(8.0 * (t as f64 * 0.004).sin().powi(3), next()))
                        .collect(),
                    1 => (0..len)
                        .map(|t| {
                            let a = t as f64 * 0.047;
                            Vec2::new(4.0 * a.cos(), 6.0 * a.sin()) + Vec2::new(0.2 * next(), 0.2 * next())
                        })
                        .collect(),
                    2 => track
                        .iter()
                        .map(|&p| if next() > 0.3 { p } else { p + Vec2::new(20.0, 0.0) })
                        .collect(),
                    3 => track
                        .iter()
                        .map(|&p| Vec2::new((p.x * 2.0).round() / 2.0, (p.y * 2.0).round() / 2.0))
                        .collect(),
                    4 => track.iter().rev().map(|&p| p + Vec2::new(next(), next())).collect(),
                    _ => (0..len)
                        .map(|t| {
                            let spot = (t / 400) as f64;
                            if t % 400 < 370 { Vec2::new(spot, 0.5 * spot) } else { track[t] }
                        })
                        .collect(),
                };
                let track: Vec<Vec2> = if shape == 5 {
                    path.iter().map(|&p| p + Vec2::new(1e-4 * next(), 1e-4 * next())).collect()
                } else {
                    track
                };
                let (a, b) = (deviation(&track, &path), deviation_brute(&track, &path));
                assert_eq!(a.to_bits(), b.to_bits(), "len {len}, shape {shape}: {a} vs {b}");
                let (a, b) = (deviation(&path, &track), deviation_brute(&path, &track));
                assert_eq!(a.to_bits(), b.to_bits(), "len {len}, shape {shape} swapped: {a} vs {b}");
            }
        }
    }
}
