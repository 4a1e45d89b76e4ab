//! ORCA people: the pedestrian model of CrowdNav's simulator (`crowd_sim`, its `ORCA` policy),
//! beside the social force model.
//!
//! Every person runs ORCA (van den Berg et al. 2011, [`crate::control::orca`], the one ORCA of the
//! core) from its own point of view each step, as CrowdNav's people do with one RVO2 simulator
//! each: the person heads for its goal (preferred velocity: the vector to the goal, cut to unit
//! length when the goal is more than 1 m away, so a person slows into its goal and stays there
//! without being removed), sees every other person and, when the robot is visible, the robot, and
//! treats every one of them as reciprocal (RVO2 takes half of each avoidance for every
//! neighbour). Parameters are CrowdNav's ([`CROWDNAV_ORCA`]): neighbour distance 10 m, 10
//! neighbours, time horizon 5 s for agents and obstacles, no perturbation of the preferred
//! velocity and no passing-side tilt (plain RVO2), each radius enlarged by
//! [`RADIUS_MARGIN`] (CrowdNav adds 0.01 m), maximum speed the agent's preferred speed.
//!
//! A person's new velocity depends only on the current positions and velocities (RVO2 overwrites
//! its agents' state every step), so one batched [`Orca::compute`] with every person active gives
//! each person's own-view velocity; the robot's ORCA of the CrowdNav protocol
//! ([`crate::world::crowdnav`]) is the same computation with the robot as the only active agent.

use crate::control::orca::{ObstacleSet, Orca, OrcaAgent, OrcaParams};
use crate::error::Result;
use crate::math::Vec2;

/// CrowdNav's ORCA parameters (its `ORCA` policy: `neighbor_dist` 10, `max_neighbors` 10,
/// `time_horizon` 5, `time_horizon_obst` 5), as plain RVO2 (no perturbation, no tilt).
pub const CROWDNAV_ORCA: OrcaParams = OrcaParams {
    time_horizon: 5.0,
    time_horizon_obst: 5.0,
    neighbor_dist: 10.0,
    max_neighbors: 10,
    perturbation: 0.0,
    pass_tilt: 0.0,
};

/// Added to every radius ORCA sees (m; CrowdNav's `radius + 0.01 + safety_space`, with its
/// safety space 0).
pub const RADIUS_MARGIN: f64 = 0.01;

/// A body as the ORCA people see it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrcaBody {
    /// Position (m).
    pub pos: Vec2,
    /// Velocity of the last step (m/s).
    pub vel: Vec2,
    /// Goal (m): where the body heads when it is active.
    pub goal: Vec2,
    /// Body radius (m), without [`RADIUS_MARGIN`].
    pub radius: f64,
    /// Preferred speed (m/s): ORCA's maximum speed for the body.
    pub v_pref: f64,
}

/// The preferred velocity toward `goal` (m/s): the vector from `pos` to `goal`, cut to unit
/// length when longer (CrowdNav's rule for its people and its ORCA robot).
pub fn preferred_velocity(pos: Vec2, goal: Vec2) -> Vec2 {
    let d = goal - pos;
    let n = d.norm();
    if n > 1.0 { d / n } else { d }
}

/// The ORCA people's solver (CrowdNav's parameters) with its buffers.
#[derive(Clone, Debug)]
pub struct OrcaPeople {
    orca: Orca,
    obstacles: ObstacleSet,
    agents: Vec<OrcaAgent>,
    out: Vec<Vec2>,
}

impl OrcaPeople {
    /// A solver with [`CROWDNAV_ORCA`] and no static obstacles (CrowdNav's scenes have none).
    pub fn new() -> Result<Self> {
        Ok(OrcaPeople {
            orca: Orca::new(CROWDNAV_ORCA)?,
            obstacles: ObstacleSet::empty(),
            agents: Vec::new(),
            out: Vec::new(),
        })
    }

    /// The new velocities (m/s) of the bodies listed in `active` (indices into `bodies`), each
    /// heading for its goal and avoiding every other body of `bodies` as a reciprocal agent;
    /// `dt` (s) is the step ORCA uses when bodies overlap. Returns one velocity per entry of
    /// `active`, in its order. Errors: [`crate::CoreError::Input`] as [`Orca::compute`].
    pub fn velocities(&mut self, bodies: &[OrcaBody], active: &[usize], dt: f64) -> Result<Vec<Vec2>> {
        self.agents.clear();
        self.agents.extend(bodies.iter().enumerate().map(|(k, b)| OrcaAgent {
            pos: b.pos,
            vel: b.vel,
            pref_vel: preferred_velocity(b.pos, b.goal),
            radius: b.radius + RADIUS_MARGIN,
            max_speed: b.v_pref,
            reciprocal: true,
            id: k as u64,
        }));
        self.out.clear();
        self.out.resize(bodies.len(), Vec2::zeros());
        self.orca.compute(&self.agents, active, &self.obstacles, dt, 0, &mut self.out)?;
        Ok(active.iter().map(|&k| self.out[k]).collect())
    }
}
