//! Who hit whom: every contact of the robot, classified and counted as events (the
//! `collisions_*` keys of `docs/metrics.md`).
//!
//! SEAN 2.0 (Tsoi et al. 2022, "SEAN 2.0: Formalizing and Generating Social Situations for Robot
//! Navigation") and HuNavSim (Pérez-Higueras et al. 2023, its evaluator's `robot_on_person_collision`
//! and `person_on_robot_collision`) count robot-on-person collisions apart from person-on-robot
//! ones, and collisions with static obstacles apart from both. HuNavSim calls a contact the
//! robot's when it faces the person more squarely and moves faster than the person. Our rule
//! asks one question instead, which does not need the robot's heading (a holonomic base can
//! drive sideways) nor the person's: **was the robot moving toward the person?**
//!
//! - A step touches person `i` when the swept relative motion of the two discs overlaps
//!   (CrowdNav's test, as `hc_count` counts it), or when the physics reports a person contact and
//!   the person's surface gap at the end of the step is at most [`PHYSICS_CONTACT_GAP`] (the
//!   physics does not say which person it was: the nearest one when none is that close).
//! - The touch is the **robot's fault** when the component of the robot's velocity over the step
//!   along the direction robot → person (centres, at the start of the step) is above
//!   [`STOPPED_SPEED`]; otherwise the **person's fault** (the person moved into a robot that was
//!   stopped, or moving away or past them slower than that).
//! - A **contact event** with a person is a maximal run of consecutive steps touching them; it is
//!   counted once, at its onset, as the robot's fault if any of its steps is (such a step ends the
//!   episode), else as the person's. A static contact event is a maximal run of steps with the
//!   physics' static bit.
//! - Robot-robot contacts are not split: they stay in `ac_count` and end the episode for both
//!   robots, as before.
//!
//! A robot-at-fault contact ends the episode and fails success like a static or robot contact;
//! a person-at-fault contact is counted (and in `hc_count`) but does not end the episode nor fail
//! success: a robot standing still that is walked into is not scored like one that drives into
//! someone.

use serde::Serialize;

use super::collisions::swept_gap;
use super::{CONTACT_PERSON, CONTACT_STATIC, PeopleTracks, Samples, Trajectory};
use crate::math::{EPS, Vec2};

/// Speed (m/s) of the robot toward a person below which a contact is the person's fault: the
/// robot counts as stopped (or moving away) at that contact. 0.05 m/s is 5 cm per second, below
/// any commanded motion of the built-in planners and above the physics' settling drift.
pub const STOPPED_SPEED: f64 = 0.05;

/// Largest surface gap (m) at the end of a step at which a person counts as the one the
/// physics' person contact touched (the physics' capsules and the metric discs share radii;
/// the margin covers the motion within the step).
pub const PHYSICS_CONTACT_GAP: f64 = 0.05;

/// How the robot touched one person over one step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Touch {
    /// No contact.
    None,
    /// The robot moved toward the person faster than [`STOPPED_SPEED`].
    RobotFault,
    /// The person moved into a robot that was stopped or moving away.
    PersonFault,
}

/// One step's robot motion and the people before and after it.
pub(crate) struct StepContact<'a> {
    /// Robot centre at the start of the step (m).
    pub p0: Vec2,
    /// Robot centre at the end of the step (m).
    pub p1: Vec2,
    /// Robot velocity over the step (m/s), `(p1 - p0) / dt`.
    pub vel: Vec2,
    /// Robot radius (m).
    pub robot_radius: f64,
    /// People's centres at the start of the step (m).
    pub before: &'a [Vec2],
    /// People's centres at the end of the step (m).
    pub after: &'a [Vec2],
    /// People's radii (m).
    pub radii: &'a [f64],
    /// Whether the physics reported a person contact over the step.
    pub physics_person: bool,
    /// Whether each person is in the scene at the start and at the end of the step (empty:
    /// everyone is). A person absent at either instant (a replayed person appearing, leaving or
    /// parked) is neither swept past nor touched: their jump is not a motion.
    pub present_before: &'a [bool],
    /// As `present_before`, at the end of the step.
    pub present_after: &'a [bool],
}

impl StepContact<'_> {
    /// Whether person `i` is in the scene over the whole step.
    pub(crate) fn here(&self, i: usize) -> bool {
        self.present_before.get(i).copied().unwrap_or(true)
            && self.present_after.get(i).copied().unwrap_or(true)
    }
}

/// The touch of every person over one step, into `out` (cleared first; one entry per person).
pub(crate) fn classify_step(s: &StepContact, out: &mut Vec<Touch>) {
    out.clear();
    let np = s.radii.len().min(s.before.len()).min(s.after.len());
    let gaps = |i: usize| (s.after[i] - s.p1).norm() - s.robot_radius - s.radii[i];
    let mut any = false;
    for i in 0..np {
        if !s.here(i) {
            out.push(Touch::None);
            continue;
        }
        let swept = swept_gap(s.p0, s.p1, s.before[i], s.after[i], s.robot_radius, s.radii[i]) < 0.0;
        let touching = swept || (s.physics_person && gaps(i) <= PHYSICS_CONTACT_GAP);
        any |= touching;
        out.push(if touching { fault(s, i) } else { Touch::None });
    }
    if s.physics_person && !any {
        // The physics touched someone the discs do not show: the nearest person among everyone
        // the physics stepped (the people as they stood at the step's start). A replayed person
        // leaving in the step is measured from where they stood to the robot's path over the
        // step (`leaving_gap`); one appearing at its end was parked for the physics. When the
        // nearest is a person leaving, the contact was theirs and counts for no one.
        let was = |i: usize| s.present_before.get(i).copied().unwrap_or(true);
        let gap = |i: usize| match (was(i), s.here(i)) {
            (true, true) => Some(gaps(i)),
            (true, false) => Some(leaving_gap(s, i)),
            (false, _) => None,
        };
        let nearest = (0..np).filter_map(|i| gap(i).map(|g| (g, i))).min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, i)) = nearest.filter(|&(_, i)| s.here(i)) {
            out[i] = fault(s, i);
        }
    }
}

/// Surface gap (m) from person `i` where they stood at the start of the step to the robot's
/// path over it (the robot moving linearly from `p0` to `p1`): how close the physics, which steps
/// the robot among the people as they stood at the step's start, brought them.
pub(crate) fn leaving_gap(s: &StepContact, i: usize) -> f64 {
    crate::geom::distance_point_segment(s.before[i], s.p0, s.p1) - s.robot_radius - s.radii[i]
}

/// Whose fault the contact with person `i` over the step is; the same rule says who approached
/// whom when the robot enters a person's zone ([`super::approach`]).
pub(crate) fn fault(s: &StepContact, i: usize) -> Touch {
    // Direction robot -> person at the start of the step (before the bodies met), else at its
    // end; with both centres coincident, any motion counts as toward.
    let dir = [s.before[i] - s.p0, s.after[i] - s.p1].into_iter().find(|d| d.norm() > EPS);
    let toward = match dir {
        Some(d) => s.vel.dot(&d) / d.norm(),
        None => s.vel.norm(),
    };
    if toward > STOPPED_SPEED { Touch::RobotFault } else { Touch::PersonFault }
}

/// The contact events of an episode by fault.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FaultMetrics {
    /// Contact events with a person in which the robot moved toward them faster than
    /// [`STOPPED_SPEED`] (count; at most one in an episode, which it ends).
    pub collisions_robot_fault: usize,
    /// Contact events with a person who moved into the robot while it was stopped or moving away
    /// (count; these do not end the episode).
    pub collisions_person_fault: usize,
    /// Contact events with walls or furniture (count; the physics' static bit, the onset of each
    /// run of steps with it).
    pub collisions_static: usize,
}

/// Per step of the recording, the touches of every person (row-major, `T * P`), the whole
/// episode classified as [`classify_step`] does step by step.
pub(crate) fn touches(s: &Samples, traj: &Trajectory, people: &PeopleTracks, contacts: &[u8]) -> Vec<Touch> {
    let np = people.count;
    let mut all = Vec::with_capacity(s.steps * np);
    let mut row = Vec::with_capacity(np);
    for k in 0..s.steps {
        classify_step(&step_contact(s, traj, people, contacts, k), &mut row);
        all.extend_from_slice(&row);
    }
    all
}

/// Step `k` of the recording (`k < s.steps`): the robot's motion, the people before and after
/// it, and the physics' person contact bit of `contacts`.
pub(crate) fn step_contact<'a>(
    s: &Samples,
    traj: &Trajectory,
    people: &'a PeopleTracks,
    contacts: &[u8],
    k: usize,
) -> StepContact<'a> {
    let np = people.count;
    let bits = contacts.get(k).copied().unwrap_or(0);
    StepContact {
        p0: s.pos[k],
        p1: s.pos[k + 1],
        vel: s.vel[k],
        robot_radius: traj.robot_radius,
        before: &people.positions[k * np..(k + 1) * np],
        after: &people.positions[(k + 1) * np..(k + 2) * np],
        radii: people.radii,
        physics_person: bits & CONTACT_PERSON != 0,
        present_before: people.present.get(k * np..(k + 1) * np).unwrap_or(&[]),
        present_after: people.present.get((k + 1) * np..(k + 2) * np).unwrap_or(&[]),
    }
}

/// The contact events of the recording from its per-step `touches` ([`touches`]) and the
/// physics' `contacts` bits per step.
pub(crate) fn evaluate(steps: usize, np: usize, touches: &[Touch], contacts: &[u8]) -> FaultMetrics {
    let (mut robot_fault, mut person_fault, mut statics) = (0usize, 0usize, 0usize);
    // Per person: the fault of the contact event under way (None between events).
    let mut open: Vec<Touch> = vec![Touch::None; np];
    let mut static_before = false;
    for k in 0..steps {
        for (i, run) in open.iter_mut().enumerate() {
            let now = touches.get(k * np + i).copied().unwrap_or(Touch::None);
            match (*run, now) {
                (_, Touch::None) => *run = Touch::None,
                (Touch::None, t) => {
                    *run = t;
                    if t == Touch::RobotFault { robot_fault += 1 } else { person_fault += 1 }
                }
                // An event the person started turns into the robot's when it drives on into them.
                (Touch::PersonFault, Touch::RobotFault) => {
                    *run = Touch::RobotFault;
                    person_fault -= 1;
                    robot_fault += 1;
                }
                _ => {}
            }
        }
        let st = contacts.get(k).is_some_and(|b| b & CONTACT_STATIC != 0);
        statics += usize::from(st && !static_before);
        static_before = st;
    }
    FaultMetrics {
        collisions_robot_fault: robot_fault,
        collisions_person_fault: person_fault,
        collisions_static: statics,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{
        EpisodeRecorder, EpisodeReport, MetricParams, Outcome, RecorderSetup, SceneLog, Snapshot,
    };

    /// A robot (radius 0.25 m) starting at the origin with its goal at (3, 0), among people of
    /// radius 0.2 m whose positions the test scripts step by step.
    struct Run {
        log: SceneLog,
        rec: EpisodeRecorder,
    }

    fn snapshot(people: &[Vec2]) -> Snapshot<'_> {
        static ZEROS: [Vec2; 2] = [Vec2::new(0.0, 0.0); 2];
        static HEADINGS: [f64; 2] = [0.0; 2];
        let n = people.len();
        Snapshot {
            positions: people,
            velocities: &ZEROS[..n],
            headings: &HEADINGS[..n],
            ospaces: &[],
            links: &[],
            active: &[],
            present: &[],
        }
    }

    impl Run {
        fn new(people: &[Vec2]) -> Self {
            let setup = RecorderSetup {
                dt: 0.1,
                robot_radius: 0.25,
                goal: Vec2::new(3.0, 0.0),
                success_radius: 0.1,
                astar_path: vec![Vec2::zeros(), Vec2::new(3.0, 0.0)],
                geodesic_length: 3.0,
                episode: "test".into(),
            };
            let mut log = SceneLog::new(vec![0.2; people.len()], vec![]);
            log.push(&snapshot(people));
            Run { log, rec: EpisodeRecorder::new(setup, [0.0; 3]) }
        }

        /// The people move to `people`, the robot to (x, 0), with the physics' `bits`.
        fn step(&mut self, people: &[Vec2], x: f64, bits: u8) -> Outcome {
            self.log.push(&snapshot(people));
            self.rec.record(&self.log, [x, 0.0, 0.0], bits, false, false)
        }

        fn eval(&self) -> EpisodeReport {
            self.rec
                .evaluate(&self.log, &|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default(), None)
                .expect("valid")
        }
    }

    fn counts(r: &EpisodeReport) -> (usize, usize, usize) {
        let f = &r.metrics.fault;
        (f.collisions_robot_fault, f.collisions_person_fault, f.collisions_static)
    }

    #[test]
    fn a_person_walking_into_a_parked_robot_is_the_persons_fault() {
        // The robot stands at the origin; a person walks in from (1, 0) at 2 m/s, touches it
        // (centre distance 0.4 < 0.45) over three swept steps, walks back out; the robot then drives to
        // its goal: one person-at-fault event, and the episode is a success.
        let mut run = Run::new(&[Vec2::new(1.0, 0.0)]);
        for x in [0.8, 0.6, 0.4, 0.4, 0.8] {
            assert_eq!(run.step(&[Vec2::new(x, 0.0)], 0.0, 0), Outcome::Running, "x = {x}");
        }
        let away = [Vec2::new(0.8, 2.0)];
        for k in 1..=3 {
            run.step(&away, f64::from(k), 0);
        }
        let r = run.eval();
        assert_eq!(counts(&r), (0, 1, 0));
        assert_eq!(r.metrics.collisions.hc_count, 3);
        assert!(r.metrics.collisions.success && !r.metrics.collisions.collision);
        assert_eq!(r.outcome, Outcome::Success);
    }

    #[test]
    fn a_robot_driving_into_a_standing_person_is_the_robots_fault() {
        // The person stands at (1, 0); the robot drives at 2 m/s: at x = 0.6 the gap is -0.05.
        let person = [Vec2::new(1.0, 0.0)];
        let mut run = Run::new(&person);
        assert_eq!(run.step(&person, 0.2, 0), Outcome::Running);
        assert_eq!(run.step(&person, 0.4, 0), Outcome::Running);
        assert_eq!(run.step(&person, 0.6, 0), Outcome::Collision);
        let r = run.eval();
        assert_eq!(counts(&r), (1, 0, 0));
        assert!(r.metrics.collisions.collision && !r.metrics.collisions.success && r.metrics.collisions.hc);
    }

    #[test]
    fn a_slow_approach_is_the_persons_a_fast_one_the_robots() {
        // Both move toward each other; the robot at 0.04 m/s (below STOPPED_SPEED) is not at
        // fault, at 0.5 m/s it is.
        for (v, want) in [(0.04, (0, 1, 0)), (0.5, (1, 0, 0))] {
            let mut run = Run::new(&[Vec2::new(0.5, 0.0)]);
            run.step(&[Vec2::new(0.43, 0.0)], v * 0.1, 0);
            assert_eq!(counts(&run.eval()), want, "robot at {v} m/s");
        }
    }

    #[test]
    fn a_wall_contact_is_static_and_ends_the_episode() {
        let mut run = Run::new(&[Vec2::new(0.0, 5.0)]);
        assert_eq!(run.step(&[Vec2::new(0.0, 5.0)], 0.1, CONTACT_STATIC), Outcome::Collision);
        let r = run.eval();
        assert_eq!(counts(&r), (0, 0, 1));
        assert!(r.metrics.collisions.wc && !r.metrics.collisions.hc && r.metrics.collisions.collision);
    }

    #[test]
    fn the_physics_contact_goes_to_the_nearest_person_and_events_count_onsets() {
        // Two people: the physics reports a person contact; the discs of the first are 0.03 m
        // apart (within PHYSICS_CONTACT_GAP), the second is far. The robot stands: person's
        // fault, one event over two steps, a second one after a step apart.
        let near = [Vec2::new(0.48, 0.0), Vec2::new(-3.0, 0.0)];
        let mut run = Run::new(&near);
        run.step(&near, 0.0, CONTACT_PERSON);
        run.step(&near, 0.0, CONTACT_PERSON);
        run.step(&near, 0.0, 0);
        run.step(&near, 0.0, CONTACT_PERSON);
        let r = run.eval();
        assert_eq!(counts(&r), (0, 2, 0));
        assert_eq!(r.outcome, Outcome::Running);
    }

    #[test]
    fn a_person_appearing_across_the_robot_touches_nobody() {
        // A replayed person parked at (50, 0), ahead of the robot, appears at (-2, 0) behind it
        // while the robot drives toward the parking spot at 1 m/s: their jump sweeps across the
        // robot (and would be the robot's fault), but a jump is no motion. Neither the
        // recorder nor the evaluator counts it (the replayed records once said outcome = success
        // with collisions_robot_fault = 1), and the record is made (its invariants hold).
        let mut run = Run::new(&[Vec2::new(50.0, 0.0)]);
        let snap = |p: &[Vec2], here: bool| -> (Vec<Vec2>, bool) { (p.to_vec(), here) };
        let steps = [snap(&[Vec2::new(50.0, 0.0)], false), snap(&[Vec2::new(-2.0, 0.0)], true)];
        // Instant 0 was logged by Run::new with everyone present: restart the log with the
        // person absent.
        run.log = SceneLog::new(vec![0.2], vec![]);
        let absent = [false];
        let push = |log: &mut SceneLog, p: &[Vec2], present: &[bool]| {
            let mut sn = snapshot(p);
            sn.present = present;
            log.push(&sn);
        };
        push(&mut run.log, &steps[0].0, &absent);
        for (k, (p, here)) in steps.iter().enumerate() {
            push(&mut run.log, p, &[*here]);
            let x = 0.1 * (k + 1) as f64;
            assert_eq!(run.rec.record(&run.log, [x, 0.0, 0.0], 0, false, false), Outcome::Running);
        }
        let r = run.eval();
        assert_eq!(counts(&r), (0, 0, 0));
        assert!(!r.metrics.collisions.hc && !r.metrics.collisions.collision);
    }

    #[test]
    fn a_physics_contact_with_a_person_leaving_touches_nobody() {
        // A replayed person at (0.5, 0), 5 cm from the robot's body, leaves the scene over the
        // step (parked far away at its end) while the physics, which stepped them where they
        // stood, reports a person contact; another person stands 3.5 m ahead. The contact was
        // the leaving person's: nobody is touched (not the person ahead, by the robot's fault),
        // no step has a person contact, the episode runs on and its record is made.
        let mut run = Run::new(&[Vec2::new(0.5, 0.0), Vec2::new(4.0, 0.0)]);
        run.log = SceneLog::new(vec![0.2; 2], vec![]);
        let push = |log: &mut SceneLog, p: &[Vec2], present: &[bool]| {
            let mut sn = snapshot(p);
            sn.present = present;
            log.push(&sn);
        };
        push(&mut run.log, &[Vec2::new(0.5, 0.0), Vec2::new(4.0, 0.0)], &[true, true]);
        push(&mut run.log, &[Vec2::new(50.0, 0.0), Vec2::new(4.0, 0.0)], &[false, true]);
        assert_eq!(run.rec.record(&run.log, [0.1, 0.0, 0.0], CONTACT_PERSON, false, false), Outcome::Running);
        let r = run.eval();
        assert_eq!(counts(&r), (0, 0, 0));
        assert_eq!(r.metrics.collisions.hc_count, 0);
        assert!(!r.metrics.collisions.collision);
    }

    #[test]
    fn a_swept_touch_is_no_physics_contact_for_the_others() {
        // A person walks into the robot from behind (swept overlap, the person's fault) while the
        // robot drives on at 1 m/s toward another person, who ends the step 3 cm from its body
        // without any overlap. No physics contact: the person ahead is not touched, by the
        // recorder nor by the evaluator (which once read the swept overlap as a physics contact
        // and blamed the robot for the person ahead, breaking `outcome_agrees`).
        let mut run = Run::new(&[Vec2::new(-0.5, 0.0), Vec2::new(0.58, 0.0)]);
        assert_eq!(run.step(&[Vec2::new(-0.3, 0.0), Vec2::new(0.58, 0.0)], 0.1, 0), Outcome::Running);
        let r = run.eval();
        assert_eq!(counts(&r), (0, 1, 0));
        assert_eq!(r.metrics.collisions.hc_count, 1);
        assert_eq!(r.outcome, Outcome::Running);
        assert!(r.metrics.collisions.timeout && !r.metrics.collisions.collision);
    }

    #[test]
    fn an_event_the_person_started_is_the_robots_once_it_drives_on() {
        let mut run = Run::new(&[Vec2::new(0.6, 0.0)]);
        // The person steps into the standing robot, then the robot drives on into them.
        assert_eq!(run.step(&[Vec2::new(0.4, 0.0)], 0.0, 0), Outcome::Running);
        assert_eq!(run.step(&[Vec2::new(0.4, 0.0)], 0.1, 0), Outcome::Collision);
        assert_eq!(counts(&run.eval()), (1, 0, 0));
    }
}
