//! The reward of one control step: five weighted terms, reported separately and summed; and
//! each robot's record of the step (metrics, outcome, reward, flags).

use super::World;
use crate::math::Vec2;
use crate::metrics::{CONTACT_ROBOT, Outcome};
use crate::scenario::RewardWeights;

/// Names of the reward terms, in the order they are summed.
pub const REWARD_TERMS: [&str; 5] = RewardTerms::NAMES;
/// Radius of the personal zone used by the personal-space reward term (metres, centre distance;
/// Hall's personal distance as used by HuNav/SEAN).
pub const PERSONAL_ZONE: f64 = 1.2;

/// The weighted reward terms of one robot's step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RewardTerms {
    /// `progress` weight times the decrease of the geodesic distance to the current target (m).
    pub progress: f64,
    /// The `success` weight on the step the robot reaches its goal, else 0.
    pub success: f64,
    /// The `collision` weight on the step the robot collides, else 0.
    pub collision: f64,
    /// The `time` weight, every step.
    pub time: f64,
    /// `personal_space` weight times how deep the robot is inside the closest person's personal
    /// zone ([`PERSONAL_ZONE`]), as a fraction of the zone (0 to 1).
    pub personal_space: f64,
}

impl RewardTerms {
    /// Names of the terms, in the order of [`RewardTerms::values`] (and of the `reward_terms`
    /// section of the output).
    pub const NAMES: [&'static str; 5] = ["progress", "success", "collision", "time", "personal_space"];

    /// The terms of a step with `progress` metres of progress, ending in `outcome`, with the
    /// closest person at centre distance `closest_person` (m; +inf without people).
    pub fn new(w: &RewardWeights, progress: f64, outcome: Outcome, closest_person: f64) -> Self {
        RewardTerms {
            progress: w.progress * progress,
            success: if outcome == Outcome::Success { w.success } else { 0.0 },
            collision: if outcome == Outcome::Collision { w.collision } else { 0.0 },
            time: w.time,
            personal_space: w.personal_space * ((PERSONAL_ZONE - closest_person) / PERSONAL_ZONE).max(0.0),
        }
    }

    /// The terms in the order of [`RewardTerms::NAMES`].
    pub fn values(&self) -> [f64; 5] {
        [self.progress, self.success, self.collision, self.time, self.personal_space]
    }

    /// The reward: the terms summed in the order of [`RewardTerms::NAMES`], so that Python's sum
    /// of the reported terms equals it exactly.
    pub fn total(&self) -> f64 {
        let mut total = 0.0;
        for t in self.values() {
            total += t;
        }
        total
    }
}

impl World {
    /// Records robot `i`'s step in its metrics (with the physics' `contacts` bits) and writes
    /// its reward terms, reward and flags into its `row`. A robot whose episode has ended gets
    /// zero reward terms and keeps its flags.
    pub(super) fn record(&mut self, i: usize, contacts: u8, out_of_time: bool, row: &mut [f64]) {
        let lay = &self.layout;
        let pose = self.robots[i].pose;
        let p = Vec2::new(pose[0], pose[1]);
        let d = self.closest_person(p);
        let robot_gap = self.closest_robot_gap(i);
        if self.robots[i].outcome != Outcome::Running {
            row[lay.reward_terms.range()].fill(0.0);
            row[lay.reward.offset] = 0.0;
            return;
        }
        let st = &self.statics[i];
        let rb = &mut self.robots[i];
        // Two robots overlapping at a control instant collide even if the physics missed it
        // (Francis et al.'s agent collisions, AC).
        rb.recorder.observe_robot_gap(robot_gap);
        let bits = contacts | if robot_gap < 0.0 { CONTACT_ROBOT } else { 0 };
        let outcome = rb.recorder.record(&self.log, pose, bits, out_of_time, rb.recovering);
        rb.outcome = outcome;
        let geo = st.fields[rb.leg].distance(p);
        let progress = if geo.is_finite() && rb.geodesic.is_finite() { rb.geodesic - geo } else { 0.0 };
        if geo.is_finite() {
            rb.geodesic = geo;
        }
        let terms = RewardTerms::new(&self.scenario.reward, progress, outcome, d);
        row[lay.reward_terms.range()].copy_from_slice(&terms.values());
        row[lay.reward.offset] = terms.total();
        let flags = &mut row[lay.flags.range()];
        flags[0] = f64::from(u8::from(matches!(outcome, Outcome::Success | Outcome::Collision)));
        flags[1] = f64::from(u8::from(outcome == Outcome::Timeout));
        flags[2] = f64::from(u8::from(outcome == Outcome::Success));
        flags[3] = f64::from(u8::from(outcome == Outcome::Collision));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn terms_follow_the_weights_and_sum_in_order() {
        let w = RewardWeights {
            progress: 2.0,
            success: 10.0,
            collision: -10.0,
            time: -0.01,
            personal_space: -0.1,
        };
        let t = RewardTerms::new(&w, 0.25, Outcome::Success, 0.6);
        assert_eq!(t.values(), [0.5, 10.0, 0.0, -0.01, -0.05]);
        assert_eq!(t.total(), (((0.0 + 0.5) + 10.0) + 0.0 + -0.01) + -0.05);
        let far = RewardTerms::new(&w, 0.0, Outcome::Collision, f64::INFINITY);
        assert_eq!((far.collision, far.success, far.personal_space), (-10.0, 0.0, 0.0));
    }
}
