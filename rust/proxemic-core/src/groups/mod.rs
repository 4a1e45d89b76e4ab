//! Group detection and groups as individuals.
//!
//! Three detectors, chosen per scenario through [`GroupMethod`]:
//! - [`GroupMethod::Delaunay`]: Delaunay triangulation of the positions with the distance rule
//!   (`d_max`) and the orientation rule (T-space, reference triangle T*, peripheral triangles T') of
//!   Sousa et al. 2022, §3.2 and §4.1-4.2, extended with the Movement dimension of Daza et al. 2021
//!   (DILMO, §2): people walking together with agreeing velocities form a moving group. See
//!   [`delaunay`] for the exact rules.
//! - [`GroupMethod::Density`]: the Gaussian-mixture density clustering of Calderita et al.
//!   (§4.1, eq. 5-8, threshold `phi = 1 + k*delta`). See [`density`].
//! - [`GroupMethod::FFormation`]: a deterministic greedy, GCFF-like o-space assignment (Setti et al.
//!   2015). See [`fformation`].
//!
//! Around them:
//! - [`group_as_individual`]: a group as one individual (Sousa 2022 §3.3.4).
//! - [`detection_accuracy`]: GCFF-style precision / recall / F1 of detected groups against ground
//!   truth.
//! - [`robot_joins_interaction`]: a stationary robot inside a person's personal zone is part of
//!   that person's interaction (Daza 2021 §4.3).
//!
//! All detectors are deterministic: the result depends only on the set of people, never on hash
//! order, and (up to renaming of labels) not on the input order either, except for exactly
//! cocircular Delaunay configurations, where the triangulation itself is not unique.

pub mod accuracy;
pub mod delaunay;
pub mod density;
pub mod fformation;
pub mod individual;
mod mesh;
pub mod robots;

#[cfg(test)]
mod tests;

pub use accuracy::{Accuracy, MATCH_THRESHOLD, detection_accuracy};
pub use delaunay::DelaunayParams;
pub use density::DensityParams;
pub use fformation::FFormationParams;
pub use individual::{FeatureAggregate, GroupIndividual, group_as_individual};
pub use robots::{JoinParams, RobotDisc, robot_joins_interaction};

use crate::error::{CoreError, Result};
use crate::math::{Real, Vec2};

/// Largest accepted absolute coordinate of a position (metres). Larger values are rejected so that
/// squared distances and the triangulation's exact predicates cannot overflow.
pub const MAX_COORD: Real = 1e9;

/// The state of one person as the group detectors see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PersonState {
    /// Position in the world frame (metres). Must be finite with `|x|, |y| <= MAX_COORD`.
    pub pos: Vec2,
    /// Body orientation in the world frame (radians, any finite value; wrapped internally).
    pub heading: Real,
    /// Velocity in the world frame (metres per second, finite).
    pub vel: Vec2,
}

impl PersonState {
    /// A standing person (zero velocity) at `pos` (m) facing `heading` (rad).
    pub fn standing(pos: Vec2, heading: Real) -> Self {
        Self { pos, heading, vel: Vec2::zeros() }
    }

    /// A walking person at `pos` (m) with velocity `vel` (m/s), facing along the velocity (the
    /// heading is `atan2(vel.y, vel.x)`, or 0 for a zero velocity).
    pub fn walking(pos: Vec2, vel: Vec2) -> Self {
        let heading = if vel.norm_squared() > 0.0 { vel.y.atan2(vel.x) } else { 0.0 };
        Self { pos, heading, vel }
    }

    /// Speed (m/s).
    pub fn speed(&self) -> Real {
        self.vel.norm()
    }

    /// Unit vector of the body orientation.
    pub fn facing(&self) -> Vec2 {
        let (s, c) = self.heading.sin_cos();
        Vec2::new(c, s)
    }
}

/// Which detector [`detect`] runs, with its parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GroupMethod {
    /// Delaunay triangulation with distance, orientation and movement rules (Sousa 2022, Daza 2021).
    Delaunay(DelaunayParams),
    /// Gaussian-mixture density clustering (Calderita eq. 5-8).
    Density(DensityParams),
    /// Greedy GCFF-like F-formation (o-space) detection for standing people.
    FFormation(FFormationParams),
}

impl Default for GroupMethod {
    /// The Delaunay detector with its default parameters.
    fn default() -> Self {
        GroupMethod::Delaunay(DelaunayParams::default())
    }
}

/// A partition of the people into groups.
///
/// Singletons are groups of one. Groups are ordered by their smallest member index, and members
/// within a group are in increasing index order, so the result is canonical.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Groups {
    /// `labels[i]` is the index into [`Groups::members`] of person `i`'s group.
    pub labels: Vec<usize>,
    /// The members (person indices, increasing) of each group.
    pub members: Vec<Vec<usize>>,
}

impl Groups {
    /// Number of groups, singletons included.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when there are no people.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// The groups with at least two members.
    pub fn multi(&self) -> impl Iterator<Item = &Vec<usize>> {
        self.members.iter().filter(|m| m.len() > 1)
    }

    /// Builds the canonical partition from any per-person labels (equal label = same group).
    pub fn from_labels(raw: &[usize]) -> Self {
        let mut uf = UnionFind::new(raw.len());
        let mut order: Vec<usize> = (0..raw.len()).collect();
        order.sort_by_key(|&i| (raw[i], i));
        for w in order.windows(2) {
            if raw[w[0]] == raw[w[1]] {
                uf.union(w[0], w[1]);
            }
        }
        uf.into_groups()
    }
}

/// Runs the chosen detector on `people`.
///
/// Errors: a non-finite or out-of-range position, heading or velocity (`people[i].pos`,
/// `people[i].heading`, `people[i].vel`), or invalid parameters (named by their field).
/// An empty input gives empty [`Groups`].
pub fn detect(people: &[PersonState], method: &GroupMethod) -> Result<Groups> {
    detect_with(people, method, &mut DetectorMemory::default())
}

/// What a detector carries from one call to the next to answer faster: the Delaunay detector's
/// triangulation. When the people have moved a little, the previous triangulation is moved with
/// them and repaired by Lawson's edge flips (with boundary vertices filled in or peeled off as
/// people enter or leave the boundary), and kept only when exact predicates prove it is the
/// unique Delaunay triangulation of the new positions; otherwise (a triangle folded over, four
/// people exactly cocircular, ...) `spade` triangulates afresh. It never changes a result:
/// [`detect_with`] gives [`detect`]'s groups whatever the memory holds. The density and
/// F-formation detectors carry nothing.
#[derive(Debug, Clone, Default)]
pub struct DetectorMemory {
    mesh: Option<mesh::Mesh>,
}

/// [`detect`], reusing and updating `memory` (kept by the caller between control steps).
///
/// Errors: as [`detect`].
pub fn detect_with(
    people: &[PersonState],
    method: &GroupMethod,
    memory: &mut DetectorMemory,
) -> Result<Groups> {
    validate_people(people)?;
    match method {
        GroupMethod::Delaunay(p) => delaunay::detect(people, p, &mut memory.mesh),
        GroupMethod::Density(p) => density::detect(people, p),
        GroupMethod::FFormation(p) => fformation::detect(people, p),
    }
}

/// Checks every person's fields; the error names `people[i].<field>`.
pub(crate) fn validate_people(people: &[PersonState]) -> Result<()> {
    for (i, p) in people.iter().enumerate() {
        if !(p.pos.x.is_finite() && p.pos.y.is_finite())
            || p.pos.x.abs() > MAX_COORD
            || p.pos.y.abs() > MAX_COORD
        {
            return Err(CoreError::input(
                format!("people[{i}].pos"),
                format!("finite coordinates with absolute value <= {MAX_COORD} m"),
                format!("({}, {})", p.pos.x, p.pos.y),
            ));
        }
        if !p.heading.is_finite() {
            return Err(CoreError::input(
                format!("people[{i}].heading"),
                "a finite angle in radians",
                p.heading.to_string(),
            ));
        }
        if !(p.vel.x.is_finite() && p.vel.y.is_finite()) {
            return Err(CoreError::input(
                format!("people[{i}].vel"),
                "a finite velocity in m/s",
                format!("({}, {})", p.vel.x, p.vel.y),
            ));
        }
    }
    Ok(())
}

/// Checks that `value` is finite and within `[lo, hi]`; the error names `field`.
pub(crate) fn check_range(field: &str, value: Real, lo: Real, hi: Real) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(CoreError::input(field, format!("a finite value in [{lo}, {hi}]"), value.to_string()))
    }
}

/// Checks that `value` is finite and strictly positive (and at most `hi`).
pub(crate) fn check_positive(field: &str, value: Real, hi: Real) -> Result<()> {
    if value.is_finite() && value > 0.0 && value <= hi {
        Ok(())
    } else {
        Err(CoreError::input(field, format!("a finite value in (0, {hi}]"), value.to_string()))
    }
}

/// Union-find over person indices; the root of every set is its smallest index, so results do
/// not depend on the order of `union` calls.
#[derive(Debug, Clone)]
pub(crate) struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    pub(crate) fn new(n: usize) -> Self {
        Self { parent: (0..n).collect() }
    }

    pub(crate) fn find(&mut self, mut x: usize) -> usize {
        let mut root = x;
        while self.parent[root] != root {
            root = self.parent[root];
        }
        while self.parent[x] != root {
            let next = self.parent[x];
            self.parent[x] = root;
            x = next;
        }
        root
    }

    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }

    /// The canonical [`Groups`]: groups ordered by smallest member.
    pub(crate) fn into_groups(mut self) -> Groups {
        let n = self.parent.len();
        let mut label_of_root = vec![usize::MAX; n];
        let mut labels = Vec::with_capacity(n);
        let mut members: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            let r = self.find(i);
            if label_of_root[r] == usize::MAX {
                label_of_root[r] = members.len();
                members.push(Vec::new());
            }
            let l = label_of_root[r];
            labels.push(l);
            members[l].push(i);
        }
        Groups { labels, members }
    }
}
