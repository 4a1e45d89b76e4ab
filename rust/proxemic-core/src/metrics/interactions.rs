//! The ground truth of groups and interactions at one instant (see "Ground truth of groups and
//! interactions" in the module documentation of [`crate::metrics`]).

use super::{InteractionLink, LinkKind, OSpace};
use crate::geom::contains_point_polygon_pnpoly;
use crate::math::Vec2;

/// A person moving slower than this (m/s) counts as standing still, for o-spaces and
/// person-object interactions.
pub const STILL_SPEED: f64 = 0.1;

/// Members of a group standing farther than this (m) from the mean position of its still members
/// are not part of its o-space: Hall's social-zone radius of 3.6 m between two people who still
/// talk means at most 1.8 m from their centre; 2.0 m leaves room for larger circles.
pub const GATHERED_RADIUS: f64 = 2.0;

/// An object whose interaction space people use, for [`interactions`].
#[derive(Clone, Debug)]
pub struct InteractionObject {
    /// Interaction polygon (world frame, m).
    pub polygon: Vec<Vec2>,
    /// The object's centre (m), the far end of a person-object interaction segment.
    pub centre: Vec2,
}

/// The ground-truth o-spaces and interaction segments of one instant (see the module
/// documentation): `groups[i]` is person `i`'s group id, if any.
pub fn interactions(
    positions: &[Vec2],
    velocities: &[Vec2],
    groups: &[Option<u32>],
    objects: &[InteractionObject],
    ospaces: &mut Vec<OSpace>,
    links: &mut Vec<InteractionLink>,
) {
    ospaces.clear();
    links.clear();
    // The still group members by group id (then index): one pass over the people.
    let mut still_members: Vec<(u32, usize)> = groups
        .iter()
        .enumerate()
        .filter_map(|(i, g)| g.filter(|_| velocities[i].norm() < STILL_SPEED).map(|id| (id, i)))
        .collect();
    still_members.sort_unstable();
    for same in still_members.chunk_by(|a, b| a.0 == b.0) {
        if same.len() < 2 {
            continue;
        }
        let still: Vec<usize> = same.iter().map(|&(_, i)| i).collect();
        // The largest gathering: around each still member, the still members within a circle's
        // diameter of it, kept if within the radius of their mean position.
        let mut members: Vec<usize> = Vec::new();
        for &i in &still {
            let near: Vec<usize> = still
                .iter()
                .copied()
                .filter(|&j| (positions[j] - positions[i]).norm() <= 2.0 * GATHERED_RADIUS)
                .collect();
            let mean = near.iter().fold(Vec2::zeros(), |a, &j| a + positions[j]) / near.len() as f64;
            let kept: Vec<usize> =
                near.into_iter().filter(|&j| (positions[j] - mean).norm() <= GATHERED_RADIUS).collect();
            if kept.len() > members.len() {
                members = kept;
            }
        }
        if members.len() < 2 {
            continue;
        }
        let centre = members.iter().fold(Vec2::zeros(), |a, &i| a + positions[i]) / members.len() as f64;
        let radius =
            members.iter().map(|&i| (positions[i] - centre).norm()).sum::<f64>() / members.len() as f64;
        ospaces.push(OSpace { centre, radius });
        for (k, &i) in members.iter().enumerate() {
            for &j in &members[k + 1..] {
                links.push(InteractionLink {
                    a: positions[i],
                    b: positions[j],
                    kind: LinkKind::PersonPerson,
                });
            }
        }
    }
    // Each space's vertical extent: the horizontal line of a point below the lowest vertex, or at
    // or above the highest, crosses no edge, so pnpoly would find it outside edge by edge.
    let extents: Vec<(f64, f64)> = objects
        .iter()
        .map(|o| {
            o.polygon
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.y), hi.max(p.y)))
        })
        .collect();
    for (&q, v) in positions.iter().zip(velocities) {
        if v.norm() >= STILL_SPEED {
            continue;
        }
        for (o, &(lo, hi)) in objects.iter().zip(&extents) {
            if q.y < lo || q.y >= hi {
                continue;
            }
            if contains_point_polygon_pnpoly(q, &o.polygon) {
                links.push(InteractionLink { a: q, b: o.centre, kind: LinkKind::PersonObject });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ground_truth_groups_and_object_interactions() {
        // A pair (group 7) 2 m apart, a lone walker, a still viewer inside a square space.
        let pos = [Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), Vec2::new(5.0, 5.0), Vec2::new(10.5, 0.5)];
        let vel = [Vec2::zeros(), Vec2::zeros(), Vec2::new(1.0, 0.0), Vec2::new(0.05, 0.0)];
        let groups = [Some(7), Some(7), None, None];
        let square =
            vec![Vec2::new(10.0, 0.0), Vec2::new(11.0, 0.0), Vec2::new(11.0, 1.0), Vec2::new(10.0, 1.0)];
        let objects = [InteractionObject { polygon: square, centre: Vec2::new(10.5, -0.5) }];
        let (mut os, mut ls) = (Vec::new(), Vec::new());
        interactions(&pos, &vel, &groups, &objects, &mut os, &mut ls);
        assert_eq!(os, vec![OSpace { centre: Vec2::new(1.0, 0.0), radius: 1.0 }]);
        assert_eq!(ls.len(), 2);
        assert_eq!(ls[0].kind, LinkKind::PersonPerson);
        assert_eq!((ls[0].a, ls[0].b), (pos[0], pos[1]));
        assert_eq!(ls[1].kind, LinkKind::PersonObject);
        assert_eq!((ls[1].a, ls[1].b), (pos[3], Vec2::new(10.5, -0.5)));
        // The viewer walking away is no longer interacting.
        let vel2 = [Vec2::zeros(), Vec2::zeros(), Vec2::zeros(), Vec2::new(0.5, 0.0)];
        interactions(&pos, &vel2, &groups, &objects, &mut os, &mut ls);
        assert_eq!(ls.len(), 1);
    }

    #[test]
    fn person_object_links_are_those_of_pnpoly_on_every_space() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(19);
        // A 24-gon and a triangle: still people scattered over and around them, some exactly at
        // a vertex's height (the extent test's edge cases).
        let ring: Vec<Vec2> = (0..24)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 24.0;
                Vec2::new(2.0 + 1.5 * a.cos(), 1.0 + 1.5 * a.sin())
            })
            .collect();
        let tri = vec![Vec2::new(-3.0, -1.0), Vec2::new(-1.0, -1.0), Vec2::new(-2.0, 2.0)];
        let ys: Vec<f64> = ring.iter().chain(&tri).map(|p| p.y).collect();
        let objects = [
            InteractionObject { polygon: ring, centre: Vec2::new(2.0, 1.0) },
            InteractionObject { polygon: tri, centre: Vec2::new(-2.0, 0.0) },
        ];
        let pos: Vec<Vec2> = (0..2000)
            .map(|i| {
                let x = rng.random_range(-4.0..4.0);
                let y = if i % 4 == 0 { ys[i % ys.len()] } else { rng.random_range(-3.0..3.0) };
                Vec2::new(x, y)
            })
            .collect();
        let vel = vec![Vec2::zeros(); pos.len()];
        let (mut os, mut ls) = (Vec::new(), Vec::new());
        interactions(&pos, &vel, &vec![None; pos.len()], &objects, &mut os, &mut ls);
        let want: Vec<(Vec2, Vec2)> = pos
            .iter()
            .flat_map(|&q| {
                objects
                    .iter()
                    .filter(move |o| contains_point_polygon_pnpoly(q, &o.polygon))
                    .map(move |o| (q, o.centre))
            })
            .collect();
        assert!(want.len() > 100, "people inside the spaces: {}", want.len());
        assert_eq!(ls.iter().map(|l| (l.a, l.b)).collect::<Vec<_>>(), want);
    }

    #[test]
    fn a_group_has_an_o_space_only_while_it_stands_gathered() {
        // Group 3: two members standing 1.2 m apart, a third still far away (waiting at home).
        let pos = [Vec2::new(0.0, 0.0), Vec2::new(1.2, 0.0), Vec2::new(12.0, 0.0)];
        let still = [Vec2::zeros(); 3];
        let groups = [Some(3), Some(3), Some(3)];
        let (mut os, mut ls) = (Vec::new(), Vec::new());
        interactions(&pos, &still, &groups, &[], &mut os, &mut ls);
        // The far member is left out: the o-space is the pair's, not a 6 m circle over the floor.
        assert_eq!(os, vec![OSpace { centre: Vec2::new(0.6, 0.0), radius: 0.6 }]);
        assert_eq!(ls.len(), 1);
        // Members spread over the floor (waiting for their conversation): no o-space.
        let spread = [Vec2::new(0.0, 0.0), Vec2::new(7.0, 0.0), Vec2::new(14.0, 0.0)];
        interactions(&spread, &still, &groups, &[], &mut os, &mut ls);
        assert!(os.is_empty() && ls.is_empty());
        // Walking together (a tour on the move): no o-space either.
        let walking = [Vec2::new(0.8, 0.0); 3];
        interactions(&pos, &walking, &groups, &[], &mut os, &mut ls);
        assert!(os.is_empty() && ls.is_empty());
    }
}
