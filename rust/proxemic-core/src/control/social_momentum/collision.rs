//! Step 2 of Social Momentum, the collision filter: the wall edges within reach, the people that
//! could be met within the horizon, and whether a sample held over the horizon comes too close to
//! either.

use super::{GaussianSpace, Scene};
use crate::geom::{cross, distance_point_segment};
use crate::map::StaticGeometry;
use crate::math::Vec2;

/// A wall edge `(a, b)` the robot could reach within the horizon, with its distance now (m).
pub(super) type Edge = (Vec2, Vec2, f64);

/// The static edges within `range` (m) of `pos`; `None` when `pos` is inside a polygon.
pub(super) fn nearby_edges(pos: Vec2, geom: Option<&StaticGeometry>, range: f64) -> Option<Vec<Edge>> {
    let mut edges: Vec<Edge> = Vec::new();
    if let Some(g) = geom {
        if g.contains(pos) {
            return None;
        }
        for (poly, bb) in g.polygons().iter().zip(g.polygon_bounds()) {
            let dx = (bb.min.x - pos.x).max(pos.x - bb.max.x).max(0.0);
            let dy = (bb.min.y - pos.y).max(pos.y - bb.max.y).max(0.0);
            if dx * dx + dy * dy > range * range {
                continue;
            }
            let n = poly.len();
            for k in 0..n {
                let (a, b) = (poly[k], poly[(k + 1) % n]);
                let d = distance_point_segment(pos, a, b);
                if d <= range {
                    edges.push((a, b, d));
                }
            }
        }
    }
    Some(edges)
}

/// A person the robot could meet within the collision horizon.
pub(super) struct Near {
    pub(super) pos: Vec2,
    pub(super) vel: Vec2,
    /// Squared keep-out bound `(radius + r_i + safety_margin)²` (m²).
    pub(super) bound2: f64,
    /// A Gaussian keep-out region and its exponent level (safety margin included).
    pub(super) gaussian: Option<(GaussianSpace, f64)>,
    /// How far the Gaussian's keep-out region reaches from the centre (m, its
    /// [`GaussianSpace::reach`] grown by a margin far above rounding; 0 for a disc).
    pub(super) gaussian_reach: f64,
}

impl Near {
    /// Whether the robot at offset `d0` from the agent is inside its keep-out region now.
    pub(super) fn contains(&self, d0: Vec2) -> bool {
        d0.norm_squared() < self.bound2 || self.gaussian.is_some_and(|(g, level)| g.exponent(d0) < level)
    }

    /// Whether holding the relative velocity `dv` over `horizon` brings the robot at offset `d0`
    /// into the keep-out region (the minimum over the horizon lies after `t = 0` and inside).
    pub(super) fn brought_inside(&self, d0: Vec2, dv: Vec2, horizon: f64) -> bool {
        let dd = dv.norm_squared();
        let t = if dd > 0.0 { (-d0.dot(&dv) / dd).clamp(0.0, horizon) } else { 0.0 };
        // The smallest squared centre distance over the horizon.
        let closest2 = (d0 + dv * t).norm_squared();
        (t > 0.0 && closest2 < self.bound2)
            || self.gaussian.is_some_and(|(g, level)| {
                // Farther than the region's reach all along the horizon (the closest approach,
                // less a slack far above its rounding, clears the reach): the exact minimum
                // cannot fall below the level, no need to look for it.
                let slack = 1e-9 * (d0.norm_squared() + dd * horizon * horizon);
                if closest2 - slack > self.gaussian_reach * self.gaussian_reach {
                    return false;
                }
                let (q, t) = g.min_along(d0, dv, horizon);
                t > 0.0 && q < level
            })
    }

    /// The gap (m) the robot at `p` leaves to the agent's centre after `tau` seconds: the
    /// centre distance for a disc, the zone distance for a Gaussian.
    pub(super) fn gap(&self, p: Vec2, tau: f64) -> f64 {
        let d = p - self.pos - self.vel * tau;
        match self.gaussian {
            None => d.norm(),
            Some((g, _)) => g.zone_distance(d),
        }
    }
}

/// Step 2 of [`social_momentum`]: `true` if holding `v` over the horizon brings the robot inside a
/// person's keep-out bound or within `wall_bound` of a wall edge (closer than it is now).
pub(super) fn collides(scene: &Scene, v: Vec2, horizon: f64) -> bool {
    let pos = scene.pos;
    let hits_person = scene.near.iter().any(|a| a.brought_inside(pos - a.pos, v - a.vel, horizon));
    if hits_person {
        return true;
    }
    if scene.edges.is_empty() {
        return false;
    }
    let end = pos + v * horizon;
    // An edge farther than the swept length plus the bound cannot come within the bound.
    let sweep = v.norm() * horizon * (1.0 + 1e-9) + 1e-9;
    scene.edges.iter().any(|&(a, b, d_now)| {
        if d_now - sweep >= scene.wall_bound {
            return false;
        }
        let d = segment_segment_distance(pos, end, a, b);
        d < scene.wall_bound && d < d_now
    })
}

/// Minimum distance (m) between the segments `pq` and `ab` (0 if they cross).
pub(super) fn segment_segment_distance(p: Vec2, q: Vec2, a: Vec2, b: Vec2) -> f64 {
    let d1 = cross(q - p, a - p);
    let d2 = cross(q - p, b - p);
    let d3 = cross(b - a, p - a);
    let d4 = cross(b - a, q - a);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return 0.0;
    }
    distance_point_segment(p, a, b)
        .min(distance_point_segment(q, a, b))
        .min(distance_point_segment(a, p, q))
        .min(distance_point_segment(b, p, q))
}
