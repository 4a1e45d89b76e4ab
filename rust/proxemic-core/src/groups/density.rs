//! Gaussian-mixture density clustering (Calderita et al., §4.1, eq. 1-8).
//!
//! # What the paper defines, and what we implement
//!
//! - Each person `h_i` carries Kirby's asymmetric Gaussian `g_i` (eq. 1-4) with the paper's fixed
//!   variances `sigma_h = 2` (ahead), `sigma_r = 1` (behind), `sigma_s = 4/3` (sides); the peak is
//!   1 at the person. "Ahead" is the half-plane in front of the person's heading (Kirby's
//!   `alpha > 0`); on the lateral line the heading term vanishes, so the switch is continuous.
//! - The global density is `G_d(x) = sum_i g_i(x)` (eq. 5).
//! - `delta = g_i(h_j)` is "the density contribution between neighbours" (eq. 6): the value of one
//!   person's Gaussian at a neighbour standing at the neighbour distance `Omega_d`. The paper also
//!   names an angular neighbour bound `Omega_theta`, but `g_i(h_j)` depends only on where `j`
//!   stands relative to `i`, not on `j`'s heading, so `Omega_theta` cannot change eq. 6-8 and is
//!   not a parameter here. We evaluate `delta` at distance [`DensityParams::neighbour_distance`]
//!   and bearing [`DensityParams::neighbour_bearing`] relative to `i`'s heading (default: straight
//!   ahead, the face-to-face neighbour), see [`DensityParams::delta`].
//! - `phi = 1 + k * delta` (eq. 7): a person with `k` neighbours at the neighbour distance has
//!   `G_d >= phi` at its own position.
//! - `J = { x : G_d(x) >= phi }` (eq. 8); each connected region of `J` is one group's space.
//!
//! `J` is computed on a grid of cell size [`DensityParams::resolution`], 8-connected, by flood
//! fill started only from people who are themselves in `J` (exact `G_d(p_i) >= phi`; their own
//! cell is counted in `J` even when its centre falls just below `phi`). People in the same
//! region form a group; people whose own position is not in `J` are singletons (a region of `J`
//! between two people who are not in `J` themselves does not group them: neither has a neighbour
//! in the paper's sense). Contributions whose exponent exceeds 40 (value < 4e-18) are skipped.

use super::{GroupMethod, Groups, PersonState, UnionFind, check_positive, check_range};
use crate::error::{CoreError, Result};
use crate::math::{Real, Vec2};
use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;

/// Largest number of grid cells one flood fill may visit before `detect` gives up with an error
/// naming `density.resolution`.
pub const MAX_CELLS: usize = 1 << 22;

/// Parameters of the density detector (Calderita eq. 5-8). Lengths in metres, angles in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DensityParams {
    /// Standard deviation ahead of the person (m, > 0, default 2, Calderita §4.1).
    pub sigma_h: Real,
    /// Standard deviation behind the person (m, > 0, default 1).
    pub sigma_r: Real,
    /// Standard deviation to the sides (m, > 0, default 4/3).
    pub sigma_s: Real,
    /// `Omega_d`: the neighbour distance at which `delta` is evaluated (m, > 0, default 1.2,
    /// Hall's personal-zone boundary used as the evaluation radius elsewhere in proxemic).
    pub neighbour_distance: Real,
    /// Bearing of that neighbour relative to the person's heading (rad, in [-pi, pi], default 0:
    /// straight ahead, as in a face-to-face conversation).
    pub neighbour_bearing: Real,
    /// `k`: number of neighbours a person needs to be in a group's space (>= 0, default 1).
    /// Non-integer values are allowed and scale the threshold continuously.
    pub k: Real,
    /// Grid cell size of the region `J` (m, in [1e-4, 1e6], default 0.1).
    pub resolution: Real,
}

impl Default for DensityParams {
    fn default() -> Self {
        Self {
            sigma_h: 2.0,
            sigma_r: 1.0,
            sigma_s: 4.0 / 3.0,
            neighbour_distance: 1.2,
            neighbour_bearing: 0.0,
            k: 1.0,
            resolution: 0.1,
        }
    }
}

impl DensityParams {
    /// Wraps these parameters in a [`GroupMethod`].
    pub fn method(self) -> GroupMethod {
        GroupMethod::Density(self)
    }

    /// Checks every field; errors name `density.<field>`.
    pub fn validate(&self) -> Result<()> {
        check_positive("density.sigma_h", self.sigma_h, 1e6)?;
        check_positive("density.sigma_r", self.sigma_r, 1e6)?;
        check_positive("density.sigma_s", self.sigma_s, 1e6)?;
        check_positive("density.neighbour_distance", self.neighbour_distance, 1e6)?;
        check_range("density.neighbour_bearing", self.neighbour_bearing, -PI, PI)?;
        check_range("density.k", self.k, 0.0, 1e6)?;
        check_range("density.resolution", self.resolution, 1e-4, 1e6)?;
        Ok(())
    }

    /// Kirby's asymmetric Gaussian of a person at the origin facing +x, at the local offset
    /// (`u` ahead, `v` to the left), in metres. Peak 1.
    pub fn gaussian_local(&self, u: Real, v: Real) -> Real {
        self.exponent_local(u, v).map_or(0.0, |q| (-q).exp())
    }

    fn exponent_local(&self, u: Real, v: Real) -> Option<Real> {
        let s = if u >= 0.0 { self.sigma_h } else { self.sigma_r };
        let q = u * u / (2.0 * s * s) + v * v / (2.0 * self.sigma_s * self.sigma_s);
        (q <= 40.0).then_some(q)
    }

    /// `delta` of eq. 6: one Gaussian's value at the reference neighbour.
    pub fn delta(&self) -> Real {
        let (s, c) = self.neighbour_bearing.sin_cos();
        self.gaussian_local(self.neighbour_distance * c, self.neighbour_distance * s)
    }

    /// `phi = 1 + k * delta` (eq. 7).
    pub fn phi(&self) -> Real {
        1.0 + self.k * self.delta()
    }
}

/// `G_d(x)` of eq. 5 (people given as position and unit facing). Every term is positive, so the
/// sum stops as soon as it reaches `stop` (the caller only compares it with `phi`).
fn density(params: &DensityParams, people: &[(Vec2, Vec2)], x: Vec2, stop: Real) -> Real {
    let mut g = 0.0;
    for (p, f) in people {
        let d = x - p;
        let u = f.x * d.x + f.y * d.y;
        let v = -f.y * d.x + f.x * d.y;
        if let Some(q) = params.exponent_local(u, v) {
            g += (-q).exp();
            if g >= stop {
                return g;
            }
        }
    }
    g
}

/// Runs the density detector (people already validated by [`super::detect`]).
pub(crate) fn detect(people: &[PersonState], params: &DensityParams) -> Result<Groups> {
    params.validate()?;
    let n = people.len();
    let mut uf = UnionFind::new(n);
    let frames: Vec<(Vec2, Vec2)> = people.iter().map(|p| (p.pos, p.facing())).collect();
    let phi = params.phi();
    let res = params.resolution;
    let cell_of = |x: Vec2| ((x.x / res).floor() as i64, (x.y / res).floor() as i64);
    // Component id of every visited cell in J (None = visited, not in J).
    let mut cells: HashMap<(i64, i64), Option<usize>> = HashMap::new();
    // Forced cells: the own cells of people in J.
    let mut forced: HashSet<(i64, i64)> = HashSet::new();
    let in_j: Vec<bool> = frames.iter().map(|&(p, _)| density(params, &frames, p, phi) >= phi).collect();
    for (i, &inside) in in_j.iter().enumerate() {
        if inside {
            forced.insert(cell_of(frames[i].0));
        }
    }
    let mut stack: Vec<(i64, i64)> = Vec::new();
    let mut first_person_of_comp: Vec<usize> = Vec::new();
    for i in 0..n {
        if !in_j[i] {
            continue;
        }
        let start = cell_of(frames[i].0);
        if let Some(Some(comp)) = cells.get(&start) {
            uf.union(first_person_of_comp[*comp], i);
            continue;
        }
        let comp = first_person_of_comp.len();
        first_person_of_comp.push(i);
        cells.insert(start, Some(comp));
        stack.clear();
        stack.push(start);
        while let Some((cx, cy)) = stack.pop() {
            for dx in -1..=1 {
                for dy in -1..=1 {
                    if dx == 0 && dy == 0 {
                        continue;
                    }
                    let c = (cx + dx, cy + dy);
                    if cells.contains_key(&c) {
                        continue;
                    }
                    if cells.len() >= MAX_CELLS {
                        return Err(CoreError::input(
                            "density.resolution",
                            format!("a cell size coarse enough for at most {MAX_CELLS} cells"),
                            res.to_string(),
                        ));
                    }
                    let centre = Vec2::new((c.0 as Real + 0.5) * res, (c.1 as Real + 0.5) * res);
                    let inside = forced.contains(&c) || density(params, &frames, centre, phi) >= phi;
                    cells.insert(c, inside.then_some(comp));
                    if inside {
                        stack.push(c);
                    }
                }
            }
        }
    }
    // People in J join the component of their own cell (the loop above already did it for the
    // person that started each fill; the others are joined here, in index order).
    for i in 0..n {
        if in_j[i]
            && let Some(Some(comp)) = cells.get(&cell_of(frames[i].0))
        {
            uf.union(first_person_of_comp[*comp], i);
        }
    }
    Ok(uf.into_groups())
}
