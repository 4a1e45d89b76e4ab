//! Greedy line-of-sight shortcutting of grid paths, and the cost of a polyline on the grid.
//!
//! # Segment cost
//! A straight segment from cell `P` to cell `Q` is walked with an exact integer supercover
//! traversal (the cells its centre-to-centre line passes through). The cells it *enters* are the
//! traversed cells other than `P` (a cell touched only at a corner is not entered); the cells it
//! *touches* are the entered cells plus, wherever the line passes exactly through a grid vertex,
//! the two cells meeting it there. Then:
//! - the segment is traversable iff every touched cell is inside the grid and passable (`P` itself
//!   is exempt, matching [`crate::plan::PathPlanner::plan`], which may leave an impassable start);
//! - its cost is `length * (1 + w * c_mean / 252)`, where `length` is the Euclidean length in metres
//!   and `c_mean` the mean cost of the entered cells.
//!
//! For a move between 8-neighbours this is exactly the A* edge cost `len * res * (1 + w * c_to /
//! 252)` (a diagonal move touches the two orthogonal cells, which A* also requires passable), so the
//! cost of a grid path's cell-centre polyline equals [`crate::plan::GridPath::cost`] up to rounding.

use crate::map::grid::GridSpec;
use crate::map::{CostGrid, INSCRIBED};
use crate::math::Vec2;
use crate::plan::astar::GridPath;

/// Relative slack allowed when comparing a shortcut's cost with the path it replaces, so that
/// collinear runs are merged despite rounding.
const COST_SLACK: f64 = 1e-12;

/// Walks the supercover line between cells `a` and `b` (integer cell coordinates), calling
/// `visit(x, y, entered)` for every cell after `a`: `entered` is true for cells the line passes
/// through, false for cells it only touches at a corner. Stops early (returning false) when `visit`
/// returns false.
fn walk(a: (i64, i64), b: (i64, i64), mut visit: impl FnMut(i64, i64, bool) -> bool) -> bool {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (nx, ny) = (dx.unsigned_abs() as i128, dy.unsigned_abs() as i128);
    let (sx, sy) = (dx.signum(), dy.signum());
    let (mut x, mut y) = a;
    let (mut ix, mut iy) = (0i128, 0i128);
    while ix < nx || iy < ny {
        // Compare where the line crosses the next vertical versus the next horizontal cell border:
        // (0.5 + ix) / nx versus (0.5 + iy) / ny, cross-multiplied to stay exact.
        let decision = (1 + 2 * ix) * ny - (1 + 2 * iy) * nx;
        if decision == 0 {
            // Exactly through a grid vertex: the two side cells are touched, the diagonal one entered.
            if !visit(x + sx, y, false) || !visit(x, y + sy, false) {
                return false;
            }
            x += sx;
            y += sy;
            ix += 1;
            iy += 1;
        } else if decision < 0 {
            x += sx;
            ix += 1;
        } else {
            y += sy;
            iy += 1;
        }
        if !visit(x, y, true) {
            return false;
        }
    }
    true
}

/// Mean cost of the cells entered by the segment between cells `a` and `b`, or `None` if it is not
/// traversable (see the module docs). `Some(0.0)` when `a == b`.
fn segment_mean_cost(grid: &CostGrid, a: (i64, i64), b: (i64, i64)) -> Option<f64> {
    let spec = &grid.spec;
    let (w, h) = (spec.width as i64, spec.height as i64);
    let (mut sum, mut n) = (0u64, 0u64);
    let ok = walk(a, b, |x, y, entered| {
        if x < 0 || y < 0 || x >= w || y >= h {
            return false;
        }
        let Some(&c) = grid.cost.get(spec.index(x as usize, y as usize)) else {
            return false;
        };
        if c >= INSCRIBED {
            return false;
        }
        if entered {
            sum += u64::from(c);
            n += 1;
        }
        true
    });
    match (ok, n) {
        (false, _) => None,
        (true, 0) => Some(0.0),
        (true, _) => Some(sum as f64 / n as f64),
    }
}

#[inline]
fn weighted(length: f64, weight: f64, mean: f64) -> f64 {
    length * (1.0 + weight * mean / 252.0)
}

/// Cost of the straight move between cells `a` and `b`, with the length taken in cells times the
/// resolution.
fn cell_segment_cost(grid: &CostGrid, a: (i64, i64), b: (i64, i64), weight: f64) -> f64 {
    match segment_mean_cost(grid, a, b) {
        None => f64::INFINITY,
        Some(mean) => {
            let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
            let len = if dx == 0.0 || dy == 0.0 { dx.abs() + dy.abs() } else { (dx * dx + dy * dy).sqrt() };
            weighted(len * grid.spec.resolution, weight, mean)
        }
    }
}

fn as_i64(c: (usize, usize)) -> (i64, i64) {
    (i64::try_from(c.0).unwrap_or(i64::MAX), i64::try_from(c.1).unwrap_or(i64::MAX))
}

fn centre(spec: &GridSpec, c: (usize, usize)) -> Vec2 {
    spec.center(c.0, c.1)
}

/// Greedy line-of-sight shortcutting of a grid path; returns world waypoints (metres, cell
/// centres), the first the start cell's centre and the last the goal cell's centre.
///
/// From the current anchor, the shortcut to later path cells is extended one cell at a time for as
/// long as the straight segment is traversable (all touched cells passable, see the module docs)
/// and its cost (with `weight`, same meaning as [`crate::plan::SearchMode::weight`]) is no more than
/// the cost of the part of the grid path it replaces (up to a 1e-12 relative slack for rounding);
/// the last such cell becomes the next anchor. Hence the result's [`path_cost`] never exceeds the
/// grid path's, and the result never crosses an impassable cell.
///
/// An empty path gives an empty vector; a one-cell path gives its centre. If `weight` is not
/// finite and `>= 0`, the cell centres are returned unchanged.
pub fn smooth_path(grid: &CostGrid, path: &GridPath, weight: f64) -> Vec<Vec2> {
    let cells = &path.cells;
    let spec = &grid.spec;
    let n = cells.len();
    if n <= 2 || !(weight.is_finite() && weight >= 0.0) {
        return cells.iter().map(|&c| centre(spec, c)).collect();
    }
    let ic: Vec<(i64, i64)> = cells.iter().map(|&c| as_i64(c)).collect();
    // prefix[k] = cost of the grid path from cell 0 to cell k.
    let mut prefix = Vec::with_capacity(n);
    prefix.push(0.0);
    for k in 1..n {
        let c = cell_segment_cost(grid, ic[k - 1], ic[k], weight);
        prefix.push(prefix[k - 1] + c);
    }
    let mut out = vec![centre(spec, cells[0])];
    let mut i = 0;
    while i + 1 < n {
        let mut best = i + 1;
        for j in i + 2..n {
            let replaced = prefix[j] - prefix[i];
            let shortcut = cell_segment_cost(grid, ic[i], ic[j], weight);
            if shortcut.is_finite() && shortcut <= replaced * (1.0 + COST_SLACK) {
                best = j;
            } else {
                break;
            }
        }
        out.push(centre(spec, cells[best]));
        i = best;
    }
    out
}

/// Cost (metres-equivalent) of a polyline evaluated on the grid, with the per-segment rule of the
/// module docs: each waypoint is mapped to the cell containing it, a segment's cost is its
/// Euclidean length in metres times `1 + weight * c_mean / 252`, and the segments' costs are
/// summed. For the cell centres of a [`GridPath`] this equals its `cost` (up to rounding).
///
/// Returns 0 for fewer than two waypoints, and `f64::INFINITY` if a waypoint is outside the grid
/// or not finite, if a segment is not traversable (the first waypoint's cell is exempt), or if
/// `weight` is not finite and `>= 0`.
pub fn path_cost(grid: &CostGrid, waypoints: &[Vec2], weight: f64) -> f64 {
    if waypoints.len() < 2 {
        return 0.0;
    }
    if !(weight.is_finite() && weight >= 0.0) {
        return f64::INFINITY;
    }
    let mut total = 0.0;
    for pair in waypoints.windows(2) {
        let (Some(a), Some(b)) = (grid.spec.cell_of(pair[0]), grid.spec.cell_of(pair[1])) else {
            return f64::INFINITY;
        };
        match segment_mean_cost(grid, as_i64(a), as_i64(b)) {
            None => return f64::INFINITY,
            Some(mean) => total += weighted((pair[1] - pair[0]).norm(), weight, mean),
        }
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::LETHAL;
    use crate::plan::astar::{PathPlanner, SearchMode};
    use proptest::prelude::*;

    fn grid(w: usize, h: usize, res: f64) -> CostGrid {
        let spec = GridSpec { origin: Vec2::new(-1.0, 2.0), resolution: res, width: w, height: h };
        CostGrid { spec, cost: vec![0; w * h] }
    }

    fn walk_cells(a: (i64, i64), b: (i64, i64)) -> Vec<(i64, i64, bool)> {
        let mut v = Vec::new();
        walk(a, b, |x, y, e| {
            v.push((x, y, e));
            true
        });
        v
    }

    #[test]
    fn walk_known_lines() {
        assert_eq!(walk_cells((0, 0), (0, 0)), vec![]);
        assert_eq!(walk_cells((0, 0), (2, 0)), vec![(1, 0, true), (2, 0, true)]);
        assert_eq!(walk_cells((0, 0), (1, 1)), vec![(1, 0, false), (0, 1, false), (1, 1, true)]);
        // Slope 1/2: (0.5, 0.5) -> (2.5, 1.5) crosses y = 1 at x = 1.5, mid-column: no vertex.
        assert_eq!(walk_cells((0, 0), (2, 1)), vec![(1, 0, true), (1, 1, true), (2, 1, true)]);
        // Slope 1/3: (0.5, 0.5) -> (3.5, 1.5) passes exactly through the vertex (2, 1).
        assert_eq!(
            walk_cells((0, 0), (3, 1)),
            vec![(1, 0, true), (2, 0, false), (1, 1, false), (2, 1, true), (3, 1, true)]
        );
        assert_eq!(
            walk_cells((3, 1), (0, 0)),
            vec![(2, 1, true), (1, 1, false), (2, 0, false), (1, 0, true), (0, 0, true)]
        );
    }

    #[test]
    fn open_space_collapses_to_a_line() {
        let g = grid(10, 10, 0.1);
        let p = PathPlanner::new().plan(&g, (0, 0), (9, 3), SearchMode::PLAIN).expect("ok");
        let s = smooth_path(&g, &p, 0.0);
        assert_eq!(s, vec![g.spec.center(0, 0), g.spec.center(9, 3)]);
        let c = path_cost(&g, &s, 0.0);
        assert!((c - 0.1 * 90f64.sqrt()).abs() < 1e-12);
        let centres: Vec<Vec2> = p.cells.iter().map(|&(x, y)| g.spec.center(x, y)).collect();
        assert!((path_cost(&g, &centres, 0.0) - p.cost).abs() < 1e-12);
    }

    #[test]
    fn shortcut_goes_around_a_block() {
        let mut g = grid(10, 10, 1.0);
        for y in 0..8 {
            let i = g.spec.index(5, y);
            g.cost[i] = LETHAL;
        }
        let p = PathPlanner::new().plan(&g, (0, 0), (9, 0), SearchMode::PLAIN).expect("ok");
        let s = smooth_path(&g, &p, 0.0);
        assert!(s.len() >= 3 && s.len() < p.cells.len());
        assert!(path_cost(&g, &s, 0.0) <= p.cost + 1e-9);
        assert!(path_cost(&g, &s, 0.0).is_finite());
    }

    #[test]
    fn costly_shortcut_is_rejected() {
        // A 3 x 3 grid with an expensive centre: with a large weight, the diagonal through the centre
        // costs more than going round.
        let mut g = grid(3, 3, 1.0);
        let path = GridPath { cells: vec![(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)], cost: 4.0, expansions: 0 };
        let s0 = smooth_path(&g, &path, 5.0);
        assert_eq!(s0.len(), 2, "free grid: straight diagonal");
        let i = g.spec.index(1, 1);
        g.cost[i] = 252;
        let s = smooth_path(&g, &path, 5.0);
        assert!(s.len() > 2);
        assert!(path_cost(&g, &s, 5.0) <= 4.0 + 1e-12);
    }

    #[test]
    fn degenerate_inputs() {
        let g = grid(4, 4, 0.5);
        let empty = GridPath { cells: vec![], cost: 0.0, expansions: 0 };
        assert!(smooth_path(&g, &empty, 1.0).is_empty());
        let one = GridPath { cells: vec![(2, 2)], cost: 0.0, expansions: 0 };
        assert_eq!(smooth_path(&g, &one, 1.0), vec![g.spec.center(2, 2)]);
        let two = GridPath { cells: vec![(0, 0), (3, 3)], cost: 0.0, expansions: 0 };
        assert_eq!(smooth_path(&g, &two, f64::NAN).len(), 2);
        assert_eq!(path_cost(&g, &[], 1.0), 0.0);
        let a = g.spec.center(0, 0);
        assert_eq!(path_cost(&g, &[a, Vec2::new(f64::NAN, 0.0)], 1.0), f64::INFINITY);
        assert_eq!(path_cost(&g, &[a, Vec2::new(100.0, 0.0)], 1.0), f64::INFINITY);
        assert_eq!(path_cost(&g, &[a, g.spec.center(1, 1)], -1.0), f64::INFINITY);
        // Out-of-grid cells in a hand-made path do not panic.
        let bad = GridPath { cells: vec![(0, 0), (7, 7), (usize::MAX, 0)], cost: 0.0, expansions: 0 };
        assert_eq!(smooth_path(&g, &bad, 1.0).len(), 3);
    }

    fn random_grid(seed: u64, w: usize, h: usize) -> CostGrid {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        let mut g = grid(w, h, 0.1);
        for c in g.cost.iter_mut() {
            let r: f64 = rng.random();
            *c = if r < 0.2 {
                LETHAL
            } else if r < 0.5 {
                rng.random_range(1..=252)
            } else {
                0
            };
        }
        g
    }

    proptest! {
        #[test]
        fn smoothing_never_increases_cost_nor_crosses_obstacles(
            seed in any::<u64>(), w in 2usize..30, h in 2usize..30, weight in 0.0f64..5.0
        ) {
            let g = random_grid(seed, w, h);
            let (start, goal) = ((0, 0), (w - 1, h - 1));
            let Some(p) = PathPlanner::new().plan(&g, start, goal, SearchMode::weighted(weight)) else {
                return Ok(());
            };
            let centres: Vec<Vec2> = p.cells.iter().map(|&(x, y)| g.spec.center(x, y)).collect();
            let grid_cost = path_cost(&g, &centres, weight);
            prop_assert!((grid_cost - p.cost).abs() < 1e-9, "{} vs {}", grid_cost, p.cost);
            let s = smooth_path(&g, &p, weight);
            prop_assert_eq!(s.first(), centres.first());
            prop_assert_eq!(s.last(), centres.last());
            let sc = path_cost(&g, &s, weight);
            prop_assert!(sc <= p.cost + 1e-9, "{} > {}", sc, p.cost);
            // Independent check: dense samples along every segment land only in passable cells
            // (apart from the start cell).
            for seg in s.windows(2) {
                for k in 1..=400 {
                    let q = seg[0] + (seg[1] - seg[0]) * (f64::from(k) / 400.0);
                    let (x, y) = g.spec.cell_of(q).expect("inside");
                    prop_assert!((x, y) == start || g.passable(x, y), "crossed ({}, {})", x, y);
                }
            }
        }
    }
}
