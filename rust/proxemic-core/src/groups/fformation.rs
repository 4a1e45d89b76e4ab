//! F-formation (o-space) detection for standing people: a deterministic greedy version of GCFF
//! (Setti, Russell, Bassetti, Cristani, "F-formation detection: individuating free-standing
//! conversational groups in images", PLoS ONE 10(5), 2015), as specified in the design notes
//! (`algorithms.md` §5.3).
//!
//! # Model
//!
//! A standing person `i` at `p_i` facing `f_i` votes for the o-space centre
//! `c_i = p_i + stride * f_i` (Kendon's o-space; stride 0.65 m as in adaptive_social_layers).
//! Every person is assigned to one label `g` with centre `o_g`, minimising
//!
//! `E = sum_i ( |c_i - o_g(i)|^2 + Vis(i, g(i)) ) + mdl * (#labels used)`.
//!
//! `Vis(i, g)` (GCFF's visibility term): for every other member `j` of `g` that is nearer to `o_g`
//! than `i` and in nearly the same direction from it (`cos > 0.75` between `p_i - o_g` and
//! `p_j - o_g`), add `100^(cos * |p_i - o_g| / |p_j - o_g|)`: `i` would be occluded by `j`.
//!
//! # Optimisation (replaces GCFF's graph-cut alpha-expansion)
//!
//! Start with one label per person at `o = c_i`. Repeat at most `max_iterations` times:
//! 1. for each standing person in index order, move it to the label that lowers `E` most: any
//!    label in use (cost: its unary term), a fresh singleton label (cost `mdl`), or stay (its
//!    unary term, plus `mdl` if it is alone); ties keep the current choice, then the lowest label;
//! 2. refit every label's centre to the mean of its members' `c_i`;
//! 3. merge labels whose centres are closer than `merge_distance` (the lower label absorbs);
//!
//! until the assignment stops changing. Moving people (speed >= `moving_speed`) are not part of
//! F-formations and come out as singletons. The greedy order is the input order, so unlike the
//! Delaunay and density detectors this one may (rarely) depend on the order of the people.

use super::{GroupMethod, Groups, PersonState, UnionFind, check_positive, check_range};
use crate::error::Result;
use crate::math::{EPS, Real, Vec2};

/// Parameters of the F-formation detector. Lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FFormationParams {
    /// Distance from a person to its o-space vote (m, > 0, default 0.65).
    pub stride: Real,
    /// Label cost, the price of one more group (m^2, > 0, default 0.8 = GCFF's 8000 cm^2).
    pub mdl: Real,
    /// Iteration cap of the assign / refit loop (>= 1, default 10).
    pub max_iterations: usize,
    /// Labels whose centres are closer than this merge (m, >= 0, default 0.3).
    pub merge_distance: Real,
    /// People at or above this speed are not in F-formations (m/s, >= 0, default 0.3).
    pub moving_speed: Real,
}

impl Default for FFormationParams {
    fn default() -> Self {
        Self { stride: 0.65, mdl: 0.8, max_iterations: 10, merge_distance: 0.3, moving_speed: 0.3 }
    }
}

impl FFormationParams {
    /// Wraps these parameters in a [`GroupMethod`].
    pub fn method(self) -> GroupMethod {
        GroupMethod::FFormation(self)
    }

    /// Checks every field; errors name `fformation.<field>`.
    pub fn validate(&self) -> Result<()> {
        check_positive("fformation.stride", self.stride, 1e6)?;
        check_positive("fformation.mdl", self.mdl, 1e12)?;
        check_range("fformation.max_iterations", self.max_iterations as Real, 1.0, 1e6)?;
        check_range("fformation.merge_distance", self.merge_distance, 0.0, 1e6)?;
        check_range("fformation.moving_speed", self.moving_speed, 0.0, 1e9)?;
        Ok(())
    }
}

struct State<'a> {
    pos: &'a [Vec2],
    votes: &'a [Vec2],
    /// Label of each standing person (indices into `centres`); `usize::MAX` for moving people.
    assign: Vec<usize>,
    centres: Vec<Vec2>,
    counts: Vec<usize>,
}

impl State<'_> {
    /// GCFF visibility cost of person `i` in label `g` (members other than `i`).
    fn vis(&self, i: usize, g: usize) -> Real {
        let o = self.centres[g];
        let di = self.pos[i] - o;
        let ni = di.norm();
        let mut cost = 0.0;
        for (j, &gj) in self.assign.iter().enumerate() {
            if j == i || gj != g {
                continue;
            }
            let dj = self.pos[j] - o;
            let nj = dj.norm();
            if nj < EPS || ni <= nj {
                continue;
            }
            let cos = di.dot(&dj) / (ni * nj);
            if cos > 0.75 {
                cost += 100f64.powf(cos * ni / nj);
            }
        }
        cost
    }

    fn unary(&self, i: usize, g: usize) -> Real {
        (self.votes[i] - self.centres[g]).norm_squared() + self.vis(i, g)
    }
}

/// Runs the F-formation detector (people already validated by [`super::detect`]).
pub(crate) fn detect(people: &[PersonState], params: &FFormationParams) -> Result<Groups> {
    params.validate()?;
    let n = people.len();
    let pos: Vec<Vec2> = people.iter().map(|p| p.pos).collect();
    let votes: Vec<Vec2> = people.iter().map(|p| p.pos + p.facing() * params.stride).collect();
    let standing: Vec<usize> = (0..n).filter(|&i| people[i].vel.norm() < params.moving_speed).collect();
    let mut st = State {
        pos: &pos,
        votes: &votes,
        assign: vec![usize::MAX; n],
        centres: Vec::with_capacity(2 * n),
        counts: Vec::with_capacity(2 * n),
    };
    for &i in &standing {
        st.assign[i] = st.centres.len();
        st.centres.push(votes[i]);
        st.counts.push(1);
    }
    let tol = 1e-12;
    for _ in 0..params.max_iterations {
        let before = st.assign.clone();
        // 1. Greedy reassignment with label costs.
        for &i in &standing {
            let g = st.assign[i];
            let alone = st.counts[g] == 1;
            let mut best_cost = st.unary(i, g) + if alone { params.mdl } else { 0.0 };
            let mut best: Option<usize> = None; // None = stay
            for h in 0..st.centres.len() {
                if h == g || st.counts[h] == 0 {
                    continue;
                }
                let c = st.unary(i, h);
                if c < best_cost - tol {
                    best_cost = c;
                    best = Some(h);
                }
            }
            let new_singleton = !alone && params.mdl < best_cost - tol;
            let target = if new_singleton {
                st.centres.push(votes[i]);
                st.counts.push(0);
                Some(st.centres.len() - 1)
            } else {
                best
            };
            if let Some(h) = target {
                st.counts[g] -= 1;
                st.counts[h] += 1;
                st.assign[i] = h;
            }
        }
        // 2. Refit centres.
        refit(&mut st);
        // 3. Merge labels with nearby centres (lower label absorbs higher).
        let mut merged = false;
        for a in 0..st.centres.len() {
            if st.counts[a] == 0 {
                continue;
            }
            for b in (a + 1)..st.centres.len() {
                if st.counts[b] == 0 || (st.centres[a] - st.centres[b]).norm() >= params.merge_distance {
                    continue;
                }
                for l in st.assign.iter_mut() {
                    if *l == b {
                        *l = a;
                    }
                }
                st.counts[a] += st.counts[b];
                st.counts[b] = 0;
                merged = true;
            }
        }
        if merged {
            refit(&mut st);
        }
        if same_partition(&before, &st.assign) {
            break;
        }
    }
    let mut uf = UnionFind::new(n);
    let mut first_of_label = vec![usize::MAX; st.centres.len()];
    for &i in &standing {
        let g = st.assign[i];
        if first_of_label[g] == usize::MAX {
            first_of_label[g] = i;
        } else {
            uf.union(first_of_label[g], i);
        }
    }
    Ok(uf.into_groups())
}

fn refit(st: &mut State<'_>) {
    let mut sums = vec![Vec2::zeros(); st.centres.len()];
    for (i, &g) in st.assign.iter().enumerate() {
        if g != usize::MAX {
            sums[g] += st.votes[i];
        }
    }
    for (g, s) in sums.into_iter().enumerate() {
        if st.counts[g] > 0 {
            st.centres[g] = s / st.counts[g] as Real;
        }
    }
}

/// Same grouping up to label renaming.
fn same_partition(a: &[usize], b: &[usize]) -> bool {
    Groups::from_labels(a) == Groups::from_labels(b)
}
