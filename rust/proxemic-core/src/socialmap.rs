//! The social cost map: layers on the map grid that the social planner searches.
//!
//! Layers (Calderita et al. §5.2.1-5.2.2, with the cost values of the paper as defaults):
//! - **static**: the inflated static map; lethal cells stay lethal;
//! - **people**: for every individual (a person, a group treated as one individual, or a robot
//!   that has joined an interaction), its intimate zone is forbidden (lethal), its personal zone
//!   costs 4.0, its social zone 2.0, and the public zone 1.0 (the free-space cost); or, in the
//!   continuous mode, the cost is `1 + gain * f(p)` with `f` the individual's personal-space
//!   function;
//! - **objects**: the cells of each object's interaction space cost R(t), the object's
//!   time-dependent cost from the agenda (1.5 idle, up to 3.5 during an activity);
//! - **combined**: the maximum of the layers, as the `u8` cost grid the A* searches.
//!
//! Costs are traversal *factors* (a path's cost is the sum of the factors of the cells it
//! enters times the step lengths, as in Calderita's Dijkstra). The A* grid stores a factor `f`
//! as `c = round((f - 1) / (max_factor - 1) * 252)` and searches with weight
//! `w = max_factor - 1`, so that its edge cost `len * (1 + w * c / 252)` is `len * f` up to the
//! 1/252 quantisation.
//!
//! Zones: a point's zone around an individual is decided by its *zone distance*, the distance
//! that the individual's space function assigns to the point (the Euclidean distance for a
//! symmetric function; stretched in front and shrunk behind for asymmetric ones), compared with
//! Hall's radii. Distances are centre to centre.
//!
//! Updates are incremental: moving individuals re-evaluate only the cells of their old and new
//! bounding boxes, and a change of the clock re-evaluates only the objects whose cost changed.

use crate::error::CoreError;
use crate::map::grid::GridSpec;
use crate::map::sight::{FreeBits, OpenRuns, Rect, Sight, SightScratch, Span, in_sight, open_span};
use crate::map::{CostGrid, INSCRIBED, LETHAL, polygon_cells};
use crate::math::Vec2;

mod density;
pub use density::{DensityLayer, density_factor, density_layer};

/// What the social map needs from an individual's personal-space model.
///
/// The personal-space value is `exp(-q(p))`. The *zone distance* of a point is
/// `zone_scale * sqrt(2 q(p))`: for a symmetric Gaussian of standard deviation `zone_scale` it is
/// the Euclidean distance; for asymmetric functions it stretches where the function is wider.
/// Zones are classified by comparing `q` with `r^2 / (2 zone_scale^2)`, without exp or sqrt.
pub trait SpaceFunction {
    /// The exponent `q(p) >= 0` of the personal-space value `exp(-q)` at `p`.
    fn exponent(&self, p: Vec2) -> f64;
    /// The length (metres) that turns `sqrt(2 q)` into a zone distance.
    fn zone_scale(&self) -> f64;
    /// Axis-aligned box `[xmin, ymin, xmax, ymax]` (metres) outside which the individual adds no
    /// cost; bounds the cells it touches.
    fn bounds(&self) -> [f64; 4];
    /// A fingerprint of the individual's state; equal fingerprints mean identical contributions.
    fn fingerprint(&self) -> [f64; 8];
    /// The exponent as a quadrant-wise quadratic form, if it is one: `(x, y, cos, sin, front,
    /// rear, right, left)` with `q = k_s d_sag^2 + k_f d_fro^2` (see
    /// [`crate::proxemics::Placed::coefficients`]); lets the map sweep rows incrementally.
    fn quadratic(&self) -> Option<[f64; 8]> {
        None
    }
    /// Where the individual stands (metres), if known: its zones are then limited to the cells in
    /// sight of it (see `crate::map::sight::in_sight`). `None` (the default) lets them through walls.
    fn centre(&self) -> Option<Vec2> {
        None
    }
}

/// How people's costs are computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CostMode {
    /// Hall zones with discrete costs (Calderita §5.2.1).
    Zones,
    /// Cost `1 + gain * f(p)` with `f` the personal-space value; the intimate zone stays lethal.
    Continuous {
        /// Gain on the personal-space value; default 3.0 (so the centre costs 4.0, like the
        /// personal zone).
        gain: f64,
    },
}

/// Parameters of the social cost map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SocialCosts {
    /// Intimate radius (metres, centre to centre); forbidden. Default 0.45.
    pub intimate: f64,
    /// Personal radius (metres). Default 1.2.
    pub personal: f64,
    /// Social radius (metres). Default 3.6.
    pub social: f64,
    /// Factor inside the personal zone. Default 4.0 (Calderita).
    pub personal_cost: f64,
    /// Factor inside the social zone. Default 2.0 (Calderita).
    pub social_cost: f64,
    /// Factor in the public zone and free space. Default 1.0 (Calderita).
    pub public_cost: f64,
    /// Zones or continuous costs. Default zones.
    pub mode: CostMode,
    /// Largest representable factor (the A* weight is `max_factor - 1`). Default 5.0.
    pub max_factor: f64,
    /// Object interaction spaces are drawn this much wider on the map (m, `>= 0`), so a path
    /// planned along a space's edge keeps the robot's centre out of it. Default 0; the social
    /// planner sets the robot's radius.
    pub object_margin: f64,
}

impl Default for SocialCosts {
    fn default() -> Self {
        SocialCosts {
            intimate: 0.45,
            personal: 1.2,
            social: 3.6,
            personal_cost: 4.0,
            social_cost: 2.0,
            public_cost: 1.0,
            mode: CostMode::Zones,
            max_factor: 5.0,
            object_margin: 0.0,
        }
    }
}

impl SocialCosts {
    /// The A* weight that turns stored costs back into factors.
    pub fn weight(&self) -> f64 {
        self.max_factor - 1.0
    }

    /// Factor of a point for one individual (f64::INFINITY for the forbidden intimate zone).
    pub fn factor<S: SpaceFunction>(&self, s: &S, p: Vec2) -> f64 {
        let q = s.exponent(p);
        if q.is_nan() {
            return self.public_cost;
        }
        // zone distance d = z sqrt(2 q)  <=>  d^2 = 2 z^2 q
        let z = s.zone_scale();
        let d2 = 2.0 * z * z * q;
        if d2 < self.intimate * self.intimate {
            return f64::INFINITY;
        }
        match self.mode {
            CostMode::Zones => {
                if d2 < self.personal * self.personal {
                    self.personal_cost
                } else if d2 < self.social * self.social {
                    self.social_cost
                } else {
                    self.public_cost
                }
            }
            CostMode::Continuous { gain } => 1.0 + gain * (-q).exp(),
        }
    }

    /// The zone distance (metres) of a point for one individual (see [`SpaceFunction`]).
    pub fn zone_distance<S: SpaceFunction>(s: &S, p: Vec2) -> f64 {
        s.zone_scale() * (2.0 * s.exponent(p)).max(0.0).sqrt()
    }

    /// Stored `u8` cost of a factor (`LETHAL` for infinity).
    pub fn encode(&self, factor: f64) -> u8 {
        if factor.is_infinite() || factor.is_nan() {
            return LETHAL;
        }
        if factor <= 1.0 {
            return 0;
        }
        let c = ((factor - 1.0) * (252.0 / (self.max_factor - 1.0))).round();
        c.min(252.0) as u8
    }
}

/// What a zone sweep of one quadratic-form individual (see [`SpaceFunction::quadratic`]) needs
/// along a row: the quadrants' coefficients, the zones' thresholds on the exponent and the
/// axis distances' steps from one cell to the next.
struct ZoneScan {
    /// `1 / 2σ²` ahead, behind, to the right and to the left.
    k: [f64; 4],
    /// The exponent's thresholds of the intimate, personal and social zones.
    q: [f64; 3],
    /// The sagittal and frontal distances' steps per cell along a row (m).
    step: (f64, f64),
}

impl ZoneScan {
    /// The zone of a cell at sagittal and frontal distances `sag`, `fro` (0 intimate,
    /// 1 personal, 2 social, [`ZoneScan::NONE`] outside the social zone).
    #[inline]
    fn zone(&self, sag: f64, fro: f64) -> usize {
        let [kf, kr, kri, kl] = self.k;
        let ks = if sag >= 0.0 { kf } else { kr };
        let kq = if fro >= 0.0 { kri } else { kl };
        let e = ks * sag * sag + kq * fro * fro;
        let [qi, qp, qs] = self.q;
        if e < qs {
            if e < qi {
                0
            } else if e < qp {
                1
            } else {
                2
            }
        } else {
            Self::NONE
        }
    }

    /// The zone of a cell outside the social zone or out of sight.
    const NONE: usize = 3;
}

/// The exponent's thresholds of the intimate, personal and social zones of an individual with
/// zone scale `zone_scale`.
fn zone_thresholds(costs: &SocialCosts, zone_scale: f64) -> [f64; 3] {
    let two_z2 = 2.0 * zone_scale * zone_scale;
    [
        costs.intimate * costs.intimate / two_z2,
        costs.personal * costs.personal / two_z2,
        costs.social * costs.social / two_z2,
    ]
}

/// The spans of the rows of `full`, in order, that can lie in the social zone of the
/// quadratic-form individual `quad` ([`ZoneRows::cells`] over the box's columns): a zone sweep
/// tests only their cells (those of a part of the box are the part's columns of them), and
/// [`in_sight`] needs to decide only theirs.
fn zone_spans(
    spec: &GridSpec,
    costs: &SocialCosts,
    quad: &[f64; 8],
    zone_scale: f64,
    full: Rect,
) -> Vec<Span> {
    let (a0, b0, a1, b1) = full;
    let rows = ZoneRows::new(quad, zone_thresholds(costs, zone_scale)[2]);
    (b0..=b1).map(|iy| rows.cells(spec, quad[0], spec.center(a0, iy).y - quad[1], (a0, a1))).collect()
}

/// The zone sweep of one quadratic-form individual (see [`SpaceFunction::quadratic`]) over a
/// box of cells. Zones are decided by comparing the exponent with the zone radii's thresholds,
/// without exp or sqrt.
struct ZoneSweep<'a> {
    spec: &'a GridSpec,
    costs: &'a SocialCosts,
    /// The individual's quadratic form.
    quad: &'a [f64; 8],
    zone_scale: f64,
    /// The individual's whole box.
    full: Rect,
    /// Which cells of `full` are in sight of the individual (from [`in_sight`]: zones do not
    /// pass through walls).
    open: &'a Sight,
    /// The cells of each row of `full` that can lie in the social zone (from [`zone_spans`]).
    spans: &'a [Span],
    /// The part of the box to visit.
    rect: Rect,
}

impl ZoneSweep<'_> {
    /// Calls `row(scan, iy, lo, hi, sag, fro, sight)` for every row `iy` of `rect` with cells
    /// that can lie in the social zone and in sight, rows in order: the cells `lo ..= hi` are to
    /// be tested (with [`ZoneScan::zone`] and bit `ix - full.0` of `sight`), `sag` and `fro` are
    /// the axis distances at `lo`, and the next cell's are `+ scan.step` (the same additions as
    /// a sweep from the rect's first cell, so every cell sees the same values).
    #[inline]
    fn rows(&self, mut row: impl FnMut(&ZoneScan, usize, usize, usize, f64, f64, Option<&[u64]>)) {
        let Self { spec, costs, quad, zone_scale, full, open, spans, rect } = *self;
        let [cx, cy, cos, sin, kf, kr, kri, kl] = *quad;
        let (a0, b0, a1, b1) = rect;
        let (f0x, f0y) = (full.0, full.1);
        let res = spec.resolution;
        let scan = ZoneScan {
            k: [kf, kr, kri, kl],
            q: zone_thresholds(costs, zone_scale),
            step: (cos * res, sin * res),
        };
        // Up to `BATCH` rows at a time: their axis distances are brought from `a0` to their
        // first tested cell together (independent chains of additions, each row's its own).
        const BATCH: usize = 4;
        let mut batch = [(0usize, 0usize, 0usize); BATCH];
        let (mut sag, mut fro) = ([0.0f64; BATCH], [0.0f64; BATCH]);
        let mut n = 0;
        for iy in b0..=b1 {
            let p0 = spec.center(a0, iy);
            let (dx, dy) = (p0.x - cx, p0.y - cy);
            let sight = open.row(iy - f0y);
            // Only the cells of the row that can be in the social zone and in sight are tested.
            if let Some((lo, hi)) = spans[iy - f0y]
                .and_then(|(lo, hi)| {
                    let (lo, hi) = (lo.max(a0), hi.min(a1));
                    (lo <= hi).then_some((lo, hi))
                })
                .and_then(|(lo, hi)| sight.map_or(Some((lo, hi)), |b| open_span(b, lo - f0x, hi - f0x)))
            {
                let (lo, hi) = if sight.is_some() { (lo + f0x, hi + f0x) } else { (lo, hi) };
                batch[n] = (iy, lo, hi);
                sag[n] = cos * dx + sin * dy;
                fro[n] = sin * dx - cos * dy;
                n += 1;
            }
            if n == BATCH || (iy == b1 && n > 0) {
                // The same additions as a sweep from `a0`: the cells from `lo` on see the same
                // values. The steps all rows of the batch take go side by side.
                let common = batch[..n].iter().map(|&(_, lo, _)| lo - a0).min().unwrap_or(0);
                for _ in 0..common {
                    for k in 0..BATCH {
                        sag[k] += scan.step.0;
                        fro[k] += scan.step.1;
                    }
                }
                for (k, &(iy, lo, hi)) in batch[..n].iter().enumerate() {
                    for _ in a0 + common..lo {
                        sag[k] += scan.step.0;
                        fro[k] += scan.step.1;
                    }
                    row(&scan, iy, lo, hi, sag[k], fro[k], open.row(iy - f0y));
                }
                n = 0;
            }
        }
    }

    /// Calls `f(iy, ix, zone)` for every tested cell `ix` of row `iy` in sight (zone
    /// [`ZoneScan::NONE`] outside the social zone), rows in order and cells from left to right,
    /// each cell decided by [`ZoneScan::zone`]; and `f(iy, e + 1, ZoneScan::NONE)` after each
    /// run `..= e` of cells in sight. The cells out of sight are stepped over.
    #[inline(always)]
    fn sweep(&self, mut f: impl FnMut(usize, usize, usize)) {
        let f0x = self.full.0;
        self.rows(|scan, iy, lo, hi, mut sag, mut fro, sight| {
            // The cell `sag` and `fro` are at.
            let mut at = lo;
            for (s, e) in OpenRuns::new(sight, f0x, lo, hi) {
                for _ in at..s {
                    sag += scan.step.0;
                    fro += scan.step.1;
                }
                for ix in s..=e {
                    f(iy, ix, scan.zone(sag, fro));
                    sag += scan.step.0;
                    fro += scan.step.1;
                }
                f(iy, e + 1, ZoneScan::NONE);
                at = e + 1;
            }
        });
    }

    /// Calls `f(cell index, zone)` (0 intimate, 1 personal, 2 social) for every cell of `rect`
    /// inside the social zone and in sight.
    fn cells(&self, mut f: impl FnMut(usize, usize)) {
        let spec = self.spec;
        self.sweep(|iy, ix, zone| {
            if zone != ZoneScan::NONE {
                f(spec.index(ix, iy), zone);
            }
        });
    }

    /// Calls `f(row, x0, x1, zone)` (zone 0 intimate, 1 personal, 2 social) for every run of
    /// consecutive cells `x0 ..= x1` of a row of `rect` that lie in the same zone and in sight,
    /// rows in order and runs from left to right: the cells of [`ZoneSweep::cells`] (the runs
    /// only group the answers), for the rebuild, which counts by runs.
    fn runs(&self, mut f: impl FnMut(usize, usize, usize, usize)) {
        // The current run: its first cell and zone (every run of cells in sight ends in `NONE`).
        let (mut start, mut run) = (0, ZoneScan::NONE);
        self.sweep(|iy, ix, zone| {
            if zone != run {
                if run != ZoneScan::NONE {
                    f(iy, start, ix - 1, run);
                }
                (start, run) = (ix, zone);
            }
        });
    }
}

/// A cell's combined cost: its static cost where that is inscribed or lethal, else the code of
/// the larger of its people and object factors, at least its static cost. `last` holds the last
/// factor encoded and its code: neighbouring cells mostly share a factor, which is encoded once
/// per run.
#[inline]
fn combined_cost(costs: &SocialCosts, fixed: u8, people: f64, objects: f64, last: &mut (u64, u8)) -> u8 {
    if fixed >= INSCRIBED {
        fixed
    } else {
        let f = people.max(objects);
        if f.to_bits() != last.0 {
            *last = (f.to_bits(), costs.encode(f));
        }
        last.1.max(fixed)
    }
}

/// The rows of the social zone of a quadrant-wise quadratic form (see
/// [`SpaceFunction::quadratic`]): per quadrant, the constants that give the zone's part of a
/// row in a few operations (see [`ZoneRows::cells`]).
#[derive(Clone, Copy, Debug)]
struct ZoneRows {
    /// Per quadrant: `1 / 2a`, `b / dy`, the discriminant's `dy^2` coefficient and constant, and
    /// per half-plane `1 / k` and `o / dy` (see [`ZoneRows::cells`]).
    quarters: [[f64; 8]; 4],
    /// Whether every quadrant could be bounded (positive, finite coefficients).
    bounded: bool,
}

impl ZoneRows {
    /// The constants of `quad` for the social zone's threshold `qs`.
    ///
    /// Along a row `dy` metres above the centre, `sag = cos dx + sin dy` and
    /// `fro = sin dx - cos dy`, so the exponent of a quadrant is `a dx^2 + b dx + c` with
    /// `a = k_s cos^2 + k_f sin^2`, `b = 2 cos sin (k_s - k_f) dy`,
    /// `c = (k_s sin^2 + k_f cos^2) dy^2 - q`: its roots at `q = qs (1 + 1e-3)` bound the quadrant's
    /// ellipse on the row.
    fn new(quad: &[f64; 8], qs: f64) -> Self {
        let [_, _, cos, sin, kf, kr, kri, kl] = *quad;
        let q = qs * (1.0 + 1e-3);
        let mut quarters = [[0.0; 8]; 4];
        let mut bounded = q.is_finite();
        for (i, (ks, s_sag, kq, s_fro)) in
            [(kf, 1.0, kri, 1.0), (kf, 1.0, kl, -1.0), (kr, -1.0, kri, 1.0), (kr, -1.0, kl, -1.0)]
                .into_iter()
                .enumerate()
        {
            let a = ks * cos * cos + kq * sin * sin;
            let b = 2.0 * cos * sin * (ks - kq);
            let c = ks * sin * sin + kq * cos * cos;
            let (d1, d0) = (b * b - 4.0 * a * c, 4.0 * a * q);
            let (k_sag, k_fro) = (s_sag * cos, s_fro * sin);
            quarters[i] = [0.5 / a, b, d1, d0, 1.0 / k_sag, s_sag * sin, 1.0 / k_fro, -s_fro * cos];
            let [_, _, _, _, inv_ks, _, inv_kf, _] = quarters[i];
            bounded &= a > 0.0
                && ks > 0.0
                && kq > 0.0
                && [0, 1, 2, 3, 5, 7].iter().all(|&j| quarters[i][j].is_finite())
                && !inv_ks.is_nan()
                && !inv_kf.is_nan();
        }
        ZoneRows { quarters, bounded }
    }

    /// The cells `lo ..= hi` (within `cols`) of a row `dy` metres above the centre `cx` outside
    /// which the exponent is at least `qs`; `None` when the row has no such cell. A superset: the
    /// row sweep still tests every cell of it. Each quadrant's part is its ellipse's chord cut to
    /// its two half-planes (`k dx + o >= 0`, widened by a cell); the parts are joined, and the
    /// cells get one more on each side: the margins are far beyond the rounding of the sweep's
    /// sums. When something cannot be bounded the whole row is kept.
    fn cells(&self, spec: &GridSpec, cx: f64, dy: f64, cols: (usize, usize)) -> Option<(usize, usize)> {
        let res = spec.resolution;
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let dy2 = dy * dy;
        for &[inv2a, b, d1, d0, inv_ks, os, inv_kf, of] in &self.quarters {
            let disc = d1 * dy2 + d0;
            if disc.is_nan() || disc < 0.0 {
                continue;
            }
            let r = disc.sqrt();
            let (mut l, mut h) = ((-b * dy - r) * inv2a, (-b * dy + r) * inv2a);
            for (inv_k, o) in [(inv_ks, os * dy), (inv_kf, of * dy)] {
                let edge = (-res - o) * inv_k;
                if inv_k > 0.0 {
                    l = l.max(edge);
                } else if inv_k < 0.0 {
                    h = h.min(edge);
                }
                // A row parallel to the edge (`k = 0`) has an infinite `1 / k`: the edge is then
                // at infinity (all or nothing), or NaN, which `max` and `min` ignore.
            }
            if l <= h {
                lo = lo.min(l);
                hi = hi.max(h);
            }
        }
        let (c0, c1) = (cols.0 as f64, cols.1 as f64);
        let (lo, hi) = if self.bounded && dy.is_finite() && !lo.is_nan() && !hi.is_nan() {
            if lo > hi {
                return None;
            }
            // Cell `ix` has its centre at `dx = origin + (ix + 0.5) res - cx`.
            let cell = |dx: f64| (cx + dx - spec.origin.x) / res - 0.5;
            ((cell(lo).floor() - 1.0).max(c0), (cell(hi).ceil() + 1.0).min(c1))
        } else {
            (c0, c1)
        };
        if lo.is_nan() || hi.is_nan() {
            return Some(cols);
        }
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

/// A bound (cells, straight line from the centre's cell, for [`in_sight`]) on the cells in the
/// social zone of a quadratic-form individual (see [`SpaceFunction::quadratic`]): a cell is in it
/// when `e = k_s sag^2 + k_f fro^2 < q_s`, and `e >= k_min (sag^2 + fro^2) = k_min (cos^2 + sin^2)
/// |d|^2`, so `|d| < sqrt(q_s / (k_min (cos^2 + sin^2)))` (metres, from the centre to the cell's
/// centre); the centre lies in its cell, less than a cell from that cell's centre, and one more
/// cell covers the rounding. Infinite when that cannot be bounded.
fn zone_reach(costs: &SocialCosts, quad: &[f64; 8], zone_scale: f64, resolution: f64) -> f64 {
    let [_, _, cos, sin, kf, kr, kri, kl] = *quad;
    let kmin = kf.min(kr).min(kri).min(kl) * (cos * cos + sin * sin);
    let qs = costs.social * costs.social / (2.0 * zone_scale * zone_scale);
    let r = (qs / kmin).sqrt() / resolution + 2.0;
    if kmin > 0.0 && r.is_finite() { r } else { f64::INFINITY }
}

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
    object_cells: Vec<Vec<u32>>,
    object_factor: Vec<f64>,
    prev: Vec<(Rect, [f64; 8])>,
    touched: usize,
    /// Scratch: cells being re-evaluated.
    mark: Vec<bool>,
    /// Zones mode with quadratic individuals: per cell, how many individuals put it in their
    /// intimate, personal and social zone; and each individual's last contribution.
    counts: Vec<[u16; 3]>,
    counted: Vec<Option<Contribution>>,
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
struct Contribution {
    quad: [f64; 8],
    zone_scale: f64,
    rect: Rect,
    spans: Vec<Span>,
    open: Sight,
}

impl Contribution {
    /// Same individual in the same place (the sight mask follows from these).
    fn same(&self, quad: &[f64; 8], zone_scale: f64, rect: Rect) -> bool {
        self.quad == *quad && self.zone_scale == zone_scale && self.rect == rect
    }

    /// The zone sweep of the whole box.
    fn sweep<'a>(&'a self, spec: &'a GridSpec, costs: &'a SocialCosts) -> ZoneSweep<'a> {
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
    /// forbidden cell), e.g. the density contours of [`density_layer`] (the `calderita` planner),
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
    /// `factors`, one factor per cell; repeats allowed): what [`DensityLayer`] changed in an
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

    fn rect_of<S: SpaceFunction>(&self, s: &S) -> Option<Rect> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::Bounds;
    use crate::map::sight::tests::in_sight_reference;

    /// A symmetric test individual: zone distance = Euclidean distance. With `quadratic` it
    /// offers its quadratic form, so the map takes the counting path; without, the generic one.
    #[derive(Clone, Copy)]
    struct Disc {
        c: Vec2,
        sigma: f64,
        quadratic: bool,
    }

    impl SpaceFunction for Disc {
        fn exponent(&self, p: Vec2) -> f64 {
            (p - self.c).norm_squared() / (2.0 * self.sigma * self.sigma)
        }
        fn zone_scale(&self) -> f64 {
            self.sigma
        }
        fn bounds(&self) -> [f64; 4] {
            [self.c.x - 3.6, self.c.y - 3.6, self.c.x + 3.6, self.c.y + 3.6]
        }
        fn fingerprint(&self) -> [f64; 8] {
            [self.c.x, self.c.y, self.sigma, 0.0, 0.0, 0.0, 0.0, 0.0]
        }
        fn centre(&self) -> Option<Vec2> {
            Some(self.c)
        }
        fn quadratic(&self) -> Option<[f64; 8]> {
            let k = 1.0 / (2.0 * self.sigma * self.sigma);
            self.quadratic.then_some([self.c.x, self.c.y, 1.0, 0.0, k, k, k, k])
        }
    }

    fn grid(w: f64, h: f64) -> CostGrid {
        let spec =
            GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(w, h) }, 0.1).expect("valid grid");
        CostGrid { spec, cost: vec![0; spec.len()] }
    }

    #[test]
    fn object_factor_updates_equal_the_max_over_the_covering_objects() {
        // Overlapping interaction spaces whose factors change a few at a time: every cell of
        // the object layer is the largest factor of the objects covering it (1 where none).
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
        let polys: Vec<Vec<Vec2>> = (0..12)
            .map(|_| {
                let (x, y) = (rng.random_range(0.5..7.0), rng.random_range(0.5..7.0));
                let (w, h) = (rng.random_range(0.3..2.5), rng.random_range(0.3..2.5));
                vec![Vec2::new(x, y), Vec2::new(x + w, y), Vec2::new(x + w, y + h), Vec2::new(x, y + h)]
            })
            .collect();
        let mut m = SocialMap::new(grid(10.0, 10.0), &polys, SocialCosts::default());
        let mut factors: Vec<f64> = (0..polys.len()).map(|_| rng.random_range(1.0..3.5)).collect();
        m.rebuild::<Disc>(&[], &factors).expect("one finite factor per object");
        for round in 0..30 {
            if round > 0 {
                for _ in 0..rng.random_range(1..4) {
                    let k = rng.random_range(0..factors.len());
                    factors[k] = rng.random_range(1.0..3.5);
                }
                m.set_object_factors(&factors).expect("one finite factor per object");
            }
            let mut want = vec![1.0f64; m.grid().spec.len()];
            for (cells, &f) in m.object_cells.iter().zip(&factors) {
                for &c in cells {
                    want[c as usize] = want[c as usize].max(f);
                }
            }
            assert_eq!(m.object_layer(), &want[..], "round {round}");
            assert!(m.mark.iter().all(|&b| !b));
            for (c, &w) in want.iter().enumerate() {
                let expected = m.costs().encode(m.people_layer()[c].max(w)).max(m.static_layer().cost[c]);
                assert_eq!(m.grid().cost[c], expected);
            }
        }
    }

    fn cost_at(m: &SocialMap, p: Vec2) -> u8 {
        let (x, y) = m.grid().spec.cell_of(p).expect("inside");
        m.grid().cost[m.grid().spec.index(x, y)]
    }

    #[test]
    fn zones_get_calderita_costs() {
        let mut m = SocialMap::new(grid(10.0, 10.0), &[], SocialCosts::default());
        m.update_people(&[Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false }]);
        let c = m.costs();
        assert_eq!(cost_at(&m, Vec2::new(5.2, 5.0)), LETHAL);
        assert_eq!(cost_at(&m, Vec2::new(5.8, 5.0)), c.encode(4.0));
        assert_eq!(cost_at(&m, Vec2::new(7.0, 5.0)), c.encode(2.0));
        assert_eq!(cost_at(&m, Vec2::new(9.5, 5.0)), 0);
        // encoded factors decode back within the quantisation
        let w = c.weight();
        assert!(((1.0 + w * f64::from(c.encode(4.0)) / 252.0) - 4.0).abs() < w / 252.0);
    }

    #[test]
    fn people_factors_of_the_wrong_length_or_out_of_range_cells_are_errors_leaving_the_map() {
        let mut m = SocialMap::new(grid(10.0, 10.0), &[], SocialCosts::default());
        let n = m.grid().spec.len();
        let mut factors = vec![1.0; n];
        factors[n / 2] = 4.0;
        m.set_people_factors(&factors).expect("one factor per cell");
        let before = m.grid().cost.clone();
        assert_ne!(before[n / 2], 0, "the 4.0 factor is drawn");
        let short = vec![1.0; n - 1];
        let err = m.set_people_factors(&short).expect_err("one short");
        let text = err.to_string();
        assert!(text.contains("factors") && text.contains(&n.to_string()), "{text}");
        assert!(text.contains(&format!("{} factors", n - 1)), "{text}");
        factors[0] = 4.0;
        let err = m.set_people_factors_at(&factors, &[0, n]).expect_err("cell n is outside");
        assert!(err.to_string().contains("cells"), "{err}");
        let err = m.set_people_factors_at(&short, &[0]).expect_err("one short");
        assert!(err.to_string().contains("factors"), "{err}");
        assert_eq!(m.grid().cost, before, "a refused write leaves the map as it was");
        m.set_people_factors_at(&factors, &[0, 0]).expect("in range");
        assert_ne!(m.grid().cost[0], 0);
        assert_eq!(m.cells_touched(), 1, "a repeated cell changes once");
    }

    #[test]
    fn zones_stop_at_walls_and_pass_doorways() {
        // A wall at x = 6 (cells 60-61) from y = 0 to 10 with a doorway at y 4.5 - 5.5; a
        // person at (5, 2) in the west room.
        let mut g = grid(10.0, 10.0);
        for iy in 0..100 {
            if !(45..55).contains(&iy) {
                for ix in 60..62 {
                    let i = g.spec.index(ix, iy);
                    g.cost[i] = LETHAL;
                }
            }
        }
        let mut m = SocialMap::new(g, &[], SocialCosts::default());
        m.update_people(&[Disc { c: Vec2::new(5.0, 2.0), sigma: 1.0, quadratic: false }]);
        let c = m.costs();
        // 1.6 m east of the person, behind the wall: no zone (2.0 without the wall).
        assert_eq!(cost_at(&m, Vec2::new(6.6, 2.0)), 0);
        // The same distance west, in the person's room: the social zone.
        assert_eq!(cost_at(&m, Vec2::new(3.4, 2.0)), c.encode(2.0));
        // Through the doorway, in sight of the person: still the social zone.
        assert_eq!(cost_at(&m, Vec2::new(6.3, 4.7)), c.encode(2.0));
        // The counted (incremental) update agrees with a rebuild.
        let mut full = m.clone();
        full.rebuild(&[Disc { c: Vec2::new(5.0, 2.0), sigma: 1.0, quadratic: false }], &[])
            .expect("one finite factor per object");
        assert_eq!(m.grid(), full.grid());
    }

    #[test]
    fn incremental_update_equals_rebuild_and_touches_fewer_cells() {
        let spec_grid = grid(40.0, 20.0);
        let poly = vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0), Vec2::new(3.0, 3.0), Vec2::new(1.0, 3.0)];
        let mut inc = SocialMap::new(spec_grid.clone(), std::slice::from_ref(&poly), SocialCosts::default());
        let mut people = vec![
            Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false },
            Disc { c: Vec2::new(15.0, 5.0), sigma: 1.0, quadratic: false },
        ];
        inc.set_object_factors(&[1.5]).expect("one finite factor per object");
        inc.update_people(&people);
        people[0].c = Vec2::new(6.0, 5.5);
        inc.update_people(&people);
        let touched = inc.cells_touched();
        inc.set_object_factors(&[3.5]).expect("one finite factor per object");
        let mut full = SocialMap::new(spec_grid, &[poly], SocialCosts::default());
        full.rebuild(&people, &[3.5]).expect("one finite factor per object");
        assert_eq!(inc.grid(), full.grid());
        assert!(touched < inc.grid().spec.len() / 2, "touched {touched}");
        // unchanged people cost nothing
        inc.update_people(&people);
        assert_eq!(inc.cells_touched(), 0);
    }

    #[test]
    fn counted_update_keeps_contributions_when_the_list_shifts() {
        let round = |x: f64, y: f64| Disc { c: Vec2::new(x, y), sigma: 1.0, quadratic: true };
        let mut people = vec![round(5.0, 5.0), round(15.0, 5.0), round(25.0, 5.0)];
        let mut inc = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
        inc.update_people(&people);
        let one = {
            let mut lone = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
            lone.update_people(&people[..1]);
            lone.cells_touched()
        };
        assert!(one > 0);
        // The first one starts walking and leaves the list: the others' indices shift, yet only
        // the leaver's cells are touched.
        people.remove(0);
        inc.update_people(&people);
        assert_eq!(inc.cells_touched(), one);
        // Someone stops at the front of the list: only the newcomer's cells.
        people.insert(0, round(35.0, 15.0));
        inc.update_people(&people);
        assert_eq!(inc.cells_touched(), one);
        let mut full = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
        full.update_people(&people);
        assert_eq!(inc.grid(), full.grid());
        // Against the zone costs of a map that never counted.
        let mut plain = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
        plain.update_people(&people.iter().map(|r| Disc { quadratic: false, ..*r }).collect::<Vec<_>>());
        assert_eq!(inc.grid(), plain.grid());
    }

    #[test]
    fn object_factors_of_the_wrong_length_or_not_finite_are_errors_leaving_the_map() {
        let square = |x: f64| {
            vec![Vec2::new(x, 1.0), Vec2::new(x + 2.0, 1.0), Vec2::new(x + 2.0, 3.0), Vec2::new(x, 3.0)]
        };
        let mut m = SocialMap::new(grid(10.0, 10.0), &[square(1.0), square(5.0)], SocialCosts::default());
        m.set_object_factors(&[3.5, 1.5]).expect("one finite factor per object");
        let before = m.clone();
        for bad in [&[3.5][..], &[3.5, 1.5, 2.0], &[]] {
            let err = m.set_object_factors(bad).expect_err("a bad factor list").to_string();
            assert!(err.contains("object_factors") && err.contains("2 polygons"), "{err}");
            assert!(err.contains(&format!("{} factors", bad.len())), "{err}");
            let err = m.rebuild::<Disc>(&[], bad).expect_err("a bad factor list").to_string();
            assert!(err.contains("2 polygons"), "{err}");
        }
        for bad in [f64::NAN, f64::INFINITY] {
            let err = m.set_object_factors(&[2.0, bad]).expect_err("a bad factor list").to_string();
            assert!(err.contains("object_factors[1]") && err.contains("finite"), "{err}");
            assert!(m.rebuild::<Disc>(&[], &[bad, 2.0]).is_err());
        }
        assert_eq!(m.grid(), before.grid());
        assert_eq!(m.object_layer(), before.object_layer());
    }

    #[test]
    fn object_space_takes_r_of_t_and_static_stays_lethal() {
        let mut g = grid(10.0, 10.0);
        let i = g.spec.index(20, 20);
        g.cost[i] = LETHAL;
        let poly = vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0), Vec2::new(3.0, 3.0), Vec2::new(1.0, 3.0)];
        let mut m = SocialMap::new(g, &[poly], SocialCosts::default());
        m.rebuild::<Disc>(&[], &[3.5]).expect("one finite factor per object");
        assert_eq!(cost_at(&m, Vec2::new(2.05, 2.05)), LETHAL);
        assert_eq!(cost_at(&m, Vec2::new(1.5, 1.5)), m.costs().encode(3.5));
        assert_eq!(cost_at(&m, Vec2::new(5.0, 5.0)), 0);
        m.set_object_factors(&[1.5]).expect("one finite factor per object");
        assert_eq!(cost_at(&m, Vec2::new(1.5, 1.5)), m.costs().encode(1.5));
        assert_eq!(m.cells_touched(), 400);
    }

    #[test]
    fn continuous_mode_follows_the_function() {
        let costs = SocialCosts { mode: CostMode::Continuous { gain: 3.0 }, ..SocialCosts::default() };
        let mut m = SocialMap::new(grid(10.0, 10.0), &[], costs);
        m.update_people(&[Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false }]);
        let near = cost_at(&m, Vec2::new(5.55, 5.05));
        let far = cost_at(&m, Vec2::new(6.55, 5.05));
        assert!(near > far && far > 0);
    }

    /// A test individual with a turned, asymmetric quadratic form (see
    /// [`SpaceFunction::quadratic`]), so the map takes the counting path.
    #[derive(Clone, Copy)]
    struct Oval {
        quad: [f64; 8],
        zone_scale: f64,
    }

    impl SpaceFunction for Oval {
        fn exponent(&self, p: Vec2) -> f64 {
            let [cx, cy, cos, sin, kf, kr, kri, kl] = self.quad;
            let (dx, dy) = (p.x - cx, p.y - cy);
            let (sag, fro) = (cos * dx + sin * dy, sin * dx - cos * dy);
            (if sag >= 0.0 { kf } else { kr }) * sag * sag + (if fro >= 0.0 { kri } else { kl }) * fro * fro
        }
        fn zone_scale(&self) -> f64 {
            self.zone_scale
        }
        fn bounds(&self) -> [f64; 4] {
            [self.quad[0] - 4.0, self.quad[1] - 3.0, self.quad[0] + 3.5, self.quad[1] + 4.5]
        }
        fn fingerprint(&self) -> [f64; 8] {
            self.quad
        }
        fn centre(&self) -> Option<Vec2> {
            Some(Vec2::new(self.quad[0], self.quad[1]))
        }
        fn quadratic(&self) -> Option<[f64; 8]> {
            Some(self.quad)
        }
    }

    /// The zone (0 intimate, 1 personal, 2 social) of every cell of `rect` (row-major), decided
    /// cell by cell over the whole rect by the row sweep as first written.
    fn plain_zones(
        spec: &GridSpec,
        c: &SocialCosts,
        quad: &[f64; 8],
        zone_scale: f64,
        rect: Rect,
    ) -> Vec<Option<usize>> {
        let [cx, cy, cos, sin, kf, kr, kri, kl] = *quad;
        let (a0, b0, a1, b1) = rect;
        let two_z2 = 2.0 * zone_scale * zone_scale;
        let (qi, qp, qs) = (
            c.intimate * c.intimate / two_z2,
            c.personal * c.personal / two_z2,
            c.social * c.social / two_z2,
        );
        let res = spec.resolution;
        let mut zones = Vec::with_capacity((a1 + 1 - a0) * (b1 + 1 - b0));
        for iy in b0..=b1 {
            let p0 = spec.center(a0, iy);
            let (dx, dy) = (p0.x - cx, p0.y - cy);
            let mut sag = cos * dx + sin * dy;
            let mut fro = sin * dx - cos * dy;
            for _ in a0..=a1 {
                let ks = if sag >= 0.0 { kf } else { kr };
                let kq = if fro >= 0.0 { kri } else { kl };
                let e = ks * sag * sag + kq * fro * fro;
                zones.push(if e < qi {
                    Some(0)
                } else if e < qp {
                    Some(1)
                } else if e < qs {
                    Some(2)
                } else {
                    None
                });
                sag += cos * res;
                fro += sin * res;
            }
        }
        zones
    }

    /// The people layer of the counting path computed the plain way: for every individual, the
    /// cells of its box in sight of it (the reference walk) get the maximum with its zone's
    /// factor, the zone decided cell by cell by [`plain_zones`].
    fn counted_layer_reference(m: &SocialMap, people: &[Oval]) -> Vec<f64> {
        let spec = m.grid().spec;
        let c = m.costs();
        let factors = [f64::INFINITY, c.personal_cost, c.social_cost];
        let mut layer = vec![1.0f64; spec.len()];
        for ind in people {
            let Some(full) = m.rect_of(ind) else { continue };
            let open = in_sight_reference(m.static_layer(), Vec2::new(ind.quad[0], ind.quad[1]), full);
            let zones = plain_zones(&spec, c, &ind.quad, ind.zone_scale, full);
            let (a0, b0, a1, _) = full;
            for (k, zone) in zones.iter().enumerate() {
                if let Some(z) = zone.filter(|_| open[k]) {
                    let i = spec.index(a0 + k % (a1 + 1 - a0), b0 + k / (a1 + 1 - a0));
                    layer[i] = layer[i].max(factors[z]);
                }
            }
        }
        layer
    }

    /// Up to `walls` (exclusive) random wall segments of 1 to `len` cells, row- or column-wise,
    /// lethal or (one in ten) inscribed.
    fn random_walls(g: &mut CostGrid, rng: &mut rand_chacha::ChaCha8Rng, walls: usize, len: usize) {
        use rand::Rng;
        for _ in 0..rng.random_range(0..walls) {
            let (x, y) = (rng.random_range(0..g.spec.width), rng.random_range(0..g.spec.height));
            let (n, vertical) = (rng.random_range(1..len), rng.random_bool(0.5));
            for t in 0..n {
                let (ix, iy) = if vertical { (x, y + t) } else { (x + t, y) };
                if ix < g.spec.width && iy < g.spec.height {
                    let i = g.spec.index(ix, iy);
                    g.cost[i] = if rng.random_bool(0.9) { LETHAL } else { INSCRIBED };
                }
            }
        }
    }

    #[test]
    fn zone_sweeps_limited_to_the_zones_rows_are_the_plain_sweep_bit_for_bit() {
        // Turned (and axis-aligned), very uneven individuals anywhere on and off a grid with an
        // odd origin, over rects smaller and larger than their zones, with and without a sight
        // mask: the sweep that tests only the cells of [`ZoneRows::cells`] and of the mask's open
        // runs (stepping over the closed cells between them), bringing a batch of rows to their
        // first tested cells side by side, visits exactly the cells, with the zones, of the plain
        // sweep of the whole rect.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
        let spec = GridSpec { origin: Vec2::new(-3.37, 1.21), ..grid(16.0, 9.0).spec };
        let costs = SocialCosts::default();
        for case in 0..3000 {
            let (cos, sin) = match case % 5 {
                0 => [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][rng.random_range(0..4)],
                _ => {
                    let th: f64 = rng.random_range(-3.2..3.2);
                    (th.cos(), th.sin())
                }
            };
            let mut k = || 10f64.powf(rng.random_range(-1.5..1.5));
            let (kf, kr, kri, kl) = (k(), k(), k(), k());
            let centre = Vec2::new(rng.random_range(-6.0..15.0), rng.random_range(-1.0..12.0));
            let quad = [centre.x, centre.y, cos, sin, kf, kr, kri, kl];
            let zone_scale = rng.random_range(0.5..1.5);
            let (x0, y0) = (rng.random_range(0..spec.width), rng.random_range(0..spec.height));
            let rect = (
                x0,
                y0,
                (x0 + rng.random_range(0..200)).min(spec.width - 1),
                (y0 + rng.random_range(0..120)).min(spec.height - 1),
            );
            let (w, h) = (rect.2 + 1 - rect.0, rect.3 + 1 - rect.1);
            let words = w.div_ceil(64);
            let open = if case % 2 == 0 {
                Sight { words, bits: None }
            } else {
                // Random runs of open and closed cells.
                let mut bits = vec![0u64; words * h];
                for y in 0..h {
                    let mut on = rng.random_bool(0.5);
                    for x in 0..w {
                        if rng.random_bool(0.05) {
                            on = !on;
                        }
                        bits[y * words + x / 64] |= u64::from(on) << (x % 64);
                    }
                }
                Sight { words, bits: Some(bits) }
            };
            let mut got = Vec::new();
            let spans = zone_spans(&spec, &costs, &quad, zone_scale, rect);
            let c = Contribution { quad, zone_scale, rect, spans, open };
            let sweep = c.sweep(&spec, &costs);
            sweep.cells(|i, z| got.push((i, z)));
            let want: Vec<(usize, usize)> = plain_zones(&spec, &costs, &quad, zone_scale, rect)
                .into_iter()
                .enumerate()
                .filter_map(|(k, z)| {
                    let (x, y) = (k % w, k / w);
                    Some((spec.index(rect.0 + x, rect.1 + y), z.filter(|_| c.open.is_open(x, y))?))
                })
                .collect();
            assert_eq!(got, want, "case {case}");
            // The runs of the rebuild: maximal, and their cells the same.
            let mut runs: Vec<(usize, usize, usize, usize)> = Vec::new();
            sweep.runs(|iy, x0, x1, z| runs.push((iy, x0, x1, z)));
            for w in runs.windows(2) {
                let ((y0, _, e0, z0), (y1, s1, _, z1)) = (w[0], w[1]);
                assert!(y0 < y1 || (y0 == y1 && (e0 + 1 < s1 || z0 != z1)), "case {case}: runs {w:?}");
            }
            let cells: Vec<(usize, usize)> = runs
                .iter()
                .flat_map(|&(iy, x0, x1, z)| (x0..=x1).map(move |ix| (spec.index(ix, iy), z)))
                .collect();
            assert_eq!(cells, want, "case {case}: runs");
        }
    }

    #[test]
    fn counted_updates_on_random_walled_scenes_are_the_plain_layer_bit_for_bit() {
        // Random walls, turned asymmetric individuals moving a few at a time (and joining and
        // leaving): after the rebuild and after every incremental update, the people layer is
        // the plain per-individual maximum bit for bit, and the grid its combination.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
        let oval = |rng: &mut rand_chacha::ChaCha8Rng| {
            let th: f64 = rng.random_range(-3.2..3.2);
            let mut k = || rng.random_range(0.2..1.5);
            let quad = [0.0, 0.0, th.cos(), th.sin(), k(), k(), k(), k()];
            Oval { quad, zone_scale: rng.random_range(0.8..1.3) }
        };
        for case in 0..10 {
            let mut g = grid(16.0, 9.0);
            random_walls(&mut g, &mut rng, 10, 80);
            let place = |o: &mut Oval, rng: &mut rand_chacha::ChaCha8Rng| {
                o.quad[0] = rng.random_range(-1.0..17.0);
                o.quad[1] = rng.random_range(-1.0..10.0);
            };
            let mut people: Vec<Oval> = (0..rng.random_range(1..9))
                .map(|_| {
                    let mut o = oval(&mut rng);
                    place(&mut o, &mut rng);
                    o
                })
                .collect();
            let mut m = SocialMap::new(g.clone(), &[], SocialCosts::default());
            m.rebuild(&people, &[]).expect("one finite factor per object");
            for round in 0..8 {
                if round > 0 {
                    for o in people.iter_mut() {
                        if rng.random_bool(0.3) {
                            o.quad[0] += rng.random_range(-0.3..0.3);
                            o.quad[1] += rng.random_range(-0.3..0.3);
                        }
                    }
                    if rng.random_bool(0.3) && people.len() > 1 {
                        people.remove(rng.random_range(0..people.len()));
                    }
                    if rng.random_bool(0.3) {
                        let mut o = oval(&mut rng);
                        place(&mut o, &mut rng);
                        people.insert(rng.random_range(0..=people.len()), o);
                    }
                    m.update_people(&people);
                }
                let want = counted_layer_reference(&m, &people);
                let got: Vec<u64> = m.people_layer().iter().map(|f| f.to_bits()).collect();
                assert_eq!(
                    got,
                    want.iter().map(|f| f.to_bits()).collect::<Vec<_>>(),
                    "case {case} round {round}"
                );
                for (c, &f) in want.iter().enumerate() {
                    let expected = m.costs().encode(f.max(m.object_layer()[c])).max(g.cost[c]);
                    let expected = if g.cost[c] >= INSCRIBED { g.cost[c] } else { expected };
                    assert_eq!(m.grid().cost[c], expected, "case {case} round {round} cell {c}");
                }
            }
        }
    }

    #[test]
    fn rebuild_by_runs_is_the_per_cell_count_bit_for_bit() {
        // Random walls (some touching the grid's edges), turned asymmetric individuals anywhere
        // on, across and off the grid's edges, some very uneven: the rebuild, which counts the
        // zones by runs, leaves the counts, contributions, people layer, grid and touched count
        // of the per-cell counting from empty, and the people layer is the plain sweep cut by
        // the reference walk.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(41);
        for case in 0..40 {
            let mut g = grid(12.0, 7.0);
            g.spec.origin = Vec2::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
            random_walls(&mut g, &mut rng, 12, 90);
            let people: Vec<Oval> = (0..rng.random_range(0..14))
                .map(|k| {
                    let th: f64 = if k % 4 == 0 {
                        [0.0, 0.5, 1.0, 1.5][rng.random_range(0..4)] * std::f64::consts::PI
                    } else {
                        rng.random_range(-3.2..3.2)
                    };
                    let mut k = || 10f64.powf(rng.random_range(-0.7..0.4));
                    let (kf, kr, kri, kl) = (k(), k(), k(), k());
                    let (x, y) = (rng.random_range(-4.0..16.0), rng.random_range(-4.0..11.0));
                    Oval {
                        quad: [x, y, th.cos(), th.sin(), kf, kr, kri, kl],
                        zone_scale: rng.random_range(0.7..1.4),
                    }
                })
                .collect();
            let mut runs = SocialMap::new(g.clone(), &[], SocialCosts::default());
            runs.rebuild(&people, &[]).expect("one finite factor per object");
            let mut cells = SocialMap::new(g.clone(), &[], SocialCosts::default());
            cells.update_people(&people);
            assert!(runs.counts == cells.counts, "case {case}: counts");
            assert_eq!(runs.counted.len(), cells.counted.len(), "case {case}");
            for (a, b) in runs.counted.iter().zip(&cells.counted) {
                let same = match (a, b) {
                    (Some(a), Some(b)) => a.same(&b.quad, b.zone_scale, b.rect) && a.open.bits == b.open.bits,
                    (a, b) => a.is_none() && b.is_none(),
                };
                assert!(same, "case {case}: contributions");
            }
            let bits = |m: &SocialMap| m.people_layer().iter().map(|f| f.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&runs), bits(&cells), "case {case}: people layer");
            let want = counted_layer_reference(&runs, &people);
            assert_eq!(bits(&runs), want.iter().map(|f| f.to_bits()).collect::<Vec<_>>(), "case {case}");
            assert_eq!(runs.grid(), cells.grid(), "case {case}: grid");
            assert_eq!(runs.cells_touched(), cells.cells_touched(), "case {case}: touched");
            assert!(runs.mark.iter().all(|&b| !b));
            // Both go on counting alike.
            let mut moved = people.clone();
            for o in moved.iter_mut().step_by(2) {
                o.quad[0] += 0.13;
                o.quad[1] -= 0.07;
            }
            runs.update_people(&moved);
            cells.update_people(&moved);
            assert!(runs.counts == cells.counts, "case {case}: counts after a move");
            assert_eq!(runs.grid(), cells.grid(), "case {case}: grid after a move");
        }
    }
}
