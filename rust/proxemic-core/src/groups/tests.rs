use super::*;
use crate::math::wrap_angle;
use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::{FRAC_PI_2, PI};

fn st(x: f64, y: f64, heading_deg: f64) -> PersonState {
    PersonState::standing(Vec2::new(x, y), heading_deg.to_radians())
}

fn walk(x: f64, y: f64, vx: f64, vy: f64) -> PersonState {
    PersonState::walking(Vec2::new(x, y), Vec2::new(vx, vy))
}

/// Standing person at `(x, y)` facing the point `(tx, ty)`.
fn facing(x: f64, y: f64, tx: f64, ty: f64) -> PersonState {
    PersonState::standing(Vec2::new(x, y), (ty - y).atan2(tx - x))
}

fn labels(people: &[PersonState], method: &GroupMethod) -> Vec<usize> {
    detect(people, method).expect("valid input").labels
}

fn delaunay() -> GroupMethod {
    GroupMethod::Delaunay(DelaunayParams::default())
}

/// Brute-force single linkage (O(N^2) union-find), the oracle for distance-only Delaunay.
fn single_linkage(people: &[PersonState], d_max: f64) -> Groups {
    let mut uf = UnionFind::new(people.len());
    for i in 0..people.len() {
        for j in (i + 1)..people.len() {
            if (people[i].pos - people[j].pos).norm_squared() <= d_max * d_max {
                uf.union(i, j);
            }
        }
    }
    uf.into_groups()
}

// ---------------------------------------------------------------- Sousa 2022 Figure 11

/// Ten people in the unit square (p.u.), scaled by a unit length of 10 m. Built so that
/// d_max = 0.40 p.u. gives exactly two groups, A = {0..4} and B = {5..9}, and 0.32 p.u. keeps A
/// but splits B into {5, 7, 9} and {6, 8}. No pairwise distance lies within 0.015 p.u. of either
/// threshold.
const FIG11: [(f64, f64); 10] = [
    (0.28, 0.50),
    (0.43, 0.99),
    (0.10, 0.61),
    (0.05, 0.31),
    (0.30, 0.80),
    (0.65, 0.14),
    (0.97, 0.98),
    (0.97, 0.41),
    (0.95, 0.75),
    (0.79, 0.35),
];
const UNIT: f64 = 10.0;

fn fig11_people() -> Vec<PersonState> {
    FIG11.iter().enumerate().map(|(i, &(x, y))| st(x * UNIT, y * UNIT, 37.0 * i as f64)).collect()
}

#[test]
fn fig11_dmax_040_gives_groups_a_and_b() {
    let g = detect(&fig11_people(), &DelaunayParams::distance_only(0.40 * UNIT).method()).expect("ok");
    assert_eq!(g.labels, vec![0, 0, 0, 0, 0, 1, 1, 1, 1, 1]);
    assert_eq!(g.members, vec![vec![0, 1, 2, 3, 4], vec![5, 6, 7, 8, 9]]);
}

#[test]
fn fig11_dmax_032_splits_differently() {
    let l = labels(&fig11_people(), &DelaunayParams::distance_only(0.32 * UNIT).method());
    assert_eq!(l, vec![0, 0, 0, 0, 0, 1, 2, 1, 2, 1]);
}

#[test]
fn fig11_without_distance_limit_is_one_mesh() {
    let l = labels(&fig11_people(), &DelaunayParams::distance_only(10.0 * UNIT).method());
    assert_eq!(l, vec![0; 10]);
}

// ---------------------------------------------------------------- Sousa 2022 Figure 12

/// Reference triangle T*: three people on a circle of radius 0.8 m around the origin, each
/// facing the centre (tips 0.15 m from the centre, inside T*).
fn ref_triangle() -> Vec<PersonState> {
    [90.0f64, 210.0, 330.0]
        .iter()
        .map(|a| {
            let a = a.to_radians();
            facing(0.8 * a.cos(), 0.8 * a.sin(), 0.0, 0.0)
        })
        .collect()
}

fn on_ring(deg: f64, r: f64) -> (f64, f64) {
    let a = deg.to_radians();
    (r * a.cos(), r * a.sin())
}

#[test]
fn fig12a_person_facing_away_is_excluded() {
    let mut p = ref_triangle();
    let (x, y) = on_ring(150.0, 1.0); // peripheral across edge (0, 1)
    p.push(st(x, y, 150.0)); // faces away from T*
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 0, 1]);
}

#[test]
fn fig12b_person_facing_the_triangle_is_included() {
    let mut p = ref_triangle();
    let (x, y) = on_ring(150.0, 1.0);
    p.push(st(x, y, -30.0)); // faces the centre of T*
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 0, 0]);
    // Facing along the T* edge direction but missing it: excluded.
    p[3] = st(x, y, 60.0);
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 0, 1]);
}

#[test]
fn fig12_triangle_facing_outwards_is_no_group() {
    let p: Vec<PersonState> = ref_triangle()
        .into_iter()
        .map(|mut q| {
            q.heading += PI;
            q
        })
        .collect();
    assert_eq!(labels(&p, &delaunay()), vec![0, 1, 2]);
    // With the orientation rule off the distance rule alone groups them.
    assert_eq!(labels(&p, &DelaunayParams::distance_only(1.5).method()), vec![0, 0, 0]);
}

/// Figure 12c: 8 people. T* (1) = {0, 1, 2}; peripherals 2 = (0, 1, 3), 3 = (1, 2, 4),
/// 4 = (2, 0, 5) (ears across T*'s edges, people 3..5 facing the centre), 5 = (3, 1, 6) chained on
/// peripheral 2 (person 6 at (-1.6, 0) facing +x: its ray crosses T*'s edge (0, 1) at x = -0.46).
/// Person 7 stands within d_max of people 2 and 4 but faces away: excluded.
fn fig12c_people() -> Vec<PersonState> {
    let mut p = ref_triangle();
    for deg in [150.0, 270.0, 30.0] {
        let (x, y) = on_ring(deg, 1.0);
        p.push(facing(x, y, 0.0, 0.0));
    }
    p.push(st(-1.6, 0.0, 0.0));
    p.push(st(0.9, -1.1, -45.0));
    p
}

#[test]
fn fig12c_reference_and_four_peripherals() {
    let p = fig12c_people();
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 0, 0, 0, 0, 0, 1]);
}

#[test]
fn fig12c_chained_peripheral_needs_its_own_orientation() {
    let mut p = fig12c_people();
    p[6].heading = PI; // person 6 now faces away from T*
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 0, 0, 0, 0, 1, 2]);
    // Person 7 turned towards T* joins through the triangle it shares with 2 and 4.
    let mut p = fig12c_people();
    p[7] = facing(0.9, -1.1, 0.0, 0.0);
    assert_eq!(labels(&p, &delaunay()), vec![0; 8]);
}

#[test]
fn fig12c_no_reference_means_no_peripherals() {
    // T* people look outwards: no T*, so no peripheral joins, even though 3..6 face the centre.
    // Only the pair rule links anyone: person 1, now looking along 210 degrees, and person 6,
    // looking along +x, face each other within 60 degrees (54 and 24 degrees) at 0.99 m.
    let mut p = fig12c_people();
    for q in p.iter_mut().take(3) {
        q.heading += PI;
    }
    let l = labels(&p, &delaunay());
    assert_eq!(l, vec![0, 1, 2, 3, 4, 5, 1, 6]);
}

// ---------------------------------------------------------------- pairs and movement

#[test]
fn standing_pair_rule() {
    let m = delaunay();
    // Vis-a-vis at 1.2 m: a pair.
    assert_eq!(labels(&[st(0.0, 0.0, 0.0), st(1.2, 0.0, 180.0)], &m), vec![0, 0]);
    // L-shape (each 45 degrees off the other): a pair.
    assert_eq!(labels(&[st(0.0, 0.0, 45.0), st(1.0, 0.0, 135.0)], &m), vec![0, 0]);
    // Side by side, both looking at the same painting: not a pair.
    assert_eq!(labels(&[st(0.0, 0.0, 90.0), st(0.8, 0.0, 90.0)], &m), vec![0, 1]);
    // Back to back: not a pair.
    assert_eq!(labels(&[st(0.0, 0.0, 180.0), st(1.0, 0.0, 0.0)], &m), vec![0, 1]);
    // Facing each other beyond d_max: not a pair.
    assert_eq!(labels(&[st(0.0, 0.0, 0.0), st(1.6, 0.0, 180.0)], &m), vec![0, 1]);
}

#[test]
fn moving_group_versus_crossing_pedestrians() {
    let m = delaunay();
    // Walking together side by side, slightly different speeds and directions.
    assert_eq!(labels(&[walk(0.0, 0.0, 1.2, 0.0), walk(0.0, 0.7, 1.25, 0.1)], &m), vec![0, 0]);
    // Passing each other in opposite directions.
    assert_eq!(labels(&[walk(0.0, 0.0, 1.2, 0.0), walk(0.5, 0.6, -1.2, 0.0)], &m), vec![0, 1]);
    // Crossing at right angles.
    assert_eq!(labels(&[walk(0.0, 0.0, 1.2, 0.0), walk(0.6, -0.6, 0.0, 1.2)], &m), vec![0, 1]);
    // Same direction, very different speeds (overtaking).
    assert_eq!(labels(&[walk(0.0, 0.0, 0.5, 0.0), walk(0.0, 0.7, 1.4, 0.0)], &m), vec![0, 1]);
    // A walker passing a standing person who faces it: mixed pairs never group.
    assert_eq!(labels(&[walk(0.0, 0.0, 1.2, 0.0), st(0.5, 0.6, -90.0)], &m), vec![0, 1]);
    // Three walking abreast plus an oncoming one in the middle of them.
    let p = [
        walk(0.0, 0.0, 1.2, 0.0),
        walk(0.0, 0.8, 1.2, 0.0),
        walk(0.0, 1.6, 1.1, 0.05),
        walk(0.6, 0.4, -1.3, 0.0),
    ];
    assert_eq!(labels(&p, &m), vec![0, 0, 0, 1]);
}

#[test]
fn far_third_person_does_not_change_a_pair() {
    for m in [delaunay(), DensityParams::default().method(), FFormationParams::default().method()] {
        let pair = [st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0)];
        assert_eq!(labels(&pair, &m), vec![0, 0], "{m:?}");
        for third in [st(20.0, 3.0, 0.0), st(-15.0, -2.0, 90.0), st(0.5, 12.0, -90.0)] {
            let l = labels(&[pair[0], pair[1], third], &m);
            assert_eq!(l, vec![0, 0, 1], "{m:?}");
        }
    }
}

// ---------------------------------------------------------------- degenerate input

#[test]
fn empty_single_and_coincident_inputs() {
    let m = delaunay();
    assert_eq!(detect(&[], &m).expect("ok"), Groups::default());
    assert_eq!(labels(&[st(1.0, 2.0, 0.0)], &m), vec![0]);
    // Coincident people are grouped (distance 0), whatever their orientation.
    assert_eq!(labels(&[st(1.0, 1.0, 0.0), st(1.0, 1.0, 90.0)], &m), vec![0, 0]);
    let p = [st(1.0, 1.0, 0.0), st(9.0, 9.0, 0.0), st(1.0, 1.0, 180.0), st(1.0, 1.0, 45.0)];
    let g = detect(&p, &m).expect("ok");
    assert_eq!(g.labels, vec![0, 1, 0, 0]);
    assert_eq!(g.members, vec![vec![0, 2, 3], vec![1]]);
    // Every person at the same spot.
    assert_eq!(labels(&vec![st(-3.0, 4.0, 10.0); 7], &m), vec![0; 7]);
    // Coincident in a triangle with a duplicate: no panic, T* still found.
    let mut t = ref_triangle();
    t.push(t[1]);
    assert_eq!(labels(&t, &m), vec![0, 0, 0, 0]);
}

#[test]
fn collinear_inputs() {
    // Five people on a line, 1 m apart: facing pairs (0,1), (2,3), and 4 alone.
    let p =
        [st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0), st(2.0, 0.0, 0.0), st(3.0, 0.0, 180.0), st(4.0, 0.0, 0.0)];
    assert_eq!(labels(&p, &delaunay()), vec![0, 0, 1, 1, 2]);
    assert_eq!(labels(&p, &DelaunayParams::distance_only(1.5).method()), vec![0; 5]);
    assert_eq!(labels(&p, &DelaunayParams::distance_only(0.9).method()), vec![0, 1, 2, 3, 4]);
    // Collinear walkers in single file.
    let q = [walk(0.0, 0.0, 1.0, 0.0), walk(1.0, 0.0, 1.0, 0.0), walk(2.0, 0.0, 1.1, 0.0)];
    assert_eq!(labels(&q, &delaunay()), vec![0, 0, 0]);
}

#[test]
fn bad_input_names_the_field() {
    let mut p = vec![st(0.0, 0.0, 0.0), st(1.0, 0.0, 0.0)];
    p[1].pos.x = f64::NAN;
    for m in [delaunay(), DensityParams::default().method(), FFormationParams::default().method()] {
        match detect(&p, &m) {
            Err(CoreError::Input { field, .. }) => assert_eq!(field, "people[1].pos"),
            other => panic!("expected an input error, got {other:?}"),
        }
    }
    let q = [st(0.0, 0.0, f64::INFINITY)];
    assert!(
        matches!(detect(&q, &delaunay()), Err(CoreError::Input { field, .. }) if field == "people[0].heading")
    );
    let q = [PersonState { pos: Vec2::zeros(), heading: 0.0, vel: Vec2::new(f64::NAN, 0.0) }];
    assert!(
        matches!(detect(&q, &delaunay()), Err(CoreError::Input { field, .. }) if field == "people[0].vel")
    );
    let q = [st(2e9, 0.0, 0.0)];
    assert!(detect(&q, &delaunay()).is_err());
    let bad = DelaunayParams { d_max: -1.0, ..DelaunayParams::default() };
    assert!(
        matches!(detect(&[], &bad.method()), Err(CoreError::Input { field, .. }) if field == "delaunay.d_max")
    );
    let bad = DensityParams { resolution: 0.0, ..DensityParams::default() };
    assert!(
        matches!(detect(&[], &bad.method()), Err(CoreError::Input { field, .. }) if field == "density.resolution")
    );
    let bad = FFormationParams { mdl: f64::NAN, ..FFormationParams::default() };
    assert!(
        matches!(detect(&[], &bad.method()), Err(CoreError::Input { field, .. }) if field == "fformation.mdl")
    );
}

#[test]
fn tiny_and_huge_coordinates_do_not_panic() {
    let p = [st(1e-300, 0.0, 0.0), st(0.0, -1e-300, 180.0), st(1e9, -1e9, 0.0), st(-1e9, 1e9, 0.0)];
    let l = labels(&p, &delaunay());
    assert_eq!(l[0], l[1]);
    assert_ne!(l[2], l[3]);
    assert!(detect(&p, &FFormationParams::default().method()).is_ok());
    assert!(detect(&p, &DensityParams::default().method()).is_ok());
}

// ---------------------------------------------------------------- properties

/// A random scene: standing circles facing their centre, walking pairs, and loners.
fn random_scene(rng: &mut ChaCha8Rng, n: usize, w: f64, h: f64) -> Vec<PersonState> {
    let mut p = Vec::with_capacity(n);
    while p.len() < n {
        let c = Vec2::new(rng.random_range(1.0..w - 1.0), rng.random_range(1.0..h - 1.0));
        match rng.random_range(0..3) {
            0 => {
                let k = rng.random_range(2..6usize).min(n - p.len());
                let r = rng.random_range(0.5..0.9);
                let a0 = rng.random_range(0.0..PI);
                for j in 0..k {
                    let a = a0 + j as f64 * std::f64::consts::TAU / k as f64 + rng.random_range(-0.2..0.2);
                    let q = c + Vec2::new(a.cos(), a.sin()) * r;
                    p.push(facing(q.x, q.y, c.x, c.y));
                }
            }
            1 => {
                let k = 2.min(n - p.len());
                let a: f64 = rng.random_range(-PI..PI);
                let v = Vec2::new(a.cos(), a.sin()) * rng.random_range(0.8..1.5);
                for j in 0..k {
                    let off = Vec2::new(-a.sin(), a.cos()) * (0.7 * j as f64);
                    p.push(PersonState::walking(c + off, v * (1.0 + 0.05 * j as f64)));
                }
            }
            _ => {
                let speed = if rng.random_bool(0.5) { 0.0 } else { 1.2 };
                let a: f64 = rng.random_range(-PI..PI);
                p.push(PersonState { pos: c, heading: a, vel: Vec2::new(a.cos(), a.sin()) * speed });
            }
        }
    }
    p
}

/// Partition of the original indices, canonical.
fn partition_after_permutation(people: &[PersonState], perm: &[usize], method: &GroupMethod) -> Groups {
    let permuted: Vec<PersonState> = perm.iter().map(|&k| people[k]).collect();
    let l = labels(&permuted, method);
    let mut back = vec![0; people.len()];
    for (pos, &k) in perm.iter().enumerate() {
        back[k] = l[pos];
    }
    Groups::from_labels(&back)
}

#[test]
fn labels_are_invariant_under_permutation() {
    for seed in 0..20u64 {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let people = random_scene(&mut rng, 40, 12.0, 8.0);
        for method in [delaunay(), DensityParams::default().method()] {
            let base = detect(&people, &method).expect("ok");
            let mut perm: Vec<usize> = (0..people.len()).collect();
            for _ in 0..3 {
                // Fisher-Yates with the seeded generator.
                for i in (1..perm.len()).rev() {
                    let j = rng.random_range(0..=i);
                    perm.swap(i, j);
                }
                assert_eq!(
                    partition_after_permutation(&people, &perm, &method),
                    base,
                    "seed {seed} {method:?}"
                );
            }
        }
    }
}

#[test]
fn random_scenes_find_the_planted_standing_circles() {
    // Sanity: in scenes with planted circles, most circles of 3+ people come out whole.
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let people = random_scene(&mut rng, 200, 36.0, 24.0);
    let g = detect(&people, &delaunay()).expect("ok");
    assert!(g.multi().count() > 10, "{}", g.multi().count());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// With only the distance criterion, Delaunay grouping equals single linkage at d_max
    /// (the Euclidean MST is a subgraph of the Delaunay triangulation). Coordinates on a 0.25 m
    /// lattice produce many duplicates, collinear and cocircular sets.
    #[test]
    fn distance_only_equals_single_linkage(
        pts in prop::collection::vec((0i32..40, 0i32..40), 0..60),
        d_max in 0.0f64..3.0,
        jitter in any::<bool>(),
    ) {
        let people: Vec<PersonState> = pts
            .iter()
            .enumerate()
            .map(|(k, &(x, y))| {
                let j = if jitter { (k as f64 * 0.618_033_988_7).fract() * 1e-3 } else { 0.0 };
                st(x as f64 * 0.25 + j, y as f64 * 0.25, k as f64 * 10.0)
            })
            .collect();
        let got = detect(&people, &DelaunayParams::distance_only(d_max).method()).expect("ok");
        prop_assert_eq!(got, single_linkage(&people, d_max));
    }

    /// No input makes any detector panic; invalid values give errors.
    #[test]
    fn never_panics(
        raw in prop::collection::vec(
            (prop::num::f64::ANY, prop::num::f64::ANY, prop::num::f64::ANY, -2.0f64..2.0, -2.0f64..2.0),
            0..12,
        ),
        small in prop::collection::vec((-3.0f64..3.0, -3.0f64..3.0, -4.0f64..4.0, -2.0f64..2.0), 0..12),
    ) {
        let mut people: Vec<PersonState> = raw
            .iter()
            .map(|&(x, y, h, vx, vy)| PersonState { pos: Vec2::new(x, y), heading: h, vel: Vec2::new(vx, vy) })
            .collect();
        for m in [delaunay(), DensityParams::default().method(), FFormationParams::default().method()] {
            let _ = detect(&people, &m);
        }
        people = small
            .iter()
            .map(|&(x, y, h, v)| PersonState { pos: Vec2::new(x, y), heading: h, vel: Vec2::new(v, 0.0) })
            .collect();
        for m in [delaunay(), DensityParams::default().method(), FFormationParams::default().method()] {
            let g = detect(&people, &m);
            prop_assert!(g.is_ok());
            let g = g.expect("ok");
            prop_assert_eq!(g.labels.len(), people.len());
        }
    }
}

// ---------------------------------------------------------------- group as individual

#[test]
fn group_as_individual_hand_example() {
    // Heading 0 (front = +x); centre (0, 0).
    let m =
        [st(2.0, 0.0, 0.0), st(1.0, 0.0, 0.0), st(-1.0, 0.0, 0.0), st(0.0, 1.0, 0.0), st(-2.0, -1.0, 0.0)];
    let f = [0.70, 0.70, 0.14, 0.98, 0.14];
    let g = group_as_individual(&m, &f, FeatureAggregate::Mean).expect("ok");
    assert!(g.centre.norm() < 1e-12);
    assert!(g.heading.abs() < 1e-12);
    assert!((g.front - 2.0).abs() < 1e-12);
    assert!((g.rear - 5f64.sqrt()).abs() < 1e-12);
    assert!((g.left - 1.0).abs() < 1e-12);
    assert_eq!(g.right, 0.0);
    assert_eq!(
        g.vertices,
        [Some(Vec2::new(2.0, 0.0)), Some(Vec2::new(0.0, 1.0)), Some(Vec2::new(-2.0, -1.0)), None]
    );
    assert!((g.feature - 2.66 / 5.0).abs() < 1e-12);
    let g = group_as_individual(&m, &f, FeatureAggregate::Min).expect("ok");
    assert_eq!(g.feature, 0.14);
    // Mode: 0.70 and 0.14 both twice; the tie goes to the smaller value.
    let g = group_as_individual(&m, &f, FeatureAggregate::Mode).expect("ok");
    assert_eq!(g.feature, 0.14);
    let g = group_as_individual(&m, &[0.7, 0.7, 0.7, 0.98, 0.14], FeatureAggregate::Mode).expect("ok");
    assert_eq!(g.feature, 0.7);
}

#[test]
fn group_heading_is_the_circular_mean_across_the_wrap() {
    // Headings 170 and -170 degrees: the arithmetic mean would be 0, the circular mean is 180.
    let m = [st(1.0, 0.0, 170.0), st(-1.0, 0.0, -170.0), st(0.0, 2.0, 180.0)];
    let g = group_as_individual(&m, &[0.5; 3], FeatureAggregate::Mean).expect("ok");
    assert!(wrap_angle(g.heading - PI).abs() < 1e-12, "{}", g.heading);
    assert!((g.centre - Vec2::new(0.0, 2.0 / 3.0)).norm() < 1e-12);
    // Front is -x now: (-1, 0) (offset (-1, -2/3)) is in front, (1, 0) behind, and (0, 2)
    // (offset (0, 4/3)) on the right: the left of a person facing -x is -y.
    assert_eq!(
        g.vertices,
        [Some(Vec2::new(-1.0, 0.0)), None, Some(Vec2::new(1.0, 0.0)), Some(Vec2::new(0.0, 2.0))]
    );
    assert!((g.right - 4.0 / 3.0).abs() < 1e-12 && g.left == 0.0);
    let diag = 13f64.sqrt() / 3.0;
    assert!((g.front - diag).abs() < 1e-12 && (g.rear - diag).abs() < 1e-12);
    // Facing pair: undefined mean, falls back to the first member's heading.
    let g =
        group_as_individual(&[st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0)], &[1.0, 1.0], FeatureAggregate::Mean)
            .expect("ok");
    assert_eq!(g.heading, 0.0);
    let g =
        group_as_individual(&[st(0.0, 0.0, 90.0), st(1.0, 0.0, 0.0)], &[1.0, 1.0], FeatureAggregate::Mean)
            .expect("ok");
    assert!((g.heading - FRAC_PI_2 / 2.0).abs() < 1e-12);
}

#[test]
fn group_as_individual_rejects_bad_input() {
    let m = [st(0.0, 0.0, 0.0), st(1.0, 0.0, 0.0)];
    assert!(group_as_individual(&[], &[], FeatureAggregate::Mean).is_err());
    assert!(group_as_individual(&m, &[0.5], FeatureAggregate::Mean).is_err());
    assert!(matches!(
        group_as_individual(&m, &[0.5, 0.0], FeatureAggregate::Mean),
        Err(CoreError::Input { field, .. }) if field == "features[1]"
    ));
    assert!(group_as_individual(&m, &[0.5, 1.5], FeatureAggregate::Mean).is_err());
}

// ---------------------------------------------------------------- density (Calderita)

#[test]
fn density_delta_and_phi_follow_eq_6_and_7() {
    let p = DensityParams::default();
    assert!((p.delta() - (-1.44f64 / 8.0).exp()).abs() < 1e-15);
    assert!((p.phi() - 1.0 - (-1.44f64 / 8.0).exp()).abs() < 1e-15);
    // Sides use sigma_s = 4/3, the rear sigma_r = 1.
    assert!((p.gaussian_local(0.0, 1.0) - (-9.0f64 / 32.0).exp()).abs() < 1e-15);
    assert!((p.gaussian_local(-1.0, 0.0) - (-0.5f64).exp()).abs() < 1e-15);
}

#[test]
fn density_two_people_facing_versus_back_to_back() {
    let m = DensityParams::default().method();
    assert_eq!(labels(&[st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0)], &m), vec![0, 0]);
    assert_eq!(labels(&[st(0.0, 0.0, 180.0), st(3.0, 0.0, 0.0)], &m), vec![0, 1]);
    // Facing at 2 m: no longer neighbours at Omega_d = 1.2 m.
    assert_eq!(labels(&[st(0.0, 0.0, 0.0), st(2.0, 0.0, 180.0)], &m), vec![0, 1]);
    // k = 2 (phi = 2.67): a facing pair alone is not enough; a trio on a 0.5 m circle facing its
    // centre is (each gets 2 * 0.884 from the others), one on a 0.8 m circle is not (2 * 0.73).
    let k2 = DensityParams { k: 2.0, ..DensityParams::default() }.method();
    assert_eq!(labels(&[st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0)], &k2), vec![0, 1]);
    let trio = |r: f64| -> Vec<PersonState> {
        [90.0f64, 210.0, 330.0]
            .iter()
            .map(|a| facing(r * a.to_radians().cos(), r * a.to_radians().sin(), 0.0, 0.0))
            .collect()
    };
    assert_eq!(labels(&trio(0.5), &k2), vec![0, 0, 0]);
    assert_eq!(labels(&trio(0.8), &k2), vec![0, 1, 2]);
}

#[test]
fn density_two_separate_groups() {
    let m = DensityParams::default().method();
    let p = [st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0), st(6.0, 0.0, 0.0), st(7.0, 0.0, 180.0)];
    assert_eq!(labels(&p, &m), vec![0, 0, 1, 1]);
}

#[test]
fn density_known_answer_pair_and_a_bystander() {
    // Hand computation, σ_h = 2, σ_r = 1, σ_s = 4/3, Ω_d = 1.2 m ahead, k = 1:
    //   δ = exp(-1.2² / (2·2²)) = exp(-0.18) = 0.83527, φ = 1 + δ = 1.83527.
    // A at (0, 0) facing +x, B at (1, 0) facing -x, C at (5, 0) facing +x.
    //   G_d(A) = 1 + g_B(A) + g_C(A); A is 1 m ahead of B: exp(-1/8) = 0.88250; A is 5 m behind C:
    //            exp(-25/2) = 3.7e-6. G_d(A) = 1.88250 >= φ: A is in J.
    //   G_d(B) = 1 + g_A(B) + g_C(B) = 1 + exp(-1/8) + exp(-16/2) = 1.88284 >= φ: B is in J.
    //   G_d(C) = 1 + g_A(C) + g_B(C); C is 5 m ahead of A: exp(-25/8) = 0.04394; C is 4 m
    //            behind B: exp(-16/2) = 0.00034. G_d(C) = 1.04428 < φ: C is alone.
    // A and B are joined by J (at their midpoint each is 0.5 m ahead of the other:
    // 2 exp(-0.25/8) = 1.93846, plus C's 4.5 m behind, 4e-5: 1.93850 >= φ), C is not:
    // groups {A, B}, {C}.
    let m = DensityParams::default().method();
    let p = [st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0), st(5.0, 0.0, 0.0)];
    assert_eq!(labels(&p, &m), vec![0, 0, 1]);
    let z = crate::proxemics::DensityZones::new(
        DensityParams::default(),
        crate::proxemics::HallZones::EVALUATION,
    )
    .expect("valid");
    assert!((z.phi() - 1.835_27).abs() < 1e-5);
    assert!((z.density(&p, Vec2::new(0.5, 0.0)) - 1.938_48).abs() < 1e-4);
    assert!((z.density(&p, Vec2::new(5.0, 0.0)) - 1.044_28).abs() < 1e-4);
    // With these parameters J lies inside the intimate contour: φ = 1.835 > L(0.45) = 0.945.
    assert!(z.phi() > z.levels()[0]);
}

// ---------------------------------------------------------------- F-formation

#[test]
fn fformation_cases() {
    let m = FFormationParams::default().method();
    // A circle facing its centre, plus someone 3 m away facing away.
    let mut p = ref_triangle();
    p.push(st(3.0, 0.0, 0.0));
    assert_eq!(labels(&p, &m), vec![0, 0, 0, 1]);
    // Two vis-a-vis pairs 4 m apart.
    let p = [st(0.0, 0.0, 0.0), st(1.3, 0.0, 180.0), st(5.3, 0.0, 0.0), st(6.6, 0.0, 180.0)];
    assert_eq!(labels(&p, &m), vec![0, 0, 1, 1]);
    // A walker crossing the o-space is not part of the F-formation.
    let p = [st(0.0, 0.0, 0.0), st(1.3, 0.0, 180.0), walk(0.65, 0.2, 0.0, 1.2)];
    assert_eq!(labels(&p, &m), vec![0, 0, 1]);
    // A person standing behind a member, in line with the o-space, is occluded (visibility).
    let p = [st(0.0, 0.0, 0.0), st(1.3, 0.0, 180.0), st(-0.6, 0.0, 0.0)];
    assert_eq!(labels(&p, &m), vec![0, 0, 1]);
}

// ---------------------------------------------------------------- accuracy

#[test]
fn accuracy_hand_example() {
    let truth = [Some(1), Some(1), Some(1), Some(2), Some(2), None, Some(3), Some(3), Some(3)];
    // Detected: {0,1,2} exact; {3,4,5} has an extra member for a group of 2 (allowed 0);
    // {6,7} covers 2 of 3 (needs 2 with T = 2/3); {8} alone.
    let detected = [0, 0, 0, 1, 1, 1, 2, 2, 3];
    let a = detection_accuracy(&detected, &truth, 2.0 / 3.0).expect("ok");
    assert_eq!((a.true_positives, a.detected, a.truth), (2, 3, 3));
    assert!((a.precision - 2.0 / 3.0).abs() < 1e-12);
    assert!((a.recall - 2.0 / 3.0).abs() < 1e-12);
    assert!((a.f1 - 2.0 / 3.0).abs() < 1e-12);
    let strict = detection_accuracy(&detected, &truth, 1.0).expect("ok");
    assert_eq!(strict.true_positives, 1);
    assert!((strict.precision - 1.0 / 3.0).abs() < 1e-12);
    // A 4-group detected as 3 + 1: with T = 2/3 (needs 3) it matches, with T = 1 it does not.
    let truth = [Some(7), Some(7), Some(7), Some(7)];
    let a = detection_accuracy(&[0, 0, 0, 1], &truth, 2.0 / 3.0).expect("ok");
    assert_eq!((a.precision, a.recall, a.f1), (1.0, 1.0, 1.0));
    let a = detection_accuracy(&[0, 0, 1, 1], &truth, 2.0 / 3.0).expect("ok");
    assert_eq!((a.true_positives, a.detected, a.truth), (0, 2, 1));
    assert_eq!(a.f1, 0.0);
    // Nobody grouped, nobody should be: perfect; lengths must match.
    let a = detection_accuracy(&[0, 1], &[None, None], 2.0 / 3.0).expect("ok");
    assert_eq!((a.precision, a.recall, a.f1), (1.0, 1.0, 1.0));
    assert!(detection_accuracy(&[0], &[None, None], 2.0 / 3.0).is_err());
    assert!(detection_accuracy(&[0], &[None], 0.0).is_err());
}

// ---------------------------------------------------------------- robots (Daza 2021 §4.3)

#[test]
fn stationary_robot_in_personal_zone_joins() {
    let people = [st(0.0, 0.0, 0.0), st(1.0, 0.0, 180.0), st(5.0, 0.0, 90.0)];
    let groups = detect(&people, &delaunay()).expect("ok");
    assert_eq!(groups.labels, vec![0, 0, 1]);
    let disc =
        |x: f64, y: f64, vx: f64| RobotDisc { pos: Vec2::new(x, y), radius: 0.3, vel: Vec2::new(vx, 0.0) };
    let robots = [
        disc(0.0, -0.9, 0.0), // gap 0.6 m to person 0, stationary: joins group 0
        disc(0.0, -0.9, 0.5), // same place, moving: no
        disc(5.0, 1.5, 0.0),  // gap 1.2 m > 1 m: no
        disc(5.0, 1.2, 0.0),  // gap 0.9 m to the lone person: joins group 1
        disc(4.0, 0.0, 0.0),  // gap 0.7 to person 2 and 2.7 to person 1: nearest decides
    ];
    let j = robot_joins_interaction(&people, &groups, &robots, &JoinParams::default()).expect("ok");
    assert_eq!(j, vec![Some(0), None, None, Some(1), Some(1)]);
    let bad = [RobotDisc { pos: Vec2::zeros(), radius: -1.0, vel: Vec2::zeros() }];
    assert!(matches!(
        robot_joins_interaction(&people, &groups, &bad, &JoinParams::default()),
        Err(CoreError::Input { field, .. }) if field == "robots[0].radius"
    ));
    assert!(robot_joins_interaction(&people[..2], &groups, &robots, &JoinParams::default()).is_err());
}

#[test]
fn carrying_the_triangulation_between_calls_changes_no_group() {
    // Walkers, standing conversations (people around a centre, facing it) and
    // two people who meet at one point and stand there; each step's groups with the detector's memory of the
    // previous step must equal a fresh detection's, with the orientation rule on and off.
    let mut rng = ChaCha8Rng::seed_from_u64(19);
    let mut people: Vec<PersonState> = Vec::new();
    for g in 0..6 {
        let (cx, cy) = (3.0 + 4.0 * f64::from(g % 3), 3.0 + 5.0 * f64::from(g / 3));
        for k in 0..4 {
            let a = FRAC_PI_2 * f64::from(k) + 0.2 * f64::from(g);
            let r = rng.random_range(0.6..0.8);
            people.push(facing(cx + r * a.cos(), cy + r * a.sin(), cx, cy));
        }
    }
    for _ in 0..40 {
        let (a, s): (f64, f64) = (rng.random_range(0.0..2.0 * PI), rng.random_range(0.4..1.4));
        people.push(walk(rng.random_range(0.0..20.0), rng.random_range(0.0..16.0), s * a.cos(), s * a.sin()));
    }
    let (meet_a, meet_b) = (people.len(), people.len() + 1);
    people.push(walk(6.0, 11.0, 0.5, 0.0));
    people.push(walk(8.0, 11.0, -0.5, 0.0));
    for method in [delaunay(), GroupMethod::Delaunay(DelaunayParams::distance_only(1.5))] {
        let mut memory = DetectorMemory::default();
        let mut people = people.clone();
        let (mut linked, mut kept, mut last) = (0, 0, 0);
        for step in 0..200 {
            for p in &mut people {
                p.pos += 0.1 * p.vel;
                if !(0.0..=20.0).contains(&p.pos.x) {
                    p.vel.x = -p.vel.x;
                }
                if !(0.0..=16.0).contains(&p.pos.y) {
                    p.vel.y = -p.vel.y;
                }
            }
            if step == 20 {
                // The two meet exactly and stand there for 20 steps: rule 1 links them.
                people[meet_b].pos = people[meet_a].pos;
                people[meet_a].vel = Vec2::zeros();
                people[meet_b].vel = Vec2::zeros();
            }
            if step == 40 {
                people[meet_b].vel = Vec2::new(0.0, -0.8);
            }
            let carried = detect_with(&people, &method, &mut memory).expect("valid");
            let fresh = detect(&people, &method).expect("valid");
            assert_eq!(carried, fresh, "step {step}");
            linked += usize::from(carried.labels[meet_a] == carried.labels[meet_b]);
            let times = memory.mesh.as_ref().map_or(0, |m| m.times_kept());
            kept += usize::from(times > last);
            last = times;
        }
        // Both paths ran: most steps on the carried mesh, the meeting on spade.
        assert!(kept > 100 && kept < 200, "kept {kept} of 200");
        assert!(linked >= 20, "the meeting was seen {linked} times");
    }
}
