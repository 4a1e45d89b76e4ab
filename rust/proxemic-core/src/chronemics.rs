//! Chronemics: the time-dependent cost R(t) of an object's interaction space (Calderita et al.
//! §4.2 and §5.2.2, Fig. 8).
//!
//! Each object has a daily agenda of activities. Its cost is `idle` (1.5) with nothing scheduled,
//! rises over the `ramp` (45 min) before an activity to `active` (3.5), stays there while the
//! activity runs, and falls back "in the same way that it increased" over `ramp` after it ends.
//! The ramps are **linear**: the paper describes R(t) as "a countdown for the remaining time until
//! the start of the activity and a count for the elapsed time after the end" and gives only the
//! end values and the 45-minute span; the curve of Fig. 8 is not available in the text we work
//! from, so the linear countdown is our reading of it. Where the ramps of two activities on one
//! object overlap, the cost is the larger of the two.
//!
//! # Time of day and midnight
//!
//! Times are seconds after midnight. The agenda **repeats every day**: a query time is reduced
//! modulo [`DAY`] into [0, 86400), and every activity also acts on the previous and next day, so the
//! ramp before an activity at 00:15 starts at 23:30 and the ramp after one ending at 23:50 runs
//! until 00:35. An activity starts in [0, 86400) and may end after midnight (`end` up to
//! `start + 86400`; e.g. 23:00-01:00 is `start = 82800, end = 90000`).
//!
//! Activities run on the half-open interval `[start, end)`: at `end` the activity is no longer
//! [`Agenda::active`], and (for `ramp > 0`) the cost starts falling from `active`.

use std::collections::BTreeMap;

use crate::error::{CoreError, Result};

/// Seconds in a day; the agenda's period.
pub const DAY: f64 = 86_400.0;

/// Change points closer than this after a query time count as passed (seconds).
const CHANGE_EPS: f64 = 1e-6;

/// One scheduled activity at an object.
#[derive(Clone, Debug, PartialEq)]
pub struct Activity {
    /// The object's name (as in the scenario).
    pub object: String,
    /// Start, in seconds after midnight, in [0, 86400).
    pub start: f64,
    /// End, in seconds after midnight of the start's day, in (start, start + 86400]; values above
    /// 86400 end the next day.
    pub end: f64,
}

impl Activity {
    /// Builds an activity (checked when the [`Agenda`] is built).
    pub fn new(object: impl Into<String>, start: f64, end: f64) -> Self {
        Activity { object: object.into(), start, end }
    }
}

/// The shape of R(t) (Calderita §5.2.2): costs are dimensionless grid-cost multipliers, `ramp` is
/// in seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AgendaParams {
    /// Cost with nothing scheduled (default 1.5). Finite.
    pub idle: f64,
    /// Cost while an activity runs (default 3.5). Finite and >= `idle`.
    pub active: f64,
    /// Duration of the rise before and the fall after an activity (seconds, default 2700 = 45 min).
    /// In [0, 86400]; 0 makes R(t) a step.
    pub ramp: f64,
}

impl AgendaParams {
    /// Calderita et al. Fig. 8: 1.5 idle, 3.5 active, 45-minute ramps.
    pub const CALDERITA: AgendaParams = AgendaParams { idle: 1.5, active: 3.5, ramp: 2700.0 };

    /// Checks the ranges documented on the fields; errors name `params.idle`, `params.active` or
    /// `params.ramp`.
    pub fn validate(&self) -> Result<()> {
        if !self.idle.is_finite() {
            return Err(CoreError::input("params.idle", "a finite cost", format!("{}", self.idle)));
        }
        if !(self.active.is_finite() && self.active >= self.idle) {
            return Err(CoreError::input(
                "params.active",
                format!("a finite cost >= idle ({})", self.idle),
                format!("{}", self.active),
            ));
        }
        if !(self.ramp >= 0.0 && self.ramp <= DAY) {
            return Err(CoreError::input(
                "params.ramp",
                "a duration in [0, 86400] s",
                format!("{}", self.ramp),
            ));
        }
        Ok(())
    }
}

impl Default for AgendaParams {
    /// [`AgendaParams::CALDERITA`].
    fn default() -> Self {
        AgendaParams::CALDERITA
    }
}

/// One object's schedule: its activity spans and the times of day where its cost changes slope.
#[derive(Clone, Debug, Default)]
struct Schedule {
    /// `(start, end)` per activity, sorted by start.
    spans: Vec<(f64, f64)>,
}

/// A validated daily agenda: the activities of every object and the R(t) they imply.
#[derive(Clone, Debug)]
pub struct Agenda {
    params: AgendaParams,
    activities: Vec<Activity>,
    objects: BTreeMap<String, Schedule>,
    /// Times of day in [0, 86400), sorted, where some object's cost changes slope (or jumps).
    changes: Vec<f64>,
}

impl Agenda {
    /// Builds an agenda. Errors (as [`CoreError::Input`]): invalid `params` (see
    /// [`AgendaParams::validate`]); `activities[i].start` not finite or outside [0, 86400);
    /// `activities[i].end` not finite, `<= start`, or more than a day after start; two activities
    /// on the same object whose intervals overlap (on the daily cycle), with field
    /// `activities[i], activities[j]`. Back-to-back activities (one ends when the next starts) are
    /// allowed.
    pub fn new(activities: Vec<Activity>, params: AgendaParams) -> Result<Agenda> {
        params.validate()?;
        for (i, a) in activities.iter().enumerate() {
            if !(a.start.is_finite() && a.start >= 0.0 && a.start < DAY) {
                return Err(CoreError::input(
                    format!("activities[{i}].start"),
                    "a time of day in [0, 86400) s",
                    format!("{}", a.start),
                ));
            }
            if !(a.end.is_finite() && a.end > a.start && a.end - a.start <= DAY) {
                return Err(CoreError::input(
                    format!("activities[{i}].end"),
                    format!("a time after start ({} s) and at most one day later", a.start),
                    format!("{}", a.end),
                ));
            }
        }
        // Group by object, sorted by start, and check for overlaps on the daily cycle.
        let mut by_object: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
        for (i, a) in activities.iter().enumerate() {
            by_object.entry(a.object.as_str()).or_default().push(i);
        }
        let mut objects = BTreeMap::new();
        for (name, mut idx) in by_object {
            idx.sort_by(|&a, &b| activities[a].start.total_cmp(&activities[b].start).then(a.cmp(&b)));
            let overlap = |i: usize, j: usize, shift: f64| {
                let (a, b) = (&activities[i], &activities[j]);
                CoreError::input(
                    format!("activities[{}], activities[{}]", i.min(j), i.max(j)),
                    format!("activities on object '{name}' that do not overlap"),
                    format!("[{}, {}) and [{}, {})", a.start, a.end, b.start + shift, b.end + shift),
                )
            };
            // Sorted by start, any overlap shows up between neighbours; on the cycle, only the last
            // activity can reach past midnight into the first one of the next day.
            for w in idx.windows(2) {
                if activities[w[0]].end > activities[w[1]].start {
                    return Err(overlap(w[0], w[1], 0.0));
                }
            }
            if let (Some(&first), Some(&last)) = (idx.first(), idx.last())
                && first != last
                && activities[last].end > activities[first].start + DAY
            {
                return Err(overlap(last, first, DAY));
            }
            let spans = idx.iter().map(|&i| (activities[i].start, activities[i].end)).collect();
            objects.insert(name.to_string(), Schedule { spans });
        }
        let mut agenda = Agenda { params, activities, objects, changes: Vec::new() };
        let mut changes: Vec<f64> =
            agenda.objects.values().flat_map(|s| agenda.schedule_changes(s)).collect();
        sort_dedup(&mut changes);
        agenda.changes = changes;
        Ok(agenda)
    }

    /// An agenda with no activities: every object costs `params.idle` at all times.
    pub fn empty(params: AgendaParams) -> Result<Agenda> {
        Agenda::new(Vec::new(), params)
    }

    /// The parameters of R(t).
    pub fn params(&self) -> AgendaParams {
        self.params
    }

    /// The activities, in the order given.
    pub fn activities(&self) -> &[Activity] {
        &self.activities
    }

    /// The names of the objects with at least one activity, sorted.
    pub fn objects(&self) -> impl Iterator<Item = &str> {
        self.objects.keys().map(String::as_str)
    }

    /// R(t) for `object` at time of day `t` (seconds after midnight; any finite value, reduced
    /// modulo one day). An object with no activities costs `idle`. A non-finite `t` gives NaN.
    pub fn cost(&self, object: &str, t: f64) -> f64 {
        if !t.is_finite() {
            return f64::NAN;
        }
        match self.objects.get(object) {
            Some(s) => self.schedule_cost(s, wrap_day(t)),
            None => self.params.idle,
        }
    }

    /// Whether an activity on `object` runs at time of day `t` (in some `[start, end)`, on the
    /// daily cycle). False for an unknown object or a non-finite `t`.
    pub fn active(&self, object: &str, t: f64) -> bool {
        if !t.is_finite() {
            return false;
        }
        let t = wrap_day(t);
        self.objects.get(object).is_some_and(|s| {
            s.spans.iter().any(|&(a, b)| {
                (-1..=0).any(|k| {
                    let shift = f64::from(k) * DAY;
                    t >= a + shift && t < b + shift
                })
            })
        })
    }

    /// The first time after `t` at which some object's cost changes slope (a ramp starts or ends,
    /// an activity starts or ends, two overlapping ramps cross) or jumps (with `ramp = 0`). Change
    /// points less than a microsecond after `t` count as passed. The result lies in (t, t + 86400]
    /// on the same clock as `t`, so it may lie past midnight (above 86400) when `t` is a time of
    /// day; for `t` in [0, 86400) change points are returned exactly. `None` when no object's cost ever changes (no
    /// activities, or activities covering the whole day) or for a non-finite `t`. Use it to
    /// schedule re-planning.
    pub fn next_change(&self, t: f64) -> Option<f64> {
        if !t.is_finite() {
            return None;
        }
        let tw = wrap_day(t);
        let first = *self.changes.first()?;
        // Whole days before t, so that the result is `days * DAY + c` for a change point c: exact
        // for times of day, and within rounding of c on later days.
        let days = ((t - tw) / DAY).round();
        // A change point within CHANGE_EPS of t counts as passed, so that feeding a result back in
        // (after rounding on a later day) moves on to the next change.
        let i = self.changes.partition_point(|&c| c <= tw + CHANGE_EPS);
        let next = match self.changes.get(i) {
            Some(&c) => days * DAY + c,
            None => (days + 1.0) * DAY + first,
        };
        Some(next.max(t))
    }

    /// R(t) of one activity span shifted by `shift` seconds, at wrapped time `t`.
    fn span_cost(&self, start: f64, end: f64, t: f64) -> f64 {
        let AgendaParams { idle, active, ramp } = self.params;
        // Calderita §5.2.2 / Fig. 8, with linear ramps (see the module docs).
        let d = if t < start {
            start - t
        } else if t < end {
            return active;
        } else {
            t - end
        };
        if ramp > 0.0 && d < ramp { idle + (active - idle) * (1.0 - d / ramp) } else { idle }
    }

    fn schedule_cost(&self, s: &Schedule, t: f64) -> f64 {
        let mut best = self.params.idle;
        for &(a, b) in &s.spans {
            // Copies on the neighbouring days; with start in [0, DAY), end <= start + DAY and
            // ramp <= DAY, only shifts -2..=1 days can reach a time in [0, DAY).
            for k in -2..=1 {
                let shift = f64::from(k) * DAY;
                best = best.max(self.span_cost(a + shift, b + shift, t));
            }
        }
        best
    }

    /// The times of day where this object's cost changes slope or jumps.
    fn schedule_changes(&self, s: &Schedule) -> Vec<f64> {
        let ramp = self.params.ramp;
        let mut cand = Vec::with_capacity(s.spans.len() * 4);
        for &(a, b) in &s.spans {
            cand.extend([a - ramp, a, b, b + ramp].map(wrap_day));
        }
        // A falling ramp (after activity i) and a rising one (before activity j) cross halfway
        // between i's end and j's start when those are less than two ramps apart.
        for &(_, ei) in &s.spans {
            for &(sj, _) in &s.spans {
                for k in -3..=3 {
                    let sj = sj + f64::from(k) * DAY;
                    if sj > ei && sj - ei < 2.0 * ramp {
                        cand.push(wrap_day(0.5 * (ei + sj)));
                    }
                }
            }
        }
        sort_dedup(&mut cand);
        if cand.is_empty() || self.params.active == self.params.idle {
            return Vec::new();
        }
        // Between consecutive candidates the cost is linear; keep a candidate only where the
        // slope or the value differs on its two sides.
        let n = cand.len();
        let pieces: Vec<(f64, f64, f64)> = (0..n)
            .map(|i| {
                let a = cand[i];
                let len = if n == 1 { DAY } else { (cand[(i + 1) % n] - a).rem_euclid(DAY) };
                let (q1, q3) = (a + 0.25 * len, a + 0.75 * len);
                let (f1, f3) = (self.schedule_cost(s, wrap_day(q1)), self.schedule_cost(s, wrap_day(q3)));
                let slope = (f3 - f1) / (0.5 * len);
                // (slope, value just after a, value just before the next candidate)
                (slope, f1 - slope * 0.25 * len, f3 + slope * 0.25 * len)
            })
            .collect();
        let m = if ramp > 0.0 { (self.params.active - self.params.idle) / ramp } else { 0.0 };
        let tol_slope = 1e-6 * m + 1e-12;
        let tol_value = 1e-9 * (1.0 + self.params.active.abs() + self.params.idle.abs());
        (0..n)
            .filter(|&i| {
                let before = pieces[(i + n - 1) % n];
                let after = pieces[i];
                (before.0 - after.0).abs() > tol_slope || (before.2 - after.1).abs() > tol_value
            })
            .map(|i| cand[i])
            .collect()
    }
}

/// Reduces a time to [0, 86400).
fn wrap_day(t: f64) -> f64 {
    let r = t.rem_euclid(DAY);
    if r >= DAY { 0.0 } else { r }
}

/// Sorts and merges times closer than a millisecond (keeping the first).
fn sort_dedup(v: &mut Vec<f64>) {
    v.sort_by(f64::total_cmp);
    v.dedup_by(|b, a| *b - *a < 1e-3);
    // Also merge across midnight.
    if v.len() > 1
        && let (Some(&first), Some(&last)) = (v.first(), v.last())
        && first + DAY - last < 1e-3
    {
        v.pop();
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    const H: f64 = 3600.0;
    const M: f64 = 60.0;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-9
    }

    fn agenda(acts: &[(&str, f64, f64)]) -> Agenda {
        Agenda::new(acts.iter().map(|&(o, a, b)| Activity::new(o, a, b)).collect(), AgendaParams::CALDERITA)
            .expect("valid test input")
    }

    /// Calderita Fig. 8 with linear ramps, written out for one activity.
    fn r_one(t: f64, s: f64, e: f64) -> f64 {
        if t < s - 2700.0 || t >= e + 2700.0 {
            1.5
        } else if t < s {
            1.5 + 2.0 * (t - (s - 2700.0)) / 2700.0
        } else if t < e {
            3.5
        } else {
            3.5 - 2.0 * (t - e) / 2700.0
        }
    }

    #[test]
    fn r_of_t_at_chosen_times() {
        // Therapy at the table 10:00-11:00.
        let ag = agenda(&[("table", 10.0 * H, 11.0 * H)]);
        let c = |t: f64| ag.cost("table", t);
        assert!(close(c(8.0 * H), 1.5), "well before");
        assert!(close(c(9.0 * H + 15.0 * M), 1.5), "ramp begins 45 min before");
        assert!(close(c(9.0 * H + 30.0 * M), 1.5 + 2.0 / 3.0), "15 of 45 min into the rise");
        assert!(close(c(9.0 * H + 37.5 * M), 2.5), "mid-ramp");
        assert!(close(c(10.0 * H), 3.5), "start");
        assert!(close(c(10.5 * H), 3.5), "during");
        assert!(close(c(11.0 * H), 3.5), "at the end the fall starts from active");
        assert!(close(c(11.0 * H + 22.5 * M), 2.5), "mid fall");
        assert!(close(c(11.0 * H + 45.0 * M), 1.5), "back to idle");
        assert!(close(c(15.0 * H), 1.5));
        for i in 0..2000 {
            let t = i as f64 * 43.2;
            assert!(close(c(t), r_one(t, 10.0 * H, 11.0 * H)), "t = {t}");
        }
        // Other objects are idle.
        assert_eq!(ag.cost("tv", 10.5 * H), 1.5);
        assert!(ag.active("table", 10.0 * H) && ag.active("table", 10.99 * H));
        assert!(!ag.active("table", 11.0 * H) && !ag.active("table", 9.9 * H) && !ag.active("tv", 10.5 * H));
    }

    #[test]
    fn overlapping_ramps_take_the_max_and_cross_halfway() {
        // 10:00-11:00 and 12:00-13:00 at one object: the fall of the first (to 11:45) and the rise
        // of the second (from 11:15) overlap; they cross at 11:30.
        let ag = agenda(&[("tv", 12.0 * H, 13.0 * H), ("tv", 10.0 * H, 11.0 * H)]);
        for i in 0..=120 {
            let t = 10.0 * H + i as f64 * 90.0;
            let want = r_one(t, 10.0 * H, 11.0 * H).max(r_one(t, 12.0 * H, 13.0 * H));
            assert!(close(ag.cost("tv", t), want), "t = {t}");
        }
        assert!(close(ag.cost("tv", 11.0 * H + 20.0 * M), 1.5 + 2.0 * 25.0 / 45.0));
        assert!(close(ag.cost("tv", 11.0 * H + 40.0 * M), 1.5 + 2.0 * 25.0 / 45.0));
        assert!(close(ag.cost("tv", 11.5 * H), 1.5 + 2.0 * 15.0 / 45.0));
        // Slope changes: 09:15, 10:00, 11:00, 11:30 (crossing), 12:00, 13:00, 13:45; the ends of the
        // hidden ramp parts (11:15, 11:45) are not changes.
        let mut t = 0.0;
        let mut seen = Vec::new();
        while let Some(n) = ag.next_change(t) {
            if n >= DAY {
                break;
            }
            seen.push(n);
            t = n;
        }
        let want = [9.25 * H, 10.0 * H, 11.0 * H, 11.5 * H, 12.0 * H, 13.0 * H, 13.75 * H];
        assert_eq!(seen.len(), want.len(), "{seen:?}");
        for (a, b) in seen.iter().zip(want) {
            assert!((a - b).abs() < 1e-6, "{seen:?}");
        }
        // Back-to-back activities are allowed and stay active across the boundary.
        let bb = agenda(&[("bed", 8.0 * H, 9.0 * H), ("bed", 9.0 * H, 10.0 * H)]);
        assert_eq!(bb.cost("bed", 9.0 * H), 3.5);
        assert!(bb.active("bed", 9.0 * H));
        let n = bb.next_change(8.0 * H).expect("valid test input");
        assert!((n - 10.0 * H).abs() < 1e-6, "no change at the 9:00 boundary: {n}");
    }

    #[test]
    fn next_change_wraps_to_the_next_day() {
        let ag = agenda(&[("tv", 20.0 * H, 21.0 * H)]);
        let n = ag.next_change(22.0 * H).expect("valid test input");
        assert!((n - (22.0 * H + (DAY - 22.0 * H) + 19.25 * H)).abs() < 1e-6, "{n}");
        let n = ag.next_change(19.25 * H).expect("valid test input");
        assert!((n - 20.0 * H).abs() < 1e-6, "strictly after: {n}");
        assert!(Agenda::empty(AgendaParams::CALDERITA).expect("valid test input").next_change(0.0).is_none());
        assert!(ag.next_change(f64::NAN).is_none());
        // Several objects: the earliest change of any.
        let two = agenda(&[("tv", 20.0 * H, 21.0 * H), ("bed", 8.0 * H, 9.0 * H)]);
        let n = two.next_change(0.0).expect("valid test input");
        assert!((n - 7.25 * H).abs() < 1e-6);
    }

    #[test]
    fn midnight_wraps_the_ramps_and_activities() {
        // 00:15-01:00: the rise starts at 23:30 the day before.
        let ag = agenda(&[("tv", 15.0 * M, 1.0 * H)]);
        assert!(close(ag.cost("tv", 23.0 * H + 45.0 * M), 1.5 + 2.0 / 3.0));
        assert!(close(ag.cost("tv", 23.0 * H + 29.0 * M), 1.5));
        assert!(close(ag.cost("tv", 0.0), 1.5 + 2.0 * 30.0 / 45.0));
        assert!(close(ag.cost("tv", DAY), ag.cost("tv", 0.0)), "t = 86400 is midnight");
        assert!(close(ag.cost("tv", -15.0 * M), ag.cost("tv", 23.0 * H + 45.0 * M)), "negative t wraps");
        assert!(close(ag.cost("tv", 3.0 * DAY + 30.0 * M), 3.5), "any day");
        // 23:00-01:00 written with end past midnight.
        let night = agenda(&[("bed", 23.0 * H, 25.0 * H)]);
        assert!(night.active("bed", 23.5 * H) && night.active("bed", 0.5 * H));
        assert!(!night.active("bed", 1.0 * H));
        assert!(close(night.cost("bed", 0.5 * H), 3.5));
        assert!(close(night.cost("bed", 1.0 * H + 22.5 * M), 2.5));
        assert!(close(night.cost("bed", 22.0 * H + 37.5 * M), 2.5));
        // An activity ending at 23:50 falls until 00:35.
        let late = agenda(&[("tv", 22.0 * H, 23.0 * H + 50.0 * M)]);
        assert!(close(late.cost("tv", 20.0 * M), 1.5 + 2.0 * 15.0 / 45.0));
        let n = late.next_change(23.0 * H + 50.0 * M).expect("valid test input");
        assert!((n - (DAY + 35.0 * M)).abs() < 1e-6, "{n}");
        // Non-finite times.
        assert!(ag.cost("tv", f64::NAN).is_nan());
        assert!(!ag.active("tv", f64::INFINITY));
    }

    #[test]
    fn step_profile_with_zero_ramp() {
        let p = AgendaParams { ramp: 0.0, ..AgendaParams::CALDERITA };
        let ag = Agenda::new(vec![Activity::new("tv", 10.0 * H, 11.0 * H)], p).expect("valid test input");
        assert_eq!(ag.cost("tv", 10.0 * H - 1.0), 1.5);
        assert_eq!(ag.cost("tv", 10.0 * H), 3.5);
        assert_eq!(ag.cost("tv", 11.0 * H - 1e-6), 3.5);
        assert_eq!(ag.cost("tv", 11.0 * H), 1.5);
        let n = ag.next_change(0.0).expect("valid test input");
        assert!((n - 10.0 * H).abs() < 1e-6);
        let n = ag.next_change(n).expect("valid test input");
        assert!((n - 11.0 * H).abs() < 1e-6);
        // Configurable values.
        let q = AgendaParams { idle: 1.0, active: 10.0, ramp: 600.0 };
        let ag = Agenda::new(vec![Activity::new("tv", 10.0 * H, 11.0 * H)], q).expect("valid test input");
        assert!(close(ag.cost("tv", 10.0 * H - 300.0), 5.5));
    }

    /// Non-overlapping activities on three objects from random (object, start, duration) triples.
    fn random_agenda(raw: &[(u8, f64, f64)], params: AgendaParams) -> Agenda {
        let mut acts = Vec::new();
        for obj in 0..3u8 {
            let mut mine: Vec<(f64, f64)> =
                raw.iter().filter(|r| r.0 % 3 == obj).map(|&(_, s, d)| (s, s + d)).collect();
            mine.sort_by(|a, b| a.0.total_cmp(&b.0));
            let mut kept: Vec<(f64, f64)> = Vec::new();
            for (s, e) in mine {
                if kept.last().is_none_or(|&(_, le)| s >= le) {
                    kept.push((s, e));
                }
            }
            if kept.len() > 1
                && let (Some(&(fs, _)), Some(&(_, le))) = (kept.first(), kept.last())
                && le > fs + DAY
            {
                kept.pop();
            }
            acts.extend(kept.into_iter().map(|(s, e)| Activity::new(format!("o{obj}"), s, e)));
        }
        Agenda::new(acts, params).expect("non-overlapping by construction")
    }

    proptest! {
        #[test]
        fn cost_is_bounded_piecewise_linear_between_reported_changes(
            raw in prop::collection::vec((any::<u8>(), 0.0f64..DAY, 60.0f64..30_000.0), 0..8),
            ramp in prop_oneof![Just(0.0), Just(2700.0), 1.0f64..20_000.0],
            t in -DAY..2.0 * DAY,
        ) {
            let params = AgendaParams { ramp, ..AgendaParams::CALDERITA };
            let ag = random_agenda(&raw, params);
            let m = if ramp > 0.0 { 2.0 / ramp } else { 0.0 };
            for o in ["o0", "o1", "o2", "none"] {
                let c = ag.cost(o, t);
                prop_assert!((1.5..=3.5).contains(&c), "{c}");
                if ramp > 0.0 {
                    // Continuous, with slope at most (active - idle) / ramp.
                    prop_assert!((ag.cost(o, t + 1.0) - c).abs() <= m * 1.0 + 1e-9);
                }
            }
            let Some(n) = ag.next_change(t) else {
                for o in ["o0", "o1", "o2"] {
                    prop_assert!((ag.cost(o, t) - ag.cost(o, t + 12_345.0)).abs() < 1e-12);
                }
                return Ok(());
            };
            prop_assert!(n > t && n <= t + DAY + 1e-6);
            let len = n - t;
            // Linear on [t, n): zero second differences at five equally spaced points.
            for o in ["o0", "o1", "o2"] {
                let f: Vec<f64> = (0..5).map(|i| ag.cost(o, t + len * i as f64 / 5.0)).collect();
                for w in f.windows(3) {
                    prop_assert!((w[0] - 2.0 * w[1] + w[2]).abs() < 1e-7, "{o}: {f:?} on [{t}, {n})");
                }
            }
            // And at n some object really changes slope or jumps.
            let after = ag.next_change(n).map_or(DAY, |a| a - n);
            let h = (0.25 * len).min(0.25 * after).min(1.0);
            let kink = ["o0", "o1", "o2"].iter().any(|o| {
                let (l, c, r) = (ag.cost(o, n - h), ag.cost(o, n), ag.cost(o, n + h));
                (l - 2.0 * c + r).abs() > 1e-9 || (c - l).abs() > 1e-9 && ramp == 0.0
            });
            prop_assert!(kink, "no change at {n}");
        }
    }

    #[test]
    fn bad_agendas_name_the_activities() {
        let field = |r: Result<Agenda>| match r {
            Err(CoreError::Input { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let p = AgendaParams::CALDERITA;
        let mk =
            |v: &[(&str, f64, f64)]| v.iter().map(|&(o, a, b)| Activity::new(o, a, b)).collect::<Vec<_>>();
        assert_eq!(field(Agenda::new(mk(&[("tv", 5.0, 5.0)]), p)), "activities[0].end");
        assert_eq!(field(Agenda::new(mk(&[("a", 1.0, 2.0), ("tv", 9.0, 5.0)]), p)), "activities[1].end");
        assert_eq!(field(Agenda::new(mk(&[("tv", f64::NAN, 5.0)]), p)), "activities[0].start");
        assert_eq!(field(Agenda::new(mk(&[("tv", -1.0, 5.0)]), p)), "activities[0].start");
        assert_eq!(field(Agenda::new(mk(&[("tv", DAY, DAY + 5.0)]), p)), "activities[0].start");
        assert_eq!(field(Agenda::new(mk(&[("tv", 1.0, f64::INFINITY)]), p)), "activities[0].end");
        assert_eq!(field(Agenda::new(mk(&[("tv", 1.0, DAY + 2.0)]), p)), "activities[0].end");
        // Overlaps on one object, in either order; other objects may overlap freely.
        let o = mk(&[("tv", 9.0 * H, 10.0 * H), ("bed", 9.5 * H, 10.5 * H), ("tv", 9.5 * H, 11.0 * H)]);
        assert_eq!(field(Agenda::new(o, p)), "activities[0], activities[2]");
        let o = mk(&[("tv", 12.0 * H, 13.0 * H), ("tv", 8.0 * H, 12.5 * H)]);
        assert_eq!(field(Agenda::new(o, p)), "activities[0], activities[1]");
        // Containment and overlap across midnight.
        let o = mk(&[("tv", 8.0 * H, 12.0 * H), ("tv", 13.0 * H, 14.0 * H), ("tv", 9.0 * H, 9.5 * H)]);
        assert_eq!(field(Agenda::new(o, p)), "activities[0], activities[2]");
        let o = mk(&[("tv", 0.5 * H, 2.0 * H), ("tv", 23.0 * H, 25.0 * H)]);
        assert_eq!(field(Agenda::new(o, p)), "activities[0], activities[1]");
        // Parameters.
        let bad = |q: AgendaParams| field(Agenda::empty(q));
        assert_eq!(bad(AgendaParams { ramp: -1.0, ..p }), "params.ramp");
        assert_eq!(bad(AgendaParams { ramp: f64::NAN, ..p }), "params.ramp");
        assert_eq!(bad(AgendaParams { ramp: 2.0 * DAY, ..p }), "params.ramp");
        assert_eq!(bad(AgendaParams { idle: f64::NAN, ..p }), "params.idle");
        assert_eq!(bad(AgendaParams { active: 1.0, ..p }), "params.active");
        assert_eq!(bad(AgendaParams { active: f64::INFINITY, ..p }), "params.active");
        // The whole day as one activity is fine.
        let full = agenda(&[("tv", 0.0, DAY)]);
        assert!(full.active("tv", 12.0 * H) && close(full.cost("tv", 0.0), 3.5));
    }
}
