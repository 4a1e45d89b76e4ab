//! The cost grid: one traversal cost a cell, the type every planner, map layer and controller
//! reads, and its inflation from the distance field.
//!
//! Cell costs are `u8`: 0 free, 1..=252 graded cost, [`INSCRIBED`] (253) and [`LETHAL`] (254)
//! impassable (anything `>= INSCRIBED`, including 255, is impassable).

use crate::map::grid::{DistanceField, GridSpec};

/// Cost of a cell occupied by static geometry (impassable).
pub const LETHAL: u8 = 254;
/// Cost of a cell where the robot's centre would put its footprint into geometry (impassable).
/// Every cost `>= INSCRIBED` is impassable.
pub const INSCRIBED: u8 = 253;
/// Largest passable cost; costs are scaled by `1 / MAX_PASSABLE` in edge weights.
pub(crate) const MAX_PASSABLE: f64 = 252.0;

/// A grid of traversal costs.
#[derive(Clone, Debug, PartialEq)]
pub struct CostGrid {
    /// The grid frame.
    pub spec: GridSpec,
    /// One cost per cell, row-major (`spec.index`): 0 free, 1..=252 graded, >= 253 impassable.
    pub cost: Vec<u8>,
}

impl CostGrid {
    /// Inflates a distance field for a disc robot of `radius` metres.
    ///
    /// Rule (with `d` the field value, `res` the resolution, `h = res * sqrt(2) / 2` the cell's
    /// half-diagonal):
    /// - `d == 0` (occupied) gives [`LETHAL`];
    /// - `d < radius + h` gives [`INSCRIBED`];
    /// - otherwise 0.
    ///
    /// Why this is safe: the geometry lies inside occupied cells (the rasterisation is
    /// conservative). If the nearest occupied cell centre is `d` away from a cell centre, every
    /// point of every occupied square is at least `d - h` away, so a passable cell (`d >= radius +
    /// h`) is one where a disc of `radius` centred on the cell centre cannot overlap the geometry.
    /// The guarantee covers geometry inside the grid only: the grid must cover the geometry (or at
    /// least everything within `radius` of the cells the robot may use). A NaN or negative `radius`
    /// is treated as 0.
    pub fn inflated(df: &DistanceField, radius: f64) -> Self {
        let radius = radius.max(0.0); // f64::max ignores NaN
        let half_diag = df.spec.resolution * std::f64::consts::SQRT_2 * 0.5;
        let limit = radius + half_diag;
        let cost = df
            .metres
            .iter()
            .map(|&d| {
                if d <= 0.0 {
                    LETHAL
                } else if d < limit {
                    INSCRIBED
                } else {
                    0
                }
            })
            .collect();
        Self { spec: df.spec, cost }
    }

    /// True if `(ix, iy)` is inside the grid and its cost is below [`INSCRIBED`].
    #[inline]
    pub fn passable(&self, ix: usize, iy: usize) -> bool {
        self.spec.contains_cell(ix, iy)
            && self.cost.get(self.spec.index(ix, iy)).is_some_and(|&c| c < INSCRIBED)
    }

    /// The cost of `(ix, iy)`, or `None` outside the grid.
    #[inline]
    pub fn cost_at(&self, ix: usize, iy: usize) -> Option<u8> {
        if self.spec.contains_cell(ix, iy) { self.cost.get(self.spec.index(ix, iy)).copied() } else { None }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;
    use proptest::prelude::*;

    #[test]
    fn inflation_rule() {
        use crate::map::grid::{DistanceField, OccupancyGrid};
        let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.1, width: 20, height: 1 };
        let mut occ = OccupancyGrid { spec, cells: vec![0; 20] };
        occ.cells[0] = 1;
        let df = DistanceField::from_occupancy(&occ);
        let cg = CostGrid::inflated(&df, 0.3);
        // limit = 0.3 + 0.0707: cells at 0.1..=0.3 are inscribed, 0.4 and beyond free.
        assert_eq!(cg.cost[0], LETHAL);
        assert_eq!(&cg.cost[1..4], &[INSCRIBED; 3]);
        assert!(cg.cost[4..].iter().all(|&c| c == 0));
        assert!(!cg.passable(0, 0) && cg.passable(4, 0) && !cg.passable(20, 0));
        let nan = CostGrid::inflated(&df, f64::NAN);
        assert_eq!(&nan.cost[..2], &[LETHAL, 0]);
    }

    proptest! {
        #[test]
        fn inflated_passable_cells_are_collision_free(seed in any::<u64>(), radius in 0.0f64..0.6, res in 0.05f64..0.3) {
            use crate::map::geometry::{Bounds, StaticGeometry};
            use crate::map::grid::{DistanceField, OccupancyGrid};
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            // The grid covers all the geometry (geometry outside the grid is not represented).
            let bounds = Bounds { min: Vec2::new(-2.5, -2.5), max: Vec2::new(8.5, 6.5) };
            let mut polys = Vec::new();
            for _ in 0..rng.random_range(1..6) {
                // Rotated rectangles, some thin.
                let c = Vec2::new(rng.random_range(-0.5..6.5), rng.random_range(-0.5..4.5));
                let (hx, hy) = (rng.random_range(0.01..1.5), rng.random_range(0.01..0.8));
                let th: f64 = rng.random_range(0.0..3.2);
                let corners = [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)];
                polys.push(corners.iter().map(|&(x, y)| c + crate::math::rotate(Vec2::new(x, y), th)).collect());
            }
            let geom = StaticGeometry::new(polys, bounds).expect("valid");
            let spec = GridSpec::covering(bounds, res).expect("valid");
            let df = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
            let cg = CostGrid::inflated(&df, radius);
            for iy in 0..spec.height {
                for ix in 0..spec.width {
                    if cg.passable(ix, iy) {
                        let d = geom.distance(spec.center(ix, iy));
                        prop_assert!(d >= radius, "cell ({}, {}) at {:?} clearance {} < {} spec {:?} polys {:?}", ix, iy, spec.center(ix, iy), d, radius, spec, geom.polygons());
                    }
                }
            }
        }
    }
}
