//! The tiled accelerator of Calderita's density layer: the people with their constants, the
//! per-tile rasteriser of their Gaussians (products instead of one `exp` per cell), the bounds of
//! a change over a tile and the exponential tables.

use crate::map::grid::GridSpec;
use crate::math::Vec2;
use crate::proxemics::DensityZones;

pub(super) const TILE: usize = 8;

/// Side of the blocks of tiles whose bound of a change [`DensityLayer::update`](super::DensityLayer::update) tries first
/// (tiles).
pub(super) const BLOCK: usize = 4;

/// People whose exponent can fall to this in a tile are summed per cell by [`DensityLayer`](super::DensityLayer)
/// (`exp(-10) = 4.5e-5`: the others together stay far below the contour levels' gaps).
pub(super) const NEAR_EXPONENT: f64 = 10.0;

/// People whose exponent stays above this over a block of [`DensityLayer`](super::DensityLayer)'s rebuild
/// (`exp(-16) = 1.1e-7`) are only bounded there, not looked at per tile.
pub(super) const BLOCK_FAR: f64 = 16.0;

/// Kirby's Gaussian is cut where its exponent exceeds this (0 beyond).
pub(super) const CUT: f64 = 40.0;

/// Above `exp(-CUT) = 4.25e-18`: the most a person's term can differ across the cut.
pub(super) const CUT_TERM: f64 = 5e-18;

/// A change whose bound over a tile is below this is bounded, not evaluated, by
/// [`DensityLayer::update`](super::DensityLayer::update).
pub(super) const PAIR_BOUND: f64 = 1e-7;

/// Relative margin for rounding in the sums and products of [`DensityLayer`](super::DensityLayer), far above the
/// errors it covers (below 1e-12 for the products, `n` ulps for a sum of `n` terms).
pub(super) const REL: f64 = 1e-9;

/// Largest exponent over a tile (one cell beyond, either side's σ) for which a person's
/// Gaussian is evaluated by products: every value, ratio and constant then lies within
/// `exp(±2 RECURRENCE_MAX)`, far from overflow and underflow. Beyond, `exp` per cell.
pub(super) const RECURRENCE_MAX: f64 = 80.0;

/// A person of [`DensityLayer`](super::DensityLayer): position (m), unit facing, the exponent's coefficients
/// `1/(2σ²)` ahead, behind and to the sides, the largest `σ` (m), and per side of the body
/// (ahead: `u >= 0`, behind) the constants of the products.
#[derive(Clone, Copy, Debug)]
pub(super) struct Person {
    pub(super) pos: Vec2,
    pub(super) f: Vec2,
    pub(super) ahead: f64,
    pub(super) behind: f64,
    pub(super) across: f64,
    pub(super) sigma_max: f64,
    pub(super) sides: [Side; 2],
}

/// One side's quadratic exponent `q = α u² + β v²` (`α = 1/(2σ_u²)`, `β = 1/(2σ_s²)`) along
/// the grid: per cell step along x, the ratio of consecutive values is multiplied by `row`;
/// along y by `col`; and a step along y multiplies the x ratio (and a step along x the y ratio)
/// by `cross`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Side {
    pub(super) alpha: f64,
    pub(super) row: f64,
    pub(super) col: f64,
    pub(super) cross: f64,
}

impl Person {
    pub(super) fn new(p: &crate::groups::DensityParams, res: f64, pos: Vec2, f: Vec2) -> Self {
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
    pub(super) fn out_of_reach(&self, lo: Vec2, hi: Vec2) -> bool {
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
    pub(super) fn bounds(&self, lo: Vec2, hi: Vec2) -> (f64, f64) {
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
    pub(super) fn upper_either(&self, lo: Vec2, hi: Vec2) -> f64 {
        let [u, du, v, dv] = box_in_frame(self.pos, self.f, lo, hi);
        let qu = ((u - du).abs().max((u + du).abs())).powi(2) * self.ahead.max(self.behind);
        let qv = ((v - dv).abs().max((v + dv).abs())).powi(2) * self.across;
        (qu + qv) * (1.0 + 1e-9)
    }
}

/// Scratch lists of [`Raster::tile`].
#[derive(Clone, Debug, Default)]
pub(super) struct Scratch {
    /// The bound of each change over a tile and over its block ([`DensityLayer::update`](super::DensityLayer::update)).
    pub(super) bounds: Vec<f64>,
    pub(super) block_bounds: Vec<f64>,
    pub(super) block: Vec<usize>,
    pub(super) some: Vec<usize>,
    pub(super) near: Vec<usize>,
}

/// What [`Raster::tile`] reads.
pub(super) struct Raster<'a> {
    pub(super) spec: &'a GridSpec,
    pub(super) zones: &'a DensityZones,
    pub(super) thresholds: &'a [f64; 4],
    pub(super) class_factor: &'a [f64; 5],
    pub(super) people: &'a [Person],
}

impl Raster<'_> {
    /// How many of the thresholds `g` reaches.
    pub(super) fn class(&self, g: f64) -> usize {
        self.thresholds.iter().filter(|&&t| g >= t).count()
    }

    /// The threshold next above class `c` (infinite above the last): a density at least one of
    /// class `c` is in that class exactly when it stays below this.
    #[inline]
    pub(super) fn above(&self, c: usize) -> f64 {
        self.thresholds.get(c).copied().unwrap_or(f64::INFINITY)
    }

    /// How far a density known to lie in `lo..=hi` (no threshold inside) may move either way
    /// and stay in its class, less a margin for rounding (negative: not at all): the distance to
    /// the nearest threshold, `max(lo - t, t - hi)` for each threshold `t` outside.
    #[inline]
    pub(super) fn slack(&self, lo: f64, hi: f64) -> f64 {
        let d = self.thresholds.iter().fold(f64::INFINITY, |d, &t| d.min((lo - t).max(t - hi)));
        d - REL * (1.0 + hi.abs())
    }

    /// The people (indices, in order) whose exponent may be 40 or below somewhere in the box
    /// `lo`-`hi` (m), into `out`: the others add exactly 0 to every sum there.
    pub(super) fn reaching(&self, lo: Vec2, hi: Vec2, out: &mut Vec<usize>) {
        out.clear();
        out.extend((0..self.people.len()).filter(|&i| self.people[i].bounds(lo, hi).0 <= CUT * (1.0 + 1e-9)));
    }

    /// Computes the factors of tile (`tx`, `ty`) into `out` and each cell's slack into `slack`
    /// (both the whole grid's, row-major) and returns the tile's slack (the smallest; module
    /// docs of [`DensityLayer`](super::DensityLayer)).
    pub(super) fn tile(
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
    pub(super) fn add_person(&self, p: &Person, x0: usize, y0: usize, acc: &mut [f64; TILE * TILE]) {
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
pub(super) fn side_values(
    side: &Side,
    beta: f64,
    res: f64,
    f: Vec2,
    u0: f64,
    v0: f64,
    mut put: impl FnMut(usize, f64),
) {
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

/// A change of one person between the reference and the current people of [`DensityLayer`](super::DensityLayer):
/// `(position, unit facing)` before and after; `None` on one side for a person who joined or
/// left.
#[derive(Clone, Copy, Debug)]
pub(super) struct Change {
    pub(super) before: Option<Person>,
    pub(super) after: Option<Person>,
}

impl Change {
    /// An upper bound on `|g_after(x) - g_before(x)|` over the box `lo`-`hi` (m) for the cut
    /// Gaussians of the change's person (module docs of [`DensityLayer`](super::DensityLayer)).
    pub(super) fn bound(&self, p: &crate::groups::DensityParams, lo: Vec2, hi: Vec2) -> f64 {
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
pub(super) fn pair_changes(base: &[Person], now: &[Person], out: &mut Vec<Change>) {
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
pub(super) fn box_in_frame(pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> [f64; 4] {
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
pub(super) fn exponent_lower_bound(
    p: &crate::groups::DensityParams,
    pos: Vec2,
    f: Vec2,
    lo: Vec2,
    hi: Vec2,
) -> f64 {
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
pub(super) const EXP_STEPS: f64 = 32.0;

/// `exp(-i / EXP_STEPS)` for `i` in `0..=40 EXP_STEPS` (Kirby's Gaussian is cut at exponent 40).
pub(super) fn exp_table() -> &'static [f64] {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| (0..=(40.0 * EXP_STEPS) as usize).map(|i| (-(i as f64) / EXP_STEPS).exp()).collect())
}

/// An upper bound on `exp(-q)` for `0 <= q <= 40` (with a margin), from [`exp_table`].
pub(super) fn exp_table_above(q: f64) -> f64 {
    // (The float-to-integer cast truncates: the floor of a non-negative value.)
    let i = (q.max(0.0) * EXP_STEPS) as usize;
    exp_table().get(i).map_or(1.0, |&e| e * (1.0 + 1e-12))
}

/// A lower bound on the term `exp(-q)` of a Gaussian cut at exponent 40 (0 beyond), from
/// [`exp_table`] (with a margin).
pub(super) fn exp_table_below(q: f64) -> f64 {
    if q > 40.0 {
        return 0.0;
    }
    let t = q.max(0.0) * EXP_STEPS;
    let i = t as usize + usize::from((t as usize as f64) < t); // the ceiling
    exp_table().get(i).map_or(0.0, |&e| e * (1.0 - 1e-12))
}
