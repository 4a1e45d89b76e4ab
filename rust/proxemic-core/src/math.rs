//! Scalar and vector types, angle helpers, and the one conversion seam to parry2d.
//!
//! Every computation in the core is `f64`. Vectors are nalgebra's [`Vector2`]; parry2d (0.31, built on
//! glam) is used for geometric queries only, and all conversions between the two go through
//! [`to_parry`] and [`from_parry`] so that no other module names glam types.

use nalgebra::Vector2;

/// The scalar type of the core (metres, seconds, radians).
pub type Real = f64;

/// A 2D vector in the world frame unless stated otherwise (metres, or metres per second).
pub type Vec2 = Vector2<Real>;

/// Small length used to guard divisions and degenerate geometry (metres).
pub const EPS: Real = 1e-9;

/// Wraps an angle to (-pi, pi].
#[inline]
pub fn wrap_angle(a: Real) -> Real {
    let two_pi = std::f64::consts::TAU;
    let mut r = a.rem_euclid(two_pi);
    if r > std::f64::consts::PI {
        r -= two_pi;
    }
    r
}

/// Rotates a vector by `theta` radians counter-clockwise.
#[inline]
pub fn rotate(v: Vec2, theta: Real) -> Vec2 {
    let (s, c) = theta.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Converts a core vector to parry2d's vector type (the only place glam enters the core).
#[inline]
pub fn to_parry(v: Vec2) -> parry2d_f64::math::Vec2 {
    parry2d_f64::math::Vec2::new(v.x, v.y)
}

/// Converts parry2d's vector type back to a core vector.
#[inline]
pub fn from_parry(v: parry2d_f64::math::Vec2) -> Vec2 {
    Vec2::new(v.x, v.y)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_angle_maps_into_half_open_interval() {
        let pi = std::f64::consts::PI;
        assert!((wrap_angle(3.0 * pi) - pi).abs() < 1e-12);
        assert!((wrap_angle(-pi) - pi).abs() < 1e-12);
        assert!((wrap_angle(0.5) - 0.5).abs() < 1e-15);
        assert!((wrap_angle(-0.5 - 4.0 * pi) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn rotate_quarter_turn() {
        let v = rotate(Vec2::new(1.0, 0.0), std::f64::consts::FRAC_PI_2);
        assert!(v.x.abs() < 1e-12 && (v.y - 1.0).abs() < 1e-12);
    }

    #[test]
    fn parry_seam_round_trips() {
        let v = Vec2::new(1.25, -3.5);
        assert_eq!(from_parry(to_parry(v)), v);
    }
}
