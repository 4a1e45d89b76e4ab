//! 2D geometry primitives shared by the maps, the planners, the group detectors and the metrics,
//! named in parry's `op_shape_shape` style (`distance_point_segment`, `contains_point_polygon`).
//!
//! Conventions: points and vectors are [`Vec2`] in metres (any consistent length unit works: no
//! primitive has a built-in scale except where a tolerance says otherwise); a polygon is a slice of
//! its vertices in order, either orientation, closed implicitly (the last vertex joins the first).
//! Every primitive is a pure function of its arguments and never panics.

use crate::math::Vec2;

/// The 2D cross product `a x b = a.x b.y - a.y b.x` (m² for two vectors in metres): positive when
/// `b` turns counter-clockwise from `a`, zero when they are parallel.
#[inline]
pub fn cross(a: Vec2, b: Vec2) -> f64 {
    a.x * b.y - a.y * b.x
}

/// Signed area of the polygon `poly` (m²): positive for counter-clockwise vertices, negative for
/// clockwise ones (the shoelace formula, half the sum of `cross(v_i, v_{i+1})`); 0 for fewer than
/// 3 vertices.
pub fn signed_area_polygon(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    0.5 * (0..n).map(|i| cross(poly[i], poly[(i + 1) % n])).sum::<f64>()
}

/// Distance (m) from the point `p` to the closed segment `[a, b]`; the distance to `a` when the
/// segment is a point (`a == b`).
#[inline]
pub fn distance_point_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    distance_squared_point_segment(p, a, b).sqrt()
}

/// The square of [`distance_point_segment`] (m²), without the square root (ORCA's static
/// obstacles compare squared distances).
pub fn distance_squared_point_segment(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = b - a;
    let l2 = ab.norm_squared();
    let t = if l2 > 0.0 { ((p - a).dot(&ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).norm_squared()
}

/// Whether the point `p` is inside the polygon `poly` by the even-odd (crossing number) rule: a
/// horizontal ray from `p` towards +x crosses the edges an odd number of times. The boundary is
/// inside on some edges and outside on others (use a distance test for a closed polygon); fewer
/// than 3 vertices contain nothing. Each edge `v_k -> v_{k+1}` is interpolated from `v_k`.
pub fn contains_point_polygon(p: Vec2, poly: &[Vec2]) -> bool {
    let n = poly.len();
    let mut inside = false;
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x) {
            inside = !inside;
        }
    }
    inside
}

/// [`contains_point_polygon`] with W. R. Franklin's PNPOLY rounding: each edge `v_{k-1} -> v_k`
/// is interpolated from `v_k`, multiplying before dividing. It is the same test in exact
/// arithmetic; the two can disagree only for a point within a few ulps of an edge. The metrics'
/// object spaces and person-object interactions use this one.
pub fn contains_point_polygon_pnpoly(p: Vec2, poly: &[Vec2]) -> bool {
    if poly.len() < 3 {
        return false;
    }
    let mut inside = false;
    let mut j = poly.len() - 1;
    for i in 0..poly.len() {
        let (a, b) = (poly[i], poly[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Whether the point `p` is in the closed triangle `t` (either orientation), by its barycentric
/// coordinates with a tolerance of 1e-12 (relative to the triangle's area); false for a
/// (near-)degenerate triangle, whose doubled area is at most 1e-14 times its longest side from
/// `t[0]` squared.
pub fn contains_point_triangle(p: Vec2, t: &[Vec2; 3]) -> bool {
    let area2 = cross(t[1] - t[0], t[2] - t[0]);
    let scale = (t[1] - t[0]).norm_squared().max((t[2] - t[0]).norm_squared());
    if area2.abs() <= 1e-14 * scale || scale == 0.0 {
        return false;
    }
    let tol = -1e-12;
    let l0 = cross(t[1] - p, t[2] - p) / area2;
    let l1 = cross(t[2] - p, t[0] - p) / area2;
    let l2 = cross(t[0] - p, t[1] - p) / area2;
    l0 >= tol && l1 >= tol && l2 >= tol
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    /// The unit square, counter-clockwise.
    fn square() -> Vec<Vec2> {
        vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)]
    }

    /// An L-shaped (concave) hexagon, clockwise: the 2 x 2 square without its upper-right quarter.
    fn ell_cw() -> Vec<Vec2> {
        vec![v(0.0, 0.0), v(0.0, 2.0), v(1.0, 2.0), v(1.0, 1.0), v(2.0, 1.0), v(2.0, 0.0)]
    }

    #[test]
    fn cross_sign_and_magnitude() {
        assert_eq!(cross(v(1.0, 0.0), v(0.0, 1.0)), 1.0);
        assert_eq!(cross(v(0.0, 1.0), v(1.0, 0.0)), -1.0);
        assert_eq!(cross(v(2.0, 3.0), v(4.0, 6.0)), 0.0);
        assert_eq!(cross(v(2.0, 1.0), v(-1.0, 3.0)), 7.0);
    }

    #[test]
    fn signed_area_by_orientation() {
        assert_eq!(signed_area_polygon(&square()), 1.0);
        let mut cw = square();
        cw.reverse();
        assert_eq!(signed_area_polygon(&cw), -1.0);
        assert_eq!(signed_area_polygon(&ell_cw()), -3.0);
        assert_eq!(signed_area_polygon(&[v(0.0, 0.0), v(1.0, 1.0)]), 0.0);
        assert_eq!(signed_area_polygon(&[]), 0.0);
    }

    #[test]
    fn distance_to_a_segment_its_ends_and_a_point() {
        let (a, b) = (v(0.0, 0.0), v(4.0, 0.0));
        assert_eq!(distance_point_segment(v(2.0, 3.0), a, b), 3.0);
        assert_eq!(distance_point_segment(v(-3.0, 4.0), a, b), 5.0);
        assert_eq!(distance_point_segment(v(7.0, -4.0), a, b), 5.0);
        assert_eq!(distance_point_segment(v(1.0, 0.0), a, b), 0.0);
        assert_eq!(distance_point_segment(v(3.0, 4.0), a, a), 5.0);
    }

    #[test]
    fn polygon_containment_both_roundings() {
        for contains in [contains_point_polygon, contains_point_polygon_pnpoly] {
            assert!(contains(v(0.5, 0.5), &square()));
            assert!(!contains(v(1.5, 0.5), &square()));
            assert!(!contains(v(0.5, -0.1), &square()));
            // The concave corner of the L is outside, its arms inside, in either orientation.
            let mut ccw = ell_cw();
            ccw.reverse();
            for poly in [ell_cw(), ccw] {
                assert!(contains(v(0.5, 1.5), &poly));
                assert!(contains(v(1.5, 0.5), &poly));
                assert!(!contains(v(1.5, 1.5), &poly));
                assert!(!contains(v(3.0, 0.5), &poly));
            }
            assert!(!contains(v(0.0, 0.0), &[v(-1.0, -1.0), v(1.0, 1.0)]));
            assert!(!contains(v(0.0, 0.0), &[]));
        }
    }

    #[test]
    fn triangle_containment_is_closed_and_rejects_degenerate_triangles() {
        let t = [v(0.0, 0.0), v(2.0, 0.0), v(0.0, 2.0)];
        let mut rev = t;
        rev.reverse();
        for tri in [t, rev] {
            assert!(contains_point_triangle(v(0.5, 0.5), &tri));
            assert!(contains_point_triangle(v(1.0, 1.0), &tri)); // on the hypotenuse
            assert!(contains_point_triangle(v(0.0, 0.0), &tri)); // a vertex
            assert!(!contains_point_triangle(v(1.1, 1.1), &tri));
            assert!(!contains_point_triangle(v(-0.1, 0.5), &tri));
        }
        let flat = [v(0.0, 0.0), v(1.0, 0.0), v(2.0, 0.0)];
        assert!(!contains_point_triangle(v(1.0, 0.0), &flat));
        assert!(!contains_point_triangle(v(0.0, 0.0), &[v(0.0, 0.0); 3]));
    }
}
