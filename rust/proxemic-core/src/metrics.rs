//! Episode metrics, accumulated step by step (definitions: `design/metrics.md`).
//!
//! First cut: success, collisions with people and with static geometry, time to goal, path
//! length, and the minimum distance to people, both centre-to-centre and as the surface gap.
//! - **success**: the robot's centre came within the success radius of the goal before any
//!   collision and before the time limit (Francis et al. S).
//! - **collision with people (HC)** / **with static geometry (WC)**: a contact reported by the
//!   physics between the robot and a person's or the static world's geometry, or (people) a
//!   surface gap below zero measured geometrically at a control instant.
//! - **collision with another robot (AC, Francis et al.'s agent collisions)**: a contact reported
//!   by the physics between two robots, or a surface gap below zero between them at a control
//!   instant; it ends the episode like the other collisions.
//! - **time to goal**: control steps until success times the control period (s); only on success.
//! - **path length**: sum of the distances between consecutive control-instant positions (m).
//! - **minimum distance to people**: over all control instants and people, the centre-to-centre
//!   distance `d = |p - q_i|` (m) and the surface gap `d - r_robot - r_i` (m).

pub mod trajectory;

use serde::Serialize;

use crate::math::Vec2;

/// How an episode ended for a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Still running.
    Running,
    /// Reached the goal.
    Success,
    /// Collided with a person, another robot or the static geometry.
    Collision,
    /// Ran out of time.
    Timeout,
}

/// Per-robot episode metrics.
#[derive(Clone, Debug, Serialize)]
pub struct EpisodeMetrics {
    /// How the episode ended.
    pub outcome: Outcome,
    /// 1 if the goal was reached without collision, else 0.
    pub success: bool,
    /// Any collision with a person.
    pub collision_person: bool,
    /// Any collision with walls or furniture.
    pub collision_static: bool,
    /// Number of control steps with a collision with a person.
    pub collision_person_steps: usize,
    /// Number of control steps with a collision with static geometry.
    pub collision_static_steps: usize,
    /// Any collision with another robot.
    pub collision_robot: bool,
    /// Number of control steps with a collision with another robot.
    pub collision_robot_steps: usize,
    /// Minimum surface gap to any other robot (metres; negative means overlap; +inf alone).
    pub min_robot_gap: f64,
    /// Seconds from the start to success (None unless successful).
    pub time_to_goal: Option<f64>,
    /// Path length (metres).
    pub path_length: f64,
    /// Minimum centre-to-centre distance to any person (metres; +inf with no people).
    pub min_person_distance: f64,
    /// Minimum surface gap to any person (metres; negative means overlap; +inf with no people).
    pub min_person_gap: f64,
    /// Control steps taken.
    pub steps: usize,
    /// Episode duration (s).
    pub duration: f64,
}

impl Default for EpisodeMetrics {
    fn default() -> Self {
        EpisodeMetrics {
            outcome: Outcome::Running,
            success: false,
            collision_person: false,
            collision_static: false,
            collision_person_steps: 0,
            collision_static_steps: 0,
            collision_robot: false,
            collision_robot_steps: 0,
            min_robot_gap: f64::INFINITY,
            time_to_goal: None,
            path_length: 0.0,
            min_person_distance: f64::INFINITY,
            min_person_gap: f64::INFINITY,
            steps: 0,
            duration: 0.0,
        }
    }
}

/// What one control step contributes to the metrics.
#[derive(Clone, Copy, Debug)]
pub struct StepSample {
    /// Robot position after the step.
    pub position: Vec2,
    /// Closest centre-to-centre distance to a person at this instant.
    pub person_distance: f64,
    /// Closest surface gap to a person at this instant.
    pub person_gap: f64,
    /// A collision with a person happened during the step.
    pub hit_person: bool,
    /// A collision with static geometry happened during the step.
    pub hit_static: bool,
    /// Closest surface gap to another robot at this instant (+inf without other robots).
    pub robot_gap: f64,
    /// A collision with another robot happened during the step.
    pub hit_robot: bool,
    /// The goal is reached at this instant.
    pub at_goal: bool,
    /// The time limit is reached at this instant.
    pub out_of_time: bool,
}

/// Accumulates [`EpisodeMetrics`] for one robot.
#[derive(Clone, Debug, Default)]
pub struct MetricsAccumulator {
    metrics: EpisodeMetrics,
    last: Option<Vec2>,
}

impl MetricsAccumulator {
    /// Starts an episode at `start`.
    pub fn new(start: Vec2) -> Self {
        MetricsAccumulator { metrics: EpisodeMetrics::default(), last: Some(start) }
    }

    /// Records the distances at the start of the episode (before any step).
    pub fn observe_start(&mut self, person_distance: f64, person_gap: f64) {
        self.metrics.min_person_distance = self.metrics.min_person_distance.min(person_distance);
        self.metrics.min_person_gap = self.metrics.min_person_gap.min(person_gap);
    }

    /// Adds one control step of `dt` seconds; returns the outcome after it. Steps after the
    /// episode has ended are ignored.
    pub fn record(&mut self, s: &StepSample, dt: f64) -> Outcome {
        let m = &mut self.metrics;
        if m.outcome != Outcome::Running {
            return m.outcome;
        }
        m.steps += 1;
        m.duration = m.steps as f64 * dt;
        if let Some(last) = self.last {
            m.path_length += (s.position - last).norm();
        }
        self.last = Some(s.position);
        m.min_person_distance = m.min_person_distance.min(s.person_distance);
        m.min_person_gap = m.min_person_gap.min(s.person_gap);
        if s.hit_person {
            m.collision_person = true;
            m.collision_person_steps += 1;
        }
        if s.hit_static {
            m.collision_static = true;
            m.collision_static_steps += 1;
        }
        m.min_robot_gap = m.min_robot_gap.min(s.robot_gap);
        if s.hit_robot {
            m.collision_robot = true;
            m.collision_robot_steps += 1;
        }
        m.outcome = if s.hit_person || s.hit_static || s.hit_robot {
            Outcome::Collision
        } else if s.at_goal {
            m.success = true;
            m.time_to_goal = Some(m.duration);
            Outcome::Success
        } else if s.out_of_time {
            Outcome::Timeout
        } else {
            Outcome::Running
        };
        m.outcome
    }

    /// The metrics so far.
    pub fn metrics(&self) -> &EpisodeMetrics {
        &self.metrics
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(x: f64, y: f64, d: f64) -> StepSample {
        StepSample {
            position: Vec2::new(x, y),
            person_distance: d,
            person_gap: d - 0.44,
            hit_person: false,
            hit_static: false,
            robot_gap: f64::INFINITY,
            hit_robot: false,
            at_goal: false,
            out_of_time: false,
        }
    }

    #[test]
    fn hand_computed_trajectory() {
        // (0,0) -> (3,0) -> (3,4) -> goal: path 7 m; closest person 0.9 m at step 2
        let mut acc = MetricsAccumulator::new(Vec2::zeros());
        acc.observe_start(2.0, 1.56);
        assert_eq!(acc.record(&sample(3.0, 0.0, 1.5), 0.1), Outcome::Running);
        assert_eq!(acc.record(&sample(3.0, 4.0, 0.9), 0.1), Outcome::Running);
        let mut last = sample(3.0, 4.0, 1.0);
        last.at_goal = true;
        assert_eq!(acc.record(&last, 0.1), Outcome::Success);
        let m = acc.metrics();
        assert!((m.path_length - 7.0).abs() < 1e-12);
        assert!((m.min_person_distance - 0.9).abs() < 1e-12);
        assert!((m.min_person_gap - 0.46).abs() < 1e-12);
        assert!(m.success);
        assert!((m.time_to_goal.expect("success") - 0.3).abs() < 1e-12);
        assert_eq!(m.steps, 3);
    }

    #[test]
    fn collision_beats_goal_and_freezes_the_episode() {
        let mut acc = MetricsAccumulator::new(Vec2::zeros());
        let mut s = sample(1.0, 0.0, 0.3);
        s.hit_person = true;
        s.at_goal = true;
        assert_eq!(acc.record(&s, 0.1), Outcome::Collision);
        assert!(!acc.metrics().success);
        assert!(acc.metrics().collision_person && !acc.metrics().collision_static);
        // ignored after the end
        assert_eq!(acc.record(&sample(5.0, 0.0, 3.0), 0.1), Outcome::Collision);
        assert!((acc.metrics().path_length - 1.0).abs() < 1e-12);
        assert_eq!(acc.metrics().time_to_goal, None);
    }

    #[test]
    fn robot_collision_ends_the_episode_and_is_counted() {
        let mut acc = MetricsAccumulator::new(Vec2::zeros());
        let mut s = sample(0.5, 0.0, 5.0);
        s.robot_gap = 0.2;
        assert_eq!(acc.record(&s, 0.1), Outcome::Running);
        s.robot_gap = -0.01;
        s.hit_robot = true;
        assert_eq!(acc.record(&s, 0.1), Outcome::Collision);
        let m = acc.metrics();
        assert!(m.collision_robot && !m.collision_person && !m.collision_static);
        assert_eq!(m.collision_robot_steps, 1);
        assert!((m.min_robot_gap + 0.01).abs() < 1e-12);
    }

    #[test]
    fn timeout() {
        let mut acc = MetricsAccumulator::new(Vec2::zeros());
        let mut s = sample(0.0, 0.0, 5.0);
        s.out_of_time = true;
        assert_eq!(acc.record(&s, 0.1), Outcome::Timeout);
        assert!(!acc.metrics().success);
    }
}
