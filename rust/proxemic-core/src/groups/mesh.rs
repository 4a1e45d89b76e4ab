//! The people's Delaunay triangulation, carried from one control step to the next.
//!
//! People move a few centimetres per control step, so the Delaunay triangulation of their new
//! positions is almost always the previous one with a few edges flipped. [`Mesh::advance`] moves
//! the previous triangulation's vertices to the new positions and repairs it with Lawson's edge
//! flips (Lawson 1977; de Berg et al., *Computational Geometry*, §9.1-9.3), and gives up (the
//! caller then triangulates from scratch with `spade`) whenever the result could differ from a
//! fresh triangulation:
//!
//! - **Validity.** Every triangle must keep a strictly positive orientation and the boundary must
//!   stay a strictly convex polygon turning once. Then, for any point not on an edge, the number
//!   of triangles covering it equals the boundary's winding number around it (the interior edges
//!   cancel in the sum of the triangles' boundaries): 1 inside, 0 outside. So the triangles tile
//!   the convex hull of the people without overlap, with every person a vertex: a triangulation
//!   of the same points.
//! - **Uniqueness.** Lawson's flips end when every interior edge is locally Delaunay. When every
//!   edge is *strictly* so (the opposite vertex strictly outside the circumcircle), the lifted
//!   surface is strictly convex across every edge, so every triangle's circumcircle has no other
//!   person inside it or on it: this is *the* Delaunay triangulation, the only one, and the one
//!   `spade` builds from the same points. A cocircular quadruple (an in-circle test of exactly
//!   zero) has several Delaunay triangulations, and which one `spade` picks depends on its
//!   insertion order, so the mesh gives up there.
//!
//! Every test is an exact predicate (Shewchuk's adaptive `orient2d` and `incircle`, crate
//! `robust`, the ones `spade` uses), so these statements hold for the floating-point positions
//! themselves. A kept mesh therefore has the same edges and the same triangles (each in
//! counter-clockwise order, possibly starting at another corner) as the fresh triangulation.

use robust::{Coord, incircle, orient2d};
use spade::handles::OUTER_FACE;
use spade::{DelaunayTriangulation, HasPosition, Point2, Triangulation};

/// No neighbour (a boundary edge).
const NONE: u32 = u32::MAX;

/// How many times [`Mesh::advance`] may halve a motion that folds a triangle over.
const HALVINGS: u32 = 3;

/// What one move of the vertices did.
enum Advance {
    /// Moved and repaired: the mesh is the Delaunay triangulation of the new positions.
    Kept,
    /// A triangle folded over; the mesh is unchanged.
    Folded,
    /// Gave up; the mesh may be half-repaired and must be rebuilt.
    GaveUp,
}

/// A triangulation of the people: triangles as counter-clockwise triples of person indices, and
/// for each triangle edge `k` (from corner `k` to corner `k + 1`) the triangle across it.
#[derive(Debug, Clone, Default)]
pub(crate) struct Mesh {
    /// Which people are vertices (the representatives of rule 1), indexed by person.
    is_vertex: Vec<bool>,
    /// Counter-clockwise triangles (person indices).
    tri: Vec<[u32; 3]>,
    /// `adj[t][k]`: the triangle across edge `k` of `t`, or [`NONE`] on the boundary.
    adj: Vec<[u32; 3]>,
    /// The boundary's vertices, counter-clockwise.
    hull: Vec<u32>,
    /// The positions the mesh is the Delaunay triangulation of (indexed by person).
    at: Vec<Point2<f64>>,
    /// True when every person is a vertex.
    everyone: bool,
    /// Edge flips, boundary fills and peels made since the mesh was built (for tests).
    flips: usize,
    fills: usize,
    peels: usize,
    /// Successful [`Mesh::advance`] calls (for tests).
    kept: usize,
    /// Flip stack, kept to reuse its allocation.
    stack: Vec<(u32, u8)>,
}

fn coord(p: Point2<f64>) -> Coord<f64> {
    Coord { x: p.x, y: p.y }
}

impl Mesh {
    /// The mesh of a fresh `spade` triangulation whose vertices carry person indices (`id`), out
    /// of `n` people; `None` when it has no triangle (fewer than three people, or all collinear).
    pub(crate) fn from_spade<V: HasPosition<Scalar = f64>>(
        dt: &DelaunayTriangulation<V>,
        n: usize,
        id: impl Fn(&V) -> usize,
    ) -> Option<Self> {
        if dt.num_inner_faces() == 0 {
            return None;
        }
        let mut is_vertex = vec![false; n];
        let mut at = vec![Point2::new(0.0, 0.0); n];
        for v in dt.vertices() {
            is_vertex[id(v.data())] = true;
            at[id(v.data())] = v.position();
        }
        // Our index of each of spade's faces (the outer face has none).
        let mut index = vec![NONE; dt.num_all_faces()];
        for (t, f) in dt.inner_faces().enumerate() {
            index[f.fix().index()] = t as u32;
        }
        let mut tri = vec![[0; 3]; dt.num_inner_faces()];
        let mut adj = vec![[NONE; 3]; dt.num_inner_faces()];
        for (t, f) in dt.inner_faces().enumerate() {
            // Counter-clockwise edges, each from corner k to corner k + 1.
            for (k, e) in f.adjacent_edges().iter().enumerate() {
                tri[t][k] = id(e.from().data()) as u32;
                let across = e.rev().face();
                adj[t][k] = if across.fix() == OUTER_FACE { NONE } else { index[across.fix().index()] };
            }
        }
        let hull = boundary_cycle(&tri, &adj, n)?;
        let everyone = is_vertex.iter().all(|&v| v);
        Some(Self {
            is_vertex,
            tri,
            adj,
            hull,
            at,
            everyone,
            flips: 0,
            fills: 0,
            peels: 0,
            kept: 0,
            stack: Vec::new(),
        })
    }

    /// True when all `n` people are the mesh's vertices.
    pub(crate) fn has_everyone(&self, n: usize) -> bool {
        self.is_vertex.len() == n && self.everyone
    }

    /// True when the mesh's vertices are exactly the people flagged in `is_vertex`.
    pub(crate) fn has_vertices(&self, is_vertex: &[bool]) -> bool {
        self.is_vertex == is_vertex
    }

    /// Moves the vertices to `pos` (indexed by person) and repairs the mesh by edge flips. True
    /// when the result is the unique Delaunay triangulation of `pos`; false when the mesh gave up
    /// (a triangle still folded over after [`HALVINGS`] halvings of the motion, the boundary
    /// stopped being strictly convex, four people are cocircular, or the flips did not end): the
    /// mesh is then unusable and must be rebuilt.
    pub(crate) fn advance(&mut self, pos: &[Point2<f64>]) -> bool {
        let ok = self.advance_within(pos, HALVINGS);
        self.kept += usize::from(ok);
        ok
    }

    /// [`Mesh::advance`], halving the motion (at most `halvings` times) while it folds a triangle:
    /// a person who crosses an edge in one step crosses it at half the step only if the edge has
    /// not been flipped away by then. Only the last move, to `pos` itself, decides the result.
    fn advance_within(&mut self, pos: &[Point2<f64>], halvings: u32) -> bool {
        match self.try_advance(pos) {
            Advance::Kept => true,
            Advance::Folded if halvings > 0 => {
                let mid: Vec<Point2<f64>> = self
                    .at
                    .iter()
                    .zip(pos)
                    .map(|(a, b)| Point2::new(a.x + 0.5 * (b.x - a.x), a.y + 0.5 * (b.y - a.y)))
                    .collect();
                self.advance_within(&mid, halvings - 1) && self.advance_within(pos, halvings - 1)
            }
            _ => false,
        }
    }

    /// One move of the vertices to `pos`, repaired by flips.
    fn try_advance(&mut self, pos: &[Point2<f64>]) -> Advance {
        let c = |v: u32| coord(pos[v as usize]);
        if pos.len() != self.is_vertex.len() {
            return Advance::GaveUp;
        }
        let folded = |m: &Self| m.tri.iter().position(|t| orient2d(c(t[0]), c(t[1]), c(t[2])) <= 0.0);
        if let Some(first) = folded(self) {
            // A person who left the boundary through a boundary edge folds the one triangle on
            // that edge: peel it off (the person joins the boundary). Any other fold is left to
            // the halvings.
            if self.peelable(first).is_none() {
                return Advance::Folded;
            }
            while let Some(t) = folded(self) {
                let Some(k) = self.peelable(t) else {
                    return Advance::GaveUp;
                };
                self.peel(t, k);
            }
        }
        let mut stack = std::mem::take(&mut self.stack);
        stack.clear();
        if !self.convexify(pos, &mut stack) || !strictly_convex_once(&self.hull, pos) {
            self.stack = stack;
            return Advance::GaveUp;
        }
        for (t, a) in self.adj.iter().enumerate() {
            for (k, &u) in a.iter().enumerate() {
                if u != NONE && (t as u32) < u {
                    stack.push((t as u32, k as u8));
                }
            }
        }
        // Each flip lowers the lifted surface (Lawson): a generous cap only guards the loop.
        let mut flips_left = 8 * self.tri.len() + 64;
        let mut ok = true;
        while let Some((t, k)) = stack.pop() {
            let (t, k) = (t as usize, k as usize);
            let u = self.adj[t][k];
            if u == NONE {
                continue;
            }
            let u = u as usize;
            let [a, b, cc] = [self.tri[t][k], self.tri[t][(k + 1) % 3], self.tri[t][(k + 2) % 3]];
            let Some(j) = (0..3).find(|&j| self.tri[u][j] == b && self.tri[u][(j + 1) % 3] == a) else {
                ok = false;
                break;
            };
            let d = self.tri[u][(j + 2) % 3];
            let inside = incircle(c(a), c(b), c(cc), c(d));
            if inside < 0.0 {
                continue;
            }
            if inside == 0.0 || flips_left == 0 {
                ok = false;
                break;
            }
            flips_left -= 1;
            self.flips += 1;
            self.flip(t, k, u, j, &mut stack);
        }
        self.stack = stack;
        if !ok {
            return Advance::GaveUp;
        }
        self.at.clear();
        self.at.extend_from_slice(pos);
        Advance::Kept
    }

    /// Fills every boundary vertex that turned inward (a right turn of the boundary) with a
    /// triangle on its neighbours along the boundary, which takes the vertex inside; the two edges
    /// that became interior go on `stack`. False when a boundary vertex is exactly collinear with
    /// its neighbours (left to `spade`) or the boundary shrinks below a triangle.
    fn convexify(&mut self, pos: &[Point2<f64>], stack: &mut Vec<(u32, u8)>) -> bool {
        let c = |v: u32| coord(pos[v as usize]);
        let mut i = 0;
        let mut straight = 0; // consecutive left turns seen since the last fill
        while straight < self.hull.len() {
            let h = self.hull.len();
            if h < 3 {
                return false;
            }
            let (u, v, w) = (self.hull[(i + h - 1) % h], self.hull[i % h], self.hull[(i + 1) % h]);
            let turn = orient2d(c(u), c(v), c(w));
            if turn > 0.0 {
                straight += 1;
                i = (i + 1) % h;
                continue;
            }
            if turn == 0.0 {
                return false;
            }
            let (Some((t1, k1)), Some((t2, k2))) = (self.boundary_edge(u, v), self.boundary_edge(v, w))
            else {
                return false;
            };
            // (u, w, v) turns left since (u, v, w) turns right.
            let t = self.tri.len() as u32;
            self.tri.push([u, w, v]);
            self.adj.push([NONE, t2, t1]);
            self.adj[t1 as usize][k1] = t;
            self.adj[t2 as usize][k2] = t;
            stack.push((t, 1));
            stack.push((t, 2));
            self.hull.remove(i % h);
            self.fills += 1;
            // Look again at the neighbours, whose turns changed.
            i = (i + h - 2) % (h - 1);
            straight = 0;
        }
        true
    }

    /// The boundary edge `k` of triangle `t` when `t` can be peeled off: one boundary edge, and
    /// the opposite corner not on the boundary yet.
    fn peelable(&self, t: usize) -> Option<usize> {
        let on_boundary: Vec<usize> = (0..3).filter(|&k| self.adj[t][k] == NONE).collect();
        match on_boundary[..] {
            [k] if !self.hull.contains(&self.tri[t][(k + 2) % 3]) => Some(k),
            _ => None,
        }
    }

    /// Removes triangle `t`, whose edge `k` is on the boundary: its opposite corner joins the
    /// boundary between the edge's ends, and its two other edges become boundary edges.
    fn peel(&mut self, t: usize, k: usize) {
        let [a, b, apex] = [self.tri[t][k], self.tri[t][(k + 1) % 3], self.tri[t][(k + 2) % 3]];
        for nb in self.adj[t] {
            self.repoint(nb, t as u32, NONE);
        }
        if let Some(i) = self.hull.iter().position(|&v| v == a) {
            debug_assert_eq!(self.hull[(i + 1) % self.hull.len()], b);
            self.hull.insert(i + 1, apex);
        }
        let last = self.tri.len() - 1;
        self.tri.swap_remove(t);
        self.adj.swap_remove(t);
        if t != last {
            for nb in self.adj[t] {
                self.repoint(nb, last as u32, t as u32);
            }
        }
        self.peels += 1;
    }

    /// The triangle and edge index of the boundary edge from `a` to `b`.
    fn boundary_edge(&self, a: u32, b: u32) -> Option<(u32, usize)> {
        self.tri.iter().zip(&self.adj).enumerate().find_map(|(t, (v, n))| {
            (0..3).find(|&k| n[k] == NONE && v[k] == a && v[(k + 1) % 3] == b).map(|k| (t as u32, k))
        })
    }

    /// Flips the edge `k` of `t` (from `a` to `b`, third corner `c`), shared with edge `j` of `u`
    /// (from `b` to `a`, third corner `d`): `t` becomes `(c, a, d)` and `u` becomes `(d, b, c)`.
    /// Pushes the four outer edges of the quadrilateral.
    fn flip(&mut self, t: usize, k: usize, u: usize, j: usize, stack: &mut Vec<(u32, u8)>) {
        let [a, b, c] = [self.tri[t][k], self.tri[t][(k + 1) % 3], self.tri[t][(k + 2) % 3]];
        let d = self.tri[u][(j + 2) % 3];
        let (t_bc, t_ca) = (self.adj[t][(k + 1) % 3], self.adj[t][(k + 2) % 3]);
        let (u_ad, u_db) = (self.adj[u][(j + 1) % 3], self.adj[u][(j + 2) % 3]);
        self.tri[t] = [c, a, d];
        self.adj[t] = [t_ca, u_ad, u as u32];
        self.tri[u] = [d, b, c];
        self.adj[u] = [u_db, t_bc, t as u32];
        // The triangles across (a, d) and (b, c) now face `t` and `u` respectively.
        self.repoint(u_ad, u as u32, t as u32);
        self.repoint(t_bc, t as u32, u as u32);
        for (tt, kk) in [(t, 0), (t, 1), (u, 0), (u, 1)] {
            if self.adj[tt][kk] != NONE {
                stack.push((tt as u32, kk as u8));
            }
        }
    }

    /// In triangle `s` (if any), the neighbour `from` becomes `to`.
    fn repoint(&mut self, s: u32, from: u32, to: u32) {
        if s == NONE {
            return;
        }
        if let Some(slot) = self.adj[s as usize].iter_mut().find(|x| **x == from) {
            *slot = to;
        }
    }

    /// Successful [`Mesh::advance`] calls since the mesh was built.
    #[cfg(test)]
    pub(crate) fn times_kept(&self) -> usize {
        self.kept
    }

    /// The triangles (counter-clockwise person indices).
    pub(crate) fn triangles(&self) -> &[[u32; 3]] {
        &self.tri
    }

    /// Every edge once, as a pair of person indices.
    pub(crate) fn edges(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.tri.iter().zip(&self.adj).enumerate().flat_map(|(t, (v, a))| {
            (0..3).filter_map(move |k| {
                (a[k] == NONE || (t as u32) < a[k]).then_some((v[k] as usize, v[(k + 1) % 3] as usize))
            })
        })
    }
}

/// The boundary edges of the triangles, chained into one counter-clockwise cycle of vertices;
/// `None` unless they form a single cycle through distinct vertices.
fn boundary_cycle(tri: &[[u32; 3]], adj: &[[u32; 3]], n: usize) -> Option<Vec<u32>> {
    let mut next = vec![NONE; n];
    let mut count = 0;
    let mut start = NONE;
    for (t, a) in adj.iter().enumerate() {
        for k in 0..3 {
            if a[k] == NONE {
                let (from, to) = (tri[t][k], tri[t][(k + 1) % 3]);
                if next[from as usize] != NONE {
                    return None;
                }
                next[from as usize] = to;
                count += 1;
                start = from;
            }
        }
    }
    let mut hull = Vec::with_capacity(count);
    let mut v = start;
    loop {
        hull.push(v);
        v = next[v as usize];
        if v == NONE || hull.len() > count {
            return None;
        }
        if v == start {
            break;
        }
    }
    (hull.len() == count).then_some(hull)
}

/// True when the closed polygon `hull` turns strictly left at every vertex and winds once.
fn strictly_convex_once(hull: &[u32], pos: &[Point2<f64>]) -> bool {
    let h = hull.len();
    if h < 3 {
        return false;
    }
    let p = |i: usize| pos[hull[i % h] as usize];
    // With every turn strictly left (less than half a turn), the edge direction's angle grows
    // monotonically; it enters the upper half-plane once per full turn.
    let upper = |i: usize| {
        let (a, b) = (p(i), p(i + 1));
        b.y > a.y || (b.y == a.y && b.x > a.x)
    };
    let mut entries = 0;
    for i in 0..h {
        if orient2d(coord(p(i)), coord(p(i + 1)), coord(p(i + 2))) <= 0.0 {
            return false;
        }
        if !upper(i) && upper(i + 1) {
            entries += 1;
        }
    }
    entries == 1
}

#[cfg(test)]
mod tests {
    use super::super::delaunay::Vertex as V;
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeSet;

    type Sets = (BTreeSet<(usize, usize)>, BTreeSet<[usize; 3]>);

    /// A triangle starting at its smallest corner, keeping its turning order.
    fn canonical(t: [usize; 3]) -> [usize; 3] {
        let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
        [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
    }

    fn spade_of(pos: &[Point2<f64>]) -> DelaunayTriangulation<V> {
        let vs: Vec<V> = pos.iter().enumerate().map(|(idx, &p)| V { p, idx }).collect();
        DelaunayTriangulation::bulk_load(vs).expect("finite points")
    }

    fn spade_sets(pos: &[Point2<f64>]) -> Sets {
        let dt = spade_of(pos);
        let edges = dt
            .undirected_edges()
            .map(|e| {
                let [a, b] = e.vertices();
                let (i, j) = (a.data().idx, b.data().idx);
                (i.min(j), i.max(j))
            })
            .collect();
        let tris = dt
            .inner_faces()
            .map(|f| {
                let [a, b, c] = f.vertices();
                canonical([a.data().idx, b.data().idx, c.data().idx])
            })
            .collect();
        (edges, tris)
    }

    fn mesh_sets(m: &Mesh) -> Sets {
        let edges = m.edges().map(|(i, j)| (i.min(j), i.max(j))).collect();
        let tris =
            m.triangles().iter().map(|t| canonical([t[0] as usize, t[1] as usize, t[2] as usize])).collect();
        (edges, tris)
    }

    /// Moves `pos` step by step with `motion`, carrying a mesh; at every step where the mesh is
    /// kept its edges and triangles must be a fresh triangulation's. Returns which steps were kept
    /// and the numbers of flips, boundary fills and peels made.
    fn run(
        mut pos: Vec<Point2<f64>>,
        steps: usize,
        mut motion: impl FnMut(usize, &mut [Point2<f64>]),
    ) -> (Vec<bool>, [usize; 3]) {
        let n = pos.len();
        let mut mesh = Mesh::from_spade(&spade_of(&pos), n, |v| v.idx);
        let (mut kept, mut events) = (Vec::new(), [0; 3]);
        let tally = |m: &Option<Mesh>, events: &mut [usize; 3]| {
            if let Some(m) = m {
                events[0] += m.flips;
                events[1] += m.fills;
                events[2] += m.peels;
            }
        };
        for step in 0..steps {
            motion(step, &mut pos);
            let ok = mesh.as_mut().is_some_and(|m| m.has_everyone(n) && m.advance(&pos));
            if ok {
                let m = mesh.as_ref().expect("kept");
                assert_eq!(mesh_sets(m), spade_sets(&pos), "step {step}: the kept mesh is not spade's");
            } else {
                tally(&mesh, &mut events);
                mesh = Mesh::from_spade(&spade_of(&pos), n, |v| v.idx);
            }
            kept.push(ok);
        }
        tally(&mesh, &mut events);
        (kept, events)
    }

    fn count(kept: &[bool]) -> usize {
        kept.iter().filter(|&&k| k).count()
    }

    #[test]
    fn a_kept_mesh_is_spades_triangulation_of_walking_people() {
        // 150 people walking at up to 1.4 m/s in a 30 x 20 m room (a control step of 0.1 s),
        // turning back at the walls: the boundary changes and triangles fold now and then.
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (w, h) = (30.0, 20.0);
        let n = 150;
        let pos: Vec<Point2<f64>> =
            (0..n).map(|_| Point2::new(rng.random_range(0.0..w), rng.random_range(0.0..h))).collect();
        let mut vel: Vec<(f64, f64)> = (0..n)
            .map(|_| {
                let (a, s): (f64, f64) =
                    (rng.random_range(0.0..std::f64::consts::TAU), rng.random_range(0.0..1.4));
                (s * a.cos(), s * a.sin())
            })
            .collect();
        let (kept, [flips, _, peels]) = run(pos, 400, |_, pos| {
            for (p, v) in pos.iter_mut().zip(vel.iter_mut()) {
                p.x += 0.1 * v.0;
                p.y += 0.1 * v.1;
                if !(0.0..=w).contains(&p.x) {
                    v.0 = -v.0;
                }
                if !(0.0..=h).contains(&p.y) {
                    v.1 = -v.1;
                }
            }
        });
        // The test must exercise both paths: most steps kept, with flips and peels made on the
        // way, and some left to spade.
        assert!(count(&kept) > 300 && count(&kept) < 400, "kept {} of 400", count(&kept));
        assert!(flips > 100 && peels > 10, "{flips} flips, {peels} peels");
    }

    #[test]
    fn cocircular_people_are_left_to_spade() {
        // A lattice (every cell's four corners on one circle) inside a ring of people (a strictly
        // convex boundary), with people walking through it: the mesh must give up at every step
        // while the lattice is whole, and, once the lattice is jittered, keep steps that match
        // spade.
        let lattice = |k: usize| Point2::new((k % 8) as f64, (k / 8) as f64);
        let mut pos: Vec<Point2<f64>> = (0..64).map(lattice).collect();
        pos.extend((0..6).map(|k| Point2::new(-1.0, 0.5 + f64::from(k))));
        pos.extend((0..24).map(|k| {
            let a = std::f64::consts::TAU * (f64::from(k) + 0.3) / 24.0;
            Point2::new(3.5 + 9.0 * a.cos(), 3.5 + 9.0 * a.sin())
        }));
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let jitter: Vec<(f64, f64)> =
            (0..64).map(|_| (rng.random_range(-0.05..0.05), rng.random_range(-0.05..0.05))).collect();
        let (kept, _) = run(pos, 100, |step, pos| {
            for p in &mut pos[64..70] {
                p.x += 0.083;
            }
            if step == 40 {
                for (p, j) in pos[..64].iter_mut().zip(&jitter) {
                    p.x += j.0;
                    p.y += j.1;
                }
            }
        });
        assert_eq!(count(&kept[..40]), 0, "{kept:?}");
        assert!(count(&kept[40..]) > 30, "{kept:?}");
    }

    #[test]
    fn a_mesh_wound_twice_is_given_up() {
        // A fan of 7 triangles around one person, each spanning 4/7 of half a turn: every
        // triangle turns left and so does every boundary vertex, but the boundary winds twice
        // around the centre. Not a triangulation of these points.
        let mut pos = vec![Point2::new(0.0, 0.0)];
        pos.extend((0..7).map(|k| {
            let a = 2.0 * std::f64::consts::TAU * f64::from(k) / 7.0;
            Point2::new(a.cos(), a.sin())
        }));
        let tri: Vec<[u32; 3]> = (0..7).map(|k| [0, 1 + k, 1 + (k + 1) % 7]).collect();
        // Edge 0 (centre to v_k) faces the previous triangle, edge 2 (v_k+1 to centre) the next.
        let adj: Vec<[u32; 3]> = (0..7).map(|k| [(k + 6) % 7, NONE, (k + 1) % 7]).collect();
        let hull = boundary_cycle(&tri, &adj, 8).expect("one cycle");
        let mut mesh = Mesh {
            is_vertex: vec![true; 8],
            everyone: true,
            tri,
            adj,
            hull,
            at: pos.clone(),
            ..Mesh::default()
        };
        assert!(mesh.tri.iter().all(|t| {
            let c = |v: u32| coord(pos[v as usize]);
            orient2d(c(t[0]), c(t[1]), c(t[2])) > 0.0
        }));
        assert!(!mesh.advance(&pos));
    }

    #[test]
    fn a_boundary_turning_inward_is_filled() {
        // People on a circle breathing in and out, with others inside: boundary vertices turn
        // inward and are filled, others leave through boundary edges and are peeled, and the mesh
        // is kept.
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 40;
        let base: Vec<Point2<f64>> = (0..n)
            .map(|k| {
                if k < 20 {
                    let a = std::f64::consts::TAU * k as f64 / 20.0;
                    Point2::new(5.0 * a.cos(), 5.0 * a.sin())
                } else {
                    Point2::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0))
                }
            })
            .collect();
        let phase: Vec<f64> = (0..n).map(|_| rng.random_range(0.0..std::f64::consts::TAU)).collect();
        let mut hull_sizes = BTreeSet::new();
        let (kept, [_, fills, _]) = run(base.clone(), 300, |step, pos| {
            for (k, p) in pos.iter_mut().enumerate() {
                let s = 1.0 + 0.08 * (0.1 * step as f64 + phase[k]).sin();
                *p = Point2::new(base[k].x * s, base[k].y * s);
            }
            hull_sizes.insert(spade_of(pos).convex_hull_size());
        });
        assert!(hull_sizes.len() > 1, "the boundary never changed");
        assert!(count(&kept) > 250 && fills > 10, "kept {} of 300, {fills} fills", count(&kept));
    }

    #[test]
    fn a_folded_triangle_is_left_to_spade() {
        // A person jumps across the room in one step: its triangles fold over.
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let pos: Vec<Point2<f64>> =
            (0..60).map(|_| Point2::new(rng.random_range(0.0..6.0), rng.random_range(0.0..6.0))).collect();
        let (kept, _) = run(pos, 60, |step, pos| {
            let k = step % 60;
            pos[k].x = 6.0 - pos[k].x;
        });
        assert!(count(&kept) < 30, "kept {} of 60", count(&kept));
    }
}
