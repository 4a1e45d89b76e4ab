//! Fast ray casting against static edges: a uniform grid of edge buckets traversed with the
//! Amanatides-Woo digital differential analyser ("A Fast Voxel Traversal Algorithm for Ray
//! Tracing", Eurographics 1987).
//!
//! Each edge is stored in every bucket its bounding box overlaps. A single ray ([`EdgeGrid::cast`])
//! visits the buckets it crosses in order and stops as soon as its best hit lies before the exit
//! of the current bucket. The lidar, which casts a whole fan of rays from one point, instead
//! visits every edge near that point once ([`EdgeGrid::for_each_edge_near`]) and tests it against
//! only the rays of its angular extent.

use crate::geom::{cross, distance_point_segment};
use crate::math::Vec2;

/// Bucket size of the grid single rays and distance queries traverse (metres).
pub const BUCKET: f64 = 1.0;

/// Bucket size of the grid [`EdgeGrid::for_each_edge_near`] visits (metres): a query of a few
/// metres covers a handful of these instead of hundreds of fine buckets.
pub const COARSE_BUCKET: f64 = 4.0;

/// Edges bucketed on a uniform grid of square buckets, in compressed-row form.
#[derive(Clone, Debug)]
struct Buckets {
    min: Vec2,
    size: f64,
    nx: usize,
    ny: usize,
    /// `start[c]..start[c + 1]` indexes `items` for bucket `c`.
    start: Vec<u32>,
    items: Vec<u32>,
    /// Per edge, the lowest bucket column and row it is stored in.
    first: Vec<[u32; 2]>,
}

impl Buckets {
    /// Buckets of `size` metres over the box `[min, max]` grown by one bucket; every edge is
    /// stored in every bucket its bounding box overlaps.
    fn new(edges: &[(Vec2, Vec2)], min: Vec2, max: Vec2, size: f64) -> Self {
        let min = min - Vec2::new(size, size);
        let max = max + Vec2::new(size, size);
        let nx = (((max.x - min.x) / size).ceil() as usize).max(1);
        let ny = (((max.y - min.y) / size).ceil() as usize).max(1);
        let cell = |p: f64, lo: f64, n: usize| (((p - lo) / size).floor().max(0.0) as usize).min(n - 1);
        let ranges: Vec<(usize, usize, usize, usize)> = edges
            .iter()
            .map(|(a, b)| {
                (
                    cell(a.x.min(b.x), min.x, nx),
                    cell(a.x.max(b.x), min.x, nx),
                    cell(a.y.min(b.y), min.y, ny),
                    cell(a.y.max(b.y), min.y, ny),
                )
            })
            .collect();
        let mut count = vec![0u32; nx * ny + 1];
        for &(x0, x1, y0, y1) in &ranges {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    count[y * nx + x + 1] += 1;
                }
            }
        }
        for c in 1..count.len() {
            count[c] += count[c - 1];
        }
        let start = count.clone();
        let mut fill = count;
        let mut items = vec![0u32; start[nx * ny] as usize];
        for (e, &(x0, x1, y0, y1)) in ranges.iter().enumerate() {
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let c = y * nx + x;
                    items[fill[c] as usize] = e as u32;
                    fill[c] += 1;
                }
            }
        }
        let first = ranges.iter().map(|&(x0, _, y0, _)| [x0 as u32, y0 as u32]).collect();
        Buckets { min, size, nx, ny, start, items, first }
    }

    /// The edges of bucket (`x`, `y`).
    #[inline]
    fn bucket(&self, x: usize, y: usize) -> &[u32] {
        let c = y * self.nx + x;
        &self.items[self.start[c] as usize..self.start[c + 1] as usize]
    }

    /// The buckets `lo..=hi` of one axis (origin `min`, `n` buckets) overlapping `[from, to]`
    /// (metres), or `None` when none does (or a bound is not finite).
    fn span(&self, from: f64, to: f64, min: f64, n: usize) -> Option<(usize, usize)> {
        let lo = ((from - min) / self.size).floor();
        let hi = ((to - min) / self.size).floor();
        if !(lo.is_finite() && hi.is_finite()) || hi < 0.0 || lo >= n as f64 {
            return None;
        }
        Some((lo.max(0.0) as usize, (hi as usize).min(n - 1)))
    }
}

/// Edges bucketed twice: on a fine grid for single rays and distances, on a coarse one for the
/// edges near a point.
#[derive(Clone, Debug)]
pub struct EdgeGrid {
    fine: Buckets,
    coarse: Buckets,
    a: Vec<Vec2>,
    b: Vec<Vec2>,
}

impl EdgeGrid {
    /// Buckets `edges` (finite segments) over the box `[min, max]` (grown by one bucket).
    pub fn new(edges: &[(Vec2, Vec2)], min: Vec2, max: Vec2) -> Self {
        EdgeGrid {
            fine: Buckets::new(edges, min, max, BUCKET),
            coarse: Buckets::new(edges, min, max, COARSE_BUCKET),
            a: edges.iter().map(|e| e.0).collect(),
            b: edges.iter().map(|e| e.1).collect(),
        }
    }

    /// Distance from `p` to the nearest edge, looking only at the buckets within `max` metres of
    /// `p` (so at most `max`; `max` when no edge is that close).
    pub fn distance_within(&self, p: Vec2, max: f64) -> f64 {
        if !(p.x.is_finite() && p.y.is_finite()) {
            return 0.0;
        }
        let g = &self.fine;
        let span = (max / BUCKET).ceil() as isize;
        let cx = ((p.x - g.min.x) / BUCKET).floor() as isize;
        let cy = ((p.y - g.min.y) / BUCKET).floor() as isize;
        let mut best = max;
        for y in (cy - span).max(0)..=(cy + span).min(g.ny as isize - 1) {
            for x in (cx - span).max(0)..=(cx + span).min(g.nx as isize - 1) {
                for &e in g.bucket(x as usize, y as usize) {
                    best = best.min(distance_point_segment(p, self.a[e as usize], self.b[e as usize]));
                }
            }
        }
        best
    }

    /// Calls `f(a, b)` once for every edge (`a` to `b`, metres) whose bounding box overlaps the
    /// square of half-side `radius` (metres) around `p`: every edge within `radius` of `p`, and
    /// some farther ones. Nothing for a non-finite `p` or `radius`.
    pub fn for_each_edge_near(&self, p: Vec2, radius: f64, mut f: impl FnMut(Vec2, Vec2)) {
        let g = &self.coarse;
        let Some((x0, x1)) = g.span(p.x - radius, p.x + radius, g.min.x, g.nx) else {
            return;
        };
        let Some((y0, y1)) = g.span(p.y - radius, p.y + radius, g.min.y, g.ny) else {
            return;
        };
        let (lo, hi) = (p - Vec2::new(radius, radius), p + Vec2::new(radius, radius));
        for y in y0..=y1 {
            for x in x0..=x1 {
                for &e in g.bucket(x, y) {
                    // An edge spans a rectangle of buckets: it is visited in the one bucket where
                    // that rectangle's lowest corner meets the query's, so exactly once.
                    let [ex, ey] = g.first[e as usize];
                    if x != (ex as usize).max(x0) || y != (ey as usize).max(y0) {
                        continue;
                    }
                    let (a, b) = (self.a[e as usize], self.b[e as usize]);
                    if a.x.max(b.x) >= lo.x
                        && a.x.min(b.x) <= hi.x
                        && a.y.max(b.y) >= lo.y
                        && a.y.min(b.y) <= hi.y
                    {
                        f(a, b);
                    }
                }
            }
        }
    }

    /// Distance along the unit ray `origin + t * dir` to the first edge, or `max_range`.
    /// The origin must be finite; a ray starting outside the grid is traced from where it
    /// enters it (or misses everything).
    pub fn cast(&self, origin: Vec2, dir: Vec2, max_range: f64) -> f64 {
        let mut best = max_range;
        let g = &self.fine;
        let lo = g.min;
        let (w, h) = (g.nx as f64 * BUCKET, g.ny as f64 * BUCKET);
        // Reciprocals once per ray: the traversal below multiplies (a zero component gives an
        // infinite reciprocal, so that axis never advances).
        let inv = Vec2::new(1.0 / dir.x, 1.0 / dir.y);
        let (mut rx, mut ry) = (origin.x - lo.x, origin.y - lo.y);
        if !(rx >= 0.0 && rx < w && ry >= 0.0 && ry < h) {
            // Clip the ray to the grid box (slab test) to find where traversal starts.
            let (mut t0, mut t1) = (0.0f64, max_range);
            for (o, d, l) in [(rx, dir.x, w), (ry, dir.y, h)] {
                if d.abs() < 1e-300 {
                    if o < 0.0 || o > l {
                        return max_range;
                    }
                } else {
                    let (mut a, mut b) = (-o / d, (l - o) / d);
                    if a > b {
                        std::mem::swap(&mut a, &mut b);
                    }
                    t0 = t0.max(a);
                    t1 = t1.min(b);
                }
            }
            if t0 > t1 {
                return max_range;
            }
            rx = (rx + dir.x * t0).clamp(0.0, w);
            ry = (ry + dir.y * t0).clamp(0.0, h);
        }
        // Bucket of the start point (coordinates are >= 0 here, so truncation is floor).
        let mut cx = ((rx * (1.0 / BUCKET)) as usize).min(g.nx - 1);
        let mut cy = ((ry * (1.0 / BUCKET)) as usize).min(g.ny - 1);
        let (rel_x, rel_y) = (origin.x - lo.x, origin.y - lo.y);
        let (step_x, next_x) = if dir.x >= 0.0 { (1isize, (cx + 1) as f64) } else { (-1, cx as f64) };
        let (step_y, next_y) = if dir.y >= 0.0 { (1isize, (cy + 1) as f64) } else { (-1, cy as f64) };
        let mut t_max_x =
            if dir.x.abs() > 1e-300 { (next_x * BUCKET - rel_x) * inv.x } else { f64::INFINITY };
        let mut t_max_y =
            if dir.y.abs() > 1e-300 { (next_y * BUCKET - rel_y) * inv.y } else { f64::INFINITY };
        let dt_x = if dir.x.abs() > 1e-300 { BUCKET * inv.x.abs() } else { f64::INFINITY };
        let dt_y = if dir.y.abs() > 1e-300 { BUCKET * inv.y.abs() } else { f64::INFINITY };
        loop {
            for &e in g.bucket(cx, cy) {
                let (a, b) = (self.a[e as usize], self.b[e as usize]);
                let seg = b - a;
                let denom = cross(dir, seg);
                if denom.abs() < 1e-15 {
                    continue;
                }
                let ao = a - origin;
                let t = cross(ao, seg) / denom;
                let s = cross(ao, dir) / denom;
                if t >= 0.0 && t < best && (-1e-12..=1.0 + 1e-12).contains(&s) {
                    best = t;
                }
            }
            let exit = t_max_x.min(t_max_y);
            if best <= exit || exit >= max_range {
                return best;
            }
            // Step to the next bucket along x or y, chosen without a branch (the choice is
            // unpredictable, a mispredicted branch cost more than the rest of a bucket visit).
            let go_x = t_max_x < t_max_y;
            let nx = cx as isize + if go_x { step_x } else { 0 };
            let ny = cy as isize + if go_x { 0 } else { step_y };
            t_max_x = if go_x { t_max_x + dt_x } else { t_max_x };
            t_max_y = if go_x { t_max_y } else { t_max_y + dt_y };
            if nx < 0 || nx >= g.nx as isize || ny < 0 || ny >= g.ny as isize {
                return best;
            }
            cx = nx as usize;
            cy = ny as usize;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute(edges: &[(Vec2, Vec2)], o: Vec2, d: Vec2, max: f64) -> f64 {
        let mut best = max;
        for &(a, b) in edges {
            let seg = b - a;
            let denom = cross(d, seg);
            if denom.abs() < 1e-15 {
                continue;
            }
            let t = cross(a - o, seg) / denom;
            let s = cross(a - o, d) / denom;
            if t >= 0.0 && t < best && (0.0..=1.0).contains(&s) {
                best = t;
            }
        }
        best
    }

    #[test]
    fn local_distance_equals_brute_force_within_range() {
        let edges = [(Vec2::new(0.0, 0.0), Vec2::new(4.0, 0.0)), (Vec2::new(4.0, 0.0), Vec2::new(4.0, 3.0))];
        let g = EdgeGrid::new(&edges, Vec2::new(-2.0, -2.0), Vec2::new(6.0, 5.0));
        assert!((g.distance_within(Vec2::new(2.0, 0.3), 1.0) - 0.3).abs() < 1e-12);
        assert!((g.distance_within(Vec2::new(4.2, 3.1), 1.0) - (0.2f64.hypot(0.1))).abs() < 1e-12);
        assert_eq!(g.distance_within(Vec2::new(2.0, 1.5), 1.0), 1.0);
    }

    #[test]
    fn hits_a_wall_across_several_buckets() {
        let edges = [(Vec2::new(5.0, -3.0), Vec2::new(5.0, 3.0))];
        let g = EdgeGrid::new(&edges, Vec2::new(-6.0, -6.0), Vec2::new(6.0, 6.0));
        assert!((g.cast(Vec2::zeros(), Vec2::new(1.0, 0.0), 10.0) - 5.0).abs() < 1e-12);
        assert_eq!(g.cast(Vec2::zeros(), Vec2::new(-1.0, 0.0), 10.0), 10.0);
        assert_eq!(g.cast(Vec2::zeros(), Vec2::new(1.0, 0.0), 4.0), 4.0);
    }

    /// Up to 39 segments starting in [-10, 10]^2, each coordinate of their extent within
    /// `max_extent` metres.
    fn random_edges(rng: &mut impl rand::Rng, max_extent: f64) -> Vec<(Vec2, Vec2)> {
        (0..rng.random_range(0..40))
            .map(|_| {
                let a = Vec2::new(rng.random_range(-10.0..10.0), rng.random_range(-10.0..10.0));
                let d = Vec2::new(
                    rng.random_range(-max_extent..max_extent),
                    rng.random_range(-max_extent..max_extent),
                );
                (a, a + d)
            })
            .collect()
    }

    proptest! {
        #[test]
        fn edges_near_a_point_are_visited_once_and_none_within_range_is_missed(seed in any::<u64>()) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let edges = random_edges(&mut rng, 6.0);
            let g = EdgeGrid::new(&edges, Vec2::new(-16.0, -16.0), Vec2::new(16.0, 16.0));
            for _ in 0..10 {
                let p = Vec2::new(rng.random_range(-25.0..25.0), rng.random_range(-25.0..25.0));
                let r = rng.random_range(0.0..12.0);
                let mut seen = Vec::new();
                g.for_each_edge_near(p, r, |a, b| seen.push((a, b)));
                for (k, e) in edges.iter().enumerate() {
                    let times = seen.iter().filter(|s| *s == e).count();
                    let copies = edges.iter().filter(|f| *f == e).count();
                    prop_assert!(times == 0 || times == copies, "edge {} seen {} times", k, times);
                    let (ab, ap) = (e.1 - e.0, p - e.0);
                    let s = if ab.norm_squared() > 0.0 { (ap.dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0) } else { 0.0 };
                    let dist = (e.0 + ab * s - p).norm();
                    prop_assert!(dist > r || times > 0, "edge {} at {} m of the point, within {} m, missed", k, dist, r);
                }
            }
        }

        #[test]
        fn equals_brute_force(seed in any::<u64>()) {
            use rand::{Rng, SeedableRng};
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
            let edges = random_edges(&mut rng, 3.0);
            let g = EdgeGrid::new(&edges, Vec2::new(-13.0, -13.0), Vec2::new(13.0, 13.0));
            for _ in 0..20 {
                let o = Vec2::new(rng.random_range(-20.0..20.0), rng.random_range(-20.0..20.0));
                let th: f64 = rng.random_range(0.0..std::f64::consts::TAU);
                let d = Vec2::new(th.cos(), th.sin());
                let max = rng.random_range(0.1..30.0);
                let (got, want) = (g.cast(o, d, max), brute(&edges, o, d, max));
                prop_assert!((got - want).abs() < 1e-9, "{} vs {}", got, want);
            }
        }
    }
}
