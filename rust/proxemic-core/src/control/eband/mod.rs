//! Elastic band: a path deformed in real time by contraction and repulsion, kept connected by
//! overlapping free-space bubbles.
//!
//! After Quinlan and Khatib, "Elastic bands: connecting path planning and control" (ICRA 1993),
//! as used by Calderita et al. (seed 003, §5.3-5.4) on top of a social global planner, with the
//! social cost as an extra repulsion source. Restated in `docs/algorithms.md` (elastic band).
//!
//! # Bubbles
//! The band is a sequence of points `b_0 … b_n`; `b_0` and `b_n` never move. The bubble radius
//! of a point is `ρ(b) = clearance(b)` (metres of free space for the robot at `b`, e.g.
//! `field.at(b) - robot_radius`; NaN or negative values count as 0), capped at `max_bubble` for
//! step sizes and spacing: `ρ̃ = min(ρ, max_bubble)`.
//!
//! # Forces (interior bubbles; all dimensionless)
//! - contraction `f_c = k_c (û_{i-1} + û_{i+1})`, `û` the unit vectors to the neighbours
//!   (Quinlan's normalised form, Calderita's Eq. 13);
//! - repulsion `f_r = k_r ((ρ0 - ρ)/ρ0) ∇ρ` for `ρ < ρ0`, else 0, with `∇ρ` by central
//!   differences of step `gradient_step` and clamped to norm 1 (a distance field is 1-Lipschitz).
//!   Calderita's Eq. 14 writes the difference as `D(p - δ) - D(p + δ)`, which points *toward*
//!   obstacles for a distance `D`; the repulsive sense `+∇ρ` is used here;
//! - social repulsion `f_s = k_s c (-∇c / |∇c|)` from an optional cost `c(p)` clamped to `[0, 1]`
//!   (e.g. a personal-space Gaussian): `c` plays the role of `(ρ0 - ρ)/ρ0`. At a cost peak, where
//!   the gradient vanishes, the push goes to the band's right (the right-hand passing convention of
//!   [`crate::control::social_momentum::PASSING_MOMENTUM_SIGN`]).
//!
//! The components along the band's tangent `t = normalize(b_{i+1} - b_{i-1})` are removed (else
//! bubbles slide and bunch up). A bubble moves by `α f` with Quinlan's step `α = max(ρ̃, min_bubble)`
//! (metres), the contraction part clamped to the distance to the chord of its neighbours (no
//! overshoot, so a dense band cannot oscillate), the total clamped to
//! `max_step_fraction * α`, and scaled by a per-bubble damping factor that halves whenever a move
//! reverses the bubble's previous one (down to 1/64) and recovers by 25% per iteration otherwise
//! (the role of eband's overshoot recursion: it stops limit cycles on quantised distance fields,
//! so a converged band passes the early-stop `tolerance`). A move is rejected (the bubble stays)
//! if it is non-finite or would leave the bubble with clearance below `min_bubble` and below its
//! current clearance.
//!
//! # Topology maintenance
//! After every iteration: an interior bubble is removed when its neighbours already satisfy the
//! overlap criterion `|b_{i-1} - b_{i+1}| < overlap (ρ̂_{i-1} + ρ̂_{i+1})`; then every consecutive
//! pair that fails it gets midpoints inserted by bisection (depth at most `max_insert_depth`, band
//! at most `max_bubbles` points). Here `ρ̂ = max(ρ̃, min_bubble)`: a point without clearance is
//! spaced like a bubble of `min_bubble`, so bisection towards it stops. [`ElasticBand::is_connected`] reports whether every consecutive
//! pair of bubbles overlaps (`|b_i - b_{i+1}| < ρ̃_i + ρ̃_{i+1}` with positive radii), which makes
//! the polyline free of obstacles; when it is false the band is broken and the caller should
//! replan.
//!
//! # Gains: mapping Calderita's kc = 120, kr = 60
//! Calderita's update (Eq. 16) is `p += k_c u_c + k_r (D0 - D) ∂D/∂p`, with `u_c` a sum of unit
//! vectors and `∂D/∂p` dimensionless; the units of `D` (and so of `k_c`, `k_r`) are not stated
//! (RoboComp works in millimetres). Once the repulsion is normalised by `ρ0` both forces are
//! dimensionless directions with magnitude at most 2 and 1, so the only unit-free content of the
//! pair is the ratio `k_r / k_c = 0.5`. The absolute scale is given here by Quinlan's step
//! `α = ρ̃` in metres instead (a bubble moves at most a fraction of its own free radius per
//! iteration, whatever the units). [`EbandParams::from_calderita_gains`] keeps the ratio:
//! `contraction_gain = 1`, `repulsion_gain = social_gain = k_r / k_c`; the defaults are
//! `from_calderita_gains(120, 60)`, i.e. 1.0 and 0.5.

use std::cell::RefCell;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use crate::error::{CoreError, Result};
use crate::math::Vec2;

/// Parameters of an [`ElasticBand`]. Lengths in metres; gains dimensionless.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EbandParams {
    /// Contraction gain `k_c` (dimensionless, finite, `>= 0`); default 1.0.
    pub contraction_gain: f64,
    /// Repulsion gain `k_r` on `((ρ0 - ρ)/ρ0) ∇ρ` (dimensionless, finite, `>= 0`); default 0.5
    /// (Calderita's `k_r / k_c = 60 / 120`).
    pub repulsion_gain: f64,
    /// Gain `k_s` of the repulsion from the social cost (dimensionless, finite, `>= 0`);
    /// default 0.5.
    pub social_gain: f64,
    /// Influence distance `ρ0` beyond which obstacles do not repel (m, finite, `> 0`);
    /// default 1.0.
    pub influence_distance: f64,
    /// Smallest clearance a move may leave a bubble with (m, finite, `>= 0`); default 0.05.
    pub min_bubble: f64,
    /// Cap on the bubble radius used for steps and spacing (m, finite, `> 0`, `>= min_bubble`);
    /// default 0.5, which keeps bubbles at most 0.7 m apart so that a person's cost bump is seen.
    pub max_bubble: f64,
    /// Relative overlap θ required between consecutive bubbles (in `(0, 1]`); default 0.7
    /// (eband's `eband_min_relative_overlap`).
    pub overlap: f64,
    /// Largest move per iteration as a fraction of the bubble's step radius (in `(0, 1)`);
    /// default 0.5.
    pub max_step_fraction: f64,
    /// Central-difference step of the gradients (m, finite, `> 0`); default 0.1. Use at least one
    /// cell when the clearance comes from a grid distance field.
    pub gradient_step: f64,
    /// Iterations per [`ElasticBand::update`] (`>= 0`); default 10.
    pub max_iterations: usize,
    /// Stop iterating early when no bubble moved more than this (m, finite, `>= 0`); default 1e-3.
    pub tolerance: f64,
    /// Bisection depth limit when filling a gap (`>= 0`); default 8.
    pub max_insert_depth: usize,
    /// Largest number of bubbles (`>= 2`); default 4096.
    pub max_bubbles: usize,
}

/// Calderita et al.'s optimal band gains `(kc, kr)` (seed 003, §5.4; units not given): the
/// defaults keep their ratio ([`EbandParams::from_calderita_gains`]).
pub const CALDERITA_GAINS: (f64, f64) = (120.0, 60.0);

impl Default for EbandParams {
    /// Every default is written here once: the gains are Calderita's optimum by their ratio
    /// ([`CALDERITA_GAINS`]: 1.0 and 0.5), the rest as documented on each field.
    fn default() -> Self {
        let ratio = CALDERITA_GAINS.1 / CALDERITA_GAINS.0;
        EbandParams {
            contraction_gain: 1.0,
            repulsion_gain: ratio,
            social_gain: ratio,
            influence_distance: 1.0,
            min_bubble: 0.05,
            max_bubble: 0.5,
            overlap: 0.7,
            max_step_fraction: 0.5,
            gradient_step: 0.1,
            max_iterations: 10,
            tolerance: 1e-3,
            max_insert_depth: 8,
            max_bubbles: 4096,
        }
    }
}

impl EbandParams {
    /// Maps Calderita's gains (`kc`, `kr` in their unstated units; the paper's optimum is
    /// [`CALDERITA_GAINS`], 120 and 60) to this unit-free form by keeping their ratio:
    /// `contraction_gain = 1`, `repulsion_gain = social_gain = kr / kc`. The other fields keep
    /// their defaults (see the module docs). A `kc` that is not finite and positive, or a `kr`
    /// that is not finite and `>= 0`, gives the default ratio (0.5).
    pub fn from_calderita_gains(kc: f64, kr: f64) -> Self {
        let defaults = EbandParams::default();
        let ratio = if kc.is_finite() && kc > 0.0 && kr.is_finite() && kr >= 0.0 {
            kr / kc
        } else {
            defaults.repulsion_gain
        };
        EbandParams { contraction_gain: 1.0, repulsion_gain: ratio, social_gain: ratio, ..defaults }
    }

    fn validate(&self) -> Result<()> {
        let nonneg = |x: f64| x.is_finite() && x >= 0.0;
        let pos = |x: f64| x.is_finite() && x > 0.0;
        let checks: [(&str, bool, &str, f64); 10] = [
            ("contraction_gain", nonneg(self.contraction_gain), "finite, >= 0", self.contraction_gain),
            ("repulsion_gain", nonneg(self.repulsion_gain), "finite, >= 0", self.repulsion_gain),
            ("social_gain", nonneg(self.social_gain), "finite, >= 0", self.social_gain),
            ("influence_distance", pos(self.influence_distance), "finite, > 0", self.influence_distance),
            ("min_bubble", nonneg(self.min_bubble), "finite, >= 0", self.min_bubble),
            (
                "max_bubble",
                pos(self.max_bubble) && self.max_bubble >= self.min_bubble,
                "finite, > 0, >= min_bubble",
                self.max_bubble,
            ),
            ("overlap", pos(self.overlap) && self.overlap <= 1.0, "in (0, 1]", self.overlap),
            (
                "max_step_fraction",
                pos(self.max_step_fraction) && self.max_step_fraction < 1.0,
                "in (0, 1)",
                self.max_step_fraction,
            ),
            ("gradient_step", pos(self.gradient_step), "finite, > 0", self.gradient_step),
            ("tolerance", nonneg(self.tolerance), "finite, >= 0", self.tolerance),
        ];
        for (field, ok, expected, found) in checks {
            if !ok {
                return Err(CoreError::input(format!("eband.{field}"), expected, format!("{found}")));
            }
        }
        if self.max_bubbles < 2 {
            return Err(CoreError::input("eband.max_bubbles", ">= 2", format!("{}", self.max_bubbles)));
        }
        Ok(())
    }
}

/// An elastic band of bubbles between two fixed endpoints (see the module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticBand {
    points: Vec<Vec2>,
    /// Clearance of each point (m, sanitised) as of the last update; empty before it.
    radii: Vec<f64>,
    /// Per point: last displacement (m) and step scale in (0, 1] (overshoot damping).
    steps: Vec<(Vec2, f64)>,
    connected: bool,
    params: EbandParams,
}

/// A cost of a point with its values remembered, keyed by the point's bit patterns: each distinct
/// point is evaluated once, and the value returned is always the function's own at that exact
/// point. For a band's social cost that is expensive and fixed for one [`ElasticBand::update`]
/// (`calderita`'s summed Gaussians of the crowd: bubbles that did not move since the previous
/// iteration look again at the same points, about a third of its evaluations); a cheap cost
/// pays more for the hashing than it saves.
pub(crate) struct PointMemo<'a> {
    f: &'a dyn Fn(Vec2) -> f64,
    seen: RefCell<HashMap<(u64, u64), f64, BuildHasherDefault<PointHasher>>>,
}

impl<'a> PointMemo<'a> {
    /// `f` remembered (nothing evaluated yet).
    pub(crate) fn new(f: &'a dyn Fn(Vec2) -> f64) -> Self {
        Self { f, seen: RefCell::new(HashMap::default()) }
    }

    /// `f(q)`, evaluated at the first call for `q`'s bits.
    pub(crate) fn get(&self, q: Vec2) -> f64 {
        let key = (q.x.to_bits(), q.y.to_bits());
        if let Some(&v) = self.seen.borrow().get(&key) {
            return v;
        }
        let v = (self.f)(q);
        self.seen.borrow_mut().insert(key, v);
        v
    }
}

/// A fast hasher for [`PointMemo`]'s keys (two `u64` bit patterns; not for untrusted input).
#[derive(Default)]
struct PointHasher(u64);

impl Hasher for PointHasher {
    fn finish(&self) -> u64 {
        self.0 ^ (self.0 >> 29)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(27) ^ x).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// Clearance sanitised: NaN and negatives are 0 (colliding), +inf stays.
#[inline]
fn sanitize(x: f64) -> f64 {
    if x > 0.0 { x } else { 0.0 }
}

/// The radius a bubble of clearance `r` is spaced by in topology maintenance: `r` capped at
/// `max_bubble` and floored at `min_bubble` (m). The floor bounds the bisection towards a point
/// without clearance (a doorpost the global path grazes): bubbles there are `2 overlap min_bubble`
/// apart instead of ever closer until `max_bubbles` is filled, so the band stays usable while the
/// repulsion pushes those bubbles out (Quinlan and Khatib space bubbles by their radii; a radius of
/// zero is their "broken band", reported by [`ElasticBand::is_connected`], which is unchanged).
#[inline]
fn spacing_radius(r: f64, p: &EbandParams) -> f64 {
    r.min(p.max_bubble).max(p.min_bubble)
}

#[inline]
fn finite2(v: Vec2) -> bool {
    v.x.is_finite() && v.y.is_finite()
}

#[inline]
fn unit_or_zero(v: Vec2) -> Vec2 {
    let n = v.norm();
    if n > 1e-12 && n.is_finite() { v / n } else { Vec2::zeros() }
}

/// Central-difference gradient of `f` at `p` with step `h`; values capped at `cap` so that an
/// infinite neighbour cannot make it infinite.
fn gradient(f: &dyn Fn(Vec2) -> f64, p: Vec2, h: f64, cap: f64) -> Vec2 {
    let g = |q: Vec2| {
        let x = f(q);
        if x.is_nan() { 0.0 } else { x.clamp(-cap, cap) }
    };
    let dx = Vec2::new(h, 0.0);
    let dy = Vec2::new(0.0, h);
    let grad = Vec2::new(g(p + dx) - g(p - dx), g(p + dy) - g(p - dy)) / (2.0 * h);
    if finite2(grad) { grad } else { Vec2::zeros() }
}

impl ElasticBand {
    /// A band through `path` (world frame, metres). Consecutive duplicate points are dropped; the
    /// first and last points are the fixed endpoints (a path of one distinct point is a band of
    /// one point). Errors with [`CoreError::Input`] for an empty path, a non-finite point, or
    /// invalid parameters.
    pub fn new(path: &[Vec2], params: EbandParams) -> Result<Self> {
        params.validate()?;
        if path.is_empty() {
            return Err(CoreError::input("path", "at least one point", "an empty path"));
        }
        if let Some((k, p)) = path.iter().enumerate().find(|(_, p)| !finite2(**p)) {
            return Err(CoreError::input(
                format!("path[{k}]"),
                "finite coordinates",
                format!("{:?}", (p.x, p.y)),
            ));
        }
        let mut points: Vec<Vec2> = Vec::with_capacity(path.len());
        for p in path {
            if points.last() != Some(p) {
                points.push(*p);
            }
        }
        let steps = vec![(Vec2::zeros(), 1.0); points.len()];
        Ok(ElasticBand { points, radii: Vec::new(), steps, connected: false, params })
    }

    /// The band's points, start to goal (m).
    pub fn points(&self) -> &[Vec2] {
        &self.points
    }

    /// Clearance of each point as of the last [`Self::update`] (m; 0 for colliding or NaN
    /// readings, may be infinite); empty before the first update.
    pub fn radii(&self) -> &[f64] {
        &self.radii
    }

    /// The parameters.
    pub fn params(&self) -> &EbandParams {
        &self.params
    }

    /// Length of the polyline (m).
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| (w[1] - w[0]).norm()).sum()
    }

    /// Whether every consecutive pair of bubbles overlaps (radii capped at `max_bubble`, all
    /// positive), as of the last [`Self::update`]; `false` before the first update. A band that is
    /// not connected is broken: replan.
    pub fn is_connected(&self) -> bool {
        self.connected
    }

    /// Moves the start (the robot) to `p`; errors for a non-finite point. The band is re-evaluated
    /// at the next [`Self::update`].
    pub fn set_start(&mut self, p: Vec2) -> Result<()> {
        if !finite2(p) {
            return Err(CoreError::input("start", "finite coordinates", format!("{:?}", (p.x, p.y))));
        }
        if let Some(first) = self.points.first_mut() {
            *first = p;
        }
        self.steps.iter_mut().for_each(|s| *s = (Vec2::zeros(), 1.0));
        self.connected = false;
        Ok(())
    }

    /// One optimisation pass: up to `max_iterations` iterations of contraction plus repulsion
    /// from `clearance` (free distance for the robot at a point, metres) and from the optional
    /// `social_cost` (in `[0, 1]`, clamped; NaN counts as 0), each followed by topology
    /// maintenance (bubble removal and insertion); the endpoints never move. Stops early when no
    /// bubble moved more than `tolerance`. Never produces a non-finite point.
    pub fn update(&mut self, clearance: &dyn Fn(Vec2) -> f64, social_cost: Option<&dyn Fn(Vec2) -> f64>) {
        let p = self.params;
        let rho = |q: Vec2| sanitize(clearance(q));
        for _ in 0..p.max_iterations {
            let radii: Vec<f64> = self.points.iter().map(|q| rho(*q)).collect();
            let moved = self.relax(&radii, &rho, clearance, social_cost);
            self.maintain(&rho);
            if moved <= p.tolerance {
                break;
            }
        }
        self.radii = self.points.iter().map(|q| rho(*q)).collect();
        self.connected = self.check_connected();
    }

    /// One Gauss-Seidel sweep of the forces, start to goal (each bubble sees its predecessor's
    /// new position: deterministic, and twice as fast as a Jacobi sweep on the contraction);
    /// returns the largest displacement (m).
    fn relax(
        &mut self,
        radii: &[f64],
        rho: &dyn Fn(Vec2) -> f64,
        clearance: &dyn Fn(Vec2) -> f64,
        social_cost: Option<&dyn Fn(Vec2) -> f64>,
    ) -> f64 {
        let p = self.params;
        let n = self.points.len();
        if n < 3 {
            return 0.0;
        }
        let h = p.gradient_step;
        let cap = 1e9;
        let mut moved: f64 = 0.0;
        for (i, &r) in radii.iter().enumerate().take(n - 1).skip(1) {
            let (prev, cur, nxt) = (self.points[i - 1], self.points[i], self.points[i + 1]);
            let t = unit_or_zero(nxt - prev);
            let tangential = |f: Vec2| f - t * f.dot(&t);
            let alpha = r.min(p.max_bubble).max(p.min_bubble);
            // Contraction, clamped to the normal distance to the neighbours' chord (no overshoot).
            let fc = tangential((unit_or_zero(prev - cur) + unit_or_zero(nxt - cur)) * p.contraction_gain);
            let mut dc = fc * alpha;
            let to_chord = tangential((prev + nxt) * 0.5 - cur).norm();
            let dc_norm = dc.norm();
            if dc_norm > to_chord {
                dc *= to_chord / dc_norm;
            }
            // Repulsion from obstacles.
            let mut fe = Vec2::zeros();
            if r < p.influence_distance && p.repulsion_gain > 0.0 {
                let mut g = gradient(clearance, cur, h, cap);
                let gn = g.norm();
                if gn > 1.0 {
                    g /= gn;
                }
                fe += g * (p.repulsion_gain * (p.influence_distance - r) / p.influence_distance);
            }
            // Repulsion from the social cost.
            if let Some(cost) = social_cost
                && p.social_gain > 0.0
            {
                let c = cost(cur);
                let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
                if c > 0.0 {
                    let g = gradient(cost, cur, h, cap);
                    let gn = g.norm();
                    let dir = if gn > 1e-9 {
                        -g / gn
                    } else {
                        // At a peak: push to the band's right (right-hand passing).
                        Vec2::new(t.y, -t.x)
                    };
                    fe += dir * (p.social_gain * c);
                }
            }
            let mut d = dc + tangential(fe) * alpha;
            let dn = d.norm();
            let max_step = p.max_step_fraction * alpha;
            if dn > max_step {
                d *= max_step / dn;
            }
            // Overshoot damping: a bubble whose move reverses its previous one halves its step
            // scale (down to 1/64), otherwise the scale recovers by 25% per iteration up to 1.
            let (last, scale) = self.steps.get(i).copied().unwrap_or((Vec2::zeros(), 1.0));
            let scale =
                if d.dot(&last) < 0.0 { (0.5 * scale).max(1.0 / 64.0) } else { (1.25 * scale).min(1.0) };
            d *= scale;
            let cand = cur + d;
            let mut taken = Vec2::zeros();
            if finite2(cand) && d.norm() > 0.0 {
                let rc = rho(cand);
                if rc >= p.min_bubble || rc >= r {
                    self.points[i] = cand;
                    moved = moved.max(d.norm());
                    taken = d;
                }
            }
            if let Some(st) = self.steps.get_mut(i) {
                *st = (taken, scale);
            }
        }
        moved
    }

    /// Bubble removal, then insertion by bisection.
    fn maintain(&mut self, rho: &dyn Fn(Vec2) -> f64) {
        let p = self.params;
        let n = self.points.len();
        if n < 2 {
            return;
        }
        let cap = |r: f64| spacing_radius(r, &p);
        let overlaps = |a: Vec2, ra: f64, b: Vec2, rb: f64| (a - b).norm() < p.overlap * (cap(ra) + cap(rb));
        let radii: Vec<f64> = self.points.iter().map(|q| rho(*q)).collect();
        self.steps.resize(n, (Vec2::zeros(), 1.0));
        // Removal (each kept bubble keeps its damping state).
        let mut kept: Vec<(Vec2, f64)> = Vec::with_capacity(n);
        let mut kept_steps: Vec<(Vec2, f64)> = Vec::with_capacity(n);
        kept.push((self.points[0], radii[0]));
        kept_steps.push(self.steps[0]);
        for i in 1..n - 1 {
            let (a, ra) = kept[kept.len() - 1];
            let (b, rb) = (self.points[i + 1], radii[i + 1]);
            let (c, rc) = (self.points[i], radii[i]);
            // Drop a bubble that is redundant, and any exact duplicate of its predecessor.
            if overlaps(a, ra, b, rb) || c == a {
                continue;
            }
            kept.push((c, rc));
            kept_steps.push(self.steps[i]);
        }
        kept.push((self.points[n - 1], radii[n - 1]));
        kept_steps.push(self.steps[n - 1]);
        // Insertion (new bubbles start undamped).
        let mut out: Vec<Vec2> = Vec::with_capacity(kept.len() * 2);
        let mut out_steps: Vec<(Vec2, f64)> = Vec::with_capacity(kept.len() * 2);
        out.push(kept[0].0);
        out_steps.push(kept_steps[0]);
        for (j, w) in kept.windows(2).enumerate() {
            // Points still to push after this gap, including `w[1]`.
            let remaining = kept.len() - (j + 1);
            self.fill(&mut out, w[0], w[1], 0, remaining, rho);
            out_steps.resize(out.len(), (Vec2::zeros(), 1.0));
            out.push(w[1].0);
            out_steps.push(kept_steps[j + 1]);
        }
        self.points = out;
        self.steps = out_steps;
    }

    /// Inserts midpoints between `a` and `b` (exclusive) until consecutive bubbles overlap, the
    /// depth limit is reached, or the band would exceed `max_bubbles`.
    fn fill(
        &self,
        out: &mut Vec<Vec2>,
        a: (Vec2, f64),
        b: (Vec2, f64),
        depth: usize,
        remaining: usize,
        rho: &dyn Fn(Vec2) -> f64,
    ) {
        let p = &self.params;
        let cap = |r: f64| spacing_radius(r, p);
        if (a.0 - b.0).norm() < p.overlap * (cap(a.1) + cap(b.1))
            || depth >= p.max_insert_depth
            || out.len() + remaining >= p.max_bubbles
        {
            return;
        }
        let m = (a.0 + b.0) * 0.5;
        if !finite2(m) || m == a.0 || m == b.0 {
            return;
        }
        let mr = rho(m);
        self.fill(out, a, (m, mr), depth + 1, remaining, rho);
        if out.len() + remaining >= p.max_bubbles {
            return;
        }
        out.push(m);
        self.fill(out, (m, mr), b, depth + 1, remaining, rho);
    }

    fn check_connected(&self) -> bool {
        let cap = |r: f64| r.min(self.params.max_bubble);
        if self.radii.len() != self.points.len() || self.radii.iter().any(|&r| r.is_nan() || r <= 0.0) {
            return false;
        }
        self.points
            .windows(2)
            .zip(self.radii.windows(2))
            .all(|(q, r)| (q[1] - q[0]).norm() < cap(r[0]) + cap(r[1]))
    }
}

#[cfg(test)]
mod tests;
