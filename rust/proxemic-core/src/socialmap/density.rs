//! Calderita et al. §4.1 and §5.2.1 rasterised: the people layer of the `calderita` planner's
//! social map, from the contours of the summed density `G_d` (eq. 5) instead of Hall radii around
//! each individual.
//!
//! A cell's people factor comes from `G_d` at its centre ([`DensityZones::zone_of`]): inside the
//! intimate contour it is forbidden (the paper sets the nodes' availability to occupied), inside
//! the personal contour it costs [`SocialCosts::personal_cost`] (paper: 4.0), inside the social
//! contour [`SocialCosts::social_cost`] (2.0), elsewhere [`SocialCosts::public_cost`] (1.0). A
//! cell in a group's space `J = {G_d >= φ}` (eq. 8), "the personal space of a group of
//! individuals" in the paper's words, costs at least the personal factor.
//!
//! With the default parameters (`σ_s = 4/3` m, Hall radii 0.45/1.2/3.6 m, `Ω_d = 1.2` m ahead,
//! `k = 1`) the group threshold `φ = 1 + e^{-0.18} = 1.835` lies above the intimate level
//! `L(0.45) = e^{-0.0570} = 0.945`, so `J` falls inside the forbidden intimate region and the group
//! term never raises a cost: the merging of the people's contours does the grouping on the map.
//! It binds only with other parameters (a larger `k`-free threshold below the intimate level).
//!
//! Choices where the paper is silent (also in `docs/algorithms.md`):
//! - the contour levels of the zones: [`DensityZones`] (the one-person Gaussian's value at
//!   Hall's radius to the side);
//! - walls: `G_d` is summed over the plane `S`, as the paper defines it, without the line-of-sight
//!   cut that proxemic's own social map applies; in the Calderita scenes every person is in the
//!   room the robot crosses, so nothing leaks into a place the robot cannot see;
//! - which people: the caller passes the people who stand still (see [`crate::plan::social`]);
//!   the paper's scenes have no walkers.

use crate::groups::PersonState;
use crate::map::grid::GridSpec;
use crate::math::Vec2;
use crate::proxemics::{DensityZones, Zone};

use super::SocialCosts;

/// The people factor at `x` (m) from the density contours of `people` (module docs):
/// `f64::INFINITY` in the intimate region, else the zone's factor of `costs`, at least
/// `costs.personal_cost` inside a group's space.
pub fn density_factor(zones: &DensityZones, costs: &SocialCosts, people: &[PersonState], x: Vec2) -> f64 {
    let g = zones.density(people, x);
    zone_factor(zones, costs, g)
}

/// The factor of a density value `g` (see [`density_factor`]).
fn zone_factor(zones: &DensityZones, costs: &SocialCosts, g: f64) -> f64 {
    let zone = zones.zone_of_density(g);
    let f = match zone {
        Zone::Intimate => return f64::INFINITY,
        Zone::Personal => costs.personal_cost,
        Zone::Social => costs.social_cost,
        Zone::Public => costs.public_cost,
    };
    if g >= zones.phi() { f.max(costs.personal_cost) } else { f }
}

/// The people layer of a grid `spec` (row-major, one factor per cell, evaluated at the cell
/// centres) for `people` (module docs).
///
/// Bit for bit the factor of [`density_factor`] at every cell centre, computed tile by tile
/// (8 cells square). Per tile, a person whose exponent is above 40 over the whole tile
/// adds exactly 0 to every cell's sum (Kirby's Gaussian is cut there, see
/// [`crate::groups::DensityParams::gaussian_local`]) and is left out. When the sum of the others'
/// smallest values over the tile and the sum of their largest values (with margins for rounding)
/// lie between the same contour levels, every cell of the tile gets that zone's factor; else its
/// quarters are tried the same way, down to blocks of 2 cells square. In a block left undecided,
/// the people whose exponent can fall to 10 in the tile are summed per cell, and the others are
/// bounded by their largest value in the tile. A cell whose sum lies, with that bound and a margin
/// for rounding, between the same contour levels at both ends gets that zone's factor; any other
/// cell is summed over every person not left out, in their order: the same sum as
/// [`density_factor`].
pub fn density_layer(
    spec: &GridSpec,
    zones: &DensityZones,
    costs: &SocialCosts,
    people: &[PersonState],
) -> Vec<f64> {
    let mut out = vec![costs.public_cost.max(1.0); spec.len()];
    if people.is_empty() {
        return out;
    }
    // Each person's facing once, not once per cell (the same sum as `density_factor`'s).
    let facing: Vec<(Vec2, Vec2)> = people.iter().map(|p| (p.pos, p.facing())).collect();
    let params = zones.params();
    let levels = zones.levels();
    let thresholds = [levels[2], levels[1], levels[0], zones.phi()];
    // How many contour levels (and φ) `g` reaches: every comparison `zone_factor` makes is
    // monotone in `g`, so equal classes at both ends of an interval give equal factors inside.
    let class = |g: f64| thresholds.iter().filter(|&&t| g >= t).count();
    let (mut some, mut near) = (Vec::with_capacity(people.len()), Vec::with_capacity(people.len()));
    let mut blocks = Vec::new();
    for ty in (0..spec.height).step_by(TILE) {
        let y1 = (ty + TILE).min(spec.height) - 1;
        for tx in (0..spec.width).step_by(TILE) {
            let x1 = (tx + TILE).min(spec.width) - 1;
            let (lo, hi) = (spec.center(tx, ty), spec.center(x1, y1));
            some.clear();
            near.clear();
            let mut far = 0.0;
            for (i, &(pos, f)) in facing.iter().enumerate() {
                let q = exponent_lower_bound(params, pos, f, lo, hi);
                if q > 40.0 * (1.0 + 1e-9) {
                    continue;
                }
                some.push(i);
                if q <= NEAR_EXPONENT {
                    near.push(i);
                } else {
                    far += exp_table_above(q);
                }
            }
            let far = far * (1.0 + 1e-9);
            // The tile, and then its quarters down to 2 cells square, at once when the bounds of
            // `G_d` over them fall in one class: none of their cells needs its sum.
            blocks.push((tx, ty, x1, y1));
            while let Some((bx0, by0, bx1, by1)) = blocks.pop() {
                let (lo, hi) = (spec.center(bx0, by0), spec.center(bx1, by1));
                // The far people add between 0 and `far` (their bound over the whole tile).
                let (mut t_lo, mut t_hi) = (0.0, far);
                for &i in &near {
                    let (pos, f) = facing[i];
                    t_hi += exp_table_above(exponent_lower_bound(params, pos, f, lo, hi));
                    t_lo += exp_table_below(exponent_upper_bound(params, pos, f, lo, hi));
                }
                let (t_lo, t_hi) = (t_lo * (1.0 - 1e-9), t_hi * (1.0 + 1e-9));
                if class(t_lo) == class(t_hi) {
                    let factor = zone_factor(zones, costs, t_lo);
                    for iy in by0..=by1 {
                        out[spec.index(bx0, iy)..=spec.index(bx1, iy)].fill(factor);
                    }
                    continue;
                }
                if bx1 - bx0 >= 2 || by1 - by0 >= 2 {
                    let (mx, my) = ((bx0 + bx1) / 2, (by0 + by1) / 2);
                    for (qx0, qx1) in [(bx0, mx), (mx + 1, bx1)] {
                        for (qy0, qy1) in [(by0, my), (my + 1, by1)] {
                            if qx0 <= qx1 && qy0 <= qy1 {
                                blocks.push((qx0, qy0, qx1, qy1));
                            }
                        }
                    }
                    continue;
                }
                for iy in by0..=by1 {
                    for ix in bx0..=bx1 {
                        let x = spec.center(ix, iy);
                        let g_near: f64 = near.iter().map(|&i| zones.term(facing[i].0, facing[i].1, x)).sum();
                        let (g_lo, g_hi) = (g_near * (1.0 - 1e-12), (g_near + far) * (1.0 + 1e-12));
                        let g = if class(g_lo) == class(g_hi) {
                            g_near
                        } else {
                            some.iter().map(|&i| zones.term(facing[i].0, facing[i].1, x)).sum()
                        };
                        out[spec.index(ix, iy)] = zone_factor(zones, costs, g);
                    }
                }
            }
        }
    }
    out
}

/// Side of the square tiles of [`density_layer`] (cells).
const TILE: usize = 8;

/// People whose exponent can fall to this in a tile are summed per cell by [`density_layer`]
/// (`exp(-10) = 4.5e-5`: the others together stay far below the contour levels' gaps).
const NEAR_EXPONENT: f64 = 10.0;

/// The box `lo`-`hi` (m) in the frame of a person at `pos` facing the unit vector `f`: the
/// centre's offsets along and across the facing, `u` and `v`, and the box's half-extents along
/// those axes, `du` and `dv`, as `[u, du, v, dv]` (m).
fn box_in_frame(pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> [f64; 4] {
    let c = (lo + hi) * 0.5 - pos;
    let (hx, hy) = (0.5 * (hi.x - lo.x), 0.5 * (hi.y - lo.y));
    [
        f.x * c.x + f.y * c.y,
        f.x.abs() * hx + f.y.abs() * hy,
        -f.y * c.x + f.x * c.y,
        f.y.abs() * hx + f.x.abs() * hy,
    ]
}

/// A lower bound on Kirby's exponent `u²/(2σ_u²) + v²/(2σ_s²)` (see
/// [`crate::groups::DensityParams::gaussian_local`]) of the person at `pos` facing the unit
/// vector `f`, over the axis-aligned box `lo`-`hi` (m): each axis term's minimum over the box,
/// less a relative margin far above rounding.
fn exponent_lower_bound(p: &crate::groups::DensityParams, pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> f64 {
    let [u, du, v, dv] = box_in_frame(pos, f, lo, hi);
    let side = |m: f64, s: f64| m * m / (2.0 * s * s);
    let qu = if u - du > 0.0 {
        side(u - du, p.sigma_h)
    } else if u + du < 0.0 {
        side(u + du, p.sigma_r)
    } else {
        0.0
    };
    let qv = if v - dv > 0.0 {
        side(v - dv, p.sigma_s)
    } else if v + dv < 0.0 {
        side(v + dv, p.sigma_s)
    } else {
        0.0
    };
    (qu + qv) * (1.0 - 1e-9)
}

/// Steps per unit of exponent of [`exp_table`].
const EXP_STEPS: f64 = 32.0;

/// `exp(-i / EXP_STEPS)` for `i` in `0..=40 EXP_STEPS` (Kirby's Gaussian is cut at exponent 40).
fn exp_table() -> &'static [f64] {
    static TABLE: std::sync::OnceLock<Vec<f64>> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| (0..=(40.0 * EXP_STEPS) as usize).map(|i| (-(i as f64) / EXP_STEPS).exp()).collect())
}

/// An upper bound on `exp(-q)` for `0 <= q <= 40` (with a margin), from [`exp_table`].
fn exp_table_above(q: f64) -> f64 {
    // (The float-to-integer cast truncates: the floor of a non-negative value.)
    let i = (q.max(0.0) * EXP_STEPS) as usize;
    exp_table().get(i).map_or(1.0, |&e| e * (1.0 + 1e-12))
}

/// A lower bound on the term `exp(-q)` of a Gaussian cut at exponent 40 (0 beyond), from
/// [`exp_table`] (with a margin).
fn exp_table_below(q: f64) -> f64 {
    if q > 40.0 {
        return 0.0;
    }
    let t = q.max(0.0) * EXP_STEPS;
    let i = t as usize + usize::from((t as usize as f64) < t); // the ceiling
    exp_table().get(i).map_or(0.0, |&e| e * (1.0 - 1e-12))
}

/// An upper bound on Kirby's exponent (see [`exponent_lower_bound`]) over the box `lo`-`hi`
/// (m): each axis term is convex with its minimum at 0, so its maximum over the box's range of
/// that axis is at one end; plus a relative margin far above rounding.
fn exponent_upper_bound(p: &crate::groups::DensityParams, pos: Vec2, f: Vec2, lo: Vec2, hi: Vec2) -> f64 {
    let [u, du, v, dv] = box_in_frame(pos, f, lo, hi);
    let side = |m: f64, s: f64| m * m / (2.0 * s * s);
    let along = |m: f64| if m >= 0.0 { side(m, p.sigma_h) } else { side(m, p.sigma_r) };
    let qu = along(u - du).max(along(u + du));
    let qv = side(v - dv, p.sigma_s).max(side(v + dv, p.sigma_s));
    (qu + qv) * (1.0 + 1e-9)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::groups::DensityParams;
    use crate::proxemics::HallZones;

    fn zones() -> DensityZones {
        DensityZones::new(DensityParams::default(), HallZones::EVALUATION).expect("valid")
    }

    #[test]
    fn one_person_facing_east_known_factors() {
        // Person at the origin facing +x, σ_h = 2 (ahead), σ_r = 1 (behind), σ_s = 4/3 (sides).
        // Levels L(r) = exp(-r² / (2 σ_s²)), 2 σ_s² = 32/9 = 3.5556:
        //   intimate L(0.45) = exp(-0.2025 / 3.5556) = exp(-0.05695) = 0.94464
        //   personal L(1.2)  = exp(-1.44 / 3.5556)   = exp(-0.405)    = 0.66698
        //   social   L(3.6)  = exp(-12.96 / 3.5556)  = exp(-3.645)    = 0.02612
        // Points and g = exp(-u²/(2σ_u²) - v²/(2σ_s²)):
        //   (0.6, 0):  exp(-0.36/8)   = 0.95600 >= 0.94464  -> intimate, forbidden
        //   (0.7, 0):  exp(-0.49/8)   = 0.94059 <  0.94464  -> personal, 4.0
        //   (-0.5, 0): exp(-0.25/2)   = 0.88250             -> personal, 4.0
        //   (0, 1.5):  exp(-2.25/3.5556) = exp(-0.63281) = 0.53110 -> social, 2.0
        //   (-2.0, 0): exp(-4/2)      = 0.13534             -> social, 2.0
        //   (-2.8, 0): exp(-7.84/2)   = 0.01984 <  0.02612  -> public, 1.0
        //   (5.0, 0):  exp(-25/8)     = 0.04394 >= 0.02612  -> social, 2.0
        let z = zones();
        let c = SocialCosts::default();
        let one = [PersonState::standing(Vec2::zeros(), 0.0)];
        let f = |x: f64, y: f64| density_factor(&z, &c, &one, Vec2::new(x, y));
        assert!(f(0.6, 0.0).is_infinite());
        assert_eq!(f(0.7, 0.0), 4.0);
        assert_eq!(f(-0.5, 0.0), 4.0);
        assert_eq!(f(0.0, 1.5), 2.0);
        assert_eq!(f(-2.0, 0.0), 2.0);
        assert_eq!(f(-2.8, 0.0), 1.0);
        assert_eq!(f(5.0, 0.0), 2.0);
    }

    #[test]
    fn two_people_side_by_side_merge_into_one_forbidden_region() {
        // Two people facing +x at (0, ±1.5), 3 m apart. At the midpoint each Gaussian is at
        // 1.5 m to its side: g = exp(-2.25 / 3.5556) = 0.53110, G_d = 1.06220 >= 0.94464: the
        // midpoint is intimate (forbidden) although it is 1.5 m from both, beyond Hall's
        // personal radius. Alone, either person puts it in the social zone (0.53110 < 0.66698).
        // At (0, 0.5): 1 m from one, 2 m from the other:
        //   exp(-1/3.5556) + exp(-4/3.5556) = 0.75484 + 0.32465 = 1.07949 -> intimate too.
        let z = zones();
        let c = SocialCosts::default();
        let pair = [
            PersonState::standing(Vec2::new(0.0, 1.5), 0.0),
            PersonState::standing(Vec2::new(0.0, -1.5), 0.0),
        ];
        assert!(density_factor(&z, &c, &pair, Vec2::zeros()).is_infinite());
        assert!(density_factor(&z, &c, &pair, Vec2::new(0.0, 0.5)).is_infinite());
        assert_eq!(density_factor(&z, &c, &pair[..1], Vec2::zeros()), 2.0);
        // 4 m apart, midpoint 2 m to the side of each: 2 exp(-4/3.5556) = 0.64930, below the
        // personal level 0.66698 and above the social one: social, 2.0.
        let wide = [
            PersonState::standing(Vec2::new(0.0, 2.0), 0.0),
            PersonState::standing(Vec2::new(0.0, -2.0), 0.0),
        ];
        assert_eq!(density_factor(&z, &c, &wide, Vec2::zeros()), 2.0);
    }

    #[test]
    fn the_layer_of_a_crowd_is_the_factor_at_each_cell_centre_bit_for_bit() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let z = zones();
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::new(0.0, 0.0), resolution: 0.1, width: 120, height: 90 };
        let crowd: Vec<PersonState> = (0..25)
            .map(|_| {
                let p = Vec2::new(rng.random_range(0.0..12.0), rng.random_range(0.0..9.0));
                PersonState::standing(p, rng.random_range(-3.2..3.2))
            })
            .collect();
        let layer = density_layer(&spec, &z, &c, &crowd);
        let facing: Vec<(Vec2, Vec2)> = crowd.iter().map(|p| (p.pos, p.facing())).collect();
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let x = spec.center(ix, iy);
                assert_eq!(z.density_facing(&facing, x).to_bits(), z.density(&crowd, x).to_bits());
                assert_eq!(layer[spec.index(ix, iy)], density_factor(&z, &c, &crowd, x));
            }
        }
    }

    #[test]
    fn the_tiled_layer_of_clustered_crowds_is_the_factor_at_each_cell_centre_bit_for_bit() {
        // Tight clusters (merged intimate regions, many contour crossings inside a tile), other
        // sigmas, a grid whose size is no multiple of the tile, and costs that do not grow with
        // the zone: every cell must still be `density_factor`'s.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(6);
        let costs = [
            SocialCosts::default(),
            SocialCosts { personal_cost: 1.5, social_cost: 3.0, public_cost: 1.2, ..SocialCosts::default() },
        ];
        let params = [
            DensityParams::default(),
            DensityParams { sigma_h: 1.0, sigma_r: 0.6, sigma_s: 0.8, k: 0.3, ..DensityParams::default() },
        ];
        let spec = GridSpec { origin: Vec2::new(-1.0, 0.5), resolution: 0.1, width: 163, height: 97 };
        for (c, dp) in costs.iter().zip(params) {
            let z = DensityZones::new(dp, HallZones::EVALUATION).expect("valid");
            let mut crowd = Vec::new();
            for _ in 0..8 {
                let centre = Vec2::new(rng.random_range(-1.0..15.0), rng.random_range(0.5..10.0));
                for _ in 0..rng.random_range(1..7) {
                    let off = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                    crowd.push(PersonState::standing(centre + off, rng.random_range(-3.2..3.2)));
                }
            }
            let layer = density_layer(&spec, &z, c, &crowd);
            let mut zones_seen = std::collections::BTreeSet::new();
            for iy in 0..spec.height {
                for ix in 0..spec.width {
                    let want = density_factor(&z, c, &crowd, spec.center(ix, iy));
                    assert_eq!(layer[spec.index(ix, iy)].to_bits(), want.to_bits(), "cell ({ix}, {iy})");
                    zones_seen.insert(want.to_bits());
                }
            }
            assert_eq!(zones_seen.len(), 4, "every factor appears");
        }
    }

    #[test]
    fn the_layer_is_the_factor_at_each_cell_centre() {
        let z = zones();
        let c = SocialCosts::default();
        let spec = GridSpec { origin: Vec2::new(-2.0, -2.0), resolution: 0.5, width: 8, height: 8 };
        let one = [PersonState::standing(Vec2::new(0.1, 0.2), 1.0)];
        let layer = density_layer(&spec, &z, &c, &one);
        for iy in 0..spec.height {
            for ix in 0..spec.width {
                let want = density_factor(&z, &c, &one, spec.center(ix, iy));
                assert_eq!(layer[spec.index(ix, iy)], want);
            }
        }
        assert!(density_layer(&spec, &z, &c, &[]).iter().all(|&f| f == 1.0));
    }
}
