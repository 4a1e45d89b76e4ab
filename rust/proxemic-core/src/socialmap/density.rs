//! Calderita et al. §4.1 and §5.2.1 rasterised: the people layer of the `calderita` planner's
//! social map, from the contours of the summed density `G_d` (eq. 5) instead of Hall radii around
//! each individual.
//!
//! A cell's people factor comes from `G_d` at its centre ([`DensityZones::zone_of`]): inside the
//! intimate contour it is forbidden (the paper sets the nodes' availability to occupied), inside
//! the personal contour it costs [`SocialCosts::personal_cost`] (paper: 4.0), inside the social
//! contour [`SocialCosts::social_cost`] (2.0), elsewhere [`SocialCosts::public_cost`] (1.0). A
//! cell in a group's space `J = {G_d >= φ}` (eq. 8), "the personal space of a group of
//! individuals" in the paper's words, costs at least the personal factor.
//!
//! With the default parameters (`σ_s = 4/3` m, Hall radii 0.45/1.2/3.6 m, `Ω_d = 1.2` m ahead,
//! `k = 1`) the group threshold `φ = 1 + e^{-0.18} = 1.835` lies above the intimate level
//! `L(0.45) = e^{-0.0570} = 0.945`, so `J` falls inside the forbidden intimate region and the group
//! term never raises a cost: the merging of the people's contours does the grouping on the map.
//! It binds only with other parameters (a larger `k`-free threshold below the intimate level).
//!
//! Choices where the paper is silent (also in `docs/algorithms.md`):
//! - the contour levels of the zones: [`DensityZones`] (the one-person Gaussian's value at
//!   Hall's radius to the side);
//! - walls: `G_d` is summed over the plane `S`, as the paper defines it, without the line-of-sight
//!   cut that proxemic's own social map applies; in the Calderita scenes every person is in the
//!   room the robot crosses, so nothing leaks into a place the robot cannot see;
//! - which people: the caller passes the people who stand still (see [`crate::plan::social`]);
//!   the paper's scenes have no walkers.

use crate::error::CoreError;
use crate::groups::PersonState;
use crate::map::grid::GridSpec;
use crate::math::Vec2;
use crate::proxemics::{DensityZones, Zone};

use super::SocialCosts;

/// The people factor at `x` (m) from the density contours of `people` (module docs):
/// `f64::INFINITY` in the intimate region, else the zone's factor of `costs`, at least
/// `costs.personal_cost` inside a group's space.
pub fn density_factor(zones: &DensityZones, costs: &SocialCosts, people: &[PersonState], x: Vec2) -> f64 {
    let g = zones.density(people, x);
    zone_factor(zones, costs, g)
}

/// The factor of a density value `g` (see [`density_factor`]).
fn zone_factor(zones: &DensityZones, costs: &SocialCosts, g: f64) -> f64 {
    let zone = zones.zone_of_density(g);
    let f = match zone {
        Zone::Intimate => return f64::INFINITY,
        Zone::Personal => costs.personal_cost,
        Zone::Social => costs.social_cost,
        Zone::Public => costs.public_cost,
    };
    if g >= zones.phi() { f.max(costs.personal_cost) } else { f }
}

/// The people layer of a grid `spec` (row-major, one factor per cell, evaluated at the cell
/// centres) for `people` (module docs): bit for bit the factor of [`density_factor`] at every
/// cell centre, computed as [`DensityLayer::rebuild`] does.
pub fn density_layer(
    spec: &GridSpec,
    zones: &DensityZones,
    costs: &SocialCosts,
    people: &[PersonState],
) -> Vec<f64> {
    let mut layer = DensityLayer::new(*spec, *zones, costs);
    layer.rebuild(people);
    layer.factors
}

/// The people layer of the `calderita` planner's map, kept between updates (module docs): one
/// factor per cell of a grid (row-major), bit for bit the factor of [`density_factor`] at each
/// cell centre for the people of the last [`DensityLayer::update`] or [`DensityLayer::rebuild`].
///
/// **Rebuild**, tile by tile (8 cells square). Per tile, a person whose exponent is above 40
/// over the whole tile adds exactly 0 to every cell's sum (Kirby's Gaussian is cut there, see
/// [`crate::groups::DensityParams::gaussian_local`]) and is left out. When the sum of the others'
/// smallest values over the tile and the sum of their largest values (with margins for rounding)
/// lie between the same contour levels, every cell of the tile gets that zone's factor. Else the
/// people whose exponent can fall to 10 in the tile are summed per cell, each Gaussian evaluated
/// by products: its exponent is quadratic in the cell indices, so a cell's value is its
/// neighbour's times a ratio, and each ratio its neighbour's times a constant (three `exp` per
/// person and tile instead of one per cell; relative error below 1e-12). The others are bounded
/// by their largest value in the tile. A cell whose sum lies, with that bound and a relative
/// margin of 1e-9, between the same contour levels at both ends gets that zone's factor; any
/// other cell is summed with `exp` over every person not left out, in their order: the same sum
/// as [`density_factor`].
///
/// **Update.** The layer keeps the people of its last rebuild (the reference) and per cell the
/// bounds on `G_d` that decided its zone; a cell's slack is how far `G_d` may move there with the
/// cell staying in its zone (the distance of its bounds from the nearest contour levels, less a
/// margin for rounding; the smallest per tile and per block of 4 by 4 tiles is kept too). The
/// people are paired with the reference's (equal ones first, then the nearest within 1 m), and
/// each pair that differs bounds the change of its Gaussian over a tile: a person who left or
/// joined by their largest value there, one who moved or turned by the smaller of that and the
/// Gaussian's steepest slope on the way times how far the tile's points moved in the person's
/// frame. A tile whose summed bound stays below its slack keeps the reference's factors (a zone
/// has one factor). The bounds over a block of 4 by 4 tiles hold in each of its tiles too: a tile
/// whose slack is above its block's summed bound is kept without bounds of its own, and a change
/// bounded below 1e-7 over the block keeps that bound in the block's tiles. In the others, the changed people's values before and after are evaluated
/// per cell (by products; changes bounded below 1e-7 over the tile are only bounded) and move the
/// cell's bounds; a cell whose moved bounds stay in one class gets that zone's factor, any other
/// is summed afresh as [`density_factor`] sums. Changes are measured from the reference, not from
/// the last update, so people moving to and fro do not wear the slack down. When more than 1/16
/// of the cells would be summed afresh, the layer is rebuilt instead and becomes the new
/// reference.
#[derive(Clone, Debug)]
pub struct DensityLayer {
    spec: GridSpec,
    zones: DensityZones,
    /// The contour levels and `φ`, ascending: a density's class is how many it reaches.
    thresholds: [f64; 4],
    /// The factor of each class.
    class_factor: [f64; 5],
    /// The factor of every cell when nobody is there.
    empty_factor: f64,
    /// The layer for the current people.
    factors: Vec<f64>,
    /// The reference people, in their order.
    base: Vec<Person>,
    /// Per cell, bounds on the reference's `G_d` (as summed by [`density_factor`]) within one
    /// class; per tile and per block, the smallest slack of their cells (see the type's docs).
    lo: Vec<f64>,
    hi: Vec<f64>,
    tile_slack: Vec<f64>,
    block_slack: Vec<f64>,
    /// Cells whose factor the last update changed from the reference's, with that factor.
    saved: Vec<(usize, f64)>,
    /// Cells whose factor may differ from before the last update (when it did not rebuild).
    changed: Vec<usize>,
    /// The current people with their constants.
    people: Vec<Person>,
    changes: Vec<Change>,
    scratch: Scratch,
    /// Whether the last call rebuilt the layer, and how many cells it summed afresh.
    rebuilt: bool,
    summed: usize,
}

impl DensityLayer {
    /// An empty layer (no people: every cell at `costs.public_cost.max(1.0)`) on `spec` for the
    /// density contours of `zones` and the zone factors of `costs`.
    pub fn new(spec: GridSpec, zones: DensityZones, costs: &SocialCosts) -> Self {
        let levels = zones.levels();
        let mut thresholds = [levels[2], levels[1], levels[0], zones.phi()];
        thresholds.sort_by(f64::total_cmp);
        // A class's factor from any density in it: `zone_factor`'s comparisons all follow from it.
        let mut class_factor = [zone_factor(&zones, costs, 0.0); 5];
        for (c, &t) in thresholds.iter().enumerate() {
            class_factor[c + 1] = zone_factor(&zones, costs, t);
        }
        let empty_factor = costs.public_cost.max(1.0);
        let (tw, th) = (spec.width.div_ceil(TILE), spec.height.div_ceil(TILE));
        DensityLayer {
            spec,
            zones,
            thresholds,
            class_factor,
            empty_factor,
            factors: vec![empty_factor; spec.len()],
            base: Vec::new(),
            lo: vec![0.0; spec.len()],
            hi: vec![0.0; spec.len()],
            tile_slack: vec![f64::NEG_INFINITY; tw * th],
            block_slack: vec![f64::NEG_INFINITY; tw.div_ceil(BLOCK) * th.div_ceil(BLOCK)],
            saved: Vec::new(),
            changed: Vec::new(),
            people: Vec::new(),
            changes: Vec::new(),
            scratch: Scratch::default(),
            rebuilt: false,
            summed: 0,
        }
    }

    /// The factor of every cell (row-major; `f64::INFINITY` in the intimate region).
    pub fn factors(&self) -> &[f64] {
        &self.factors
    }

    /// Whether the last update rebuilt the whole layer (and made its people the reference).
    pub fn rebuilt(&self) -> bool {
        self.rebuilt
    }

    /// The cells (row-major indices, possibly repeated) whose factor may differ from before the
    /// last [`DensityLayer::update`], when it did not rebuild (see [`DensityLayer::rebuilt`];
    /// after a rebuild, any cell may have changed).
    pub fn changed_cells(&self) -> &[usize] {
        &self.changed
    }

    /// How many cells the last update summed afresh (a measure of incrementality; 0 after a
    /// rebuild).
    pub fn cells_summed(&self) -> usize {
        self.summed
    }

    /// Writes the layer into `map`'s people layer: all of it after a rebuild, else the cells the
    /// last update changed. Call it after every update of a layer that feeds `map` (and only
    /// that layer).
    ///
    /// # Errors
    /// [`CoreError::Input`] when `map`'s grid is not the layer's (a different number of cells);
    /// `map` is then unchanged.
    pub fn write_to(&self, map: &mut super::SocialMap) -> Result<(), CoreError> {
        if self.rebuilt {
            map.set_people_factors(&self.factors)
        } else {
            map.set_people_factors_at(&self.factors, &self.changed)
        }
    }

    /// Computes the whole layer for `people` and makes them the reference of later updates.
    pub fn rebuild(&mut self, people: &[PersonState]) {
        self.rebuilt = true;
        self.summed = 0;
        self.saved.clear();
        self.changed.clear();
        let (params, res) = (*self.zones.params(), self.spec.resolution);
        self.base.clear();
        self.base.extend(people.iter().map(|p| Person::new(&params, res, p.pos, p.facing())));
        let (tw, th) = (self.spec.width.div_ceil(TILE), self.spec.height.div_ceil(TILE));
        if people.is_empty() {
            self.factors.fill(self.empty_factor);
            self.tile_slack.fill(f64::NEG_INFINITY);
            self.block_slack.fill(f64::NEG_INFINITY);
            return;
        }
        let raster = Raster {
            spec: &self.spec,
            zones: &self.zones,
            thresholds: &self.thresholds,
            class_factor: &self.class_factor,
            people: &self.base,
        };
        let bw = tw.div_ceil(BLOCK);
        for by in 0..th.div_ceil(BLOCK) {
            for bx in 0..bw {
                // The people who may matter in the block's tiles; the ones whose exponent stays
                // above `BLOCK_FAR` over the whole block are only bounded.
                let (tx0, ty0) = (bx * BLOCK, by * BLOCK);
                let (tx1, ty1) = ((tx0 + BLOCK).min(tw), (ty0 + BLOCK).min(th));
                let lo = self.spec.center(tx0 * TILE, ty0 * TILE);
                let hi = self
                    .spec
                    .center((tx1 * TILE).min(self.spec.width) - 1, (ty1 * TILE).min(self.spec.height) - 1);
                let mut far = 0.0;
                self.scratch.block.clear();
                for (i, p) in self.base.iter().enumerate() {
                    if p.out_of_reach(lo, hi) {
                        continue;
                    }
                    let q = p.bounds(lo, hi).0;
                    if q > BLOCK_FAR {
                        if q <= CUT * (1.0 + 1e-9) {
                            far += exp_table_above(q);
                        }
                    } else {
                        self.scratch.block.push(i);
                    }
                }
                let mut least = f64::INFINITY;
                for ty in ty0..ty1 {
                    for tx in tx0..tx1 {
                        let s = raster.tile(
                            tx,
                            ty,
                            far,
                            &mut self.scratch,
                            &mut self.factors,
                            (&mut self.lo, &mut self.hi),
                        );
                        self.tile_slack[ty * tw + tx] = s;
                        least = least.min(s);
                    }
                }
                self.block_slack[by * bw + bx] = least;
            }
        }
    }

    /// Brings the layer to `people` (module docs of [`DensityLayer`]): the cells where the
    /// people's changes since the reference might change the zone are summed afresh, the others
    /// keep the reference's factors. The result is the rebuild's, bit for bit.
    pub fn update(&mut self, people: &[PersonState]) {
        if people.is_empty() || self.base.is_empty() {
            self.rebuild(people);
            return;
        }
        self.rebuilt = false;
        self.summed = 0;
        // Back to the reference's factors where the last update changed them.
        self.changed.clear();
        for &(c, f) in &self.saved {
            self.factors[c] = f;
            self.changed.push(c);
        }
        self.saved.clear();
        let (params, res) = (*self.zones.params(), self.spec.resolution);
        self.people.clear();
        self.people.extend(people.iter().map(|p| Person::new(&params, res, p.pos, p.facing())));
        pair_changes(&self.base, &self.people, &mut self.changes);
        if self.changes.is_empty() {
            return;
        }
        let spec = self.spec;
        let (tw, th) = (spec.width.div_ceil(TILE), spec.height.div_ceil(TILE));
        let bw = tw.div_ceil(BLOCK);
        let raster = Raster {
            spec: &self.spec,
            zones: &self.zones,
            thresholds: &self.thresholds,
            class_factor: &self.class_factor,
            people: &self.people,
        };
        let changes = &self.changes;
        // The box of the cell centres of tiles `t0` to `t1` (inclusive), and the changes' bound
        // over it.
        let span = |t0: (usize, usize), t1: (usize, usize)| {
            let lo = spec.center(t0.0 * TILE, t0.1 * TILE);
            let hi = spec
                .center(((t1.0 + 1) * TILE).min(spec.width) - 1, ((t1.1 + 1) * TILE).min(spec.height) - 1);
            (lo, hi)
        };
        let limit = spec.len() / 16;
        for by in 0..th.div_ceil(BLOCK) {
            for bx in 0..bw {
                let (tx0, ty0) = (bx * BLOCK, by * BLOCK);
                let (tx1, ty1) = ((tx0 + BLOCK).min(tw) - 1, (ty0 + BLOCK).min(th) - 1);
                // Each change's bound over the block, and their sum (with margins for the sum's
                // rounding).
                let (block_lo, block_hi) = span((tx0, ty0), (tx1, ty1));
                let block_bounds = &mut self.scratch.block_bounds;
                block_bounds.clear();
                block_bounds.extend(changes.iter().map(|c| c.bound(&params, block_lo, block_hi)));
                let block_bound = block_bounds.iter().sum::<f64>() * (1.0 + 2.0 * REL);
                if block_bound < self.block_slack[by * bw + bx] {
                    continue;
                }
                for ty in ty0..=ty1 {
                    for tx in tx0..=tx1 {
                        // The block's bound holds at the tile's points too: a tile with more
                        // slack keeps its factors without bounds of its own.
                        if block_bound < self.tile_slack[ty * tw + tx] {
                            continue;
                        }
                        let (lo, hi) = span((tx, ty), (tx, ty));
                        // Each change's bound over the tile (its block's where that is below
                        // `PAIR_BOUND`: it is only bounded then), and their sum.
                        let Scratch { bounds, block_bounds, .. } = &mut self.scratch;
                        bounds.clear();
                        bounds.extend(
                            changes
                                .iter()
                                .zip(block_bounds.iter())
                                .map(|(c, &b)| if b < PAIR_BOUND { b } else { c.bound(&params, lo, hi) }),
                        );
                        if bounds.iter().sum::<f64>() * (1.0 + 2.0 * REL) < self.tile_slack[ty * tw + tx] {
                            continue;
                        }
                        // The changes' values on the tile by products where they may matter;
                        // the others (together below 1e-6 at most) by their bounds.
                        let (x0, y0) = (tx * TILE, ty * TILE);
                        let mut added = [0.0; TILE * TILE];
                        let mut taken = [0.0; TILE * TILE];
                        let (mut rest, mut terms) = (0.0, 0.0);
                        for (ch, &b) in changes.iter().zip(&self.scratch.bounds) {
                            if b < PAIR_BOUND {
                                rest += b;
                                continue;
                            }
                            if let Some(p) = &ch.after {
                                raster.add_person(p, x0, y0, &mut added);
                                terms += 1.0;
                            }
                            if let Some(p) = &ch.before {
                                raster.add_person(p, x0, y0, &mut taken);
                                terms += 1.0;
                            }
                        }
                        let rest = rest * (1.0 + 2.0 * REL) + terms * CUT_TERM;
                        let mut some_ready = false;
                        for iy in y0..(y0 + TILE).min(spec.height) {
                            for ix in x0..(x0 + TILE).min(spec.width) {
                                let c = spec.index(ix, iy);
                                let k = (iy - y0) * TILE + ix - x0;
                                // The reference's bounds moved by the changes (with margins for
                                // the products and every sum's rounding).
                                let (a, t) = (added[k], taken[k]);
                                let pad = rest + REL * (1.0 + self.hi[c].abs() + a + t);
                                let g_lo = self.lo[c] + a * (1.0 - REL) - t * (1.0 + REL) - pad;
                                let g_hi = self.hi[c] + a * (1.0 + REL) - t * (1.0 - REL) + pad;
                                // (`g_hi >= g_lo`: the reference's `hi >= lo`, and every
                                // term of `g_hi` at least its counterpart, rounding monotone.)
                                let class = raster.class(g_lo);
                                let class = if g_hi < raster.above(class) {
                                    class
                                } else {
                                    if !some_ready {
                                        raster.reaching(lo, hi, &mut self.scratch.some);
                                        some_ready = true;
                                    }
                                    // The same sum as `density_factor`'s.
                                    let x = spec.center(ix, iy);
                                    let g: f64 = self
                                        .scratch
                                        .some
                                        .iter()
                                        .map(|&i| self.zones.term(self.people[i].pos, self.people[i].f, x))
                                        .sum();
                                    self.summed += 1;
                                    raster.class(g)
                                };
                                let f = self.class_factor[class];
                                if f.to_bits() != self.factors[c].to_bits() {
                                    self.saved.push((c, self.factors[c]));
                                    self.factors[c] = f;
                                    self.changed.push(c);
                                }
                            }
                        }
                        if self.summed > limit {
                            self.rebuild(people);
                            return;
                        }
                    }
                }
            }
        }
    }
}

/// Side of the square tiles of [`DensityLayer`] (cells).
const TILE: usize = 8;

/// Side of the blocks of tiles whose bound of a change [`DensityLayer::update`] tries first
/// (tiles).
const BLOCK: usize = 4;

/// People whose exponent can fall to this in a tile are summed per cell by [`DensityLayer`]
/// (`exp(-10) = 4.5e-5`: the others together stay far below the contour levels' gaps).
const NEAR_EXPONENT: f64 = 10.0;

/// People whose exponent stays above this over a block of [`DensityLayer`]'s rebuild
/// (`exp(-16) = 1.1e-7`) are only bounded there, not looked at per tile.
const BLOCK_FAR: f64 = 16.0;

/// Kirby's Gaussian is cut where its exponent exceeds this (0 beyond).
const CUT: f64 = 40.0;

/// Above `exp(-CUT) = 4.25e-18`: the most a person's term can differ across the cut.
const CUT_TERM: f64 = 5e-18;

/// A change whose bound over a tile is below this is bounded, not evaluated, by
/// [`DensityLayer::update`].
const PAIR_BOUND: f64 = 1e-7;

/// Relative margin for rounding in the sums and products of [`DensityLayer`], far above the
/// errors it covers (below 1e-12 for the products, `n` ulps for a sum of `n` terms).
const REL: f64 = 1e-9;

/// Largest exponent over a tile (one cell beyond, either side's σ) for which a person's
/// Gaussian is evaluated by products: every value, ratio and constant then lies within
/// `exp(±2 RECURRENCE_MAX)`, far from overflow and underflow. Beyond, `exp` per cell.
const RECURRENCE_MAX: f64 = 80.0;

/// A person of [`DensityLayer`]: position (m), unit facing, the exponent's coefficients
/// `1/(2σ²)` ahead, behind and to the sides, the largest `σ` (m), and per side of the body
/// (ahead: `u >= 0`, behind) the constants of the products.
#[derive(Clone, Copy, Debug)]
struct Person {
    pos: Vec2,
    f: Vec2,
    ahead: f64,
    behind: f64,
    across: f64,
    sigma_max: f64,
    sides: [Side; 2],
}

/// One side's quadratic exponent `q = α u² + β v²` (`α = 1/(2σ_u²)`, `β = 1/(2σ_s²)`) along
/// the grid: per cell step along x, the ratio of consecutive values is multiplied by `row`;
/// along y by `col`; and a step along y multiplies the x ratio (and a step along x the y ratio)
/// by `cross`.
#[derive(Clone, Copy, Debug)]
struct Side {
    alpha: f64,
    row: f64,
    col: f64,
    cross: f64,
}

impl Person {
    fn new(p: &crate::groups::DensityParams, res: f64, pos: Vec2, f: Vec2) -> Self {
        let beta = 1.0 / (2.0 * p.sigma_s * p.sigma_s);
        // Local offsets of one cell step along x and along y.
        let (ui, vi, uj, vj) = (res * f.x, -res * f.y, res * f.y, res * f.x);
        let side = |s: f64| {
            let alpha = 1.0 / (2.0 * s * s);
            Side {
                alpha,
                row: (-2.0 * (alpha * ui * ui + beta * vi * vi)).exp(),
                col: (-2.0 * (alpha * uj * uj + beta * vj * vj)).exp(),
                cross: (-2.0 * (alpha * ui * uj + beta * vi * vj)).exp(),
            }
        };
        let sides = [side(p.sigma_h), side(p.sigma_r)];
        Person {
            pos,
            f,
            ahead: sides[0].alpha,
            behind: sides[1].alpha,
            across: beta,
            sigma_max: p.sigma_h.max(p.sigma_r).max(p.sigma_s),
            sides,
        }
    }

    /// Whether the box `lo`-`hi` (m) is out of the Gaussian's reach: the exponent is above 40
    /// there by distance alone (with the widest σ).
    #[inline]
    fn out_of_reach(&self, lo: Vec2, hi: Vec2) -> bool {
        let dx = (lo.x - self.pos.x).max(self.pos.x - hi.x).max(0.0);
        let dy = (lo.y - self.pos.y).max(self.pos.y - hi.y).max(0.0);
        let r = self.sigma_max * (2.0 * CUT).sqrt() * (1.0 + 1e-9);
        dx * dx + dy * dy > r * r
    }

    /// A lower and an upper bound on the exponent over the box `lo`-`hi` (m) (relative margins
    /// 1e-9): each axis term's minimum over the box, and its maximum (the term is convex with
    /// its minimum at 0, so the maximum is at one end). Without branches: of `max(m, 0)` and
    /// `min(m, 0)` one is 0.
    #[inline]
    fn bounds(&self, lo: Vec2, hi: Vec2) -> (f64, f64) {
        let [u, du, v, dv] = box_in_frame(self.pos, self.f, lo, hi);
        let (u0, u1, v0, v1) = (u - du, u + du, v - dv, v + dv);
        let sq = |m: f64| m * m;
        let along = |m: f64| self.ahead * sq(m.max(0.0)) + self.behind * sq(m.min(0.0));
        let qu_lo = self.ahead * sq(u0.max(0.0)) + self.behind * sq(u1.min(0.0));
        let qv_lo = sq(v0.max(0.0)) + sq(v1.min(0.0));
        let qu_hi = along(u0).max(along(u1));
        let qv_hi = sq(v0).max(sq(v1));
        ((qu_lo + self.across * qv_lo) * (1.0 - 1e-9), (qu_hi + self.across * qv_hi) * (1.0 + 1e-9))
    }

    /// An upper bound on either side's exponent (the larger of the two `1/(2σ_u²)` for `u` of
    /// either sign) over the box `lo`-`hi` (m): bounds both quadratics of [`Side`] at once.
    #[inline]
    fn upper_either(&self, lo: Vec2, hi: Vec2) -> f64 {
        let [u, du, v, dv] = box_in_frame(self.pos, self.f, lo, hi);
        let qu = ((u - du).abs().max((u + du).abs())).powi(2) * self.ahead.max(self.behind);
        let qv = ((v - dv).abs().max((v + dv).abs())).powi(2) * self.across;
        (qu + qv) * (1.0 + 1e-9)
    }
}

/// Scratch lists of [`Raster::tile`].
#[derive(Clone, Debug, Default)]
struct Scratch {
    /// The bound of each change over a tile and over its block ([`DensityLayer::update`]).
    bounds: Vec<f64>,
    block_bounds: Vec<f64>,
    block: Vec<usize>,
    some: Vec<usize>,
    near: Vec<usize>,
}

/// What [`Raster::tile`] reads.
struct Raster<'a> {
    spec: &'a GridSpec,
    zones: &'a DensityZones,
    thresholds: &'a [f64; 4],
    class_factor: &'a [f64; 5],
    people: &'a [Person],
}

impl Raster<'_> {
    /// How many of the thresholds `g` reaches.
    fn class(&self, g: f64) -> usize {
        self.thresholds.iter().filter(|&&t| g >= t).count()
    }

    /// The threshold next above class `c` (infinite above the last): a density at least one of
    /// class `c` is in that class exactly when it stays below this.
    #[inline]
    fn above(&self, c: usize) -> f64 {
        self.thresholds.get(c).copied().unwrap_or(f64::INFINITY)
    }

    /// How far a density known to lie in `lo..=hi` (no threshold inside) may move either way
    /// and stay in its class, less a margin for rounding (negative: not at all): the distance to
    /// the nearest threshold, `max(lo - t, t - hi)` for each threshold `t` outside.
    #[inline]
    fn slack(&self, lo: f64, hi: f64) -> f64 {
        let d = self.thresholds.iter().fold(f64::INFINITY, |d, &t| d.min((lo - t).max(t - hi)));
        d - REL * (1.0 + hi.abs())
    }

    /// The people (indices, in order) whose exponent may be 40 or below somewhere in the box
    /// `lo`-`hi` (m), into `out`: the others add exactly 0 to every sum there.
    fn reaching(&self, lo: Vec2, hi: Vec2, out: &mut Vec<usize>) {
        out.clear();
        out.extend((0..self.people.len()).filter(|&i| self.people[i].bounds(lo, hi).0 <= CUT * (1.0 + 1e-9)));
    }

    /// Computes the factors of tile (`tx`, `ty`) into `out` and each cell's slack into `slack`
    /// (both the whole grid's, row-major) and returns the tile's slack (the smallest; module
    /// docs of [`DensityLayer`]).
    fn tile(
        &self,
        tx: usize,
        ty: usize,
        block_far: f64,
        s: &mut Scratch,
        out: &mut [f64],
        (lo_out, hi_out): (&mut [f64], &mut [f64]),
    ) -> f64 {
        let spec = self.spec;
        let (x0, y0) = (tx * TILE, ty * TILE);
        let (x1, y1) = ((x0 + TILE).min(spec.width) - 1, (y0 + TILE).min(spec.height) - 1);
        let (lo, hi) = (spec.center(x0, y0), spec.center(x1, y1));
        s.near.clear();
        let (mut far, mut t_lo, mut t_hi) = (block_far, 0.0, 0.0);
        for &i in &s.block {
            let (q_lo, q_hi) = self.people[i].bounds(lo, hi);
            if q_lo > CUT * (1.0 + 1e-9) {
                continue;
            }
            if q_lo <= NEAR_EXPONENT {
                s.near.push(i);
                t_hi += exp_table_above(q_lo);
                t_lo += exp_table_below(q_hi);
            } else {
                far += exp_table_above(q_lo);
            }
        }
        let far = far * (1.0 + 1e-9);
        // The whole tile at once when the bounds of `G_d` over it fall in one class.
        let (t_lo, t_hi) = (t_lo * (1.0 - 1e-9), (t_hi + far) * (1.0 + 1e-9));
        let c = self.class(t_lo);
        if c == self.class(t_hi) {
            let sl = self.slack(t_lo, t_hi);
            for iy in y0..=y1 {
                let row = spec.index(x0, iy)..=spec.index(x1, iy);
                out[row.clone()].fill(self.class_factor[c]);
                lo_out[row.clone()].fill(t_lo);
                hi_out[row].fill(t_hi);
            }
            return sl;
        }
        // Per cell: the near people's values by products, the far ones bounded by `far`.
        let mut acc = [0.0; TILE * TILE];
        for &i in &s.near {
            self.add_person(&self.people[i], x0, y0, &mut acc);
        }
        // The products may count a near person's value where their exponent passes the cut.
        let pad = s.near.len() as f64 * CUT_TERM;
        let mut tile_slack = f64::INFINITY;
        let mut undecided = false;
        let n = x1 - x0 + 1;
        let [t0, t1, t2, t3] = *self.thresholds;
        // The thresholds next below and above each class (the nearest ones to a density in it).
        let below = [f64::NEG_INFINITY, t0, t1, t2, t3];
        let above = [t0, t1, t2, t3, f64::INFINITY];
        for iy in y0..=y1 {
            let row = spec.index(x0, iy);
            let a = &acc[(iy - y0) * TILE..(iy - y0) * TILE + n];
            let (o, l, h) = (&mut out[row..row + n], &mut lo_out[row..row + n], &mut hi_out[row..row + n]);
            for i in 0..n {
                let (g_lo, g_hi) = ((a[i] - pad) * (1.0 - REL), (a[i] + far) * (1.0 + REL));
                let class = |g: f64| {
                    usize::from(g >= t0) + usize::from(g >= t1) + usize::from(g >= t2) + usize::from(g >= t3)
                };
                let c = class(g_lo);
                o[i] = self.class_factor[c];
                l[i] = g_lo;
                h[i] = g_hi;
                // `g_hi >= g_lo` is in `g_lo`'s class exactly when it stays below the class's
                // next threshold.
                if g_hi >= above[c] {
                    undecided = true;
                } else {
                    // The distance to the nearest threshold (`slack`, the same value: with no
                    // threshold in `g_lo..=g_hi`, the nearest are the class's next below and
                    // above).
                    let d = (g_lo - below[c]).min(above[c] - g_hi);
                    tile_slack = tile_slack.min(d - REL * (1.0 + g_hi.abs()));
                }
            }
        }
        if !undecided {
            return tile_slack;
        }
        // The cells left undecided: the same sum as `density_factor`'s, every person not left
        // out, in order.
        self.reaching(lo, hi, &mut s.some);
        for iy in y0..=y1 {
            for ix in x0..=x1 {
                let k = spec.index(ix, iy);
                if self.class(lo_out[k]) == self.class(hi_out[k]) {
                    continue;
                }
                let x = spec.center(ix, iy);
                let g: f64 =
                    s.some.iter().map(|&i| self.zones.term(self.people[i].pos, self.people[i].f, x)).sum();
                out[k] = self.class_factor[self.class(g)];
                lo_out[k] = g;
                hi_out[k] = g;
                tile_slack = tile_slack.min(self.slack(g, g));
            }
        }
        tile_slack
    }

    /// Adds person `p`'s Gaussian at the centres of the tile's cells (from cell `x0`, `y0`; 8 by
    /// 8, cells beyond the grid included) to `acc` (row-major), by products where the exponent
    /// stays below [`RECURRENCE_MAX`] (relative error below 1e-12), else by `exp` per cell.
    fn add_person(&self, p: &Person, x0: usize, y0: usize, acc: &mut [f64; TILE * TILE]) {
        let spec = self.spec;
        let res = spec.resolution;
        let c0 = spec.center(x0, y0);
        // The products reach one cell beyond the tile on each axis.
        let ext = Vec2::new(c0.x + (TILE + 1) as f64 * res, c0.y + (TILE + 1) as f64 * res);
        if p.upper_either(c0, ext) > RECURRENCE_MAX {
            for j in 0..TILE.min(spec.height - y0) {
                for i in 0..TILE.min(spec.width - x0) {
                    acc[j * TILE + i] += self.zones.term(p.pos, p.f, spec.center(x0 + i, y0 + j));
                }
            }
            return;
        }
        let d = c0 - p.pos;
        let (u0, v0) = (p.f.x * d.x + p.f.y * d.y, -p.f.y * d.x + p.f.x * d.y);
        let beta = p.across;
        let [u, du, _, _] = box_in_frame(p.pos, p.f, c0, spec.center(x0 + TILE - 1, y0 + TILE - 1));
        if u - du > 0.0 || u + du < 0.0 {
            let side = &p.sides[usize::from(u + du < 0.0)];
            side_values(side, beta, res, p.f, u0, v0, |k, e| acc[k] += e);
            return;
        }
        // The tile straddles the line across the person's facing: each cell takes its side's
        // value, the side decided as `gaussian_local` decides it.
        let mut ahead = [0.0; TILE * TILE];
        side_values(&p.sides[0], beta, res, p.f, u0, v0, |k, e| ahead[k] = e);
        let mut behind = [0.0; TILE * TILE];
        side_values(&p.sides[1], beta, res, p.f, u0, v0, |k, e| behind[k] = e);
        // The side as `p.f.x * d.x + p.f.y * d.y` of `d = spec.center(ix, iy) - p.pos` decides
        // it, the same operations: a cell centre's x depends on its column only, its y on its
        // row only, so each product is taken once per column or row.
        let nx = TILE.min(spec.width - x0);
        let mut ux = [0.0; TILE];
        for (i, u) in ux.iter_mut().enumerate().take(nx) {
            *u = p.f.x * (spec.center(x0 + i, y0).x - p.pos.x);
        }
        for j in 0..TILE.min(spec.height - y0) {
            let uy = p.f.y * (spec.center(x0, y0 + j).y - p.pos.y);
            for (i, &u) in ux.iter().enumerate().take(nx) {
                let k = j * TILE + i;
                acc[k] += if u + uy >= 0.0 { ahead[k] } else { behind[k] };
            }
        }
    }
}

/// `exp(-q)` of one side's quadratic exponent (see [`Side`]) at the 8 by 8 cells from the one
/// whose local offsets (m) are `u0`, `v0`, passed to `put(k, value)` with `k = 8 j + i`, by
/// products: `e(i+1, j) = e(i, j) R(i, j)`, `R(i+1, j) = R(i, j) row`, `R(i, j+1) = R(i, j) cross`,
/// and the same along y with `V` and `col`.
fn side_values(side: &Side, beta: f64, res: f64, f: Vec2, u0: f64, v0: f64, mut put: impl FnMut(usize, f64)) {
    let a = side.alpha;
    let (ui, vi, uj, vj) = (res * f.x, -res * f.y, res * f.y, res * f.x);
    let q0 = a * u0 * u0 + beta * v0 * v0;
    let qi = a * (2.0 * u0 * ui + ui * ui) + beta * (2.0 * v0 * vi + vi * vi);
    let qj = a * (2.0 * u0 * uj + uj * uj) + beta * (2.0 * v0 * vj + vj * vj);
    let mut e = [0.0; TILE];
    let mut v = [0.0; TILE];
    e[0] = (-q0).exp();
    v[0] = (-qj).exp();
    let mut r = (-qi).exp();
    for i in 1..TILE {
        e[i] = e[i - 1] * r;
        r *= side.row;
        v[i] = v[i - 1] * side.cross;
    }
    for j in 0..TILE {
        for i in 0..TILE {
            put(j * TILE + i, e[i]);
            e[i] *= v[i];
            v[i] *= side.col;
        }
    }
}

/// A change of one person between the reference and the current people of [`DensityLayer`]:
/// `(position, unit facing)` before and after; `None` on one side for a person who joined or
/// left.
#[derive(Clone, Copy, Debug)]
struct Change {
    before: Option<Person>,
    after: Option<Person>,
}

impl Change {
    /// An upper bound on `|g_after(x) - g_before(x)|` over the box `lo`-`hi` (m) for the cut
    /// Gaussians of the change's person (module docs of [`DensityLayer`]).
    fn bound(&self, p: &crate::groups::DensityParams, lo: Vec2, hi: Vec2) -> f64 {
        // The largest value over the box, with the exponent's lower bound.
        let top = |x: &Person| {
            let q = exponent_lower_bound(p, x.pos, x.f, lo, hi);
            (q, if q > CUT * (1.0 + 1e-9) { 0.0 } else { exp_table_above(q) })
        };
        let (Some(a), Some(b)) = (&self.before, &self.after) else {
            return self.before.as_ref().or(self.after.as_ref()).map_or(0.0, |x| top(x).1);
        };
        let ((qa, ta), (qb, tb)) = (top(a), top(b));
        let crude = ta.max(tb);
        if crude == 0.0 {
            return 0.0;
        }
        // A box point x is at y_a = R_a (x - p_a) in the frame before and y_b after, with
        // |y_b - y_a| <= |p_b - p_a| + |f_b - f_a| |x - p_a| (rotations' difference). Along the
        // segment between them, s = sqrt(2 q) moves at most that over σ_min (|∇s| <= 1/σ_min),
        // and |∇ e^{-q}| = e^{-q} |∇q| <= e^{-s²/2} s / σ_min, largest (e^{-1/2}) at s = 1 and
        // falling beyond; the cut adds a jump of e^{-40} where the segment crosses it (twice at
        // most: q is convex along it).
        let smin = p.sigma_h.min(p.sigma_r).min(p.sigma_s);
        let dx = (lo.x - a.pos.x).abs().max((hi.x - a.pos.x).abs());
        let dy = (lo.y - a.pos.y).abs().max((hi.y - a.pos.y).abs());
        let moved = (b.pos - a.pos).norm() + (b.f - a.f).norm() * (dx * dx + dy * dy).sqrt();
        let d = moved / smin * (1.0 + 1e-9);
        let s = ((2.0 * qa).sqrt().max((2.0 * qb).sqrt()) * (1.0 - 1e-9) - d).max(0.0);
        // (`exp_table_above` bounds `e^{-s²/2}` from above, by 1 beyond its table.)
        let slope = if s <= 1.0 { (-0.5f64).exp() } else { s * exp_table_above(0.5 * s * s) };
        crude.min(d * slope * (1.0 + 1e-9) + 2.0 * CUT_TERM)
    }
}

/// The changes from the reference people `base` to `now` (see [`Change`]): people equal (bit
/// for bit) to one of the reference are unchanged; the others are paired with the nearest
/// unpaired reference person within 1 m (position plus facing), or joined; the reference people
/// left over left. Any pairing gives a valid bound; near pairs give tight ones.
fn pair_changes(base: &[Person], now: &[Person], out: &mut Vec<Change>) {
    let same = |a: &Person, b: &Person| {
        [a.pos.x, a.pos.y, a.f.x, a.f.y].map(f64::to_bits)
            == [b.pos.x, b.pos.y, b.f.x, b.f.y].map(f64::to_bits)
    };
    let mut used = vec![false; base.len()];
    let mut joined = Vec::new();
    for (i, p) in now.iter().enumerate() {
        let k = if i < base.len() && !used[i] && same(&base[i], p) {
            Some(i)
        } else {
            (0..base.len()).find(|&k| !used[k] && same(&base[k], p))
        };
        match k {
            Some(k) => used[k] = true,
            None => joined.push(p),
        }
    }
    out.clear();
    for p in joined {
        let gap = |k: usize| (base[k].pos - p.pos).norm() + (base[k].f - p.f).norm();
        let nearest = (0..base.len()).filter(|&k| !used[k]).min_by(|&a, &b| gap(a).total_cmp(&gap(b)));
        match nearest.filter(|&k| gap(k) < 1.0) {
            Some(k) => {
                used[k] = true;
                out.push(Change { before: Some(base[k]), after: Some(*p) });
            }
            None => out.push(Change { before: None, after: Some(*p) }),
        }
    }
    out.extend((0..base.len()).filter(|&k| !used[k]).map(|k| Change { before: Some(base[k]), after: None }));
}

/// The box `lo`-`hi` (m) in the frame of a person at `pos` facing the unit vector `f`: the
/// centre's offsets along and across the facing, `u` and `v`, and the box's half-extents along
/// those axes, `du` and `dv`, as `[u, du, v, dv]` (m).
fn box_in_frame(pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> [f64; 4] {
    let c = (lo + hi) * 0.5 - pos;
    let (hx, hy) = (0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y));
    [
        f.x * c.x + f.y * c.y,
        f.x.abs() * hx + f.y.abs() * hy,
        -f.y * c.x + f.x * c.y,
        f.y.abs() * hx + f.x.abs() * hy,
    ]
}

/// A lower bound on Kirby's exponent `u²/(2σ_u²) + v²/(2σ_s²)` (see
/// [`crate::groups::DensityParams::gaussian_local`]) of the person at `pos` facing the unit
/// vector `f`, over the axis-aligned box `lo`-`hi` (m): each axis term's minimum over the box,
/// less a relative margin far above rounding.
fn exponent_lower_bound(p: &crate::groups::DensityParams, pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> f64 {
    let [u, du, v, dv] = box_in_frame(pos, f, lo, hi);
    let side = |m: f64, s: f64| m * m / (2.0 * s * s);
    let qu = if u - du > 0.0 {
        side(u - du, p.sigma_h)
    } else if u + du < 0.0 {
        side(u + du, p.sigma_r)
    } else {
        0.0
    };
    let qv = if v - dv > 0.0 {
        side(v - dv, p.sigma_s)
    } else if v + dv < 0.0 {
        side(v + dv, p.sigma_s)
    } else {
        0.0
    };
    (qu + qv) * (1.0 - 1e-9)
}

/// Steps per unit of exponent of [`exp_table`].
const EXP_STEPS: f64 = 32.0;

/// `exp(-i / EXP_STEPS)` for `i` in `0..=40 EXP_STEPS` (Kirby's Gaussian is cut at exponent 40).
fn exp_table() -> &'static [f64] {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| (0..=(40.0 * EXP_STEPS) as usize).map(|i| (-(i as f64) / EXP_STEPS).exp()).collect())
}

/// An upper bound on `exp(-q)` for `0 <= q <= 40` (with a margin), from [`exp_table`].
fn exp_table_above(q: f64) -> f64 {
    // (The float-to-integer cast truncates: the floor of a non-negative value.)
    let i = (q.max(0.0) * EXP_STEPS) as usize;
    exp_table().get(i).map_or(1.0, |&e| e * (1.0 + 1e-12))
}

/// A lower bound on the term `exp(-q)` of a Gaussian cut at exponent 40 (0 beyond), from
/// [`exp_table`] (with a margin).
fn exp_table_below(q: f64) -> f64 {
    if q > 40.0 {
        return 0.0;
    }
    let t = q.max(0.0) * EXP_STEPS;
    let i = t as usize + usize::from((t as usize as f64) < t); // the ceiling
    exp_table().get(i).map_or(0.0, |&e| e * (1.0 - 1e-12))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groups::DensityParams;
    use crate::proxemics::HallZones;

    fn zones() -> DensityZones {
        DensityZones::new(DensityParams::default(), HallZones::EVALUATION).expect("valid")
    }

    #[test]
    fn one_person_facing_east_known_factors() {
        // Person at the origin facing +x, σ_h = 2 (ahead), σ_r = 1 (behind), σ_s = 4/3 (sides).
        // Levels L(r) = exp(-r² / (2 σ_s²)), 2 σ_s² = 32/9 = 3.5556:
        //   intimate L(0.45) = exp(-0.2025 / 3.5556) = exp(-0.05695) = 0.94464
        //   personal L(1.2)  = exp(-1.44 / 3.5556)   = exp(-0.405)    = 0.66698
        //   social   L(3.6)  = exp(-12.96 / 3.5556)  = exp(-3.645)    = 0.02612
        // Points and g = exp(-u²/(2σ_u²) - v²/(2σ_s²)):
        //   (0.6, 0):  exp(-0.36/8)   = 0.95600 >= 0.94464  -> intimate, forbidden
        //   (0.7, 0):  exp(-0.49/8)   = 0.94059 <  0.94464  -> personal, 4.0
        //   (-0.5, 0): exp(-0.25/2)   = 0.88250             -> personal, 4.0
        //   (0, 1.5):  exp(-2.25/3.5556) = exp(-0.63281) = 0.53110 -> social, 2.0
        //   (-2.0, 0): exp(-4/2)      = 0.13534             -> social, 2.0
        //   (-2.8, 0): exp(-7.84/2)   = 0.01984 <  0.02612  -> public, 1.0
        //   (5.0, 0):  exp(-25/8)     = 0.04394 >= 0.02612  -> social, 2.0
        let z = zones();
        let c = SocialCosts::default();
        let one = [PersonState::standing(Vec2::zeros(), 0.0)];
        let f = |x: f64, y: f64| density_factor(&z, &c, &one, Vec2::new(x, y));
        assert!(f(0.6, 0.0).is_infinite());
        assert_eq!(f(0.7, 0.0), 4.0);
        assert_eq!(f(-0.5, 0.0), 4.0);
        assert_eq!(f(0.0, 1.5), 2.0);
        assert_eq!(f(-2.0, 0.0), 2.0);
        assert_eq!(f(-2.8, 0.0), 1.0);
        assert_eq!(f(5.0, 0.0), 2.0);
    }

    #[test]
    fn two_people_side_by_side_merge_into_one_forbidden_region() {
        // Two people facing +x at (0, ±1.5), 3 m apart. At the midpoint each Gaussian is at
        // 1.5 m to its side: g = exp(-2.25 / 3.5556) = 0.53110, G_d = 1.06220 >= 0.94464: the
        // midpoint is intimate (forbidden) although it is 1.5 m from both, beyond Hall's
        // personal radius. Alone, either person puts it in the social zone (0.53110 < 0.66698).
        // At (0, 0.5): 1 m from one, 2 m from the other:
        //   exp(-1/3.5556) + exp(-4/3.5556) = 0.75484 + 0.32465 = 1.07949 -> intimate too.
        let z = zones();
        let c = SocialCosts::default();
        let pair = [
            PersonState::standing(Vec2::new(0.0, 1.5), 0.0),
            PersonState::standing(Vec2::new(0.0, -1.5), 0.0),
        ];
        assert!(density_factor(&z, &c, &pair, Vec2::zeros()).is_infinite());
        assert!(density_factor(&z, &c, &pair, Vec2::new(0.0, 0.5)).is_infinite());
        assert_eq!(density_factor(&z, &c, &pair[..1], Vec2::zeros()), 2.0);
        // 4 m apart, midpoint 2 m to the side of each: 2 exp(-4/3.5556) = 0.64930, below the
        // personal level 0.66698 and above the social one: social, 2.0.
        let wide = [
            PersonState::standing(Vec2::new(0.0, 2.0), 0.0),
            PersonState::standing(Vec2::new(0.0, -2.0), 0.0),
        ];
        assert_eq!(density_factor(&z, &c, &wide, Vec2::zeros()), 2.0);
    }

    #[test]
    fn the_layer_of_a_crowd_is_the_factor_at_each_cell_centre_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let z = zones();
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::new(0.0, 0.0), resolution: 0.1, width: 120, height: 90 };
        let crowd: Vec<PersonState> = (0..25)
            .map(|_| {
                let p = Vec2::new(rng.random_range(0.0..12.0), rng.random_range(0.0..9.0));
                PersonState::standing(p, rng.random_range(-3.2..3.2))
            })
            .collect();
        let layer = density_layer(&spec, &z, &c, &crowd);
        let facing: Vec<(Vec2, Vec2)> = crowd.iter().map(|p| (p.pos, p.facing())).collect();
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let x = spec.center(ix, iy);
                assert_eq!(z.density_facing(&facing, x).to_bits(), z.density(&crowd, x).to_bits());
                assert_eq!(layer[spec.index(ix, iy)], density_factor(&z, &c, &crowd, x));
            }
        }
    }

    #[test]
    fn the_tiled_layer_of_clustered_crowds_is_the_factor_at_each_cell_centre_bit_for_bit() {
        // Tight clusters (merged intimate regions, many contour crossings inside a tile), other
        // sigmas, a grid whose size is no multiple of the tile, and costs that do not grow with
        // the zone: every cell must still be `density_factor`'s.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(6);
        let costs = [
            SocialCosts::default(),
            SocialCosts { personal_cost: 1.5, social_cost: 3.0, public_cost: 1.2, ..SocialCosts::default() },
        ];
        let params = [
            DensityParams::default(),
            DensityParams { sigma_h: 1.0, sigma_r: 0.6, sigma_s: 0.8, k: 0.3, ..DensityParams::default() },
        ];
        let spec = GridSpec { origin: Vec2::new(-1.0, 0.5), resolution: 0.1, width: 163, height: 97 };
        for (c, dp) in costs.iter().zip(params) {
            let z = DensityZones::new(dp, HallZones::EVALUATION).expect("valid");
            let mut crowd = Vec::new();
            for _ in 0..8 {
                let centre = Vec2::new(rng.random_range(-1.0..15.0), rng.random_range(0.5..10.0));
                for _ in 0..rng.random_range(1..7) {
                    let off = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                    crowd.push(PersonState::standing(centre + off, rng.random_range(-3.2..3.2)));
                }
            }
            let layer = density_layer(&spec, &z, c, &crowd);
            let mut zones_seen = std::collections::BTreeSet::new();
            for iy in 0..spec.height {
                for ix in 0..spec.width {
                    let want = density_factor(&z, c, &crowd, spec.center(ix, iy));
                    assert_eq!(layer[spec.index(ix, iy)].to_bits(), want.to_bits(), "cell ({ix}, {iy})");
                    zones_seen.insert(want.to_bits());
                }
            }
            assert_eq!(zones_seen.len(), 4, "every factor appears");
        }
    }

    /// Every cell of `layer` against [`density_factor`] for `people` (bit for bit).
    fn assert_layer(
        layer: &DensityLayer,
        z: &DensityZones,
        c: &SocialCosts,
        people: &[PersonState],
        what: &str,
    ) {
        let spec = layer.spec;
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let want = density_factor(z, c, people, spec.center(ix, iy));
                let got = layer.factors()[spec.index(ix, iy)];
                assert_eq!(got.to_bits(), want.to_bits(), "{what}: cell ({ix}, {iy}): {got} != {want}");
            }
        }
    }

    /// A person facing +x with the centre of a cell of the region `x0..x1` (m) exactly at one of
    /// the Hall radii to their left: `G_d` there is exactly that contour level when nobody else
    /// reaches the cell, the hardest case for the margins.
    fn on_a_contour(spec: &GridSpec, rng: &mut rand_chacha::ChaCha8Rng, x0: f64, x1: f64) -> PersonState {
        use rand::Rng;
        let radii =
            [HallZones::EVALUATION.intimate, HallZones::EVALUATION.personal, HallZones::EVALUATION.social];
        loop {
            let r = radii[rng.random_range(0..3)];
            let ix = spec.cell_of(Vec2::new(rng.random_range(x0..x1), spec.origin.y)).map_or(0, |c| c.0);
            let iy = rng.random_range(0..spec.height);
            let x = spec.center(ix, iy);
            let p = Vec2::new(x.x, x.y - r);
            if x.y - p.y == r {
                return PersonState::standing(p, 0.0);
            }
        }
    }

    #[test]
    fn the_updated_layer_is_the_factor_at_each_cell_centre_as_people_move_leave_join_and_turn() {
        // Random scenes on a grid whose sides are no multiple of the tile or the block: a crowd
        // in clusters that moves (by centimetres and by metres), turns, loses and gains people
        // (anywhere in the list), goes back to earlier states (to and fro), with people outside
        // the grid, and, away from the crowd (narrow Gaussians: nobody else reaches it), a
        // person with a cell centre exactly on a contour level. After every update every cell
        // must be `density_factor`'s, and most updates must stay incremental.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
        let spec = GridSpec { origin: Vec2::new(-0.35, 0.25), resolution: 0.1, width: 203, height: 161 };
        let configs = [
            (DensityParams::default(), SocialCosts::default(), false),
            (
                DensityParams {
                    sigma_h: 0.8,
                    sigma_r: 0.4,
                    sigma_s: 0.6,
                    k: 0.3,
                    ..DensityParams::default()
                },
                SocialCosts {
                    personal_cost: 1.5,
                    social_cost: 3.0,
                    public_cost: 0.8,
                    ..SocialCosts::default()
                },
                true,
            ),
        ];
        let mut incremental = 0;
        for (dp, c, contour) in configs {
            let z = DensityZones::new(dp, HallZones::EVALUATION).expect("valid");
            // The crowd keeps to x < 8 m (narrow Gaussians reach 7.2 m), the contour person's
            // cell to x > 15.5 m.
            let crowd_x = if contour { 8.0 } else { 20.0 };
            let person = |rng: &mut rand_chacha::ChaCha8Rng| {
                let p = Vec2::new(rng.random_range(-1.0..crowd_x), rng.random_range(-0.5..16.5));
                PersonState::standing(p, rng.random_range(-3.2..3.2))
            };
            let mut people: Vec<PersonState> = Vec::new();
            for _ in 0..4 {
                let centre = person(&mut rng).pos;
                for _ in 0..rng.random_range(1..6) {
                    let off = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                    people.push(PersonState::standing(centre + off, rng.random_range(-3.2..3.2)));
                }
            }
            if contour {
                people.push(on_a_contour(&spec, &mut rng, 15.5, 19.5));
            }
            let mut layer = DensityLayer::new(spec, z, &c);
            let open = crate::map::CostGrid { spec, cost: vec![0; spec.len()] };
            let mut map = super::super::SocialMap::new(open, &[], c);
            layer.update(&people);
            layer.write_to(&mut map).expect("same grid");
            assert_layer(&layer, &z, &c, &people, "first");
            let mut history = vec![people.clone()];
            for step in 0..40 {
                let n = people.len();
                match rng.random_range(0..8) {
                    0 | 1 => {
                        for _ in 0..rng.random_range(1..4) {
                            let p = &mut people[rng.random_range(0..n)];
                            p.pos += Vec2::new(rng.random_range(-0.15..0.15), rng.random_range(-0.15..0.15));
                        }
                    }
                    2 => {
                        let p = &mut people[rng.random_range(0..n)];
                        p.heading += rng.random_range(-0.5..0.5);
                    }
                    3 if n > 2 => {
                        people.remove(rng.random_range(0..n));
                    }
                    4 => {
                        let p = if contour && rng.random_bool(0.5) {
                            on_a_contour(&spec, &mut rng, 15.5, 19.5)
                        } else {
                            person(&mut rng)
                        };
                        people.insert(rng.random_range(0..=n), p);
                    }
                    5 => people = history[rng.random_range(0..history.len())].clone(),
                    6 => {
                        let k = rng.random_range(0..n);
                        people[k] = person(&mut rng);
                    }
                    _ => {
                        // The contour person moves to another contour cell.
                        if let Some(k) = people.iter().position(|p| p.pos.x > crowd_x + 5.0) {
                            people[k] = on_a_contour(&spec, &mut rng, 15.5, 19.5);
                        }
                    }
                }
                if contour {
                    for p in &mut people {
                        if p.pos.x < crowd_x + 5.0 {
                            p.pos.x = p.pos.x.min(crowd_x);
                        }
                    }
                }
                history.push(people.clone());
                layer.update(&people);
                layer.write_to(&mut map).expect("same grid");
                if !layer.rebuilt() {
                    incremental += 1;
                    assert!(layer.cells_summed() < spec.len() / 16);
                }
                assert_layer(&layer, &z, &c, &people, &format!("step {step}"));
                let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
                assert_eq!(
                    bits(map.people_layer()),
                    bits(layer.factors()),
                    "step {step}: the map's people layer"
                );
            }
        }
        assert!(incremental > 50, "most updates incremental: {incremental} of 80");
    }

    #[test]
    fn cells_exactly_on_a_contour_get_the_factor_of_density_factor_rebuilt_and_updated() {
        // On a grid of 1/8 m cells from the origin (exact centres), people facing +x at cell
        // centres, out of each other's reach (narrow Gaussians, at least 9.4 m apart), with
        // Hall radii 0.5/1/4 m: the cells 4, 8 and 32 rows beside each person have `G_d`
        // exactly at a contour level. Any margin too small for the products' rounding puts some
        // of them in the wrong zone. Then people move between such places, leave and come back.
        let dp = DensityParams { sigma_h: 1.0, sigma_r: 0.5, sigma_s: 1.0, ..DensityParams::default() };
        let z = DensityZones::new(dp, HallZones::DAZA2021).expect("valid");
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.125, width: 290, height: 177 };
        let at = |ix: usize, iy: usize| PersonState::standing(spec.center(ix, iy), 0.0);
        let mut people: Vec<PersonState> = [30, 113, 195, 270]
            .into_iter()
            .flat_map(|ix| [35, 138].map(|iy| (ix, iy)))
            .enumerate()
            .map(|(k, (ix, iy))| at(ix + k % 3, iy + k % 5))
            .collect();
        let on_contour = |people: &[PersonState]| {
            let mut n = 0;
            for p in people {
                for (r, level) in [0.5, 1.0, 4.0].into_iter().zip(z.levels()) {
                    for side in [-r, r] {
                        if z.density(people, p.pos + Vec2::new(0.0, side)) == level {
                            n += 1;
                        }
                    }
                }
            }
            n
        };
        assert!(on_contour(&people) >= 40, "cells exactly on a contour: {}", on_contour(&people));
        let mut layer = DensityLayer::new(spec, z, &c);
        layer.rebuild(&people);
        assert_layer(&layer, &z, &c, &people, "rebuilt");
        let moves: [(usize, isize, isize); 6] =
            [(0, 1, 0), (3, 0, 2), (5, -3, 1), (0, -1, 0), (7, 2, -2), (3, 0, -2)];
        for (step, (k, dx, dy)) in moves.into_iter().enumerate() {
            let (ix, iy) = spec.cell_of(people[k].pos).expect("inside");
            people[k] = at(ix.wrapping_add_signed(dx), iy.wrapping_add_signed(dy));
            layer.update(&people);
            assert!(!layer.rebuilt());
            assert_layer(&layer, &z, &c, &people, &format!("move {step}"));
        }
        let gone = people.remove(2);
        layer.update(&people);
        assert_layer(&layer, &z, &c, &people, "one left");
        people.insert(2, gone);
        layer.update(&people);
        assert_layer(&layer, &z, &c, &people, "back");
        assert!(on_contour(&people) >= 40);
    }

    #[test]
    fn small_moves_in_a_dense_crowd_update_to_the_factor_at_each_cell_centre() {
        // The benchmark's kind of scene: 50 people over a 36 by 25 m hall (contours everywhere,
        // most tiles summed per cell), a few of them moving by centimetres, turning, or going
        // back, updated from the same reference each time: the blocks' and tiles' bounds of the
        // changes decide which cells keep the reference's factors. Every cell must still be
        // `density_factor`'s, and the updates must stay incremental.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
        let z = zones();
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.1, width: 360, height: 252 };
        let crowd: Vec<PersonState> = (0..50)
            .map(|_| {
                let p = Vec2::new(rng.random_range(0.5..35.5), rng.random_range(0.5..24.7));
                PersonState::standing(p, rng.random_range(-3.2..3.2))
            })
            .collect();
        let mut layer = DensityLayer::new(spec, z, &c);
        layer.rebuild(&crowd);
        assert_layer(&layer, &z, &c, &crowd, "rebuilt");
        for step in 0..6 {
            let mut moved = crowd.clone();
            for _ in 0..5 {
                let p = &mut moved[rng.random_range(0..50)];
                if step % 3 == 2 {
                    p.heading += rng.random_range(-0.2..0.2);
                } else {
                    p.pos += Vec2::new(rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1));
                }
            }
            layer.update(&moved);
            assert!(!layer.rebuilt(), "step {step}");
            assert_layer(&layer, &z, &c, &moved, &format!("step {step}"));
        }
        layer.update(&crowd);
        assert_layer(&layer, &z, &c, &crowd, "back");
    }

    #[test]
    fn the_layer_is_the_factor_at_each_cell_centre() {
        let z = zones();
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::new(-2.0, -2.0), resolution: 0.5, width: 8, height: 8 };
        let one = [PersonState::standing(Vec2::new(0.1, 0.2), 1.0)];
        let layer = density_layer(&spec, &z, &c, &one);
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let want = density_factor(&z, &c, &one, spec.center(ix, iy));
                assert_eq!(layer[spec.index(ix, iy)], want);
            }
        }
        assert!(density_layer(&spec, &z, &c, &[]).iter().all(|&f| f == 1.0));
    }
}
