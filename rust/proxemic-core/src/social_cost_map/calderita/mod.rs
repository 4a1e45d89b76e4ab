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

mod tiled;
use tiled::*;

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

#[cfg(test)]
mod tests;
