//! Proxemics: Hall's zones, personal-space functions and socialization features.
//!
//! - [`HallZones`] and [`Zone`]: Hall's intimate / personal / social / public distances, with the
//!   radii of Daza et al. 2021 §2 and the common evaluation radii as presets.
//! - [`PersonalSpace`]: a person's personal-space function, a value in [0, 1] that is 1 at the
//!   person's centre and falls off with distance:
//!   - the symmetric Gaussian of Daza et al. 2021 §5.1,
//!   - Kirby's asymmetric Gaussian as used by Calderita et al. (eq. 1-4),
//!   - the fully asymmetric Gaussian of Sousa et al. 2022 (eq. 5-8), [`Asymmetric`].
//!
//!   [`PersonalSpace::extent`] / [`PersonalSpace::extent_toward`] give the distance at which the
//!   value falls to a level in a direction (the edge of someone's personal space),
//!   [`PersonalSpace::max_extent`] the radius beyond which it is below that level everywhere, and
//!   [`PersonalSpace::at`] a [`Placed`] evaluator for filling many cells around one person.
//! - [`features`]: Sousa et al. 2022 §3.3.1 and §3.3.3, socialization features (FV) and influence
//!   vectors (IV) reshaping the four sides of an [`Asymmetric`] Gaussian, and the "emotional
//!   state" feature of Table 1.
//!
//! Conventions: positions in metres in the world frame, angles in radians measured
//! counter-clockwise from the world x axis; a person's `theta` is the direction they face. "Left"
//! and "right" are the person's own left and right (left = `theta + pi/2`). All functions are
//! deterministic `f64` and never panic; bad parameters are reported by the constructors and
//! `validate` methods as [`CoreError::Input`] naming the field.

pub mod density_zones;
pub mod features;
mod space;

pub use density_zones::DensityZones;
pub use features::{
    EMOTIONAL_STATES, InfluenceValues, MAX_VARIANCE_SCALE, SideInfluences, adapt, emotional_state_value,
    influence_values, variance_scale,
};
pub use space::{Asymmetric, PersonalSpace, Placed, zone_distance, zone_distances};

use crate::error::{CoreError, Result};
use crate::math::Vec2;

/// A person's pose: position (metres, world frame) and facing direction `theta` (radians,
/// counter-clockwise from the world x axis, any real value; it is used through sin/cos and wrapped
/// where an angle comparison is needed).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Pose {
    /// x position (metres).
    pub x: f64,
    /// y position (metres).
    pub y: f64,
    /// Facing direction (radians).
    pub theta: f64,
}

impl Pose {
    /// Builds a pose from its position (metres) and facing direction (radians).
    pub const fn new(x: f64, y: f64, theta: f64) -> Self {
        Pose { x, y, theta }
    }

    /// The position as a vector (metres).
    pub fn position(&self) -> Vec2 {
        Vec2::new(self.x, self.y)
    }

    /// Checks that every component is finite; the error names `field` with the component, e.g.
    /// `people[3].theta`.
    pub fn validate(&self, field: &str) -> Result<()> {
        for (name, v) in [("x", self.x), ("y", self.y), ("theta", self.theta)] {
            if !v.is_finite() {
                return Err(CoreError::input(format!("{field}.{name}"), "a finite number", format!("{v}")));
            }
        }
        Ok(())
    }
}

/// One of Hall's four proxemic zones.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Zone {
    /// Closer than [`HallZones::intimate`].
    Intimate,
    /// From [`HallZones::intimate`] (inclusive) to [`HallZones::personal`] (exclusive).
    Personal,
    /// From [`HallZones::personal`] (inclusive) to [`HallZones::social`] (exclusive).
    Social,
    /// At [`HallZones::social`] or beyond.
    Public,
}

/// Hall's zone radii (metres): a distance `d` from a person is intimate if `d < intimate`,
/// personal if `intimate <= d < personal`, social if `personal <= d < social`, public beyond.
///
/// Valid radii are finite with `0 < intimate < personal < social` (see [`HallZones::validate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HallZones {
    /// Outer radius of the intimate zone (metres).
    pub intimate: f64,
    /// Outer radius of the personal zone (metres).
    pub personal: f64,
    /// Outer radius of the social zone (metres); the public zone lies beyond.
    pub social: f64,
}

impl HallZones {
    /// Daza et al. 2021 §2 (after Hall): intimate 0-0.5 m, personal 0.5-1 m, social 1-4 m, public
    /// beyond 4 m.
    pub const DAZA2021: HallZones = HallZones { intimate: 0.5, personal: 1.0, social: 4.0 };

    /// The radii commonly used when evaluating social navigation: 0.45 / 1.2 / 3.6 m.
    pub const EVALUATION: HallZones = HallZones { intimate: 0.45, personal: 1.2, social: 3.6 };

    /// Builds validated zone radii (metres); see [`HallZones::validate`].
    pub fn new(intimate: f64, personal: f64, social: f64) -> Result<Self> {
        let z = HallZones { intimate, personal, social };
        z.validate()?;
        Ok(z)
    }

    /// Checks `0 < intimate < personal < social`, all finite; the error names the first offending
    /// field (`intimate`, `personal` or `social`).
    pub fn validate(&self) -> Result<()> {
        let fields = [("intimate", self.intimate), ("personal", self.personal), ("social", self.social)];
        for (name, v) in fields {
            if !v.is_finite() {
                return Err(CoreError::input(name, "a finite radius in metres", format!("{v}")));
            }
        }
        if self.intimate <= 0.0 {
            return Err(CoreError::input("intimate", "a radius > 0 m", format!("{}", self.intimate)));
        }
        if self.personal <= self.intimate {
            return Err(CoreError::input(
                "personal",
                format!("a radius > intimate ({} m)", self.intimate),
                format!("{}", self.personal),
            ));
        }
        if self.social <= self.personal {
            return Err(CoreError::input(
                "social",
                format!("a radius > personal ({} m)", self.personal),
                format!("{}", self.social),
            ));
        }
        Ok(())
    }

    /// The zone at distance `d` (metres). Boundaries belong to the outer zone (`d == intimate` is
    /// personal). A negative distance counts as intimate; NaN counts as public (no constraint).
    pub fn zone_of(&self, d: f64) -> Zone {
        if d < self.intimate {
            Zone::Intimate
        } else if d < self.personal {
            Zone::Personal
        } else if d < self.social {
            Zone::Social
        } else {
            Zone::Public
        }
    }
}

impl Default for HallZones {
    /// [`HallZones::DAZA2021`].
    fn default() -> Self {
        HallZones::DAZA2021
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hall_zone_presets_validate_and_classify() {
        for z in [HallZones::DAZA2021, HallZones::EVALUATION] {
            z.validate().expect("valid test input");
        }
        let z = HallZones::DAZA2021;
        assert_eq!(z.zone_of(0.0), Zone::Intimate);
        assert_eq!(z.zone_of(0.49), Zone::Intimate);
        assert_eq!(z.zone_of(0.5), Zone::Personal);
        assert_eq!(z.zone_of(0.99), Zone::Personal);
        assert_eq!(z.zone_of(1.0), Zone::Social);
        assert_eq!(z.zone_of(3.99), Zone::Social);
        assert_eq!(z.zone_of(4.0), Zone::Public);
        assert_eq!(z.zone_of(f64::INFINITY), Zone::Public);
        assert_eq!(z.zone_of(-1.0), Zone::Intimate);
        assert_eq!(z.zone_of(f64::NAN), Zone::Public);
        let e = HallZones::EVALUATION;
        assert_eq!(e.zone_of(0.46), Zone::Personal);
        assert_eq!(e.zone_of(1.1), Zone::Personal);
        assert_eq!(e.zone_of(3.7), Zone::Public);
    }

    #[test]
    fn hall_zones_reject_bad_radii_naming_the_field() {
        let field = |r: Result<HallZones>| match r {
            Err(CoreError::Input { field, .. }) => field,
            other => panic!("expected an input error, got {other:?}"),
        };
        assert_eq!(field(HallZones::new(0.0, 1.0, 4.0)), "intimate");
        assert_eq!(field(HallZones::new(-0.5, 1.0, 4.0)), "intimate");
        assert_eq!(field(HallZones::new(f64::NAN, 1.0, 4.0)), "intimate");
        assert_eq!(field(HallZones::new(0.5, 0.5, 4.0)), "personal");
        assert_eq!(field(HallZones::new(0.5, f64::INFINITY, 4.0)), "personal");
        assert_eq!(field(HallZones::new(0.5, 1.0, 0.9)), "social");
        assert_eq!(field(HallZones::new(0.5, 1.0, f64::NAN)), "social");
        assert!(HallZones::new(0.3, 0.8, 2.0).is_ok());
    }

    #[test]
    fn pose_validation_names_the_component() {
        assert!(Pose::new(1.0, 2.0, 3.0).validate("people[0]").is_ok());
        match Pose::new(1.0, f64::NAN, 0.0).validate("people[2]") {
            Err(CoreError::Input { field, .. }) => assert_eq!(field, "people[2].y"),
            other => panic!("{other:?}"),
        }
    }
}
