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
mod tests {
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
}
