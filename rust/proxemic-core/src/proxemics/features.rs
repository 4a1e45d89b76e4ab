//! Socialization features and influence vectors (Sousa et al. 2022 §3.3.1 and §3.3.3).
//!
//! A person carries a feature vector `FV` (one value per feature, each in (0, 1]; higher means a
//! more socially open expression). Each side of the person (front, rear, right, left) has an
//! influence vector `IV` of the same length (each in [-1, 1]). The side's influence value is the
//! dot product `iv = FV . IV` (§3.3.3), and it reshapes that side's variance.
//!
//! # The mapping from `iv` to the variance
//!
//! The paper writes `sigma^2 = iv * sigma^2`, which cannot be taken literally: a negative `iv`
//! would give a negative variance, `iv = 0` would collapse the side to nothing, and even for
//! positive `iv` a *larger* `iv` (a happier person, Figure 14a) would give a *larger* zone, the
//! opposite of what the text says. We keep the paper's stated meaning instead: a positive `iv`
//! lets the robot come closer on that side (smaller variance), a negative one makes it keep
//! farther (larger variance), and 0 leaves the side unchanged. The scale applied to the variance
//! is
//!
//! ```text
//! s(iv) = MAX_VARIANCE_SCALE ^ (-clamp(iv, -1, 1))      sigma^2 <- s(iv) * sigma^2
//! ```
//!
//! With [`MAX_VARIANCE_SCALE`] = 4 the variance scale lies in [1/4, 4] (the side's sigma, and so
//! its extent at any level, in [1/2, 2]). It is strictly decreasing in `iv` on [-1, 1], equals 1
//! at 0, and treats approach and retreat symmetrically in log scale (`s(-iv) = 1 / s(iv)`). The
//! clamp only matters with several features, where `|FV . IV|` can exceed 1.

use std::sync::OnceLock;

use serde::Deserialize;

use super::space::Asymmetric;
use crate::error::{CoreError, Result};

/// Bound on the variance scale of one side: the scale lies in `[1 / MAX_VARIANCE_SCALE,
/// MAX_VARIANCE_SCALE]`, reached at `iv = 1` and `iv = -1` respectively.
pub const MAX_VARIANCE_SCALE: f64 = 4.0;

/// The influence vectors of the four sides (Sousa 2022 §3.3.3: IV^f, IV^r, IV^ri, IV^l), each with
/// one entry per feature, each entry in [-1, 1]. Positive: as the feature grows, the robot may
/// come closer on that side; negative: it keeps farther.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SideInfluences {
    /// Influence on the front side (IV^f).
    pub front: Vec<f64>,
    /// Influence on the rear side (IV^r).
    pub rear: Vec<f64>,
    /// Influence on the person's right side (IV^ri).
    pub right: Vec<f64>,
    /// Influence on the person's left side (IV^l).
    pub left: Vec<f64>,
}

impl SideInfluences {
    /// The same single-feature influence per side; a convenience for the one-feature examples of
    /// Sousa 2022 §4.3.
    pub fn single(front: f64, rear: f64, right: f64, left: f64) -> Self {
        SideInfluences { front: vec![front], rear: vec![rear], right: vec![right], left: vec![left] }
    }
}

/// The influence value `iv = FV . IV` of each side (unbounded by the paper: in [-n, n] for n
/// features).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InfluenceValues {
    /// Front side.
    pub front: f64,
    /// Rear side.
    pub rear: f64,
    /// Right side.
    pub right: f64,
    /// Left side.
    pub left: f64,
}

/// The variance scale for an influence value (see the module docs): `MAX_VARIANCE_SCALE ^
/// (-clamp(iv, -1, 1))`, in [1/4, 4], 1 at `iv = 0`. NaN gives 1 (no change).
pub fn variance_scale(iv: f64) -> f64 {
    if iv.is_nan() {
        return 1.0;
    }
    MAX_VARIANCE_SCALE.powf(-iv.clamp(-1.0, 1.0))
}

/// Sousa 2022 §3.3.3: the influence value `iv = FV . IV` of each side, after checking the inputs.
/// Errors (as [`CoreError::Input`]): `fv[i]` outside (0, 1] or NaN, `ivs.<side>` of a length other
/// than `fv.len()`, `ivs.<side>[i]` outside [-1, 1] or NaN. An empty `fv` with empty influence
/// vectors is valid and gives 0 on every side.
pub fn influence_values(fv: &[f64], ivs: &SideInfluences) -> Result<InfluenceValues> {
    for (i, &v) in fv.iter().enumerate() {
        if !(v > 0.0 && v <= 1.0) {
            return Err(CoreError::input(format!("fv[{i}]"), "a feature value in (0, 1]", format!("{v}")));
        }
    }
    let sides = [("front", &ivs.front), ("rear", &ivs.rear), ("right", &ivs.right), ("left", &ivs.left)];
    let mut out = [0.0; 4];
    for (k, (name, iv)) in sides.into_iter().enumerate() {
        if iv.len() != fv.len() {
            return Err(CoreError::input(
                format!("ivs.{name}"),
                format!("{} influences (one per feature)", fv.len()),
                format!("{}", iv.len()),
            ));
        }
        for (i, &w) in iv.iter().enumerate() {
            if !(-1.0..=1.0).contains(&w) {
                return Err(CoreError::input(
                    format!("ivs.{name}[{i}]"),
                    "an influence in [-1, 1]",
                    format!("{w}"),
                ));
            }
        }
        // Sousa 2022 §3.3.3: iv = FV . IV.
        out[k] = fv.iter().zip(iv.iter()).map(|(a, b)| a * b).sum();
    }
    Ok(InfluenceValues { front: out[0], rear: out[1], right: out[2], left: out[3] })
}

/// Sousa 2022 §3.3.3: reshapes `base` by the person's features `fv` and the sides' influence
/// vectors `ivs`. Each side's variance is multiplied by [`variance_scale`]`(iv)` (so its sigma by
/// the square root). Errors: those of [`influence_values`], and an invalid `base` (field
/// `base.<side>`).
pub fn adapt(base: Asymmetric, fv: &[f64], ivs: &SideInfluences) -> Result<Asymmetric> {
    base.validate().map_err(|e| match e {
        CoreError::Input { field, expected, found } => {
            CoreError::Input { field: format!("base.{field}"), expected, found }
        }
        other => other,
    })?;
    let iv = influence_values(fv, ivs)?;
    let s = |sigma: f64, iv: f64| sigma * variance_scale(iv).sqrt();
    Ok(Asymmetric {
        front: s(base.front, iv.front),
        rear: s(base.rear, iv.rear),
        right: s(base.right, iv.right),
        left: s(base.left, iv.left),
    })
}

/// The emotional states of Sousa 2022 Table 1, in the table's order (least to most open).
pub const EMOTIONAL_STATES: [&str; 7] =
    ["angry", "disgusted", "fearful", "sad", "neutral", "surprised", "happy"];

/// Table 1 as shipped data (`python/proxemic/data/proxemics/emotional_states.toml`).
const EMOTIONAL_STATES_TOML: &str =
    include_str!("../../../../python/proxemic/data/proxemics/emotional_states.toml");

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StateFile {
    state: Vec<StateEntry>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct StateEntry {
    name: String,
    value: f64,
}

fn parse_states(text: &str) -> std::result::Result<Vec<(String, f64)>, String> {
    let file: StateFile = toml::from_str(text).map_err(|e| e.to_string())?;
    Ok(file.state.into_iter().map(|s| (s.name.to_ascii_lowercase(), s.value)).collect())
}

fn states() -> &'static [(String, f64)] {
    static TABLE: OnceLock<Vec<(String, f64)>> = OnceLock::new();
    // The file is embedded at compile time and checked by the tests; a parse failure would leave
    // the table empty (every lookup None) rather than panic.
    TABLE.get_or_init(|| parse_states(EMOTIONAL_STATES_TOML).unwrap_or_default())
}

/// The feature value of an emotional state (Sousa 2022 Table 1), e.g. `"happy"` -> 0.98; the name
/// is matched case-insensitively after trimming. `None` for an unknown state.
pub fn emotional_state_value(name: &str) -> Option<f64> {
    let key = name.trim().to_ascii_lowercase();
    states().iter().find(|(n, _)| *n == key).map(|&(_, v)| v)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::{FRAC_PI_2, PI};

    use proptest::prelude::*;

    use super::*;
    use crate::proxemics::PersonalSpace;

    /// Half-value distance (metres) on the front, rear, right and left axes.
    fn extents(a: Asymmetric) -> [f64; 4] {
        let sp = PersonalSpace::Asymmetric(a);
        [0.0, PI, -FRAC_PI_2, FRAC_PI_2].map(|b| sp.extent(b, 0.5).expect("valid test input"))
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    const BASE: Asymmetric = Asymmetric::SOUSA2022;

    #[test]
    fn table1_ships_as_data() {
        let want = [0.14, 0.28, 0.42, 0.56, 0.70, 0.84, 0.98];
        let parsed = parse_states(EMOTIONAL_STATES_TOML).expect("valid test input");
        assert_eq!(parsed.len(), 7);
        for ((name, v), (&n, &w)) in parsed.iter().zip(EMOTIONAL_STATES.iter().zip(want.iter())) {
            assert_eq!(name, n);
            assert_eq!(*v, w);
            assert_eq!(emotional_state_value(n), Some(w));
            assert!(*v > 0.0 && *v <= 1.0);
        }
        assert_eq!(emotional_state_value(" Happy "), Some(0.98));
        assert_eq!(emotional_state_value("bored"), None);
        assert!(parse_states("[[state]]\nname = 1").is_err());
    }

    #[test]
    fn variance_scale_is_monotone_bounded_and_neutral_at_zero() {
        assert_eq!(variance_scale(0.0), 1.0);
        assert!(close(variance_scale(1.0), 0.25));
        assert!(close(variance_scale(-1.0), 4.0));
        assert!(close(variance_scale(5.0), 0.25));
        assert!(close(variance_scale(-5.0), 4.0));
        assert_eq!(variance_scale(f64::NAN), 1.0);
        let mut prev = f64::INFINITY;
        for i in -20..=20 {
            let s = variance_scale(i as f64 / 20.0);
            assert!(s < prev);
            assert!((0.25..=4.0).contains(&s));
            assert!(close(s * variance_scale(-(i as f64) / 20.0), 1.0));
            prev = s;
        }
    }

    #[test]
    fn figure_13a_concentric_circles() {
        // FV = 0.5, IV = 0.5 on all sides: iv = 0.25 everywhere, a circle, smaller than the base.
        let a = adapt(BASE, &[0.5], &SideInfluences::single(0.5, 0.5, 0.5, 0.5)).expect("valid test input");
        let e = extents(a);
        let base = extents(BASE);
        assert!(e.iter().all(|&x| close(x, e[0])), "{e:?}");
        assert!(e[0] < base[0]);
        // And the value is circular at an oblique bearing too.
        let sp = PersonalSpace::Asymmetric(a);
        assert!(close(sp.extent(0.7, 0.5).expect("valid test input"), e[0]));
    }

    #[test]
    fn figure_13b_egg() {
        // FV = 0.5; front -0.5, left -0.2, right -0.2, rear -0.1: front beyond the sides beyond the
        // rear, sides equal.
        let a =
            adapt(BASE, &[0.5], &SideInfluences::single(-0.5, -0.1, -0.2, -0.2)).expect("valid test input");
        let [f, r, ri, l] = extents(a);
        assert!(f > ri && ri > r, "{f} {ri} {r}");
        assert!(close(ri, l));
        assert!(f > r);
    }

    #[test]
    fn figure_13c_d_ellipses() {
        // 13c: front/rear -0.5, sides +0.5: long along the sagittal axis.
        let c = adapt(BASE, &[0.5], &SideInfluences::single(-0.5, -0.5, 0.5, 0.5)).expect("valid test input");
        let [f, r, ri, l] = extents(c);
        assert!(close(f, r) && close(ri, l));
        assert!(f > ri);
        // 13d: the reverse, long along the frontal axis.
        let d = adapt(BASE, &[0.5], &SideInfluences::single(0.5, 0.5, -0.5, -0.5)).expect("valid test input");
        let [f2, r2, ri2, l2] = extents(d);
        assert!(close(f2, r2) && close(ri2, l2));
        assert!(ri2 > f2);
        // Mirror images of each other.
        assert!(close(f, ri2) && close(ri, f2));
    }

    #[test]
    fn figure_13e_dominant_side() {
        // FV = 0.5; front -0.5, left -0.4, right -0.1, rear -0.1: the right (dominant) side is the
        // smaller one.
        let a =
            adapt(BASE, &[0.5], &SideInfluences::single(-0.5, -0.1, -0.1, -0.4)).expect("valid test input");
        let [f, r, ri, l] = extents(a);
        assert!(ri < l, "dominant right {ri} vs left {l}");
        assert!(f > l && close(ri, r));
    }

    #[test]
    fn figure_14a_emotional_states_resize_the_front() {
        // Front 0.9, left 0.5, right 0.5, rear 0.0, FV = Table 1: the angrier the person the larger
        // the front of the zone; the rear never changes.
        let ivs = SideInfluences::single(0.9, 0.0, 0.5, 0.5);
        let base = extents(BASE);
        let mut prev: Option<[f64; 4]> = None;
        for name in EMOTIONAL_STATES {
            let fv = emotional_state_value(name).expect("valid test input");
            let e = extents(adapt(BASE, &[fv], &ivs).expect("valid test input"));
            assert!(close(e[1], base[1]), "{name}: rear unchanged");
            assert!(e[0] < base[0] && e[2] < base[2]);
            assert!(close(e[2], e[3]));
            if let Some(p) = prev {
                assert!(e[0] < p[0], "{name}: front shrinks as the mood improves");
                assert!(e[2] < p[2]);
            }
            prev = Some(e);
        }
        // The front of an angry person reaches farther than a happy one's by a clear margin.
        let angry = extents(adapt(BASE, &[0.14], &ivs).expect("valid test input"))[0];
        let happy = extents(adapt(BASE, &[0.98], &ivs).expect("valid test input"))[0];
        assert!(angry > 1.5 * happy, "{angry} vs {happy}");
    }

    #[test]
    fn figure_14b_table_2_waiter() {
        // Features [food need, beverage need] (Table 2: 0.1 / 0.5 / 0.9). Food is served from the
        // left, drinks from the right: front [0, 0], right [0, 0.5], left [0.5, 0], rear [0, 0].
        let ivs = SideInfluences {
            front: vec![0.0, 0.0],
            rear: vec![0.0, 0.0],
            right: vec![0.0, 0.5],
            left: vec![0.5, 0.0],
        };
        let base = extents(BASE);
        let e = |food: f64, drink: f64| extents(adapt(BASE, &[food, drink], &ivs).expect("valid test input"));
        // Needs both: both sides shrink equally; front and rear untouched.
        let both = e(0.9, 0.9);
        assert!(close(both[2], both[3]) && both[2] < base[2]);
        assert!(close(both[0], base[0]) && close(both[1], base[1]));
        // Needs food, not a drink: the robot may come closer on the left.
        let food = e(0.9, 0.1);
        assert!(food[3] < food[2], "left {} < right {}", food[3], food[2]);
        // Needs a drink, not food: closer on the right.
        let drink = e(0.1, 0.9);
        assert!(drink[2] < drink[3]);
        assert!(close(drink[2], food[3]) && close(drink[3], food[2]));
        // Neutral food, no drink; needs food, neutral drink: the left is the closer side in both.
        let a = e(0.5, 0.1);
        let b = e(0.9, 0.5);
        assert!(a[3] < a[2] && b[3] < b[2]);
        assert!(b[3] < a[3] && b[2] < a[2]);
    }

    #[test]
    fn adapt_is_identity_at_zero_influence_and_checks_input() {
        let base = Asymmetric { front: 1.4, rear: 0.7, right: 0.9, left: 1.1 };
        assert_eq!(
            adapt(base, &[0.3, 0.8], &SideInfluences { front: vec![0.0; 2], ..zeros(2) })
                .expect("valid test input"),
            base
        );
        assert_eq!(adapt(base, &[], &SideInfluences::default()).expect("valid test input"), base);
        let field = |r: Result<Asymmetric>| match r {
            Err(CoreError::Input { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let one = SideInfluences::single(0.1, 0.1, 0.1, 0.1);
        assert_eq!(field(adapt(base, &[0.0], &one)), "fv[0]");
        assert_eq!(field(adapt(base, &[1.01], &one)), "fv[0]");
        assert_eq!(field(adapt(base, &[0.5, f64::NAN], &zeros(2))), "fv[1]");
        assert_eq!(field(adapt(base, &[0.5, 0.5], &one)), "ivs.front");
        let mut bad = zeros(3);
        bad.left[2] = -1.5;
        assert_eq!(field(adapt(base, &[0.5, 0.5, 0.5], &bad)), "ivs.left[2]");
        bad.left[2] = f64::NAN;
        assert_eq!(field(adapt(base, &[0.5, 0.5, 0.5], &bad)), "ivs.left[2]");
        let mut short = zeros(2);
        short.rear.pop();
        assert_eq!(field(adapt(base, &[0.5, 0.5], &short)), "ivs.rear");
        assert_eq!(field(adapt(Asymmetric { rear: 0.0, ..base }, &[0.5], &one)), "base.rear");
        // Saturation with several features keeps the sigma within [1/2, 2] of the base.
        let many = SideInfluences::single(1.0, -1.0, 0.0, 0.0);
        let fv = [1.0];
        let a = adapt(base, &fv, &many).expect("valid test input");
        assert!(close(a.front, 0.7) && close(a.rear, 1.4));
        let three = SideInfluences {
            front: vec![1.0; 3],
            rear: vec![-1.0; 3],
            right: vec![0.0; 3],
            left: vec![0.0; 3],
        };
        let a = adapt(base, &[1.0; 3], &three).expect("valid test input");
        assert!(close(a.front, 0.7) && close(a.rear, 1.4));
    }

    proptest! {
        #[test]
        fn adapt_keeps_sigmas_within_the_bound_and_is_monotone(
            fv in prop::collection::vec(0.001f64..=1.0, 0..5),
            seed in prop::collection::vec(-1.0f64..=1.0, 20),
            bump in 0.0f64..1.0,
        ) {
            let n = fv.len();
            let ivs = SideInfluences {
                front: seed[0..n].to_vec(),
                rear: seed[5..5 + n].to_vec(),
                right: seed[10..10 + n].to_vec(),
                left: seed[15..15 + n].to_vec(),
            };
            let base = Asymmetric { front: 1.4, rear: 0.7, right: 0.9, left: 1.1 };
            let a = adapt(base, &fv, &ivs).expect("valid input");
            for (x, b) in [(a.front, base.front), (a.rear, base.rear), (a.right, base.right), (a.left, base.left)] {
                prop_assert!(x >= 0.5 * b - 1e-12 && x <= 2.0 * b + 1e-12);
            }
            // Raising one influence on the front never makes the front larger.
            if n > 0 {
                let mut more = ivs.clone();
                more.front[0] = (more.front[0] + bump).min(1.0);
                let b = adapt(base, &fv, &more).expect("valid input");
                prop_assert!(b.front <= a.front + 1e-12);
                prop_assert_eq!((b.rear, b.right, b.left), (a.rear, a.right, a.left));
            }
        }
    }

    fn zeros(n: usize) -> SideInfluences {
        SideInfluences { front: vec![0.0; n], rear: vec![0.0; n], right: vec![0.0; n], left: vec![0.0; n] }
    }
}
