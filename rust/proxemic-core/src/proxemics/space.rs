//! Personal-space functions: Gaussians centred on a person, rotated with their facing direction.
//!
//! A note on names: the papers call the parameters "variances" but use them as the standard
//! deviation `sigma` of `exp(-d^2 / (2 sigma^2))`; here every parameter is that `sigma`, in metres.
//! Along any ray from the person's centre each function has the form `exp(-r^2 q)` with `q`
//! depending only on the ray's direction, which is what [`PersonalSpace::extent`] inverts.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use super::Pose;
use crate::error::{CoreError, Result};
use crate::math::{Vec2, wrap_angle};

/// Sousa et al. 2022 (eq. 5-8): a fully asymmetric Gaussian with one `sigma` (metres) per side of
/// the person, rotated with them. Valid values are finite and > 0 ([`Asymmetric::validate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Asymmetric {
    /// Along the facing direction, in front of the person (metres; the paper's sigma_f).
    pub front: f64,
    /// Along the facing direction, behind the person (metres; sigma_r).
    pub rear: f64,
    /// Across, on the person's right (metres; sigma_ri).
    pub right: f64,
    /// Across, on the person's left (metres; sigma_l).
    pub left: f64,
}

impl Asymmetric {
    /// Base shape for Sousa et al. 2022: 1 m on every side. The paper gives no numeric base
    /// sigmas; Figure 13a (equal influences on all sides give concentric circles) implies a
    /// circular base, and 1 m is our choice of size. The features then reshape it
    /// ([`super::adapt`]).
    pub const SOUSA2022: Asymmetric = Asymmetric { front: 1.0, rear: 1.0, right: 1.0, left: 1.0 };

    /// Builds a validated asymmetric Gaussian from its four sigmas (metres).
    pub fn new(front: f64, rear: f64, right: f64, left: f64) -> Result<Self> {
        let a = Asymmetric { front, rear, right, left };
        a.validate()?;
        Ok(a)
    }

    /// Kirby's Gaussian as a special case: front `sigma_h`, rear `sigma_r`, both sides `sigma_s`.
    pub const fn from_kirby(sigma_h: f64, sigma_r: f64, sigma_s: f64) -> Self {
        Asymmetric { front: sigma_h, rear: sigma_r, right: sigma_s, left: sigma_s }
    }

    /// Checks each sigma is finite and > 0; the error names the side (`front`, `rear`, `right`,
    /// `left`).
    pub fn validate(&self) -> Result<()> {
        check_sigmas(&[
            ("front", self.front),
            ("rear", self.rear),
            ("right", self.right),
            ("left", self.left),
        ])
    }

    /// The exponent `q` with value `exp(-q)`, from Sousa et al. 2022 eq. 5, 7 and 8.
    fn exponent(&self, person: Pose, point: Vec2) -> f64 {
        let dx = point.x - person.x;
        let dy = point.y - person.y;
        let (s, c) = person.theta.sin_cos();
        // Sousa 2022 eq. 5: distances along the sagittal (facing) and frontal (lateral) axes.
        // d_fro is positive on the person's right.
        let d_sag = c * dx + s * dy;
        let d_fro = s * dx - c * dy;
        // Sousa 2022 eq. 7: alpha = atan2(y - y_c, x - x_c) - theta + pi/2. The paper does not say
        // so, but eq. 8 only covers [-pi, pi), so alpha is wrapped into [-pi, pi) first. With that,
        // alpha = pi/2 is straight ahead (the facing direction), 0 is the person's right, -pi/2
        // straight behind, and -pi (= pi) the left: eq. 8's "front" sigma governs exactly the half
        // plane in front of the person (d_sag > 0).
        let alpha = wrap_half_open(dy.atan2(dx) - person.theta + FRAC_PI_2);
        // Sousa 2022 eq. 8, case by case as written.
        let (sigma, sigma_s) = if (0.0..FRAC_PI_2).contains(&alpha) {
            (self.front, self.right)
        } else if (FRAC_PI_2..PI).contains(&alpha) {
            (self.front, self.left)
        } else if (-FRAC_PI_2..0.0).contains(&alpha) {
            (self.rear, self.right)
        } else {
            // -pi <= alpha < -pi/2 (and NaN, whose value is NaN anyway).
            (self.rear, self.left)
        };
        d_sag * d_sag / (2.0 * sigma * sigma) + d_fro * d_fro / (2.0 * sigma_s * sigma_s)
    }
}

/// A person's personal-space function: value 1 at their centre, falling towards 0 with distance.
///
/// All parameters are standard deviations in metres, finite and > 0 ([`PersonalSpace::validate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PersonalSpace {
    /// Daza et al. 2021 §5.1: the symmetric (circular) Gaussian, i.e. Sousa 2022 eq. 4 with
    /// `sigma_x = sigma_y = sigma`; orientation plays no part.
    Symmetric {
        /// Standard deviation in every direction (metres).
        sigma: f64,
    },
    /// Kirby's asymmetric Gaussian as used by Calderita et al. (eq. 1-4): `sigma_h` in front of the
    /// person, `sigma_r` behind, `sigma_s` to both sides.
    Kirby {
        /// Along the heading, in front (metres).
        sigma_h: f64,
        /// Along the heading, behind (metres).
        sigma_r: f64,
        /// To the sides (metres).
        sigma_s: f64,
    },
    /// Sousa et al. 2022 eq. 5-8: one sigma per side (front, rear, right, left).
    Asymmetric(Asymmetric),
}

impl PersonalSpace {
    /// Daza et al. 2021 §5.1: a symmetric Gaussian. The paper draws the zones as level curves of a
    /// symmetric Gaussian but gives no sigma; 1 m is our choice (value 0.88 at the intimate radius
    /// 0.5 m, 0.61 at the personal radius 1 m).
    pub const DAZA2021: PersonalSpace = PersonalSpace::Symmetric { sigma: 1.0 };

    /// Calderita et al. §4.1: Kirby's Gaussian with the fixed values sigma_h = 2, sigma_r = 1,
    /// sigma_s = 4/3 (metres). Calderita fixes these regardless of speed; they are Kirby's
    /// speed-dependent values at 1 m/s (see [`PersonalSpace::kirby_for_speed`]).
    pub const CALDERITA: PersonalSpace =
        PersonalSpace::Kirby { sigma_h: 2.0, sigma_r: 1.0, sigma_s: 4.0 / 3.0 };

    /// Sousa et al. 2022: the fully asymmetric Gaussian with [`Asymmetric::SOUSA2022`].
    pub const SOUSA2022: PersonalSpace = PersonalSpace::Asymmetric(Asymmetric::SOUSA2022);

    /// A validated symmetric Gaussian (sigma in metres).
    pub fn symmetric(sigma: f64) -> Result<Self> {
        let p = PersonalSpace::Symmetric { sigma };
        p.validate()?;
        Ok(p)
    }

    /// A validated Kirby Gaussian (sigmas in metres).
    pub fn kirby(sigma_h: f64, sigma_r: f64, sigma_s: f64) -> Result<Self> {
        let p = PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s };
        p.validate()?;
        Ok(p)
    }

    /// Kirby's speed-dependent parameters (R. Kirby, PhD thesis, CMU 2010): sigma_h =
    /// max(2 v, 0.5), sigma_s = 2/3 sigma_h, sigma_r = 1/2 sigma_h, for a walking speed `v` (m/s;
    /// its magnitude is used; a non-finite speed counts as 0). At v = 1 m/s this is
    /// [`PersonalSpace::CALDERITA`].
    pub fn kirby_for_speed(v: f64) -> Self {
        let v = if v.is_finite() { v.abs() } else { 0.0 };
        let sigma_h = (2.0 * v).max(0.5);
        PersonalSpace::Kirby { sigma_h, sigma_r: 0.5 * sigma_h, sigma_s: sigma_h * 2.0 / 3.0 }
    }

    /// Checks every sigma is finite and > 0; the error names the parameter (`sigma`, `sigma_h`,
    /// `sigma_r`, `sigma_s`, `front`, `rear`, `right`, `left`).
    pub fn validate(&self) -> Result<()> {
        match *self {
            PersonalSpace::Symmetric { sigma } => check_sigmas(&[("sigma", sigma)]),
            PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s } => {
                check_sigmas(&[("sigma_h", sigma_h), ("sigma_r", sigma_r), ("sigma_s", sigma_s)])
            }
            PersonalSpace::Asymmetric(a) => a.validate(),
        }
    }

    /// The exponent `q >= 0` of `value = exp(-q)`.
    fn exponent(&self, person: Pose, point: Vec2) -> f64 {
        match *self {
            PersonalSpace::Symmetric { sigma } => {
                // Daza 2021 §5.1 / Sousa 2022 eq. 4 with sigma_x = sigma_y.
                let d2 = (point.x - person.x).powi(2) + (point.y - person.y).powi(2);
                d2 / (2.0 * sigma * sigma)
            }
            PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s } => {
                let dx = point.x - person.x;
                let dy = point.y - person.y;
                let theta = person.theta;
                // Kirby's front/rear choice (Kirby's thesis; `docs/algorithms.md` §2): alpha = atan2(dy, dx) -
                // theta + pi/2 wrapped into (-pi, pi]; the rear sigma for alpha <= 0, else the front.
                let alpha = wrap_angle(dy.atan2(dx) - theta + FRAC_PI_2);
                let sigma = if alpha <= 0.0 { sigma_r } else { sigma_h };
                // Calderita eq. 2-4.
                let (s, c) = theta.sin_cos();
                let s2 = (2.0 * theta).sin();
                let g1 = c * c / (2.0 * sigma * sigma) + s * s / (2.0 * sigma_s * sigma_s);
                let g2 = s2 / (4.0 * sigma * sigma) - s2 / (4.0 * sigma_s * sigma_s);
                let g3 = s * s / (2.0 * sigma * sigma) + c * c / (2.0 * sigma_s * sigma_s);
                // Calderita eq. 1 prints the cross term as gamma_2 (x - x_i)(y - y_i); Kirby's
                // original (and Sousa 2022 eq. 6, with the same coefficient) has 2 gamma_2, which is
                // what makes the function a rotated Gaussian. We use 2 gamma_2.
                g1 * dx * dx + 2.0 * g2 * dx * dy + g3 * dy * dy
            }
            PersonalSpace::Asymmetric(a) => a.exponent(person, point),
        }
    }

    /// The personal-space value at `point` (metres, world frame) for a person at `person`: in
    /// [0, 1], exactly 1 at the person's centre. Deterministic and panic-free; if any input or
    /// parameter is NaN (or the result is otherwise undefined) the value is 0 (no personal space),
    /// so validate poses and parameters upstream.
    pub fn value(&self, person: Pose, point: Vec2) -> f64 {
        let v = (-self.exponent(person, point)).exp();
        if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }
    }

    /// The distance (metres) from the person's centre along a ray at `bearing` (radians,
    /// counter-clockwise from the person's facing direction: 0 straight ahead, pi/2 to their
    /// left) at which the value falls to `level`. Level 1 gives 0; level in (0, 1) a finite
    /// distance. Errors: `level` not in (0, 1] or NaN, `bearing` not finite.
    pub fn extent(&self, bearing: f64, level: f64) -> Result<f64> {
        if !bearing.is_finite() {
            return Err(CoreError::input("bearing", "a finite angle in radians", format!("{bearing}")));
        }
        if !(level > 0.0 && level <= 1.0) {
            return Err(CoreError::input("level", "a value in (0, 1]", format!("{level}")));
        }
        // exp(-r^2 q) = level  <=>  r = sqrt(-ln(level) / q), with q the exponent at unit distance.
        let (s, c) = bearing.sin_cos();
        let q = self.exponent(Pose::new(0.0, 0.0, 0.0), Vec2::new(c, s));
        let need = -level.ln();
        if need <= 0.0 {
            return Ok(0.0);
        }
        let r = (need / q).sqrt();
        if r.is_nan() {
            // Only with invalid parameters (NaN or zero sigma); report the distance as unbounded
            // rather than NaN.
            return Ok(f64::INFINITY);
        }
        Ok(r)
    }

    /// [`PersonalSpace::extent`] along the ray from the person towards `point` (the robot, say):
    /// the distance from the person at which the value falls to `level` in that direction. A
    /// point at the person's centre uses the facing direction. Errors: as for `extent`, and a
    /// non-finite pose or point (field `person` or `point`).
    pub fn extent_toward(&self, person: Pose, point: Vec2, level: f64) -> Result<f64> {
        person.validate("person")?;
        if !(point.x.is_finite() && point.y.is_finite()) {
            return Err(CoreError::input(
                "point",
                "finite coordinates",
                format!("({}, {})", point.x, point.y),
            ));
        }
        let bearing = (point.y - person.y).atan2(point.x - person.x) - person.theta;
        self.extent(bearing, level)
    }
}

impl PersonalSpace {
    /// The largest extent over all directions (metres) at which the value falls to `level`:
    /// `sigma_max * sqrt(2 ln(1 / level))`, with `sigma_max` the largest parameter. Outside this
    /// radius the value is below `level` everywhere, so a cost map can limit the cells it visits
    /// to it. Errors: `level` not in (0, 1] or NaN.
    pub fn max_extent(&self, level: f64) -> Result<f64> {
        if !(level > 0.0 && level <= 1.0) {
            return Err(CoreError::input("level", "a value in (0, 1]", format!("{level}")));
        }
        let sigma_max = match *self {
            PersonalSpace::Symmetric { sigma } => sigma,
            PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s } => sigma_h.max(sigma_r).max(sigma_s),
            PersonalSpace::Asymmetric(a) => a.front.max(a.rear).max(a.right).max(a.left),
        };
        Ok(sigma_max * (-2.0 * level.ln()).max(0.0).sqrt())
    }

    /// The function placed at one person's pose, with the trigonometry and the per-side
    /// coefficients computed once: [`Placed::value`] equals [`PersonalSpace::value`] (to rounding)
    /// and is several times cheaper, for filling many cells around one person.
    pub fn at(&self, person: Pose) -> Placed {
        let k = |sigma: f64| 1.0 / (2.0 * sigma * sigma);
        let (front, rear, right, left) = match *self {
            PersonalSpace::Symmetric { sigma } => (k(sigma), k(sigma), k(sigma), k(sigma)),
            PersonalSpace::Kirby { sigma_h, sigma_r, sigma_s } => {
                (k(sigma_h), k(sigma_r), k(sigma_s), k(sigma_s))
            }
            PersonalSpace::Asymmetric(a) => (k(a.front), k(a.rear), k(a.right), k(a.left)),
        };
        let (sin, cos) = person.theta.sin_cos();
        Placed { x: person.x, y: person.y, cos, sin, front, rear, right, left }
    }
}

/// A [`PersonalSpace`] placed at a person's pose (see [`PersonalSpace::at`]).
///
/// It evaluates Sousa 2022 eq. 5 with the quadrant of eq. 8 taken from the signs of the two axis
/// distances instead of the angle of eq. 7: `alpha` in [0, pi) (eq. 8's front cases) is exactly
/// the half plane `d_sag >= 0` and `alpha` in [-pi/2, pi/2) (its right cases) the half plane
/// `d_fro >= 0`, up to the boundary lines, where the term whose sigma would differ is zero. Kirby's
/// function is the case left = right; the symmetric one has all four equal. The tests check that
/// the values agree with [`PersonalSpace::value`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placed {
    x: f64,
    y: f64,
    cos: f64,
    sin: f64,
    /// 1 / (2 sigma^2) per side (1/m^2).
    front: f64,
    rear: f64,
    right: f64,
    left: f64,
}

impl Placed {
    /// The coefficients `(x, y, cos, sin, front, rear, right, left)`: the centre, the facing
    /// direction, and `1 / (2 sigma^2)` per side, so that `q = k_s d_sag^2 + k_f d_fro^2` with
    /// `d_sag = cos dx + sin dy`, `d_fro = sin dx - cos dy` (Sousa 2022 eq. 5).
    pub fn coefficients(&self) -> [f64; 8] {
        [self.x, self.y, self.cos, self.sin, self.front, self.rear, self.right, self.left]
    }

    /// The exponent `q >= 0` with `value = exp(-q)` at `point` (NaN for NaN inputs).
    #[inline]
    pub fn exponent(&self, point: Vec2) -> f64 {
        let (d_sag, d_fro) = self.axes(Vec2::new(point.x - self.x, point.y - self.y));
        let (ks, kf) = self.side_coefficients(d_sag, d_fro);
        ks * d_sag * d_sag + kf * d_fro * d_fro
    }

    /// `(d_sag, d_fro)` of the offset `d` (m) from the centre: its components along the facing
    /// direction and to the person's right (Sousa 2022 eq. 5). Linear in `d`.
    #[inline]
    pub fn axes(&self, d: Vec2) -> (f64, f64) {
        (self.cos * d.x + self.sin * d.y, self.sin * d.x - self.cos * d.y)
    }

    /// `(k_s, k_f)`, the `1 / (2 sigma^2)` (1/m^2) of the sides whose half planes hold the axis
    /// offsets `(d_sag, d_fro)`: Sousa 2022 eq. 8 by half planes (see the type's docs).
    #[inline]
    pub fn side_coefficients(&self, d_sag: f64, d_fro: f64) -> (f64, f64) {
        (if d_sag >= 0.0 { self.front } else { self.rear }, if d_fro >= 0.0 { self.right } else { self.left })
    }

    /// The zone distance (m) of `point` for the zone scale `zone_scale` (m): see [`zone_distance`].
    #[inline]
    pub fn zone_distance(&self, point: Vec2, zone_scale: f64) -> f64 {
        zone_distance(self.exponent(point), zone_scale)
    }

    /// The value at `point` (metres, world frame), in [0, 1]; 0 where undefined (NaN inputs).
    #[inline]
    pub fn value(&self, point: Vec2) -> f64 {
        self.value_of_exponent(self.exponent(point))
    }

    /// The value for the exponent `q` of [`Placed::exponent`]: `exp(-q)` at most 1, 0 for NaN.
    #[inline]
    pub fn value_of_exponent(&self, q: f64) -> f64 {
        let v = (-q).exp();
        if v.is_nan() { 0.0 } else { v.min(1.0) }
    }
}

impl Default for PersonalSpace {
    /// [`PersonalSpace::CALDERITA`].
    fn default() -> Self {
        PersonalSpace::CALDERITA
    }
}

impl From<Asymmetric> for PersonalSpace {
    fn from(a: Asymmetric) -> Self {
        PersonalSpace::Asymmetric(a)
    }
}

/// The *zone distance* (m) of a point whose personal-space exponent is `q` (value `exp(-q)`):
/// `zone_scale * sqrt(2 q)`, the distance that Hall's zone radii are compared with. For a
/// symmetric Gaussian of standard deviation `zone_scale` it is the Euclidean distance to the
/// centre; an asymmetric function stretches it where it is wider (Sousa et al. 2022 eq. 5: with
/// 1 m sigmas, `sqrt((d_sag / sigma_s)^2 + (d_fro / sigma_f)^2)` times the base sigma). The one
/// definition: the social map's zones ([`crate::social_cost_map::SpaceFunction::zone_distance`]),
/// Social Momentum's Gaussian agents and the binding's `zone_distances` use it.
#[inline]
pub fn zone_distance(q: f64, zone_scale: f64) -> f64 {
    zone_scale * (2.0 * q).max(0.0).sqrt()
}

/// The zone distances (m, [`zone_distance`]) of `points` (m, world frame) in the fully asymmetric
/// Gaussian (Sousa 2022 eq. 5-8) of an individual centred at `centre` (m) facing `heading` (rad),
/// with per-side sigmas `sides` (m) and zone scale `zone_scale` (m; the base function's, e.g.
/// 1 m for the `sousa2022` space): one value per point. Errors with [`CoreError::Input`] naming
/// `centre`, `heading`, the side, `zone_scale` or `points[k]` for a value that is not finite
/// (or, for the sigmas and the scale, not > 0).
pub fn zone_distances(
    centre: Vec2,
    heading: f64,
    sides: Asymmetric,
    zone_scale: f64,
    points: &[Vec2],
) -> Result<Vec<f64>> {
    if !(centre.x.is_finite() && centre.y.is_finite()) {
        return Err(CoreError::input("centre", "a point of finite numbers (m)", format!("{centre:?}")));
    }
    if !heading.is_finite() {
        return Err(CoreError::input("heading", "a finite angle (rad)", heading.to_string()));
    }
    sides.validate()?;
    if !(zone_scale.is_finite() && zone_scale > 0.0) {
        return Err(CoreError::input("zone_scale", "a finite length > 0 (m)", zone_scale.to_string()));
    }
    if let Some((k, p)) = points.iter().enumerate().find(|(_, p)| !(p.x.is_finite() && p.y.is_finite())) {
        return Err(CoreError::input(
            format!("points[{k}]"),
            "a point of finite numbers (m)",
            format!("{p:?}"),
        ));
    }
    let placed = PersonalSpace::Asymmetric(sides).at(Pose::new(centre.x, centre.y, heading));
    Ok(points.iter().map(|&p| placed.zone_distance(p, zone_scale)).collect())
}

/// Wraps an angle into [-pi, pi), the range of Sousa 2022 eq. 8.
fn wrap_half_open(a: f64) -> f64 {
    let mut r = (a + PI).rem_euclid(TAU) - PI;
    if r >= PI {
        r -= TAU;
    }
    r
}

fn check_sigmas(fields: &[(&str, f64)]) -> Result<()> {
    for &(name, v) in fields {
        if !(v.is_finite() && v > 0.0) {
            return Err(CoreError::input(name, "a finite standard deviation > 0 m", format!("{v}")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
