//! The layout of a robot's row in the output buffer: one typed field per section, so the core
//! writes each section through its field (no look-up by name), and the bindings hand Python the
//! same sections by name ([`Layout::sections`]).

use std::ops::Range;

use super::observe::{PEER_FEATURES, PERSON_FEATURES, ROBOT_FEATURES};
use super::reward::RewardTerms;

/// One section of a robot's row in the output buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Section {
    /// Offset within the row.
    pub offset: usize,
    /// Number of values.
    pub len: usize,
}

impl Section {
    /// The section's indices within a row.
    pub fn range(&self) -> Range<usize> {
        self.offset..self.offset + self.len
    }
}

/// Layout of a robot's row in the output buffer: the sections, in the order they follow each
/// other in the row.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Values per robot row.
    pub stride: usize,
    /// 3: vx, vy, wz, robot frame, to execute.
    pub command: Section,
    /// 3: the built-in planner's command as a normalised action.
    pub planner_action: Section,
    /// [`ROBOT_FEATURES`]: the goal offset and the robot's velocity in its own frame.
    pub obs_robot: Section,
    /// k * [`PERSON_FEATURES`]: the k nearest people within sensor range.
    pub obs_people: Section,
    /// k: 1 for each filled slot of `obs_people`.
    pub obs_people_mask: Section,
    /// One range per lidar ray.
    pub obs_lidar: Section,
    /// 2 with the `subgoal` sensor (the point along the shortest path, robot frame), else 0.
    pub obs_subgoal: Section,
    /// (n - 1) * [`PEER_FEATURES`]: the other robots within sensor range, nearest first.
    pub obs_robots: Section,
    /// n - 1: 1 for each filled slot of `obs_robots`.
    pub obs_robots_mask: Section,
    /// The reward terms, in the order of [`RewardTerms::NAMES`].
    pub reward_terms: Section,
    /// 1: the reward, the sum of the terms.
    pub reward: Section,
    /// 4: terminated, truncated, success, collision.
    pub flags: Section,
    /// 3: x, y, theta (world frame).
    pub pose: Section,
    /// 1: the local planner's mode, see [`crate::control::mode_switch::Mode::code`].
    pub mode: Section,
    /// 1: 1.0 while the robot is within [`super::CONTACT_RANGE`] of a wall or object, else 0.0
    /// (whether the physics must test it against the static geometry).
    pub near_static: Section,
    /// 1: 1.0 while another robot is within [`super::CONTACT_RANGE`] of it, else 0.0.
    pub near_robot: Section,
    /// 1: 1.0 while any contact can happen in the next control step (some robot's
    /// `near_static` or `near_robot` hint or some person's contact hint is set), else 0.0 (the
    /// physics may step with contacts off); the same in every row.
    pub contacts_possible: Section,
    /// 1: seconds after midnight, the same in every row.
    pub time_of_day: Section,
}

/// Hands out consecutive sections of a row.
struct Cursor(usize);

impl Cursor {
    fn take(&mut self, len: usize) -> Section {
        let s = Section { offset: self.0, len };
        self.0 += len;
        s
    }
}

impl Layout {
    /// The layout for `k` observed people, `rays` lidar rays, `robots` robots and, with
    /// `subgoal`, the subgoal observation.
    pub(super) fn new(k: usize, rays: usize, robots: usize, subgoal: bool) -> Self {
        let others = robots.saturating_sub(1);
        let mut c = Cursor(0);
        let mut layout = Layout {
            stride: 0,
            command: c.take(3),
            planner_action: c.take(3),
            obs_robot: c.take(ROBOT_FEATURES),
            obs_people: c.take(k * PERSON_FEATURES),
            obs_people_mask: c.take(k),
            obs_lidar: c.take(rays),
            obs_subgoal: c.take(if subgoal { 2 } else { 0 }),
            obs_robots: c.take(others * PEER_FEATURES),
            obs_robots_mask: c.take(others),
            reward_terms: c.take(RewardTerms::NAMES.len()),
            reward: c.take(1),
            flags: c.take(4),
            pose: c.take(3),
            mode: c.take(1),
            near_static: c.take(1),
            near_robot: c.take(1),
            contacts_possible: c.take(1),
            time_of_day: c.take(1),
        };
        layout.stride = c.0;
        layout
    }

    /// The sections by name, in row order (what the Python binding exposes as `World.layout`).
    pub fn sections(&self) -> [(&'static str, Section); 18] {
        [
            ("command", self.command),
            ("planner_action", self.planner_action),
            ("obs_robot", self.obs_robot),
            ("obs_people", self.obs_people),
            ("obs_people_mask", self.obs_people_mask),
            ("obs_lidar", self.obs_lidar),
            ("obs_subgoal", self.obs_subgoal),
            ("obs_robots", self.obs_robots),
            ("obs_robots_mask", self.obs_robots_mask),
            ("reward_terms", self.reward_terms),
            ("reward", self.reward),
            ("flags", self.flags),
            ("pose", self.pose),
            ("mode", self.mode),
            ("near_static", self.near_static),
            ("near_robot", self.near_robot),
            ("contacts_possible", self.contacts_possible),
            ("time_of_day", self.time_of_day),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_tile_the_row_in_order_with_distinct_names() {
        for subgoal in [false, true] {
            check_tiling(Layout::new(4, 16, 3, subgoal), subgoal);
        }
    }

    fn check_tiling(layout: Layout, subgoal: bool) {
        let sections = layout.sections();
        let mut end = 0;
        for (name, s) in &sections {
            assert_eq!(s.offset, end, "{name} starts where the previous section ends");
            end = s.range().end;
        }
        assert_eq!(end, layout.stride);
        let mut names: Vec<&str> = sections.iter().map(|(n, _)| *n).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), sections.len());
        assert_eq!(layout.obs_people.len, 4 * PERSON_FEATURES);
        assert_eq!(layout.obs_robots.len, 2 * PEER_FEATURES);
        assert_eq!(layout.obs_lidar.len, 16);
        assert_eq!(layout.obs_subgoal.len, if subgoal { 2 } else { 0 });
    }
}
