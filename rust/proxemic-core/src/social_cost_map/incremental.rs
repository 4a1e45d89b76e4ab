//! The layered social cost map and its incremental updates: moving individuals re-evaluate only
//! the cells of their old and new boxes, and a change of the clock only the objects whose cost
//! changed.

use super::cost_model::{CostMode, SocialCosts, SpaceFunction, combined_cost};
use super::zone_sweep::{ZoneSweep, zone_reach, zone_spans};
use crate::error::CoreError;
use crate::map::grid::GridSpec;
use crate::map::sight::{FreeBits, Rect, Sight, SightScratch, Span, in_sight};
use crate::map::{CostGrid, polygon_cells};
use crate::math::Vec2;

/// The layered social cost map of one robot footprint.
#[derive(Clone, Debug)]
pub struct SocialMap {
    costs: SocialCosts,
    static_grid: CostGrid,
    /// Per-cell factor from people (1.0 where nobody contributes; infinity = intimate).
    people: Vec<f64>,
    /// Per-cell factor from objects (1.0 outside every interaction space).
    objects: Vec<f64>,
    combined: CostGrid,
    pub(super) object_cells: Vec<Vec<u32>>,
    object_factor: Vec<f64>,
    prev: Vec<(Rect, [f64; 8])>,
    touched: usize,
    /// Scratch: cells being re-evaluated.
    pub(super) mark: Vec<bool>,
    /// Zones mode with quadratic individuals: per cell, how many individuals put it in their
    /// intimate, personal and social zone; and each individual's last contribution.
    pub(super) counts: Vec<[u16; 3]>,
    pub(super) counted: Vec<Option<Contribution>>,
    /// The static layer's free cells and the scratch of [`in_sight`].
    free_bits: FreeBits,
    sight: SightScratch,
    /// The last factor [`SocialMap::combine`] encoded (its bits) and its code.
    last_code: (u64, u8),
}

/// What one individual added to the zone counts: its quadratic form, zone scale and box, the
/// spans of the box's rows that can lie in its social zone and the cells of the box in sight of
/// it (kept, so taking the contribution back costs no search).
#[derive(Clone, Debug)]
pub(super) struct Contribution {
    pub(super) quad: [f64; 8],
    pub(super) zone_scale: f64,
    pub(super) rect: Rect,
    pub(super) spans: Vec<Span>,
    pub(super) open: Sight,
}

impl Contribution {
    /// Same individual in the same place (the sight mask follows from these).
    pub(super) fn same(&self, quad: &[f64; 8], zone_scale: f64, rect: Rect) -> bool {
        self.quad == *quad && self.zone_scale == zone_scale && self.rect == rect
    }

    /// The zone sweep of the whole box.
    pub(super) fn sweep<'a>(&'a self, spec: &'a GridSpec, costs: &'a SocialCosts) -> ZoneSweep<'a> {
        let Self { ref quad, zone_scale, rect, ref spans, ref open } = *self;
        ZoneSweep { spec, costs, quad, zone_scale, full: rect, open, spans, rect }
    }
}

impl SocialMap {
    /// A social map over `static_grid` (the inflated static map) with the interaction-space
    /// polygons of the objects (world coordinates; an empty polygon for objects without one).
    pub fn new(static_grid: CostGrid, object_polygons: &[Vec<Vec2>], costs: SocialCosts) -> Self {
        let n = static_grid.spec.len();
        let object_cells: Vec<Vec<u32>> = object_polygons
            .iter()
            .map(|poly| polygon_cells(&static_grid.spec, poly, costs.object_margin))
            .collect();
        let m = object_cells.len();
        let free_bits = FreeBits::of(&static_grid);
        SocialMap {
            costs,
            combined: static_grid.clone(),
            static_grid,
            people: vec![1.0; n],
            objects: vec![1.0; n],
            object_cells,
            object_factor: vec![1.0; m],
            prev: Vec::new(),
            touched: 0,
            mark: Vec::new(),
            counts: Vec::new(),
            counted: Vec::new(),
            free_bits,
            sight: SightScratch::default(),
            last_code: (1f64.to_bits(), costs.encode(1.0)),
        }
    }

    /// The cost parameters.
    pub fn costs(&self) -> &SocialCosts {
        &self.costs
    }

    /// The combined cost grid (what the social A* searches with weight [`SocialCosts::weight`]).
    pub fn grid(&self) -> &CostGrid {
        &self.combined
    }

    /// The static layer.
    pub fn static_layer(&self) -> &CostGrid {
        &self.static_grid
    }

    /// The people layer as factors (infinity marks intimate zones).
    pub fn people_layer(&self) -> &[f64] {
        &self.people
    }

    /// The object layer as factors.
    pub fn object_layer(&self) -> &[f64] {
        &self.objects
    }

    /// Number of cells re-evaluated by the last update (a measure of incrementality).
    pub fn cells_touched(&self) -> usize {
        self.touched
    }

    /// Sets the objects' factors R(t) (one per object polygon, in the polygons' order; finite);
    /// only changed objects are redrawn.
    ///
    /// # Errors
    /// [`CoreError::Input`] when `factors` does not hold one factor per object polygon or a factor
    /// is not finite; the map is then unchanged.
    pub fn set_object_factors(&mut self, factors: &[f64]) -> Result<(), CoreError> {
        self.check_object_factors(factors)?;
        let changed: Vec<usize> =
            (0..factors.len()).filter(|&k| self.object_factor[k] != factors[k]).collect();
        self.touched = 0;
        if changed.is_empty() {
            return Ok(());
        }
        for &k in &changed {
            self.object_factor[k] = factors[k];
        }
        // Cells of changed objects (marked, each once): recompute as the max over every object
        // covering them, in the objects' order.
        self.mark.resize(self.static_grid.spec.len(), false);
        let mut dirty: Vec<u32> = Vec::new();
        for &k in &changed {
            for &c in &self.object_cells[k] {
                if !self.mark[c as usize] {
                    self.mark[c as usize] = true;
                    self.objects[c as usize] = 1.0;
                    dirty.push(c);
                }
            }
        }
        for (k, cells) in self.object_cells.iter().enumerate() {
            let f = self.object_factor[k];
            for &c in cells {
                if self.mark[c as usize] && f > self.objects[c as usize] {
                    self.objects[c as usize] = f;
                }
            }
        }
        for &c in &dirty {
            self.combine(c as usize);
            self.mark[c as usize] = false;
        }
        self.touched = dirty.len();
        Ok(())
    }

    /// The error of [`SocialMap::set_object_factors`] for `factors`, if any.
    fn check_object_factors(&self, factors: &[f64]) -> Result<(), CoreError> {
        if factors.len() != self.object_factor.len() {
            return Err(CoreError::input(
                "object_factors",
                format!("one factor per object polygon of the map ({} polygons)", self.object_factor.len()),
                format!("{} factors", factors.len()),
            ));
        }
        if let Some((k, f)) = factors.iter().enumerate().find(|(_, f)| !f.is_finite()) {
            return Err(CoreError::input(format!("object_factors[{k}]"), "a finite factor", f.to_string()));
        }
        Ok(())
    }

    /// Replaces the whole people layer with `factors` (one per cell, row-major; infinity marks a
    /// forbidden cell), e.g. the density contours of [`crate::social_cost_map::DensityLayer`] (the `calderita` planner),
    /// and recombines the cells whose factor changed. The incremental bookkeeping of
    /// [`SocialMap::update_people`] is dropped: a map is fed by one of the two, not both.
    ///
    /// # Errors
    /// [`CoreError::Input`] when `factors` does not hold one factor per cell; the map is then
    /// unchanged.
    pub fn set_people_factors(&mut self, factors: &[f64]) -> Result<(), CoreError> {
        self.set_people_factors_over(factors, 0..factors.len())
    }

    /// As [`SocialMap::set_people_factors`], for the listed `cells` only (row-major indices into
    /// `factors`, one factor per cell; repeats allowed): what [`crate::social_cost_map::DensityLayer`] changed in an
    /// update.
    ///
    /// # Errors
    /// [`CoreError::Input`] when `factors` does not hold one factor per cell or a cell is out of
    /// the grid; the map is then unchanged.
    pub fn set_people_factors_at(&mut self, factors: &[f64], cells: &[usize]) -> Result<(), CoreError> {
        if let Some(&c) = cells.iter().find(|&&c| c >= self.people.len()) {
            return Err(CoreError::input(
                "cells",
                format!("row-major cell indices below {}", self.people.len()),
                c.to_string(),
            ));
        }
        self.set_people_factors_over(factors, cells.iter().copied())
    }

    /// Sets the people factor of each of `cells` (all in range) from `factors` and recombines
    /// the cells whose factor changed (bit for bit): the combined grid always holds the layers'
    /// combination, so only those need it again.
    fn set_people_factors_over(
        &mut self,
        factors: &[f64],
        cells: impl Iterator<Item = usize>,
    ) -> Result<(), CoreError> {
        if factors.len() != self.people.len() {
            return Err(CoreError::input(
                "factors",
                format!("one people factor per cell of the map ({} cells)", self.people.len()),
                format!("{} factors", factors.len()),
            ));
        }
        self.counts.clear();
        self.counted.clear();
        self.prev.clear();
        let mut touched = 0;
        for c in cells {
            let f = factors[c];
            if self.people[c].to_bits() != f.to_bits() {
                self.people[c] = f;
                self.combine(c);
                touched += 1;
            }
        }
        self.touched = touched;
        Ok(())
    }

    pub(super) fn rect_of<S: SpaceFunction>(&self, s: &S) -> Option<Rect> {
        let spec = &self.static_grid.spec;
        let [x0, y0, x1, y1] = s.bounds();
        if !(x0.is_finite() && y0.is_finite() && x1.is_finite() && y1.is_finite()) {
            return None;
        }
        let res = spec.resolution;
        let cx = |v: f64| ((v - spec.origin.x) / res).floor();
        let cy = |v: f64| ((v - spec.origin.y) / res).floor();
        let (a0, a1, b0, b1) = (cx(x0), cx(x1), cy(y0), cy(y1));
        if a1 < 0.0 || b1 < 0.0 || a0 >= spec.width as f64 || b0 >= spec.height as f64 {
            return None;
        }
        let clampx = |v: f64| (v.max(0.0) as usize).min(spec.width - 1);
        let clampy = |v: f64| (v.max(0.0) as usize).min(spec.height - 1);
        Some((clampx(a0), clampy(b0), clampx(a1), clampy(b1)))
    }

    /// Updates the people layer for the current individuals. Individuals whose fingerprint is
    /// unchanged since the last call cost nothing; otherwise the cells of the changed
    /// individuals' old and new boxes are cleared and every individual overlapping them is
    /// splatted (max) over the overlap. Individuals with non-finite state are ignored.
    pub fn update_people<S: SpaceFunction>(&mut self, individuals: &[S]) {
        if self.costs.mode == CostMode::Zones && individuals.iter().all(|s| s.quadratic().is_some()) {
            self.update_people_counted(individuals);
            return;
        }
        // Leaving the counting path: its counts no longer describe the layer.
        self.counts.clear();
        self.counted.clear();
        let rects: Vec<Option<Rect>> = individuals.iter().map(|s| self.rect_of(s)).collect();
        let same_count = self.prev.len() == individuals.len();
        let mut dirty: Vec<Rect> = Vec::new();
        if same_count {
            for (k, s) in individuals.iter().enumerate() {
                if self.prev[k].1 != s.fingerprint() {
                    // An individual's old and new boxes mostly overlap: take their union.
                    let old = self.prev[k].0;
                    match rects[k] {
                        Some(r) if old.0 <= old.2 => {
                            dirty.push((old.0.min(r.0), old.1.min(r.1), old.2.max(r.2), old.3.max(r.3)))
                        }
                        Some(r) => dirty.push(r),
                        None => dirty.push(old),
                    }
                }
            }
        } else {
            dirty.extend(self.prev.iter().map(|p| p.0));
            dirty.extend(rects.iter().flatten().copied());
        }
        let empty = (usize::MAX, usize::MAX, 0, 0);
        self.prev =
            individuals.iter().zip(&rects).map(|(s, r)| (r.unwrap_or(empty), s.fingerprint())).collect();
        dirty.retain(|&(x0, y0, x1, y1)| x0 <= x1 && y0 <= y1);
        if dirty.is_empty() {
            self.touched = 0;
            return;
        }
        let spec = self.static_grid.spec;
        // 1. Mark and clear the dirty cells (all of them when the boxes cover most of the grid).
        self.mark.resize(spec.len(), false);
        let area: usize = dirty.iter().map(|&(x0, y0, x1, y1)| (x1 - x0 + 1) * (y1 - y0 + 1)).sum();
        let whole = area >= spec.len();
        let mut cells: Vec<u32> = Vec::new();
        if whole {
            self.mark.fill(true);
            self.people.fill(1.0);
            dirty = vec![(0, 0, spec.width - 1, spec.height - 1)];
        } else {
            for &(x0, y0, x1, y1) in &dirty {
                for iy in y0..=y1 {
                    for ix in x0..=x1 {
                        let idx = spec.index(ix, iy);
                        if !self.mark[idx] {
                            self.mark[idx] = true;
                            self.people[idx] = 1.0;
                            cells.push(idx as u32);
                        }
                    }
                }
            }
        }
        // 2. Splat every individual over the parts of its box inside the dirty rectangles (every
        //    cell there was cleared, so overlapping rectangles only repeat an idempotent max).
        for (k, ind) in individuals.iter().enumerate() {
            let Some((a0, b0, a1, b1)) = rects[k] else { continue };
            for &(x0, y0, x1, y1) in &dirty {
                let (lo_x, lo_y, hi_x, hi_y) = (a0.max(x0), b0.max(y0), a1.min(x1), b1.min(y1));
                if lo_x > hi_x || lo_y > hi_y {
                    continue;
                }
                let part = (lo_x, lo_y, hi_x, hi_y);
                match (ind.quadratic(), self.costs.mode) {
                    (Some(qf), CostMode::Zones) => {
                        self.splat_zones(&qf, ind.zone_scale(), (a0, b0, a1, b1), part)
                    }
                    _ => {
                        let full = (a0, b0, a1, b1);
                        let open = ind.centre().map(|c| {
                            in_sight(
                                &self.static_grid,
                                &self.free_bits,
                                c,
                                full,
                                f64::INFINITY,
                                None,
                                &mut self.sight,
                            )
                        });
                        for iy in lo_y..=hi_y {
                            let row = spec.index(0, iy);
                            let sight = open.as_ref().and_then(|o| o.row(iy - b0));
                            for ix in lo_x..=hi_x {
                                let x = ix - a0;
                                if sight.is_some_and(|b| b[x / 64] >> (x % 64) & 1 == 0) {
                                    continue;
                                }
                                let f = self.costs.factor(ind, spec.center(ix, iy));
                                if f > self.people[row + ix] {
                                    self.people[row + ix] = f;
                                }
                            }
                        }
                    }
                }
            }
        }
        // 3. Combine and unmark.
        if whole {
            for c in 0..spec.len() {
                self.combine(c);
            }
            self.mark.fill(false);
            self.touched = spec.len();
        } else {
            for &c in &cells {
                self.combine(c as usize);
                self.mark[c as usize] = false;
            }
            self.touched = cells.len();
        }
    }

    /// Zones mode, quadratic individuals: the layer is kept as per-cell zone counts, so a moving
    /// individual only subtracts its old contribution and adds its new one (two sweeps of its
    /// own box), whoever else overlaps it. The factor of a touched cell is the highest zone with a
    /// non-zero count.
    fn update_people_counted<S: SpaceFunction>(&mut self, individuals: &[S]) {
        let spec = self.static_grid.spec;
        if self.counts.len() != spec.len() {
            // (Re)start counting from an empty layer.
            self.counts = vec![[0; 3]; spec.len()];
            self.counted.clear();
            self.people.fill(1.0);
            for c in 0..spec.len() {
                self.combine(c);
            }
        }
        self.mark.resize(spec.len(), false);
        let mut touched: Vec<u32> = Vec::new();
        // Match the new individuals with the counted contributions by content, not by index:
        // when someone joins or leaves the list, the others keep their contributions.
        let new: Vec<Option<([f64; 8], f64, Rect)>> =
            individuals.iter().map(|s| Some((s.quadratic()?, s.zone_scale(), self.rect_of(s)?))).collect();
        let mut old = std::mem::take(&mut self.counted);
        let mut next: Vec<Option<Contribution>> = Vec::with_capacity(new.len());
        for n in &new {
            let Some((quad, zone_scale, rect)) = *n else {
                next.push(None);
                continue;
            };
            let kept = old.iter_mut().find(|c| c.as_ref().is_some_and(|c| c.same(&quad, zone_scale, rect)));
            next.push(kept.and_then(Option::take));
        }
        for c in old.into_iter().flatten() {
            self.count_zones(&c, -1, &mut touched);
        }
        for (k, n) in new.iter().enumerate() {
            if let (None, Some((quad, zone_scale, rect))) = (&next[k], *n) {
                let (spans, open) = self.zone_sight(&quad, zone_scale, rect);
                let c = Contribution { quad, zone_scale, rect, spans, open };
                self.count_zones(&c, 1, &mut touched);
                next[k] = Some(c);
            }
        }
        self.counted = next;
        let c = self.costs;
        for &cell in &touched {
            let i = cell as usize;
            let [ci, cp, cs] = self.counts[i];
            self.people[i] = if ci > 0 {
                f64::INFINITY
            } else if cp > 0 {
                c.personal_cost
            } else if cs > 0 {
                c.social_cost
            } else {
                c.public_cost.max(1.0)
            };
            self.combine(i);
            self.mark[i] = false;
        }
        self.touched = touched.len();
        // Keep the max-path bookkeeping consistent for a later switch to it.
        self.prev.clear();
    }

    /// Adds `delta` to the zone counts of the cells of one contribution.
    fn count_zones(&mut self, c: &Contribution, delta: i32, touched: &mut Vec<u32>) {
        let (counts, mark) = (&mut self.counts, &mut self.mark);
        c.sweep(&self.static_grid.spec, &self.costs).cells(|idx, zone| {
            let slot = &mut counts[idx][zone];
            *slot = (i32::from(*slot) + delta).clamp(0, i32::from(u16::MAX)) as u16;
            if !mark[idx] {
                mark[idx] = true;
                touched.push(idx as u32);
            }
        });
    }

    /// The spans of the rows of `rect` (an individual's whole box) that can lie in the social
    /// zone of the quadratic-form individual `quad` ([`zone_spans`]), and which cells of the box
    /// are in sight of it, decided for the spans' cells within its social zone's reach
    /// ([`in_sight`], [`zone_reach`]).
    fn zone_sight(&mut self, quad: &[f64; 8], zone_scale: f64, rect: Rect) -> (Vec<Span>, Sight) {
        let spec = &self.static_grid.spec;
        let spans = zone_spans(spec, &self.costs, quad, zone_scale, rect);
        let reach = zone_reach(&self.costs, quad, zone_scale, spec.resolution);
        let open = in_sight(
            &self.static_grid,
            &self.free_bits,
            Vec2::new(quad[0], quad[1]),
            rect,
            reach,
            Some(&spans),
            &mut self.sight,
        );
        (spans, open)
    }

    /// Zone costs of one quadratic-form individual over a cell box (max with what is there).
    fn splat_zones(&mut self, q: &[f64; 8], zone_scale: f64, full: Rect, rect: Rect) {
        let c = self.costs;
        let factors = [f64::INFINITY, c.personal_cost, c.social_cost];
        let (spans, open) = self.zone_sight(q, zone_scale, full);
        let people = &mut self.people;
        let spec = &self.static_grid.spec;
        ZoneSweep { spec, costs: &c, quad: q, zone_scale, full, open: &open, spans: &spans, rect }.cells(
            |idx, zone| {
                if factors[zone] > people[idx] {
                    people[idx] = factors[zone];
                }
            },
        );
    }

    #[inline(always)]
    fn combine(&mut self, idx: usize) {
        self.combined.cost[idx] = combined_cost(
            &self.costs,
            self.static_grid.cost[idx],
            self.people[idx],
            self.objects[idx],
            &mut self.last_code,
        );
    }

    /// Rebuilds every layer from scratch (for tests and benchmarks of the full rebuild).
    ///
    /// # Errors
    /// As [`SocialMap::set_object_factors`], checked first: the map is then unchanged.
    pub fn rebuild<S: SpaceFunction>(
        &mut self,
        individuals: &[S],
        object_factors: &[f64],
    ) -> Result<(), CoreError> {
        self.check_object_factors(object_factors)?;
        // The layer starts empty, so the counting path can start from zero counts directly.
        self.counts.clear();
        self.counts.resize(self.static_grid.spec.len(), [0; 3]);
        self.counted.clear();
        self.people.fill(1.0);
        self.objects.fill(1.0);
        self.object_factor.fill(f64::NAN);
        self.prev.clear();
        self.combined = self.static_grid.clone();
        self.set_object_factors(object_factors)?; // checked above: cannot fail here
        // Fewer individuals than a count can hold: the counts never reach the clamp of
        // `count_zones`, so they can be summed from the zones' runs.
        if self.costs.mode == CostMode::Zones
            && individuals.len() < usize::from(u16::MAX)
            && individuals.iter().all(|s| s.quadratic().is_some())
        {
            self.rebuild_counted(individuals);
        } else {
            self.update_people(individuals);
        }
        Ok(())
    }

    /// The counting path's update from empty counts (what [`SocialMap::update_people_counted`]
    /// does after a reset, with the same counts, contributions, layer and grid), by runs: each
    /// run of cells of one zone in a row adds one at its first cell and takes one back after its
    /// last (wrapping `u16` differences, exact as no count reaches `u16::MAX`), and one pass
    /// over the grid sums each row's differences into the counts and sets the touched cells'
    /// factors, in row order.
    fn rebuild_counted<S: SpaceFunction>(&mut self, individuals: &[S]) {
        let spec = self.static_grid.spec;
        let mut counted = Vec::with_capacity(individuals.len());
        for s in individuals {
            let Some((quad, zone_scale, rect)) =
                s.quadratic().and_then(|q| Some((q, s.zone_scale(), self.rect_of(s)?)))
            else {
                counted.push(None);
                continue;
            };
            let (spans, open) = self.zone_sight(&quad, zone_scale, rect);
            let c = Contribution { quad, zone_scale, rect, spans, open };
            let counts = &mut self.counts;
            c.sweep(&spec, &self.costs).runs(|iy, x0, x1, zone| {
                let row = spec.index(0, iy);
                counts[row + x0][zone] = counts[row + x0][zone].wrapping_add(1);
                if x1 + 1 < spec.width {
                    counts[row + x1 + 1][zone] = counts[row + x1 + 1][zone].wrapping_sub(1);
                }
            });
            counted.push(Some(c));
        }
        self.counted = counted;
        // The touched cells' factors and codes as `combine` sets them (the code of a factor
        // kept for the run of cells that share it), over the layers' rows.
        let c = self.costs;
        let mut touched = 0;
        let mut last = self.last_code;
        let (counts, people) = (&mut self.counts[..], &mut self.people[..]);
        let (objects, fixed, combined) =
            (&self.objects[..], &self.static_grid.cost[..], &mut self.combined.cost[..]);
        let rows = counts.chunks_exact_mut(spec.width).zip(people.chunks_exact_mut(spec.width));
        for (iy, (counts, people)) in rows.enumerate() {
            let row = spec.index(0, iy);
            let mut sum = [0u16; 3];
            for (x, (count, person)) in counts.iter_mut().zip(people.iter_mut()).enumerate() {
                let d = *count;
                sum = [sum[0].wrapping_add(d[0]), sum[1].wrapping_add(d[1]), sum[2].wrapping_add(d[2])];
                *count = sum;
                if sum != [0; 3] {
                    let [ci, cp, _] = sum;
                    *person = if ci > 0 {
                        f64::INFINITY
                    } else if cp > 0 {
                        c.personal_cost
                    } else {
                        c.social_cost
                    };
                    let i = row + x;
                    combined[i] = combined_cost(&c, fixed[i], *person, objects[i], &mut last);
                    touched += 1;
                }
            }
        }
        self.last_code = last;
        self.mark.resize(spec.len(), false);
        self.touched = touched;
    }
}
