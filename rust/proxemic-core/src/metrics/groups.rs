//! Groups and interactions (`docs/metrics.md`, Groups and interactions): the share of instants per Hall zone of
//! the closest o-space centre (HuNav's IS_prox), the time inside o-spaces and the entries into
//! them, and the crossings of interaction segments (person-person and person-object).

use serde::Serialize;

use super::{Groups, LinkKind, Samples, pct, zone_of};
use crate::geom::cross;
use crate::math::{EPS, Vec2};

/// The group and interaction metrics of an episode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GroupMetrics {
    /// Percentage of instants with the robot centre's distance to the closest o-space *centre*
    /// in `[0, zones[0])` (HuNav IS_prox; `docs/metrics.md`, Groups and interactions); `None` without samples.
    pub group_psi_intimate: Option<f64>,
    /// Same in `[zones[0], zones[1])`.
    pub group_psi_personal: Option<f64>,
    /// Same in `[zones[1], zones[2])`.
    pub group_psi_social: Option<f64>,
    /// Same at `>= zones[2]` or with no group present.
    pub group_psi_public: Option<f64>,
    /// Percentage of instants with the robot centre inside some o-space circle (distance to
    /// its centre <= radius) (`docs/metrics.md`, Groups and interactions); `None` without samples.
    pub ospace_pct: Option<f64>,
    /// Time with the robot centre inside some o-space (s): the steps starting at an instant
    /// inside times `dt` (each step's interval `[t, t + 1)` counted by its start, as
    /// `stalled_time`; the last instant starts no step), so at most the episode's duration.
    pub ospace_time: f64,
    /// Entries into o-spaces: instants inside some o-space after an instant inside none (the
    /// first instant counts if inside).
    pub ospace_entries: usize,
    /// Interaction crossings (`docs/metrics.md`, Groups and interactions): steps whose centre segment `[p_t, p_{t+1})`
    /// intersects an interaction segment present at instant `t` (half-open, so a crossing
    /// through a sample point counts once; parallel segments never cross).
    pub interaction_crossings: usize,
    /// The person-person part of `interaction_crossings`.
    pub interaction_crossings_person_person: usize,
    /// The person-object part of `interaction_crossings`.
    pub interaction_crossings_person_object: usize,
}

/// The rows `lo..hi` of instant `t` in compressed rows `offsets` (empty offsets: no rows).
fn rows(offsets: &[usize], t: usize) -> (usize, usize) {
    if offsets.is_empty() { (0, 0) } else { (offsets[t], offsets[t + 1]) }
}

/// The group metrics of the recording `s` (control period `dt`, s) among the o-spaces and
/// interaction segments `groups`, with the Hall zone radii `zones` (m).
pub(crate) fn evaluate(s: &Samples, dt: f64, groups: &Groups, zones: &[f64; 3]) -> GroupMetrics {
    let n = s.n;
    let mut group_zone_counts = [0usize; 4];
    let mut inside_count = 0usize;
    let mut inside_steps = 0usize;
    let mut ospace_entries = 0usize;
    let mut was_inside = false;
    for (t, &p) in s.pos.iter().enumerate() {
        let (lo, hi) = rows(groups.ospace_offsets, t);
        let mut closest = f64::INFINITY;
        let mut inside = false;
        for o in &groups.ospaces[lo..hi] {
            let d = (p - o.centre).norm();
            closest = closest.min(d);
            inside |= d <= o.radius;
        }
        group_zone_counts[zone_of(closest, zones)] += 1;
        inside_count += usize::from(inside);
        inside_steps += usize::from(inside && t < s.steps);
        ospace_entries += usize::from(inside && !was_inside);
        was_inside = inside;
    }
    let (mut cross_pp, mut cross_po) = (0usize, 0usize);
    for t in 0..s.steps {
        let (lo, hi) = rows(groups.link_offsets, t);
        for l in &groups.links[lo..hi] {
            if crosses(s.pos[t], s.pos[t + 1], l.a, l.b) {
                match l.kind {
                    LinkKind::PersonPerson => cross_pp += 1,
                    LinkKind::PersonObject => cross_po += 1,
                }
            }
        }
    }
    GroupMetrics {
        group_psi_intimate: pct(group_zone_counts[0], n),
        group_psi_personal: pct(group_zone_counts[1], n),
        group_psi_social: pct(group_zone_counts[2], n),
        group_psi_public: pct(group_zone_counts[3], n),
        ospace_pct: pct(inside_count, n),
        ospace_time: inside_steps as f64 * dt,
        ospace_entries,
        interaction_crossings: cross_pp + cross_po,
        interaction_crossings_person_person: cross_pp,
        interaction_crossings_person_object: cross_po,
    }
}

/// Whether the half-open segment `[p, q)` intersects the closed segment `[a, b]` (parallel or
/// degenerate segments never intersect).
fn crosses(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> bool {
    let r = q - p;
    let s = b - a;
    let denom = cross(r, s);
    if denom.abs() <= EPS * (r.norm() * s.norm()).max(EPS) {
        return false;
    }
    let ap = a - p;
    let t = cross(ap, s) / denom;
    let u = cross(ap, r) / denom;
    (0.0..1.0).contains(&t) && (0.0..=1.0).contains(&u)
}
