//! The social force model: its parameters, the interaction between two people (Moussaid et al.
//! 2009) and the walking-group terms (Moussaid et al. 2010). The driving and wall terms are summed
//! with these in [`Crowd`]'s substep.

use super::{Crowd, PASS_ON_RIGHT};
use crate::math::{Vec2, wrap_angle};

/// Parameters of the social force model (defaults from the sources named in the module doc; the
/// interaction's strength, range and angular widths calibrated on the UCY recordings, see
/// `docs/people-validation.md`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SocialForceParams {
    /// Integration step (s); default 0.1, the control period (control periods are split into
    /// whole steps). Explicit Euler on the relaxation term needs `dt < 2 tau`; `docs/algorithms.md`
    /// suggests 0.05 for the stiff interaction terms. At 0.1 every pedestrian test (Moussaid's
    /// known answers, no wall penetration in long crowded runs, passing side, group cohesion,
    /// determinism) still holds and a person costs half as much, which keeps the whole per-step
    /// Rust call under a tenth of an env step on the museum; set 0.05 for finer dynamics.
    pub dt: f64,
    /// Relaxation time of the driving force (s); default 0.5 (Helbing & Molnar 1995; the UCY
    /// calibration keeps it).
    pub tau: f64,
    /// Interaction strength A (m/s^2); default 2.0, calibrated on the UCY recordings
    /// (`proxemic crowd-fit`, `docs/people-validation.md`; Moussaid et al. 2009 published 4.5).
    pub strength: f64,
    /// Weight of the relative velocity in the interaction direction, lambda (the anisotropy);
    /// default 2.0 (Moussaid et al. 2009; the UCY calibration keeps it).
    pub lambda: f64,
    /// Range factor gamma of the interaction (B = gamma |D|); default 0.27, calibrated on the
    /// UCY recordings (Moussaid et al. 2009: 0.35).
    pub gamma: f64,
    /// Angular width n of the lateral term; default 2.0 (Moussaid et al. 2009; the UCY
    /// calibration keeps it).
    pub n: f64,
    /// Angular width n' of the deceleration term; default 4.5, calibrated on the UCY recordings
    /// (Moussaid et al. 2009: 3.0).
    pub n_prime: f64,
    /// Neighbours farther than this are ignored (m); default 4.0 (their force is below 1e-4).
    pub cutoff: f64,
    /// Wall force magnitude F_o (m/s^2); default 10 (pedsim_ros).
    pub wall_strength: f64,
    /// Wall force range sigma_o (m); default 0.2 (pedsim_ros).
    pub wall_range: f64,
    /// Group gaze weight beta_1; default 4.0 (Moussaid et al. 2010 as in PySocialForce).
    pub group_gaze: f64,
    /// Group coherence weight beta_2; default 3.0.
    pub group_coherence: f64,
    /// Group repulsion weight beta_3; default 1.0.
    pub group_repulsion: f64,
    /// Group repulsion distance d0 (m); default 0.55.
    pub group_d0: f64,
    /// A waypoint counts as reached within this distance (m); default 0.3.
    pub arrival: f64,
    /// Maximum speed as a multiple of the preferred speed; default 1.3 (Helbing & Molnar 1995).
    pub max_speed_factor: f64,
}

impl Default for SocialForceParams {
    fn default() -> Self {
        SocialForceParams {
            dt: 0.1,
            tau: 0.5,
            strength: 2.0,
            lambda: 2.0,
            gamma: 0.27,
            n: 2.0,
            n_prime: 4.5,
            cutoff: 4.0,
            wall_strength: 10.0,
            wall_range: 0.2,
            group_gaze: 4.0,
            group_coherence: 3.0,
            group_repulsion: 1.0,
            group_d0: 0.55,
            arrival: 0.3,
            max_speed_factor: 1.3,
        }
    }
}

impl SocialForceParams {
    /// The parameters' names, in declaration order (for [`SocialForceParams::get`] and
    /// [`SocialForceParams::set`]).
    pub const NAMES: [&'static str; 16] = [
        "dt",
        "tau",
        "strength",
        "lambda",
        "gamma",
        "n",
        "n_prime",
        "cutoff",
        "wall_strength",
        "wall_range",
        "group_gaze",
        "group_coherence",
        "group_repulsion",
        "group_d0",
        "arrival",
        "max_speed_factor",
    ];

    fn slot(&mut self, name: &str) -> Option<&mut f64> {
        Some(match name {
            "dt" => &mut self.dt,
            "tau" => &mut self.tau,
            "strength" => &mut self.strength,
            "lambda" => &mut self.lambda,
            "gamma" => &mut self.gamma,
            "n" => &mut self.n,
            "n_prime" => &mut self.n_prime,
            "cutoff" => &mut self.cutoff,
            "wall_strength" => &mut self.wall_strength,
            "wall_range" => &mut self.wall_range,
            "group_gaze" => &mut self.group_gaze,
            "group_coherence" => &mut self.group_coherence,
            "group_repulsion" => &mut self.group_repulsion,
            "group_d0" => &mut self.group_d0,
            "arrival" => &mut self.arrival,
            "max_speed_factor" => &mut self.max_speed_factor,
            _ => return None,
        })
    }

    /// The value of parameter `name` (one of [`SocialForceParams::NAMES`]).
    pub fn get(&self, name: &str) -> Option<f64> {
        let mut copy = *self;
        copy.slot(name).map(|v| *v)
    }

    /// Sets parameter `name` to `value`. Errors (naming the parameter, leaving the parameters
    /// unchanged) for an unknown name, a non-finite value, a negative one, or a zero `dt`,
    /// `tau`, `gamma` or `max_speed_factor` (they divide or bound the motion), and for `dt` not
    /// below `2 tau` (explicit Euler on the relaxation term).
    pub fn set(&mut self, name: &str, value: f64) -> crate::Result<()> {
        let field = format!("social_force.{name}");
        let positive = matches!(name, "dt" | "tau" | "gamma" | "max_speed_factor");
        let mut next = *self;
        let Some(slot) = next.slot(name) else {
            return Err(crate::CoreError::input(
                field,
                format!("one of {:?}", Self::NAMES),
                format!("{name:?}"),
            ));
        };
        if !value.is_finite() || value < 0.0 || (positive && value <= 0.0) {
            let want = if positive { "a finite value > 0" } else { "a finite value >= 0" };
            return Err(crate::CoreError::input(field, want, format!("{value}")));
        }
        *slot = value;
        if next.dt >= 2.0 * next.tau {
            return Err(crate::CoreError::input(
                field,
                format!("dt below 2 tau (explicit Euler), tau = {}", next.tau),
                format!("dt = {}", next.dt),
            ));
        }
        *self = next;
        Ok(())
    }
}

/// Interaction force on a pedestrian at `pi` with velocity `vi` from an agent at `pj` with
/// velocity `vj` (Moussaid, Helbing, Garnier, Johansson, Combe & Theraulaz 2009, Proc. R. Soc. B
/// 276). Centre-to-centre distances; m/s^2.
pub fn interaction_force(pi: Vec2, vi: Vec2, pj: Vec2, vj: Vec2, p: &SocialForceParams) -> Vec2 {
    interaction_term(pi, vi, pj, vj, p).unwrap_or_else(Vec2::zeros)
}

/// [`interaction_force`], or None where it is zero without being computed: the agents farther
/// apart than the cutoff or at the same point, no interaction direction, or a magnitude below
/// 1e-6 m/s^2 (the crowd's sums skip those terms).
pub(super) fn interaction_term(
    pi: Vec2,
    vi: Vec2,
    pj: Vec2,
    vj: Vec2,
    p: &SocialForceParams,
) -> Option<Vec2> {
    let diff = pj - pi;
    let d2 = diff.norm_squared();
    if d2 < 1e-18 || d2 > p.cutoff * p.cutoff {
        return None;
    }
    let d = d2.sqrt();
    let e = diff / d;
    let big_d = (vi - vj) * p.lambda + e;
    let dn = big_d.norm();
    if dn < 1e-12 {
        return None;
    }
    let b = p.gamma * dn;
    // Checked before the angle, which a negligible force does not need.
    let magnitude = p.strength * (-d / b).exp();
    if magnitude < 1e-6 {
        return None;
    }
    let t = big_d / dn;
    let n = Vec2::new(-t.y, t.x);
    let theta = (t.x * e.y - t.y * e.x).atan2(t.dot(&e));
    // sign(theta), with exact symmetry resolved by the passing convention: K = +1 pushes i to
    // its right (-n), so both agents of a head-on encounter pass on the right.
    let k = if theta > 0.0 {
        1.0
    } else if theta < 0.0 {
        -1.0
    } else if PASS_ON_RIGHT {
        1.0
    } else {
        -1.0
    };
    let decel = (-(p.n_prime * b * theta).powi(2)).exp();
    let lateral = (-(p.n * b * theta).powi(2)).exp();
    Some(-(t * decel + n * (k * lateral)) * magnitude)
}

impl Crowd {
    /// Moussaid et al. 2010 group terms for person `i` of the walking group in `slot`.
    pub(super) fn group_force(&self, i: usize, slot: usize) -> Vec2 {
        let p = &self.params;
        let members = &self.groups[slot];
        let pi = self.pos[i];
        let mut f = Vec2::zeros();
        let others = members.iter().filter(|&&k| k != i).map(|&k| self.pos[k]);
        let c_others = others.clone().fold(Vec2::zeros(), |a, b| a + b) / (members.len() - 1) as f64;
        let walk = self.vel[i];
        if walk.norm() > 1e-6 {
            // Gaze: turn the walking direction toward the others (phi_v = 90 degrees).
            let to = c_others - pi;
            if to.norm() > 1e-9 {
                let alpha = wrap_angle(to.y.atan2(to.x) - walk.y.atan2(walk.x)).abs();
                let phi_v = std::f64::consts::FRAC_PI_2;
                if alpha > phi_v {
                    f -= walk.normalize() * (p.group_gaze * (alpha - phi_v));
                }
            }
        }
        // Coherence: toward the centre of all members beyond (|G| - 1) / 2 metres.
        let c_all = members.iter().fold(Vec2::zeros(), |a, &k| a + self.pos[k]) / members.len() as f64;
        let to = c_all - pi;
        if to.norm() > (members.len() as f64 - 1.0) / 2.0 {
            f += to.normalize() * p.group_coherence;
        }
        // Repulsion between members closer than d0.
        for q in others {
            let away = pi - q;
            let d = away.norm();
            if d < p.group_d0 && d > 1e-9 {
                f += away / d * p.group_repulsion;
            }
        }
        f
    }
}
