//! World-frame polygons of walls, object footprints and interaction spaces.

use crate::scenario::model::CIRCLE_VERTICES;

/// Oriented rectangle centred at `c` with half extents along its local axes, CCW.
pub(in crate::scenario) fn oriented_rect(c: [f64; 2], theta: f64, half_x: f64, half_y: f64) -> Vec<[f64; 2]> {
    let (s, co) = theta.sin_cos();
    [(-half_x, -half_y), (half_x, -half_y), (half_x, half_y), (-half_x, half_y)]
        .iter()
        .map(|&(lx, ly)| [c[0] + co * lx - s * ly, c[1] + s * lx + co * ly])
        .collect()
}

/// Circle approximated by [`CIRCLE_VERTICES`] vertices, CCW, circumscribing the circle (so the
/// polygon contains the disc).
pub(in crate::scenario) fn circle_polygon(c: [f64; 2], r: f64) -> Vec<[f64; 2]> {
    let n = CIRCLE_VERTICES;
    let rr = r / (std::f64::consts::PI / n as f64).cos();
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            [c[0] + rr * a.cos(), c[1] + rr * a.sin()]
        })
        .collect()
}

/// Signed area (positive when CCW).
pub(in crate::scenario) fn signed_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let a = poly[i];
            let b = poly[(i + 1) % n];
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
        * 0.5
}
