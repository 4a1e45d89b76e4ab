//! Optimal Reciprocal Collision Avoidance (ORCA) for holonomic agents among static polygons.
//!
//! The algorithm is the one of J. van den Berg, S. J. Guy, M. Lin and D. Manocha, "Reciprocal n-body
//! collision avoidance", Robotics Research (ISRR 2009), Springer STAR 70, 2011, pp. 3-19, as
//! published in the authors' RVO2 library. This module is an independent implementation written from
//! the restated spec in `shared/design/algorithms.md` §1 (no code was copied), in `f64`.
//!
//! # One step
//! [`Orca::compute`] reads a snapshot of all agents (positions, current and preferred velocities)
//! and returns a new velocity for each *active* agent; it never moves anything (the caller integrates,
//! e.g. `p <- p + v dt`). For each active agent it
//! 1. gathers the obstacle edges within `(time_horizon_obst * max_speed + radius)` (free side facing
//!    the agent, nearest first) from the [`ObstacleSet`] index and turns them into velocity half-planes;
//! 2. gathers up to `max_neighbors` agents within `neighbor_dist`, ordered by (squared distance, id,
//!    index), from a k-d tree rebuilt every call, and adds one half-plane per neighbour;
//! 3. finds the velocity closest to its (perturbed) preferred velocity inside the disk of radius
//!    `max_speed` satisfying every half-plane (an incremental 2D linear program). When that is
//!    infeasible it minimises the largest violation of the agent half-planes while keeping the obstacle
//!    half-planes hard (see [`Orca::last_lp3_fallbacks`]).
//!
//! # Conventions
//! - Units: metres, seconds, metres per second; world frame, x forward, y left (REP-103).
//! - Passing side: [`PASS_ON_RIGHT`]. At an exact head-on encounter the velocity obstacle's right leg
//!   is chosen, so both agents veer to their own right (right-hand traffic).
//! - Responsibility: against a neighbour with `reciprocal == true` an agent takes half of the
//!   avoidance (RVO2's 1/2); against a neighbour with `reciprocal == false` (a person, who does not run
//!   ORCA) it takes all of it (alpha = 1). The factor depends only on the neighbour's flag.
//! - Symmetry breaking: the preferred velocity gets a deterministic perturbation of
//!   `perturbation * |pref_vel|` in a direction hashed from `(agent id, step)`; there is no random
//!   state, so a call with the same inputs always gives bit-identical outputs. The direction is drawn
//!   from the half-circle on the passing side of the preferred heading (its along-track part is
//!   symmetric), so a symmetric deadlock resolves into right-hand traffic. This matters because an
//!   exact head-on approach that starts slowly stays in the cut-off-disk case, which pushes straight
//!   back and has no side of its own; the right-leg tie-break only acts once the legs are reached.
//! - Passing-side tilt (an extension of RVO2, [`OrcaParams::pass_tilt`]): a perturbed preferred
//!   velocity cannot break a deadlock in which the optimum sits at the vertex of two mirror-image
//!   half-planes (four robots crossing through a common centre stall that way). So, near head-on
//!   only, the cut-off-disk half-plane is taken tangent at a point of the disk rotated towards the
//!   passing side instead of at the point nearest the current relative velocity. Any tangent on the
//!   disk's arc between the two legs supports the truncated velocity obstacle, so the half-plane still
//!   excludes every colliding relative velocity; both agents of a pair pick the same tangent point,
//!   so reciprocity holds. The known-answer cases (legs, overlap, obstacles) are unaffected.
//! - Obstacles: closed polygons with counter-clockwise vertices (free space to the right of each
//!   edge when walking it), or 2-vertex thin walls. See [`ObstacleSet::new`].
//!
//! # Bad input
//! An agent with a non-finite position, velocity or preferred velocity, or a negative or non-finite
//! radius or maximum speed, is *invalid*: if active it gets the zero velocity (it stops), and it is not
//! seen as a neighbour by anyone. Every output is finite and has norm at most the agent's `max_speed`;
//! should an intermediate value overflow (only possible with coordinates beyond about 1e150 m) the
//! agent also stops. Malformed arguments (bad parameters, `dt`, indices or buffer sizes) are reported
//! as [`CoreError::Input`].

use crate::error::{CoreError, Result};
use crate::math::Vec2;

/// The project's passing convention ([`crate::control::PASS_ON_RIGHT`]). ORCA realises it three
/// ways, all keyed on this constant: the right leg of the velocity obstacle when the relative
/// velocity points exactly at the other agent, the passing-side tilt of the cut-off half-plane near
/// head-on ([`OrcaParams::pass_tilt`]), and the side of the preferred-velocity perturbation.
pub use crate::control::PASS_ON_RIGHT;

/// Tolerance for parallel lines in the linear programs (dimensionless, on unit directions).
const LP_EPS: f64 = 1e-9;

/// Squared length under which a vector is treated as zero when normalising (m^2 or (m/s)^2).
const TINY_SQ: f64 = 1e-24;

/// Maximum number of agents in a k-d tree leaf.
const MAX_LEAF: usize = 10;

/// ORCA parameters shared by all agents of one [`Orca`] instance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrcaParams {
    /// Time horizon against other agents, tau (s, > 0); default 5.
    pub time_horizon: f64,
    /// Time horizon against static obstacles, tau_o (s, > 0); default 2.
    pub time_horizon_obst: f64,
    /// Only agents closer than this are neighbours (m, >= 0); default 10.
    pub neighbor_dist: f64,
    /// At most this many nearest agents are considered (0 disables agent avoidance); default 10.
    pub max_neighbors: usize,
    /// Magnitude of the deterministic perturbation of the preferred velocity, as a fraction of
    /// `|pref_vel|` (dimensionless, in [0, 1]); default 0.05. Breaks symmetric deadlocks.
    pub perturbation: f64,
    /// Passing-side tilt of the cut-off-disk half-plane (rad, in [0, 0.5]); default 0.1, and 0 gives
    /// plain RVO2 ORCA. When the relative velocity points (almost) straight at the neighbour, the
    /// half-plane is taken tangent to the cut-off disk at a point rotated by up to this angle towards
    /// the passing side ([`PASS_ON_RIGHT`]), fading linearly to no rotation at
    /// [`PASS_TILT_FADE`] away from head-on. The line still supports the velocity obstacle, so the
    /// collision-avoidance guarantee is kept; see the module documentation.
    pub pass_tilt: f64,
}

/// Angle between the relative velocity's cut-off direction and the exact head-on direction at which
/// the passing-side tilt ([`OrcaParams::pass_tilt`]) has faded to zero (rad).
pub const PASS_TILT_FADE: f64 = 0.35;

impl Default for OrcaParams {
    fn default() -> Self {
        OrcaParams {
            time_horizon: 5.0,
            time_horizon_obst: 2.0,
            neighbor_dist: 10.0,
            max_neighbors: 10,
            perturbation: 0.05,
            pass_tilt: 0.1,
        }
    }
}

impl OrcaParams {
    /// Checks every field's range; the error names the offending field.
    pub fn validate(&self) -> Result<()> {
        let positive = |name: &str, x: f64| {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err(CoreError::input(format!("orca.{name}"), "a finite number > 0 (s)", format!("{x}")))
            }
        };
        positive("time_horizon", self.time_horizon)?;
        positive("time_horizon_obst", self.time_horizon_obst)?;
        if !(self.neighbor_dist.is_finite() && self.neighbor_dist >= 0.0) {
            return Err(CoreError::input(
                "orca.neighbor_dist",
                "a finite number >= 0 (m)",
                format!("{}", self.neighbor_dist),
            ));
        }
        if !(self.perturbation.is_finite() && (0.0..=1.0).contains(&self.perturbation)) {
            return Err(CoreError::input(
                "orca.perturbation",
                "a number in [0, 1]",
                format!("{}", self.perturbation),
            ));
        }
        if !(self.pass_tilt.is_finite() && (0.0..=0.5).contains(&self.pass_tilt)) {
            return Err(CoreError::input(
                "orca.pass_tilt",
                "a number in [0, 0.5] (rad)",
                format!("{}", self.pass_tilt),
            ));
        }
        Ok(())
    }
}

/// One agent's state as ORCA sees it (world frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrcaAgent {
    /// Position of the centre (m).
    pub pos: Vec2,
    /// Current velocity (m/s).
    pub vel: Vec2,
    /// Preferred velocity, typically towards the (partial) goal (m/s).
    pub pref_vel: Vec2,
    /// Radius of the disc, including any safety margin (m, >= 0).
    pub radius: f64,
    /// Maximum speed, the radius of the velocity disk (m/s, >= 0).
    pub max_speed: f64,
    /// Whether this agent runs ORCA too and so takes half of each avoidance. `false` for people and
    /// scripted pedestrians: whoever avoids them takes the whole avoidance (alpha = 1).
    pub reciprocal: bool,
    /// A stable identifier: seeds the perturbation and breaks distance ties between neighbours.
    pub id: u64,
}

impl OrcaAgent {
    /// True when every field is finite and the radius and maximum speed are non-negative.
    pub fn is_valid(&self) -> bool {
        self.pos.iter().chain(self.vel.iter()).chain(self.pref_vel.iter()).all(|x| x.is_finite())
            && self.radius.is_finite()
            && self.radius >= 0.0
            && self.max_speed.is_finite()
            && self.max_speed >= 0.0
    }
}

/// A directed line in velocity space: the feasible half-plane is `{x : det(dir, x - point) >= 0}`,
/// the left side of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// A point on the line (m/s).
    pub point: Vec2,
    /// Unit direction of the line.
    pub dir: Vec2,
}

#[inline]
fn det(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

#[inline]
fn left_normal(d: Vec2) -> Vec2 {
    Vec2::new(-d.y, d.x)
}

/// `v / |v|`, or `fallback` when `v` is (almost) zero or not finite.
#[inline]
fn normalize_or(v: Vec2, fallback: Vec2) -> Vec2 {
    let n2 = v.norm_squared();
    if n2 > TINY_SQ && n2.is_finite() { v / n2.sqrt() } else { fallback }
}

/// One vertex of an obstacle polygon, also the start of the edge to `next`.
#[derive(Clone, Copy, Debug)]
struct Vertex {
    point: Vec2,
    /// Unit direction of the edge from this vertex to `next`.
    dir: Vec2,
    next: u32,
    prev: u32,
    convex: bool,
}

/// Static obstacles for ORCA: the vertices of closed polygons, with a uniform grid of edge buckets
/// for range queries. Built once, shared read-only by every [`Orca::compute`] call.
#[derive(Clone, Debug, Default)]
pub struct ObstacleSet {
    vertices: Vec<Vertex>,
    /// Grid origin (m).
    origin: Vec2,
    /// Grid cell side (m).
    cell: f64,
    nx: usize,
    ny: usize,
    /// CSR offsets into `cell_edges`, length `nx * ny + 1`.
    cell_start: Vec<u32>,
    /// Edge (start vertex) indices per cell.
    cell_edges: Vec<u32>,
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
                let area2: f64 = (0..pts.len()).map(|i| det(pts[i], pts[(i + 1) % pts.len()])).sum();
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
                    det(pts[i] - pts[prev], pts[next] - pts[i]) >= 0.0
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
                        if seg_dist_sq(c, v.point, p2) > 0.5 * cell * cell + 1e-12 {
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
    fn query(&self, pos: Vec2, range_sq: f64, out: &mut Vec<(f64, u32)>, stamps: &mut Stamps) {
        out.clear();
        let consider = |e: usize, out: &mut Vec<(f64, u32)>| {
            let v = &self.vertices[e];
            let p2 = self.vertices[v.next as usize].point;
            let e_vec = p2 - v.point;
            // Back-face culling: only edges with the agent on their right (free) side or on their line
            // (RVO2 drops the latter; we keep it so an agent touching a wall cannot step into it).
            if det(e_vec, pos - v.point) > 0.0 {
                return;
            }
            let d2 = seg_dist_sq(pos, v.point, p2);
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

/// Squared distance from `p` to the segment `a`-`b`.
#[inline]
fn seg_dist_sq(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let e = b - a;
    let l2 = e.norm_squared();
    let s = if l2 > 0.0 { ((p - a).dot(&e) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (p - (a + e * s)).norm_squared()
}

/// Visit marks for de-duplicating edges found in several grid cells.
#[derive(Clone, Debug, Default)]
struct Stamps {
    marks: Vec<u32>,
    current: u32,
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

/// An agent as stored in the k-d tree.
#[derive(Clone, Copy, Debug)]
struct TreeAgent {
    pos: Vec2,
    id: u64,
    idx: u32,
}

/// A k-d tree node over `agents[begin..end]` with its bounding box.
#[derive(Clone, Copy, Debug)]
struct Node {
    begin: u32,
    end: u32,
    /// Child node indices; `left == u32::MAX` for a leaf.
    left: u32,
    right: u32,
    min: Vec2,
    max: Vec2,
}

/// A neighbour candidate: squared distance, id, index into the caller's agent slice.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Neighbor {
    d2: f64,
    id: u64,
    idx: u32,
}

impl Neighbor {
    #[inline]
    fn before(&self, o: &Neighbor) -> bool {
        (self.d2, self.id, self.idx) < (o.d2, o.id, o.idx)
    }
}

/// Statistics of the last [`Orca::compute`] call.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OrcaStats {
    /// Active agents whose linear program was infeasible, so that the minimax fallback (LP3) ran and
    /// the no-collision guarantee does not hold for them this step.
    pub lp3_fallbacks: usize,
    /// Active agents that were invalid (non-finite or negative fields) and were stopped.
    pub invalid_agents: usize,
    /// Sum over active agents of the number of agent neighbours used.
    pub neighbors: usize,
}

/// The ORCA solver: parameters plus reusable buffers and the agent neighbour index (a k-d tree
/// rebuilt by every [`Orca::compute`] call). Not thread-safe to share; use one per thread.
#[derive(Clone, Debug)]
pub struct Orca {
    params: OrcaParams,
    tree: Vec<TreeAgent>,
    nodes: Vec<Node>,
    neighbors: Vec<Neighbor>,
    obst_neighbors: Vec<(f64, u32)>,
    stamps: Stamps,
    lines: Vec<Line>,
    proj: Vec<Line>,
    stats: OrcaStats,
}

impl Orca {
    /// A solver with validated parameters.
    pub fn new(params: OrcaParams) -> Result<Self> {
        params.validate()?;
        Ok(Orca {
            params,
            tree: Vec::new(),
            nodes: Vec::new(),
            neighbors: Vec::new(),
            obst_neighbors: Vec::new(),
            stamps: Stamps::default(),
            lines: Vec::new(),
            proj: Vec::new(),
            stats: OrcaStats::default(),
        })
    }

    /// The parameters in use.
    pub fn params(&self) -> &OrcaParams {
        &self.params
    }

    /// Statistics of the last [`Orca::compute`] call.
    pub fn stats(&self) -> OrcaStats {
        self.stats
    }

    /// Number of active agents of the last call that needed the LP3 fallback.
    pub fn last_lp3_fallbacks(&self) -> usize {
        self.stats.lp3_fallbacks
    }

    /// The half-planes (obstacle lines first) built for the last active agent of the last call, for
    /// inspection and drawing.
    pub fn last_lines(&self) -> &[Line] {
        &self.lines
    }

    /// Computes new velocities (m/s) for the agents whose indices are listed in `active`; every valid
    /// agent in `agents` is a potential neighbour. Writes `out[i]` for each active `i` and leaves the
    /// other entries untouched. `dt` (s, > 0) is the step used in the overlapping case; `step` seeds
    /// the perturbation together with each agent's id.
    ///
    /// Errors: `dt` not finite and positive, `out` shorter than `agents`, an index in `active` out of
    /// range, or more than `u32::MAX` agents.
    pub fn compute(
        &mut self,
        agents: &[OrcaAgent],
        active: &[usize],
        obstacles: &ObstacleSet,
        dt: f64,
        step: u64,
        out: &mut [Vec2],
    ) -> Result<()> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(CoreError::input("dt", "a finite number > 0 (s)", format!("{dt}")));
        }
        if out.len() < agents.len() {
            return Err(CoreError::input(
                "out",
                format!("a buffer of at least {} velocities", agents.len()),
                format!("{}", out.len()),
            ));
        }
        if agents.len() > u32::MAX as usize {
            return Err(CoreError::input("agents", "at most 2^32 - 1 agents", format!("{}", agents.len())));
        }
        if let Some(&bad) = active.iter().find(|&&i| i >= agents.len()) {
            return Err(CoreError::input(
                "active",
                format!("indices below {}", agents.len()),
                format!("{bad}"),
            ));
        }
        self.stats = OrcaStats::default();
        self.build_tree(agents);
        for &i in active {
            out[i] = self.compute_one(agents, i, obstacles, dt, step);
        }
        Ok(())
    }

    fn compute_one(
        &mut self,
        agents: &[OrcaAgent],
        i: usize,
        obstacles: &ObstacleSet,
        dt: f64,
        step: u64,
    ) -> Vec2 {
        let a = agents[i];
        self.lines.clear();
        if !a.is_valid() {
            self.stats.invalid_agents += 1;
            return Vec2::zeros();
        }
        let speed = a.max_speed;

        // Obstacle half-planes first.
        if obstacles.num_edges() > 0 {
            let range = self.params.time_horizon_obst * speed + a.radius;
            let mut obst = std::mem::take(&mut self.obst_neighbors);
            obstacles.query(a.pos, range * range, &mut obst, &mut self.stamps);
            for &(_, e) in &obst {
                obstacle_line(
                    &a,
                    obstacles,
                    e as usize,
                    1.0 / self.params.time_horizon_obst,
                    &mut self.lines,
                );
            }
            self.obst_neighbors = obst;
        }
        let n_obst = self.lines.len();

        // Agent half-planes, nearest first.
        self.query_neighbors(a.pos, i);
        self.stats.neighbors += self.neighbors.len();
        let inv_tau = 1.0 / self.params.time_horizon;
        for nb in &self.neighbors {
            let b = &agents[nb.idx as usize];
            self.lines.push(agent_line(&a, b, i, nb.idx as usize, inv_tau, dt, self.params.pass_tilt));
        }

        let pref_speed = a.pref_vel.norm();
        let pref = if pref_speed > 0.0 && self.params.perturbation > 0.0 {
            let h = a.pref_vel / pref_speed;
            a.pref_vel + perturbation(a.id, step, h) * (self.params.perturbation * pref_speed)
        } else {
            a.pref_vel
        };
        let mut result = Vec2::zeros();
        let failed = lp2(&self.lines, speed, pref, false, &mut result);
        if failed < self.lines.len() {
            self.stats.lp3_fallbacks += 1;
            lp3(&self.lines, n_obst, failed, speed, &mut result, &mut self.proj);
        }
        finish(result, speed)
    }

    /// Rebuilds the k-d tree over the valid agents.
    fn build_tree(&mut self, agents: &[OrcaAgent]) {
        self.tree.clear();
        self.nodes.clear();
        self.tree.extend(agents.iter().enumerate().filter(|(_, a)| a.is_valid()).map(|(k, a)| TreeAgent {
            pos: a.pos,
            id: a.id,
            idx: k as u32,
        }));
        if !self.tree.is_empty() {
            self.build_node(0, self.tree.len());
        }
    }

    fn build_node(&mut self, begin: usize, end: usize) -> u32 {
        let mut min = self.tree[begin].pos;
        let mut max = min;
        for t in &self.tree[begin + 1..end] {
            min = min.inf(&t.pos);
            max = max.sup(&t.pos);
        }
        let id = self.nodes.len() as u32;
        self.nodes.push(Node {
            begin: begin as u32,
            end: end as u32,
            left: u32::MAX,
            right: u32::MAX,
            min,
            max,
        });
        if end - begin > MAX_LEAF {
            let axis = if max.x - min.x > max.y - min.y { 0 } else { 1 };
            let split = 0.5 * (min[axis] + max[axis]);
            let (mut l, mut r) = (begin, end);
            while l < r {
                while l < r && self.tree[l].pos[axis] < split {
                    l += 1;
                }
                while r > l && self.tree[r - 1].pos[axis] >= split {
                    r -= 1;
                }
                if l < r {
                    self.tree.swap(l, r - 1);
                    l += 1;
                    r -= 1;
                }
            }
            let mid = if l == begin || l == end { begin + (end - begin) / 2 } else { l };
            let left = self.build_node(begin, mid);
            let right = self.build_node(mid, end);
            self.nodes[id as usize].left = left;
            self.nodes[id as usize].right = right;
        }
        id
    }

    /// Fills `self.neighbors` with up to `max_neighbors` agents other than `self_idx` closer than
    /// `neighbor_dist` to `pos`, sorted by (squared distance, id, index).
    fn query_neighbors(&mut self, pos: Vec2, self_idx: usize) {
        self.neighbors.clear();
        if self.params.max_neighbors == 0 || self.nodes.is_empty() {
            return;
        }
        let range = self.params.neighbor_dist * self.params.neighbor_dist;
        let mut q = Query {
            tree: &self.tree,
            nodes: &self.nodes,
            pos,
            self_idx: self_idx as u32,
            max: self.params.max_neighbors,
            range,
            out: &mut self.neighbors,
        };
        q.visit(0);
    }
}

struct Query<'a> {
    tree: &'a [TreeAgent],
    nodes: &'a [Node],
    pos: Vec2,
    self_idx: u32,
    max: usize,
    range: f64,
    out: &'a mut Vec<Neighbor>,
}

impl Query<'_> {
    #[inline]
    fn box_dist2(&self, n: &Node) -> f64 {
        let dx = (n.min.x - self.pos.x).max(0.0) + (self.pos.x - n.max.x).max(0.0);
        let dy = (n.min.y - self.pos.y).max(0.0) + (self.pos.y - n.max.y).max(0.0);
        dx * dx + dy * dy
    }

    /// Current pruning bound: the range, or the k-th distance once the list is full.
    #[inline]
    fn bound(&self) -> f64 {
        if self.out.len() == self.max { self.out[self.max - 1].d2 } else { self.range }
    }

    fn visit(&mut self, node: u32) {
        let n = self.nodes[node as usize];
        if n.left == u32::MAX {
            for t in &self.tree[n.begin as usize..n.end as usize] {
                if t.idx == self.self_idx {
                    continue;
                }
                let d2 = (t.pos - self.pos).norm_squared();
                if d2 >= self.range || d2.is_nan() {
                    continue;
                }
                let cand = Neighbor { d2, id: t.id, idx: t.idx };
                if self.out.len() == self.max {
                    if !cand.before(&self.out[self.max - 1]) {
                        continue;
                    }
                    self.out.pop();
                }
                let mut k = self.out.len();
                self.out.push(cand);
                while k > 0 && cand.before(&self.out[k - 1]) {
                    self.out[k] = self.out[k - 1];
                    k -= 1;
                }
                self.out[k] = cand;
            }
            return;
        }
        let (l, r) = (n.left, n.right);
        let dl = self.box_dist2(&self.nodes[l as usize]);
        let dr = self.box_dist2(&self.nodes[r as usize]);
        let (first, d_first, second, d_second) = if dl <= dr { (l, dl, r, dr) } else { (r, dr, l, dl) };
        if d_first <= self.bound() {
            self.visit(first);
            if d_second <= self.bound() {
                self.visit(second);
            }
        }
    }
}

/// Deterministic unit vector hashed from `(id, step)` (SplitMix64 finaliser), relative to the unit
/// heading `h`: its component across `h` always points to the passing side ([`PASS_ON_RIGHT`]), its
/// component along `h` is uniform in sign. The angle from the passing-side normal is uniform in
/// [-pi/2, pi/2].
fn perturbation(id: u64, step: u64, h: Vec2) -> Vec2 {
    let mut z =
        id.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ step.wrapping_add(0x632B_E59B_D9B4_E019).rotate_left(29);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    let phi = ((z >> 11) as f64 * (1.0 / (1u64 << 53) as f64) - 0.5) * std::f64::consts::PI;
    let (s, c) = phi.sin_cos();
    let side = if PASS_ON_RIGHT { Vec2::new(h.y, -h.x) } else { Vec2::new(-h.y, h.x) };
    side * c + h * s
}

/// Final guard: finite, and norm at most `speed`.
fn finish(v: Vec2, speed: f64) -> Vec2 {
    if !(v.x.is_finite() && v.y.is_finite()) {
        return Vec2::zeros();
    }
    let n = v.norm();
    if n > speed {
        let mut w = v * (speed / n);
        // Rounding can leave the scaled norm one ulp above `speed`.
        while w.norm() > speed {
            w *= 1.0 - 1e-15;
        }
        w
    } else {
        v
    }
}

/// The half-plane of agent `a` against neighbour `b` (§1.3 of the spec). `ia`, `ib` are their
/// indices, used only for the coincident-agents fallback.
fn agent_line(a: &OrcaAgent, b: &OrcaAgent, ia: usize, ib: usize, inv_tau: f64, dt: f64, tilt: f64) -> Line {
    let p = b.pos - a.pos;
    let v = a.vel - b.vel;
    let r = a.radius + b.radius;
    let r2 = r * r;
    let dist2 = p.norm_squared();
    let (dir, u);
    if dist2 > r2 {
        // Not colliding: cut-off disk of radius r/tau centred at p/tau, or one of the two legs.
        let w = v - p * inv_tau;
        let wl2 = w.norm_squared();
        let dot = w.dot(&p);
        if dot < 0.0 && dot * dot > r2 * wl2 {
            let wl = wl2.sqrt();
            let mut n = w / wl;
            let mut push = r * inv_tau - wl;
            if tilt > 0.0 {
                // Passing-side tilt near head-on: a tangent point rotated towards the passing side,
                // kept on the arc between the legs (n . (-p^) > R/|p|) so the line supports the VO.
                let dist = dist2.sqrt();
                let toward = -p / dist;
                let angle = n.dot(&toward).clamp(-1.0, 1.0).acos();
                let delta = tilt * (1.0 - angle / PASS_TILT_FADE);
                if delta > 0.0 {
                    let (s, c) = (if PASS_ON_RIGHT { delta } else { -delta }).sin_cos();
                    let m = Vec2::new(c * n.x - s * n.y, s * n.x + c * n.y);
                    if m.dot(&toward) > r / dist {
                        n = m;
                        push = r * inv_tau - w.dot(&n);
                    }
                }
            }
            dir = Vec2::new(n.y, -n.x);
            u = n * push;
        } else {
            let leg = (dist2 - r2).sqrt();
            dir = if det(p, w) > 0.0 {
                // Left leg.
                Vec2::new(p.x * leg - p.y * r, p.x * r + p.y * leg) / dist2
            } else {
                // Right leg; also taken at det == 0 (exact head-on): PASS_ON_RIGHT.
                -Vec2::new(p.x * leg + p.y * r, -p.x * r + p.y * leg) / dist2
            };
            u = dir * v.dot(&dir) - v;
        }
    } else {
        // Overlapping: cut-off disk at time dt, pushing apart within one step.
        let inv_dt = 1.0 / dt;
        let w = v - p * inv_dt;
        let wl = w.norm();
        let n = if wl * wl > TINY_SQ && wl.is_finite() {
            w / wl
        } else {
            // Relative velocity exactly p/dt: move straight away from B; if coincident, along a fixed
            // axis whose sign is decided by (id, index) so the two agents move apart.
            let away = if (a.id, ia) < (b.id, ib) { Vec2::new(-1.0, 0.0) } else { Vec2::new(1.0, 0.0) };
            normalize_or(-p, away)
        };
        dir = Vec2::new(n.y, -n.x);
        u = n * (r * inv_dt - wl);
    }
    let alpha = if b.reciprocal { 0.5 } else { 1.0 };
    Line { point: a.vel + u * alpha, dir }
}

/// Appends the half-plane (if any) of agent `a` against obstacle edge `e1` -> next (§1.4).
fn obstacle_line(a: &OrcaAgent, obstacles: &ObstacleSet, e1: usize, inv_tau: f64, lines: &mut Vec<Line>) {
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
        .any(|l| det(c1 - l.point, l.dir) - ir >= -LP_EPS && det(c2 - l.point, l.dir) - ir >= -LP_EPS)
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
        if o2.convex && det(q2, o2.dir) >= 0.0 {
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
    if o1.convex && det(left, -prev_dir) >= 0.0 {
        left = -prev_dir;
        left_foreign = true;
    }
    if o2.convex && det(right, o2.dir) <= 0.0 {
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

/// Optimises on line `i` subject to lines `0..i` and the speed disk (LP1). Returns false if infeasible.
fn lp1(lines: &[Line], i: usize, speed: f64, opt: Vec2, dir_opt: bool, result: &mut Vec2) -> bool {
    let li = lines[i];
    let b = li.point.dot(&li.dir);
    let disc = b * b + speed * speed - li.point.norm_squared();
    if disc < 0.0 || disc.is_nan() {
        return false;
    }
    let sq = disc.sqrt();
    let mut t_left = -b - sq;
    let mut t_right = -b + sq;
    for lj in &lines[..i] {
        let den = det(li.dir, lj.dir);
        let num = det(lj.dir, li.point - lj.point);
        if den.abs() <= LP_EPS {
            if num < 0.0 {
                return false;
            }
            continue;
        }
        let t = num / den;
        if den >= 0.0 {
            t_right = t_right.min(t);
        } else {
            t_left = t_left.max(t);
        }
        if t_left > t_right {
            return false;
        }
    }
    *result = if dir_opt {
        if opt.dot(&li.dir) > 0.0 { li.point + li.dir * t_right } else { li.point + li.dir * t_left }
    } else {
        let t = li.dir.dot(&(opt - li.point));
        li.point + li.dir * t.clamp(t_left, t_right)
    };
    true
}

/// Closest point to `opt` (or furthest along direction `opt` if `dir_opt`) in the disk of radius
/// `speed` satisfying all lines (LP2). Returns the index of the first line that made it infeasible,
/// or `lines.len()` on success; on failure `result` holds the best point before that line.
fn lp2(lines: &[Line], speed: f64, opt: Vec2, dir_opt: bool, result: &mut Vec2) -> usize {
    *result = if dir_opt {
        opt * speed
    } else if opt.norm_squared() > speed * speed {
        normalize_or(opt, Vec2::zeros()) * speed
    } else {
        opt
    };
    for (i, l) in lines.iter().enumerate() {
        if det(l.dir, l.point - *result) > 0.0 {
            let before = *result;
            if !lp1(lines, i, speed, opt, dir_opt, result) {
                *result = before;
                return i;
            }
        }
    }
    lines.len()
}

/// Minimises the largest violation of the agent lines `n_obst..` from `begin` on, keeping the
/// obstacle lines `..n_obst` hard (LP3).
fn lp3(lines: &[Line], n_obst: usize, begin: usize, speed: f64, result: &mut Vec2, proj: &mut Vec<Line>) {
    let mut dist = 0.0;
    for i in begin..lines.len() {
        let li = lines[i];
        if det(li.dir, li.point - *result) > dist {
            proj.clear();
            proj.extend_from_slice(&lines[..n_obst]);
            for lj in &lines[n_obst..i] {
                let den = det(li.dir, lj.dir);
                let point = if den.abs() <= LP_EPS {
                    if li.dir.dot(&lj.dir) > 0.0 {
                        continue;
                    }
                    (li.point + lj.point) * 0.5
                } else {
                    li.point + li.dir * (det(lj.dir, li.point - lj.point) / den)
                };
                proj.push(Line { point, dir: normalize_or(lj.dir - li.dir, left_normal(li.dir)) });
            }
            let before = *result;
            if lp2(proj, speed, left_normal(li.dir), true, result) < proj.len() {
                // Only through rounding: keep the previous point.
                *result = before;
            }
            dist = det(li.dir, li.point - *result);
        }
    }
}

#[cfg(test)]
mod tests;
