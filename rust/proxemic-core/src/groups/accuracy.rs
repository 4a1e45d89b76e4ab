//! Group-detection accuracy as in GCFF's evaluation (Setti et al. 2015; `algorithms.md` §5.3).
//!
//! Groups of one are removed from both sides first (GCFF's `ff_deletesingletons`): being alone is
//! not a detected group. A detected group `D` **matches** a ground-truth group `G` when at least
//! `ceil(T * |G|)` of `G`'s members are in `D` and at most `floor((1 - T) * |G|)` members of `D`
//! are not in `G` (T = 2/3 is the usual tolerant setting, T = 1 the strict one). Each
//! ground-truth group can be matched once; detected groups are visited in order of their smallest
//! member, and each takes the first unmatched ground-truth group it matches (with `T > 1/2` a
//! detected group can match at most one ground-truth group anyway).
//!
//! `precision = TP / #detected`, `recall = TP / #truth`, `f1 = 2PR / (P + R)`. With no groups on
//! a side the corresponding ratio is 1 when the other side is also empty and 0 otherwise; `f1` is
//! 0 when `P + R = 0`.

use serde::Serialize;

use super::Groups;
use crate::error::{CoreError, Result};
use crate::math::Real;

/// GCFF's tolerant match threshold `T = 2/3` (Setti et al. 2015): a detected group matches a
/// true one holding at least 2/3 of its members, with at most 1/3 outsiders. The threshold of
/// [`crate::world::World::perception_report`]'s scores.
pub const MATCH_THRESHOLD: Real = 2.0 / 3.0;

/// Precision, recall and F1 of a group detection, each in [0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Accuracy {
    /// Matched detected groups over detected groups.
    pub precision: Real,
    /// Matched ground-truth groups over ground-truth groups.
    pub recall: Real,
    /// Harmonic mean of precision and recall.
    pub f1: Real,
    /// Number of matched groups (true positives).
    pub true_positives: usize,
    /// Number of detected groups with at least two members.
    pub detected: usize,
    /// Number of ground-truth groups with at least two members.
    pub truth: usize,
}

/// Scores detected group labels against ground truth.
///
/// `detected[i]` is person `i`'s detected group label (e.g. [`Groups::labels`]); `truth[i]` is
/// the ground-truth group id from the scenario, `None` for a person who is alone. `threshold` is
/// `T` in (0, 1] (2/3 in GCFF). Errors: lengths differ (`truth`), or `threshold` outside (0, 1].
pub fn detection_accuracy(detected: &[usize], truth: &[Option<u32>], threshold: Real) -> Result<Accuracy> {
    if truth.len() != detected.len() {
        return Err(CoreError::input(
            "truth",
            format!("{} entries, one per person", detected.len()),
            truth.len().to_string(),
        ));
    }
    if !(threshold.is_finite() && threshold > 0.0 && threshold <= 1.0) {
        return Err(CoreError::input("threshold", "a value in (0, 1]", threshold.to_string()));
    }
    let det: Vec<Vec<usize>> =
        Groups::from_labels(detected).members.into_iter().filter(|m| m.len() > 1).collect();
    // Ground truth: people with the same Some(id) form a group; None people are alone.
    let mut ids: Vec<(u32, usize)> =
        truth.iter().enumerate().filter_map(|(i, t)| t.map(|id| (id, i))).collect();
    ids.sort_unstable();
    let mut gt: Vec<Vec<usize>> = Vec::new();
    for (k, &(id, i)) in ids.iter().enumerate() {
        if k > 0 && ids[k - 1].0 == id {
            if let Some(last) = gt.last_mut() {
                last.push(i);
            }
        } else {
            gt.push(vec![i]);
        }
    }
    gt.retain(|g| g.len() > 1);
    gt.sort_by_key(|g| g[0]);

    let eps = 1e-9;
    let mut used = vec![false; gt.len()];
    let mut tp = 0;
    for d in &det {
        for (gi, g) in gt.iter().enumerate() {
            if used[gi] {
                continue;
            }
            let common = d.iter().filter(|i| g.binary_search(i).is_ok()).count();
            let false_members = d.len() - common;
            let size = g.len() as Real;
            let need = (threshold * size - eps).ceil();
            let allowed = ((1.0 - threshold) * size + eps).floor();
            if common as Real >= need && false_members as Real <= allowed {
                used[gi] = true;
                tp += 1;
                break;
            }
        }
    }
    let ratio = |num: usize, den: usize, other: usize| {
        if den > 0 {
            num as Real / den as Real
        } else if other == 0 {
            1.0
        } else {
            0.0
        }
    };
    let precision = ratio(tp, det.len(), gt.len());
    let recall = ratio(tp, gt.len(), det.len());
    let f1 = if precision + recall > 0.0 { 2.0 * precision * recall / (precision + recall) } else { 0.0 };
    Ok(Accuracy { precision, recall, f1, true_positives: tp, detected: det.len(), truth: gt.len() })
}
