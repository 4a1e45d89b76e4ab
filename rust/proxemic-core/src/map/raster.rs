//! Polygon rasterising: the grid cells whose centres lie inside a polygon, optionally with a
//! margin around it (the social cost map draws objects' interaction spaces with it).

use crate::geom::distance_point_segment;
use crate::map::grid::GridSpec;
use crate::math::Vec2;

/// Cells whose centres lie inside a polygon (even-odd rule), as grid indices in row order.
pub fn polygon_cells(spec: &GridSpec, polygon: &[Vec2], margin: f64) -> Vec<u32> {
    let mut cells = polygon_interior_cells(spec, polygon);
    if margin <= 0.0 || cells.is_empty() {
        return cells;
    }
    // The ring: cells outside whose centre lies within `margin` of an edge.
    let (mut lo, mut hi) =
        (Vec2::new(f64::INFINITY, f64::INFINITY), Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY));
    for p in polygon {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let res = spec.resolution;
    let cell_of = |v: f64, o: f64, n: usize| (((v - o) / res).floor().max(0.0) as usize).min(n - 1);
    let (x0, x1) = (
        cell_of(lo.x - margin, spec.origin.x, spec.width),
        cell_of(hi.x + margin, spec.origin.x, spec.width),
    );
    let (y0, y1) = (
        cell_of(lo.y - margin, spec.origin.y, spec.height),
        cell_of(hi.y + margin, spec.origin.y, spec.height),
    );
    let inside: std::collections::HashSet<u32> = cells.iter().copied().collect();
    for iy in y0..=y1 {
        for ix in x0..=x1 {
            let idx = spec.index(ix, iy) as u32;
            if inside.contains(&idx) {
                continue;
            }
            let c =
                Vec2::new(spec.origin.x + (ix as f64 + 0.5) * res, spec.origin.y + (iy as f64 + 0.5) * res);
            let near = (0..polygon.len()).any(|k| {
                let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
                distance_point_segment(c, a, b) <= margin
            });
            if near {
                cells.push(idx);
            }
        }
    }
    cells.sort_unstable();
    cells
}

/// The cells whose centre lies inside `polygon` (scanline fill).
fn polygon_interior_cells(spec: &GridSpec, polygon: &[Vec2]) -> Vec<u32> {
    let mut cells = Vec::new();
    if polygon.len() < 3 {
        return cells;
    }
    let (mut ymin, mut ymax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in polygon {
        ymin = ymin.min(p.y);
        ymax = ymax.max(p.y);
    }
    let res = spec.resolution;
    let row0 = (((ymin - spec.origin.y) / res - 0.5).ceil().max(0.0)) as usize;
    let row1 = ((((ymax - spec.origin.y) / res - 0.5).floor()).min(spec.height as f64 - 1.0)).max(-1.0);
    if row1 < 0.0 {
        return cells;
    }
    let mut xs: Vec<f64> = Vec::new();
    for iy in row0..=(row1 as usize) {
        let y = spec.origin.y + (iy as f64 + 0.5) * res;
        xs.clear();
        for k in 0..polygon.len() {
            let a = polygon[k];
            let b = polygon[(k + 1) % polygon.len()];
            if (a.y <= y && b.y > y) || (b.y <= y && a.y > y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            let c0 = ((pair[0] - spec.origin.x) / res - 0.5).ceil().max(0.0) as usize;
            let c1 = ((pair[1] - spec.origin.x) / res - 0.5).floor().min(spec.width as f64 - 1.0);
            if c1 < 0.0 {
                continue;
            }
            for ix in c0..=(c1 as usize) {
                cells.push(spec.index(ix, iy) as u32);
            }
        }
    }
    cells
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::Bounds;

    #[test]
    fn polygon_cells_of_a_square() {
        let spec = GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(10.0, 10.0) }, 0.1)
            .expect("valid grid");
        let poly = vec![Vec2::new(1.0, 1.0), Vec2::new(2.0, 1.0), Vec2::new(2.0, 2.0), Vec2::new(1.0, 2.0)];
        assert_eq!(polygon_cells(&spec, &poly, 0.0).len(), 100);
        assert!(polygon_cells(&spec, &poly[..2], 0.0).is_empty());
        // A 0.22 m margin adds the cells whose centre is within 0.22 m of an edge: 2 more
        // columns or rows along each side (centres 0.05 and 0.15 m out) and, at each corner,
        // the 2 x 2 cells whose centres are at most 0.15 * sqrt(2) = 0.21 m from it.
        let ring = polygon_cells(&spec, &poly, 0.22);
        assert_eq!(ring.len(), 100 + 4 * 2 * 10 + 4 * 4);
        assert!(ring.windows(2).all(|w| w[0] < w[1]), "sorted, no duplicates");
    }
}
