//! Geodesic distance to a goal over a cost grid (Dijkstra from the goal, 8-connected, the same
//! edge lengths and corner-cutting rule as the A* search with weight 0).
//!
//! Used for the progress reward (decrease of the geodesic distance to the goal), and as the
//! shortest-path length `l*` of the path-length ratio and SPL metrics.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::map::CostGrid;
use crate::map::grid::GridSpec;
use crate::math::Vec2;

/// Distance (metres) from every passable cell centre to the goal cell centre along 8-connected
/// grid paths; `f64::INFINITY` for impassable or unreachable cells.
#[derive(Clone, Debug)]
pub struct GoalField {
    spec: GridSpec,
    dist: Vec<f64>,
}

#[derive(PartialEq)]
struct Entry(f64, usize);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // min-heap on distance, then on index for determinism
        other.0.total_cmp(&self.0).then_with(|| other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl GoalField {
    /// Runs Dijkstra from `goal` (a passable cell) over `grid`.
    pub fn compute(grid: &CostGrid, goal: (usize, usize)) -> Self {
        let spec = grid.spec;
        let (w, h) = (spec.width, spec.height);
        let mut dist = vec![f64::INFINITY; spec.len()];
        let mut heap = BinaryHeap::new();
        if goal.0 < w && goal.1 < h && grid.passable(goal.0, goal.1) {
            let gi = spec.index(goal.0, goal.1);
            dist[gi] = 0.0;
            heap.push(Entry(0.0, gi));
        }
        let res = spec.resolution;
        let diag = std::f64::consts::SQRT_2 * res;
        while let Some(Entry(d, idx)) = heap.pop() {
            if d > dist[idx] {
                continue;
            }
            let (x, y) = ((idx % w) as isize, (idx / w) as isize);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (1, -1), (-1, 1), (-1, -1)] {
                let (nx, ny) = (x + dx, y + dy);
                if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                    continue;
                }
                let (ux, uy) = (nx as usize, ny as usize);
                if !grid.passable(ux, uy) {
                    continue;
                }
                let step = if dx != 0 && dy != 0 {
                    // no corner cutting: both orthogonal neighbours must be passable
                    if !grid.passable(ux, y as usize) || !grid.passable(x as usize, uy) {
                        continue;
                    }
                    diag
                } else {
                    res
                };
                let ni = spec.index(ux, uy);
                let nd = d + step;
                if nd < dist[ni] {
                    dist[ni] = nd;
                    heap.push(Entry(nd, ni));
                }
            }
        }
        GoalField { spec, dist }
    }

    /// Distance of the cell containing `p` (metres), infinite outside the grid or unreachable.
    pub fn cell_distance(&self, p: Vec2) -> f64 {
        match self.spec.cell_of(p) {
            Some((x, y)) => self.dist[self.spec.index(x, y)],
            None => f64::INFINITY,
        }
    }

    /// The grid's resolution (metres per cell).
    pub fn resolution(&self) -> f64 {
        self.spec.resolution
    }

    /// Smooth geodesic distance at `p` (metres): the minimum over the reachable cells of the 3x3
    /// neighbourhood of (cell distance + straight-line distance from `p` to that cell's centre).
    /// Continuous in `p` where the neighbourhood is free, so progress rewards do not jump at cell
    /// borders. Infinite when no neighbouring cell is reachable.
    pub fn distance(&self, p: Vec2) -> f64 {
        let Some((cx, cy)) = self.spec.cell_of(p) else {
            return f64::INFINITY;
        };
        let mut best = f64::INFINITY;
        for dy in -1isize..=1 {
            for dx in -1isize..=1 {
                let (nx, ny) = (cx as isize + dx, cy as isize + dy);
                if nx < 0 || ny < 0 || nx >= self.spec.width as isize || ny >= self.spec.height as isize {
                    continue;
                }
                let (ux, uy) = (nx as usize, ny as usize);
                let d = self.dist[self.spec.index(ux, uy)];
                if d.is_finite() {
                    best = best.min(d + (p - self.spec.center(ux, uy)).norm());
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::Bounds;

    fn open_grid(w: usize, h: usize) -> CostGrid {
        let spec = GridSpec::covering(
            Bounds { min: Vec2::zeros(), max: Vec2::new(w as f64 * 0.1, h as f64 * 0.1) },
            0.1,
        )
        .expect("valid spec");
        CostGrid { spec, cost: vec![0; spec.len()] }
    }

    #[test]
    fn open_grid_distance_is_octile() {
        let g = open_grid(10, 10);
        let f = GoalField::compute(&g, (0, 0));
        let d = f.cell_distance(g.spec.center(9, 3));
        assert!((d - (3.0 * std::f64::consts::SQRT_2 + 6.0) * 0.1).abs() < 1e-9, "{d}");
        // smooth distance at the goal centre is 0, and it grows continuously
        assert!(f.distance(g.spec.center(0, 0)).abs() < 1e-12);
        let a = f.distance(Vec2::new(0.449, 0.05));
        let b = f.distance(Vec2::new(0.451, 0.05));
        assert!((a - b).abs() < 0.01, "{a} {b}");
    }

    #[test]
    fn walls_make_distance_longer_and_blocked_cells_infinite() {
        let mut g = open_grid(10, 10);
        // wall at x = 5 from y = 0 to 8 (gap at the top)
        for y in 0..9 {
            let i = g.spec.index(5, y);
            g.cost[i] = crate::map::LETHAL;
        }
        let f = GoalField::compute(&g, (0, 0));
        let behind = f.cell_distance(g.spec.center(9, 0));
        assert!(behind > 0.9 + 1e-9);
        assert!(f.cell_distance(g.spec.center(5, 0)).is_infinite());
    }
}
