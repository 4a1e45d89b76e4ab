//! Episode metrics (definitions: `design/metrics.md`).
//!
//! While an episode runs, an [`EpisodeRecorder`] per robot keeps what the post-hoc evaluator
//! [`trajectory::evaluate`] needs (the robot's poses, the people's tracks, the groups' o-spaces and
//! the interaction segments, the object spaces' activity, the contacts per step) and decides the
//! episode's [`Outcome`] step by step with the same rules the evaluator applies afterwards, so
//! the env's termination flags and the final [`FullMetrics`] always agree. At the end,
//! [`EpisodeRecorder::evaluate`] gives the full metric set ([`EpisodeReport`]).
//!
//! Groups and interactions are the scenario's ground truth, the same for every planner:
//! - a group is the people sharing a `group` id; it has an o-space while it stands gathered:
//!   the largest set of its members standing still (speed below [`STILL_SPEED`]) within
//!   [`GATHERED_RADIUS`] of their mean position, when it has two or more. The o-space is the
//!   circle centred on their mean position through their mean distance to it (Kendon's o-space
//!   as the space the members enclose). Members still walking to their places, or spread over
//!   the floor waiting for their conversation to start, or a tour on the move, form none (an
//!   F-formation is a standing arrangement);
//! - a person-person interaction is the segment between two members of a gathered group;
//! - a person-object interaction is the segment from a person standing still (speed below
//!   [`STILL_SPEED`]) inside an object's interaction space to the object's centre (a visitor
//!   looking at a painting, a senior watching the TV).

pub mod trajectory;

use serde::Serialize;

use crate::error::Result;
use crate::math::Vec2;
pub use trajectory::{
    CONTACT_PERSON, CONTACT_ROBOT, CONTACT_STATIC, EvalContext, FullMetrics, Groups, InteractionLink,
    LinkKind, MetricParams, OSpace, ObjectSpaces, PeopleTracks, Trajectory, evaluate,
};

/// A person moving slower than this (m/s) counts as standing still, for o-spaces and
/// person-object interactions.
pub const STILL_SPEED: f64 = 0.1;

/// Members of a group standing farther than this (m) from the mean position of its still members
/// are not part of its o-space: Hall's social-zone radius of 3.6 m between two people who still
/// talk means at most 1.8 m from their centre; 2.0 m leaves room for larger circles.
pub const GATHERED_RADIUS: f64 = 2.0;

/// How an episode ended for a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Still running.
    Running,
    /// Reached the goal.
    Success,
    /// Collided with a person, the static geometry or another robot.
    Collision,
    /// Ran out of time.
    Timeout,
}

/// A robot's episode metrics: the outcome and every metric of [`FullMetrics`] (flattened when
/// serialised, one key per metric).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EpisodeReport {
    /// How the episode ended (`running` while it runs).
    pub outcome: Outcome,
    /// Episode duration so far (s): control steps times the control period.
    pub duration: f64,
    /// Daza et al. 2021's D_A* (m): length of the plain A* path from the episode's start to the
    /// goal, planned by the world at reset (the denominator of nothing, the numerator of
    /// `l_ratio`).
    pub astar_length: f64,
    /// Geodesic (shortest collision-free) start-goal length `l*` (m) of `path_length_ratio` and
    /// `spl`; `None` when unreachable.
    pub geodesic_length: Option<f64>,
    /// Smallest surface gap to another robot over the episode's instants (m; negative means
    /// overlap; `None` for a robot alone).
    pub min_robot_gap: Option<f64>,
    /// Every metric.
    #[serde(flatten)]
    pub metrics: FullMetrics,
}

/// What stays fixed over a robot's episode.
#[derive(Clone, Debug)]
pub struct RecorderSetup {
    /// Control period (s), > 0.
    pub dt: f64,
    /// Robot disc radius (m).
    pub robot_radius: f64,
    /// Goal position (m).
    pub goal: Vec2,
    /// Success radius around the goal (m, robot centre).
    pub success_radius: f64,
    /// People's disc radii (m).
    pub people_radii: Vec<f64>,
    /// Objects' interaction polygons (world frame, m).
    pub object_polygons: Vec<Vec<Vec2>>,
    /// The plain A* path from the start to the goal (Daza et al. 2021's reference path).
    pub astar_path: Vec<Vec2>,
    /// Geodesic start-goal length (m); `f64::INFINITY` when unreachable.
    pub geodesic_length: f64,
}

/// What the world looks like at one control instant.
#[derive(Clone, Copy, Debug)]
pub struct Snapshot<'a> {
    /// Robot pose `[x, y, theta]` (m, m, rad).
    pub pose: [f64; 3],
    /// People's centres (m).
    pub positions: &'a [Vec2],
    /// People's velocities (m/s).
    pub velocities: &'a [Vec2],
    /// People's headings (rad).
    pub headings: &'a [f64],
    /// The groups' o-spaces at this instant.
    pub ospaces: &'a [OSpace],
    /// The interaction segments at this instant.
    pub links: &'a [InteractionLink],
    /// Per object polygon, whether its activity is on.
    pub active: &'a [bool],
}

/// Records one robot's episode and decides its outcome (see the module documentation).
#[derive(Clone, Debug)]
pub struct EpisodeRecorder {
    setup: RecorderSetup,
    poses: Vec<[f64; 3]>,
    positions: Vec<Vec2>,
    velocities: Vec<Vec2>,
    headings: Vec<f64>,
    ospace_offsets: Vec<usize>,
    ospaces: Vec<OSpace>,
    link_offsets: Vec<usize>,
    links: Vec<InteractionLink>,
    active: Vec<bool>,
    contacts: Vec<u8>,
    min_robot_gap: f64,
    outcome: Outcome,
}

impl EpisodeRecorder {
    /// Starts an episode at the instant `start` (instant 0).
    pub fn new(setup: RecorderSetup, start: &Snapshot) -> Self {
        let mut r = EpisodeRecorder {
            setup,
            poses: Vec::new(),
            positions: Vec::new(),
            velocities: Vec::new(),
            headings: Vec::new(),
            ospace_offsets: vec![0],
            ospaces: Vec::new(),
            link_offsets: vec![0],
            links: Vec::new(),
            active: Vec::new(),
            contacts: Vec::new(),
            min_robot_gap: f64::INFINITY,
            outcome: Outcome::Running,
        };
        r.push(start);
        r
    }

    /// Starts a new episode as [`EpisodeRecorder::new`] does, keeping the buffers' memory (a
    /// world reuses its robots' recorders from episode to episode).
    pub fn restart(&mut self, setup: RecorderSetup, start: &Snapshot) {
        self.setup = setup;
        self.poses.clear();
        self.positions.clear();
        self.velocities.clear();
        self.headings.clear();
        self.ospace_offsets.clear();
        self.ospace_offsets.push(0);
        self.ospaces.clear();
        self.link_offsets.clear();
        self.link_offsets.push(0);
        self.links.clear();
        self.active.clear();
        self.contacts.clear();
        self.min_robot_gap = f64::INFINITY;
        self.outcome = Outcome::Running;
        self.push(start);
    }

    fn push(&mut self, s: &Snapshot) {
        let np = self.setup.people_radii.len();
        let nm = self.setup.object_polygons.len();
        self.poses.push(s.pose);
        // Sizes come from the world, which builds the snapshot from the same crowd and objects;
        // pad or cut defensively so the evaluator's length checks always hold.
        let fill = |dst: &mut Vec<Vec2>, src: &[Vec2]| {
            dst.extend((0..np).map(|i| src.get(i).copied().unwrap_or_else(Vec2::zeros)));
        };
        fill(&mut self.positions, s.positions);
        fill(&mut self.velocities, s.velocities);
        self.headings.extend((0..np).map(|i| s.headings.get(i).copied().unwrap_or(0.0)));
        self.ospaces.extend_from_slice(s.ospaces);
        self.ospace_offsets.push(self.ospaces.len());
        self.links.extend_from_slice(s.links);
        self.link_offsets.push(self.links.len());
        self.active.extend((0..nm).map(|k| s.active.get(k).copied().unwrap_or(false)));
    }

    /// Notes the surface gap (m) to the closest other robot at an instant (for `min_robot_gap`;
    /// a negative gap is a robot-robot collision, which the caller reports as `CONTACT_ROBOT`).
    pub fn observe_robot_gap(&mut self, gap: f64) {
        self.min_robot_gap = self.min_robot_gap.min(gap);
    }

    /// Adds one control step ending at `s`, with the physics' `CONTACT_*` bits of the step;
    /// returns the outcome after it. A collision (physics contact, or a negative surface gap to a
    /// person anywhere on the relative motion swept over the step) ends the episode before the
    /// goal does; the goal before the time limit. Steps after the end are ignored.
    pub fn record(&mut self, s: &Snapshot, contacts: u8, out_of_time: bool) -> Outcome {
        if self.outcome != Outcome::Running {
            return self.outcome;
        }
        let np = self.setup.people_radii.len();
        let prev_t = self.poses.len() - 1;
        let prev = self.poses[prev_t];
        self.push(s);
        let (p0, p1) = (Vec2::new(prev[0], prev[1]), Vec2::new(s.pose[0], s.pose[1]));
        let rr = self.setup.robot_radius;
        let swept = (0..np).any(|i| {
            let a = self.positions[prev_t * np + i] - p0;
            let b = self.positions[(prev_t + 1) * np + i] - p1;
            trajectory::origin_to_segment(a, b) - rr - self.setup.people_radii[i] < 0.0
        });
        let bits = contacts | if swept { CONTACT_PERSON } else { 0 };
        self.contacts.push(bits);
        self.outcome = if bits != 0 {
            Outcome::Collision
        } else if (p1 - self.setup.goal).norm() <= self.setup.success_radius {
            Outcome::Success
        } else if out_of_time {
            Outcome::Timeout
        } else {
            Outcome::Running
        };
        self.outcome
    }

    /// The outcome so far.
    pub fn outcome(&self) -> Outcome {
        self.outcome
    }

    /// Control steps recorded.
    pub fn steps(&self) -> usize {
        self.poses.len() - 1
    }

    /// The recorded robot poses `[x, y, theta]`, instant 0 first.
    pub fn poses(&self) -> &[[f64; 3]] {
        &self.poses
    }

    /// The plain A* reference path.
    pub fn astar_path(&self) -> &[Vec2] {
        &self.setup.astar_path
    }

    /// Evaluates the recording: every metric of [`FullMetrics`], with `clearance` the distance
    /// from a point to the static geometry (m) and `zones` the Hall zone radii (m, centre
    /// distance: intimate, personal, social).
    ///
    /// # Errors
    /// [`crate::error::CoreError::Input`] from [`evaluate`] when a recorded value is not finite
    /// or the zones are not non-decreasing.
    pub fn evaluate(
        &self,
        clearance: &dyn Fn(Vec2) -> f64,
        zones: [f64; 3],
        params: MetricParams,
    ) -> Result<EpisodeReport> {
        let s = &self.setup;
        let traj = Trajectory {
            dt: s.dt,
            robot: &self.poses,
            robot_radius: s.robot_radius,
            goal: s.goal,
            success_radius: s.success_radius,
        };
        let people = PeopleTracks {
            positions: &self.positions,
            velocities: &self.velocities,
            headings: &self.headings,
            radii: &s.people_radii,
            count: s.people_radii.len(),
        };
        let groups = Groups {
            ospace_offsets: &self.ospace_offsets,
            ospaces: &self.ospaces,
            link_offsets: &self.link_offsets,
            links: &self.links,
        };
        let objects = ObjectSpaces { polygons: &s.object_polygons, active: &self.active };
        let ctx = EvalContext {
            geodesic_length: s.geodesic_length,
            astar_path: &s.astar_path,
            clearance,
            zones,
            collision_steps: &self.contacts,
            params,
        };
        let metrics = evaluate(&traj, &people, &groups, &objects, &ctx)?;
        let astar_length = s.astar_path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        Ok(EpisodeReport {
            outcome: self.outcome,
            duration: self.steps() as f64 * s.dt,
            astar_length,
            geodesic_length: s.geodesic_length.is_finite().then_some(s.geodesic_length),
            min_robot_gap: self.min_robot_gap.is_finite().then_some(self.min_robot_gap),
            metrics,
        })
    }
}

/// An object whose interaction space people use, for [`interactions`].
#[derive(Clone, Debug)]
pub struct InteractionObject {
    /// Interaction polygon (world frame, m).
    pub polygon: Vec<Vec2>,
    /// The object's centre (m), the far end of a person-object interaction segment.
    pub centre: Vec2,
}

/// The ground-truth o-spaces and interaction segments of one instant (see the module
/// documentation): `groups[i]` is person `i`'s group id, if any.
pub fn interactions(
    positions: &[Vec2],
    velocities: &[Vec2],
    groups: &[Option<u32>],
    objects: &[InteractionObject],
    ospaces: &mut Vec<OSpace>,
    links: &mut Vec<InteractionLink>,
) {
    ospaces.clear();
    links.clear();
    // The still group members by group id (then index): one pass over the people.
    let mut still_members: Vec<(u32, usize)> = groups
        .iter()
        .enumerate()
        .filter_map(|(i, g)| g.filter(|_| velocities[i].norm() < STILL_SPEED).map(|id| (id, i)))
        .collect();
    still_members.sort_unstable();
    for same in still_members.chunk_by(|a, b| a.0 == b.0) {
        if same.len() < 2 {
            continue;
        }
        let still: Vec<usize> = same.iter().map(|&(_, i)| i).collect();
        // The largest gathering: around each still member, the still members within a circle's
        // diameter of it, kept if within the radius of their mean position.
        let mut members: Vec<usize> = Vec::new();
        for &i in &still {
            let near: Vec<usize> = still
                .iter()
                .copied()
                .filter(|&j| (positions[j] - positions[i]).norm() <= 2.0 * GATHERED_RADIUS)
                .collect();
            let mean = near.iter().fold(Vec2::zeros(), |a, &j| a + positions[j]) / near.len() as f64;
            let kept: Vec<usize> =
                near.into_iter().filter(|&j| (positions[j] - mean).norm() <= GATHERED_RADIUS).collect();
            if kept.len() > members.len() {
                members = kept;
            }
        }
        if members.len() < 2 {
            continue;
        }
        let centre = members.iter().fold(Vec2::zeros(), |a, &i| a + positions[i]) / members.len() as f64;
        let radius =
            members.iter().map(|&i| (positions[i] - centre).norm()).sum::<f64>() / members.len() as f64;
        ospaces.push(OSpace { centre, radius });
        for (k, &i) in members.iter().enumerate() {
            for &j in &members[k + 1..] {
                links.push(InteractionLink {
                    a: positions[i],
                    b: positions[j],
                    kind: LinkKind::PersonPerson,
                });
            }
        }
    }
    for (&q, v) in positions.iter().zip(velocities) {
        if v.norm() >= STILL_SPEED {
            continue;
        }
        for o in objects {
            if trajectory::inside_polygon(q, &o.polygon) {
                links.push(InteractionLink { a: q, b: o.centre, kind: LinkKind::PersonObject });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(radii: Vec<f64>) -> RecorderSetup {
        RecorderSetup {
            dt: 0.1,
            robot_radius: 0.25,
            goal: Vec2::new(3.0, 4.0),
            success_radius: 0.3,
            people_radii: radii,
            object_polygons: vec![],
            astar_path: vec![Vec2::zeros(), Vec2::new(3.0, 0.0), Vec2::new(3.0, 4.0)],
            geodesic_length: 7.0,
        }
    }

    fn snap<'a>(x: f64, y: f64, people: &'a [Vec2], zeros: &'a [Vec2], h: &'a [f64]) -> Snapshot<'a> {
        Snapshot {
            pose: [x, y, 0.0],
            positions: people,
            velocities: zeros,
            headings: h,
            ospaces: &[],
            links: &[],
            active: &[],
        }
    }

    #[test]
    fn hand_computed_episode_reaches_the_goal() {
        // (0,0) -> (3,0) -> (3,4): path 7 m = the A* path, so L_ratio = 1; person at (1.5, 1)
        // is 1.0 m from the robot at no sample but (1.5, 0) lies between samples: d_min is over
        // the samples, (0,0) and (3,0) are both sqrt(1.5² + 1) = 1.803 m away.
        let far = [Vec2::new(1.5, 1.0)];
        let z = [Vec2::zeros()];
        let h = [0.0];
        let mut rec = EpisodeRecorder::new(setup(vec![0.2]), &snap(0.0, 0.0, &far, &z, &h));
        assert_eq!(rec.record(&snap(3.0, 0.0, &far, &z, &h), 0, false), Outcome::Running);
        assert_eq!(rec.record(&snap(3.0, 4.0, &far, &z, &h), 0, false), Outcome::Success);
        // ignored after the end
        assert_eq!(rec.record(&snap(9.0, 9.0, &far, &z, &h), CONTACT_STATIC, true), Outcome::Success);
        let r = rec.evaluate(&|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default()).expect("valid");
        assert_eq!(r.outcome, Outcome::Success);
        assert_eq!(r.metrics.steps, 2);
        assert!((r.metrics.path_length - 7.0).abs() < 1e-12);
        assert!((r.astar_length - 7.0).abs() < 1e-12);
        assert!((r.metrics.l_ratio.expect("success") - 1.0).abs() < 1e-12);
        assert!((r.metrics.time_to_goal.expect("success") - 0.2).abs() < 1e-12);
        assert!((r.duration - 0.2).abs() < 1e-12);
        let dmin = r.metrics.d_min[0].expect("sampled");
        assert!((dmin - 3.25f64.sqrt()).abs() < 1e-12);
        assert_eq!(r.geodesic_length, Some(7.0));
    }

    #[test]
    fn swept_contact_ends_the_episode_as_the_evaluator_counts_it() {
        // The robot jumps from (0,0) to (2,0) through a person at (1,0): no sample overlaps, the
        // swept relative motion does; the recorder stops and the evaluator agrees (hc = 1).
        let p = [Vec2::new(1.0, 0.0)];
        let z = [Vec2::zeros()];
        let h = [0.0];
        let mut rec = EpisodeRecorder::new(setup(vec![0.2]), &snap(0.0, 0.0, &p, &z, &h));
        assert_eq!(rec.record(&snap(2.0, 0.0, &p, &z, &h), 0, false), Outcome::Collision);
        let r = rec.evaluate(&|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default()).expect("valid");
        assert!(r.metrics.hc && r.metrics.collision && !r.metrics.success && !r.metrics.timeout);
        assert_eq!(r.metrics.hc_count, 1);
        assert_eq!(r.metrics.l_ratio, None);
    }

    #[test]
    fn a_restarted_recorder_equals_a_new_one() {
        let far = [Vec2::new(1.5, 1.0)];
        let near = [Vec2::new(0.3, 0.0)];
        let z = [Vec2::zeros()];
        let h = [0.0];
        let mut old = EpisodeRecorder::new(setup(vec![0.2]), &snap(0.0, 0.0, &near, &z, &h));
        old.observe_robot_gap(-0.1);
        old.record(&snap(0.1, 0.0, &near, &z, &h), CONTACT_STATIC, false);
        old.restart(setup(vec![0.2]), &snap(0.0, 0.0, &far, &z, &h));
        let mut new = EpisodeRecorder::new(setup(vec![0.2]), &snap(0.0, 0.0, &far, &z, &h));
        for rec in [&mut old, &mut new] {
            assert_eq!(rec.record(&snap(3.0, 0.0, &far, &z, &h), 0, false), Outcome::Running);
            assert_eq!(rec.record(&snap(3.0, 4.0, &far, &z, &h), 0, false), Outcome::Success);
        }
        let eval = |r: &EpisodeRecorder| {
            let rep =
                r.evaluate(&|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default()).expect("valid");
            serde_json::to_string(&rep).expect("json")
        };
        assert_eq!(eval(&old), eval(&new));
    }

    #[test]
    fn contact_bits_and_timeout() {
        let z: [Vec2; 0] = [];
        let mut rec = EpisodeRecorder::new(setup(vec![]), &snap(0.0, 0.0, &z, &z, &[]));
        assert_eq!(rec.record(&snap(0.1, 0.0, &z, &z, &[]), 0, true), Outcome::Timeout);
        let r = rec.evaluate(&|_| 1.0, [0.45, 1.2, 3.6], MetricParams::default()).expect("valid");
        assert!(r.metrics.timeout);
        let mut rec = EpisodeRecorder::new(setup(vec![]), &snap(0.0, 0.0, &z, &z, &[]));
        assert_eq!(rec.record(&snap(0.1, 0.0, &z, &z, &[]), CONTACT_STATIC, false), Outcome::Collision);
        let r = rec.evaluate(&|_| 1.0, [0.45, 1.2, 3.6], MetricParams::default()).expect("valid");
        assert!(r.metrics.wc && !r.metrics.hc);
    }

    #[test]
    fn ground_truth_groups_and_object_interactions() {
        // A pair (group 7) 2 m apart, a lone walker, a still viewer inside a square space.
        let pos = [Vec2::new(0.0, 0.0), Vec2::new(2.0, 0.0), Vec2::new(5.0, 5.0), Vec2::new(10.5, 0.5)];
        let vel = [Vec2::zeros(), Vec2::zeros(), Vec2::new(1.0, 0.0), Vec2::new(0.05, 0.0)];
        let groups = [Some(7), Some(7), None, None];
        let square =
            vec![Vec2::new(10.0, 0.0), Vec2::new(11.0, 0.0), Vec2::new(11.0, 1.0), Vec2::new(10.0, 1.0)];
        let objects = [InteractionObject { polygon: square, centre: Vec2::new(10.5, -0.5) }];
        let (mut os, mut ls) = (Vec::new(), Vec::new());
        interactions(&pos, &vel, &groups, &objects, &mut os, &mut ls);
        assert_eq!(os, vec![OSpace { centre: Vec2::new(1.0, 0.0), radius: 1.0 }]);
        assert_eq!(ls.len(), 2);
        assert_eq!(ls[0].kind, LinkKind::PersonPerson);
        assert_eq!((ls[0].a, ls[0].b), (pos[0], pos[1]));
        assert_eq!(ls[1].kind, LinkKind::PersonObject);
        assert_eq!((ls[1].a, ls[1].b), (pos[3], Vec2::new(10.5, -0.5)));
        // The viewer walking away is no longer interacting.
        let vel2 = [Vec2::zeros(), Vec2::zeros(), Vec2::zeros(), Vec2::new(0.5, 0.0)];
        interactions(&pos, &vel2, &groups, &objects, &mut os, &mut ls);
        assert_eq!(ls.len(), 1);
    }

    #[test]
    fn a_group_has_an_o_space_only_while_it_stands_gathered() {
        // Group 3: two members standing 1.2 m apart, a third still far away (waiting at home).
        let pos = [Vec2::new(0.0, 0.0), Vec2::new(1.2, 0.0), Vec2::new(12.0, 0.0)];
        let still = [Vec2::zeros(); 3];
        let groups = [Some(3), Some(3), Some(3)];
        let (mut os, mut ls) = (Vec::new(), Vec::new());
        interactions(&pos, &still, &groups, &[], &mut os, &mut ls);
        // The far member is left out: the o-space is the pair's, not a 6 m circle over the floor.
        assert_eq!(os, vec![OSpace { centre: Vec2::new(0.6, 0.0), radius: 0.6 }]);
        assert_eq!(ls.len(), 1);
        // Members spread over the floor (waiting for their conversation): no o-space.
        let spread = [Vec2::new(0.0, 0.0), Vec2::new(7.0, 0.0), Vec2::new(14.0, 0.0)];
        interactions(&spread, &still, &groups, &[], &mut os, &mut ls);
        assert!(os.is_empty() && ls.is_empty());
        // Walking together (a tour on the move): no o-space either.
        let walking = [Vec2::new(0.8, 0.0); 3];
        interactions(&pos, &walking, &groups, &[], &mut os, &mut ls);
        assert!(os.is_empty() && ls.is_empty());
    }
}
