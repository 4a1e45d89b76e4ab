//! The zone row sweeps of the social cost map: for a quadratic-form individual (see
//! [`SpaceFunction::quadratic`](super::SpaceFunction::quadratic)), the zone of every cell of its box, decided row by row from the
//! exponent's thresholds without exp or sqrt, only on the cells of each row that can lie in the
//! social zone and in sight.

use super::cost_model::SocialCosts;
use crate::map::grid::GridSpec;
use crate::map::sight::{OpenRuns, Rect, Sight, Span, open_span};

/// What a zone sweep of one quadratic-form individual (see [`SpaceFunction::quadratic`](super::SpaceFunction::quadratic)) needs
/// along a row: the quadrants' coefficients, the zones' thresholds on the exponent and the
/// axis distances' steps from one cell to the next.
pub(super) struct ZoneScan {
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
    pub(super) fn zone(&self, sag: f64, fro: f64) -> usize {
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
    pub(super) const NONE: usize = 3;
}

/// The exponent's thresholds of the intimate, personal and social zones of an individual with
/// zone scale `zone_scale`.
pub(super) fn zone_thresholds(costs: &SocialCosts, zone_scale: f64) -> [f64; 3] {
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
pub(super) fn zone_spans(
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

/// The zone sweep of one quadratic-form individual (see [`SpaceFunction::quadratic`](super::SpaceFunction::quadratic)) over a
/// box of cells. Zones are decided by comparing the exponent with the zone radii's thresholds,
/// without exp or sqrt.
pub(super) struct ZoneSweep<'a> {
    pub(super) spec: &'a GridSpec,
    pub(super) costs: &'a SocialCosts,
    /// The individual's quadratic form.
    pub(super) quad: &'a [f64; 8],
    pub(super) zone_scale: f64,
    /// The individual's whole box.
    pub(super) full: Rect,
    /// Which cells of `full` are in sight of the individual (from [`in_sight`]: zones do not
    /// pass through walls).
    pub(super) open: &'a Sight,
    /// The cells of each row of `full` that can lie in the social zone (from [`zone_spans`]).
    pub(super) spans: &'a [Span],
    /// The part of the box to visit.
    pub(super) rect: Rect,
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
    pub(super) fn cells(&self, mut f: impl FnMut(usize, usize)) {
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
    pub(super) fn runs(&self, mut f: impl FnMut(usize, usize, usize, usize)) {
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

/// The rows of the social zone of a quadrant-wise quadratic form (see
/// [`SpaceFunction::quadratic`](super::SpaceFunction::quadratic)): per quadrant, the constants that give the zone's part of a
/// row in a few operations (see [`ZoneRows::cells`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct ZoneRows {
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
    pub(super) fn new(quad: &[f64; 8], qs: f64) -> Self {
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
    pub(super) fn cells(
        &self,
        spec: &GridSpec,
        cx: f64,
        dy: f64,
        cols: (usize, usize),
    ) -> Option<(usize, usize)> {
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
/// social zone of a quadratic-form individual (see [`SpaceFunction::quadratic`](super::SpaceFunction::quadratic)): a cell is in it
/// when `e = k_s sag^2 + k_f fro^2 < q_s`, and `e >= k_min (sag^2 + fro^2) = k_min (cos^2 + sin^2)
/// |d|^2`, so `|d| < sqrt(q_s / (k_min (cos^2 + sin^2)))` (metres, from the centre to the cell's
/// centre); the centre lies in its cell, less than a cell from that cell's centre, and one more
/// cell covers the rounding. Infinite when that cannot be bounded.
pub(super) fn zone_reach(costs: &SocialCosts, quad: &[f64; 8], zone_scale: f64, resolution: f64) -> f64 {
    let [_, _, cos, sin, kf, kr, kri, kl] = *quad;
    let kmin = kf.min(kr).min(kri).min(kl) * (cos * cos + sin * sin);
    let qs = costs.social * costs.social / (2.0 * zone_scale * zone_scale);
    let r = (qs / kmin).sqrt() / resolution + 2.0;
    if kmin > 0.0 && r.is_finite() { r } else { f64::INFINITY }
}
