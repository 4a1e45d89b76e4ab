//! The line-of-sight walk on a cost grid: which cells of a rectangle lie open to a point (reached
//! from it around the obstacles in about the straight-line distance), as bit rows, with the runs
//! and spans of open cells read off them. The social cost map limits a person's zones to the cells
//! in sight of the person with it.

use crate::map::cost_grid::{CostGrid, LETHAL};
use crate::math::Vec2;

/// Inclusive cell rectangle `(x0, y0, x1, y1)`.
pub(crate) type Rect = (usize, usize, usize, usize);

/// The cells `lo ..= hi` of a row (e.g. those that can lie in a social zone), `None` for none.
pub(crate) type Span = Option<(usize, usize)>;

/// The first and last open cell of `x0 ..= x1` in a bit row of a [`Sight`], `None` when none is.
pub(crate) fn open_span(bits: &[u64], x0: usize, x1: usize) -> Option<(usize, usize)> {
    let (j0, j1) = (x0 / 64, x1 / 64);
    let first = (j0..=j1).find_map(|j| {
        let w = bits[j] & span_bits(j, x0, x1);
        (w != 0).then(|| 64 * j + w.trailing_zeros() as usize)
    })?;
    let last = (j0..=j1).rev().find_map(|j| {
        let w = bits[j] & span_bits(j, x0, x1);
        (w != 0).then(|| 64 * j + 63 - w.leading_zeros() as usize)
    })?;
    Some((first, last))
}

/// The maximal runs `x0 ..= x1` of open cells of `lo ..= hi`, from left to right: bit `x - off`
/// of `bits` is cell `x`; all of `lo ..= hi` when `bits` is `None`.
pub(crate) struct OpenRuns<'a> {
    bits: Option<&'a [u64]>,
    off: usize,
    /// The next cell to look at and the last cell (minus `off`).
    x: usize,
    end: usize,
}

impl<'a> OpenRuns<'a> {
    pub(crate) fn new(bits: Option<&'a [u64]>, off: usize, lo: usize, hi: usize) -> Self {
        OpenRuns { bits, off, x: lo - off, end: hi - off }
    }

    /// The first cell of `x ..= end` whose bit is `bit`, if any.
    #[inline]
    fn find(bits: &[u64], x: usize, end: usize, bit: bool) -> Option<usize> {
        (x / 64..=end / 64).find_map(|j| {
            let w = if bit { bits[j] } else { !bits[j] } & span_bits(j, x, end);
            (w != 0).then(|| 64 * j + w.trailing_zeros() as usize)
        })
    }
}

impl Iterator for OpenRuns<'_> {
    type Item = (usize, usize);

    #[inline]
    fn next(&mut self) -> Option<(usize, usize)> {
        let Self { bits, off, x, end } = *self;
        if x > end {
            return None;
        }
        let (s, e) = match bits {
            None => (x, end),
            Some(bits) => {
                let s = Self::find(bits, x, end, true)?;
                (s, Self::find(bits, s, end, false).map_or(end, |z| z - 1))
            }
        };
        self.x = e + 1;
        Some((s + off, e + off))
    }
}

/// Which cells of a rect lie open to an individual (see [`in_sight`]): bit `x % 64` of word
/// `y * words + x / 64` is the rect-local cell (x, y); `None` when every cell is open.
#[derive(Clone, Debug)]
pub(crate) struct Sight {
    pub(crate) words: usize,
    pub(crate) bits: Option<Vec<u64>>,
}

impl Sight {
    /// The bit row of rect-local row `y`, `None` when every cell is open.
    pub(crate) fn row(&self, y: usize) -> Option<&[u64]> {
        self.bits.as_ref().map(|b| &b[y * self.words..(y + 1) * self.words])
    }

    /// Whether the rect-local cell (x, y) is open.
    #[cfg(test)]
    pub(crate) fn is_open(&self, x: usize, y: usize) -> bool {
        self.row(y).is_none_or(|r| r[x / 64] >> (x % 64) & 1 == 1)
    }
}

/// The non-obstacle cells of a cost grid as bit rows (bit `x % 64` of word
/// `y * words + x / 64` is cell (x, y)), built once per static map for [`in_sight`].
#[derive(Clone, Debug)]
pub(crate) struct FreeBits {
    words: usize,
    bits: Vec<u64>,
}

impl FreeBits {
    pub(crate) fn of(grid: &CostGrid) -> Self {
        let spec = &grid.spec;
        let words = spec.width.div_ceil(64);
        let mut bits = vec![0u64; words * spec.height];
        for iy in 0..spec.height {
            let row = &grid.cost[spec.index(0, iy)..spec.index(0, iy) + spec.width];
            for (j, chunk) in row.chunks(64).enumerate() {
                bits[iy * words + j] =
                    chunk.iter().enumerate().fold(0u64, |m, (x, &c)| m | (u64::from(c < LETHAL) << x));
            }
        }
        FreeBits { words, bits }
    }

    /// Writes the bits of the cells `a0 .. a0 + w` of row `iy` to `out` (`w.div_ceil(64)` words,
    /// the bits past `w` cleared); whether all `w` cells are free.
    fn row_into(&self, iy: usize, a0: usize, w: usize, out: &mut [u64]) -> bool {
        let src = &self.bits[iy * self.words..(iy + 1) * self.words];
        let r = a0 % 64;
        let mut all = true;
        for (j, o) in out.iter_mut().enumerate() {
            let q = a0 / 64 + j;
            let lo = src.get(q).copied().unwrap_or(0) >> r;
            let hi = if r > 0 { src.get(q + 1).copied().unwrap_or(0) << (64 - r) } else { 0 };
            let n = (w - 64 * j).min(64);
            let valid = if n == 64 { u64::MAX } else { (1u64 << n) - 1 };
            *o = (lo | hi) & valid;
            all &= *o == valid;
        }
        all
    }
}

/// The bit rows [`in_sight`] walks on, kept by the map between individuals (no allocation per
/// individual).
#[derive(Clone, Debug, Default)]
pub(crate) struct SightScratch {
    free: Vec<u64>,
    visited: Vec<u64>,
    layer: Vec<u64>,
    spread: Vec<u64>,
    /// The same rows as single `u128`s, for rects at most 128 cells wide (see [`walk_narrow`]).
    narrow: [Vec<u128>; 3],
    /// The hulls of [`spread_hulls`], per layer.
    hulls: Vec<[i64; 4]>,
}

/// Whether a walk of `k` steps to a cell `dx`, `dy` cells from the centre is longer than its
/// straight-line distance plus [`SIGHT_SLACK`]: the cell is reached only the long way round. The
/// test in floating point, as the reference walk makes it.
pub(crate) fn too_long(k: u64, dx: u64, dy: u64) -> bool {
    let (dx, dy) = (dx as f64, dy as f64);
    k as f64 > (dx * dx + dy * dy).sqrt() + SIGHT_SLACK
}

/// The largest `dx` with [`too_long`]`(k, dx, dy)`, `None` when there is none: the cells of a
/// row reached the long way round by a `k`-step walk are the ones within this half-width of the
/// centre's column.
///
/// With `m = k - 2`, [`too_long`] holds exactly when `dx^2 + dy^2 < m^2`, as long as
/// `m <= 2^20`; so the half-width is `isqrt(m^2 - dy^2 - 1)`. Proof, with `d2 = dx^2 + dy^2` and
/// `fl` the rounding to nearest double:
/// - `d2 >= m^2`: `fl(d2) >= m^2` (rounding is monotone and `m^2` a double), so the rounded
///   square root is `>= m` and the rounded sum `>= m + 2 = k`: not too long.
/// - `d2 <= m^2 - 1 < 2^40`: `d2` is exact and `sqrt(d2) <= sqrt(m^2 - 1) < m - 1/(2m)`; the
///   square root and the sum round by at most half an ulp each, both below `2^-32` for values
///   below `2^21`, far less than the gap `1/(2m) >= 2^-21`: the rounded sum stays below `m + 2 = k`,
///   too long.
///
/// For `k <= 2` nothing is too long (`k > sqrt(d2) + 2` needs `k > 2`). Beyond `m = 2^20` (a walk
/// of a million steps) the half-width is found with the test itself, which is monotone in `dx`
/// (each rounded step of it is a non-decreasing function of `dx`).
pub(crate) fn long_way_half_width(k: u64, dy: u64) -> Option<u64> {
    let m = k.checked_sub(2)?;
    if m <= 1 << 20 {
        return Some(isqrt((m * m).checked_sub(dy * dy + 1)?));
    }
    if !too_long(k, 0, dy) {
        return None;
    }
    let mut a = (m * m).saturating_sub(dy.saturating_mul(dy).saturating_add(1)).isqrt();
    while too_long(k, a + 1, dy) {
        a += 1;
    }
    while a > 0 && !too_long(k, a, dy) {
        a -= 1;
    }
    Some(a)
}

/// The integer square root of `t <= 2^40` (the rounded square root, then made exact).
fn isqrt(t: u64) -> u64 {
    let mut a = (t as f64).sqrt() as u64;
    while a * a > t {
        a -= 1;
    }
    while (a + 1) * (a + 1) <= t {
        a += 1;
    }
    a
}

/// The bits of word `j` (cells `64 j ..= 64 j + 63`) of the cells `x0 ..= x1`.
fn span_bits(j: usize, x0: usize, x1: usize) -> u64 {
    let (lo, hi) = (x0.max(64 * j), x1.min(64 * j + 63));
    if lo > hi {
        return 0;
    }
    (u64::MAX >> (63 - (hi - 64 * j))) & (u64::MAX << (lo - 64 * j))
}

/// Which cells of `rect` lie open to `centre`: reached from the centre's cell by a
/// breadth-first walk over non-obstacle cells (8-connected) in at most the straight-line
/// distance in cells plus [`SIGHT_SLACK`] steps. A cell behind a wall is reached only around it,
/// in more steps, so a person's zones stop at the walls of the room they are in instead of
/// spreading into the next room or corridor (where they would push the robot's path away from
/// people it cannot even see). Every cell is open when the centre lies outside the rect or on an
/// obstacle. `scratch` holds the walk's bit rows.
///
/// Only the cells within `reach` cells of the centre's cell (straight line, e.g. from
/// the social cost map's `zone_reach`; infinite for all) are decided, the others may come out either way: a cell
/// within reach is in sight only when the walk reaches it in at most `reach + SIGHT_SLACK` steps,
/// so the walk stops after that many layers, and when no obstacle lies within that many steps of
/// the centre (Chebyshev distance, where those layers stay) every cell within reach is open.
/// With `zone` (the spans of the rect's rows, in order, e.g. from the social cost map's `zone_spans`) only the
/// spans' cells within reach need to be decided: a rect at most 128 cells wide is walked only
/// where a span's cell can still be reached in sight (see [`spread_hulls`]).
pub(crate) fn in_sight(
    grid: &CostGrid,
    free_bits: &FreeBits,
    centre: Vec2,
    rect: Rect,
    reach: f64,
    zone: Option<&[Span]>,
    scratch: &mut SightScratch,
) -> Sight {
    let spec = &grid.spec;
    let (a0, b0, a1, b1) = rect;
    let (w, h) = (a1 + 1 - a0, b1 + 1 - b0);
    let words = w.div_ceil(64);
    let all = Sight { words, bits: None };
    let res = spec.resolution;
    let cx = ((centre.x - spec.origin.x) / res).floor();
    let cy = ((centre.y - spec.origin.y) / res).floor();
    let inside = cx >= a0 as f64 && cx <= a1 as f64 && cy >= b0 as f64 && cy <= b1 as f64;
    if !inside || grid.cost[spec.index(cx as usize, cy as usize)] >= LETHAL {
        return all;
    }
    let (sx, sy) = (cx as usize - a0, cy as usize - b0);
    // Breadth-first, one layer (walk length) at a time, on bit rows (as in [`Sight`]). Only the
    // cells of a layer that are in sight expand to the next layer (the free, unvisited
    // 8-neighbours of them).
    let SightScratch { free, visited, layer, spread, narrow, hulls } = scratch;
    let n = words * h;
    for v in [&mut *free, &mut *visited, &mut *layer] {
        v.clear();
        v.resize(n, 0);
    }
    // `spread` has two zero rows above and below the layer's rows (row `y` at `y + 2`).
    spread.clear();
    spread.resize(n + 4 * words, 0);
    // The last layer that can open a cell within reach.
    let last = (reach + SIGHT_SLACK).floor().min(1e9) as usize;
    let (x0, x1) = (sx.saturating_sub(last), sx.saturating_add(last).min(w - 1));
    let mut blocked = false;
    for y in 0..h {
        let row = &mut free[y * words..(y + 1) * words];
        if !free_bits.row_into(b0 + y, a0, w, row) && y.abs_diff(sy) <= last {
            blocked |= (x0 / 64..=x1 / 64).any(|j| !row[j] & span_bits(j, x0, x1) != 0);
        }
    }
    // Without an obstacle within `last` steps of the centre the walk to every cell it reaches in
    // `last` steps is its Chebyshev distance, never longer than the straight line: every cell
    // within reach is open, no walk needed.
    if !blocked {
        return all;
    }
    let mut open = vec![0u64; n];
    if words <= 2 {
        let hulls = zone.map(|spans| {
            spread_hulls(spans, a0, (sx, sy), last, hulls);
            &hulls[..]
        });
        walk_narrow(free, narrow, hulls, words, (sx, sy), last, &mut open);
        return Sight { words, bits: Some(open) };
    }
    layer[sy * words + sx / 64] = 1 << (sx % 64);
    visited[sy * words + sx / 64] = 1 << (sx % 64);
    let (mut lo, mut hi) = (sy, sy); // the rows the current layer occupies
    let mut k = 0u64;
    while k <= last as u64 {
        // The layer's cells in sight (all but those within the long-way half-width of the
        // centre's column), spread to their row neighbours in place.
        for y in lo..=hi {
            let (r, p) = (y * words, (y + 2) * words);
            let cells = &mut layer[r..r + words];
            if cells.iter().all(|&b| b == 0) {
                spread[p..p + words].fill(0);
                continue;
            }
            let m = usize::try_from(k.saturating_sub(2)).unwrap_or(usize::MAX);
            // The half-width is below `m`: a row without cells nearer the centre's column skips it.
            let near = m > 0
                && cells
                    .iter()
                    .enumerate()
                    .any(|(j, &b)| b & span_bits(j, sx.saturating_sub(m - 1), sx + (m - 1)) != 0);
            if let Some(a) = long_way_half_width(k, y.abs_diff(sy) as u64).filter(|_| near) {
                let a = usize::try_from(a).unwrap_or(usize::MAX);
                let (x0, x1) = (sx.saturating_sub(a), sx.saturating_add(a));
                for (j, b) in cells.iter_mut().enumerate() {
                    *b &= !span_bits(j, x0, x1);
                }
            }
            for j in 0..words {
                open[r + j] |= layer[r + j];
            }
            let mut west = 0u64;
            for j in 0..words {
                let e = layer[r + j];
                let east = if j + 1 < words { layer[r + j + 1] } else { 0 };
                spread[p + j] = e | (e << 1) | (west >> 63) | (e >> 1) | (east << 63);
                west = e;
            }
        }
        // The next layer, written over this one (read no more): the free, unvisited cells of
        // the spread rows and the rows above and below them.
        spread[lo * words..(lo + 2) * words].fill(0);
        spread[(hi + 3) * words..(hi + 5) * words].fill(0);
        let (nlo, nhi) = (lo.saturating_sub(1), (hi + 1).min(h - 1));
        let (mut first, mut last) = (usize::MAX, 0);
        for y in nlo..=nhi {
            let mut row_any = 0u64;
            for j in 0..words {
                let p = (y + 2) * words + j;
                let acc = spread[p - words] | spread[p] | spread[p + words];
                let i = y * words + j;
                let fresh = acc & free[i] & !visited[i];
                visited[i] |= fresh;
                layer[i] = fresh;
                row_any |= fresh;
            }
            if row_any != 0 {
                first = first.min(y);
                last = y;
            }
        }
        if first > last {
            break;
        }
        (lo, hi) = (first, last);
        k += 1;
    }
    Sight { words, bits: Some(open) }
}

/// The walk of [`in_sight`] for a rect at most 128 cells wide (`words` 1 or 2), one `u128` per
/// row: `free` the rect's free cells (bit rows of `words` words), `start` the centre's cell; adds
/// the cells in sight to `open` (bit rows of `words` words). The same steps as the general walk,
/// each layer in two passes over its rows: the first cuts the rows near the centre's column to
/// their cells in sight, the second spreads every row to its neighbours and keeps the free cells
/// not yet visited (one row of those, `avail`, stands for the free and the visited rows). A cell
/// is in sight when the layer that reached it did not cut it, so the open cells are the visited
/// ones (free, no longer available) less the cut ones, gathered once at the end. The walk stops
/// after layer `last`. With `hulls` (from [`spread_hulls`]) the cells of layer `k` outside
/// `hulls[k + 1]` do not spread.
fn walk_narrow(
    free: &[u64],
    rows: &mut [Vec<u128>; 3],
    hulls: Option<&[[i64; 4]]>,
    words: usize,
    start: (usize, usize),
    last: usize,
    open: &mut [u64],
) {
    let h = free.len() / words;
    let (sx, sy) = start;
    let [avail, layer, cut] = rows;
    let row = |r: &[u64]| u128::from(r[0]) | r.get(1).map_or(0, |&hi| u128::from(hi) << 64);
    avail.clear();
    avail.extend(free.chunks_exact(words).map(row));
    for v in [&mut *layer, &mut *cut] {
        v.clear();
        v.resize(h, 0);
    }
    // The cells `x - a ..= x + a` (within the row).
    let span = |x: usize, a: usize| {
        let (lo, hi) = (x.saturating_sub(a), x.saturating_add(a).min(127));
        (u128::MAX >> (127 - hi)) & (u128::MAX << lo)
    };
    layer[sy] = 1 << sx;
    avail[sy] &= !(1 << sx);
    // The rows of the current layer are `lo ..= hi`; only those are read (the others may hold
    // cells of earlier layers).
    let (mut lo, mut hi) = (sy, sy);
    let mut k = 0u64;
    loop {
        if k > last as u64 {
            // Past the last layer: its cells are not visited (nor open).
            for y in lo..=hi {
                avail[y] |= layer[y];
            }
            break;
        }
        // The layer's rows cut to their cells in sight: only the rows less than `m` from the
        // centre's have a long-way half-width (below `m`: a row without cells nearer the
        // centre's column keeps all).
        let m = usize::try_from(k.saturating_sub(2)).unwrap_or(usize::MAX);
        if m > 0 {
            let near = span(sx, m - 1);
            for y in lo.max(sy.saturating_sub(m - 1))..=hi.min(sy.saturating_add(m - 1)) {
                let e = layer[y];
                if e & near != 0
                    && let Some(a) = long_way_half_width(k, y.abs_diff(sy) as u64)
                {
                    let c = e & span(sx, usize::try_from(a).unwrap_or(usize::MAX));
                    cut[y] |= c;
                    layer[y] = e & !c;
                }
            }
        }
        // The rows `slo ..= shi` and columns `cols` of the layer's cells that spread: all, or
        // those within the layer's hull.
        let (slo, shi, cols) = match hulls {
            None => (lo, hi, u128::MAX),
            Some(hulls) => {
                let [r0, r1, c0, c1] = hulls.get(k as usize + 1).copied().unwrap_or(EMPTY_HULL);
                let k = k as i64;
                let (slo, shi) = ((r0 + k).max(lo as i64), (r1 - k).min(hi as i64));
                let (clo, chi) = ((c0 + k).max(0), (c1 - k).min(127));
                if slo > shi || clo > chi {
                    break;
                }
                let cols = (u128::MAX >> (127 - chi)) & (u128::MAX << clo);
                (slo as usize, shi as usize, cols)
            }
        };
        // Layer row spread to its row neighbours.
        let spread = |e: u128| {
            let e = e & cols;
            e | (e << 1) | (e >> 1)
        };
        let (nlo, nhi) = (slo.saturating_sub(1), (shi + 1).min(h - 1));
        let (mut first, mut last) = (usize::MAX, 0);
        // The spread rows above, at and below `y` (rows outside `slo ..= shi` do not spread).
        let (mut above, mut at) = (0u128, if nlo < slo { 0 } else { spread(layer[slo]) });
        for y in nlo..=nhi {
            let below = if y < shi { spread(layer[y + 1]) } else { 0 };
            let fresh = (above | at | below) & avail[y];
            avail[y] ^= fresh;
            layer[y] = fresh;
            if fresh != 0 {
                first = first.min(y);
                last = y;
            }
            (above, at) = (at, below);
        }
        if first > last {
            break;
        }
        (lo, hi) = (first, last);
        k += 1;
    }
    for (y, (&a, &c)) in avail.iter().zip(cut.iter()).enumerate() {
        let o = row(&free[y * words..(y + 1) * words]) & !a & !c;
        open[y * words] |= o as u64;
        if words == 2 {
            open[y * words + 1] |= (o >> 64) as u64;
        }
    }
}

/// Per layer `k` of [`walk_narrow`], the hull of the cells that can still lead
/// to a cell of `spans` (the spans of the rect's rows, columns from `a0`) in sight: rows
/// `r0 + k ..= r1 - k` and rect columns `c0 + k ..= c1 - k` of `hulls[k + 1] = [r0, r1, c0, c1]`
/// (empty when `r0 > r1`, and past the end of `hulls`). Only the cells of layer `k` in it need to
/// spread.
///
/// Why the spans' cells come out the same. Let `A(y)` be the largest layer at which a cell of
/// row `y`'s span can be open: at most `last`, and at most the largest `k` with
/// `!too_long(k, dx, dy)` for the span's farthest `dx` from the centre's column, since that
/// test's rounded steps are all non-decreasing in `dx`, so it holds for every nearer cell of the
/// span at the same `k`. The hull of layer `k` is that of the rectangles `y - (A - k) ..= y + (A - k)`
/// by `l - (A - k) ..= r + (A - k)` over the spans `(l, r)` of the rows `y` with `A(y) >= k + 1`.
/// Write `d(v)` for the layer at which the plain walk reaches `v` and `d'(v)` for the pruned one.
/// - `d' >= d` everywhere: if `v` is reached at `d'(v) = j + 1` from `u` that spread at
///   `d'(u) = j`, then `u` was not cut at `j`, so (by induction `d(u) <= j`, and a cell not cut at
///   a layer is not cut at an earlier one) not cut at `d(u)` in the plain walk either, where it
///   spread: `d(v) <= d(u) + 1 <= j + 1`.
/// - A span's cell `c` open in the plain walk, `n = d(c) <= A(c_y)`: take a plain walk's path
///   `v_0 .. v_n = c` with `d(v_i) = i`, every `v_i` (`i < n`) spread. Then `i + 1 <= n <= A(c_y)`
///   and `v_i` lies within `n - i <= A(c_y) - i` cells of `c` (Chebyshev) in rows and columns, so
///   in the hull of layer `i`; by induction `d'(v_i) = i` (`>= d` above, and `v_{i-1}` spread
///   in the pruned walk too, not cut at the same layer) and `v_i` spreads: `d'(c) = n`, open.
/// - A span's cell not open in the plain walk is reached at a layer past `last` or cut at
///   `d(c)`; `d'(c) >= d(c)`, so it is again past `last` or cut (a later layer cuts too).
///
/// The other cells may come out either way.
fn spread_hulls(spans: &[Span], a0: usize, start: (usize, usize), last: usize, hulls: &mut Vec<[i64; 4]>) {
    hulls.clear();
    let (sx, sy) = start;
    for (y, span) in spans.iter().enumerate() {
        let Some((l, r)) = *span else { continue };
        let (l, r) = (l - a0, r - a0);
        // The largest `k` with `!too_long(k, dx, dy)`: `k <= sqrt(dx^2 + dy^2) + SIGHT_SLACK`.
        let (dx, dy) = (sx.abs_diff(l).max(sx.abs_diff(r)) as f64, y.abs_diff(sy) as f64);
        let a = ((dx * dx + dy * dy).sqrt() + SIGHT_SLACK).floor().min(last as f64) as usize;
        let (y, l, r, ai) = (y as i64, l as i64, r as i64, a as i64);
        if hulls.len() < a + 2 {
            hulls.resize(a + 2, EMPTY_HULL);
        }
        let h = &mut hulls[a];
        *h = [h[0].min(y - ai), h[1].max(y + ai), h[2].min(l - ai), h[3].max(r + ai)];
    }
    for a in (0..hulls.len().saturating_sub(1)).rev() {
        let n = hulls[a + 1];
        let h = &mut hulls[a];
        *h = [h[0].min(n[0]), h[1].max(n[1]), h[2].min(n[2]), h[3].max(n[3])];
    }
}

/// The empty hull of [`spread_hulls`].
const EMPTY_HULL: [i64; 4] = [i64::MAX / 4, i64::MIN / 4, i64::MAX / 4, i64::MIN / 4];

/// Steps (cells) a walk to a cell may take beyond its straight-line distance and still count
/// as in sight (see [`in_sight`]): the 8-connected walk is never longer than the straight line
/// in open space, so the slack only absorbs the grid's staircase along walls and doorposts.
pub(crate) const SIGHT_SLACK: f64 = 2.0;

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::map::cost_grid::INSCRIBED;
    use crate::map::geometry::Bounds;
    use crate::map::grid::GridSpec;

    fn grid(w: f64, h: f64) -> CostGrid {
        let spec =
            GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(w, h) }, 0.1).expect("valid grid");
        CostGrid { spec, cost: vec![0; spec.len()] }
    }

    /// The walk of [`in_sight`] as first written (a queue of cell pairs, every cell walked), the
    /// reference its faster form must match cell for cell.
    pub(crate) fn in_sight_reference(grid: &CostGrid, centre: Vec2, rect: Rect) -> Vec<bool> {
        let spec = &grid.spec;
        let (a0, b0, a1, b1) = rect;
        let (w, h) = (a1 + 1 - a0, b1 + 1 - b0);
        let res = spec.resolution;
        let cx = ((centre.x - spec.origin.x) / res).floor();
        let cy = ((centre.y - spec.origin.y) / res).floor();
        let inside = cx >= a0 as f64 && cx <= a1 as f64 && cy >= b0 as f64 && cy <= b1 as f64;
        if !inside || grid.cost[spec.index(cx as usize, cy as usize)] >= LETHAL {
            return vec![true; w * h];
        }
        let (sx, sy) = (cx as usize - a0, cy as usize - b0);
        let mut steps = vec![u16::MAX; w * h];
        let mut open = vec![false; w * h];
        let mut queue = std::collections::VecDeque::new();
        steps[sy * w + sx] = 0;
        queue.push_back((sx, sy));
        while let Some((x, y)) = queue.pop_front() {
            let k = steps[y * w + x];
            let (dx, dy) = (x as f64 - sx as f64, y as f64 - sy as f64);
            if f64::from(k) > (dx * dx + dy * dy).sqrt() + SIGHT_SLACK {
                continue;
            }
            open[y * w + x] = true;
            for (ox, oy) in [(-1i64, -1i64), (0, -1), (1, -1), (-1, 0), (1, 0), (-1, 1), (0, 1), (1, 1)] {
                let (nx, ny) = (x as i64 + ox, y as i64 + oy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let (nx, ny) = (nx as usize, ny as usize);
                let j = ny * w + nx;
                if steps[j] != u16::MAX || grid.cost[spec.index(a0 + nx, b0 + ny)] >= LETHAL {
                    continue;
                }
                steps[j] = k + 1;
                queue.push_back((nx, ny));
            }
        }
        open
    }

    #[test]
    fn in_sight_matches_the_reference_walk() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
        let mut scratch = SightScratch::default();
        for case in 0..2000 {
            let mut g = grid(16.0, 9.0);
            // Random wall segments and blocks, some cases with none (the open fast path).
            let walls = if case % 5 == 0 { 0 } else { rng.random_range(1..8) };
            for _ in 0..walls {
                let (x, y) = (rng.random_range(0..g.spec.width), rng.random_range(0..g.spec.height));
                let (len, vertical) = (rng.random_range(1..60), rng.random_bool(0.5));
                for t in 0..len {
                    let (ix, iy) = if vertical { (x, y + t) } else { (x + t, y) };
                    if ix < g.spec.width && iy < g.spec.height {
                        let i = g.spec.index(ix, iy);
                        g.cost[i] = if rng.random_bool(0.9) { LETHAL } else { INSCRIBED };
                    }
                }
            }
            let (x0, y0) = (rng.random_range(0..g.spec.width), rng.random_range(0..g.spec.height));
            let rect = (
                x0,
                y0,
                (x0 + rng.random_range(0..150)).min(g.spec.width - 1),
                (y0 + rng.random_range(0..80)).min(g.spec.height - 1),
            );
            // Mostly a centre inside the rect (the walk), sometimes anywhere.
            let c = if case % 7 == 0 {
                Vec2::new(rng.random_range(-0.5..16.5), rng.random_range(-0.5..9.5))
            } else {
                let cell = (rng.random_range(rect.0..=rect.2), rng.random_range(rect.1..=rect.3));
                g.spec.center(cell.0, cell.1)
            };
            // Half the cases decide every cell, the others only those within a random reach; and
            // in half of either, only the cells of random row spans (some rows without).
            let reach = if case % 2 == 0 { f64::INFINITY } else { rng.random_range(0.0..60.0) };
            let (w, h) = (rect.2 + 1 - rect.0, rect.3 + 1 - rect.1);
            let spans: Vec<Span> = (0..h)
                .map(|_| {
                    let l = rng.random_range(rect.0..=rect.2);
                    let r = (l + rng.random_range(0..8)).min(rect.2);
                    rng.random_bool(0.3).then_some((l, r))
                })
                .collect();
            let zone = (case % 4 >= 2).then_some(&spans[..]);
            let sight = in_sight(&g, &FreeBits::of(&g), c, rect, reach, zone, &mut scratch);
            let res = g.spec.resolution;
            let (sx, sy) = (((c.x - g.spec.origin.x) / res).floor(), ((c.y - g.spec.origin.y) / res).floor());
            let within = |i: usize| {
                let (x, y) = (rect.0 + i % w, i / w);
                let (dx, dy) = (x as f64 - sx, (rect.1 + y) as f64 - sy);
                let spanned = zone.is_none_or(|z| z[y].is_some_and(|(l, r)| (l..=r).contains(&x)));
                (dx * dx + dy * dy).sqrt() <= reach && spanned
            };
            // The cells decided as the reference walk decides them, the others as they came.
            let want: Vec<bool> = in_sight_reference(&g, c, rect)
                .into_iter()
                .enumerate()
                .map(|(i, open)| if within(i) { open } else { sight.is_open(i % w, i / w) })
                .collect();
            let bits: Vec<bool> = (0..w * h).map(|i| sight.is_open(i % w, i / w)).collect();
            assert_eq!(bits, want, "case {case}");
        }
    }

    #[test]
    fn long_way_half_width_is_the_float_test() {
        // Every small walk length and row against the floating-point test of the reference
        // walk, and walks around the 2^20 steps where the integer formula hands over.
        for k in 0..160u64 {
            for dy in 0..160u64 {
                let a = long_way_half_width(k, dy);
                for dx in 0..170u64 {
                    assert_eq!(too_long(k, dx, dy), a.is_some_and(|a| dx <= a), "k {k} dy {dy} dx {dx}");
                }
            }
        }
        for k in [(1u64 << 20) - 3, (1 << 20) + 2, (1 << 20) + 3, (1 << 20) + 7, 3 << 20] {
            for dy in [0u64, 1, 17, 1000, 654_321, (1 << 20) - 1, 1 << 20, 2 << 20] {
                match long_way_half_width(k, dy) {
                    Some(a) => assert!(too_long(k, a, dy) && !too_long(k, a + 1, dy), "k {k} dy {dy}"),
                    None => assert!(!too_long(k, 0, dy), "k {k} dy {dy}"),
                }
            }
        }
    }
}
