//! Static obstacles for ORCA: the polygon index ([`ObstacleSet`]) and the half-plane of an agent
//! against one obstacle edge (van den Berg et al. 2011, as in RVO2).

use super::{LP_EPS, Line, OrcaAgent, TINY_SQ, cross, left_normal, normalize_or};
use crate::error::{CoreError, Result};
use crate::geom::distance_squared_point_segment;
use crate::math::Vec2;

/// One vertex of an obstacle polygon, also the start of the edge to `next`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Vertex {
    pub(super) point: Vec2,
    /// Unit direction of the edge from this vertex to `next`.
    pub(super) dir: Vec2,
    pub(super) next: u32,
    pub(super) prev: u32,
    pub(super) convex: bool,
}

/// Static obstacles for ORCA: the vertices of closed polygons, with a uniform grid of edge buckets
/// for range queries. Built once, shared read-only by every [`super::Orca::compute`] call.
#[derive(Clone, Debug, Default)]
pub struct ObstacleSet {
    pub(super) vertices: Vec<Vertex>,
    /// Grid origin (m).
    pub(super) origin: Vec2,
    /// Grid cell side (m).
    pub(super) cell: f64,
    pub(super) nx: usize,
    pub(super) ny: usize,
    /// CSR offsets into `cell_edges`, length `nx * ny + 1`.
    pub(super) cell_start: Vec<u32>,
    /// Edge (start vertex) indices per cell.
    pub(super) cell_edges: Vec<u32>,
}

/// Below this many edges a query scans all edges instead of the grid.
const LINEAR_SCAN_EDGES: usize = 48;

impl ObstacleSet {
    /// An empty set (no static obstacles).
    pub fn empty() -> Self {
        Self::default()
    }

    /// Builds the obstacle set from polygons given as vertex loops (m), counter-clockwise, without a
    /// repeated closing vertex (a repeated one is dropped, as are consecutive duplicates). A
    /// polygon of three or more vertices with negative signed area (clockwise) is reversed. A
    /// 2-vertex polygon is a thin wall that blocks from both sides. A vertex is convex when the
    /// polygon turns left (or goes straight) there.
    ///
    /// Errors: a non-finite coordinate, or a polygon with fewer than two distinct vertices.
    pub fn new(polygons: &[Vec<Vec2>]) -> Result<Self> {
        let mut vertices: Vec<Vertex> = Vec::new();
        for (k, poly) in polygons.iter().enumerate() {
            if let Some(bad) = poly.iter().find(|p| !(p.x.is_finite() && p.y.is_finite())) {
                return Err(CoreError::input(
                    format!("obstacles[{k}]"),
                    "finite vertex coordinates (m)",
                    format!("({}, {})", bad.x, bad.y),
                ));
            }
            let mut pts: Vec<Vec2> = Vec::with_capacity(poly.len());
            for &p in poly {
                if pts.last().is_none_or(|&q| (p - q).norm_squared() > TINY_SQ) {
                    pts.push(p);
                }
            }
            while pts.len() > 1 && pts.last().is_some_and(|&q| (q - pts[0]).norm_squared() <= TINY_SQ) {
                pts.pop();
            }
            if pts.len() < 2 {
                return Err(CoreError::input(
                    format!("obstacles[{k}]"),
                    "a polygon with at least 2 distinct vertices",
                    format!("{} distinct vertices", pts.len()),
                ));
            }
            if pts.len() >= 3 {
                let area2: f64 = (0..pts.len()).map(|i| cross(pts[i], pts[(i + 1) % pts.len()])).sum();
                if area2 < 0.0 {
                    pts.reverse();
                }
            }
            let base = vertices.len();
            let n = pts.len();
            for i in 0..n {
                let next = (i + 1) % n;
                let prev = (i + n - 1) % n;
                let convex = if n == 2 {
                    true
                } else {
                    // The polygon turns left (or goes straight) at vertex i.
                    cross(pts[i] - pts[prev], pts[next] - pts[i]) >= 0.0
                };
                vertices.push(Vertex {
                    point: pts[i],
                    dir: normalize_or(pts[next] - pts[i], Vec2::new(1.0, 0.0)),
                    next: (base + next) as u32,
                    prev: (base + prev) as u32,
                    convex,
                });
            }
        }
        let mut set = ObstacleSet { vertices, ..Self::default() };
        set.build_grid();
        Ok(set)
    }

    /// Builds the set from a map's static geometry (its polygons are already counter-clockwise).
    pub fn from_geometry(geometry: &crate::map::StaticGeometry) -> Result<Self> {
        Self::new(geometry.polygons())
    }

    /// Number of obstacle edges (equal to the number of vertices).
    pub fn num_edges(&self) -> usize {
        self.vertices.len()
    }

    fn build_grid(&mut self) {
        let n = self.vertices.len();
        if n < LINEAR_SCAN_EDGES {
            return;
        }
        let mut lo = Vec2::new(f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        for v in &self.vertices {
            lo = lo.inf(&v.point);
            hi = hi.sup(&v.point);
        }
        let ext = hi - lo;
        let area = (ext.x.max(1e-6)) * (ext.y.max(1e-6));
        // About four cells per edge, at most 2^20 cells.
        let mut cell = (area / (4.0 * n as f64)).sqrt().max(1e-3);
        let cells_for = |c: f64| ((ext.x / c).floor() as usize + 1, (ext.y / c).floor() as usize + 1);
        let (mut nx, mut ny) = cells_for(cell);
        while nx.saturating_mul(ny) > (1 << 20) {
            cell *= 2.0;
            (nx, ny) = cells_for(cell);
        }
        self.origin = lo;
        self.cell = cell;
        self.nx = nx;
        self.ny = ny;
        let mut counts = vec![0u32; nx * ny + 1];
        let cell_range = |a: Vec2, b: Vec2| {
            let x0 = (((a.x.min(b.x) - lo.x) / cell).floor().max(0.0) as usize).min(nx - 1);
            let x1 = (((a.x.max(b.x) - lo.x) / cell).floor().max(0.0) as usize).min(nx - 1);
            let y0 = (((a.y.min(b.y) - lo.y) / cell).floor().max(0.0) as usize).min(ny - 1);
            let y1 = (((a.y.max(b.y) - lo.y) / cell).floor().max(0.0) as usize).min(ny - 1);
            (x0, x1, y0, y1)
        };
        for pass in 0..2 {
            for (e, v) in self.vertices.iter().enumerate() {
                let p2 = self.vertices[v.next as usize].point;
                let (x0, x1, y0, y1) = cell_range(v.point, p2);
                for cy in y0..=y1 {
                    for cx in x0..=x1 {
                        // Keep only cells the segment actually comes near (conservative by half a cell).
                        let c = lo + Vec2::new((cx as f64 + 0.5) * cell, (cy as f64 + 0.5) * cell);
                        if distance_squared_point_segment(c, v.point, p2) > 0.5 * cell * cell + 1e-12 {
                            continue;
                        }
                        let k = cy * nx + cx;
                        if pass == 0 {
                            counts[k + 1] += 1;
                        } else {
                            self.cell_edges[counts[k] as usize] = e as u32;
                            counts[k] += 1;
                        }
                    }
                }
            }
            if pass == 0 {
                for k in 0..nx * ny {
                    counts[k + 1] += counts[k];
                }
                self.cell_start = counts.clone();
                self.cell_edges = vec![0; counts[nx * ny] as usize];
            }
        }
    }

    /// Appends to `out` every edge whose free (right) side faces `pos` (or whose line contains it) and whose distance to `pos`
    /// is below `sqrt(range_sq)`, as `(squared distance, edge index)`, sorted by that pair.
    pub(super) fn query(&self, pos: Vec2, range_sq: f64, out: &mut Vec<(f64, u32)>, stamps: &mut Stamps) {
        out.clear();
        let consider = |e: usize, out: &mut Vec<(f64, u32)>| {
            let v = &self.vertices[e];
            let p2 = self.vertices[v.next as usize].point;
            let e_vec = p2 - v.point;
            // Back-face culling: only edges with the agent on their right (free) side or on their line
            // (RVO2 drops the latter; we keep it so an agent touching a wall cannot step into it).
            if cross(e_vec, pos - v.point) > 0.0 {
                return;
            }
            let d2 = distance_squared_point_segment(pos, v.point, p2);
            if d2 < range_sq {
                out.push((d2, e as u32));
            }
        };
        let n = self.vertices.len();
        if n < LINEAR_SCAN_EDGES || self.cell_start.is_empty() {
            for e in 0..n {
                consider(e, out);
            }
        } else {
            let r = range_sq.sqrt();
            let lo = self.origin;
            let fx0 = ((pos.x - r - lo.x) / self.cell).floor();
            let fx1 = ((pos.x + r - lo.x) / self.cell).floor();
            let fy0 = ((pos.y - r - lo.y) / self.cell).floor();
            let fy1 = ((pos.y + r - lo.y) / self.cell).floor();
            let (nxf, nyf) = (self.nx as f64, self.ny as f64);
            if fx1 < 0.0 || fy1 < 0.0 || fx0 >= nxf || fy0 >= nyf || fx0.is_nan() || fy0.is_nan() {
                return;
            }
            let x0 = fx0.max(0.0) as usize;
            let x1 = fx1.min(nxf - 1.0) as usize;
            let y0 = fy0.max(0.0) as usize;
            let y1 = fy1.min(nyf - 1.0) as usize;
            if (x1 - x0 + 1).saturating_mul(y1 - y0 + 1) >= n {
                for e in 0..n {
                    consider(e, out);
                }
            } else {
                let stamp = stamps.next(n);
                for cy in y0..=y1 {
                    for cx in x0..=x1 {
                        let k = cy * self.nx + cx;
                        let (s, t) = (self.cell_start[k] as usize, self.cell_start[k + 1] as usize);
                        for &e in &self.cell_edges[s..t] {
                            let e = e as usize;
                            if stamps.marks[e] != stamp {
                                stamps.marks[e] = stamp;
                                consider(e, out);
                            }
                        }
                    }
                }
            }
        }
        out.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    }
}

/// Visit marks for de-duplicating edges found in several grid cells.
#[derive(Clone, Debug, Default)]
pub(super) struct Stamps {
    pub(super) marks: Vec<u32>,
    pub(super) current: u32,
}

impl Stamps {
    fn next(&mut self, n: usize) -> u32 {
        if self.marks.len() < n {
            self.marks.resize(n, 0);
        }
        self.current = self.current.wrapping_add(1);
        if self.current == 0 {
            self.marks.iter_mut().for_each(|m| *m = 0);
            self.current = 1;
        }
        self.current
    }
}

/// Appends the half-plane (if any) of agent `a` against obstacle edge `e1` -> next (van den
/// Berg et al. 2011 as in RVO2, restated in `docs/algorithms.md`).
pub(super) fn obstacle_line(
    a: &OrcaAgent,
    obstacles: &ObstacleSet,
    e1: usize,
    inv_tau: f64,
    lines: &mut Vec<Line>,
) {
    let verts = &obstacles.vertices;
    let mut o1 = &verts[e1];
    let mut o2 = &verts[o1.next as usize];
    let q1 = o1.point - a.pos;
    let q2 = o2.point - a.pos;
    let r = a.radius;
    let r2 = r * r;

    // Already covered by an earlier obstacle line?
    let ir = inv_tau * r;
    let c1 = q1 * inv_tau;
    let c2 = q2 * inv_tau;
    if lines
        .iter()
        .any(|l| cross(c1 - l.point, l.dir) - ir >= -LP_EPS && cross(c2 - l.point, l.dir) - ir >= -LP_EPS)
    {
        return;
    }

    let d1 = q1.norm_squared();
    let d2 = q2.norm_squared();
    let e = o2.point - o1.point;
    let s = (-q1).dot(&e) / e.norm_squared();
    let dl = (-q1 - e * s).norm_squared();

    // Direction for a line through the origin keeping velocities pointing away from vertex q.
    let away_line = |q: Vec2, v: &Vertex| {
        let prev_dir = verts[v.prev as usize].dir;
        // Outward direction of the vertex: the sum of the right normals of its two edges.
        let out = Vec2::new(prev_dir.y + v.dir.y, -prev_dir.x - v.dir.x);
        let q = normalize_or(q, -normalize_or(out, Vec2::new(v.dir.y, -v.dir.x)));
        Line { point: Vec2::zeros(), dir: Vec2::new(-q.y, q.x) }
    };

    if s < 0.0 && d1 <= r2 {
        // Colliding with the first vertex.
        if o1.convex {
            lines.push(away_line(q1, o1));
        }
        return;
    }
    if s > 1.0 && d2 <= r2 {
        // Colliding with the second vertex; the next edge handles it unless this one must.
        if o2.convex && cross(q2, o2.dir) >= 0.0 {
            lines.push(away_line(q2, o2));
        }
        return;
    }
    if (0.0..=1.0).contains(&s) && dl <= r2 {
        // Colliding with the edge.
        lines.push(Line { point: Vec2::zeros(), dir: -o1.dir });
        return;
    }

    let tangent_left = |q: Vec2, dq: f64| {
        let leg = (dq - r2).max(0.0).sqrt();
        Vec2::new(q.x * leg - q.y * r, q.x * r + q.y * leg) / dq
    };
    let tangent_right = |q: Vec2, dq: f64| {
        let leg = (dq - r2).max(0.0).sqrt();
        Vec2::new(q.x * leg + q.y * r, -q.x * r + q.y * leg) / dq
    };
    let (mut left, mut right);
    if s < 0.0 && dl <= r2 {
        // Oblique view: only the first vertex matters.
        if !o1.convex {
            return;
        }
        o2 = o1;
        left = tangent_left(q1, d1);
        right = tangent_right(q1, d1);
    } else if s > 1.0 && dl <= r2 {
        // Oblique view: only the second vertex matters.
        if !o2.convex {
            return;
        }
        o1 = o2;
        left = tangent_left(q2, d2);
        right = tangent_right(q2, d2);
    } else {
        left = if o1.convex { tangent_left(q1, d1) } else { -o1.dir };
        right = if o2.convex { tangent_right(q2, d2) } else { o1.dir };
    }
    let same = std::ptr::eq(o1, o2);

    // Legs pointing into the neighbouring edges are replaced by those edges ("foreign" legs).
    let prev_dir = verts[o1.prev as usize].dir;
    let mut left_foreign = false;
    let mut right_foreign = false;
    if o1.convex && cross(left, -prev_dir) >= 0.0 {
        left = -prev_dir;
        left_foreign = true;
    }
    if o2.convex && cross(right, o2.dir) <= 0.0 {
        right = o2.dir;
        right_foreign = true;
    }

    // Cut-off centres and the projection of the current velocity.
    let cl = (o1.point - a.pos) * inv_tau;
    let cr = (o2.point - a.pos) * inv_tau;
    let cvec = cr - cl;
    let v = a.vel;
    let t = if same { 0.5 } else { (v - cl).dot(&cvec) / cvec.norm_squared() };
    let tl = (v - cl).dot(&left);
    let tr = (v - cr).dot(&right);

    if (t < 0.0 && tl < 0.0) || (same && tl < 0.0 && tr < 0.0) {
        let m = normalize_or(v - cl, normalize_or(-cl, Vec2::new(1.0, 0.0)));
        lines.push(Line { point: cl + m * ir, dir: Vec2::new(m.y, -m.x) });
        return;
    }
    if t > 1.0 && tr < 0.0 {
        let m = normalize_or(v - cr, normalize_or(-cr, Vec2::new(1.0, 0.0)));
        lines.push(Line { point: cr + m * ir, dir: Vec2::new(m.y, -m.x) });
        return;
    }
    let inf = f64::INFINITY;
    let dist_cut = if !(0.0..=1.0).contains(&t) || same { inf } else { (v - (cl + cvec * t)).norm_squared() };
    let dist_left = if tl < 0.0 { inf } else { (v - (cl + left * tl)).norm_squared() };
    let dist_right = if tr < 0.0 { inf } else { (v - (cr + right * tr)).norm_squared() };
    if dist_cut <= dist_left && dist_cut <= dist_right {
        let dir = -o1.dir;
        lines.push(Line { point: cl + left_normal(dir) * ir, dir });
    } else if dist_left <= dist_right {
        if !left_foreign {
            lines.push(Line { point: cl + left_normal(left) * ir, dir: left });
        }
    } else if !right_foreign {
        let dir = -right;
        lines.push(Line { point: cr + left_normal(dir) * ir, dir });
    }
}
