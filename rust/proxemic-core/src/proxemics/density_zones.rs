//! Calderita et al. §4.1: the intimate, personal and social zones as contours of the summed
//! density `G_d` (eq. 5), not as Hall radii around each person.
//!
//! `G_d(x) = Σ_i g_i(x)`, with `g_i` Kirby's asymmetric Gaussian of person `i` (eq. 1-4, the
//! paper's fixed `σ_h = 2`, `σ_r = 1`, `σ_s = 4/3`; [`DensityParams`]). The paper draws each zone
//! as the contour of `G_d` at "different values of the density threshold φ" (Fig. 6), and the
//! space of a group as the region `G_d >= φ = 1 + kδ` (eq. 7-8, [`DensityParams::phi`]). Near
//! several people the contours merge: two people standing close share one personal zone.
//!
//! **The zone thresholds.** Paper: not given (only that they differ per zone, Fig. 6). Ours: the
//! level of one person's Gaussian at Hall's radius `r` to the side, `L(r) = exp(-r² / (2 σ_s²))`.
//! A person alone then has their zones exactly at Hall's radii sideways, stretched by `σ_h / σ_s`
//! ahead and shrunk by `σ_r / σ_s` behind, which is also how proxemic's social map places one
//! person's zones (Kirby's function, zone scale `σ_s`); with several people the levels are
//! compared with the sum. In the paper's own terms this is `φ_z = 1 + k δ_z` (eq. 7) with `k = 1`
//! and `δ_z = L(r_z)`, the density at `x` counting the robot standing there as the point's own 1:
//! the robot is in zone `z` when it would be a "neighbour at Hall's radius `r_z`" of the people.
//! Why: it is the one choice that agrees with Hall's radii where the paper uses them (one
//! person, Table 1's zone metrics) and needs no new number.
//!
//! A consequence worth knowing (a test checks it): with Calderita's wide `σ_s = 4/3` m, two people
//! standing side by side closer than `2 σ_s sqrt(2 ln(2 / L(r_intimate)))` (3.27 m with the
//! evaluation radii 0.45/1.2/3.6 m) share one intimate region, so no path passes between them.

use crate::error::Result;
use crate::groups::{DensityParams, PersonState};
use crate::math::Vec2;
use crate::proxemics::{HallZones, Zone};

/// Zones and group space from the summed density (Calderita §4.1; module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DensityZones {
    params: DensityParams,
    /// `G_d` levels of the intimate, personal and social contours (decreasing, in (0, 1)).
    levels: [f64; 3],
}

impl DensityZones {
    /// Zones for the Gaussian of `params` (Calderita's σ by default) with contour levels from
    /// Hall's radii `zones` (m; module docs). Errors: invalid parameters or radii, naming the
    /// field.
    pub fn new(params: DensityParams, zones: HallZones) -> Result<Self> {
        params.validate()?;
        zones.validate()?;
        let level = |r: f64| (-r * r / (2.0 * params.sigma_s * params.sigma_s)).exp();
        Ok(DensityZones {
            params,
            levels: [level(zones.intimate), level(zones.personal), level(zones.social)],
        })
    }

    /// The `G_d` levels (dimensionless) of the intimate, personal and social contours.
    pub fn levels(&self) -> [f64; 3] {
        self.levels
    }

    /// The group threshold `φ = 1 + kδ` (eq. 7).
    pub fn phi(&self) -> f64 {
        self.params.phi()
    }

    /// `G_d(x)` (eq. 5) for `people` (positions in m, facing from [`PersonState::facing`]).
    pub fn density(&self, people: &[PersonState], x: Vec2) -> f64 {
        people.iter().map(|p| self.term(p.pos, p.facing(), x)).sum()
    }

    /// `G_d(x)` as [`DensityZones::density`], for people given as (position, unit facing): the
    /// same sum, bit for bit, without a `sin_cos` per person and point (for rasterising a grid).
    pub fn density_facing(&self, people: &[(Vec2, Vec2)], x: Vec2) -> f64 {
        people.iter().map(|&(pos, f)| self.term(pos, f, x)).sum()
    }

    /// `G_d(x)` as [`DensityZones::density_facing`], capped at `cap`: the sum stops once it
    /// reaches `cap`. Every term is `>= 0` and rounding is monotone, so a partial sum that
    /// reached `cap` stays at or above it, and the result equals
    /// `density_facing(people, x).min(cap)` bit for bit (the elastic band's clamped social cost).
    pub fn density_facing_capped(&self, people: &[(Vec2, Vec2)], x: Vec2, cap: f64) -> f64 {
        // The same neutral element and order as `Iterator::sum` in `density_facing`.
        let mut g: f64 = std::iter::empty::<f64>().sum();
        for &(pos, f) in people {
            g += self.term(pos, f, x);
            if g >= cap {
                return cap;
            }
        }
        g.min(cap)
    }

    /// The Gaussian's parameters (σ per side and the group threshold's).
    pub(crate) fn params(&self) -> &DensityParams {
        &self.params
    }

    /// One person's Gaussian at `x`, the person at `pos` facing the unit vector `f`.
    #[inline]
    pub(crate) fn term(&self, pos: Vec2, f: Vec2, x: Vec2) -> f64 {
        let d = x - pos;
        self.params.gaussian_local(f.x * d.x + f.y * d.y, -f.y * d.x + f.x * d.y)
    }

    /// The zone of the point `x` (m): intimate where `G_d(x)` reaches the intimate level, and so
    /// on outward; public below the social level.
    pub fn zone_of(&self, people: &[PersonState], x: Vec2) -> Zone {
        self.zone_of_density(self.density(people, x))
    }

    /// The zone of a point where `G_d` equals `g` (see [`DensityZones::zone_of`]).
    pub fn zone_of_density(&self, g: f64) -> Zone {
        if g >= self.levels[0] {
            Zone::Intimate
        } else if g >= self.levels[1] {
            Zone::Personal
        } else if g >= self.levels[2] {
            Zone::Social
        } else {
            Zone::Public
        }
    }

    /// Whether `x` lies in a group's space `J = {G_d >= φ}` (eq. 8).
    pub fn in_group_space(&self, people: &[PersonState], x: Vec2) -> bool {
        self.density(people, x) >= self.phi()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groups::detect;

    fn zones() -> DensityZones {
        DensityZones::new(DensityParams::default(), HallZones::EVALUATION).expect("valid")
    }

    fn st(x: f64, y: f64, deg: f64) -> PersonState {
        PersonState::standing(Vec2::new(x, y), deg.to_radians())
    }

    /// Just inside and just outside `r` along the unit direction `u` from `c`.
    fn around(c: Vec2, u: Vec2, r: f64) -> (Vec2, Vec2) {
        (c + u * (r - 1e-6), c + u * (r + 1e-6))
    }

    #[test]
    fn one_person_the_contours_are_halls_radii_sideways_stretched_ahead_and_shrunk_behind() {
        let z = zones();
        let h = HallZones::EVALUATION;
        let p = DensityParams::default();
        let one = [st(1.0, 2.0, 90.0)]; // facing +y
        let c = Vec2::new(1.0, 2.0);
        // Closed form: the level L(r) = exp(-r²/(2σ_s²)) is reached at distance r·σ/σ_s along a
        // half-axis of standard deviation σ.
        for (r, inner, outer) in [
            (h.intimate, Zone::Intimate, Zone::Personal),
            (h.personal, Zone::Personal, Zone::Social),
            (h.social, Zone::Social, Zone::Public),
        ] {
            for (u, sigma) in [
                (Vec2::new(1.0, 0.0), p.sigma_s),  // right side
                (Vec2::new(-1.0, 0.0), p.sigma_s), // left side
                (Vec2::new(0.0, 1.0), p.sigma_h),  // ahead
                (Vec2::new(0.0, -1.0), p.sigma_r), // behind
            ] {
                let (a, b) = around(c, u, r * sigma / p.sigma_s);
                assert_eq!(z.zone_of(&one, a), inner, "r {r} dir {u:?}");
                assert_eq!(z.zone_of(&one, b), outer, "r {r} dir {u:?}");
            }
        }
        // A person alone is never in a group's space: G_d <= 1 < φ.
        assert!(!z.in_group_space(&one, c));
    }

    #[test]
    fn two_people_close_share_one_personal_contour_and_far_apart_they_do_not() {
        let z = zones();
        let s = DensityParams::default().sigma_s;
        // Side by side, both facing +x, D apart: the midpoint is D/2 to the side of each and
        // G_d = 2 exp(-(D/2)²/(2σ_s²)). Alone, each puts it in the social zone for D = 3 m
        // (1.5 m > 1.2 m); together the contours merge. The intimate level is reached at the
        // midpoint up to D* = 2 σ_s sqrt(2 ln(2 / L_i)) (3.27 m), the personal one beyond it.
        let [l_i, l_p, _] = z.levels();
        let d_star = 2.0 * s * (2.0 * (2.0 / l_i).ln()).sqrt();
        assert!((d_star - 3.27).abs() < 0.01, "{d_star}");
        let mid = Vec2::zeros();
        let pair = |d: f64| [st(0.0, d / 2.0, 0.0), st(0.0, -d / 2.0, 0.0)];
        let g = 2.0 * (-1.5f64 * 1.5 / (2.0 * s * s)).exp();
        assert!((z.density(&pair(3.0), mid) - g).abs() < 1e-12);
        assert_eq!(z.zone_of(&pair(3.0)[..1], mid), Zone::Social);
        assert_eq!(z.zone_of(&pair(d_star - 1e-6), mid), Zone::Intimate);
        assert_eq!(z.zone_of(&pair(d_star + 1e-6), mid), Zone::Personal);
        // The personal level at the midpoint ends at 2 σ_s sqrt(2 ln(2 / L_p)).
        let d_p = 2.0 * s * (2.0 * (2.0 / l_p).ln()).sqrt();
        assert_eq!(z.zone_of(&pair(d_p - 1e-6), mid), Zone::Personal);
        assert_eq!(z.zone_of(&pair(d_p + 1e-6), mid), Zone::Social);
        // At 3.5 m the personal contour is one region: the whole segment between them is
        // personal or closer.
        for k in 0..=35 {
            let y = -1.75 + 0.1 * k as f64;
            assert!(
                matches!(z.zone_of(&pair(3.5), Vec2::new(0.0, y)), Zone::Personal | Zone::Intimate),
                "{y}"
            );
        }
        // 10 m apart: the midpoint (5 m to the side of each) is public, each keeps its own
        // contours, 2 exp(-25/(2σ_s²)) = 0.0018 below the social level 0.026.
        let far = [st(0.0, 5.0, 0.0), st(0.0, -5.0, 0.0)];
        assert_eq!(z.zone_of(&far, mid), Zone::Public);
        assert_eq!(z.zone_of(&far, Vec2::new(0.0, 4.0)), Zone::Personal);
        assert_eq!(z.zone_of(&far, Vec2::new(0.0, -4.0)), Zone::Personal);
    }

    #[test]
    fn the_group_space_of_a_facing_pair_starts_at_the_neighbour_distance() {
        // Two people facing each other at distance d: at each person G_d = 1 + exp(-d²/(2σ_h²))
        // (the other's Gaussian ahead), and φ = 1 + exp(-Ω_d²/(2σ_h²)) with Ω_d = 1.2 m, k = 1:
        // the pair is in J (and one group) exactly when d <= 1.2 m.
        let z = zones();
        let params = DensityParams::default();
        for (d, grouped) in [(1.19, true), (1.21, false)] {
            let pair = [st(0.0, 0.0, 0.0), st(d, 0.0, 180.0)];
            let g = 1.0 + (-d * d / 8.0f64).exp();
            assert!((z.density(&pair, Vec2::zeros()) - g).abs() < 1e-12);
            assert_eq!(z.in_group_space(&pair, Vec2::zeros()), grouped, "d = {d}");
            let groups = detect(&pair, &params.method()).expect("valid");
            assert_eq!(groups.labels[0] == groups.labels[1], grouped, "d = {d}: {:?}", groups.labels);
        }
        // Back to back at 1 m: the other is behind (σ_r = 1), 1 + exp(-0.5) = 1.61 < φ = 1.84.
        let pair = [st(0.0, 0.0, 180.0), st(1.0, 0.0, 0.0)];
        assert!(!z.in_group_space(&pair, Vec2::zeros()));
        let groups = detect(&pair, &params.method()).expect("valid");
        assert_ne!(groups.labels[0], groups.labels[1]);
    }

    #[test]
    fn the_capped_density_is_the_full_sum_capped_bit_for_bit() {
        let z = zones();
        // A crowd with people packed close (sums above the caps), spread out (sums below) and
        // far away (terms of exactly 0), in a fixed pseudo-random layout.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut next = || rng.random_range(0.0..1.0);
        let mut people = Vec::new();
        for k in 0..40 {
            let spread = if k < 10 {
                1.0
            } else if k < 30 {
                8.0
            } else {
                60.0
            };
            let pos = Vec2::new(spread * (next() - 0.5), spread * (next() - 0.5));
            let th = 6.3 * next() - 3.15;
            people.push((pos, Vec2::new(th.cos(), th.sin())));
        }
        let mut reached = [0usize; 2];
        for i in 0..400 {
            let x = Vec2::new(12.0 * (next() - 0.5), 12.0 * (next() - 0.5));
            let few = &people[..(i % 41)];
            for cap in [0.25, 1.0, 3.0, f64::INFINITY] {
                let full = z.density_facing(few, x);
                let capped = z.density_facing_capped(few, x, cap);
                assert_eq!(
                    capped.to_bits(),
                    full.min(cap).to_bits(),
                    "x {x:?}, {} people, cap {cap}",
                    few.len()
                );
                reached[usize::from(full >= cap)] += 1;
            }
        }
        assert!(reached[0] > 100 && reached[1] > 100, "both sides of the caps are tested: {reached:?}");
    }

    #[test]
    fn bad_parameters_are_typed_errors() {
        let bad = DensityParams { sigma_s: 0.0, ..DensityParams::default() };
        assert!(DensityZones::new(bad, HallZones::EVALUATION).is_err());
        let bad_zones = HallZones { intimate: 2.0, personal: 1.0, social: 3.0 };
        assert!(DensityZones::new(DensityParams::default(), bad_zones).is_err());
    }
}
