//! The grid frame, conservative rasterisation of the static geometry, and the exact Euclidean
//! distance transform.
//!
//! Cell `(ix, iy)` covers the half-open square `[origin + (ix, iy) * res, origin + (ix + 1, iy + 1) *
//! res)`; cells are stored row-major with `y` rows (`index = iy * width + ix`).

use crate::error::{CoreError, Result};
use crate::map::geometry::{Bounds, StaticGeometry};
use crate::math::Vec2;

/// Largest grid [`GridSpec::covering`] will build (cells); keeps indices within `u32` and memory
/// bounded.
pub const MAX_CELLS: usize = 100_000_000;

/// Largest accepted resolution (metres per cell).
pub const MAX_RESOLUTION: f64 = 5.0;

/// Tolerance (in cells) by which rasterisation grows every polygon, so that geometry that exactly
/// touches a cell border marks both neighbours (conservative).
const TOUCH_EPS_CELLS: f64 = 1e-9;

/// Geometry of a regular grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    /// World coordinates (metres) of the lower-left corner of cell `(0, 0)`.
    pub origin: Vec2,
    /// Cell side (metres), in `(0, 5]`.
    pub resolution: f64,
    /// Number of columns (cells along x).
    pub width: usize,
    /// Number of rows (cells along y).
    pub height: usize,
}

impl GridSpec {
    /// The smallest grid with cell side `resolution` (metres) whose lower-left corner is
    /// `bounds.min` and which covers `bounds`: `width = ceil(extent.x / resolution)` (at least 1;
    /// an extent within 1e-9 cells of a whole number is not rounded up), likewise `height`.
    ///
    /// Errors with [`CoreError::Input`] if `resolution` is not finite or not in `(0, 5]`, if the
    /// bounds are not finite with `min <= max`, or if the grid would exceed [`MAX_CELLS`] cells.
    pub fn covering(bounds: Bounds, resolution: f64) -> Result<Self> {
        if !(resolution.is_finite() && resolution > 0.0 && resolution <= MAX_RESOLUTION) {
            return Err(CoreError::input(
                "resolution",
                "a finite value in (0, 5] metres",
                format!("{resolution}"),
            ));
        }
        if !bounds.is_valid() {
            return Err(CoreError::input(
                "bounds",
                "finite corners with min <= max",
                format!("min {:?}, max {:?}", bounds.min, bounds.max),
            ));
        }
        let ext = bounds.extent();
        let count = |e: f64| -> f64 { (e / resolution - 1e-9).ceil().max(1.0) };
        let (w, h) = (count(ext.x), count(ext.y));
        if w * h > MAX_CELLS as f64 {
            return Err(CoreError::input(
                "bounds",
                format!("a grid of at most {MAX_CELLS} cells"),
                format!("{w} x {h} cells"),
            ));
        }
        // Both are whole numbers in [1, MAX_CELLS], so the casts are exact.
        Ok(Self { origin: bounds.min, resolution, width: w as usize, height: h as usize })
    }

    /// The cell containing `p` (metres), or `None` if `p` is outside the grid or not finite.
    pub fn cell_of(&self, p: Vec2) -> Option<(usize, usize)> {
        let fx = (p.x - self.origin.x) / self.resolution;
        let fy = (p.y - self.origin.y) / self.resolution;
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.width as f64 && fy < self.height as f64) {
            return None;
        }
        let (ix, iy) = (fx as usize, fy as usize);
        (ix < self.width && iy < self.height).then_some((ix, iy))
    }

    /// World coordinates (metres) of the centre of cell `(ix, iy)`. Defined for any indices (cells
    /// outside the grid extrapolate the lattice).
    pub fn center(&self, ix: usize, iy: usize) -> Vec2 {
        Vec2::new(
            self.origin.x + (ix as f64 + 0.5) * self.resolution,
            self.origin.y + (iy as f64 + 0.5) * self.resolution,
        )
    }

    /// Row-major index `iy * width + ix`. The caller guarantees `ix < width`, `iy < height`.
    #[inline]
    pub fn index(&self, ix: usize, iy: usize) -> usize {
        iy * self.width + ix
    }

    /// Inverse of [`Self::index`]: `(idx % width, idx / width)`.
    #[inline]
    pub fn cell(&self, idx: usize) -> (usize, usize) {
        (idx % self.width.max(1), idx / self.width.max(1))
    }

    /// True if `(ix, iy)` is inside the grid.
    #[inline]
    pub fn contains_cell(&self, ix: usize, iy: usize) -> bool {
        ix < self.width && iy < self.height
    }

    /// Number of cells, `width * height`.
    pub fn len(&self) -> usize {
        self.width * self.height
    }

    /// True if the grid has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `p` (metres) in continuous cell units: cell `(ix, iy)` covers `[ix, ix+1) x [iy, iy+1)`.
    #[inline]
    fn in_cell_units(&self, p: Vec2) -> Vec2 {
        (p - self.origin) / self.resolution
    }
}

/// Binary occupancy: `cells[spec.index(ix, iy)]` is 1 if occupied, 0 if free.
#[derive(Clone, Debug, PartialEq)]
pub struct OccupancyGrid {
    /// The grid frame.
    pub spec: GridSpec,
    /// One byte per cell, row-major: 1 = occupied, 0 = free.
    pub cells: Vec<u8>,
}

/// Clamps a (possibly huge or negative) cell coordinate range to `[0, n)`; `None` if empty.
fn clamp_range(lo: f64, hi: f64, n: usize) -> Option<(usize, usize)> {
    if !(hi >= 0.0 && lo < n as f64 && lo <= hi) || n == 0 {
        return None;
    }
    let lo = lo.floor().max(0.0) as usize;
    let hi = (hi.floor() as usize).min(n - 1);
    (lo <= hi).then_some((lo, hi))
}

impl OccupancyGrid {
    /// Rasterises the polygons conservatively: a cell is occupied if any polygon overlaps the
    /// closed cell square (polygons are grown by 1e-9 cells so exact contact counts).
    ///
    /// Every edge marks all the cells it passes through (row strip by row strip), and each polygon
    /// interior is filled by an even-odd scanline on the cell centres. A cell square either meets an
    /// edge or lies wholly inside or outside the polygon, so this marks exactly the overlapping
    /// cells. Cost: O(perimeter + area) in cells. Geometry outside the grid is ignored.
    pub fn rasterize(geom: &StaticGeometry, spec: GridSpec) -> Self {
        let mut cells = vec![0u8; spec.len()];
        let mut xs: Vec<f64> = Vec::new();
        for poly in geom.polygons() {
            let g: Vec<Vec2> = poly.iter().map(|p| spec.in_cell_units(*p)).collect();
            let n = g.len();
            for i in 0..n {
                mark_segment(&mut cells, &spec, g[i], g[(i + 1) % n]);
            }
            fill_interior(&mut cells, &spec, &g, &mut xs);
        }
        Self { spec, cells }
    }

    /// True if `(ix, iy)` is inside the grid and occupied.
    pub fn occupied(&self, ix: usize, iy: usize) -> bool {
        self.spec.contains_cell(ix, iy) && self.cells[self.spec.index(ix, iy)] != 0
    }
}

/// Marks every cell the segment `ab` (cell units) touches.
fn mark_segment(cells: &mut [u8], spec: &GridSpec, a: Vec2, b: Vec2) {
    let e = TOUCH_EPS_CELLS;
    let Some((r0, r1)) = clamp_range(a.y.min(b.y) - e, a.y.max(b.y) + e, spec.height) else {
        return;
    };
    let d = b - a;
    for iy in r0..=r1 {
        let (y_lo, y_hi) = (iy as f64 - e, iy as f64 + 1.0 + e);
        let (t0, t1) = if d.y.abs() < 1e-300 {
            (0.0, 1.0)
        } else {
            let u = (y_lo - a.y) / d.y;
            let v = (y_hi - a.y) / d.y;
            (u.min(v).max(0.0), u.max(v).min(1.0))
        };
        if t0.is_nan() || t1.is_nan() || t0 > t1 {
            continue;
        }
        let (x0, x1) = (a.x + d.x * t0, a.x + d.x * t1);
        if let Some((c0, c1)) = clamp_range(x0.min(x1) - e, x0.max(x1) + e, spec.width) {
            let row = iy * spec.width;
            cells[row + c0..=row + c1].fill(1);
        }
    }
}

/// Marks every cell whose centre is inside the polygon `g` (cell units), even-odd rule.
fn fill_interior(cells: &mut [u8], spec: &GridSpec, g: &[Vec2], xs: &mut Vec<f64>) {
    let (mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in g {
        ymin = ymin.min(p.y);
        ymax = ymax.max(p.y);
    }
    // Rows whose centre iy + 0.5 lies in [ymin, ymax].
    let Some((r0, r1)) = clamp_range((ymin - 0.5).ceil(), (ymax - 0.5).floor(), spec.height) else {
        return;
    };
    let n = g.len();
    for iy in r0..=r1 {
        let yc = iy as f64 + 0.5;
        xs.clear();
        for i in 0..n {
            let (a, b) = (g[i], g[(i + 1) % n]);
            if (a.y > yc) != (b.y > yc) {
                xs.push(a.x + (yc - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            // Columns whose centre ix + 0.5 lies in [pair[0], pair[1]].
            if let Some((c0, c1)) = clamp_range((pair[0] - 0.5).ceil(), (pair[1] - 0.5).floor(), spec.width) {
                let row = iy * spec.width;
                cells[row + c0..=row + c1].fill(1);
            }
        }
    }
}

/// Exact Euclidean distance (metres, between cell centres) from each cell to the nearest occupied
/// cell.
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceField {
    /// The grid frame.
    pub spec: GridSpec,
    /// One value per cell, row-major (metres): 0 on occupied cells, `f64::INFINITY` everywhere if
    /// nothing is occupied.
    pub metres: Vec<f64>,
}

/// Felzenszwalb-Huttenlocher 1D squared distance transform of `f` into `d` (same length).
/// `v` (len n) and `z` (len n + 1) are scratch.
fn dt1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let sq = |q: usize| (q * q) as f64;
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let mut s;
        loop {
            let vk = v[k];
            s = ((f[q] + sq(q)) - (f[vk] + sq(vk))) / (2.0 * (q as f64 - vk as f64));
            // z[0] is -inf, so this stops at k == 0.
            if s <= z[k] && k > 0 {
                k -= 1;
            } else {
                break;
            }
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, out) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let dq = q as f64 - v[k] as f64;
        *out = dq * dq + f[v[k]];
    }
}

impl DistanceField {
    /// Exact Euclidean distance transform (Felzenszwalb-Huttenlocher, a column pass then a row
    /// pass over squared distances), converted to metres: the distance between the centre of each
    /// cell and the centre of the nearest occupied cell. Occupied cells are 0; if nothing is
    /// occupied (or `grid.cells` does not have `spec.len()` entries) every cell is
    /// `f64::INFINITY`. O(cells).
    pub fn from_occupancy(grid: &OccupancyGrid) -> Self {
        let spec = grid.spec;
        let (w, h) = (spec.width, spec.height);
        let n = spec.len();
        if !grid.cells.iter().any(|&c| c != 0) || grid.cells.len() != n {
            return Self { spec, metres: vec![f64::INFINITY; n] };
        }
        // A finite "infinity" larger than any squared distance in the grid, small enough that all
        // arithmetic stays exact on integers.
        let big = 2.0 * ((w as f64).powi(2) + (h as f64).powi(2)) + 1.0;
        let mut sq: Vec<f64> = grid.cells.iter().map(|&c| if c != 0 { 0.0 } else { big }).collect();
        let m = w.max(h);
        let (mut f, mut d) = (vec![0.0; m], vec![0.0; m]);
        let (mut v, mut z) = (vec![0usize; m], vec![0.0; m + 1]);
        // Columns.
        for ix in 0..w {
            for iy in 0..h {
                f[iy] = sq[iy * w + ix];
            }
            dt1d(&f[..h], &mut d[..h], &mut v, &mut z);
            for iy in 0..h {
                sq[iy * w + ix] = d[iy];
            }
        }
        // Rows.
        for iy in 0..h {
            let row = &mut sq[iy * w..(iy + 1) * w];
            f[..w].copy_from_slice(row);
            dt1d(&f[..w], row, &mut v, &mut z);
        }
        let res = spec.resolution;
        let metres = sq.into_iter().map(|s| s.sqrt() * res).collect();
        Self { spec, metres }
    }

    /// The value (metres) of the cell containing `p`; 0 outside the grid or for a non-finite `p`
    /// (treated as colliding).
    pub fn at(&self, p: Vec2) -> f64 {
        match self.spec.cell_of(p) {
            Some((ix, iy)) => self.metres.get(self.spec.index(ix, iy)).copied().unwrap_or(0.0),
            None => 0.0,
        }
    }

    /// Gradient of the field at `p` (central differences over the neighbouring cells; unit-free,
    /// about unit length away from obstacles), or zero where a neighbour is outside the grid or
    /// infinitely far from any obstacle. Points away from the nearest obstacle.
    pub fn gradient(&self, p: Vec2) -> Vec2 {
        let Some((ix, iy)) = self.spec.cell_of(p) else {
            return Vec2::zeros();
        };
        if ix == 0 || iy == 0 || ix + 1 >= self.spec.width || iy + 1 >= self.spec.height {
            return Vec2::zeros();
        }
        let v = |x: usize, y: usize| self.metres[self.spec.index(x, y)];
        let (l, r, d, u) = (v(ix - 1, iy), v(ix + 1, iy), v(ix, iy - 1), v(ix, iy + 1));
        if !(l.is_finite() && r.is_finite() && d.is_finite() && u.is_finite()) {
            return Vec2::zeros();
        }
        let h = 2.0 * self.spec.resolution;
        Vec2::new((r - l) / h, (u - d) / h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn bounds(w: f64, h: f64) -> Bounds {
        Bounds { min: v(0.0, 0.0), max: v(w, h) }
    }

    fn occupied_set(g: &OccupancyGrid) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for iy in 0..g.spec.height {
            for ix in 0..g.spec.width {
                if g.occupied(ix, iy) {
                    out.push((ix, iy));
                }
            }
        }
        out
    }

    /// Reference: does the polygon overlap the closed square of cell (ix, iy) (world units)?
    fn overlaps(poly: &[Vec2], spec: &GridSpec, ix: usize, iy: usize, grow: f64) -> bool {
        use crate::map::geometry::segments_intersect;
        let r = spec.resolution;
        let lo = spec.origin + v(ix as f64 * r - grow, iy as f64 * r - grow);
        let hi = spec.origin + v((ix + 1) as f64 * r + grow, (iy + 1) as f64 * r + grow);
        let sq = [lo, v(hi.x, lo.y), hi, v(lo.x, hi.y)];
        let g = StaticGeometry::new(vec![poly.to_vec()], bounds(100.0, 100.0)).expect("poly");
        let n = poly.len();
        if sq.iter().any(|c| g.contains(*c)) {
            return true;
        }
        if poly.iter().any(|p| p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y) {
            return true;
        }
        (0..n).any(|i| (0..4).any(|j| segments_intersect(poly[i], poly[(i + 1) % n], sq[j], sq[(j + 1) % 4])))
    }

    #[test]
    fn covering_sizes_and_errors() {
        let s = GridSpec::covering(bounds(36.0, 24.0), 0.1).expect("valid");
        assert_eq!((s.width, s.height), (360, 240));
        let s = GridSpec::covering(bounds(1.05, 0.0), 0.1).expect("valid");
        assert_eq!((s.width, s.height), (11, 1));
        assert_eq!(s.len(), 11);
        assert!(!s.is_empty());
        for bad in [0.0, -0.1, 5.01, f64::NAN, f64::INFINITY] {
            assert!(matches!(GridSpec::covering(bounds(1.0, 1.0), bad), Err(CoreError::Input { .. })));
        }
        assert!(GridSpec::covering(bounds(1e6, 1e6), 0.01).is_err());
        let bad = Bounds { min: v(0.0, f64::NAN), max: v(1.0, 1.0) };
        assert!(GridSpec::covering(bad, 0.1).is_err());
    }

    #[test]
    fn cell_of_and_center() {
        let s = GridSpec::covering(Bounds { min: v(-1.0, -2.0), max: v(1.0, 2.0) }, 0.5).expect("valid");
        assert_eq!((s.width, s.height), (4, 8));
        assert_eq!(s.cell_of(v(-1.0, -2.0)), Some((0, 0)));
        assert_eq!(s.cell_of(v(0.99, 1.99)), Some((3, 7)));
        assert_eq!(s.cell_of(v(1.0, 0.0)), None, "upper edge is outside");
        assert_eq!(s.cell_of(v(-1.01, 0.0)), None);
        assert_eq!(s.cell_of(v(f64::NAN, 0.0)), None);
        assert_eq!(s.cell_of(v(0.0, f64::INFINITY)), None);
        assert_eq!(s.center(0, 0), v(-0.75, -1.75));
        assert_eq!(s.index(3, 2), 11);
        assert_eq!(s.cell(11), (3, 2));
        for iy in 0..s.height {
            for ix in 0..s.width {
                assert_eq!(s.cell_of(s.center(ix, iy)), Some((ix, iy)));
            }
        }
    }

    #[test]
    fn rectangle_cells() {
        let spec = GridSpec::covering(bounds(2.0, 2.0), 0.1).expect("valid");
        // [0.25, 0.75] x [0.3, 0.5]: x cells 2..=7, y: 0.3 is a cell border (touching cell 2),
        // 0.5 is a border (touching cell 5).
        let r = vec![v(0.25, 0.3), v(0.75, 0.3), v(0.75, 0.5), v(0.25, 0.5)];
        let g = StaticGeometry::new(vec![r], bounds(2.0, 2.0)).expect("valid");
        let occ = OccupancyGrid::rasterize(&g, spec);
        let mut expected = Vec::new();
        for iy in 2..=5 {
            for ix in 2..=7 {
                expected.push((ix, iy));
            }
        }
        assert_eq!(occupied_set(&occ), expected);
    }

    #[test]
    fn thin_wall_blocks() {
        let spec = GridSpec::covering(bounds(4.0, 4.0), 0.1).expect("valid");
        // A 0.05 m thick vertical wall strictly inside column 20 (x in [2.02, 2.07]).
        let wall = vec![v(2.02, 0.0), v(2.07, 0.0), v(2.07, 4.0), v(2.02, 4.0)];
        let g = StaticGeometry::new(vec![wall], bounds(4.0, 4.0)).expect("valid");
        let occ = OccupancyGrid::rasterize(&g, spec);
        for iy in 0..spec.height {
            assert!(occ.occupied(20, iy), "row {iy}");
            assert!(!occ.occupied(19, iy) && !occ.occupied(21, iy));
        }
        // A thin (0.05 m) diagonal wall: exactly the overlapping cells are marked, and it leaves no
        // 8-connected gap (no two free cells on opposite sides that touch diagonally across it).
        let d = 0.025;
        let diag = vec![v(0.5, 0.5), v(0.5 + d, 0.5 - d), v(3.5 + d, 3.5 - d), v(3.5, 3.5)];
        let g = StaticGeometry::new(vec![diag.clone()], bounds(4.0, 4.0)).expect("valid");
        let occ = OccupancyGrid::rasterize(&g, spec);
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let got = occ.occupied(ix, iy);
                assert!(!overlaps(&diag, &spec, ix, iy, 0.0) || got, "missed {ix},{iy}");
                assert!(!got || overlaps(&diag, &spec, ix, iy, 1e-8), "extra {ix},{iy}");
            }
        }
        for i in 6..34 {
            // Cells (i, i+1) (above the wall) and (i+1, i) (below) touch diagonally at a corner on the
            // wall's centre line: one of the two cells between them must be blocked.
            assert!(occ.occupied(i, i) || occ.occupied(i + 1, i + 1), "diagonal leak at {i}");
        }
    }

    #[test]
    fn rotated_rectangle_matches_reference() {
        let spec = GridSpec::covering(bounds(4.0, 4.0), 0.1).expect("valid");
        let th: f64 = 0.4;
        let c = v(2.0, 2.0);
        let corners = [v(-1.0, -0.3), v(1.0, -0.3), v(1.0, 0.3), v(-1.0, 0.3)];
        let poly: Vec<Vec2> = corners.iter().map(|p| c + crate::math::rotate(*p, th)).collect();
        let g = StaticGeometry::new(vec![poly.clone()], bounds(4.0, 4.0)).expect("valid");
        let occ = OccupancyGrid::rasterize(&g, spec);
        let mut count = 0;
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let exact = overlaps(&poly, &spec, ix, iy, 0.0);
                let grown = overlaps(&poly, &spec, ix, iy, 1e-8);
                let got = occ.occupied(ix, iy);
                assert!(!exact || got, "missed overlapping cell {ix},{iy}");
                assert!(!got || grown, "marked non-overlapping cell {ix},{iy}");
                count += usize::from(got);
            }
        }
        // Area 1.2 m^2 = 120 cells plus a perimeter band.
        assert!(count > 120 && count < 250, "{count}");
    }

    #[test]
    fn geometry_outside_grid_is_ignored() {
        let spec = GridSpec::covering(bounds(1.0, 1.0), 0.1).expect("valid");
        let far = vec![v(5.0, 5.0), v(6.0, 5.0), v(6.0, 6.0)];
        let over = vec![v(-1.0, -1.0), v(2.0, -1.0), v(2.0, 0.05), v(-1.0, 0.05)];
        let g = StaticGeometry::new(vec![far, over], bounds(1.0, 1.0)).expect("valid");
        let occ = OccupancyGrid::rasterize(&g, spec);
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                assert_eq!(occ.occupied(ix, iy), iy == 0);
            }
        }
    }

    #[test]
    fn distance_field_basics() {
        let spec = GridSpec::covering(bounds(1.0, 0.5), 0.1).expect("valid");
        let mut occ = OccupancyGrid { spec, cells: vec![0; spec.len()] };
        let df = DistanceField::from_occupancy(&occ);
        assert!(df.metres.iter().all(|d| *d == f64::INFINITY));
        occ.cells[spec.index(0, 0)] = 1;
        let df = DistanceField::from_occupancy(&occ);
        assert_eq!(df.at(v(0.05, 0.05)), 0.0);
        assert!((df.at(v(0.35, 0.45)) - 0.5).abs() < 1e-12); // (3, 4) cells away
        assert_eq!(df.at(v(-1.0, 0.0)), 0.0);
        assert_eq!(df.at(v(f64::NAN, 0.0)), 0.0);
    }

    proptest! {
        #[test]
        fn edt_equals_brute_force(w in 1usize..24, h in 1usize..24, seed in any::<u64>(), density in 0.0f64..0.3) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let spec = GridSpec { origin: v(0.0, 0.0), resolution: 0.1, width: w, height: h };
            let cells: Vec<u8> = (0..w * h).map(|_| u8::from(rng.random::<f64>() < density)).collect();
            let occ = OccupancyGrid { spec, cells };
            let df = DistanceField::from_occupancy(&occ);
            let occupied: Vec<(usize, usize)> =
                (0..w * h).filter(|&i| occ.cells[i] != 0).map(|i| spec.cell(i)).collect();
            for i in 0..w * h {
                let (x, y) = spec.cell(i);
                let brute = occupied
                    .iter()
                    .map(|&(ox, oy)| {
                        let dx = x as f64 - ox as f64;
                        let dy = y as f64 - oy as f64;
                        (dx * dx + dy * dy).sqrt() * 0.1
                    })
                    .fold(f64::INFINITY, f64::min);
                prop_assert!(
                    df.metres[i] == brute || (df.metres[i] - brute).abs() < 1e-12,
                    "cell {:?}: {} vs {}", (x, y), df.metres[i], brute
                );
            }
        }
    }
}
