//! Optimal Reciprocal Collision Avoidance (ORCA) for holonomic agents among static polygons.
//!
//! The algorithm is the one of J. van den Berg, S. J. Guy, M. Lin and D. Manocha, "Reciprocal n-body
//! collision avoidance", Robotics Research (ISRR 2009), Springer STAR 70, 2011, pp. 3-19, as
//! published in the authors' RVO2 library. This module is an independent implementation written from
//! the paper and the restatement in `docs/algorithms.md` (ORCA) (no code was copied), in `f64`.
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

mod halfplanes;
pub mod nonholonomic;
mod obstacles;
mod tree;

use crate::error::{CoreError, Result};
use crate::geom::cross;
#[cfg(test)]
use crate::geom::distance_squared_point_segment;
use crate::math::Vec2;
use halfplanes::{agent_line, lp2, lp3};
pub use obstacles::ObstacleSet;
use obstacles::{Stamps, obstacle_line};
use tree::{Neighbor, Node, TreeAgent};

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

/// A directed line in velocity space: the feasible half-plane is `{x : cross(dir, x - point) >= 0}`,
/// the left side of `dir`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// A point on the line (m/s).
    pub point: Vec2,
    /// Unit direction of the line.
    pub dir: Vec2,
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
        self.compute_within(agents, active, obstacles, dt, step, &[], out)
    }

    /// [`Orca::compute`] with hard velocity constraints of each agent's own: `within[i]` (when
    /// `i < within.len()`) are half-planes agent `i`'s new velocity must satisfy, kept hard like
    /// the obstacles' (e.g. the velocities a differential-drive robot can track,
    /// [`nonholonomic::TrackableSet`]). They must contain the zero velocity.
    #[allow(clippy::too_many_arguments)]
    pub fn compute_within(
        &mut self,
        agents: &[OrcaAgent],
        active: &[usize],
        obstacles: &ObstacleSet,
        dt: f64,
        step: u64,
        within: &[Vec<Line>],
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
            let own = within.get(i).map_or(&[][..], |l| &l[..]);
            out[i] = self.compute_one(agents, i, obstacles, dt, step, own);
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
        own: &[Line],
    ) -> Vec2 {
        let a = agents[i];
        self.lines.clear();
        if !a.is_valid() {
            self.stats.invalid_agents += 1;
            return Vec2::zeros();
        }
        let speed = a.max_speed;

        // The agent's own hard constraints first, kept hard with the obstacles'.
        self.lines.extend_from_slice(own);

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

#[cfg(test)]
mod tests;
