//! Tests of the personal-space functions.

use proptest::prelude::*;

use super::*;
use crate::math::rotate;

const TOL: f64 = 1e-12;

/// Sousa 2022 eq. 6 (the g, h, k form in world coordinates), with the quadrant chosen from the
/// point's coordinates in the person's frame (ahead/behind, left/right) rather than eq. 7's
/// angle: an independent route to the same value.
fn sousa_eq6(a: &Asymmetric, person: Pose, p: Vec2) -> f64 {
    let d = p - person.position();
    let local = rotate(d, -person.theta);
    let sigma = if local.x >= 0.0 { a.front } else { a.rear };
    let sigma_s = if local.y >= 0.0 { a.left } else { a.right };
    let t = person.theta;
    let g = t.cos().powi(2) / (2.0 * sigma * sigma) + t.sin().powi(2) / (2.0 * sigma_s * sigma_s);
    let h = (2.0 * t).sin() / (4.0 * sigma * sigma) - (2.0 * t).sin() / (4.0 * sigma_s * sigma_s);
    let k = t.sin().powi(2) / (2.0 * sigma * sigma) + t.cos().powi(2) / (2.0 * sigma_s * sigma_s);
    (-(g * d.x * d.x + 2.0 * h * d.x * d.y + k * d.y * d.y)).exp()
}

/// Kirby's Gaussian through Sousa 2022 eq. 5 (d_sag / d_fro), front/rear from the sign of d_sag.
fn kirby_eq5(sigma_h: f64, sigma_r: f64, sigma_s: f64, person: Pose, p: Vec2) -> f64 {
    let (dx, dy) = (p.x - person.x, p.y - person.y);
    let (s, c) = person.theta.sin_cos();
    let d_sag = c * dx + s * dy;
    let d_fro = s * dx - c * dy;
    let sigma = if d_sag >= 0.0 { sigma_h } else { sigma_r };
    (-(d_sag * d_sag / (2.0 * sigma * sigma) + d_fro * d_fro / (2.0 * sigma_s * sigma_s))).exp()
}

fn pts() -> Vec<Vec2> {
    let mut v = Vec::new();
    for i in -6..=6 {
        for j in -6..=6 {
            // Offsets avoid the exact quadrant boundaries.
            v.push(Vec2::new(0.37 * i as f64 + 0.013, 0.41 * j as f64 - 0.007));
        }
    }
    v
}

#[test]
fn kirby_known_answers() {
    // `docs/algorithms.md` §2 (sigma_h = 2, sigma_s = 4/3, sigma_r = 1, theta = 0).
    let k = PersonalSpace::CALDERITA;
    let o = Pose::new(0.0, 0.0, 0.0);
    let cases = [
        ((1.0, 0.0), 0.882497),
        ((0.0, 1.0), 0.754840),
        ((-1.0, 0.0), 0.606531),
        ((1.0, 1.0), 0.666144),
        ((-1.0, 1.0), 0.457833),
    ];
    for ((x, y), want) in cases {
        let got = k.value(o, Vec2::new(x, y));
        assert!((got - want).abs() < 5e-7, "({x}, {y}): {got} vs {want}");
    }
    assert_eq!(k.value(o, Vec2::zeros()), 1.0);
}

#[test]
fn kirby_matches_the_d_sag_d_fro_form_at_any_rotation() {
    let (h, r, s) = (2.0, 1.0, 4.0 / 3.0);
    let k = PersonalSpace::Kirby { sigma_h: h, sigma_r: r, sigma_s: s };
    for theta in [0.0, 0.3, 1.2, 2.9, -2.0, 7.5] {
        let person = Pose::new(1.5, -0.5, theta);
        for p in pts() {
            let p = p + person.position();
            let (got, want) = (k.value(person, p), kirby_eq5(h, r, s, person, p));
            assert!((got - want).abs() < TOL, "theta {theta} at {p:?}: {got} vs {want}");
        }
    }
}

#[test]
fn sousa_eq5_matches_eq6_with_all_sides_different() {
    let a = Asymmetric::new(1.7, 0.6, 0.9, 1.3).expect("valid test input");
    let sp = PersonalSpace::Asymmetric(a);
    for theta in [0.0, 0.4, 1.9, -0.8, 3.1, -3.1, 12.0] {
        let person = Pose::new(-2.0, 3.0, theta);
        for p in pts() {
            let p = p + person.position();
            let (got, want) = (sp.value(person, p), sousa_eq6(&a, person, p));
            assert!((got - want).abs() < TOL, "theta {theta} at {p:?}: {got} vs {want}");
        }
    }
}

#[test]
fn eq8_quadrants_select_the_expected_pair() {
    // Distinct sigmas so each quadrant has a unique value at a diagonal point.
    let a = Asymmetric { front: 2.0, rear: 0.5, right: 0.8, left: 1.6 };
    let sp = PersonalSpace::Asymmetric(a);
    let expect = |sig: f64, sig_s: f64, u: f64, v: f64| {
        (-(u * u / (2.0 * sig * sig) + v * v / (2.0 * sig_s * sig_s))).exp()
    };
    for theta in [0.0, 1.0, -2.5] {
        let person = Pose::new(0.5, 0.25, theta);
        let at = |u: f64, v: f64| person.position() + rotate(Vec2::new(u, v), theta);
        // front-left, front-right, rear-left, rear-right (u ahead, v to the left).
        let (u, v) = (0.8, 0.6);
        assert!((sp.value(person, at(u, v)) - expect(2.0, 1.6, u, v)).abs() < TOL);
        assert!((sp.value(person, at(u, -v)) - expect(2.0, 0.8, u, v)).abs() < TOL);
        assert!((sp.value(person, at(-u, v)) - expect(0.5, 1.6, u, v)).abs() < TOL);
        assert!((sp.value(person, at(-u, -v)) - expect(0.5, 0.8, u, v)).abs() < TOL);
    }
}

#[test]
fn front_sigma_governs_the_points_in_front() {
    // Only the front sigma differs between a and b: points ahead change, points behind don't.
    let a = Asymmetric { front: 2.0, rear: 0.5, right: 1.0, left: 1.0 };
    let b = Asymmetric { front: 0.7, ..a };
    let person = Pose::new(3.0, -1.0, 2.2);
    let ahead = person.position() + rotate(Vec2::new(1.0, 0.0), person.theta);
    let behind = person.position() + rotate(Vec2::new(-1.0, 0.0), person.theta);
    let va = PersonalSpace::from(a).value(person, ahead);
    assert!((va - (-1.0f64 / 8.0).exp()).abs() < TOL, "ahead uses sigma_f = 2: {va}");
    let vb = PersonalSpace::from(b).value(person, ahead);
    assert!((vb - (-1.0 / (2.0 * 0.49f64)).exp()).abs() < TOL);
    let ra = PersonalSpace::from(a).value(person, behind);
    let rb = PersonalSpace::from(b).value(person, behind);
    assert_eq!(ra, rb);
    assert!((ra - (-2.0f64).exp()).abs() < TOL, "behind uses sigma_r = 0.5: {ra}");
    // The extents agree: the front reaches sqrt(2 ln 2) sigma_f.
    let e = PersonalSpace::from(a).extent(0.0, 0.5).expect("valid test input");
    assert!((e - 2.0 * (2.0 * 2f64.ln()).sqrt()).abs() < 1e-12);
}

#[test]
fn kirby_is_sousa_with_equal_sides() {
    let k = PersonalSpace::CALDERITA;
    let a = PersonalSpace::Asymmetric(Asymmetric::from_kirby(2.0, 1.0, 4.0 / 3.0));
    for theta in [0.0, 0.7, -1.4, 3.0] {
        let person = Pose::new(0.2, 0.1, theta);
        for p in pts() {
            assert!((k.value(person, p) - a.value(person, p)).abs() < TOL);
        }
    }
}

#[test]
fn rotation_and_translation_invariance() {
    let spaces = [
        PersonalSpace::DAZA2021,
        PersonalSpace::CALDERITA,
        PersonalSpace::Asymmetric(Asymmetric { front: 1.7, rear: 0.6, right: 0.9, left: 1.3 }),
    ];
    for sp in spaces {
        for p in pts() {
            let base = sp.value(Pose::new(0.0, 0.0, 0.0), p);
            for (theta, shift) in
                [(0.5, Vec2::new(3.0, -2.0)), (-2.0, Vec2::new(-1.0, 7.0)), (30.0, Vec2::zeros())]
            {
                let person = Pose::new(shift.x, shift.y, theta);
                let q = shift + rotate(p, theta);
                assert!((sp.value(person, q) - base).abs() < 1e-9, "{sp:?} at {p:?}");
            }
        }
    }
}

#[test]
fn symmetric_gaussian_values() {
    let sp = PersonalSpace::symmetric(0.8).expect("valid test input");
    let person = Pose::new(1.0, 1.0, 0.3);
    for p in pts() {
        let d2 = p.norm_squared();
        let want = (-d2 / (2.0 * 0.64)).exp();
        assert!((sp.value(person, person.position() + p) - want).abs() < TOL);
    }
    // Orientation does not matter.
    let q = Vec2::new(1.3, 0.2);
    assert_eq!(sp.value(person, q), sp.value(Pose { theta: -2.0, ..person }, q));
}

#[test]
fn values_stay_in_unit_interval_and_bad_input_never_panics() {
    let spaces = [PersonalSpace::DAZA2021, PersonalSpace::CALDERITA, PersonalSpace::SOUSA2022];
    let weird = [0.0, -0.0, 1e-300, 1e300, f64::INFINITY, f64::NEG_INFINITY, f64::NAN];
    for sp in spaces {
        for &x in &weird {
            for &t in &weird {
                let v = sp.value(Pose::new(x, 0.0, t), Vec2::new(0.5, x));
                assert!((0.0..=1.0).contains(&v), "{sp:?} {x} {t}: {v}");
            }
        }
        assert_eq!(sp.value(Pose::new(f64::NAN, 0.0, 0.0), Vec2::zeros()), 0.0);
    }
    // Invalid parameters: still in [0, 1], and validate() names them.
    let bad = PersonalSpace::Kirby { sigma_h: 0.0, sigma_r: f64::NAN, sigma_s: -1.0 };
    let v = bad.value(Pose::default(), Vec2::new(1.0, 1.0));
    assert!((0.0..=1.0).contains(&v));
    let field = |r: Result<()>| match r {
        Err(CoreError::Input { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    assert_eq!(field(bad.validate()), "sigma_h");
    assert_eq!(
        field(PersonalSpace::Kirby { sigma_h: 1.0, sigma_r: f64::NAN, sigma_s: 1.0 }.validate()),
        "sigma_r"
    );
    assert_eq!(field(PersonalSpace::Symmetric { sigma: f64::INFINITY }.validate()), "sigma");
    assert_eq!(field(Asymmetric { front: 1.0, rear: 1.0, right: 1.0, left: 0.0 }.validate()), "left");
    assert!(PersonalSpace::symmetric(-1.0).is_err());
    assert!(PersonalSpace::kirby(2.0, 1.0, 0.0).is_err());
    assert!(Asymmetric::new(1.0, -1.0, 1.0, 1.0).is_err());
    for sp in [PersonalSpace::DAZA2021, PersonalSpace::CALDERITA, PersonalSpace::SOUSA2022] {
        sp.validate().expect("valid test input");
    }
}

#[test]
fn extent_inverts_value() {
    let spaces = [
        PersonalSpace::DAZA2021,
        PersonalSpace::CALDERITA,
        PersonalSpace::Asymmetric(Asymmetric { front: 1.7, rear: 0.6, right: 0.9, left: 1.3 }),
    ];
    let person = Pose::new(-1.0, 2.0, 0.9);
    for sp in spaces {
        for i in 0..24 {
            let bearing = i as f64 * TAU / 24.0 + 0.01;
            for level in [0.9, 0.5, 0.1, 0.01] {
                let r = sp.extent(bearing, level).expect("valid test input");
                let dir = rotate(Vec2::new(bearing.cos(), bearing.sin()), person.theta);
                let p = person.position() + dir * r;
                assert!((sp.value(person, p) - level).abs() < 1e-12, "{sp:?} {bearing} {level}");
                let r2 = sp.extent_toward(person, p, level).expect("valid test input");
                assert!((r2 - r).abs() < 1e-9);
            }
        }
    }
    // Kirby along the axes, closed form sqrt(2 ln 2) sigma.
    let k = PersonalSpace::CALDERITA;
    let f = (2.0 * 2f64.ln()).sqrt();
    assert!((k.extent(0.0, 0.5).expect("valid test input") - 2.0 * f).abs() < 1e-12);
    assert!((k.extent(PI, 0.5).expect("valid test input") - 1.0 * f).abs() < 1e-12);
    assert!((k.extent(FRAC_PI_2, 0.5).expect("valid test input") - 4.0 / 3.0 * f).abs() < 1e-12);
    assert!((k.extent(-FRAC_PI_2, 0.5).expect("valid test input") - 4.0 / 3.0 * f).abs() < 1e-12);
    assert_eq!(k.extent(1.0, 1.0).expect("valid test input"), 0.0);
    // Bad input.
    assert!(k.extent(0.0, 0.0).is_err());
    assert!(k.extent(0.0, 1.5).is_err());
    assert!(k.extent(0.0, f64::NAN).is_err());
    assert!(k.extent(f64::NAN, 0.5).is_err());
    assert!(k.extent_toward(Pose::new(f64::NAN, 0.0, 0.0), Vec2::zeros(), 0.5).is_err());
    assert!(k.extent_toward(Pose::default(), Vec2::new(f64::INFINITY, 0.0), 0.5).is_err());
    // Coincident point: the facing direction.
    assert_eq!(
        k.extent_toward(Pose::default(), Vec2::zeros(), 0.5).expect("valid test input"),
        k.extent(0.0, 0.5).expect("valid test input")
    );
}

#[test]
fn kirby_speed_parameters() {
    assert_eq!(PersonalSpace::kirby_for_speed(1.0), PersonalSpace::CALDERITA);
    assert_eq!(PersonalSpace::kirby_for_speed(-1.0), PersonalSpace::CALDERITA);
    assert_eq!(
        PersonalSpace::kirby_for_speed(0.0),
        PersonalSpace::Kirby { sigma_h: 0.5, sigma_r: 0.25, sigma_s: 1.0 / 3.0 }
    );
    assert_eq!(PersonalSpace::kirby_for_speed(f64::NAN), PersonalSpace::kirby_for_speed(0.0));
    PersonalSpace::kirby_for_speed(1e300).validate().expect("valid test input");
}

#[test]
fn placed_matches_value_including_the_quadrant_boundaries() {
    let spaces = [
        PersonalSpace::DAZA2021,
        PersonalSpace::CALDERITA,
        PersonalSpace::kirby_for_speed(0.3),
        PersonalSpace::Asymmetric(Asymmetric { front: 1.7, rear: 0.6, right: 0.9, left: 1.3 }),
    ];
    for sp in spaces {
        for theta in [0.0, FRAC_PI_2, PI, -FRAC_PI_2, 0.4, -2.7, 9.0] {
            let person = Pose::new(0.7, -1.1, theta);
            let placed = sp.at(person);
            let mut points = pts();
            // Points exactly on the axes and the diagonals, at several distances.
            for i in 0..16 {
                let b = i as f64 * TAU / 16.0;
                for r in [0.0, 0.3, 1.0, 2.5] {
                    points.push(rotate(Vec2::new(r * b.cos(), r * b.sin()), theta));
                }
            }
            for p in points {
                let q = person.position() + p;
                let (a, b) = (sp.value(person, q), placed.value(q));
                assert!((a - b).abs() < 1e-12, "{sp:?} theta {theta} at {p:?}: {a} vs {b}");
            }
        }
    }
    let placed = PersonalSpace::CALDERITA.at(Pose::new(f64::NAN, 0.0, 0.0));
    assert_eq!(placed.value(Vec2::zeros()), 0.0);
}

#[test]
fn max_extent_bounds_every_direction() {
    let sp = PersonalSpace::Asymmetric(Asymmetric { front: 1.7, rear: 0.6, right: 0.9, left: 1.3 });
    let m = sp.max_extent(0.1).expect("valid level");
    assert!((m - 1.7 * (2.0 * 10f64.ln()).sqrt()).abs() < 1e-12);
    for i in 0..360 {
        let e = sp.extent(i as f64 * TAU / 360.0, 0.1).expect("valid level");
        assert!(e <= m + 1e-12);
    }
    assert!(
        (PersonalSpace::CALDERITA.max_extent(0.5).expect("valid") - 2.0 * (2.0 * 2f64.ln()).sqrt()).abs()
            < 1e-12
    );
    assert_eq!(PersonalSpace::DAZA2021.max_extent(1.0).expect("valid"), 0.0);
    assert!(PersonalSpace::DAZA2021.max_extent(0.0).is_err());
    assert!(PersonalSpace::DAZA2021.max_extent(f64::NAN).is_err());
}

fn any_f64() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -50.0f64..50.0,
        1 => prop::num::f64::ANY,
        1 => Just(0.0),
    ]
}

fn space_of(kind: u8, a: f64, b: f64, c: f64, d: f64) -> PersonalSpace {
    match kind % 3 {
        0 => PersonalSpace::Symmetric { sigma: a },
        1 => PersonalSpace::Kirby { sigma_h: a, sigma_r: b, sigma_s: c },
        _ => PersonalSpace::Asymmetric(Asymmetric { front: a, rear: b, right: c, left: d }),
    }
}

proptest! {
    #[test]
    fn any_input_gives_a_value_in_unit_interval(
        kind in any::<u8>(), s in prop::array::uniform4(any_f64()),
        pose in prop::array::uniform3(any_f64()), pt in prop::array::uniform2(any_f64()),
    ) {
        let sp = space_of(kind, s[0], s[1], s[2], s[3]);
        let person = Pose::new(pose[0], pose[1], pose[2]);
        let p = Vec2::new(pt[0], pt[1]);
        let v = sp.value(person, p);
        prop_assert!((0.0..=1.0).contains(&v), "{v}");
        let w = sp.at(person).value(p);
        prop_assert!((0.0..=1.0).contains(&w), "{w}");
        let _ = sp.extent(pose[2], pt[0]);
        let _ = sp.max_extent(pt[1]);
    }

    #[test]
    fn valid_spaces_agree_placed_and_are_rotation_invariant(
        kind in any::<u8>(), s in prop::array::uniform4(0.1f64..5.0),
        x in -20.0f64..20.0, y in -20.0f64..20.0, theta in -10.0f64..10.0,
        u in -6.0f64..6.0, v in -6.0f64..6.0, turn in -7.0f64..7.0,
    ) {
        let sp = space_of(kind, s[0], s[1], s[2], s[3]);
        let person = Pose::new(x, y, theta);
        let local = Vec2::new(u, v);
        let q = person.position() + rotate(local, theta);
        let a = sp.value(person, q);
        prop_assert!((a - sp.at(person).value(q)).abs() < 1e-12);
        // Turn the person and the point together about the origin of the world.
        let p2 = Pose::new(rotate(person.position(), turn).x, rotate(person.position(), turn).y, theta + turn);
        let b = sp.value(p2, rotate(q, turn));
        prop_assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        // Monotone along every ray from the centre.
        prop_assert!(sp.value(person, person.position() + rotate(local * 1.1, theta)) <= a + 1e-15);
    }
}

#[test]
fn wrap_half_open_range() {
    assert_eq!(wrap_half_open(PI), -PI);
    assert_eq!(wrap_half_open(-PI), -PI);
    assert!((wrap_half_open(1.5 * PI) + 0.5 * PI).abs() < 1e-12);
    for i in -100..100 {
        let a = wrap_half_open(i as f64 * 0.377);
        assert!((-PI..PI).contains(&a));
    }
}
