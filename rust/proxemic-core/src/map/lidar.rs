//! A 2D lidar: evenly spaced range readings against the static geometry and moving discs.

use crate::error::{CoreError, Result};
use crate::geom::cross;
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;

/// Distance along the unit ray `origin + t * dir` to the circle of radius `r` centred at `c`:
/// `Some(0)` if the origin is inside or on the disc, `None` on a miss or if the hit is beyond
/// `max_t`.
#[inline]
fn ray_disc(origin: Vec2, dir: Vec2, c: Vec2, r: f64, max_t: f64) -> Option<f64> {
    let m = origin - c;
    let cc = m.norm_squared() - r * r;
    if cc <= 0.0 {
        return Some(0.0);
    }
    let b = m.dot(&dir);
    if b >= 0.0 {
        return None; // outside and pointing away
    }
    let disc = b * b - cc;
    if disc < 0.0 {
        return None;
    }
    let t = -b - disc.sqrt();
    (t < max_t).then_some(t.max(0.0))
}

/// 2D lidar: `n_rays = out.len()` rays evenly spaced over 2*pi starting at `heading` (radians; ray k
/// at `heading + k * 2*pi / n_rays`), cast from `origin` (metres) against the static geometry and
/// the given discs `(centre, radius)` (metres). Writes the distance to the first hit (metres), or
/// `max_range` if nothing is hit within it, into `out[k]`. An origin inside a polygon or a disc
/// reads 0 on every ray that starts inside.
///
/// Every polygon edge near the origin that faces it, and every disc, is intersected exactly
/// with only the rays inside its angular extent, so the cost grows with the rays an edge or a
/// disc covers, not with rays times edges and discs. [`Scanner`] does the same with reusable buffers and a cache of the
/// static part for a lidar that has not moved.
///
/// Errors with [`CoreError::Input`] if `out` is empty (`out.len()` is the number of rays), if
/// `origin` or `heading` is not finite, if `max_range` is not finite and positive, or if a disc
/// has a non-finite centre or a negative or non-finite radius. `out` is left untouched on error.
pub fn scan(
    geom: &StaticGeometry,
    discs: &[(Vec2, f64)],
    origin: Vec2,
    heading: f64,
    max_range: f64,
    out: &mut [f64],
) -> Result<()> {
    Scanner::default().scan(geom, discs, origin, heading, max_range, out)
}

/// A lidar with its working buffers: [`scan`] without allocations, and with the static part of
/// the last scan kept, so a lidar that has not moved (same origin, heading, range and ray count,
/// bit for bit) against the same geometry reuses it instead of casting its rays again; a lidar
/// that only turned (same origin and range) reuses the edges facing it, with their bearings,
/// and casts its rays against them. Results are exactly those of [`scan`]. Use one `Scanner`
/// per lidar and one static geometry.
#[derive(Clone, Debug, Default)]
pub struct Scanner {
    /// (origin x, origin y, heading, range) of the cached static ranges and directions, as bits.
    key: Option<[u64; 4]>,
    /// The static ranges of the last scan.
    ranges: Vec<f64>,
    /// The unit direction of every ray of the last scan.
    dirs: Vec<Vec2>,
    /// (origin x, origin y, range) of the cached facing edges, as bits.
    edges_key: Option<[u64; 3]>,
    /// Whether that origin is inside the static geometry (then there are no edges).
    inside: bool,
    /// The edges near that origin that face it, in the geometry's order.
    edges: Vec<FacingEdge>,
}

/// A polygon edge `a -> b` that faces a lidar's origin, as the static cast uses it.
#[derive(Clone, Copy, Debug)]
struct FacingEdge {
    /// `a` relative to the origin (m).
    pa: Vec2,
    /// `b - a` (m).
    seg: Vec2,
    /// The bearing of `b` from the origin ([`atan2_approx`], radians, world frame).
    bearing: f64,
    /// The angle the edge spans seen from the origin, from `b` counter-clockwise to `a`
    /// ([`atan2_approx`], radians, below pi).
    span: f64,
}

/// Largest error of [`atan2_approx`] (radians): the series' first omitted term,
/// `tan(pi/8)^11 / 11 < 6e-6`, plus rounding; checked by a test.
const ATAN2_MAX_ERROR: f64 = 1e-5;

/// `y.atan2(x)` within [`ATAN2_MAX_ERROR`] (0 for the origin). The ratio `z` in [0, 1] of the
/// smaller to the larger coordinate magnitude is reduced to `|w| <= tan(pi/8)` with
/// `atan z = pi/4 + atan((z - 1) / (z + 1))`, and `atan w` is the Taylor series to `w^9`
/// (alternating, so its error is below the first omitted term); the octant is folded back. It
/// only picks which rays may meet an edge: the hits themselves are computed exactly.
#[inline]
fn atan2_approx(y: f64, x: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let (num, den) = if ay > ax { (ax, ay) } else { (ay, ax) };
    if den == 0.0 {
        return 0.0;
    }
    let z = num / den;
    let (base, w) =
        if z > std::f64::consts::SQRT_2 - 1.0 { (FRAC_PI_4, (z - 1.0) / (z + 1.0)) } else { (0.0, z) };
    let w2 = w * w;
    let mut a = base + w * (1.0 - w2 * (1.0 / 3.0 - w2 * (1.0 / 5.0 - w2 * (1.0 / 7.0 - w2 / 9.0))));
    if ay > ax {
        a = FRAC_PI_2 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    if y < 0.0 { -a } else { a }
}

/// `x.floor() as i64` for `|x| < 2^53` without a libm call (ray indices, a few per edge and
/// disc).
#[inline]
fn floor_i64(x: f64) -> i64 {
    let t = x as i64;
    if t as f64 > x { t - 1 } else { t }
}

/// `x.ceil() as i64` for `|x| < 2^53` without a libm call.
#[inline]
fn ceil_i64(x: f64) -> i64 {
    let t = x as i64;
    if (t as f64) < x { t + 1 } else { t }
}

impl Scanner {
    /// Scans as [`scan`] does (same arguments, results and errors).
    pub fn scan(
        &mut self,
        geom: &StaticGeometry,
        discs: &[(Vec2, f64)],
        origin: Vec2,
        heading: f64,
        max_range: f64,
        out: &mut [f64],
    ) -> Result<()> {
        if out.is_empty() {
            return Err(CoreError::input("out", "a buffer of n_rays >= 1 ranges", "an empty buffer"));
        }
        if !(origin.x.is_finite() && origin.y.is_finite()) {
            return Err(CoreError::input("origin", "finite coordinates (metres)", format!("{origin:?}")));
        }
        if !heading.is_finite() {
            return Err(CoreError::input("heading", "a finite angle (radians)", format!("{heading}")));
        }
        if !(max_range.is_finite() && max_range > 0.0) {
            return Err(CoreError::input("max_range", "a finite range > 0 (metres)", format!("{max_range}")));
        }
        for (k, &(c, r)) in discs.iter().enumerate() {
            if !(c.x.is_finite() && c.y.is_finite() && r.is_finite() && r >= 0.0) {
                return Err(CoreError::input(
                    format!("discs[{k}]"),
                    "a finite centre and a finite radius >= 0 (metres)",
                    format!("centre {:?}, radius {r}", (c.x, c.y)),
                ));
            }
        }
        let n = out.len();
        let step = std::f64::consts::TAU / n as f64;
        let key = [origin.x.to_bits(), origin.y.to_bits(), heading.to_bits(), max_range.to_bits()];
        if self.key == Some(key) && self.ranges.len() == n {
            out.copy_from_slice(&self.ranges);
        } else {
            self.set_directions(heading, step, n);
            self.facing_edges(geom, origin, max_range);
            Self::cast_static(&self.edges, self.inside, heading, max_range, step, &self.dirs, out);
            self.ranges.clear();
            self.ranges.extend_from_slice(out);
            self.key = Some(key);
        }
        if out[0] == 0.0 && geom.contains(origin) {
            return Ok(()); // inside the static geometry: every ray reads 0 already
        }
        // Discs: each only touches the rays inside its angular extent asin(r / d) around its bearing
        // (both from `atan2_approx`, widened by its error and one extra ray on each side); those
        // are intersected exactly.
        let tol = 2.0 * ATAN2_MAX_ERROR;
        let wrapped = heading.rem_euclid(std::f64::consts::TAU);
        for &(c, r) in discs {
            let rel = c - origin;
            let d = rel.norm();
            if d - r >= max_range {
                continue;
            }
            if d <= r {
                out.fill(0.0);
                continue;
            }
            let half = atan2_approx(r, (d * d - r * r).sqrt()) + tol;
            let bearing = atan2_approx(rel.y, rel.x) - wrapped;
            let first = floor_i64((bearing - half) / step) - 1;
            let last = ceil_i64((bearing + half) / step) + 1;
            let span = (last - first + 1).min(n as i64);
            // Ray indices wrap around: one division for the first, then counted on.
            let mut k = first.rem_euclid(n as i64) as usize;
            for _ in 0..span {
                if let Some(t) = ray_disc(origin, self.dirs[k], c, r, out[k]) {
                    out[k] = t;
                }
                k += 1;
                if k == n {
                    k = 0;
                }
            }
        }
        Ok(())
    }

    /// The unit directions of the `n` rays from `heading`, `step` apart: by exact rotation of the
    /// previous one (two trig calls per 16 rays, not per ray), re-anchored every 16 rays so
    /// rounding cannot accumulate.
    fn set_directions(&mut self, heading: f64, step: f64, n: usize) {
        let (rs, rc) = step.sin_cos();
        self.dirs.clear();
        let mut dir = Vec2::zeros();
        for k in 0..n {
            if k % 16 == 0 {
                let a = heading + k as f64 * step;
                dir = Vec2::new(a.cos(), a.sin());
            }
            self.dirs.push(dir);
            dir = Vec2::new(rc * dir.x - rs * dir.y, rs * dir.x + rc * dir.y);
        }
    }

    /// The edges near `origin` (within `max_range`) that face it, into `edges` (and whether
    /// `origin` is inside the static geometry), unless they are those of the last call.
    ///
    /// Polygons are counter-clockwise and the origin is outside all of them, so a ray's first hit
    /// is where it enters a polygon: on an edge that has the origin on its right.
    fn facing_edges(&mut self, geom: &StaticGeometry, origin: Vec2, max_range: f64) {
        let key = [origin.x.to_bits(), origin.y.to_bits(), max_range.to_bits()];
        if self.edges_key == Some(key) {
            return;
        }
        self.edges.clear();
        self.inside = geom.contains(origin);
        if !self.inside {
            let edges = &mut self.edges;
            geom.for_each_edge_near(origin, max_range, |a, b| {
                let (pa, pb) = (a - origin, b - origin);
                let turn = cross(pa, pb);
                if turn >= 0.0 {
                    return; // the origin on the edge's inner side or on its line: never a first hit
                }
                // The edge spans the angles from pb counter-clockwise to pa (less than pi).
                let bearing = atan2_approx(pb.y, pb.x);
                let span = atan2_approx(-turn, pb.dot(&pa));
                edges.push(FacingEdge { pa, seg: b - a, bearing, span });
            });
        }
        self.edges_key = Some(key);
    }

    /// The static part of a scan along `dirs` against the facing `edges` (0 everywhere from
    /// `inside` a polygon). Each edge is tested against the rays of its angular extent only
    /// (found with [`atan2_approx`] and widened by its error), with the hit computed exactly.
    fn cast_static(
        edges: &[FacingEdge],
        inside: bool,
        heading: f64,
        max_range: f64,
        step: f64,
        dirs: &[Vec2],
        out: &mut [f64],
    ) {
        if inside {
            out.fill(0.0);
            return;
        }
        out.fill(max_range);
        let n = out.len() as i64;
        let heading = heading.rem_euclid(std::f64::consts::TAU);
        let tol = 2.0 * ATAN2_MAX_ERROR;
        for &FacingEdge { pa, seg, bearing, span } in edges {
            let start = bearing - heading;
            let first = floor_i64((start - tol) / step);
            let last = ceil_i64((start + span + tol) / step).min(first + n - 1);
            // Ray indices wrap around: one division for the first, then counted on.
            let mut next = first.rem_euclid(n) as usize;
            for _ in first..=last {
                let k = next;
                next = if k + 1 == dirs.len() { 0 } else { k + 1 };
                let dir = dirs[k];
                let denom = cross(dir, seg);
                if denom.abs() < 1e-15 {
                    continue;
                }
                let t = cross(pa, seg) / denom;
                // Where along the edge, only for a nearer hit (one division less for most rays).
                if t >= 0.0 && t < out[k] && (-1e-12..=1.0 + 1e-12).contains(&(cross(pa, dir) / denom)) {
                    out[k] = t;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::Bounds;
    use proptest::prelude::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn world() -> Bounds {
        Bounds { min: v(-10.0, -10.0), max: v(10.0, 10.0) }
    }

    /// A wall at x in [3, 3.2], y in [-5, 5].
    fn wall() -> StaticGeometry {
        let w = vec![v(3.0, -5.0), v(3.2, -5.0), v(3.2, 5.0), v(3.0, 5.0)];
        StaticGeometry::new(vec![w], world()).expect("valid wall")
    }

    /// Brute force: every edge and every disc, no culling, no BVH.
    fn reference(
        geom: &StaticGeometry,
        discs: &[(Vec2, f64)],
        o: Vec2,
        heading: f64,
        max: f64,
        n: usize,
    ) -> Vec<f64> {
        (0..n)
            .map(|k| {
                let a = heading + k as f64 * std::f64::consts::TAU / n as f64;
                let d = v(a.cos(), a.sin());
                if geom.contains(o) {
                    return 0.0;
                }
                let mut best = max;
                for (p, q) in geom.edges() {
                    let e = q - p;
                    let den = cross(d, e);
                    if den.abs() < 1e-15 {
                        continue;
                    }
                    let t = cross(p - o, e) / den;
                    let u = cross(p - o, d) / den;
                    if t >= 0.0 && (-1e-12..=1.0 + 1e-12).contains(&u) {
                        best = best.min(t);
                    }
                }
                for &(c, r) in discs {
                    let m = o - c;
                    if m.norm() <= r {
                        best = 0.0;
                        continue;
                    }
                    let b = m.dot(&d);
                    let disc = b * b - (m.norm_squared() - r * r);
                    if disc >= 0.0 {
                        let t = -b - disc.sqrt();
                        if t >= 0.0 {
                            best = best.min(t);
                        }
                    }
                }
                best
            })
            .collect()
    }

    #[test]
    fn approximate_atan2_stays_within_its_error_bound() {
        let mut worst: f64 = 0.0;
        for i in 0..200_000 {
            let th = -std::f64::consts::PI + i as f64 * std::f64::consts::TAU / 200_000.0;
            for r in [1e-9, 0.3, 7.0, 1e6] {
                let (y, x) = (r * th.sin(), r * th.cos());
                worst = worst.max(crate::math::wrap_angle(atan2_approx(y, x) - y.atan2(x)).abs());
            }
        }
        assert!(worst <= ATAN2_MAX_ERROR, "worst error {worst}");
        assert!(worst > 0.1 * ATAN2_MAX_ERROR, "the bound is tight enough to mean something: {worst}");
        assert_eq!(atan2_approx(0.0, 0.0), 0.0);
    }

    #[test]
    fn integer_floor_and_ceil_equal_the_float_ones() {
        for x in [-3.5, -3.0, -2.9, -0.5, -0.0, 0.0, 1e-300, 0.5, 2.0, 2.000001, 71.99999, 1e15 + 0.5] {
            assert_eq!(floor_i64(x), x.floor() as i64, "floor {x}");
            assert_eq!(ceil_i64(x), x.ceil() as i64, "ceil {x}");
        }
    }

    #[test]
    fn hits_wall_at_known_distance() {
        let g = wall();
        let mut out = vec![0.0; 4];
        scan(&g, &[], v(0.0, 0.0), 0.0, 10.0, &mut out).expect("valid scan");
        assert!((out[0] - 3.0).abs() < 1e-12, "{out:?}");
        assert_eq!(&out[1..], &[10.0, 10.0, 10.0]);
        // Ray 0 at 45 degrees hits x = 3 at distance 3 * sqrt(2).
        scan(&g, &[], v(0.0, 0.0), std::f64::consts::FRAC_PI_4, 10.0, &mut out).expect("valid");
        assert!((out[0] - 3.0 * 2f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn disc_shadows_wall() {
        let g = wall();
        let mut out = vec![0.0; 8];
        let discs = [(v(1.5, 0.0), 0.25), (v(-50.0, 0.0), 1.0)];
        scan(&g, &discs, v(0.0, 0.0), 0.0, 10.0, &mut out).expect("valid");
        assert!((out[0] - 1.25).abs() < 1e-12, "{out:?}");
        // Disc behind the robot does not matter for the forward ray, and the far disc is culled.
        assert_eq!(out[4], 10.0);
        // Origin inside a disc reads 0.
        scan(&g, &[(v(0.1, 0.0), 0.5)], v(0.0, 0.0), 0.0, 10.0, &mut out).expect("valid");
        assert!(out.iter().all(|r| *r == 0.0));
        // Origin inside the wall reads 0.
        scan(&g, &[], v(3.1, 0.0), 0.0, 10.0, &mut out).expect("valid");
        assert!(out.iter().all(|r| *r == 0.0));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let g = wall();
        let mut out = vec![7.0; 4];
        let o = v(0.0, 0.0);
        assert!(scan(&g, &[], o, 0.0, 10.0, &mut []).is_err());
        assert!(scan(&g, &[], v(f64::NAN, 0.0), 0.0, 10.0, &mut out).is_err());
        assert!(scan(&g, &[], o, f64::INFINITY, 10.0, &mut out).is_err());
        assert!(scan(&g, &[], o, 0.0, f64::NAN, &mut out).is_err());
        assert!(scan(&g, &[], o, 0.0, 0.0, &mut out).is_err());
        assert!(scan(&g, &[(o, -1.0)], o, 0.0, 10.0, &mut out).is_err());
        assert!(matches!(
            scan(&g, &[(v(f64::NAN, 1.0), 1.0)], o, 0.0, 10.0, &mut out),
            Err(CoreError::Input { .. })
        ));
        assert!(out.iter().all(|r| *r == 7.0), "untouched on error");
    }

    #[test]
    fn many_discs_take_the_slow_path_correctly() {
        let g = wall();
        let discs: Vec<(Vec2, f64)> =
            (0..100).map(|i| (v(1.0 + 0.01 * i as f64, -2.0 + 0.04 * i as f64), 0.05)).collect();
        let mut out = vec![0.0; 90];
        scan(&g, &discs, v(0.0, 0.0), 0.1, 8.0, &mut out).expect("valid");
        let want = reference(&g, &discs, v(0.0, 0.0), 0.1, 8.0, 90);
        for (a, b) in out.iter().zip(&want) {
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
    }

    #[test]
    fn scanner_equals_scan_bit_for_bit_with_and_without_its_cache() {
        let g = wall();
        let mut sc = Scanner::default();
        let discs = [(v(1.5, 0.2), 0.25), (v(2.0, -1.0), 0.3)];
        let mut a = vec![0.0; 36];
        let mut b = vec![0.0; 36];
        for (o, h, d) in [
            (v(0.0, 0.0), 0.3, &discs[..]),
            (v(0.0, 0.0), 0.3, &discs[..1]), // same pose: the static part comes from the cache
            (v(0.0, 0.0), 0.3, &[][..]),
            (v(0.5, 0.1), 0.3, &discs[..]),  // moved
            (v(0.5, 0.1), -1.0, &discs[..]), // turned: the facing edges come from the cache
            (v(0.5, 0.1), 2.5, &discs[..1]),
            (v(0.5, 0.1), 2.5 + 1e-9, &[][..]),
            (v(3.1, 0.0), 0.0, &discs[..]), // inside the wall
            (v(3.1, 0.0), 0.0, &discs[..]),
            (v(3.1, 0.0), 1.0, &discs[..]), // turned inside the wall
            (v(0.5, 0.1), 0.3, &discs[..]), // back where it was (the cache holds one origin)
        ] {
            sc.scan(&g, d, o, h, 8.0, &mut a).expect("valid");
            scan(&g, d, o, h, 8.0, &mut b).expect("valid");
            assert_eq!(
                a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                b.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
        }
        // Turning in place at the same origin with a range the edges were not gathered for: the
        // edges (gathered within the range) are gathered again, a wall beyond 2.5 m is not hit.
        sc.scan(&g, &[], v(0.0, 0.0), 0.7, 8.0, &mut a).expect("valid");
        for (range, h) in [(2.5, 0.8), (2.5, 0.9), (8.0, 1.0)] {
            sc.scan(&g, &[], v(0.0, 0.0), h, range, &mut a).expect("valid");
            scan(&g, &[], v(0.0, 0.0), h, range, &mut b).expect("valid");
            assert_eq!(
                a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                b.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
            assert_eq!(a.iter().any(|&r| r < range), range > 3.0, "range {range}");
        }
        // A different ray count at the same pose is not served from the cache.
        let mut c = vec![0.0; 12];
        sc.scan(&g, &[], v(3.1, 0.0), 0.0, 8.0, &mut c).expect("valid");
        sc.scan(&g, &[], v(0.0, 0.0), 0.0, 8.0, &mut c).expect("valid");
        let mut d = vec![0.0; 12];
        scan(&g, &[], v(0.0, 0.0), 0.0, 8.0, &mut d).expect("valid");
        assert_eq!(c, d);
    }

    proptest! {
        #[test]
        fn a_turning_scanner_equals_scan_bit_for_bit(seed in any::<u64>(), n in 1usize..400) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let polys = (0..rng.random_range(1..6))
                .map(|_| {
                    let c = v(rng.random_range(-6.0..6.0), rng.random_range(-6.0..6.0));
                    let r = rng.random_range(0.3..2.0);
                    (0..5).map(|i| c + v((i as f64 * 1.2566).cos(), (i as f64 * 1.2566).sin()) * r).collect()
                })
                .collect();
            let g = StaticGeometry::new(polys, world()).expect("valid polygons");
            let mut sc = Scanner::default();
            let o = v(rng.random_range(-9.0..9.0), rng.random_range(-9.0..9.0));
            let mut heading: f64 = rng.random_range(-4.0..4.0);
            let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
            for _ in 0..6 {
                heading += rng.random_range(-0.5..0.5);
                sc.scan(&g, &[], o, heading, 7.0, &mut a).expect("valid");
                scan(&g, &[], o, heading, 7.0, &mut b).expect("valid");
                prop_assert_eq!(
                    a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                    b.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
                );
            }
        }

        #[test]
        fn equals_brute_force_on_random_scenes(seed in any::<u64>(), n in 1usize..1500) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let mut polys = Vec::new();
            for _ in 0..rng.random_range(0..8) {
                let c = v(rng.random_range(-8.0..8.0), rng.random_range(-8.0..8.0));
                let k = rng.random_range(3..9);
                let r = rng.random_range(0.2..2.0);
                let th0: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                // Star-shaped, so simple.
                let poly = (0..k)
                    .map(|i| {
                        let th = th0 + i as f64 * std::f64::consts::TAU / k as f64;
                        let rr = r * rng.random_range(0.4..1.0);
                        c + v(th.cos(), th.sin()) * rr
                    })
                    .collect();
                polys.push(poly);
            }
            let g = StaticGeometry::new(polys, world()).expect("valid polygons");
            let discs: Vec<(Vec2, f64)> = (0..rng.random_range(0..25))
                .map(|_| (v(rng.random_range(-9.0..9.0), rng.random_range(-9.0..9.0)), rng.random_range(0.0..0.6)))
                .collect();
            let o = v(rng.random_range(-9.0..9.0), rng.random_range(-9.0..9.0));
            let heading = rng.random_range(-4.0..4.0);
            let max = rng.random_range(0.5..15.0);
            let mut out = vec![0.0; n];
            scan(&g, &discs, o, heading, max, &mut out).expect("valid scan");
            let want = reference(&g, &discs, o, heading, max, n);
            for k in 0..n {
                prop_assert!((out[k] - want[k]).abs() < 1e-9, "ray {}: {} vs {}", k, out[k], want[k]);
            }
        }
    }
}
