//! The social cost map's cost model: what it needs of an individual's personal-space model, the
//! zones' radii and factors, and the `u8` encoding of factors in the cost grid.

use crate::map::{INSCRIBED, LETHAL};
use crate::math::Vec2;

/// What the social map needs from an individual's personal-space model.
///
/// The personal-space value is `exp(-q(p))`. The *zone distance* of a point is
/// `zone_scale * sqrt(2 q(p))`: for a symmetric Gaussian of standard deviation `zone_scale` it is
/// the Euclidean distance; for asymmetric functions it stretches where the function is wider.
/// Zones are classified by comparing `q` with `r^2 / (2 zone_scale^2)`, without exp or sqrt.
pub trait SpaceFunction {
    /// The exponent `q(p) >= 0` of the personal-space value `exp(-q)` at `p`.
    fn exponent(&self, p: Vec2) -> f64;
    /// The length (metres) that turns `sqrt(2 q)` into a zone distance.
    fn zone_scale(&self) -> f64;
    /// The zone distance (metres) of `p` ([`crate::proxemics::zone_distance`]).
    fn zone_distance(&self, p: Vec2) -> f64 {
        crate::proxemics::zone_distance(self.exponent(p), self.zone_scale())
    }
    /// Axis-aligned box `[xmin, ymin, xmax, ymax]` (metres) outside which the individual adds no
    /// cost; bounds the cells it touches.
    fn bounds(&self) -> [f64; 4];
    /// A fingerprint of the individual's state; equal fingerprints mean identical contributions.
    fn fingerprint(&self) -> [f64; 8];
    /// The exponent as a quadrant-wise quadratic form, if it is one: `(x, y, cos, sin, front,
    /// rear, right, left)` with `q = k_s d_sag^2 + k_f d_fro^2` (see
    /// [`crate::proxemics::Placed::coefficients`]); lets the map sweep rows incrementally.
    fn quadratic(&self) -> Option<[f64; 8]> {
        None
    }
    /// Where the individual stands (metres), if known: its zones are then limited to the cells in
    /// sight of it (see `crate::map::sight::in_sight`). `None` (the default) lets them through walls.
    fn centre(&self) -> Option<Vec2> {
        None
    }
}

/// How people's costs are computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CostMode {
    /// Hall zones with discrete costs (Calderita §5.2.1).
    Zones,
    /// Cost `1 + gain * f(p)` with `f` the personal-space value; the intimate zone stays lethal.
    Continuous {
        /// Gain on the personal-space value; default 3.0 (so the centre costs 4.0, like the
        /// personal zone).
        gain: f64,
    },
}

/// Parameters of the social cost map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SocialCosts {
    /// Intimate radius (metres, centre to centre); forbidden. Default 0.45.
    pub intimate: f64,
    /// Personal radius (metres). Default 1.2.
    pub personal: f64,
    /// Social radius (metres). Default 3.6.
    pub social: f64,
    /// Factor inside the personal zone. Default 4.0 (Calderita).
    pub personal_cost: f64,
    /// Factor inside the social zone. Default 2.0 (Calderita).
    pub social_cost: f64,
    /// Factor in the public zone and free space. Default 1.0 (Calderita).
    pub public_cost: f64,
    /// Zones or continuous costs. Default zones.
    pub mode: CostMode,
    /// Largest representable factor (the A* weight is `max_factor - 1`). Default 5.0.
    pub max_factor: f64,
    /// Object interaction spaces are drawn this much wider on the map (m, `>= 0`), so a path
    /// planned along a space's edge keeps the robot's centre out of it. Default 0; the social
    /// planner sets the robot's radius.
    pub object_margin: f64,
}

impl Default for SocialCosts {
    fn default() -> Self {
        SocialCosts {
            intimate: 0.45,
            personal: 1.2,
            social: 3.6,
            personal_cost: 4.0,
            social_cost: 2.0,
            public_cost: 1.0,
            mode: CostMode::Zones,
            max_factor: 5.0,
            object_margin: 0.0,
        }
    }
}

impl SocialCosts {
    /// The A* weight that turns stored costs back into factors.
    pub fn weight(&self) -> f64 {
        self.max_factor - 1.0
    }

    /// Whether `p` lies inside the individual's personal zone (its zone distance below
    /// [`Self::personal`], the intimate zone included); false where the space function is
    /// undefined.
    pub fn in_personal_zone<S: SpaceFunction>(&self, s: &S, p: Vec2) -> bool {
        let q = s.exponent(p);
        let z = s.zone_scale();
        !q.is_nan() && 2.0 * z * z * q < self.personal * self.personal
    }

    /// Factor of a point for one individual (f64::INFINITY for the forbidden intimate zone).
    pub fn factor<S: SpaceFunction>(&self, s: &S, p: Vec2) -> f64 {
        let q = s.exponent(p);
        if q.is_nan() {
            return self.public_cost;
        }
        // zone distance d = z sqrt(2 q)  <=>  d^2 = 2 z^2 q
        let z = s.zone_scale();
        let d2 = 2.0 * z * z * q;
        if d2 < self.intimate * self.intimate {
            return f64::INFINITY;
        }
        match self.mode {
            CostMode::Zones => {
                if d2 < self.personal * self.personal {
                    self.personal_cost
                } else if d2 < self.social * self.social {
                    self.social_cost
                } else {
                    self.public_cost
                }
            }
            CostMode::Continuous { gain } => 1.0 + gain * (-q).exp(),
        }
    }

    /// Stored `u8` cost of a factor (`LETHAL` for infinity).
    pub fn encode(&self, factor: f64) -> u8 {
        if factor.is_infinite() || factor.is_nan() {
            return LETHAL;
        }
        if factor <= 1.0 {
            return 0;
        }
        let c = ((factor - 1.0) * (252.0 / (self.max_factor - 1.0))).round();
        c.min(252.0) as u8
    }
}

/// A cell's combined cost: its static cost where that is inscribed or lethal, else the code of
/// the larger of its people and object factors, at least its static cost. `last` holds the last
/// factor encoded and its code: neighbouring cells mostly share a factor, which is encoded once
/// per run.
#[inline]
pub(super) fn combined_cost(
    costs: &SocialCosts,
    fixed: u8,
    people: f64,
    objects: f64,
    last: &mut (u64, u8),
) -> u8 {
    if fixed >= INSCRIBED {
        fixed
    } else {
        let f = people.max(objects);
        if f.to_bits() != last.0 {
            *last = (f.to_bits(), costs.encode(f));
        }
        last.1.max(fixed)
    }
}
