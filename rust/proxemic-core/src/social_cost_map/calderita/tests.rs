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
    let pair =
        [PersonState::standing(Vec2::new(0.0, 1.5), 0.0), PersonState::standing(Vec2::new(0.0, -1.5), 0.0)];
    assert!(density_factor(&z, &c, &pair, Vec2::zeros()).is_infinite());
    assert!(density_factor(&z, &c, &pair, Vec2::new(0.0, 0.5)).is_infinite());
    assert_eq!(density_factor(&z, &c, &pair[..1], Vec2::zeros()), 2.0);
    // 4 m apart, midpoint 2 m to the side of each: 2 exp(-4/3.5556) = 0.64930, below the
    // personal level 0.66698 and above the social one: social, 2.0.
    let wide =
        [PersonState::standing(Vec2::new(0.0, 2.0), 0.0), PersonState::standing(Vec2::new(0.0, -2.0), 0.0)];
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

/// Every cell of `layer` against [`density_factor`] for `people` (bit for bit).
fn assert_layer(layer: &DensityLayer, z: &DensityZones, c: &SocialCosts, people: &[PersonState], what: &str) {
    let spec = layer.spec;
    for iy in 0..spec.height {
        for ix in 0..spec.width {
            let want = density_factor(z, c, people, spec.center(ix, iy));
            let got = layer.factors()[spec.index(ix, iy)];
            assert_eq!(got.to_bits(), want.to_bits(), "{what}: cell ({ix}, {iy}): {got} != {want}");
        }
    }
}

/// A person facing +x with the centre of a cell of the region `x0..x1` (m) exactly at one of
/// the Hall radii to their left: `G_d` there is exactly that contour level when nobody else
/// reaches the cell, the hardest case for the margins.
fn on_a_contour(spec: &GridSpec, rng: &mut rand_chacha::ChaCha8Rng, x0: f64, x1: f64) -> PersonState {
    use rand::Rng;
    let radii =
        [HallZones::EVALUATION.intimate, HallZones::EVALUATION.personal, HallZones::EVALUATION.social];
    loop {
        let r = radii[rng.random_range(0..3)];
        let ix = spec.cell_of(Vec2::new(rng.random_range(x0..x1), spec.origin.y)).map_or(0, |c| c.0);
        let iy = rng.random_range(0..spec.height);
        let x = spec.center(ix, iy);
        let p = Vec2::new(x.x, x.y - r);
        if x.y - p.y == r {
            return PersonState::standing(p, 0.0);
        }
    }
}

#[test]
fn the_updated_layer_is_the_factor_at_each_cell_centre_as_people_move_leave_join_and_turn() {
    // Random scenes on a grid whose sides are no multiple of the tile or the block: a crowd
    // in clusters that moves (by centimetres and by metres), turns, loses and gains people
    // (anywhere in the list), goes back to earlier states (to and fro), with people outside
    // the grid, and, away from the crowd (narrow Gaussians: nobody else reaches it), a
    // person with a cell centre exactly on a contour level. After every update every cell
    // must be `density_factor`'s, and most updates must stay incremental.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
    let spec = GridSpec { origin: Vec2::new(-0.35, 0.25), resolution: 0.1, width: 203, height: 161 };
    let configs = [
        (DensityParams::default(), SocialCosts::default(), false),
        (
            DensityParams { sigma_h: 0.8, sigma_r: 0.4, sigma_s: 0.6, k: 0.3, ..DensityParams::default() },
            SocialCosts { personal_cost: 1.5, social_cost: 3.0, public_cost: 0.8, ..SocialCosts::default() },
            true,
        ),
    ];
    let mut incremental = 0;
    for (dp, c, contour) in configs {
        let z = DensityZones::new(dp, HallZones::EVALUATION).expect("valid");
        // The crowd keeps to x < 8 m (narrow Gaussians reach 7.2 m), the contour person's
        // cell to x > 15.5 m.
        let crowd_x = if contour { 8.0 } else { 20.0 };
        let person = |rng: &mut rand_chacha::ChaCha8Rng| {
            let p = Vec2::new(rng.random_range(-1.0..crowd_x), rng.random_range(-0.5..16.5));
            PersonState::standing(p, rng.random_range(-3.2..3.2))
        };
        let mut people: Vec<PersonState> = Vec::new();
        for _ in 0..4 {
            let centre = person(&mut rng).pos;
            for _ in 0..rng.random_range(1..6) {
                let off = Vec2::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
                people.push(PersonState::standing(centre + off, rng.random_range(-3.2..3.2)));
            }
        }
        if contour {
            people.push(on_a_contour(&spec, &mut rng, 15.5, 19.5));
        }
        let mut layer = DensityLayer::new(spec, z, &c);
        let open = crate::map::CostGrid { spec, cost: vec![0; spec.len()] };
        let mut map = super::super::SocialMap::new(open, &[], c);
        layer.update(&people);
        layer.write_to(&mut map).expect("same grid");
        assert_layer(&layer, &z, &c, &people, "first");
        let mut history = vec![people.clone()];
        for step in 0..40 {
            let n = people.len();
            match rng.random_range(0..8) {
                0 | 1 => {
                    for _ in 0..rng.random_range(1..4) {
                        let p = &mut people[rng.random_range(0..n)];
                        p.pos += Vec2::new(rng.random_range(-0.15..0.15), rng.random_range(-0.15..0.15));
                    }
                }
                2 => {
                    let p = &mut people[rng.random_range(0..n)];
                    p.heading += rng.random_range(-0.5..0.5);
                }
                3 if n > 2 => {
                    people.remove(rng.random_range(0..n));
                }
                4 => {
                    let p = if contour && rng.random_bool(0.5) {
                        on_a_contour(&spec, &mut rng, 15.5, 19.5)
                    } else {
                        person(&mut rng)
                    };
                    people.insert(rng.random_range(0..=n), p);
                }
                5 => people = history[rng.random_range(0..history.len())].clone(),
                6 => {
                    let k = rng.random_range(0..n);
                    people[k] = person(&mut rng);
                }
                _ => {
                    // The contour person moves to another contour cell.
                    if let Some(k) = people.iter().position(|p| p.pos.x > crowd_x + 5.0) {
                        people[k] = on_a_contour(&spec, &mut rng, 15.5, 19.5);
                    }
                }
            }
            if contour {
                for p in &mut people {
                    if p.pos.x < crowd_x + 5.0 {
                        p.pos.x = p.pos.x.min(crowd_x);
                    }
                }
            }
            history.push(people.clone());
            layer.update(&people);
            layer.write_to(&mut map).expect("same grid");
            if !layer.rebuilt() {
                incremental += 1;
                assert!(layer.cells_summed() < spec.len() / 16);
            }
            assert_layer(&layer, &z, &c, &people, &format!("step {step}"));
            let bits = |v: &[f64]| v.iter().map(|f| f.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(map.people_layer()),
                bits(layer.factors()),
                "step {step}: the map's people layer"
            );
        }
    }
    assert!(incremental > 50, "most updates incremental: {incremental} of 80");
}

#[test]
fn cells_exactly_on_a_contour_get_the_factor_of_density_factor_rebuilt_and_updated() {
    // On a grid of 1/8 m cells from the origin (exact centres), people facing +x at cell
    // centres, out of each other's reach (narrow Gaussians, at least 9.4 m apart), with
    // Hall radii 0.5/1/4 m: the cells 4, 8 and 32 rows beside each person have `G_d`
    // exactly at a contour level. Any margin too small for the products' rounding puts some
    // of them in the wrong zone. Then people move between such places, leave and come back.
    let dp = DensityParams { sigma_h: 1.0, sigma_r: 0.5, sigma_s: 1.0, ..DensityParams::default() };
    let z = DensityZones::new(dp, HallZones::DAZA2021).expect("valid");
    let c = SocialCosts::default();
    let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.125, width: 290, height: 177 };
    let at = |ix: usize, iy: usize| PersonState::standing(spec.center(ix, iy), 0.0);
    let mut people: Vec<PersonState> = [30, 113, 195, 270]
        .into_iter()
        .flat_map(|ix| [35, 138].map(|iy| (ix, iy)))
        .enumerate()
        .map(|(k, (ix, iy))| at(ix + k % 3, iy + k % 5))
        .collect();
    let on_contour = |people: &[PersonState]| {
        let mut n = 0;
        for p in people {
            for (r, level) in [0.5, 1.0, 4.0].into_iter().zip(z.levels()) {
                for side in [-r, r] {
                    if z.density(people, p.pos + Vec2::new(0.0, side)) == level {
                        n += 1;
                    }
                }
            }
        }
        n
    };
    assert!(on_contour(&people) >= 40, "cells exactly on a contour: {}", on_contour(&people));
    let mut layer = DensityLayer::new(spec, z, &c);
    layer.rebuild(&people);
    assert_layer(&layer, &z, &c, &people, "rebuilt");
    let moves: [(usize, isize, isize); 6] =
        [(0, 1, 0), (3, 0, 2), (5, -3, 1), (0, -1, 0), (7, 2, -2), (3, 0, -2)];
    for (step, (k, dx, dy)) in moves.into_iter().enumerate() {
        let (ix, iy) = spec.cell_of(people[k].pos).expect("inside");
        people[k] = at(ix.wrapping_add_signed(dx), iy.wrapping_add_signed(dy));
        layer.update(&people);
        assert!(!layer.rebuilt());
        assert_layer(&layer, &z, &c, &people, &format!("move {step}"));
    }
    let gone = people.remove(2);
    layer.update(&people);
    assert_layer(&layer, &z, &c, &people, "one left");
    people.insert(2, gone);
    layer.update(&people);
    assert_layer(&layer, &z, &c, &people, "back");
    assert!(on_contour(&people) >= 40);
}

#[test]
fn small_moves_in_a_dense_crowd_update_to_the_factor_at_each_cell_centre() {
    // The benchmark's kind of scene: 50 people over a 36 by 25 m hall (contours everywhere,
    // most tiles summed per cell), a few of them moving by centimetres, turning, or going
    // back, updated from the same reference each time: the blocks' and tiles' bounds of the
    // changes decide which cells keep the reference's factors. Every cell must still be
    // `density_factor`'s, and the updates must stay incremental.
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(23);
    let z = zones();
    let c = SocialCosts::default();
    let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.1, width: 360, height: 252 };
    let crowd: Vec<PersonState> = (0..50)
        .map(|_| {
            let p = Vec2::new(rng.random_range(0.5..35.5), rng.random_range(0.5..24.7));
            PersonState::standing(p, rng.random_range(-3.2..3.2))
        })
        .collect();
    let mut layer = DensityLayer::new(spec, z, &c);
    layer.rebuild(&crowd);
    assert_layer(&layer, &z, &c, &crowd, "rebuilt");
    for step in 0..6 {
        let mut moved = crowd.clone();
        for _ in 0..5 {
            let p = &mut moved[rng.random_range(0..50)];
            if step % 3 == 2 {
                p.heading += rng.random_range(-0.2..0.2);
            } else {
                p.pos += Vec2::new(rng.random_range(-0.1..0.1), rng.random_range(-0.1..0.1));
            }
        }
        layer.update(&moved);
        assert!(!layer.rebuilt(), "step {step}");
        assert_layer(&layer, &z, &c, &moved, &format!("step {step}"));
    }
    layer.update(&crowd);
    assert_layer(&layer, &z, &c, &crowd, "back");
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
