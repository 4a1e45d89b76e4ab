//! Observations (the robot's own state, the nearest people, the other robots, the lidar), the
//! people buffer with the physics' contact hints, and the ground truth of each instant.

use super::World;
use crate::control::world_to_body;
use crate::math::Vec2;
use crate::metrics::{Outcome, interactions};

/// Number of values per person in the people observation.
pub const PERSON_FEATURES: usize = 5;
/// Number of values in the robot observation.
pub const ROBOT_FEATURES: usize = 5;
/// Number of values per other robot in the robots observation: id (the robot's index), position
/// (x, y) and velocity (vx, vy) in the observer's frame, radius, and 1 while that robot's episode
/// is running (0 once it has ended: it then stands still).
pub const PEER_FEATURES: usize = 7;
/// Bound on velocities in observations (m/s); values beyond are clipped (documented in the env).
pub const OBS_MAX_SPEED: f64 = 5.0;
/// Bound on the angular velocity in observations (rad/s).
pub const OBS_MAX_ANGULAR: f64 = 10.0;
/// Values per person in the people buffer: x, y, heading (world frame, m and rad), a contact
/// hint (1.0 while the person is within [`CONTACT_RANGE`] of a robot, else 0.0), and the
/// heading as the w and z of a yaw quaternion (cos and sin of half the heading, for MuJoCo).
pub const PERSON_OUT: usize = 6;
/// Surface gap (m) within which the physics must test a robot against the static geometry or a
/// person for contacts. Beyond it nothing can touch during one control step: closing 0.5 m in
/// 0.1 s takes 5 m/s, and robots move at most 0.55 m/s, people at most 1.3 times their preferred
/// speed; a robot moving faster than [`CONTACT_RANGE`] per control period is always tested.
/// The hints only let the physics skip pairs that cannot collide: contacts are the same.
pub const CONTACT_RANGE: f64 = 0.5;

impl World {
    /// Centre distance from `p` to the closest person present (m; +inf without people).
    pub(super) fn closest_person(&self, p: Vec2) -> f64 {
        let c = &self.crowd;
        c.pos
            .iter()
            .zip(&c.present)
            .filter(|(_, h)| **h)
            .map(|(q, _)| (q - p).norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// Closest surface gap from robot `i` to any other robot (+inf alone).
    pub(super) fn closest_robot_gap(&self, i: usize) -> f64 {
        let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
        let r = self.statics[i].radius;
        let mut best = f64::INFINITY;
        for (j, (o, st)) in self.robots.iter().zip(&self.statics).enumerate() {
            if j != i {
                best = best.min((Vec2::new(o.pose[0], o.pose[1]) - p).norm() - r - st.radius);
            }
        }
        best
    }

    /// Writes the people's poses and contact hints into `people_out`, and each robot's
    /// `near_static` and `near_robot` hints, whether any contact is possible and the time of day
    /// into its row of `out`.
    pub(super) fn write_people(&self, out: &mut [f64], people_out: &mut [f64]) {
        let stride = self.layout.stride;
        let (near_off, robot_off, tod_off) =
            (self.layout.near_static.offset, self.layout.near_robot.offset, self.layout.time_of_day.offset);
        let mut possible = false;
        let dt = self.scenario.control_dt();
        let tod = self.time_of_day();
        // Robot discs grown by the contact range and what the robot can travel in one period.
        let reach: Vec<(Vec2, f64)> = self
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(rb, st)| {
                let travel = (rb.velocity.norm() * dt).min(1e6);
                (Vec2::new(rb.pose[0], rb.pose[1]), st.radius + CONTACT_RANGE + travel)
            })
            .collect();
        for (i, &(p, r)) in reach.iter().enumerate() {
            // Centre distance to the nearest wall or object edge, looked up within `r` only (a
            // robot cannot be deep inside an object: the physics pushes it out first).
            let near = self.geometry.boundary_distance_within(p, r) < r;
            let near_robot = reach
                .iter()
                .enumerate()
                .any(|(j, &(q, rq))| j != i && (q - p).norm_squared() < (r + rq - CONTACT_RANGE).powi(2));
            let row = &mut out[i * stride..(i + 1) * stride];
            row[near_off] = f64::from(u8::from(near));
            row[robot_off] = f64::from(u8::from(near_robot));
            row[tod_off] = tod;
            possible |= near || near_robot;
        }
        for (k, chunk) in people_out.chunks_exact_mut(PERSON_OUT).enumerate() {
            let q = self.crowd.pos[k];
            let rk = self.crowd.radius[k];
            let near = reach.iter().any(|&(p, r)| (q - p).norm_squared() < (r + rk) * (r + rk));
            chunk[0] = q.x;
            chunk[1] = q.y;
            let h = self.crowd.heading[k];
            chunk[2] = h;
            chunk[3] = f64::from(u8::from(near));
            let (sin, cos) = (0.5 * h).sin_cos();
            chunk[4] = cos;
            chunk[5] = sin;
            possible |= near;
        }
        let possible_off = self.layout.contacts_possible.offset;
        for row in out.chunks_exact_mut(stride) {
            row[possible_off] = f64::from(u8::from(possible));
        }
    }

    /// Fills the observation sections and `pose` of every robot's row (only `pose` for robots
    /// whose episode had ended before this step: their last observation stays).
    pub(super) fn observe_all(&mut self, out: &mut [f64]) {
        let stride = self.layout.stride;
        let lay = self.layout;
        let (o_robot, o_people, o_mask, o_pose) =
            (lay.obs_robot.offset, lay.obs_people.offset, lay.obs_people_mask.offset, lay.pose.offset);
        let k = self.scenario.sensors.k_nearest;
        let range = self.scenario.sensors.lidar_range;
        let diag = self.obs_position_bound();
        for i in 0..self.robots.len() {
            let rb = &self.robots[i];
            let st = &self.statics[i];
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            let th = rb.pose[2];
            let row = &mut out[i * stride..(i + 1) * stride];
            row[o_pose..o_pose + 3].copy_from_slice(&rb.pose);
            if self.ended[i] {
                continue;
            }
            let g = world_to_body(st.route[rb.leg] - p, th);
            let v = world_to_body(rb.velocity, th);
            let obs = &mut row[o_robot..o_robot + ROBOT_FEATURES];
            obs[0] = g.x.clamp(-diag, diag);
            obs[1] = g.y.clamp(-diag, diag);
            obs[2] = v.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            obs[3] = v.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            obs[4] = rb.wz.clamp(-OBS_MAX_ANGULAR, OBS_MAX_ANGULAR);
            if lay.obs_subgoal.len == 2 {
                let w = self.subgoal_offset(i, self.scenario.sensors.subgoal);
                row[lay.obs_subgoal.range()].copy_from_slice(&w);
            }
            // K nearest people present within sensor range, ties broken by index.
            self.scratch_people.clear();
            for (j, q) in self.crowd.pos.iter().enumerate() {
                let d = (q - p).norm();
                if d <= range && self.crowd.present[j] {
                    self.scratch_people.push((d, j));
                }
            }
            self.scratch_people.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let people = &mut row[o_people..o_people + k * PERSON_FEATURES];
            people.fill(0.0);
            let mut mask = [0.0; 64];
            for (slot, &(_, j)) in self.scratch_people.iter().take(k).enumerate() {
                let rel = world_to_body(self.crowd.pos[j] - p, th);
                let vel = world_to_body(self.crowd.vel[j], th);
                let f = &mut people[slot * PERSON_FEATURES..(slot + 1) * PERSON_FEATURES];
                f[0] = rel.x.clamp(-range, range);
                f[1] = rel.y.clamp(-range, range);
                f[2] = vel.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[3] = vel.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
                f[4] = self.crowd.radius[j];
                mask[slot] = 1.0;
            }
            row[o_mask..o_mask + k].copy_from_slice(&mask[..k]);
            self.observe_peers(i, row);
            self.scan(i, row);
        }
    }

    /// The other robots within sensor range of robot `i`, nearest first (ties by index), with
    /// their ids, into the `obs_robots` and `obs_robots_mask` sections of `row`
    /// ([`PEER_FEATURES`] values per slot).
    fn observe_peers(&mut self, i: usize, row: &mut [f64]) {
        let lay = self.layout;
        let range = self.scenario.sensors.lidar_range;
        let (p, th) = (Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]), self.robots[i].pose[2]);
        self.scratch_people.clear();
        for (j, o) in self.robots.iter().enumerate() {
            let d = (Vec2::new(o.pose[0], o.pose[1]) - p).norm();
            if j != i && d <= range {
                self.scratch_people.push((d, j));
            }
        }
        self.scratch_people.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let peers = &mut row[lay.obs_robots.range()];
        peers.fill(0.0);
        for (slot, &(_, j)) in self.scratch_people.iter().enumerate() {
            let o = &self.robots[j];
            let rel = world_to_body(Vec2::new(o.pose[0], o.pose[1]) - p, th);
            let vel = world_to_body(o.velocity, th);
            let f = &mut peers[slot * PEER_FEATURES..(slot + 1) * PEER_FEATURES];
            f[0] = j as f64;
            f[1] = rel.x.clamp(-range, range);
            f[2] = rel.y.clamp(-range, range);
            f[3] = vel.x.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            f[4] = vel.y.clamp(-OBS_MAX_SPEED, OBS_MAX_SPEED);
            f[5] = self.statics[j].radius;
            f[6] = f64::from(u8::from(o.outcome == Outcome::Running));
        }
        let seen = self.scratch_people.len();
        let mask = &mut row[lay.obs_robots_mask.range()];
        mask.fill(0.0);
        mask[..seen].fill(1.0);
    }

    /// Robot `i`'s lidar scan into the `obs_lidar` section of `row`: it sees the static world,
    /// the people and the other robots.
    fn scan(&mut self, i: usize, row: &mut [f64]) {
        let scan = &mut row[self.layout.obs_lidar.range()];
        let range = self.scenario.sensors.lidar_range;
        let (p, th) = (Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]), self.robots[i].pose[2]);
        self.scratch_discs.clear();
        for ((q, r), _) in
            self.crowd.pos.iter().zip(&self.crowd.radius).zip(&self.crowd.present).filter(|(_, h)| **h)
        {
            self.scratch_discs.push((*q, *r));
        }
        for (j, (other, ost)) in self.robots.iter().zip(&self.statics).enumerate() {
            if j != i {
                self.scratch_discs.push((Vec2::new(other.pose[0], other.pose[1]), ost.radius));
            }
        }
        // Failures are an empty buffer or non-finite inputs, which the layout and the checks
        // of `step` rule out.
        let _ = self.scanners[i].scan(&self.geometry, &self.scratch_discs, p, th, range, scan);
    }

    /// Robot `i`'s subgoal `lookahead` metres along its shortest path to its current target
    /// ([`GoalField::subgoal`](crate::plan::geodesic::GoalField::subgoal) on its goal field),
    /// as an offset in its own frame, each component clamped to `[-lookahead, lookahead]`. Where
    /// the field has no distance (the robot pushed into an inflated wall cell), the straight-line
    /// offset to the target, shortened to `lookahead`.
    pub(super) fn subgoal_offset(&self, i: usize, lookahead: f64) -> [f64; 2] {
        let rb = &self.robots[i];
        let st = &self.statics[i];
        let p = Vec2::new(rb.pose[0], rb.pose[1]);
        let target = st.route[rb.leg];
        let offset = match st.fields[rb.leg].subgoal(p, target, lookahead) {
            Some(w) => w - p,
            None => {
                let g = target - p;
                let n = g.norm();
                if n > lookahead { g * (lookahead / n) } else { g }
            }
        };
        let b = world_to_body(offset, rb.pose[2]);
        [b.x.clamp(-lookahead, lookahead), b.y.clamp(-lookahead, lookahead)]
    }

    /// Bound on goal offsets in observations: the diagonal of the map, rounded up (metres).
    pub fn obs_position_bound(&self) -> f64 {
        let b = self.scenario.scene.bounds;
        ((b[2] - b[0]).hypot(b[3] - b[1])).ceil()
    }

    /// Updates the ground-truth o-spaces, interactions and object activities of this instant.
    pub(super) fn observe_interactions(&mut self) {
        interactions(
            &self.crowd.pos,
            &self.crowd.vel,
            &self.crowd.group,
            &self.interaction_objects,
            &mut self.now.ospaces,
            &mut self.now.links,
        );
        let tod = self.time_of_day();
        self.social.object_activity(tod, &mut self.now.active);
    }
}
