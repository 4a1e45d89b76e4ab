//! Sousa et al. 2022 §4.5: Social Momentum whose agents are the people's and groups' fully
//! asymmetric Gaussians (Sousa 2022 eq. 5-8, reshaped by the socialization features, a group as
//! one individual with its own Gaussian), not discs.
//!
//! Sousa 2022 runs Daza et al. 2021's planner (A* + Social Momentum) with these Gaussians as the
//! people's and groups' spaces, and shows (Figs. 16-17) that the path "respects groups and
//! individual space imposed by Gaussian functions". The paper does not say how a Gaussian enters
//! Social Momentum. Our choice, in one place:
//!
//! - **Collision filter, not the score.** Daza 2021 (Algorithm 1, lines 16 and 19, and §5: "the
//!   intimate zones of people will never be invaded") uses Social Momentum only to keep the robot
//!   out of a zone; Sousa 2022 changes the *shape* of that zone. So a Gaussian agent
//!   rejects a sample whose constant-velocity motion over the collision horizon brings the robot's
//!   centre to a *zone distance* below [`GaussianSpace::keep_out`] `+ safety_margin`, where the
//!   zone distance of a point is `zone_scale * sqrt(2 q)` with `exp(-q)` the Gaussian's value
//!   there (the distance the social map compares with Hall's radii, see
//!   [`crate::social_cost_map::SpaceFunction`]). The momentum and efficiency terms are unchanged (they
//!   use the individual's centre and velocity); no cost term is added (Daza 2021 has none).
//! - **The level.** `keep_out` is the caller's. The `sousa2022` planner passes Hall's personal
//!   radius (Daza 2021: 1 m; Sousa 2022 §4.5: Daza's method is used "for avoiding the personal
//!   space of persons", and the path "respects groups and individual space imposed by Gaussian
//!   functions"), centre to centre like every Hall radius in proxemic. With all four sigmas
//!   equal to the zone scale the keep-out region is the disc of radius `keep_out` (a test checks
//!   this), so the Gaussian model only differs from a disc where the features or a group stretch
//!   it.
//! - **Bodies.** A Gaussian agent is also checked as a disc of its `radius` (the disc model's
//!   bound), so a Gaussian shrunk by the features never lets the robot touch the person. A group
//!   individual has no body at its centre: give it radius 0 and pass its members as disc agents
//!   of weight 0 (collision filter only).
//! - **Exact test.** Along the relative motion `d(t) = d0 + dv t` the exponent `q` is a
//!   quadratic in `t` on each of the (at most three) pieces between the times the robot crosses
//!   the individual's sagittal and frontal axes, and it is C¹ and convex on the whole line (each
//!   side term `k d²` has zero slope on its axis). Its minimum over `[0, horizon]` is therefore
//!   exact, and, as for discs, a sample is only rejected when that minimum lies after `t = 0`:
//!   a robot already inside can always back away.

use crate::error::{CoreError, Result};
use crate::math::Vec2;
use crate::perception::Individual;
use crate::proxemics::{Asymmetric, PersonalSpace, Placed, Pose};
use crate::social_cost_map::SpaceFunction;

/// How an agent's keep-out region is shaped in the collision filter of
/// [`super::social_momentum_shaped`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AgentShape {
    /// A disc of the agent's radius: keep-out bound `radius + r_i + safety_margin` (centre
    /// distance). The default, and the only shape of [`super::social_momentum`].
    Disc,
    /// The disc, plus the region where the agent's fully asymmetric Gaussian puts the robot's
    /// centre at a zone distance below `keep_out + safety_margin` (Sousa 2022; module docs).
    Gaussian(GaussianSpace),
}

impl AgentShape {
    /// Whether a robot of radius `robot_radius` (m) whose centre is at offset `d` (m) from an
    /// agent of radius `agent_radius` (m) is inside this shape's keep-out region grown by `margin`
    /// (m): the collision filter's region of [`super::social_momentum_shaped`] (centre distance
    /// below `robot_radius + agent_radius + margin`, or for a Gaussian a zone distance below
    /// `keep_out + margin`), computed as the filter computes it.
    pub fn holds(&self, d: Vec2, robot_radius: f64, agent_radius: f64, margin: f64) -> bool {
        let bound = robot_radius + agent_radius + margin;
        d.norm_squared() < bound * bound
            || matches!(self, AgentShape::Gaussian(g) if g.exponent(d) < g.level(margin))
    }
}

/// A fully asymmetric Gaussian (Sousa 2022 eq. 5-8) as a keep-out region, moving with its agent.
///
/// The centre is the agent's position ([`super::Agent::pos`]); this holds the orientation, the
/// four per-side sigmas, the zone scale and the keep-out zone distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussianSpace {
    /// The Gaussian placed at the origin (the agent's centre) facing its heading: orientation and
    /// `1 / (2 sigma²)` per side (1/m²), evaluated on offsets from the centre.
    placed: Placed,
    zone_scale: f64,
    keep_out: f64,
}

impl GaussianSpace {
    /// A Gaussian facing `heading` (rad, world frame) with per-side sigmas `sides` (m, validated
    /// by [`Asymmetric::validate`]), the length `zone_scale` (m, `> 0`) that turns `sqrt(2 q)`
    /// into a zone distance, and the keep-out zone distance `keep_out` (m, `>= 0`; the
    /// `sousa2022` planner's is Hall's personal radius, 1 m in Daza 2021). Errors name
    /// `heading`, the side, `zone_scale` or `keep_out`.
    pub fn new(heading: f64, sides: Asymmetric, zone_scale: f64, keep_out: f64) -> Result<Self> {
        if !heading.is_finite() {
            return Err(CoreError::input("heading", "a finite angle in radians", heading.to_string()));
        }
        sides.validate()?;
        if !(zone_scale.is_finite() && zone_scale > 0.0) {
            return Err(CoreError::input("zone_scale", "a finite length > 0 (m)", zone_scale.to_string()));
        }
        if !(keep_out.is_finite() && keep_out >= 0.0) {
            return Err(CoreError::input("keep_out", "a finite length >= 0 (m)", keep_out.to_string()));
        }
        let placed = PersonalSpace::Asymmetric(sides).at(Pose::new(0.0, 0.0, heading));
        Ok(GaussianSpace { placed, zone_scale, keep_out })
    }

    /// The Gaussian of one individual of the social map (a person alone or a group as one
    /// individual, Sousa 2022 §3.3.4, with its features applied): its heading, sides and zone
    /// scale, with the keep-out zone distance `keep_out` (m). Pair it with an
    /// [`super::Agent`] at [`Individual::centre`].
    pub fn of_individual(ind: &Individual, keep_out: f64) -> Result<Self> {
        GaussianSpace::new(ind.heading, ind.sides, ind.zone_scale(), keep_out)
    }

    /// The keep-out zone distance (m).
    pub fn keep_out(&self) -> f64 {
        self.keep_out
    }

    /// The exponent `q` at the offset `d` (m) from the centre (Sousa 2022 eq. 5, the quadrant of
    /// eq. 8 by half planes as in [`crate::proxemics::Placed::exponent`]).
    pub fn exponent(&self, d: Vec2) -> f64 {
        self.placed.exponent(d)
    }

    /// The zone distance (m) of the offset `d` from the centre ([`crate::proxemics::zone_distance`]).
    pub fn zone_distance(&self, d: Vec2) -> f64 {
        self.placed.zone_distance(d, self.zone_scale)
    }

    /// The exponent level below which a point is inside the keep-out region grown by `margin`
    /// (m): zone distance `< keep_out + margin`  ⟺  `q < (keep_out + margin)² / (2 z²)`.
    pub(super) fn level(&self, margin: f64) -> f64 {
        let r = self.keep_out + margin;
        r * r / (2.0 * self.zone_scale * self.zone_scale)
    }

    /// The farthest the region grown by `margin` (m) reaches from the centre (m).
    pub(super) fn reach(&self, margin: f64) -> f64 {
        let [.., front, rear, right, left] = self.placed.coefficients();
        let k_min = front.min(rear).min(right).min(left);
        (self.level(margin) / k_min).sqrt()
    }

    /// The minimum of `q(d0 + dv t)` over `t` in `[0, horizon]` and the first time it is reached
    /// (exact; module docs).
    pub(super) fn min_along(&self, d0: Vec2, dv: Vec2, horizon: f64) -> (f64, f64) {
        let (s0, f0) = self.placed.axes(d0);
        let (s1, f1) = self.placed.axes(dv);
        // Axis crossings inside the horizon split the line into quadratic pieces.
        let mut cuts = [0.0, horizon, horizon, horizon];
        let mut n = 1;
        for (a, b) in [(s0, s1), (f0, f1)] {
            if b != 0.0 {
                let t = -a / b;
                if t > 0.0 && t < horizon {
                    cuts[n] = t;
                    n += 1;
                }
            }
        }
        cuts[n] = horizon;
        // Only the (at most two) crossings between 0 and the horizon can be out of order.
        if n == 3 && cuts[2] < cuts[1] {
            cuts.swap(1, 2);
        }
        let mut best = (self.exponent(d0), 0.0);
        for w in cuts[..=n].windows(2) {
            let (t0, t1) = (w[0], w[1]);
            if t1 <= t0 {
                continue;
            }
            let mid = 0.5 * (t0 + t1);
            let (ks, kf) = self.placed.side_coefficients(s0 + s1 * mid, f0 + f1 * mid);
            let a = ks * s1 * s1 + kf * f1 * f1;
            let t = if a > 0.0 { (-(ks * s0 * s1 + kf * f0 * f1) / a).clamp(t0, t1) } else { t0 };
            let q = ks * (s0 + s1 * t).powi(2) + kf * (f0 + f1 * t).powi(2);
            if q < best.0 {
                best = (q, t);
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::super::*;
    use super::*;
    use crate::control::clamp_norm;
    use crate::groups::PersonState;
    use crate::perception::{ProxemicsConfig, perceive};
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::f64::consts::{FRAC_PI_2, PI};

    const DT: f64 = 0.1;
    const R: f64 = 0.3;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }

    fn person(pos: Vec2, vel: Vec2) -> Agent {
        Agent { pos, vel, radius: 0.3, weight: 1.0, comfort: 0.0 }
    }

    fn plain() -> SocialMomentumParams {
        // Daza 2021 / Sousa 2022: no comfort term.
        SocialMomentumParams { comfort_weight: 0.0, ..SocialMomentumParams::default() }
    }

    /// Facing +x (heading 0), front sigma 2 m, rear 0.5 m, sides 1 m; zone scale 1 m; keep-out
    /// 0.5 m (Daza 2021's intimate radius).
    fn long_front(heading: f64) -> GaussianSpace {
        GaussianSpace::new(heading, Asymmetric { front: 2.0, rear: 0.5, right: 1.0, left: 1.0 }, 1.0, 0.5)
            .expect("valid")
    }

    fn one_sample_collides(robot: Vec2, sample: Vec2, agent: Agent, shape: AgentShape) -> bool {
        let p = plain();
        let (near, _) = people_sets(robot, Vec2::zeros(), R, None, &[agent], &[shape], 0.55, &p);
        let scene = Scene {
            pos: robot,
            partial_goal: robot,
            wall_bound: R + p.safety_margin,
            edges: &[],
            near: &near,
            reactive: &[],
        };
        collides(&scene, sample, p.horizon)
    }

    #[test]
    fn a_sample_into_the_front_lobe_is_rejected_where_the_disc_accepts_it_and_behind_it_is_not() {
        let at_origin = person(Vec2::zeros(), Vec2::zeros());
        let g = AgentShape::Gaussian(long_front(0.0));
        // In front, 1.8 m away, walking at the person at 0.55 m/s: after the 1.5 s horizon the
        // robot is 0.975 m ahead, zone distance 0.975 / 2 = 0.4875 < 0.5 + 0.1 (keep-out plus
        // margin), while the disc bound is 0.3 + 0.3 + 0.1 = 0.7 < 0.975.
        assert!(one_sample_collides(v(1.8, 0.0), v(-0.55, 0.0), at_origin, g));
        assert!(!one_sample_collides(v(1.8, 0.0), v(-0.55, 0.0), at_origin, AgentShape::Disc));
        // The same approach from behind: zone distance 0.975 / 0.5 = 1.95, accepted by both.
        assert!(!one_sample_collides(v(-1.8, 0.0), v(0.55, 0.0), at_origin, g));
        assert!(!one_sample_collides(v(-1.8, 0.0), v(0.55, 0.0), at_origin, AgentShape::Disc));
        // Turned to face -x, the lobe is on the other side.
        let turned = AgentShape::Gaussian(long_front(PI));
        assert!(!one_sample_collides(v(1.8, 0.0), v(-0.55, 0.0), at_origin, turned));
        assert!(one_sample_collides(v(-1.8, 0.0), v(0.55, 0.0), at_origin, turned));
        // The body disc still counts: from behind at 1.2 m the robot would touch the person
        // (0.375 m < 0.7) although it stays outside the small rear lobe (0.375 / 0.5 = 0.75).
        assert!(one_sample_collides(v(-1.2, 0.0), v(0.55, 0.0), at_origin, g));
        // Already inside the lobe and backing away: accepted (the minimum is at t = 0).
        assert!(!one_sample_collides(v(0.9, 0.0), v(0.3, 0.0), at_origin, g));
        assert!(one_sample_collides(v(0.9, 0.0), v(-0.1, 0.0), at_origin, g));
    }

    #[test]
    fn equal_sigmas_make_the_keep_out_region_a_disc_of_radius_keep_out() {
        let g = GaussianSpace::new(0.7, Asymmetric::SOUSA2022, 1.0, 0.5).expect("valid");
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for _ in 0..200 {
            let d = v(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
            assert!((g.zone_distance(d) - d.norm()).abs() < 1e-12, "{d:?}");
        }
        assert!((g.reach(0.1) - 0.6).abs() < 1e-12);
        assert!((g.level(0.1) - 0.18).abs() < 1e-15);
    }

    #[test]
    fn the_exact_minimum_along_a_motion_matches_dense_sampling() {
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        for _ in 0..500 {
            let sides = Asymmetric {
                front: rng.random_range(0.3..3.0),
                rear: rng.random_range(0.3..3.0),
                right: rng.random_range(0.3..3.0),
                left: rng.random_range(0.3..3.0),
            };
            let g = GaussianSpace::new(rng.random_range(-PI..PI), sides, 1.0, 0.5).expect("valid");
            let d0 = v(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0));
            let dv = v(rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0));
            let h = rng.random_range(0.1..3.0);
            let (q, t) = g.min_along(d0, dv, h);
            assert!((0.0..=h).contains(&t));
            assert!((g.exponent(d0 + dv * t) - q).abs() < 1e-9);
            let dense = (0..=4000)
                .map(|k| g.exponent(d0 + dv * (h * k as f64 / 4000.0)))
                .fold(f64::INFINITY, f64::min);
            assert!(q <= dense + 1e-12, "exact {q} above sampled {dense}");
            assert!(dense - q < 1e-4 * (1.0 + q), "exact {q} far below sampled {dense}");
        }
    }

    #[test]
    fn the_zone_distance_is_the_social_maps_for_an_individual_and_for_a_group() {
        let cfg = ProxemicsConfig::default();
        let people = [
            PersonState::standing(v(0.0, 0.0), 0.0),
            PersonState::standing(v(1.2, 0.0), PI),
            PersonState::standing(v(6.0, 2.0), FRAC_PI_2),
        ];
        let perception = perceive(&cfg, &people, &[vec![], vec![], vec![]], &[]).expect("valid");
        assert_eq!(perception.individuals.len(), 2, "{:?}", perception.groups);
        let mut rng = ChaCha8Rng::seed_from_u64(4);
        for ind in &perception.individuals {
            let g = GaussianSpace::of_individual(ind, 0.5).expect("valid");
            for _ in 0..100 {
                let p = ind.centre + v(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0));
                let ours = g.zone_distance(p - ind.centre);
                let map = ind.zone_distance(p);
                assert!((ours - map).abs() < 1e-9, "{ours} vs {map}");
            }
        }
    }

    #[test]
    fn all_discs_is_social_momentum_bit_for_bit_and_bad_shapes_stop() {
        let mut rng = ChaCha8Rng::seed_from_u64(21);
        let p = SocialMomentumParams::default();
        for _ in 0..100 {
            let vel = v(rng.random_range(-0.4..0.55), rng.random_range(-0.3..0.3));
            let goal = v(rng.random_range(2.0..5.0), rng.random_range(-2.0..2.0));
            let others: Vec<Agent> = (0..3)
                .map(|_| {
                    let a = person(
                        v(rng.random_range(-3.0..4.0), rng.random_range(-2.0..2.0)),
                        v(rng.random_range(-1.0..0.5), rng.random_range(-0.5..0.5)),
                    );
                    Agent { comfort: 1.2, ..a }
                })
                .collect();
            let discs = vec![AgentShape::Disc; others.len()];
            let l = Limits::PEPPER;
            let a = social_momentum(Vec2::zeros(), vel, R, goal, &others, None, &l, DT, &p);
            let b =
                social_momentum_shaped(Vec2::zeros(), vel, R, goal, &others, &discs, None, &l, DT, &p, None);
            assert_eq!(a, b);
        }
        let one = [person(v(3.0, 0.0), Vec2::zeros())];
        let two = [AgentShape::Disc, AgentShape::Disc];
        let l = Limits::PEPPER;
        assert!(
            social_momentum_shaped(
                Vec2::zeros(),
                Vec2::zeros(),
                R,
                v(5.0, 0.0),
                &one,
                &[],
                None,
                &l,
                DT,
                &p,
                None
            )
            .is_some()
        );
        assert_eq!(
            social_momentum_shaped(
                Vec2::zeros(),
                Vec2::zeros(),
                R,
                v(5.0, 0.0),
                &one,
                &two,
                None,
                &l,
                DT,
                &p,
                None
            ),
            None
        );
        assert!(GaussianSpace::new(f64::NAN, Asymmetric::SOUSA2022, 1.0, 0.5).is_err());
        assert!(
            GaussianSpace::new(0.0, Asymmetric { front: 0.0, ..Asymmetric::SOUSA2022 }, 1.0, 0.5).is_err()
        );
        assert!(GaussianSpace::new(0.0, Asymmetric::SOUSA2022, 0.0, 0.5).is_err());
        assert!(GaussianSpace::new(0.0, Asymmetric::SOUSA2022, 1.0, -0.1).is_err());
    }

    /// Drives the robot from the origin to (7, 0) past a person standing at (3, 0.9) facing the
    /// robot's line (heading -π/2) with a long front lobe; returns the smallest zone distance of
    /// the robot's centre (sampled every 10 ms) and the final position.
    fn pass_the_lobe(shape: AgentShape) -> (f64, Vec2) {
        // λ = 0: only the collision filter differs between the two runs (with the momentum term
        // the disc robot also swings right, past a standing person on its left).
        let p = SocialMomentumParams { lambda: 0.0, ..plain() };
        let l = Limits::PEPPER;
        let ped = person(v(3.0, 0.9), Vec2::zeros());
        let lobe = long_front(-FRAC_PI_2);
        let goal = v(7.0, 0.0);
        let (mut pos, mut vel) = (Vec2::zeros(), Vec2::zeros());
        let mut min_zd = f64::INFINITY;
        for _ in 0..400 {
            let partial = pos + clamp_norm(goal - pos, 2.0);
            let out = social_momentum_shaped(pos, vel, R, partial, &[ped], &[shape], None, &l, DT, &p, None)
                .unwrap_or_else(|| l.apply(Vec2::zeros(), 0.0, vel, 0.0, DT).0);
            for k in 1..=10 {
                min_zd = min_zd.min(lobe.zone_distance(pos + out * (DT * k as f64 / 10.0) - ped.pos));
            }
            vel = out;
            pos += vel * DT;
        }
        (min_zd, pos)
    }

    #[test]
    fn the_gaussian_robot_keeps_out_of_the_front_lobe_that_the_disc_robot_crosses() {
        // Straight along y = 0 the robot passes 0.9 m from the person's centre: clear of the disc
        // bound (0.7 m) but at zone distance 0.9 / 2 = 0.45 < 0.5 inside the front lobe.
        let (disc_min, disc_end) = pass_the_lobe(AgentShape::Disc);
        assert!(disc_min < 0.5, "the disc robot stayed out of the lobe: {disc_min}");
        assert!((disc_end - v(7.0, 0.0)).norm() < 0.1, "{disc_end:?}");
        let (gauss_min, gauss_end) = pass_the_lobe(AgentShape::Gaussian(long_front(-FRAC_PI_2)));
        assert!(gauss_min >= 0.5, "the Gaussian robot entered the keep-out zone: {gauss_min}");
        assert!((gauss_end - v(7.0, 0.0)).norm() < 0.1, "did not arrive: {gauss_end:?}");
    }
}
