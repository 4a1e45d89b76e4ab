//! Delaunay-based group detection (Sousa et al. 2022, §3.2 and §4.1-4.2), with the Movement
//! dimension of Daza et al. 2021 (DILMO, §2).
//!
//! # Rules, as implemented
//!
//! The people's positions are triangulated (Delaunay, `spade`; from one control step to the next
//! the previous triangulation repaired by edge flips where that gives the same one, see
//! [`super::DetectorMemory`]). Each person is *moving* when its
//! speed is at least [`DelaunayParams::moving_speed`], *standing* otherwise. Groups are the
//! connected components (union-find, smallest index as root) of the following links:
//!
//! 1. **Coincident people** (exactly equal positions) are always linked: their distance 0 passes
//!    the distance rule, and the triangulation can hold only one of them. The lowest index of a
//!    coincident set represents it in the triangulation and in the orientation rule.
//! 2. **Distance rule** (Sousa eq. 1): no link, and no triangle, survives with an edge longer than
//!    `d_max` (`|p_i - p_j| <= d_max` keeps it).
//! 3. **Moving pairs** (Daza 2021, Movement and Orientation of DILMO): a Delaunay edge between two
//!    moving people is a link when it passes the distance rule, their speeds differ by at most
//!    `max_speed_diff`, and their velocity directions differ by at most `max_heading_diff`. People
//!    passing each other in opposite directions therefore never group.
//! 4. **Mixed pairs** (one standing, one moving) never link.
//! 5. **Standing people, orientation rule off** (`orientation_rule = false`, Sousa §4.1 / Fig. 11):
//!    a Delaunay edge between two standing people is a link when it passes the distance rule. With
//!    everyone standing this equals single-linkage clustering at `d_max`, because the Euclidean
//!    minimum spanning tree is a subgraph of the Delaunay triangulation.
//! 6. **Standing people, orientation rule on** (Sousa §3.2, Fig. 5-7, §4.2 / Fig. 12):
//!    - Every person carries an orientation vector of length `vector_length` along its heading;
//!      its tip is `P_v = p + vector_length * (cos heading, sin heading)` (Sousa eq. 2-3).
//!    - A Delaunay triangle whose three people are standing and whose three edges pass the distance
//!      rule is a **reference triangle T\*** when all three tips lie in the closed triangle (the
//!      T-space, eq. 3). Its three people are linked.
//!    - A **peripheral triangle T'** shares an edge (two people) with T\* or with a peripheral
//!      triangle already accepted for that T\* (so chains such as Fig. 12c's peripherals 2..5 can
//!      grow outwards), is standing-only and passes the distance rule. It is accepted, and its
//!      third person joins T\*'s group, when that person's orientation vector **points to T\***:
//!      the half-line from the person along its heading intersects the closed triangle T\*
//!      ("ray intersects T\*", not "tip inside T\*": the paper's Fig. 6/7 wording is "pointing to
//!      T\*", and a tip inside T\* would need vectors longer than the gap to T\*). Acceptance is
//!      monotone, so the accepted set is the unique fixed point whatever the visiting order.
//!    - **Pairs** (no triangle, e.g. two people talking in a crowd or `N = 2`): two standing people
//!      joined by a Delaunay edge that passes the distance rule are linked when each faces the
//!      other within `pair_facing_tolerance` (the angle between a person's heading and the
//!      direction to the other is at most the tolerance). With the default 60 degrees this takes
//!      vis-a-vis (0 degrees) and L-shaped (45 degrees) arrangements and rejects side-by-side
//!      (90 degrees) and back-to-back ones. The paper says a pair follows "the regular proxemics
//!      rules" without defining them; this is our rule.
//!
//! Degenerate input: fewer than three distinct positions or all positions collinear give no
//! triangles, so only the pair rules apply; this never panics.

use super::mesh::Mesh;
use super::{GroupMethod, Groups, PersonState, UnionFind, check_positive, check_range};
use crate::error::{CoreError, Result};
use crate::geom::{contains_point_triangle, cross};
use crate::math::{Real, Vec2};
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};
use std::f64::consts::PI;

/// Parameters of the Delaunay detector. All lengths in metres, speeds in m/s, angles in radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DelaunayParams {
    /// Distance rule: largest distance between two linked people (m, >= 0, default 1.5, the
    /// upper end of Hall's personal-to-social boundary range used for groups in the design notes).
    pub d_max: Real,
    /// Apply the orientation rule (T-space) to standing people (default true). When false,
    /// standing people are linked by the distance rule alone (Sousa §4.1, Fig. 11).
    pub orientation_rule: bool,
    /// Length of the orientation vector `P_v` (m, > 0, default 0.65). The paper does not give
    /// it; 0.65 m is the o-space stride of F-formation detectors (GCFF / adaptive_social_layers),
    /// i.e. the tip lands where the o-space centre is expected.
    pub vector_length: Real,
    /// Largest angle between a standing person's heading and the direction to the other person
    /// for the pair rule (rad, in [0, pi], default 60 degrees).
    pub pair_facing_tolerance: Real,
    /// A person whose speed is at least this is moving (m/s, >= 0, default 0.3).
    pub moving_speed: Real,
    /// Largest difference of speeds within a moving group (m/s, >= 0, default 0.3).
    pub max_speed_diff: Real,
    /// Largest angle between the velocities of two people in a moving group (rad, in [0, pi],
    /// default 30 degrees).
    pub max_heading_diff: Real,
}

impl Default for DelaunayParams {
    fn default() -> Self {
        Self {
            d_max: 1.5,
            orientation_rule: true,
            vector_length: 0.65,
            pair_facing_tolerance: 60f64.to_radians(),
            moving_speed: 0.3,
            max_speed_diff: 0.3,
            max_heading_diff: 30f64.to_radians(),
        }
    }
}

impl DelaunayParams {
    /// Distance-only grouping (orientation rule off) at `d_max` metres.
    pub fn distance_only(d_max: Real) -> Self {
        Self { d_max, orientation_rule: false, ..Self::default() }
    }

    /// Wraps these parameters in a [`GroupMethod`].
    pub fn method(self) -> GroupMethod {
        GroupMethod::Delaunay(self)
    }

    /// Checks every field; errors name `delaunay.<field>`.
    pub fn validate(&self) -> Result<()> {
        check_range("delaunay.d_max", self.d_max, 0.0, 1e9)?;
        check_positive("delaunay.vector_length", self.vector_length, 1e9)?;
        check_range("delaunay.pair_facing_tolerance", self.pair_facing_tolerance, 0.0, PI)?;
        check_range("delaunay.moving_speed", self.moving_speed, 0.0, 1e9)?;
        check_range("delaunay.max_speed_diff", self.max_speed_diff, 0.0, 1e9)?;
        check_range("delaunay.max_heading_diff", self.max_heading_diff, 0.0, PI)?;
        Ok(())
    }
}

/// A triangulation vertex: a position and the index of the person it stands for.
#[derive(Debug, Clone, Copy)]
pub(super) struct Vertex {
    pub(super) p: Point2<Real>,
    pub(super) idx: usize,
}

impl HasPosition for Vertex {
    type Scalar = Real;
    fn position(&self) -> Point2<Real> {
        self.p
    }
}

/// Flushes coordinates too small for spade's exact predicates (|x| < 2^-142) to zero.
#[inline]
fn flush(x: Real) -> Real {
    if x.abs() < 1e-40 { 0.0 } else { x }
}

/// True when the half-line `o + s*d` (s >= 0) meets the segment `[a, b]`.
fn ray_hits_segment(o: Vec2, d: Vec2, a: Vec2, b: Vec2) -> bool {
    let e = b - a;
    let w = a - o;
    let denom = cross(d, e);
    let scale = d.norm() * e.norm();
    if denom.abs() <= 1e-12 * scale {
        // Parallel: only a collinear segment ahead of the origin counts.
        if cross(w, d).abs() > 1e-12 * d.norm() * w.norm().max(1.0) {
            return false;
        }
        return w.dot(&d) >= 0.0 || (b - o).dot(&d) >= 0.0;
    }
    let s_ray = cross(w, e) / denom;
    let s_seg = cross(w, d) / denom;
    s_ray >= 0.0 && (-1e-12..=1.0 + 1e-12).contains(&s_seg)
}

/// True when the half-line from `o` along `d` meets the closed triangle `t`.
pub(crate) fn ray_hits_triangle(o: Vec2, d: Vec2, t: &[Vec2; 3]) -> bool {
    contains_point_triangle(o, t) || (0..3).any(|k| ray_hits_segment(o, d, t[k], t[(k + 1) % 3]))
}

/// The per-call context: people, parameters and the moving flags.
struct Ctx<'a> {
    people: &'a [PersonState],
    params: &'a DelaunayParams,
    moving: Vec<bool>,
    d_max2: Real,
    cos_pair: Real,
    cos_heading: Real,
}

impl Ctx<'_> {
    fn within(&self, i: usize, j: usize) -> bool {
        (self.people[i].pos - self.people[j].pos).norm_squared() <= self.d_max2
    }

    /// The pairwise link of rules 3-6 (pair part) for a Delaunay edge.
    fn pair_link(&self, i: usize, j: usize) -> bool {
        if !self.within(i, j) {
            return false;
        }
        let (a, b) = (&self.people[i], &self.people[j]);
        match (self.moving[i], self.moving[j]) {
            (true, true) => {
                // Daza 2021 DILMO Movement: agreeing speed and direction.
                let (sa, sb) = (a.vel.norm(), b.vel.norm());
                (sa - sb).abs() <= self.params.max_speed_diff
                    && a.vel.dot(&b.vel) >= self.cos_heading * sa * sb
            }
            (false, false) => {
                if !self.params.orientation_rule {
                    return true;
                }
                // Pair rule (ours, see module docs): mutual facing within the tolerance.
                let d = b.pos - a.pos;
                let len = d.norm();
                a.facing().dot(&d) >= self.cos_pair * len && b.facing().dot(&(-d)) >= self.cos_pair * len
            }
            _ => false,
        }
    }

    /// Standing-only triangle whose three edges pass the distance rule.
    fn valid_triangle(&self, t: &[usize; 3]) -> bool {
        t.iter().all(|&v| !self.moving[v])
            && self.within(t[0], t[1])
            && self.within(t[1], t[2])
            && self.within(t[2], t[0])
    }

    fn corners(&self, t: &[usize; 3]) -> [Vec2; 3] {
        [self.people[t[0]].pos, self.people[t[1]].pos, self.people[t[2]].pos]
    }

    fn tip(&self, i: usize) -> Vec2 {
        self.people[i].pos + self.people[i].facing() * self.params.vector_length
    }
}

/// Runs the Delaunay detector (people already validated by [`super::detect`]), carrying the
/// triangulation in `mesh` from one call to the next ([`Mesh`]; `None` to start afresh). The groups
/// do not depend on what `mesh` holds: a kept mesh is exactly the triangulation `spade` builds.
pub(crate) fn detect(
    people: &[PersonState],
    params: &DelaunayParams,
    mesh: &mut Option<Mesh>,
) -> Result<Groups> {
    params.validate()?;
    let n = people.len();
    let mut uf = UnionFind::new(n);
    let ctx = Ctx {
        people,
        params,
        moving: people.iter().map(|p| p.vel.norm() >= params.moving_speed).collect(),
        d_max2: params.d_max * params.d_max,
        cos_pair: params.pair_facing_tolerance.cos(),
        cos_heading: params.max_heading_diff.cos(),
    };
    let keys: Vec<Point2<Real>> =
        people.iter().map(|p| Point2::new(flush(p.pos.x), flush(p.pos.y))).collect();

    // A mesh with everyone as a vertex that is still valid proves that no two people coincide
    // (two vertices at one point would make their triangles overlap, see `Mesh`), so rule 1 has
    // nothing to do.
    let mut kept = mesh.as_mut().is_some_and(|m| m.has_everyone(n) && m.advance(&keys));
    if !kept && mesh.as_ref().is_some_and(|m| m.has_everyone(n)) {
        *mesh = None;
    }
    if !kept {
        // Rule 1: de-duplicate exact coincidences; the lowest index represents the set.
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_unstable_by(|&a, &b| {
            let (ka, kb) = (keys[a], keys[b]);
            ka.x.total_cmp(&kb.x).then(ka.y.total_cmp(&kb.y)).then(a.cmp(&b))
        });
        let mut reps: Vec<Vertex> = Vec::with_capacity(n);
        let mut is_vertex = vec![false; n];
        let mut prev: Option<usize> = None;
        for &i in &order {
            if let Some(r) = prev
                && keys[r] == keys[i]
            {
                uf.union(r, i);
                continue;
            }
            prev = Some(i);
            reps.push(Vertex { p: keys[i], idx: i });
            is_vertex[i] = true;
        }
        if reps.len() < 2 {
            *mesh = None;
            return Ok(uf.into_groups());
        }
        kept = mesh.as_mut().is_some_and(|m| m.has_vertices(&is_vertex) && m.advance(&keys));
        if !kept {
            let tri: DelaunayTriangulation<Vertex> = DelaunayTriangulation::bulk_load(reps).map_err(|e| {
                CoreError::input("people", "positions the triangulation accepts", format!("{e:?}"))
            })?;
            *mesh = Mesh::from_spade(&tri, n, |v| v.idx);
            if mesh.is_none() {
                // No triangle (all collinear): the pair rules on the edges alone.
                for e in tri.undirected_edges() {
                    let [a, b] = e.vertices();
                    let (i, j) = (a.data().idx, b.data().idx);
                    if ctx.pair_link(i, j) {
                        uf.union(i, j);
                    }
                }
                return Ok(uf.into_groups());
            }
        }
    }
    let Some(m) = mesh.as_ref() else {
        return Ok(uf.into_groups());
    };

    // Rules 2-5 and the pair part of rule 6: one test per Delaunay edge.
    for (i, j) in m.edges() {
        if ctx.pair_link(i, j) {
            uf.union(i, j);
        }
    }

    if params.orientation_rule {
        let triangles: Vec<[usize; 3]> =
            m.triangles().iter().map(|t| [t[0] as usize, t[1] as usize, t[2] as usize]).collect();
        orientation_rule(&ctx, &triangles, &mut uf);
    }
    Ok(uf.into_groups())
}

/// Rule 6: reference triangles T* and their peripheral triangles T'.
fn orientation_rule(ctx: &Ctx<'_>, triangles: &[[usize; 3]], uf: &mut UnionFind) {
    let valid: Vec<bool> = triangles.iter().map(|t| ctx.valid_triangle(t)).collect();
    let is_ref: Vec<bool> = triangles
        .iter()
        .zip(&valid)
        .map(|(t, &ok)| {
            ok && {
                let c = ctx.corners(t);
                t.iter().all(|&v| contains_point_triangle(ctx.tip(v), &c))
            }
        })
        .collect();
    if !is_ref.iter().any(|&r| r) {
        return;
    }
    // Edge -> triangles adjacency, as a sorted list (deterministic, no hashing).
    let mut edges: Vec<((usize, usize), usize)> = Vec::with_capacity(triangles.len() * 3);
    for (ti, t) in triangles.iter().enumerate() {
        if !valid[ti] {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            edges.push(((a.min(b), a.max(b)), ti));
        }
    }
    edges.sort_unstable();
    let neighbours = |a: usize, b: usize| {
        let key = (a.min(b), a.max(b));
        let start = edges.partition_point(|e| e.0 < key);
        edges[start..].iter().take_while(move |e| e.0 == key).map(|e| e.1)
    };

    let mut stamp = vec![usize::MAX; triangles.len()];
    let mut queue: Vec<usize> = Vec::new();
    for (r, t_ref) in triangles.iter().enumerate() {
        if !is_ref[r] {
            continue;
        }
        uf.union(t_ref[0], t_ref[1]);
        uf.union(t_ref[0], t_ref[2]);
        let ref_corners = ctx.corners(t_ref);
        stamp[r] = r;
        queue.clear();
        queue.push(r);
        while let Some(acc) = queue.pop() {
            let t = triangles[acc];
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                for nb in neighbours(a, b) {
                    if stamp[nb] == r {
                        continue;
                    }
                    let tn = triangles[nb];
                    let Some(&w) = tn.iter().find(|&&v| v != a && v != b) else {
                        continue;
                    };
                    let pw = &ctx.people[w];
                    if ray_hits_triangle(pw.pos, pw.facing(), &ref_corners) {
                        stamp[nb] = r;
                        uf.union(t_ref[0], w);
                        queue.push(nb);
                    }
                }
            }
        }
    }
}
