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
/// (row-major, at least `n * np`) against the robot-free run `free`, control period `dt`.
pub(crate) fn evaluate(
    n: usize,
    np: usize,
    dt: f64,
    real: &[Vec2],
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
        let track = |pos: &[Vec2]| -> Vec<Vec2> { (0..n).map(|t| pos[t * np + i]).collect() };
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
        let walked = |pts: &[Vec2], upto: usize| -> f64 {
            pts[..=upto].windows(2).map(|w| (w[1] - w[0]).norm()).sum()
        };
        extra.push(common.map_or(0.0, |(r, c)| (walked(&a, r) - walked(&b, c)).max(0.0)));
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
/// Each point tries the segments in order of their distance in time from its own instant (the
/// two tracks run in step, so the nearest segment comes early) and stops as soon as one is
/// within the largest distance found so far: such a point cannot raise it, so the result is
/// the same maximum as trying every segment, without the quadratic cost.
fn deviation(track: &[Vec2], path: &[Vec2]) -> f64 {
    if path.len() < 2 {
        let to_path = |p: Vec2| path.first().map_or(f64::INFINITY, |&q| (p - q).norm());
        return track.iter().map(|&p| to_path(p)).fold(0.0, f64::max);
    }
    let segments = path.len() - 1;
    let distance = |p: Vec2, j: usize| distance_point_segment(p, path[j], path[j + 1]);
    let mut worst = 0.0f64;
    for (t, &p) in track.iter().enumerate() {
        let start = t.min(segments - 1);
        let mut near = distance(p, start);
        let mut step = 1;
        while near > worst && (step <= start || start + step < segments) {
            if start + step < segments {
                near = near.min(distance(p, start + step));
            }
            if step <= start {
                near = near.min(distance(p, start - step));
            }
            step += 1;
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
    }
}
