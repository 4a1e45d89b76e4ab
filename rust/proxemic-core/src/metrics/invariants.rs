//! The invariants every episode record satisfies, checked where the record is made
//! ([`super::EpisodeRecorder::evaluate`]). A violation is a bug in proxemic, never a user's
//! error: the record is refused with [`crate::error::CoreError::Invariant`] naming the episode
//! and the invariant, instead of being written with numbers that contradict each other.
//!
//! The invariants ([`INVARIANTS`]):
//! - `outcome_agrees`: `outcome` and `success`/`collision`/`timeout` say the same thing, exactly
//!   one of the three is true, `time_to_goal` is given exactly with success, each `hc`/`wc`/`ac`
//!   flag is its count above zero, and a collision has a cause (a robot-fault person contact, a
//!   wall or a robot contact);
//! - `robot_fault_ends_episode`: robot-at-fault person contact events only in the last recorded
//!   step (one per person touched then: a robot can touch two people at once), which fail
//!   success and end the episode; each person touched by the robot's fault then is present over
//!   that step and meets the robot's body: a surface gap at or below zero on the swept relative
//!   motion, or else the physics' person contact, with no replayed person leaving in that step
//!   standing closer to the robot's path (the contact would then be theirs);
//! - `absent_people_never_count`: a person who is not in the scene (a replayed person before
//!   they appear, after they leave, parked) counts in no contact, zone (centre distance or body
//!   gap), nearest distance, social force, SNQI input or people's cost: the record equals the one
//!   computed with every absent person moved to the far side of the world;
//! - `within_bounds`: every value with bounds in the metric reference ([`super::METRICS`]: shares
//!   within [0, 100], fractions and flags within [0, 1], lengths and counts non-negative) is
//!   within them;
//! - `whole_counts`: every count (units `steps`, `count`, `windows`, `events`, `instants`,
//!   `instant-person pairs`) is a whole number;
//! - `duration_and_path`: `duration` is `steps * dt`, `steps` the recorded poses minus one,
//!   `path_length` the length of the recorded poses, Calderita's `d_t` and `tau` are
//!   `path_length` and `duration`, and no time (to goal, stalled, in o-spaces, in the intimate
//!   and personal zones together) or count of steps exceeds the episode's;
//! - `columns_add_up`: the four Hall zone shares (of people, of groups) add up to 100, the two
//!   kinds of interaction crossings to their total, each object's share of active time is at
//!   most its share of any time, the share inside some object space is at least each object's
//!   and at most their sum, `dist_person_min` is the least of the per-person `d_min`, the
//!   robot-caused and person-caused zone time and entries (body gaps) add up to their totals,
//!   there are person contact events exactly when there are person contact steps and static
//!   events exactly when static steps (never more events than static steps), and every summary
//!   of one set of values is ordered (`*_min <= *_avg <= *_max`, `ped_*_mean <= ped_*_max`).

use super::fault::{Touch, leaving_gap, step_contact, touches};
use super::{EpisodeReport, METRICS, Outcome, collisions::swept_gap};
use super::{
    EvalContext, FullMetrics, Groups, ObjectSpaces, PeopleTracks, RobotFreeTracks, Samples, Trajectory,
    evaluate,
};
use crate::math::Vec2;

/// The names of the invariants, in the order they are checked.
pub const INVARIANTS: [&str; 7] = [
    "outcome_agrees",
    "robot_fault_ends_episode",
    "absent_people_never_count",
    "within_bounds",
    "whole_counts",
    "duration_and_path",
    "columns_add_up",
];

/// Units of the metrics that count things (whole numbers).
const COUNT_UNITS: [&str; 6] = ["steps", "count", "windows", "events", "instants", "instant-person pairs"];

/// Relative tolerance of sums recomputed in another order (shares adding up to 100, path
/// lengths): far above the rounding of a few thousand additions, far below any real mismatch.
const SUM_TOL: f64 = 1e-9;

/// A broken invariant: its name (one of [`INVARIANTS`]) and what was found.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// The invariant's name.
    pub invariant: &'static str,
    /// What the record says that breaks it.
    pub detail: String,
}

fn fail(invariant: &'static str, detail: String) -> Result<(), Violation> {
    Err(Violation { invariant, detail })
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= SUM_TOL * (1.0 + a.abs().max(b.abs()))
}

/// Checks `report`, made from the recording `traj` among `people`, `groups` and `objects` with
/// `ctx` (the inputs of [`evaluate`]); the first broken invariant is returned.
pub(crate) fn check(
    report: &EpisodeReport,
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<(), Violation> {
    let m = &report.metrics;
    outcome_agrees(report)?;
    robot_fault_ends_episode(m, traj, people, ctx)?;
    absent_people_never_count(m, traj, people, groups, objects, ctx)?;
    bounds_and_counts(report)?;
    duration_and_path(report, traj)?;
    columns_add_up(m)
}

fn outcome_agrees(r: &EpisodeReport) -> Result<(), Violation> {
    let c = &r.metrics.collisions;
    let name = "outcome_agrees";
    let expect = (
        r.outcome == Outcome::Success,
        r.outcome == Outcome::Collision,
        matches!(r.outcome, Outcome::Timeout | Outcome::Running),
    );
    if (c.success, c.collision, c.timeout) != expect {
        return fail(
            name,
            format!(
                "outcome = {:?} but success = {}, collision = {}, timeout = {}",
                r.outcome, c.success, c.collision, c.timeout
            ),
        );
    }
    if c.time_to_goal.is_some() != c.success {
        return fail(name, format!("success = {} but time_to_goal = {:?}", c.success, c.time_to_goal));
    }
    for (flag, count, key) in [(c.hc, c.hc_count, "hc"), (c.wc, c.wc_count, "wc"), (c.ac, c.ac_count, "ac")] {
        if flag != (count > 0) {
            return fail(name, format!("{key} = {flag} but {key}_count = {count}"));
        }
    }
    let robot_fault = r.metrics.fault.collisions_robot_fault;
    if c.collision && robot_fault == 0 && c.wc_count == 0 && c.ac_count == 0 {
        return fail(name, "collision = true with no robot-fault, wall or robot contact".into());
    }
    Ok(())
}

fn robot_fault_ends_episode(
    m: &FullMetrics,
    traj: &Trajectory,
    people: &PeopleTracks,
    ctx: &EvalContext,
) -> Result<(), Violation> {
    let name = "robot_fault_ends_episode";
    let (faults, c) = (m.fault.collisions_robot_fault, &m.collisions);
    if faults == 0 {
        return Ok(());
    }
    if c.success || !c.collision {
        return fail(
            name,
            format!(
                "collisions_robot_fault = {faults} with success = {}, collision = {} (a robot-fault \
                 contact ends the episode and fails success)",
                c.success, c.collision
            ),
        );
    }
    let s = Samples::new(traj);
    let np = people.count;
    let all = touches(&s, traj, people, ctx.collision_steps);
    let Some(k) = (0..s.steps).find(|&k| all[k * np..(k + 1) * np].contains(&Touch::RobotFault)) else {
        return fail(name, format!("collisions_robot_fault = {faults} but no step has a robot-fault touch"));
    };
    if k + 1 != s.steps {
        return fail(
            name,
            format!("the robot-fault contact is at step {k} but the episode went on to step {}", s.steps - 1),
        );
    }
    // Several people touched in that same last step are one contact event each.
    let touched = all[k * np..(k + 1) * np].iter().filter(|&&t| t == Touch::RobotFault).count();
    if faults > touched {
        return fail(
            name,
            format!(
                "collisions_robot_fault = {faults} but {touched} people are touched by the robot's fault in its last step"
            ),
        );
    }
    // Each person touched by the robot's fault in that step was in the scene over the whole step
    // (a replayed person appearing, leaving or parked is never touched) and met the robot's body:
    // a surface gap at or below zero somewhere on the swept relative motion, or the physics'
    // person contact, never one that a person leaving in the step stood closer to.
    let step = step_contact(&s, traj, people, ctx.collision_steps, k);
    for i in (0..np).filter(|&i| all[k * np + i] == Touch::RobotFault) {
        if !step.here(i) {
            return fail(
                name,
                format!(
                    "the robot-fault contact at step {k} is with person {i}, who is absent at instant {} \
                     (a replayed person appearing, leaving or parked)",
                    if people.is_present(k, i) { k + 1 } else { k }
                ),
            );
        }
        let swept =
            swept_gap(step.p0, step.p1, step.before[i], step.after[i], traj.robot_radius, people.radii[i]);
        if swept <= 0.0 {
            continue;
        }
        let leaving = (0..np)
            .filter(|&j| people.is_present(k, j) && !people.is_present(k + 1, j))
            .map(|j| (leaving_gap(&step, j), j))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let end = (step.after[i] - step.p1).norm() - traj.robot_radius - people.radii[i];
        let own = end.min(leaving_gap(&step, i));
        if !step.physics_person || leaving.is_some_and(|(g, _)| g < own) {
            return fail(
                name,
                format!(
                    "the robot-fault contact at step {k} with person {i} has no body contact: swept gap \
                     {swept:+.3} m, gap {own:+.3} m, physics person contact {}, nearest person leaving in \
                     the step (gap, index): {leaving:?}",
                    step.physics_person
                ),
            );
        }
    }
    Ok(())
}

/// A point on the far side of the world for absent person `i` (distinct per person, so no two
/// absent people coincide).
fn far(i: usize) -> Vec2 {
    Vec2::new(1.0e7 + 10.0 * i as f64, 1.0e7)
}

fn absent_people_never_count(
    m: &FullMetrics,
    traj: &Trajectory,
    people: &PeopleTracks,
    groups: &Groups,
    objects: &ObjectSpaces,
    ctx: &EvalContext,
) -> Result<(), Violation> {
    if people.present.iter().all(|&p| p) {
        return Ok(());
    }
    let move_away = |pos: &[Vec2]| -> Vec<Vec2> {
        pos.iter()
            .enumerate()
            .map(
                |(j, &p)| {
                    if people.present.get(j).copied().unwrap_or(true) { p } else { far(j % people.count) }
                },
            )
            .collect()
    };
    let positions = move_away(people.positions);
    let moved = PeopleTracks { positions: &positions, ..*people };
    let free_positions = ctx.robot_free.as_ref().map(|f| {
        let n = f.positions.len().min(people.present.len());
        let mut v = move_away(&f.positions[..n]);
        v.extend_from_slice(&f.positions[n..]);
        v
    });
    let robot_free = ctx
        .robot_free
        .as_ref()
        .zip(free_positions.as_deref())
        .map(|(f, p)| RobotFreeTracks { positions: p, ..*f });
    let ctx2 = EvalContext { robot_free, ..*ctx };
    let Ok(away) = evaluate(traj, &moved, groups, objects, &ctx2) else {
        return fail(
            "absent_people_never_count",
            "the record with absent people moved away is invalid".into(),
        );
    };
    let families: [(&str, bool); 7] = [
        ("collisions", m.collisions == away.collisions),
        ("fault", m.fault == away.fault),
        ("proximity", m.proximity == away.proximity),
        ("approach", m.approach == away.approach),
        ("clearance", m.clearance == away.clearance),
        ("snqi", m.snqi == away.snqi),
        ("people_cost", m.people_cost == away.people_cost),
    ];
    let changed: Vec<&str> = families.iter().filter(|f| !f.1).map(|f| f.0).collect();
    if changed.is_empty() {
        return Ok(());
    }
    let json = |v: &FullMetrics| serde_json::to_value(v).unwrap_or_default();
    let (a, b) = (json(m), json(&away));
    let keys: Vec<String> = a
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(k, v)| b.get(k.as_str()) != Some(v))
                .take(4)
                .map(|(k, v)| format!("{k} = {v} (without the absent people: {})", b[k.as_str()]))
                .collect()
        })
        .unwrap_or_default();
    fail(
        "absent_people_never_count",
        format!("absent people change the metrics of {}: {}", changed.join(", "), keys.join("; ")),
    )
}

fn bounds_and_counts(r: &EpisodeReport) -> Result<(), Violation> {
    let Ok(value) = serde_json::to_value(r) else {
        return fail("within_bounds", "the record does not serialise".into());
    };
    for info in METRICS {
        let Some(v) = value.get(info.key) else { continue };
        let numbers: Vec<f64> = match v {
            serde_json::Value::Array(items) => items.iter().filter_map(serde_json::Value::as_f64).collect(),
            other => other.as_f64().into_iter().collect(),
        };
        for x in numbers {
            let low = info.low.is_some_and(|l| x < l);
            let high = info.high.is_some_and(|h| x > h);
            if low || high || x.is_nan() {
                return fail(
                    "within_bounds",
                    format!("{} = {x} outside [{:?}, {:?}] ({})", info.key, info.low, info.high, info.unit),
                );
            }
            if COUNT_UNITS.contains(&info.unit) && x.fract() != 0.0 {
                return fail(
                    "whole_counts",
                    format!("{} = {x} is a count ({}) but not whole", info.key, info.unit),
                );
            }
        }
    }
    Ok(())
}

fn duration_and_path(r: &EpisodeReport, traj: &Trajectory) -> Result<(), Violation> {
    let name = "duration_and_path";
    let m = &r.metrics;
    let steps = m.collisions.steps;
    if steps + 1 != traj.robot.len() {
        return fail(name, format!("steps = {steps} but {} poses were recorded", traj.robot.len()));
    }
    let duration = steps as f64 * traj.dt;
    if r.duration != duration {
        return fail(
            name,
            format!("duration = {} s but steps * dt = {steps} * {} = {duration} s", r.duration, traj.dt),
        );
    }
    let length: f64 = traj.robot.windows(2).map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1])).sum();
    if !close(m.efficiency.path_length, length) {
        return fail(
            name,
            format!(
                "path_length = {} m but the recorded poses are {length} m long",
                m.efficiency.path_length
            ),
        );
    }
    if m.papers.d_t != m.efficiency.path_length || m.papers.tau != r.duration {
        return fail(
            name,
            format!(
                "d_t = {} m and tau = {} s but path_length = {} m and duration = {} s (the same numbers)",
                m.papers.d_t, m.papers.tau, m.efficiency.path_length, r.duration
            ),
        );
    }
    let times = [
        ("time_to_goal", m.collisions.time_to_goal.unwrap_or(0.0)),
        ("stalled_time", m.motion.stalled_time),
        ("ospace_time", m.groups.ospace_time),
        (
            "intimate_gap_time + personal_gap_time",
            m.approach.intimate_gap_time + m.approach.personal_gap_time,
        ),
        ("monitor_stalled_time", r.recovery.monitor_stalled_time),
    ];
    for (key, t) in times {
        if t > duration + SUM_TOL * (1.0 + duration) {
            return fail(name, format!("{key} = {t} s exceeds the episode's duration {duration} s"));
        }
    }
    let counts = [
        ("hc_count", m.collisions.hc_count),
        ("wc_count", m.collisions.wc_count),
        ("ac_count", m.collisions.ac_count),
        ("interaction_crossings", m.groups.interaction_crossings),
    ];
    for (key, c) in counts {
        if c > steps {
            return fail(name, format!("{key} = {c} steps exceeds the episode's {steps} steps"));
        }
    }
    Ok(())
}

fn columns_add_up(m: &FullMetrics) -> Result<(), Violation> {
    let name = "columns_add_up";
    let p = &m.proximity;
    let g = &m.groups;
    for (who, zones) in [
        ("psi", [p.psi_intimate, p.psi_personal, p.psi_social, p.psi_public]),
        ("group_psi", [g.group_psi_intimate, g.group_psi_personal, g.group_psi_social, g.group_psi_public]),
    ] {
        if zones.iter().all(Option::is_some) {
            let total: f64 = zones.iter().flatten().sum();
            if !close(total, 100.0) {
                return fail(
                    name,
                    format!("{who}_intimate + _personal + _social + _public = {total}, not 100"),
                );
            }
        } else if zones.iter().any(Option::is_some) {
            return fail(name, format!("{who}_* zones are partly undefined: {zones:?}"));
        }
    }
    let z = &m.approach;
    for (key, total, robot, person) in [
        (
            "intimate_gap_time",
            z.intimate_gap_time,
            z.intimate_gap_time_robot_caused,
            z.intimate_gap_time_person_caused,
        ),
        (
            "personal_gap_time",
            z.personal_gap_time,
            z.personal_gap_time_robot_caused,
            z.personal_gap_time_person_caused,
        ),
    ] {
        if !close(robot + person, total) {
            return fail(
                name,
                format!("{key} = {total} s but robot_caused + person_caused = {robot} + {person} s"),
            );
        }
    }
    for (key, total, robot, person) in [
        (
            "intimate_gap_entries",
            z.intimate_gap_entries,
            z.intimate_gap_entries_robot_caused,
            z.intimate_gap_entries_person_caused,
        ),
        (
            "personal_gap_entries",
            z.personal_gap_entries,
            z.personal_gap_entries_robot_caused,
            z.personal_gap_entries_person_caused,
        ),
    ] {
        if robot + person != total {
            return fail(
                name,
                format!("{key} = {total} but robot_caused + person_caused = {robot} + {person}"),
            );
        }
    }
    let (pp, po) = (g.interaction_crossings_person_person, g.interaction_crossings_person_object);
    if g.interaction_crossings != pp + po {
        return fail(
            name,
            format!(
                "interaction_crossings = {} but person_person + person_object = {pp} + {po}",
                g.interaction_crossings
            ),
        );
    }
    let o = &m.objects;
    for (k, (act, any)) in o.psi_object_active.iter().zip(&o.psi_object_any).enumerate() {
        if let (Some(a), Some(b)) = (act, any)
            && a > b
        {
            return fail(name, format!("object {k}: psi_object_active = {a} exceeds psi_object_any = {b}"));
        }
    }
    for (total, each, key) in [
        (o.psi_objects_any, &o.psi_object_any, "any"),
        (o.psi_objects_active, &o.psi_object_active, "active"),
    ] {
        let Some(total) = total else { continue };
        let most = each.iter().flatten().copied().fold(0.0, f64::max);
        let sum: f64 = each.iter().flatten().sum();
        if total < most || (total > sum && !close(total, sum)) {
            return fail(
                name,
                format!(
                    "psi_objects_{key} = {total} outside [largest object's {most}, sum over objects {sum}]"
                ),
            );
        }
    }
    if let (Some(a), Some(b)) = (o.psi_objects_active, o.psi_objects_any)
        && a > b
    {
        return fail(name, format!("psi_objects_active = {a} exceeds psi_objects_any = {b}"));
    }
    // Contact events against the steps with contact: every person-contact step belongs to an
    // event with a person and every event has such a step; static events are runs of static steps.
    let (c, f) = (&m.collisions, &m.fault);
    let person_events = f.collisions_robot_fault + f.collisions_person_fault;
    if (c.hc_count > 0) != (person_events > 0) {
        return fail(
            name,
            format!(
                "hc_count = {} steps but collisions_robot_fault + collisions_person_fault = {person_events} events",
                c.hc_count
            ),
        );
    }
    if f.collisions_static > c.wc_count || (c.wc_count > 0) != (f.collisions_static > 0) {
        return fail(
            name,
            format!("wc_count = {} steps but collisions_static = {} events", c.wc_count, f.collisions_static),
        );
    }
    // Summaries of one set of values: least <= mean <= largest.
    let v = &m.motion;
    let q = &m.people_cost;
    let c = &m.clearance;
    let ordered: [(&str, Vec<Option<f64>>); 7] = [
        ("vel_min <= vel_avg <= vel_max", vec![v.vel_min, v.vel_avg, v.vel_max]),
        ("acc_min <= acc_avg <= acc_max", vec![v.acc_min, v.acc_avg, v.acc_max]),
        ("jerk_min <= jerk_avg <= jerk_max", vec![v.jerk_min, v.jerk_avg, v.jerk_max]),
        ("clearance_min <= clearance_avg", vec![c.clearance_min, c.clearance_avg]),
        ("ped_delay_s_mean <= ped_delay_s_max", vec![q.ped_delay_s_mean, q.ped_delay_s_max]),
        (
            "ped_extra_distance_m_mean <= ped_extra_distance_m_max",
            vec![q.ped_extra_distance_m_mean, q.ped_extra_distance_m_max],
        ),
        (
            "ped_path_deviation_m_mean <= ped_path_deviation_m_max",
            vec![q.ped_path_deviation_m_mean, q.ped_path_deviation_m_max],
        ),
    ];
    for (key, values) in ordered {
        let broken = values.windows(2).any(|w| match (w[0], w[1]) {
            (Some(a), Some(b)) => a > b && !close(a, b),
            (a, b) => a.is_some() != b.is_some(),
        });
        if broken {
            return fail(name, format!("{key} does not hold: {values:?}"));
        }
    }
    let least = p.d_min.iter().flatten().copied().reduce(f64::min);
    if least != p.dist_person_min {
        return fail(
            name,
            format!("dist_person_min = {:?} but the least per-person d_min is {least:?}", p.dist_person_min),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::{EpisodeRecorder, MetricParams, RecorderSetup, SceneLog, Snapshot};

    /// A robot driving from (0, 0) to its goal (1, 0) in ten 0.1 m steps, one person standing
    /// at (0.5, 2) who is `present` at each instant.
    fn episode(present: &[bool]) -> (SceneLog, EpisodeRecorder) {
        let person = [Vec2::new(0.5, 2.0)];
        let still = [Vec2::new(0.0, 0.0)];
        let heading = [0.0];
        let snap = |k: usize| Snapshot {
            positions: &person,
            velocities: &still,
            headings: &heading,
            present: std::slice::from_ref(&present[k]),
            ospaces: &[],
            links: &[],
            active: &[],
        };
        let setup = RecorderSetup {
            dt: 0.1,
            robot_radius: 0.25,
            goal: Vec2::new(1.0, 0.0),
            success_radius: 0.05,
            astar_path: vec![Vec2::zeros(), Vec2::new(1.0, 0.0)],
            geodesic_length: 1.0,
            episode: "test, seed 0, robot 0".into(),
        };
        let mut log = SceneLog::new(vec![0.2], vec![]);
        log.push(&snap(0));
        let mut rec = EpisodeRecorder::new(setup, [0.0; 3]);
        for k in 1..=10 {
            log.push(&snap(k));
            rec.record(&log, [0.1 * k as f64, 0.0, 0.0], 0, false, false);
        }
        (log, rec)
    }

    fn report(present: &[bool]) -> EpisodeReport {
        let (log, rec) = episode(present);
        rec.evaluate(&log, &|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default(), None)
            .expect("consistent")
    }

    #[test]
    fn a_consistent_record_passes() {
        let r = report(&[true; 11]);
        assert_eq!(r.outcome, Outcome::Success);
        assert!(
            outcome_agrees(&r).is_ok() && bounds_and_counts(&r).is_ok() && columns_add_up(&r.metrics).is_ok()
        );
    }

    #[test]
    fn each_broken_record_names_its_invariant() {
        let r = report(&[true; 11]);
        let name = |res: Result<(), Violation>| res.expect_err("broken").invariant;
        let mut b = r.clone();
        b.metrics.collisions.success = false;
        assert_eq!(name(outcome_agrees(&b)), "outcome_agrees");
        let mut b = r.clone();
        b.metrics.proximity.psi_public = Some(101.0);
        assert_eq!(name(bounds_and_counts(&b)), "within_bounds");
        let mut b = r.clone();
        b.metrics.proximity.psi_social = Some(1.0);
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up");
        let mut b = r.clone();
        b.metrics.groups.interaction_crossings = 1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up");
        let mut b = r.clone();
        b.metrics.approach.intimate_gap_time_robot_caused = 0.1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up");
        let mut b = r.clone();
        b.metrics.approach.personal_gap_time = 0.3;
        b.metrics.approach.personal_gap_time_person_caused = 0.3;
        assert!(columns_add_up(&b.metrics).is_ok(), "time that adds up");
        b.metrics.approach.personal_gap_entries_person_caused = 1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up");
        let mut b = r.clone();
        b.metrics.approach.intimate_gap_entries = 2;
        b.metrics.approach.intimate_gap_entries_robot_caused = 1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up");
        let mut b = r.clone();
        b.metrics.approach.personal_gap_time = 1.1;
        b.metrics.approach.personal_gap_time_robot_caused = 1.1;
        let poses: Vec<[f64; 3]> = (0..=10).map(|k| [0.1 * f64::from(k), 0.0, 0.0]).collect();
        let traj = Trajectory {
            dt: 0.1,
            robot: &poses,
            robot_radius: 0.25,
            goal: Vec2::new(1.0, 0.0),
            success_radius: 0.05,
        };
        assert_eq!(name(duration_and_path(&b, &traj)), "duration_and_path", "zone time above the duration");
        let mut b = r.clone();
        b.duration = 2.0;
        assert_eq!(name(duration_and_path(&b, &traj)), "duration_and_path");
        let mut b = r.clone();
        b.metrics.papers.d_t += 0.5;
        assert_eq!(name(duration_and_path(&b, &traj)), "duration_and_path", "d_t is path_length");
        // Summaries out of order, contact events without contact steps.
        let mut b = r.clone();
        b.metrics.motion.vel_avg = b.metrics.motion.vel_max.map(|v| v + 0.1);
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up", "mean above the max");
        let mut b = r.clone();
        b.metrics.people_cost.ped_delay_s_mean = Some(1.0);
        b.metrics.people_cost.ped_delay_s_max = Some(0.5);
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up", "mean delay above the max");
        let mut b = r.clone();
        b.metrics.fault.collisions_person_fault = 1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up", "an event without a contact step");
        let mut b = r;
        b.metrics.collisions.wc_count = 1;
        assert_eq!(name(columns_add_up(&b.metrics)), "columns_add_up", "a static step without its event");
    }

    #[test]
    fn a_person_who_comes_and_goes_is_checked_against_the_record_without_them() {
        // Present in the middle instants only: the record is made (the invariant holds) and says
        // the same as with the person always away.
        let present: Vec<bool> = (0..=10).map(|k| (3..=6).contains(&k)).collect();
        let r = report(&present);
        assert_eq!(r.outcome, Outcome::Success);
        assert!(r.metrics.proximity.d_min[0].is_some());
    }
}
