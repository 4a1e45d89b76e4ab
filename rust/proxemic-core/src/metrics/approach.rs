//! Who approached whom in people's zones (the `intimate_gap_*` and `personal_gap_*` keys of
//! `docs/metrics.md`): the time the robot spent in a person's intimate and personal zones and
//! its entries into them, each split into **robot-caused** and **person-caused** by the rule
//! that decides whose fault a contact is ([`super::fault`]): over the step, the component of
//! the robot's velocity along the direction robot → person (centres, at the start of the step)
//! above [`super::fault::STOPPED_SPEED`] (0.05 m/s) makes it the robot's; otherwise the person
//! came to a robot that was stopped, moving away or passing slower than that.
//!
//! The zones are measured on **body gaps** (robot surface to person surface, `s_i,t = d_i,t −
//! r_R − r_i`) against the scene's Hall radii (by default 0.45 m and 1.2 m, the radii of
//! `psi_intimate` and `psi_personal`, which read them on centre distances): the intimate zone is
//! `s < zones[0]`, the personal zone the ring `zones[0] ≤ s < zones[1]`.
//!
//! - A **visit** of person `i`'s zone is a maximal run of steps at whose ends their body gap is
//!   below the zone's outer radius (`zones[0]` for the intimate zone, `zones[1]` for the
//!   personal one). Like a contact event, it is robot-caused from the first of its steps over
//!   which the robot moved toward them, person-caused until then: a person who walks up to a
//!   standing robot makes a person-caused visit, which turns robot-caused if the robot then
//!   drives on toward them; a robot that drives up to someone and parks there keeps its visit
//!   robot-caused while it stands.
//! - **Time** (s): each step `k` whose end (instant `k + 1`) has the closest present person (by
//!   body gap) in the zone adds `dt`, robot-caused or person-caused as that person's visit is at
//!   that step. Per step, not per instant like `psi_*`: the start instant had no motion.
//! - **Entries** (count): the visits that start with the gap crossing the zone's outer radius
//!   inward (at or above it at the step's start, below it at its end; a person met already
//!   inside, at the start or on appearing, is a visit but no entry), per person, robot-caused
//!   when the robot moved toward the person over that step. Entering the intimate zone from
//!   beyond the personal one in one step is an entry into both.
//!
//! A person absent at either end of a step (a replayed person appearing, leaving or parked)
//! counts in neither (the presence test of the fault rule).

use serde::Serialize;

use super::fault::{Touch, fault, step_contact};
use super::{EvalContext, PeopleTracks, Samples, Trajectory};

/// Time in and entries into one zone, robot-caused (index 0) and person-caused (index 1).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct ZoneTally {
    /// Steps in the zone, by the cause of the closest person's visit.
    steps: [usize; 2],
    /// Entries, by who approached whom over the step of the entry.
    entries: [usize; 2],
}

/// The zone time and entries of an episode, robot-caused and person-caused.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ApproachMetrics {
    /// Seconds with the closest present person's body gap below `zones[0]` (the intimate zone),
    /// counted per step at its end (`dt` each); 0 without people.
    pub intimate_gap_time: f64,
    /// The part of `intimate_gap_time` in steps in which the robot moved toward that person
    /// faster than 0.05 m/s (s).
    pub intimate_gap_time_robot_caused: f64,
    /// The rest of `intimate_gap_time`: the robot stopped, moving away or slower (s).
    pub intimate_gap_time_person_caused: f64,
    /// Entries into a person's intimate zone: steps over which a person's body gap fell below
    /// `zones[0]` from at or above it (count, per person).
    pub intimate_gap_entries: usize,
    /// The entries of `intimate_gap_entries` made while the robot moved toward the person faster
    /// than 0.05 m/s (count).
    pub intimate_gap_entries_robot_caused: usize,
    /// The other entries: the person came to the robot (count).
    pub intimate_gap_entries_person_caused: usize,
    /// Seconds with the closest present person's body gap in `[zones[0], zones[1])` (the
    /// personal zone), per step like `intimate_gap_time`.
    pub personal_gap_time: f64,
    /// The robot-caused part of `personal_gap_time` (s).
    pub personal_gap_time_robot_caused: f64,
    /// The person-caused part of `personal_gap_time` (s).
    pub personal_gap_time_person_caused: f64,
    /// Entries into a person's personal zone: steps over which their body gap fell below
    /// `zones[1]` from at or above it (count, per person).
    pub personal_gap_entries: usize,
    /// The robot-caused entries of `personal_gap_entries` (count).
    pub personal_gap_entries_robot_caused: usize,
    /// The person-caused entries of `personal_gap_entries` (count).
    pub personal_gap_entries_person_caused: usize,
}

/// The zone time and entries of the recording `s` among `people`, split by who approached whom.
pub(crate) fn evaluate(
    s: &Samples,
    traj: &Trajectory,
    people: &PeopleTracks,
    ctx: &EvalContext,
) -> ApproachMetrics {
    let (np, rr) = (people.count, traj.robot_radius);
    let radii = [ctx.zones[0], ctx.zones[1]];
    let mut zones = [ZoneTally::default(); 2];
    // Per person and zone, the cause of the visit under way (Touch::None between visits).
    let mut visits = vec![[Touch::None; 2]; np];
    for k in 0..s.steps {
        let step = step_contact(s, traj, people, ctx.collision_steps, k);
        let mut closest: Option<(f64, usize)> = None;
        for (i, visit) in visits.iter_mut().enumerate() {
            if !step.here(i) {
                *visit = [Touch::None; 2];
                continue;
            }
            let gap_before = (step.before[i] - step.p0).norm() - rr - step.radii[i];
            let gap_after = (step.after[i] - step.p1).norm() - rr - step.radii[i];
            let now = fault(&step, i);
            for ((run, tally), r) in visit.iter_mut().zip(zones.iter_mut()).zip(radii) {
                if gap_after >= r {
                    *run = Touch::None;
                    continue;
                }
                if gap_before >= r {
                    tally.entries[cause(now)] += 1;
                }
                // A visit turns robot-caused at the first step the robot approaches.
                if *run != Touch::RobotFault {
                    *run = now;
                }
            }
            if closest.is_none_or(|(g, _)| gap_after < g) {
                closest = Some((gap_after, i));
            }
        }
        if let Some((gap, i)) = closest {
            if gap < radii[0] {
                zones[0].steps[cause(visits[i][0])] += 1;
            } else if gap < radii[1] {
                zones[1].steps[cause(visits[i][1])] += 1;
            }
        }
    }
    let secs = |n: usize| n as f64 * traj.dt;
    let [intimate, personal] = zones;
    ApproachMetrics {
        intimate_gap_time: secs(intimate.steps[0] + intimate.steps[1]),
        intimate_gap_time_robot_caused: secs(intimate.steps[0]),
        intimate_gap_time_person_caused: secs(intimate.steps[1]),
        intimate_gap_entries: intimate.entries[0] + intimate.entries[1],
        intimate_gap_entries_robot_caused: intimate.entries[0],
        intimate_gap_entries_person_caused: intimate.entries[1],
        personal_gap_time: secs(personal.steps[0] + personal.steps[1]),
        personal_gap_time_robot_caused: secs(personal.steps[0]),
        personal_gap_time_person_caused: secs(personal.steps[1]),
        personal_gap_entries: personal.entries[0] + personal.entries[1],
        personal_gap_entries_robot_caused: personal.entries[0],
        personal_gap_entries_person_caused: personal.entries[1],
    }
}

/// Index of a cause in a tally: 0 robot-caused, 1 person-caused.
fn cause(t: Touch) -> usize {
    usize::from(t != Touch::RobotFault)
}

#[cfg(test)]
mod tests {
    use crate::math::Vec2;
    use crate::metrics::{EpisodeRecorder, EpisodeReport, MetricParams, RecorderSetup, SceneLog, Snapshot};

    /// An episode of a robot (radius 0.3 m, goal far away at (10, 0), so it never ends) among one
    /// person (radius 0.22 m), both scripted: the robot's x and the person's centre per step.
    fn run(start: Vec2, steps: &[(f64, Vec2)]) -> EpisodeReport {
        let setup = RecorderSetup {
            dt: 0.1,
            robot_radius: 0.3,
            goal: Vec2::new(10.0, 0.0),
            success_radius: 0.1,
            astar_path: vec![Vec2::zeros(), Vec2::new(10.0, 0.0)],
            geodesic_length: 10.0,
            episode: "approach test".into(),
        };
        let (zero, heading) = ([Vec2::zeros()], [0.0]);
        let mut log = SceneLog::new(vec![0.22], vec![]);
        let push = |log: &mut SceneLog, p: Vec2| {
            let pos = [p];
            log.push(&Snapshot {
                positions: &pos,
                velocities: &zero,
                headings: &heading,
                ospaces: &[],
                links: &[],
                active: &[],
                present: &[],
            });
        };
        push(&mut log, start);
        let mut rec = EpisodeRecorder::new(setup, [0.0; 3]);
        for &(x, p) in steps {
            push(&mut log, p);
            rec.record(&log, [x, 0.0, 0.0], 0, false, false);
        }
        rec.evaluate(&log, &|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default(), None)
            .expect("a record whose invariants hold")
    }

    /// (time, robot-caused, person-caused) in seconds, then (entries, robot, person), intimate
    /// then personal.
    fn tallies(r: &EpisodeReport) -> [(f64, f64, f64, usize, usize, usize); 2] {
        let a = &r.metrics.approach;
        [
            (
                a.intimate_gap_time,
                a.intimate_gap_time_robot_caused,
                a.intimate_gap_time_person_caused,
                a.intimate_gap_entries,
                a.intimate_gap_entries_robot_caused,
                a.intimate_gap_entries_person_caused,
            ),
            (
                a.personal_gap_time,
                a.personal_gap_time_robot_caused,
                a.personal_gap_time_person_caused,
                a.personal_gap_entries,
                a.personal_gap_entries_robot_caused,
                a.personal_gap_entries_person_caused,
            ),
        ]
    }

    fn assert_secs(got: f64, want: f64, what: &str) {
        assert!((got - want).abs() < 1e-9, "{what}: {got} s, want {want} s");
    }

    #[test]
    fn a_robot_driving_up_to_a_standing_person_causes_its_entries_and_time() {
        // The person stands at (3, 0); the robot drives along x at 0.5 m/s (0.05 m a step) to
        // x = 2.3, then stands there 10 steps. Body gap 3 - x - 0.52: the personal zone
        // (gap < 1.2) from x = 1.30 (step 26) to 2.00 (step 40), 15 steps; the intimate zone
        // (gap < 0.45) from x = 2.05 (step 41) to the end, 6 moving steps and 10 standing ones.
        let person = Vec2::new(3.0, 0.0);
        let mut steps: Vec<(f64, Vec2)> = (1..=46).map(|k| (0.05 * f64::from(k), person)).collect();
        steps.extend([(2.3, person); 10]);
        let [intimate, personal] = tallies(&run(person, &steps));
        // Standing there keeps the visit robot-caused: the robot came, the person did not.
        assert_secs(intimate.0, 1.6, "intimate time");
        assert_secs(intimate.1, 1.6, "intimate time, robot-caused");
        assert_secs(intimate.2, 0.0, "intimate time, person-caused");
        assert_eq!((intimate.3, intimate.4, intimate.5), (1, 1, 0), "intimate entries");
        assert_secs(personal.0, 1.5, "personal time");
        assert_secs(personal.1, 1.5, "personal time, robot-caused");
        assert_eq!((personal.3, personal.4, personal.5), (1, 1, 0), "personal entries");
    }

    #[test]
    fn a_walker_passing_a_standing_robot_causes_its_entries_and_time() {
        // The robot stands at the origin; a person walks from (3, 0.6) to (-3, 0.6) at 0.5 m/s.
        // Body gap sqrt(x² + 0.36) - 0.52: intimate (< 0.45) for |x| < 0.762, x = 0.75 .. -0.75
        // (31 steps); personal ring for 0.762 <= |x| < 1.612, x = 1.60 .. 0.80 and its mirror
        // (2 x 17 steps).
        let steps: Vec<(f64, Vec2)> =
            (1..=120).map(|k| (0.0, Vec2::new(3.0 - 0.05 * f64::from(k), 0.6))).collect();
        let [intimate, personal] = tallies(&run(Vec2::new(3.0, 0.6), &steps));
        assert_secs(intimate.0, 3.1, "intimate time");
        assert_secs(intimate.1, 0.0, "intimate time, robot-caused");
        assert_secs(intimate.2, 3.1, "intimate time, person-caused");
        assert_eq!((intimate.3, intimate.4, intimate.5), (1, 0, 1), "intimate entries");
        assert_secs(personal.0, 3.4, "personal time");
        assert_secs(personal.2, 3.4, "personal time, person-caused");
        assert_eq!((personal.3, personal.4, personal.5), (1, 0, 1), "personal entries");
    }

    #[test]
    fn a_visit_the_person_started_turns_robot_caused_when_the_robot_drives_on_and_time_adds_up() {
        // The robot stands at the origin; a person walks from (2, 0) at 0.5 m/s to (1.2, 0)
        // (16 steps) and stops: gap 0.68 m, in the personal zone from x = 1.70 (step 6, gap
        // 1.18) on, 11 person-caused steps. They stand 5 steps more (person-caused), then the
        // robot drives toward them at 0.1 m a step for 3 steps to x = 0.3 (gap 0.38, intimate at
        // x = 0.3 only): 2 robot-caused personal steps, 1 robot-caused intimate step and entry.
        let stop = Vec2::new(1.2, 0.0);
        let mut steps: Vec<(f64, Vec2)> =
            (1..=16).map(|k| (0.0, Vec2::new(2.0 - 0.05 * f64::from(k), 0.0))).collect();
        steps.extend([(0.0, stop); 5]);
        steps.extend([(0.1, stop), (0.2, stop), (0.3, stop)]);
        let r = run(Vec2::new(2.0, 0.0), &steps);
        let [intimate, personal] = tallies(&r);
        assert_secs(personal.1, 0.2, "personal time, robot-caused");
        assert_secs(personal.2, 1.6, "personal time, person-caused");
        assert_secs(personal.1 + personal.2, personal.0, "personal time adds up");
        assert_eq!((personal.3, personal.4, personal.5), (1, 0, 1), "personal entries");
        assert_secs(intimate.0, 0.1, "intimate time");
        assert_secs(intimate.1, 0.1, "intimate time, robot-caused");
        assert_eq!((intimate.3, intimate.4, intimate.5), (1, 1, 0), "intimate entries");
        assert!(intimate.0 + personal.0 <= r.duration + 1e-9);
    }

    #[test]
    fn an_absent_person_counts_nowhere() {
        // A walker passing the standing robot at 0.6 m, absent at every instant (a replayed
        // person parked): no zone time, no entry; present, they count.
        let setup_steps: Vec<(f64, Vec2)> =
            (1..=40).map(|k| (0.0, Vec2::new(1.0 - 0.05 * f64::from(k), 0.6))).collect();
        let present = run(Vec2::new(1.0, 0.6), &setup_steps);
        assert!(present.metrics.approach.intimate_gap_time > 0.0, "the present walker counts");
        let mut log = SceneLog::new(vec![0.22], vec![]);
        let setup = RecorderSetup {
            dt: 0.1,
            robot_radius: 0.3,
            goal: Vec2::new(10.0, 0.0),
            success_radius: 0.1,
            astar_path: vec![Vec2::zeros(), Vec2::new(10.0, 0.0)],
            geodesic_length: 10.0,
            episode: "approach test".into(),
        };
        let mut rec = EpisodeRecorder::new(setup, [0.0; 3]);
        let (zero, heading, absent) = ([Vec2::zeros()], [0.0], [false]);
        for (k, &(x, p)) in std::iter::once(&(0.0, Vec2::new(1.0, 0.6))).chain(&setup_steps).enumerate() {
            let pos = [p];
            log.push(&Snapshot {
                positions: &pos,
                velocities: &zero,
                headings: &heading,
                ospaces: &[],
                links: &[],
                active: &[],
                present: &absent,
            });
            if k > 0 {
                rec.record(&log, [x, 0.0, 0.0], 0, false, false);
            }
        }
        let r = rec
            .evaluate(&log, &|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default(), None)
            .expect("valid");
        assert_eq!(tallies(&r), [(0.0, 0.0, 0.0, 0, 0, 0); 2]);
    }
}
