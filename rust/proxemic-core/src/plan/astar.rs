//! The one 8-connected A* of `docs/algorithms.md` §5 (plain, cost-aware, Dijkstra) on a
//! [`CostGrid`].
//!
//! Conventions:
//! - cell costs are `u8`: 0 free, 1..=252 graded cost, [`INSCRIBED`] (253) and [`LETHAL`] (254)
//!   impassable (anything `>= INSCRIBED`, including 255, is impassable);
//! - moving from a cell to one of its 8 neighbours costs `len * res * (1 + w * c_to / 252)` metres,
//!   with `len` 1 (orthogonal) or sqrt(2) (diagonal) and `c_to` the cost of the cell entered;
//! - a diagonal move needs both orthogonal cells it passes between to be passable (no corner
//!   cutting);
//! - neighbours are generated in the fixed order E, W, N, S, NE, NW, SE, SW (`+x` is east, `+y`
//!   north), and the open list breaks ties in `f` on the larger `g` (compared to 25 mantissa bits),
//!   then on the smaller cell index, so a search is a pure function of its inputs;
//! - the open list is a ring of buckets over `f` (width: 1/512 of the largest step of `f` per
//!   move) whose current bucket is an exact 4-ary heap, with lazy deletion: a popped entry whose
//!   cell is already closed (a bitset) is skipped, and the entries of closed cells are dropped
//!   when their bucket is taken into the heap (most stale entries never reach the heap).

use crate::map::cost_grid::{CostGrid, INSCRIBED, LETHAL, MAX_PASSABLE};
use crate::map::grid::GridSpec;
use crate::math::Vec2;
use crate::plan::open_list::{IDX_BITS, OpenList, open_entry, open_index};

/// How [`PathPlanner::plan`] weighs cost and guides the search.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchMode {
    /// Cost multiplier `w` in `len * res * (1 + w * c / 252)`: 0 = plain (binary) A*, 2.0 is the
    /// social default (like Nav2 Smac). Must be finite and `>= 0`; keep it `<= 5`.
    pub weight: f64,
    /// `true` for A* with the octile heuristic, `false` for Dijkstra (heuristic 0).
    pub heuristic: bool,
}

impl SearchMode {
    /// Plain A*: binary passability, weight 0.
    pub const PLAIN: SearchMode = SearchMode { weight: 0.0, heuristic: true };

    /// Cost-aware A* with the given weight.
    pub fn weighted(weight: f64) -> Self {
        Self { weight, heuristic: true }
    }

    /// Dijkstra with the given weight (the optimality oracle).
    pub fn dijkstra(weight: f64) -> Self {
        Self { weight, heuristic: false }
    }
}

/// A path on the grid.
#[derive(Clone, Debug, PartialEq)]
pub struct GridPath {
    /// Cells from start to goal inclusive; consecutive cells are 8-neighbours.
    pub cells: Vec<(usize, usize)>,
    /// Total cost (metres-equivalent): the sum over moves of `len * res * (1 + w * c_to / 252)`.
    pub cost: f64,
    /// Number of cells expanded (popped and closed) by the search.
    pub expansions: usize,
}

/// Octile distance in cells between `(ax, ay)` and `(bx, by)` (coordinates below 2^32).
#[inline]
fn octile(ax: usize, ay: usize, bx: usize, by: usize) -> f64 {
    // Differences below 2^32 convert exactly, and from `u32` in one instruction (x86-64 has no
    // direct conversion from a 64-bit unsigned integer).
    let (dx, dy) = (ax.abs_diff(bx) as u32, ay.abs_diff(by) as u32);
    let (lo, hi) = (f64::from(dx.min(dy)), f64::from(dx.max(dy)));
    hi + (std::f64::consts::SQRT_2 - 1.0) * lo
}

/// Cost (metres-equivalent) of one move of `len` cells into a cell of cost `c_to` (test reference).
#[cfg(test)]
pub(crate) fn step_cost(len: f64, res: f64, weight: f64, c_to: u8) -> f64 {
    len * res * (1.0 + weight * f64::from(c_to) / MAX_PASSABLE)
}

/// The reached and closed bits of 64 consecutive cells (bit `i % 64` for cell `i`).
#[derive(Clone, Copy, Debug, Default)]
struct Flags {
    reached: u64,
    closed: u64,
}

/// The grid search, with its per-cell buffers kept across calls.
///
/// The per-cell `g` and parent buffers are sized to the largest grid seen and never cleared: a
/// cell's entries are valid only if its bit in the reached bitset is set. The reached and closed
/// sets are bitsets (one bit a cell, small enough to stay in cache), cleared per call and
/// interleaved word by word (`Flags`), so one load serves both tests of a neighbour: stale
/// open-list entries, closed neighbours and first visits are told apart without touching the
/// per-cell buffers, and a relaxation reads 8 bytes of `g` (not a 16-byte node) only for a cell
/// already reached, which keeps the search's working set small on large grids.
#[derive(Debug, Default)]
pub struct PathPlanner {
    /// Cost from the start of each cell (valid where `reached` is set).
    g: Vec<f64>,
    /// The cell each cell was reached from (valid where `reached` is set).
    parent: Vec<u32>,
    /// Cells reached and closed in the current search: bit `i % 64` of entry `i / 64`.
    flags: Vec<Flags>,
    heap: OpenList,
}

impl PathPlanner {
    /// An empty planner; buffers grow on first use.
    pub fn new() -> Self {
        Self::default()
    }

    /// Plans from `start` to `goal` (cell indices) on `grid`.
    ///
    /// Returns `None` if `start` or `goal` is outside the grid, if `goal` is impassable (relocate it
    /// first with [`nearest_passable`]), if `mode.weight` is not finite and `>= 0`, if the grid's
    /// cost buffer does not match its spec, or if the goal is unreachable. The start cell may be
    /// impassable (the robot is allowed to leave it). `start == goal` gives a one-cell path of cost
    /// 0.
    ///
    /// The result is optimal for the edge cost in the module docs (A* with the octile heuristic
    /// times `res`, which is admissible and consistent because every move costs at least its
    /// length). Deterministic: see the module docs for the tie-break rules.
    pub fn plan(
        &mut self,
        grid: &CostGrid,
        start: (usize, usize),
        goal: (usize, usize),
        mode: SearchMode,
    ) -> Option<GridPath> {
        let spec = grid.spec;
        let n = spec.len();
        if grid.cost.len() != n
            || n >= 1usize << IDX_BITS
            || !spec.contains_cell(start.0, start.1)
            || !grid.passable(goal.0, goal.1)
            || !(mode.weight.is_finite() && mode.weight >= 0.0)
        {
            return None;
        }
        // One copy of the search for each mode: Dijkstra's carries no heuristic code at all.
        if mode.heuristic {
            self.search::<true>(grid, start, goal, mode.weight)
        } else {
            self.search::<false>(grid, start, goal, mode.weight)
        }
    }

    /// The search of [`PathPlanner::plan`] on checked arguments, with the octile heuristic if
    /// `HEURISTIC` (Dijkstra otherwise).
    fn search<const HEURISTIC: bool>(
        &mut self,
        grid: &CostGrid,
        start: (usize, usize),
        goal: (usize, usize),
        weight: f64,
    ) -> Option<GridPath> {
        let spec = grid.spec;
        let n = spec.len();
        self.begin(n);
        let (w, h) = (spec.width, spec.height);
        let res = spec.resolution;
        // Per-move cost: len * factor[c] with factor[c] = res * (1 + weight * c / 252).
        let mut factor = [0.0f64; 256];
        for (c, f) in factor.iter_mut().enumerate() {
            *f = res * (1.0 + weight * c as f64 / MAX_PASSABLE);
        }
        let s_idx = spec.index(start.0, start.1);
        let goal_idx = spec.index(goal.0, goal.1);
        let (gx, gy) = goal;
        // A macro, not a closure, so that it is always inlined.
        macro_rules! heur {
            ($ix:expr, $iy:expr) => {
                if HEURISTIC { octile($ix, $iy, gx, gy) * res } else { 0.0 }
            };
        }

        let gs = &mut self.g[..n];
        let parent = &mut self.parent[..n];
        let flags = &mut self.flags[..n.div_ceil(64)];
        let heap = &mut self.heap;
        gs[s_idx] = 0.0;
        parent[s_idx] = s_idx as u32;
        flags[s_idx / 64].reached |= 1u64 << (s_idx % 64);
        let f0 = heur!(start.0, start.1);
        // f grows per push by at most the dearest move plus the heuristic's change over a move
        // (octile is 1-Lipschitz): sqrt(2) res (1 + w) + sqrt(2) res.
        heap.reset(std::f64::consts::SQRT_2 * res * (2.0 + weight), f0);
        heap.push(open_entry(f0, 0.0, s_idx as u32), f0);
        let mut expansions = 0usize;
        let cost = &grid.cost[..n];
        // Cell indices and the width fit in 32 bits (n < 2^27): the coordinates of a popped cell
        // come from a 32-bit division.
        let w32 = w as u32;

        while let Some(entry) = heap.pop(|i| flags[i / 64].closed & (1u64 << (i % 64)) != 0) {
            let cur = open_index(entry);
            // An entry is stale (lazy deletion) if its cell is closed; otherwise the cell's current
            // g is the one its freshest entry was pushed with, and any older entry for the same
            // cell carries a larger f and pops after it, finding the cell closed.
            let (word, bit) = (cur / 64, 1u64 << (cur % 64));
            if flags[word].closed & bit != 0 {
                continue;
            }
            flags[word].closed |= bit;
            let g = gs[cur];
            expansions += 1;
            if cur == goal_idx {
                return Some(Self::reconstruct(parent, &spec, s_idx, goal_idx, g, expansions));
            }
            let (cx, cy) = ((cur as u32 % w32) as usize, (cur as u32 / w32) as usize);
            // The costs of the orthogonal neighbours E, W, N, S (off the grid: impassable); each
            // cost is read once, for the passability tests and the move's cost.
            let ce = if cx + 1 < w { cost[cur + 1] } else { LETHAL };
            let cw = if cx > 0 { cost[cur - 1] } else { LETHAL };
            let cn = if cy + 1 < h { cost[cur + w] } else { LETHAL };
            let cs = if cy > 0 { cost[cur - w] } else { LETHAL };
            let (e, wst, nth, sth) = (ce < INSCRIBED, cw < INSCRIBED, cn < INSCRIBED, cs < INSCRIBED);
            // Relaxes the edge of length `len` cells into neighbour `ni` at `(nx, ny)`, of cost
            // `c` (a macro so that it is always inlined).
            macro_rules! relax {
                ($ni:expr, $c:expr, $nx:expr, $ny:expr, $len:expr) => {{
                    let ni: usize = $ni;
                    let (word, bit) = (ni / 64, 1u64 << (ni % 64));
                    let fl = &mut flags[word];
                    if fl.closed & bit == 0 {
                        let ng = g + $len * factor[usize::from($c)];
                        if fl.reached & bit == 0 || ng < gs[ni] {
                            fl.reached |= bit;
                            gs[ni] = ng;
                            parent[ni] = cur as u32;
                            let f = ng + heur!($nx, $ny);
                            heap.push(open_entry(f, ng, ni as u32), f);
                        }
                    }
                }};
            }
            if e {
                relax!(cur + 1, ce, cx + 1, cy, 1.0);
            }
            if wst {
                relax!(cur - 1, cw, cx - 1, cy, 1.0);
            }
            if nth {
                relax!(cur + w, cn, cx, cy + 1, 1.0);
            }
            if sth {
                relax!(cur - w, cs, cx, cy - 1, 1.0);
            }
            // Diagonals NE, NW, SE, SW: both orthogonal cells must be passable (no corner cutting).
            const D: f64 = std::f64::consts::SQRT_2;
            if nth && e {
                let c = cost[cur + w + 1];
                if c < INSCRIBED {
                    relax!(cur + w + 1, c, cx + 1, cy + 1, D);
                }
            }
            if nth && wst {
                let c = cost[cur + w - 1];
                if c < INSCRIBED {
                    relax!(cur + w - 1, c, cx - 1, cy + 1, D);
                }
            }
            if sth && e {
                let c = cost[cur - w + 1];
                if c < INSCRIBED {
                    relax!(cur - w + 1, c, cx + 1, cy - 1, D);
                }
            }
            if sth && wst {
                let c = cost[cur - w - 1];
                if c < INSCRIBED {
                    relax!(cur - w - 1, c, cx - 1, cy - 1, D);
                }
            }
        }
        None
    }

    /// Prepares the buffers for a search over `n` cells: nothing reached, nothing closed.
    fn begin(&mut self, n: usize) {
        if self.g.len() < n {
            self.g.resize(n, 0.0);
            self.parent.resize(n, 0);
        }
        let words = n.div_ceil(64);
        if self.flags.len() < words {
            self.flags.resize(words, Flags::default());
        }
        self.flags[..words].fill(Flags::default());
    }

    fn reconstruct(
        parent: &[u32],
        spec: &GridSpec,
        s_idx: usize,
        goal_idx: usize,
        cost: f64,
        expansions: usize,
    ) -> GridPath {
        let mut cells = vec![spec.cell(goal_idx)];
        let mut cur = goal_idx;
        // Every cell on the chain was reached in this search; the chain is at most n long.
        while cur != s_idx && cells.len() <= spec.len() {
            cur = parent[cur] as usize;
            cells.push(spec.cell(cur));
        }
        cells.reverse();
        GridPath { cells, cost, expansions }
    }
}

/// The passable cell nearest to `cell` (Euclidean distance in cells) among those within
/// `max_radius_cells` of it, or `None` if there is none. `cell` itself is returned if passable.
/// `cell` may lie outside the grid (only in-grid cells are candidates).
///
/// Deterministic: candidates are scanned in square rings of growing Chebyshev radius and the
/// search stops once no farther ring can hold a closer cell; ties in distance go to the smaller
/// `(iy, ix)` (row-major index).
pub fn nearest_passable(
    grid: &CostGrid,
    cell: (usize, usize),
    max_radius_cells: usize,
) -> Option<(usize, usize)> {
    let (cx, cy) = (cell.0 as i128, cell.1 as i128);
    let rmax = max_radius_cells as i128;
    let (w, h) = (grid.spec.width as i128, grid.spec.height as i128);
    let mut best: Option<(i128, i128, i128)> = None; // (d2, iy, ix)
    for r in 0..=rmax {
        if let Some((d2, _, _)) = best
            && d2 <= r * r
        {
            break; // every cell in ring r or beyond is at least r away
        }
        let y_lo = (cy - r).max(0);
        let y_hi = (cy + r).min(h - 1);
        let mut consider = |x: i128, y: i128| {
            if x < 0 || y < 0 || x >= w || y >= h {
                return;
            }
            let d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
            if d2 > rmax * rmax || !grid.passable(x as usize, y as usize) {
                return;
            }
            let key = (d2, y, x);
            if best.is_none_or(|b| key < b) {
                best = Some(key);
            }
        };
        if r == 0 {
            consider(cx, cy);
            continue;
        }
        for y in y_lo..=y_hi {
            if y == cy - r || y == cy + r {
                let x_lo = (cx - r).max(0);
                let x_hi = (cx + r).min(w - 1);
                for x in x_lo..=x_hi {
                    consider(x, y);
                }
            } else {
                consider(cx - r, y);
                consider(cx + r, y);
            }
        }
    }
    best.map(|(_, y, x)| (x as usize, y as usize))
}

/// The nearest passable cell to the world point `p` (metres) within 0.5 m, or `None` when `p` is
/// off the grid or every cell within 0.5 m is impassable.
pub fn snap_to_passable(grid: &CostGrid, p: Vec2) -> Option<(usize, usize)> {
    let cell = grid.spec.cell_of(p)?;
    let radius = (0.5 / grid.spec.resolution).ceil() as usize;
    nearest_passable(grid, cell, radius)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::open_list::{BUCKET_KEEP, REACH, RING};
    use proptest::prelude::*;

    const S2: f64 = std::f64::consts::SQRT_2;

    fn grid(w: usize, h: usize) -> CostGrid {
        let spec = GridSpec { origin: Vec2::zeros(), resolution: 1.0, width: w, height: h };
        CostGrid { spec, cost: vec![0; w * h] }
    }

    fn set(g: &mut CostGrid, x: usize, y: usize, c: u8) {
        let i = g.spec.index(x, y);
        g.cost[i] = c;
    }

    fn random_grid(seed: u64, w: usize, h: usize, density: f64) -> CostGrid {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut g = grid(w, h);
        for c in g.cost.iter_mut() {
            *c = if rng.random::<f64>() < density { LETHAL } else { rng.random_range(0..=252) };
        }
        g
    }

    fn assert_valid_path(g: &CostGrid, p: &GridPath, start: (usize, usize), goal: (usize, usize), w: f64) {
        assert_eq!(p.cells.first(), Some(&start));
        assert_eq!(p.cells.last(), Some(&goal));
        let mut total = 0.0;
        for win in p.cells.windows(2) {
            let ((ax, ay), (bx, by)) = (win[0], win[1]);
            let (dx, dy) = (ax.abs_diff(bx), ay.abs_diff(by));
            assert!(dx <= 1 && dy <= 1 && dx + dy > 0);
            assert!(g.passable(bx, by));
            if dx == 1 && dy == 1 {
                assert!(g.passable(bx, ay) && g.passable(ax, by), "corner cut");
            }
            let len = if dx + dy == 2 { S2 } else { 1.0 };
            total += step_cost(len, g.spec.resolution, w, g.cost[g.spec.index(bx, by)]);
        }
        assert!((total - p.cost).abs() < 1e-9);
    }

    #[test]
    fn empty_grid_costs() {
        let g = grid(10, 10);
        let mut pl = PathPlanner::new();
        for mode in [SearchMode::PLAIN, SearchMode::weighted(2.0), SearchMode::dijkstra(0.0)] {
            let p = pl.plan(&g, (0, 0), (9, 9), mode).expect("reachable");
            assert!((p.cost - 9.0 * S2).abs() < 1e-12);
            assert_valid_path(&g, &p, (0, 0), (9, 9), mode.weight);
            let p = pl.plan(&g, (0, 0), (9, 3), mode).expect("reachable");
            assert!((p.cost - (3.0 * S2 + 6.0)).abs() < 1e-12);
        }
        // Plain A* in open space with the larger-g tie-break goes straight to the goal.
        let p = pl.plan(&g, (0, 0), (9, 9), SearchMode::PLAIN).expect("reachable");
        assert_eq!(p.expansions, 10);
        let p = pl.plan(&g, (4, 4), (4, 4), SearchMode::PLAIN).expect("trivial");
        assert_eq!((p.cells.len(), p.cost), (1, 0.0));
    }

    #[test]
    fn resolution_scales_cost() {
        let mut g = grid(10, 10);
        g.spec.resolution = 0.1;
        let p = PathPlanner::new().plan(&g, (0, 0), (9, 3), SearchMode::PLAIN).expect("reachable");
        assert!((p.cost - 0.1 * (3.0 * S2 + 6.0)).abs() < 1e-12);
    }

    #[test]
    fn wall_with_gap() {
        let mut g = grid(10, 10);
        for y in 0..10 {
            if y != 7 {
                set(&mut g, 5, y, LETHAL);
            }
        }
        let mut pl = PathPlanner::new();
        let p = pl.plan(&g, (0, 0), (9, 0), SearchMode::PLAIN).expect("through the gap");
        assert!(p.cells.contains(&(5, 7)));
        assert_valid_path(&g, &p, (0, 0), (9, 0), 0.0);
        // No gap: unreachable, and Dijkstra expands every reachable cell exactly once.
        set(&mut g, 5, 7, LETHAL);
        assert!(pl.plan(&g, (0, 0), (9, 0), SearchMode::PLAIN).is_none());
        let none = pl.plan(&g, (0, 0), (9, 0), SearchMode::dijkstra(2.0));
        assert!(none.is_none());
        let count = expansions_when_unreachable(&g, (0, 0), (9, 0));
        assert_eq!(count, 50, "the 5 x 10 reachable half, each once");
    }

    /// Runs Dijkstra to an unreachable goal and returns how many cells it closed.
    fn expansions_when_unreachable(g: &CostGrid, start: (usize, usize), goal: (usize, usize)) -> usize {
        let mut pl = PathPlanner::new();
        assert!(pl.plan(g, start, goal, SearchMode::dijkstra(1.0)).is_none());
        pl.flags.iter().map(|w| w.closed.count_ones() as usize).sum()
    }

    #[test]
    fn no_corner_cutting() {
        // Two blocked cells (1,0) and (0,1) touching at a corner.
        let mut g = grid(3, 3);
        set(&mut g, 1, 0, LETHAL);
        set(&mut g, 0, 1, LETHAL);
        // From (0,0) the only moves are orthogonal (blocked) or the diagonal to (1,1), which would
        // squeeze between (1,0) and (0,1).
        assert!(PathPlanner::new().plan(&g, (0, 0), (2, 2), SearchMode::PLAIN).is_none());
        // With one of them open, the path goes around.
        set(&mut g, 0, 1, 0);
        let p = PathPlanner::new().plan(&g, (0, 0), (2, 2), SearchMode::PLAIN).expect("open");
        assert_valid_path(&g, &p, (0, 0), (2, 2), 0.0);
        assert!((p.cost - (1.0 + S2 + 1.0)).abs() < 1e-12, "{}", p.cost);
    }

    #[test]
    fn start_may_be_impassable_goal_may_not() {
        let mut g = grid(5, 5);
        set(&mut g, 0, 0, INSCRIBED);
        let mut pl = PathPlanner::new();
        let p = pl.plan(&g, (0, 0), (4, 4), SearchMode::PLAIN).expect("leave the start");
        assert!((p.cost - 4.0 * S2).abs() < 1e-12);
        set(&mut g, 4, 4, LETHAL);
        assert!(pl.plan(&g, (0, 0), (4, 4), SearchMode::PLAIN).is_none());
        assert!(pl.plan(&g, (0, 0), (5, 4), SearchMode::PLAIN).is_none(), "goal outside");
        assert!(pl.plan(&g, (9, 0), (3, 3), SearchMode::PLAIN).is_none(), "start outside");
        for bad in [f64::NAN, -1.0, f64::INFINITY] {
            assert!(pl.plan(&g, (0, 0), (3, 3), SearchMode::weighted(bad)).is_none());
        }
        let wrong = CostGrid { spec: g.spec, cost: vec![0; 3] };
        assert!(pl.plan(&wrong, (0, 0), (1, 1), SearchMode::PLAIN).is_none());
    }

    #[test]
    fn weight_avoids_costly_cells() {
        let mut g = grid(9, 5);
        for y in 0..4 {
            set(&mut g, 4, y, 252);
        }
        let mut pl = PathPlanner::new();
        let plain = pl.plan(&g, (0, 0), (8, 0), SearchMode::PLAIN).expect("reachable");
        assert!((plain.cost - 8.0).abs() < 1e-12);
        // Crossing costs 7 + 6 at w = 5; going round the top costs 8 * sqrt(2) ~ 11.3.
        let social = pl.plan(&g, (0, 0), (8, 0), SearchMode::weighted(5.0)).expect("reachable");
        assert!(social.cells.iter().all(|&(x, y)| x != 4 || y == 4));
    }

    #[test]
    fn social_path_avoids_a_person_in_a_corridor() {
        // A 40 x 9 corridor with a person (Gaussian personal space, peak 252, sigma 1.5 cells)
        // standing on the centre line at x = 20.
        let mut g = grid(40, 9);
        for y in 0..9 {
            for x in 0..40 {
                let d2 = (x as f64 - 20.0).powi(2) + (y as f64 - 4.0).powi(2);
                set(&mut g, x, y, (252.0 * (-d2 / (2.0 * 1.5 * 1.5)).exp()).floor() as u8);
            }
        }
        let mut pl = PathPlanner::new();
        let plain = pl.plan(&g, (0, 4), (39, 4), SearchMode::PLAIN).expect("open corridor");
        let social = pl.plan(&g, (0, 4), (39, 4), SearchMode::weighted(2.0)).expect("open corridor");
        let max_cost = |p: &GridPath| p.cells.iter().map(|&(x, y)| g.cost[g.spec.index(x, y)]).max();
        let length = |p: &GridPath| {
            p.cells
                .windows(2)
                .map(|w| if w[0].0 != w[1].0 && w[0].1 != w[1].1 { S2 } else { 1.0 })
                .sum::<f64>()
        };
        assert_eq!(max_cost(&plain), Some(252), "plain A* walks through the person");
        assert!(max_cost(&social) < Some(60), "{:?}", max_cost(&social));
        assert!(length(&social) <= length(&plain) * 1.25, "{} vs {}", length(&social), length(&plain));
    }

    #[test]
    fn buffers_reused_across_grid_sizes() {
        let mut pl = PathPlanner::new();
        let big = grid(30, 30);
        let small = grid(4, 4);
        let a = pl.plan(&big, (0, 0), (29, 29), SearchMode::PLAIN).expect("ok");
        let b = pl.plan(&small, (0, 0), (3, 3), SearchMode::PLAIN).expect("ok");
        let c = pl.plan(&big, (0, 0), (29, 29), SearchMode::PLAIN).expect("ok");
        assert_eq!(a, c);
        assert!((b.cost - 3.0 * S2).abs() < 1e-12);
    }

    #[test]
    fn nearest_passable_cases() {
        let mut g = grid(7, 7);
        for y in 1..6 {
            for x in 1..6 {
                set(&mut g, x, y, LETHAL);
            }
        }
        assert_eq!(nearest_passable(&g, (0, 0), 0), Some((0, 0)));
        // From the centre (3,3): nearest free cells are at distance 3, (3,0) first by index.
        assert_eq!(nearest_passable(&g, (3, 3), 2), None);
        assert_eq!(nearest_passable(&g, (3, 3), 3), Some((3, 0)));
        assert_eq!(nearest_passable(&g, (2, 4), 10), Some((0, 4)));
        // Outside the grid.
        assert_eq!(nearest_passable(&g, (9, 3), 3), Some((6, 3)));
        assert_eq!(nearest_passable(&g, (usize::MAX, 3), 3), None);
    }

    #[test]
    fn open_list_ring_never_wraps() {
        // Dearest moves (cost 252, diagonal, away from the goal) at a large weight: pushes land at
        // most REACH + 1 buckets ahead, and the worst case comes close to REACH (the bound is not
        // loose, so the ring stays small).
        let mut g = random_grid(5, 40, 40, 0.1);
        for (i, c) in g.cost.iter_mut().enumerate() {
            if *c < INSCRIBED {
                *c = if (i / 40 + i % 40) % 3 == 0 { 0 } else { 252 };
            }
        }
        let mut pl = PathPlanner::new();
        let mut worst = 0;
        for mode in [SearchMode::weighted(20.0), SearchMode::dijkstra(20.0), SearchMode::PLAIN] {
            pl.plan(&g, (39, 39), (0, 0), mode);
            assert!((pl.heap.max_ahead as f64) < REACH + 2.0, "{} buckets ahead", pl.heap.max_ahead);
            worst = worst.max(pl.heap.max_ahead);
        }
        assert!(worst as f64 > 0.9 * REACH, "{worst}");
    }

    #[test]
    fn open_list_memory_stays_bounded_over_many_searches() {
        // Regression (soak test): every bucket of the ring kept the largest buffer it ever held,
        // and plain searches load single buckets with thousands of entries, so over many plans
        // the ring's buffers grew towards RING times the largest load (90 MB in the museum).
        use rand::{Rng, SeedableRng};
        let mut g = grid(300, 200);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(12);
        for c in g.cost.iter_mut() {
            if rng.random::<f64>() < 0.05 {
                *c = LETHAL;
            }
        }
        let mut pl = PathPlanner::new();
        let retained = |pl: &PathPlanner| pl.heap.buckets.iter().map(Vec::capacity).sum::<usize>();
        for _ in 0..300 {
            let mut cell = || loop {
                let c = (rng.random_range(0..300), rng.random_range(0..200));
                if g.passable(c.0, c.1) {
                    return c;
                }
            };
            let (s, t) = (cell(), cell());
            pl.plan(&g, s, t, SearchMode::PLAIN);
        }
        // One search pushes each of the 60,000 cells a few times at most; the old buffers held
        // over ten times the grid after a few hundred plans.
        let bound = RING * BUCKET_KEEP + 300 * 200;
        assert!(retained(&pl) <= bound, "open-list buffers hold {} entries (bound {bound})", retained(&pl));
    }

    /// The search of [`PathPlanner::plan`] written the plain way (a `BinaryHeap` of the same keys,
    /// `Vec<Option<f64>>` for `g`, a `Vec<bool>` closed set, the same neighbour order and
    /// per-move cost, the octile distance from floats): the reference the tuned planner must
    /// match bit for bit. The keys are totally ordered and two equal keys are the same bits (the
    /// cell index is part of the key), so any exact min-queue pops the same sequence; this checks
    /// the tuned buffers, tables, the integer octile and the bucketed open list (which drops the
    /// entries of closed cells when it takes a bucket in) against that.
    fn reference_plan(
        grid: &CostGrid,
        start: (usize, usize),
        goal: (usize, usize),
        mode: SearchMode,
    ) -> Option<GridPath> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let spec = grid.spec;
        let (w, h, res) = (spec.width, spec.height, spec.resolution);
        if !spec.contains_cell(start.0, start.1) || !grid.passable(goal.0, goal.1) {
            return None;
        }
        let n = w * h;
        let mut g: Vec<Option<f64>> = vec![None; n];
        let mut parent = vec![0usize; n];
        let mut closed = vec![false; n];
        // The octile distance in floats throughout.
        let octile_ref = |x: usize, y: usize| {
            let (dx, dy) = (x.abs_diff(goal.0) as f64, y.abs_diff(goal.1) as f64);
            dx.max(dy) + (S2 - 1.0) * dx.min(dy)
        };
        let heur = |x: usize, y: usize| if mode.heuristic { octile_ref(x, y) * res } else { 0.0 };
        let s = spec.index(start.0, start.1);
        g[s] = Some(0.0);
        parent[s] = s;
        let mut open = BinaryHeap::new();
        open.push(Reverse(open_entry(heur(start.0, start.1), 0.0, s as u32)));
        let mut expansions = 0;
        while let Some(Reverse(e)) = open.pop() {
            let cur = open_index(e);
            if closed[cur] {
                continue;
            }
            closed[cur] = true;
            expansions += 1;
            let gc = g[cur].expect("reached");
            if cur == spec.index(goal.0, goal.1) {
                let mut cells = vec![spec.cell(cur)];
                let mut c = cur;
                while c != s {
                    c = parent[c];
                    cells.push(spec.cell(c));
                }
                cells.reverse();
                return Some(GridPath { cells, cost: gc, expansions });
            }
            let (cx, cy) = (cur % w, cur / w);
            let ok = |x: isize, y: isize| x >= 0 && y >= 0 && grid.passable(x as usize, y as usize);
            let (x, y) = (cx as isize, cy as isize);
            let moves = [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, 1), (1, -1), (-1, -1)];
            for (dx, dy) in moves {
                let (nx, ny) = (x + dx, y + dy);
                if !ok(nx, ny) || (dx != 0 && dy != 0 && !(ok(nx, y) && ok(x, ny))) {
                    continue;
                }
                let ni = spec.index(nx as usize, ny as usize);
                if closed[ni] {
                    continue;
                }
                let len = if dx != 0 && dy != 0 { S2 } else { 1.0 };
                let ng = gc + len * (res * (1.0 + mode.weight * f64::from(grid.cost[ni]) / MAX_PASSABLE));
                if g[ni].is_none_or(|old| ng < old) {
                    g[ni] = Some(ng);
                    parent[ni] = cur;
                    open.push(Reverse(open_entry(ng + heur(nx as usize, ny as usize), ng, ni as u32)));
                }
            }
        }
        None
    }

    #[test]
    fn plan_matches_the_reference_search_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
        let mut pl = PathPlanner::new();
        let mut found = 0;
        for case in 0..400 {
            let (w, h) = if case % 10 == 9 {
                // Large enough that buckets are taken in after their cells were closed.
                (rng.random_range(100..200), rng.random_range(100..200))
            } else {
                (rng.random_range(2..70), rng.random_range(2..70))
            };
            let mut g = random_grid(case, w, h, rng.random_range(0.0..0.35));
            g.spec.resolution = [0.05, 0.1, 1.0][case as usize % 3];
            if case % 4 == 0 {
                // Few distinct costs: many ties in f.
                for c in g.cost.iter_mut().filter(|c| **c < INSCRIBED) {
                    *c = if *c < 126 { 0 } else { 100 };
                }
            } else if case % 4 == 1 {
                // One cost everywhere (0 half the time): the most ties.
                let uniform = if case % 8 == 1 { 0 } else { rng.random_range(1..=252) };
                for c in g.cost.iter_mut().filter(|c| **c < INSCRIBED) {
                    *c = uniform;
                }
            }
            let start = (rng.random_range(0..w), rng.random_range(0..h));
            let goal = (rng.random_range(0..w), rng.random_range(0..h));
            let weight = [0.0, 2.0, rng.random_range(0.0..5.0)][case as usize % 3];
            for mode in [SearchMode::weighted(weight), SearchMode::dijkstra(weight)] {
                let got = pl.plan(&g, start, goal, mode);
                let want = reference_plan(&g, start, goal, mode);
                found += usize::from(want.is_some());
                let bits = |p: &Option<GridPath>| {
                    p.as_ref().map(|p| (p.cells.clone(), p.cost.to_bits(), p.expansions))
                };
                assert_eq!(bits(&got), bits(&want), "case {case} {mode:?}");
            }
        }
        assert!(found > 400, "{found} of 800 searches found a path");
    }

    proptest! {
        #[test]
        fn astar_matches_dijkstra(seed in any::<u64>(), w in 2usize..30, h in 2usize..30, density in 0.0f64..0.4, weight in 0.0f64..5.0) {
            let g = random_grid(seed, w, h, density);
            let start = (0, 0);
            let goal = (w - 1, h - 1);
            let mut pl = PathPlanner::new();
            let a = pl.plan(&g, start, goal, SearchMode::weighted(weight));
            prop_assert!((pl.heap.max_ahead as f64) < REACH + 2.0, "{} buckets ahead", pl.heap.max_ahead);
            let d = pl.plan(&g, start, goal, SearchMode::dijkstra(weight));
            prop_assert!((pl.heap.max_ahead as f64) < REACH + 2.0, "{} buckets ahead", pl.heap.max_ahead);
            prop_assert_eq!(a.is_some(), d.is_some());
            if let (Some(a), Some(d)) = (a, d) {
                prop_assert!((a.cost - d.cost).abs() < 1e-9, "{} vs {}", a.cost, d.cost);
                prop_assert!(a.expansions <= d.expansions);
                assert_valid_path(&g, &a, start, goal, weight);
                assert_valid_path(&g, &d, start, goal, weight);
                // Determinism: the same query on a fresh planner gives an identical path.
                let again = PathPlanner::new().plan(&g, start, goal, SearchMode::weighted(weight));
                prop_assert_eq!(Some(a), again);
            }
        }

        #[test]
        fn raising_a_cost_never_lowers_the_optimum(seed in any::<u64>(), w in 2usize..20, h in 2usize..20, cell in any::<prop::sample::Index>(), raise in 1u8..=254, weight in 0.0f64..4.0) {
            let g = random_grid(seed, w, h, 0.2);
            let start = (0, 0);
            let goal = (w - 1, h - 1);
            let mut pl = PathPlanner::new();
            let before = pl.plan(&g, start, goal, SearchMode::weighted(weight));
            let mut g2 = g.clone();
            let i = cell.index(w * h);
            g2.cost[i] = g2.cost[i].saturating_add(raise).min(LETHAL);
            let after = pl.plan(&g2, start, goal, SearchMode::weighted(weight));
            match (before, after) {
                (Some(b), Some(a)) => prop_assert!(a.cost >= b.cost - 1e-9),
                (None, Some(_)) => prop_assert!(false, "raising a cost made the goal reachable"),
                _ => {}
            }
        }
    }
}
