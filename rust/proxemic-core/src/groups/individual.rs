//! A group as one individual (Sousa et al. 2022, §3.3.4).
//!
//! - Position: the midpoint (mean) of the members' positions.
//! - Orientation: "the mean of orientations"; we use the circular mean `atan2(sum sin, sum cos)`
//!   so that headings across the +-pi wrap average correctly. When the resultant is
//!   (numerically) zero, e.g. two people facing each other, the mean is undefined and the first
//!   member's heading is used (documented fallback).
//! - Shape: four quadrants around the group orientation, each a 90 degree sector centred on the
//!   front, left, rear and right directions (boundaries on the diagonals; a member exactly on a
//!   diagonal counts as front or rear). In each quadrant the member farthest from the centre
//!   gives that side's vertex; the extent is its distance from the centre (0 for an empty
//!   quadrant, and for a member exactly at the centre).
//! - Feature: one value aggregated from the members' values ([`FeatureAggregate`]).

use crate::error::{CoreError, Result};
use crate::math::{Real, Vec2, wrap_angle};

use super::{PersonState, validate_people};

/// How a group's single feature value is combined from its members' values in (0, 1].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FeatureAggregate {
    /// Arithmetic mean (default).
    #[default]
    Mean,
    /// Minimum: the least socially accepting member decides (conservative).
    Min,
    /// Statistical mode (exact equality of values); ties resolve to the smallest value.
    Mode,
}

/// A group seen as one individual with its own asymmetric personal space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroupIndividual {
    /// Centre of the group: the members' mean position (m, world frame).
    pub centre: Vec2,
    /// Orientation: circular mean of the members' headings (rad, in (-pi, pi]).
    pub heading: Real,
    /// Distance from the centre to the farthest member in the front quadrant (m, >= 0).
    pub front: Real,
    /// Distance from the centre to the farthest member in the rear quadrant (m, >= 0).
    pub rear: Real,
    /// Distance from the centre to the farthest member in the left quadrant (m, >= 0).
    pub left: Real,
    /// Distance from the centre to the farthest member in the right quadrant (m, >= 0).
    pub right: Real,
    /// The quadrilateral's vertices (front, left, rear, right), `None` for an empty quadrant.
    pub vertices: [Option<Vec2>; 4],
    /// The group's single feature value, in (0, 1].
    pub feature: Real,
}

/// Builds the individual that stands for a group.
///
/// `features[i]` is member `i`'s feature value in (0, 1]; it must have one value per member.
/// Errors: no members (`members`), a length mismatch or a value outside (0, 1] (`features[i]`),
/// or an invalid person (`people[i]...`, indices into `members`).
pub fn group_as_individual(
    members: &[PersonState],
    features: &[Real],
    aggregate: FeatureAggregate,
) -> Result<GroupIndividual> {
    if members.is_empty() {
        return Err(CoreError::input("members", "at least one person", "0"));
    }
    validate_people(members)?;
    if features.len() != members.len() {
        return Err(CoreError::input(
            "features",
            format!("{} values, one per member", members.len()),
            features.len().to_string(),
        ));
    }
    for (i, &f) in features.iter().enumerate() {
        if !(f.is_finite() && f > 0.0 && f <= 1.0) {
            return Err(CoreError::input(format!("features[{i}]"), "a value in (0, 1]", f.to_string()));
        }
    }
    let n = members.len() as Real;
    let centre = members.iter().fold(Vec2::zeros(), |acc, p| acc + p.pos) / n;
    let (s, c) = members.iter().fold((0.0, 0.0), |(s, c), p| {
        let (ps, pc) = p.heading.sin_cos();
        (s + ps, c + pc)
    });
    let heading = if (s * s + c * c).sqrt() > 1e-9 * n { s.atan2(c) } else { wrap_angle(members[0].heading) };

    let (hs, hc) = heading.sin_cos();
    let mut best: [(Real, Option<Vec2>); 4] = [(0.0, None); 4];
    for p in members {
        let d = p.pos - centre;
        let u = hc * d.x + hs * d.y; // ahead
        let v = -hs * d.x + hc * d.y; // left
        let q = if u.abs() >= v.abs() {
            if u >= 0.0 { 0 } else { 2 }
        } else if v > 0.0 {
            1
        } else {
            3
        };
        let r = d.norm();
        if best[q].1.is_none() || r > best[q].0 {
            best[q] = (r, Some(p.pos));
        }
    }
    let feature = match aggregate {
        FeatureAggregate::Mean => features.iter().sum::<Real>() / n,
        FeatureAggregate::Min => features.iter().copied().fold(Real::INFINITY, Real::min),
        FeatureAggregate::Mode => {
            let mut sorted = features.to_vec();
            sorted.sort_by(|a, b| a.total_cmp(b));
            let (mut best_v, mut best_n) = (sorted[0], 0usize);
            let mut k = 0;
            while k < sorted.len() {
                let run = sorted[k..].iter().take_while(|&&x| x == sorted[k]).count();
                if run > best_n {
                    best_n = run;
                    best_v = sorted[k];
                }
                k += run;
            }
            best_v
        }
    };
    Ok(GroupIndividual {
        centre,
        heading,
        front: best[0].0,
        left: best[1].0,
        rear: best[2].0,
        right: best[3].0,
        vertices: [best[0].1, best[1].1, best[2].1, best[3].1],
        feature,
    })
}
