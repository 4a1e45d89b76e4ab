use super::cost_model::*;
use super::incremental::*;
use super::zone_sweep::*;
use crate::map::geometry::Bounds;
use crate::map::grid::GridSpec;
use crate::map::sight::tests::in_sight_reference;
use crate::map::sight::{Rect, Sight};
use crate::map::{CostGrid, INSCRIBED, LETHAL};
use crate::math::Vec2;

/// A symmetric test individual: zone distance = Euclidean distance. With `quadratic` it
/// offers its quadratic form, so the map takes the counting path; without, the generic one.
#[derive(Clone, Copy)]
struct Disc {
    c: Vec2,
    sigma: f64,
    quadratic: bool,
}

impl SpaceFunction for Disc {
    fn exponent(&self, p: Vec2) -> f64 {
        (p - self.c).norm_squared() / (2.0 * self.sigma * self.sigma)
    }
    fn zone_scale(&self) -> f64 {
        self.sigma
    }
    fn bounds(&self) -> [f64; 4] {
        [self.c.x - 3.6, self.c.y - 3.6, self.c.x + 3.6, self.c.y + 3.6]
    }
    fn fingerprint(&self) -> [f64; 8] {
        [self.c.x, self.c.y, self.sigma, 0.0, 0.0, 0.0, 0.0, 0.0]
    }
    fn centre(&self) -> Option<Vec2> {
        Some(self.c)
    }
    fn quadratic(&self) -> Option<[f64; 8]> {
        let k = 1.0 / (2.0 * self.sigma * self.sigma);
        self.quadratic.then_some([self.c.x, self.c.y, 1.0, 0.0, k, k, k, k])
    }
}

fn grid(w: f64, h: f64) -> CostGrid {
    let spec =
        GridSpec::covering(Bounds { min: Vec2::zeros(), max: Vec2::new(w, h) }, 0.1).expect("valid grid");
    CostGrid { spec, cost: vec![0; spec.len()] }
}

#[test]
fn object_factor_updates_equal_the_max_over_the_covering_objects() {
    // Overlapping interaction spaces whose factors change a few at a time: every cell of
    // the object layer is the largest factor of the objects covering it (1 where none).
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
    let polys: Vec<Vec<Vec2>> = (0..12)
        .map(|_| {
            let (x, y) = (rng.random_range(0.5..7.0), rng.random_range(0.5..7.0));
            let (w, h) = (rng.random_range(0.3..2.5), rng.random_range(0.3..2.5));
            vec![Vec2::new(x, y), Vec2::new(x + w, y), Vec2::new(x + w, y + h), Vec2::new(x, y + h)]
        })
        .collect();
    let mut m = SocialMap::new(grid(10.0, 10.0), &polys, SocialCosts::default());
    let mut factors: Vec<f64> = (0..polys.len()).map(|_| rng.random_range(1.0..3.5)).collect();
    m.rebuild::<Disc>(&[], &factors).expect("one finite factor per object");
    for round in 0..30 {
        if round > 0 {
            for _ in 0..rng.random_range(1..4) {
                let k = rng.random_range(0..factors.len());
                factors[k] = rng.random_range(1.0..3.5);
            }
            m.set_object_factors(&factors).expect("one finite factor per object");
        }
        let mut want = vec![1.0f64; m.grid().spec.len()];
        for (cells, &f) in m.object_cells.iter().zip(&factors) {
            for &c in cells {
                want[c as usize] = want[c as usize].max(f);
            }
        }
        assert_eq!(m.object_layer(), &want[..], "round {round}");
        assert!(m.mark.iter().all(|&b| !b));
        for (c, &w) in want.iter().enumerate() {
            let expected = m.costs().encode(m.people_layer()[c].max(w)).max(m.static_layer().cost[c]);
            assert_eq!(m.grid().cost[c], expected);
        }
    }
}

fn cost_at(m: &SocialMap, p: Vec2) -> u8 {
    let (x, y) = m.grid().spec.cell_of(p).expect("inside");
    m.grid().cost[m.grid().spec.index(x, y)]
}

#[test]
fn zones_get_calderita_costs() {
    let mut m = SocialMap::new(grid(10.0, 10.0), &[], SocialCosts::default());
    m.update_people(&[Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false }]);
    let c = m.costs();
    assert_eq!(cost_at(&m, Vec2::new(5.2, 5.0)), LETHAL);
    assert_eq!(cost_at(&m, Vec2::new(5.8, 5.0)), c.encode(4.0));
    assert_eq!(cost_at(&m, Vec2::new(7.0, 5.0)), c.encode(2.0));
    assert_eq!(cost_at(&m, Vec2::new(9.5, 5.0)), 0);
    // encoded factors decode back within the quantisation
    let w = c.weight();
    assert!(((1.0 + w * f64::from(c.encode(4.0)) / 252.0) - 4.0).abs() < w / 252.0);
}

#[test]
fn people_factors_of_the_wrong_length_or_out_of_range_cells_are_errors_leaving_the_map() {
    let mut m = SocialMap::new(grid(10.0, 10.0), &[], SocialCosts::default());
    let n = m.grid().spec.len();
    let mut factors = vec![1.0; n];
    factors[n / 2] = 4.0;
    m.set_people_factors(&factors).expect("one factor per cell");
    let before = m.grid().cost.clone();
    assert_ne!(before[n / 2], 0, "the 4.0 factor is drawn");
    let short = vec![1.0; n - 1];
    let err = m.set_people_factors(&short).expect_err("one short");
    let text = err.to_string();
    assert!(text.contains("factors") && text.contains(&n.to_string()), "{text}");
    assert!(text.contains(&format!("{} factors", n - 1)), "{text}");
    factors[0] = 4.0;
    let err = m.set_people_factors_at(&factors, &[0, n]).expect_err("cell n is outside");
    assert!(err.to_string().contains("cells"), "{err}");
    let err = m.set_people_factors_at(&short, &[0]).expect_err("one short");
    assert!(err.to_string().contains("factors"), "{err}");
    assert_eq!(m.grid().cost, before, "a refused write leaves the map as it was");
    m.set_people_factors_at(&factors, &[0, 0]).expect("in range");
    assert_ne!(m.grid().cost[0], 0);
    assert_eq!(m.cells_touched(), 1, "a repeated cell changes once");
}

#[test]
fn zones_stop_at_walls_and_pass_doorways() {
    // A wall at x = 6 (cells 60-61) from y = 0 to 10 with a doorway at y 4.5 - 5.5; a
    // person at (5, 2) in the west room.
    let mut g = grid(10.0, 10.0);
    for iy in 0..100 {
        if !(45..55).contains(&iy) {
            for ix in 60..62 {
                let i = g.spec.index(ix, iy);
                g.cost[i] = LETHAL;
            }
        }
    }
    let mut m = SocialMap::new(g, &[], SocialCosts::default());
    m.update_people(&[Disc { c: Vec2::new(5.0, 2.0), sigma: 1.0, quadratic: false }]);
    let c = m.costs();
    // 1.6 m east of the person, behind the wall: no zone (2.0 without the wall).
    assert_eq!(cost_at(&m, Vec2::new(6.6, 2.0)), 0);
    // The same distance west, in the person's room: the social zone.
    assert_eq!(cost_at(&m, Vec2::new(3.4, 2.0)), c.encode(2.0));
    // Through the doorway, in sight of the person: still the social zone.
    assert_eq!(cost_at(&m, Vec2::new(6.3, 4.7)), c.encode(2.0));
    // The counted (incremental) update agrees with a rebuild.
    let mut full = m.clone();
    full.rebuild(&[Disc { c: Vec2::new(5.0, 2.0), sigma: 1.0, quadratic: false }], &[])
        .expect("one finite factor per object");
    assert_eq!(m.grid(), full.grid());
}

#[test]
fn incremental_update_equals_rebuild_and_touches_fewer_cells() {
    let spec_grid = grid(40.0, 20.0);
    let poly = vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0), Vec2::new(3.0, 3.0), Vec2::new(1.0, 3.0)];
    let mut inc = SocialMap::new(spec_grid.clone(), std::slice::from_ref(&poly), SocialCosts::default());
    let mut people = vec![
        Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false },
        Disc { c: Vec2::new(15.0, 5.0), sigma: 1.0, quadratic: false },
    ];
    inc.set_object_factors(&[1.5]).expect("one finite factor per object");
    inc.update_people(&people);
    people[0].c = Vec2::new(6.0, 5.5);
    inc.update_people(&people);
    let touched = inc.cells_touched();
    inc.set_object_factors(&[3.5]).expect("one finite factor per object");
    let mut full = SocialMap::new(spec_grid, &[poly], SocialCosts::default());
    full.rebuild(&people, &[3.5]).expect("one finite factor per object");
    assert_eq!(inc.grid(), full.grid());
    assert!(touched < inc.grid().spec.len() / 2, "touched {touched}");
    // unchanged people cost nothing
    inc.update_people(&people);
    assert_eq!(inc.cells_touched(), 0);
}

#[test]
fn counted_update_keeps_contributions_when_the_list_shifts() {
    let round = |x: f64, y: f64| Disc { c: Vec2::new(x, y), sigma: 1.0, quadratic: true };
    let mut people = vec![round(5.0, 5.0), round(15.0, 5.0), round(25.0, 5.0)];
    let mut inc = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
    inc.update_people(&people);
    let one = {
        let mut lone = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
        lone.update_people(&people[..1]);
        lone.cells_touched()
    };
    assert!(one > 0);
    // The first one starts walking and leaves the list: the others' indices shift, yet only
    // the leaver's cells are touched.
    people.remove(0);
    inc.update_people(&people);
    assert_eq!(inc.cells_touched(), one);
    // Someone stops at the front of the list: only the newcomer's cells.
    people.insert(0, round(35.0, 15.0));
    inc.update_people(&people);
    assert_eq!(inc.cells_touched(), one);
    let mut full = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
    full.update_people(&people);
    assert_eq!(inc.grid(), full.grid());
    // Against the zone costs of a map that never counted.
    let mut plain = SocialMap::new(grid(40.0, 20.0), &[], SocialCosts::default());
    plain.update_people(&people.iter().map(|r| Disc { quadratic: false, ..*r }).collect::<Vec<_>>());
    assert_eq!(inc.grid(), plain.grid());
}

#[test]
fn object_factors_of_the_wrong_length_or_not_finite_are_errors_leaving_the_map() {
    let square =
        |x: f64| vec![Vec2::new(x, 1.0), Vec2::new(x + 2.0, 1.0), Vec2::new(x + 2.0, 3.0), Vec2::new(x, 3.0)];
    let mut m = SocialMap::new(grid(10.0, 10.0), &[square(1.0), square(5.0)], SocialCosts::default());
    m.set_object_factors(&[3.5, 1.5]).expect("one finite factor per object");
    let before = m.clone();
    for bad in [&[3.5][..], &[3.5, 1.5, 2.0], &[]] {
        let err = m.set_object_factors(bad).expect_err("a bad factor list").to_string();
        assert!(err.contains("object_factors") && err.contains("2 polygons"), "{err}");
        assert!(err.contains(&format!("{} factors", bad.len())), "{err}");
        let err = m.rebuild::<Disc>(&[], bad).expect_err("a bad factor list").to_string();
        assert!(err.contains("2 polygons"), "{err}");
    }
    for bad in [f64::NAN, f64::INFINITY] {
        let err = m.set_object_factors(&[2.0, bad]).expect_err("a bad factor list").to_string();
        assert!(err.contains("object_factors[1]") && err.contains("finite"), "{err}");
        assert!(m.rebuild::<Disc>(&[], &[bad, 2.0]).is_err());
    }
    assert_eq!(m.grid(), before.grid());
    assert_eq!(m.object_layer(), before.object_layer());
}

#[test]
fn object_space_takes_r_of_t_and_static_stays_lethal() {
    let mut g = grid(10.0, 10.0);
    let i = g.spec.index(20, 20);
    g.cost[i] = LETHAL;
    let poly = vec![Vec2::new(1.0, 1.0), Vec2::new(3.0, 1.0), Vec2::new(3.0, 3.0), Vec2::new(1.0, 3.0)];
    let mut m = SocialMap::new(g, &[poly], SocialCosts::default());
    m.rebuild::<Disc>(&[], &[3.5]).expect("one finite factor per object");
    assert_eq!(cost_at(&m, Vec2::new(2.05, 2.05)), LETHAL);
    assert_eq!(cost_at(&m, Vec2::new(1.5, 1.5)), m.costs().encode(3.5));
    assert_eq!(cost_at(&m, Vec2::new(5.0, 5.0)), 0);
    m.set_object_factors(&[1.5]).expect("one finite factor per object");
    assert_eq!(cost_at(&m, Vec2::new(1.5, 1.5)), m.costs().encode(1.5));
    assert_eq!(m.cells_touched(), 400);
}

#[test]
fn continuous_mode_follows_the_function() {
    let costs = SocialCosts { mode: CostMode::Continuous { gain: 3.0 }, ..SocialCosts::default() };
    let mut m = SocialMap::new(grid(10.0, 10.0), &[], costs);
    m.update_people(&[Disc { c: Vec2::new(5.0, 5.0), sigma: 1.0, quadratic: false }]);
    let near = cost_at(&m, Vec2::new(5.55, 5.05));
    let far = cost_at(&m, Vec2::new(6.55, 5.05));
    assert!(near > far && far > 0);
}

/// A test individual with a turned, asymmetric quadratic form (see
/// [`SpaceFunction::quadratic`]), so the map takes the counting path.
#[derive(Clone, Copy)]
struct Oval {
    quad: [f64; 8],
    zone_scale: f64,
}

impl SpaceFunction for Oval {
    fn exponent(&self, p: Vec2) -> f64 {
        let [cx, cy, cos, sin, kf, kr, kri, kl] = self.quad;
        let (dx, dy) = (p.x - cx, p.y - cy);
        let (sag, fro) = (cos * dx + sin * dy, sin * dx - cos * dy);
        (if sag >= 0.0 { kf } else { kr }) * sag * sag + (if fro >= 0.0 { kri } else { kl }) * fro * fro
    }
    fn zone_scale(&self) -> f64 {
        self.zone_scale
    }
    fn bounds(&self) -> [f64; 4] {
        [self.quad[0] - 4.0, self.quad[1] - 3.0, self.quad[0] + 3.5, self.quad[1] + 4.5]
    }
    fn fingerprint(&self) -> [f64; 8] {
        self.quad
    }
    fn centre(&self) -> Option<Vec2> {
        Some(Vec2::new(self.quad[0], self.quad[1]))
    }
    fn quadratic(&self) -> Option<[f64; 8]> {
        Some(self.quad)
    }
}

/// The zone (0 intimate, 1 personal, 2 social) of every cell of `rect` (row-major), decided
/// cell by cell over the whole rect by the row sweep as first written.
fn plain_zones(
    spec: &GridSpec,
    c: &SocialCosts,
    quad: &[f64; 8],
    zone_scale: f64,
    rect: Rect,
) -> Vec<Option<usize>> {
    let [cx, cy, cos, sin, kf, kr, kri, kl] = *quad;
    let (a0, b0, a1, b1) = rect;
    let two_z2 = 2.0 * zone_scale * zone_scale;
    let (qi, qp, qs) =
        (c.intimate * c.intimate / two_z2, c.personal * c.personal / two_z2, c.social * c.social / two_z2);
    let res = spec.resolution;
    let mut zones = Vec::with_capacity((a1 + 1 - a0) * (b1 + 1 - b0));
    for iy in b0..=b1 {
        let p0 = spec.center(a0, iy);
        let (dx, dy) = (p0.x - cx, p0.y - cy);
        let mut sag = cos * dx + sin * dy;
        let mut fro = sin * dx - cos * dy;
        for _ in a0..=a1 {
            let ks = if sag >= 0.0 { kf } else { kr };
            let kq = if fro >= 0.0 { kri } else { kl };
            let e = ks * sag * sag + kq * fro * fro;
            zones.push(if e < qi {
                Some(0)
            } else if e < qp {
                Some(1)
            } else if e < qs {
                Some(2)
            } else {
                None
            });
            sag += cos * res;
            fro += sin * res;
        }
    }
    zones
}

/// The people layer of the counting path computed the plain way: for every individual, the
/// cells of its box in sight of it (the reference walk) get the maximum with its zone's
/// factor, the zone decided cell by cell by [`plain_zones`].
fn counted_layer_reference(m: &SocialMap, people: &[Oval]) -> Vec<f64> {
    let spec = m.grid().spec;
    let c = m.costs();
    let factors = [f64::INFINITY, c.personal_cost, c.social_cost];
    let mut layer = vec![1.0f64; spec.len()];
    for ind in people {
        let Some(full) = m.rect_of(ind) else { continue };
        let open = in_sight_reference(m.static_layer(), Vec2::new(ind.quad[0], ind.quad[1]), full);
        let zones = plain_zones(&spec, c, &ind.quad, ind.zone_scale, full);
        let (a0, b0, a1, _) = full;
        for (k, zone) in zones.iter().enumerate() {
            if let Some(z) = zone.filter(|_| open[k]) {
                let i = spec.index(a0 + k % (a1 + 1 - a0), b0 + k / (a1 + 1 - a0));
                layer[i] = layer[i].max(factors[z]);
            }
        }
    }
    layer
}

/// Up to `walls` (exclusive) random wall segments of 1 to `len` cells, row- or column-wise,
/// lethal or (one in ten) inscribed.
fn random_walls(g: &mut CostGrid, rng: &mut rand_chacha::ChaCha8Rng, walls: usize, len: usize) {
    use rand::Rng;
    for _ in 0..rng.random_range(0..walls) {
        let (x, y) = (rng.random_range(0..g.spec.width), rng.random_range(0..g.spec.height));
        let (n, vertical) = (rng.random_range(1..len), rng.random_bool(0.5));
        for t in 0..n {
            let (ix, iy) = if vertical { (x, y + t) } else { (x + t, y) };
            if ix < g.spec.width && iy < g.spec.height {
                let i = g.spec.index(ix, iy);
                g.cost[i] = if rng.random_bool(0.9) { LETHAL } else { INSCRIBED };
            }
        }
    }
}

#[test]
fn zone_sweeps_limited_to_the_zones_rows_are_the_plain_sweep_bit_for_bit() {
    // Turned (and axis-aligned), very uneven individuals anywhere on and off a grid with an
    // odd origin, over rects smaller and larger than their zones, with and without a sight
    // mask: the sweep that tests only the cells of [`ZoneRows::cells`] and of the mask's open
    // runs (stepping over the closed cells between them), bringing a batch of rows to their
    // first tested cells side by side, visits exactly the cells, with the zones, of the plain
    // sweep of the whole rect.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
    let spec = GridSpec { origin: Vec2::new(-3.37, 1.21), ..grid(16.0, 9.0).spec };
    let costs = SocialCosts::default();
    for case in 0..3000 {
        let (cos, sin) = match case % 5 {
            0 => [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)][rng.random_range(0..4)],
            _ => {
                let th: f64 = rng.random_range(-3.2..3.2);
                (th.cos(), th.sin())
            }
        };
        let mut k = || 10f64.powf(rng.random_range(-1.5..1.5));
        let (kf, kr, kri, kl) = (k(), k(), k(), k());
        let centre = Vec2::new(rng.random_range(-6.0..15.0), rng.random_range(-1.0..12.0));
        let quad = [centre.x, centre.y, cos, sin, kf, kr, kri, kl];
        let zone_scale = rng.random_range(0.5..1.5);
        let (x0, y0) = (rng.random_range(0..spec.width), rng.random_range(0..spec.height));
        let rect = (
            x0,
            y0,
            (x0 + rng.random_range(0..200)).min(spec.width - 1),
            (y0 + rng.random_range(0..120)).min(spec.height - 1),
        );
        let (w, h) = (rect.2 + 1 - rect.0, rect.3 + 1 - rect.1);
        let words = w.div_ceil(64);
        let open = if case % 2 == 0 {
            Sight { words, bits: None }
        } else {
            // Random runs of open and closed cells.
            let mut bits = vec![0u64; words * h];
            for y in 0..h {
                let mut on = rng.random_bool(0.5);
                for x in 0..w {
                    if rng.random_bool(0.05) {
                        on = !on;
                    }
                    bits[y * words + x / 64] |= u64::from(on) << (x % 64);
                }
            }
            Sight { words, bits: Some(bits) }
        };
        let mut got = Vec::new();
        let spans = zone_spans(&spec, &costs, &quad, zone_scale, rect);
        let c = Contribution { quad, zone_scale, rect, spans, open };
        let sweep = c.sweep(&spec, &costs);
        sweep.cells(|i, z| got.push((i, z)));
        let want: Vec<(usize, usize)> = plain_zones(&spec, &costs, &quad, zone_scale, rect)
            .into_iter()
            .enumerate()
            .filter_map(|(k, z)| {
                let (x, y) = (k % w, k / w);
                Some((spec.index(rect.0 + x, rect.1 + y), z.filter(|_| c.open.is_open(x, y))?))
            })
            .collect();
        assert_eq!(got, want, "case {case}");
        // The runs of the rebuild: maximal, and their cells the same.
        let mut runs: Vec<(usize, usize, usize, usize)> = Vec::new();
        sweep.runs(|iy, x0, x1, z| runs.push((iy, x0, x1, z)));
        for w in runs.windows(2) {
            let ((y0, _, e0, z0), (y1, s1, _, z1)) = (w[0], w[1]);
            assert!(y0 < y1 || (y0 == y1 && (e0 + 1 < s1 || z0 != z1)), "case {case}: runs {w:?}");
        }
        let cells: Vec<(usize, usize)> = runs
            .iter()
            .flat_map(|&(iy, x0, x1, z)| (x0..=x1).map(move |ix| (spec.index(ix, iy), z)))
            .collect();
        assert_eq!(cells, want, "case {case}: runs");
    }
}

#[test]
fn counted_updates_on_random_walled_scenes_are_the_plain_layer_bit_for_bit() {
    // Random walls, turned asymmetric individuals moving a few at a time (and joining and
    // leaving): after the rebuild and after every incremental update, the people layer is
    // the plain per-individual maximum bit for bit, and the grid its combination.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
    let oval = |rng: &mut rand_chacha::ChaCha8Rng| {
        let th: f64 = rng.random_range(-3.2..3.2);
        let mut k = || rng.random_range(0.2..1.5);
        let quad = [0.0, 0.0, th.cos(), th.sin(), k(), k(), k(), k()];
        Oval { quad, zone_scale: rng.random_range(0.8..1.3) }
    };
    for case in 0..10 {
        let mut g = grid(16.0, 9.0);
        random_walls(&mut g, &mut rng, 10, 80);
        let place = |o: &mut Oval, rng: &mut rand_chacha::ChaCha8Rng| {
            o.quad[0] = rng.random_range(-1.0..17.0);
            o.quad[1] = rng.random_range(-1.0..10.0);
        };
        let mut people: Vec<Oval> = (0..rng.random_range(1..9))
            .map(|_| {
                let mut o = oval(&mut rng);
                place(&mut o, &mut rng);
                o
            })
            .collect();
        let mut m = SocialMap::new(g.clone(), &[], SocialCosts::default());
        m.rebuild(&people, &[]).expect("one finite factor per object");
        for round in 0..8 {
            if round > 0 {
                for o in people.iter_mut() {
                    if rng.random_bool(0.3) {
                        o.quad[0] += rng.random_range(-0.3..0.3);
                        o.quad[1] += rng.random_range(-0.3..0.3);
                    }
                }
                if rng.random_bool(0.3) && people.len() > 1 {
                    people.remove(rng.random_range(0..people.len()));
                }
                if rng.random_bool(0.3) {
                    let mut o = oval(&mut rng);
                    place(&mut o, &mut rng);
                    people.insert(rng.random_range(0..=people.len()), o);
                }
                m.update_people(&people);
            }
            let want = counted_layer_reference(&m, &people);
            let got: Vec<u64> = m.people_layer().iter().map(|f| f.to_bits()).collect();
            assert_eq!(
                got,
                want.iter().map(|f| f.to_bits()).collect::<Vec<_>>(),
                "case {case} round {round}"
            );
            for (c, &f) in want.iter().enumerate() {
                let expected = m.costs().encode(f.max(m.object_layer()[c])).max(g.cost[c]);
                let expected = if g.cost[c] >= INSCRIBED { g.cost[c] } else { expected };
                assert_eq!(m.grid().cost[c], expected, "case {case} round {round} cell {c}");
            }
        }
    }
}

#[test]
fn rebuild_by_runs_is_the_per_cell_count_bit_for_bit() {
    // Random walls (some touching the grid's edges), turned asymmetric individuals anywhere
    // on, across and off the grid's edges, some very uneven: the rebuild, which counts the
    // zones by runs, leaves the counts, contributions, people layer, grid and touched count
    // of the per-cell counting from empty, and the people layer is the plain sweep cut by
    // the reference walk.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(41);
    for case in 0..40 {
        let mut g = grid(12.0, 7.0);
        g.spec.origin = Vec2::new(rng.random_range(-0.3..0.3), rng.random_range(-0.3..0.3));
        random_walls(&mut g, &mut rng, 12, 90);
        let people: Vec<Oval> = (0..rng.random_range(0..14))
            .map(|k| {
                let th: f64 = if k % 4 == 0 {
                    [0.0, 0.5, 1.0, 1.5][rng.random_range(0..4)] * std::f64::consts::PI
                } else {
                    rng.random_range(-3.2..3.2)
                };
                let mut k = || 10f64.powf(rng.random_range(-0.7..0.4));
                let (kf, kr, kri, kl) = (k(), k(), k(), k());
                let (x, y) = (rng.random_range(-4.0..16.0), rng.random_range(-4.0..11.0));
                Oval {
                    quad: [x, y, th.cos(), th.sin(), kf, kr, kri, kl],
                    zone_scale: rng.random_range(0.7..1.4),
                }
            })
            .collect();
        let mut runs = SocialMap::new(g.clone(), &[], SocialCosts::default());
        runs.rebuild(&people, &[]).expect("one finite factor per object");
        let mut cells = SocialMap::new(g.clone(), &[], SocialCosts::default());
        cells.update_people(&people);
        assert!(runs.counts == cells.counts, "case {case}: counts");
        assert_eq!(runs.counted.len(), cells.counted.len(), "case {case}");
        for (a, b) in runs.counted.iter().zip(&cells.counted) {
            let same = match (a, b) {
                (Some(a), Some(b)) => a.same(&b.quad, b.zone_scale, b.rect) && a.open.bits == b.open.bits,
                (a, b) => a.is_none() && b.is_none(),
            };
            assert!(same, "case {case}: contributions");
        }
        let bits = |m: &SocialMap| m.people_layer().iter().map(|f| f.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&runs), bits(&cells), "case {case}: people layer");
        let want = counted_layer_reference(&runs, &people);
        assert_eq!(bits(&runs), want.iter().map(|f| f.to_bits()).collect::<Vec<_>>(), "case {case}");
        assert_eq!(runs.grid(), cells.grid(), "case {case}: grid");
        assert_eq!(runs.cells_touched(), cells.cells_touched(), "case {case}: touched");
        assert!(runs.mark.iter().all(|&b| !b));
        // Both go on counting alike.
        let mut moved = people.clone();
        for o in moved.iter_mut().step_by(2) {
            o.quad[0] += 0.13;
            o.quad[1] -= 0.07;
        }
        runs.update_people(&moved);
        cells.update_people(&moved);
        assert!(runs.counts == cells.counts, "case {case}: counts after a move");
        assert_eq!(runs.grid(), cells.grid(), "case {case}: grid after a move");
    }
}
