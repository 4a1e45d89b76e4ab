//! Progress monitoring of the built-in planners: a robot that has not come [`ProgressParams::distance`]
//! closer to its target (geodesic distance on its inflated grid, [`crate::plan::geodesic`]) within
//! [`ProgressParams::window`] seconds is *stalled*, and recovers.
//!
//! A recovery, decided here and carried out by the world for every built-in planner alike:
//! 1. the local control state is dropped (the partial goal, the mode and its hysteresis, the
//!    elastic band, the social path): the robot follows a new path;
//! 2. that path first drives back along the way the robot came ([`ProgressMonitor::way_back`],
//!    about [`BACKOFF_DISTANCE`] metres of its recent track) when that leads to more clearance
//!    (out of the doorway or dead end it stepped into), else to the point of greatest clearance
//!    within that distance ([`clearest_point`]), if one has more than where it is;
//! 3. then it follows a plain A* path re-planned from there with the blocking people (those within
//!    [`BLOCKING_RADIUS`] of the robot or near its path ahead, [`blocking_people`]) as temporary
//!    obstacles on a copy of the grid ([`mark_discs`]), so the new way goes round them (for the
//!    `astar_orca` baseline, the larger discs its ORCA keeps out of, and backing out keeps away
//!    from the blocking people too: `World::recover`);
//! 4. the recovery path is kept, without the planner's own re-planning, for [`RECOVERY_HOLD`]
//!    seconds, followed with ORCA among everyone by the planners that have a local planner (the
//!    social terms that held the robot back are off meanwhile), and for the first
//!    [`BACKOFF_TIME`] seconds the monitor does not count the distance given up by backing out.
//!
//! The monitor records the number of recoveries and the time the robot was stalled (from the
//! start of a window without progress to the progress that ends it), reported in the episode
//! metrics as `recoveries` and `monitor_stalled_time` ([`crate::metrics::RecoveryMetrics`]).
//!
//! The papers' planners have no such monitor (Daza et al. 2021, Sousa et al. 2022 and Calderita et
//! al. describe none); it is ours, in the spirit of ROS navigation's recovery behaviours (clear
//! the costmap, back up, re-plan). Deterministic: no randomness, the same inputs give the same
//! recovery.

use serde::Serialize;

use crate::map::{CostGrid, LETHAL};
use crate::math::Vec2;

/// Default of [`ProgressParams::distance`] (m).
pub const DEFAULT_DISTANCE: f64 = 0.5;
/// Default of [`ProgressParams::window`] (s). Chosen on the tuning split: the `social` planner's
/// deliberate detours round groups and waits for people to pass kept it from making 0.5 m of
/// progress for up to 9.9 s in episodes it completed (museum, episode seeds 0-9; 5.5 s in
/// `daza2021_path5`, seed 0), so 5 s would recover from detours that work.
pub const DEFAULT_WINDOW: f64 = 15.0;
/// People within this centre distance of the robot (m) block it and become temporary obstacles
/// of the recovery's re-plan.
pub const BLOCKING_RADIUS: f64 = 2.0;
/// People within this distance (m, centre to the path) of the first [`BLOCKING_PATH_AHEAD`]
/// metres of the robot's path block it too.
pub const BLOCKING_PATH_CLEARANCE: f64 = 1.0;
/// Length of the path ahead (m) whose nearby people block the robot.
pub const BLOCKING_PATH_AHEAD: f64 = 4.0;
/// How far a recovery backs out (m of the robot's recent track, or straight to the clearest point).
pub const BACKOFF_DISTANCE: f64 = 1.0;
/// For this long after a recovery (s) the distance given up by backing out is not counted: the
/// monitor's reference follows the robot.
pub const BACKOFF_TIME: f64 = 4.0;
/// A recovery path is kept (the social planners do not re-plan it) for this long (s).
pub const RECOVERY_HOLD: f64 = 8.0;
/// The monitor keeps a point of the robot's track every this many metres...
pub const TRACK_SPACING: f64 = 0.2;
/// ...and at most this many points (the last 6.4 m).
pub const TRACK_POINTS: usize = 32;

/// Settings of the progress monitor (scenario file: `[[robot]] progress = { ... }`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ProgressParams {
    /// Whether the monitor runs; default true. Off, the planner behaves as before the monitor
    /// existed and records no recovery.
    pub enabled: bool,
    /// Decrease of the geodesic distance to the current target (m) that counts as progress, in
    /// (0, 10]; default 0.5.
    pub distance: f64,
    /// Time (s) the robot has to make that progress before it recovers, in (0, 600]; default 15.
    pub window: f64,
}

impl Default for ProgressParams {
    fn default() -> Self {
        ProgressParams { enabled: true, distance: DEFAULT_DISTANCE, window: DEFAULT_WINDOW }
    }
}

impl ProgressParams {
    /// Largest accepted [`ProgressParams::distance`] (m).
    pub const MAX_DISTANCE: f64 = 10.0;
    /// Largest accepted [`ProgressParams::window`] (s).
    pub const MAX_WINDOW: f64 = 600.0;
}

/// One robot's progress monitor over an episode.
#[derive(Clone, Debug)]
pub struct ProgressMonitor {
    params: ProgressParams,
    /// Index of the target the distances are measured to.
    target: usize,
    /// Geodesic distance (m) at the last progress (or the last restart).
    anchor: f64,
    /// Time since then (s).
    since: f64,
    /// Whether the robot is stalled now (a window passed without progress, and no progress since).
    stalled: bool,
    /// Seconds left of the grace after a recovery (the reference follows the robot).
    grace: f64,
    /// Seconds left of the hold of the recovery path.
    hold: f64,
    /// The robot's recent track, oldest first, points [`TRACK_SPACING`] apart.
    track: Vec<Vec2>,
    recoveries: usize,
    stalled_time: f64,
}

impl ProgressMonitor {
    /// A monitor with `params` for a robot at `pos`, `geodesic` metres from its target.
    pub fn new(params: ProgressParams, geodesic: f64, pos: Vec2) -> Self {
        ProgressMonitor {
            params,
            target: 0,
            anchor: geodesic,
            since: 0.0,
            stalled: false,
            grace: 0.0,
            hold: 0.0,
            track: vec![pos],
            recoveries: 0,
            stalled_time: 0.0,
        }
    }

    /// The settings.
    pub fn params(&self) -> &ProgressParams {
        &self.params
    }

    /// Starts a new window at `geodesic` metres from the target (a new target, or the end of a
    /// stop where the robot stood on purpose); the track, the counts and the hold are kept.
    pub fn restart(&mut self, geodesic: f64) {
        self.anchor = geodesic;
        self.since = 0.0;
        self.stalled = false;
        self.grace = 0.0;
    }

    /// One control step of `dt` seconds, the robot now at `pos`, `geodesic` metres from its
    /// target number `target` (index in its route: a new target restarts the window; a
    /// non-finite distance is unknown, no progress). Returns whether the robot must recover now:
    /// a window of [`ProgressParams::window`] seconds has passed without a decrease of
    /// [`ProgressParams::distance`]. The caller then carries out the recovery and calls
    /// [`ProgressMonitor::recovered`]. Always false when the monitor is off.
    pub fn update(&mut self, target: usize, geodesic: f64, pos: Vec2, dt: f64) -> bool {
        if !self.params.enabled {
            return false;
        }
        self.note_track(pos);
        if target != self.target {
            self.target = target;
            self.restart(geodesic);
        }
        self.hold = (self.hold - dt).max(0.0);
        if self.grace > 1e-9 {
            self.grace = (self.grace - dt).max(0.0);
            if geodesic.is_finite() {
                self.anchor = geodesic;
            }
            self.since = 0.0;
            if self.stalled {
                self.stalled_time += dt;
            }
            return false;
        }
        if geodesic.is_finite()
            && (!self.anchor.is_finite() || geodesic <= self.anchor - self.params.distance)
        {
            self.anchor = geodesic;
            self.since = 0.0;
            self.stalled = false;
            return false;
        }
        self.since += dt;
        if self.stalled {
            self.stalled_time += dt;
        }
        if self.since + 1e-9 < self.params.window {
            return false;
        }
        if !self.stalled {
            // The whole window was without progress.
            self.stalled = true;
            self.stalled_time += self.since;
        }
        true
    }

    /// Notes that the caller carried out a recovery: counts it, starts the grace and the hold.
    pub fn recovered(&mut self) {
        self.recoveries += 1;
        self.since = 0.0;
        self.grace = BACKOFF_TIME;
        self.hold = RECOVERY_HOLD;
    }

    /// Whether the recovery path is held (the planner's own re-planning waits).
    pub fn holds_path(&self) -> bool {
        self.hold > 1e-9
    }

    /// Whether the robot is stalled now.
    pub fn stalled(&self) -> bool {
        self.stalled
    }

    /// Recoveries so far.
    pub fn recoveries(&self) -> usize {
        self.recoveries
    }

    /// Seconds the robot was stalled so far.
    pub fn stalled_time(&self) -> f64 {
        self.stalled_time
    }

    fn note_track(&mut self, pos: Vec2) {
        if !(pos.x.is_finite() && pos.y.is_finite()) {
            return;
        }
        match self.track.last() {
            Some(last) if (pos - last).norm() < TRACK_SPACING => {}
            _ => {
                if self.track.len() >= TRACK_POINTS {
                    self.track.remove(0);
                }
                self.track.push(pos);
            }
        }
    }

    /// The way back from `pos` along the robot's recent track: `pos`, then track points newest
    /// first until [`BACKOFF_DISTANCE`] metres are covered (or the track ends). Just `[pos]` when
    /// the track holds no point away from `pos`.
    pub fn way_back(&self, pos: Vec2) -> Vec<Vec2> {
        let mut out = vec![pos];
        let mut length = 0.0;
        for &q in self.track.iter().rev() {
            let Some(&last) = out.last() else { break };
            let step = (q - last).norm();
            if step < 1e-6 {
                continue;
            }
            length += step;
            out.push(q);
            if length >= BACKOFF_DISTANCE {
                break;
            }
        }
        out
    }
}

/// The point within `reach` metres of `pos` (sampled on 16 rays, every 0.1 m) with the greatest
/// `clearance` that the robot can drive to in a straight line (`visible`), if one beats `pos`'s.
pub fn clearest_point(
    pos: Vec2,
    reach: f64,
    clearance: &dyn Fn(Vec2) -> f64,
    visible: &dyn Fn(Vec2, Vec2) -> bool,
) -> Option<Vec2> {
    let mut best = (clearance(pos), None);
    let steps = (reach / 0.1).round().max(1.0) as usize;
    for k in 0..16 {
        let a = std::f64::consts::TAU * k as f64 / 16.0;
        let dir = Vec2::new(a.cos(), a.sin());
        for s in 1..=steps {
            let q = pos + dir * (reach * s as f64 / steps as f64);
            let c = clearance(q);
            if c > best.0 + 1e-9 && visible(pos, q) {
                best = (c, Some(q));
            }
        }
    }
    best.1
}

/// Indices of the people (centres `people`) who block a robot at `pos` with `path_ahead` (its
/// path from here on): within [`BLOCKING_RADIUS`] of the robot, or within
/// [`BLOCKING_PATH_CLEARANCE`] of the first [`BLOCKING_PATH_AHEAD`] metres of the path.
pub fn blocking_people(pos: Vec2, path_ahead: &[Vec2], people: &[Vec2]) -> Vec<usize> {
    let mut ahead: Vec<(Vec2, Vec2)> = Vec::new();
    let mut left = BLOCKING_PATH_AHEAD;
    for w in path_ahead.windows(2) {
        if left <= 0.0 {
            break;
        }
        let len = (w[1] - w[0]).norm();
        let end = if len > left { w[0] + (w[1] - w[0]) * (left / len) } else { w[1] };
        ahead.push((w[0], end));
        left -= len;
    }
    people
        .iter()
        .enumerate()
        .filter(|(_, q)| {
            (*q - pos).norm() <= BLOCKING_RADIUS
                || ahead.iter().any(|&(a, b)| segment_distance(**q, a, b) <= BLOCKING_PATH_CLEARANCE)
        })
        .map(|(k, _)| k)
        .collect()
}

/// Distance (m) from `q` to the segment `ab`.
fn segment_distance(q: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 { ((q - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (q - (a + ab * t)).norm()
}

/// Marks as [`LETHAL`] every cell of `grid` whose centre lies within a disc of `discs` (centre,
/// radius in metres): temporary obstacles for a re-plan.
pub fn mark_discs(grid: &mut CostGrid, discs: &[(Vec2, f64)]) {
    let spec = grid.spec;
    let res = spec.resolution;
    for &(c, r) in discs {
        if !(c.x.is_finite() && c.y.is_finite() && r.is_finite()) || r <= 0.0 {
            continue;
        }
        let n = (r / res).ceil() as isize + 1;
        let Some((cx, cy)) = spec.cell_of(c) else { continue };
        for dy in -n..=n {
            for dx in -n..=n {
                let (x, y) = (cx as isize + dx, cy as isize + dy);
                if x < 0 || y < 0 || x >= spec.width as isize || y >= spec.height as isize {
                    continue;
                }
                let (ux, uy) = (x as usize, y as usize);
                if (spec.center(ux, uy) - c).norm() <= r {
                    let i = spec.index(ux, uy);
                    grid.cost[i] = LETHAL;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::grid::GridSpec;

    /// The tests' settings: 0.5 m in 5 s.
    fn five() -> ProgressParams {
        ProgressParams { window: 5.0, ..Default::default() }
    }

    fn run(m: &mut ProgressMonitor, geo: impl Fn(usize) -> f64, steps: usize) -> Vec<usize> {
        (0..steps).filter(|&k| m.update(0, geo(k), Vec2::new(k as f64 * 0.01, 0.0), 0.1)).collect()
    }

    #[test]
    fn a_robot_making_progress_never_recovers() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::zeros());
        // 0.2 m/s: 1 m per window, twice the required progress.
        assert!(run(&mut m, |k| 20.0 - 0.02 * k as f64, 900).is_empty());
        assert_eq!((m.recoveries(), m.stalled_time()), (0, 0.0));
    }

    #[test]
    fn a_still_robot_recovers_once_per_window_and_counts_the_stall() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::zeros());
        let mut fired = Vec::new();
        for k in 0..200 {
            if m.update(0, 20.0, Vec2::zeros(), 0.1) {
                fired.push(k);
                m.recovered();
            }
        }
        // The first window ends at step 49 (5 s); after each recovery, 4 s of grace then a
        // new 5 s window: 49, 139.
        assert_eq!(fired, vec![49, 139]);
        assert_eq!(m.recoveries(), 2);
        // Stalled from t = 0 to the end: 200 steps.
        assert!((m.stalled_time() - 20.0).abs() < 1e-9, "{}", m.stalled_time());
        assert!(m.stalled());
    }

    #[test]
    fn progress_ends_a_stall_and_slow_progress_does_not_count() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::zeros());
        // 0.09 m/s: 0.45 m per window, short of 0.5 m.
        let fired = run(&mut m, |k| 20.0 - 0.009 * k as f64, 50);
        assert_eq!(fired, vec![49]);
        m.recovered();
        // Then it moves on at 0.6 m/s: the grace ends, progress ends the stall.
        let mut stalled_steps = 0;
        for k in 0..100 {
            assert!(!m.update(0, 19.0 - 0.06 * k as f64, Vec2::zeros(), 0.1));
            stalled_steps += usize::from(m.stalled());
        }
        assert!(!m.stalled());
        // Stalled: the 5 s window, the 4 s grace (40 steps, the reference following the robot to
        // 16.66 m), then 8 steps until 16.16 m (step 48 reaches 16.12 m).
        assert!((m.stalled_time() - (5.0 + 4.0 + 0.8)).abs() < 1e-9, "{}", m.stalled_time());
        assert_eq!(stalled_steps, 48);
    }

    #[test]
    fn a_disabled_monitor_never_fires_and_records_nothing() {
        let params = ProgressParams { enabled: false, ..five() };
        let mut m = ProgressMonitor::new(params, 20.0, Vec2::zeros());
        assert!(run(&mut m, |_| 20.0, 500).is_empty());
        assert_eq!((m.recoveries(), m.stalled_time(), m.stalled()), (0, 0.0, false));
    }

    #[test]
    fn an_unknown_distance_is_no_progress() {
        let mut m = ProgressMonitor::new(five(), f64::INFINITY, Vec2::zeros());
        assert_eq!(run(&mut m, |_| f64::NAN, 50), vec![49]);
        // A finite distance after an unknown start is progress.
        let mut m = ProgressMonitor::new(five(), f64::INFINITY, Vec2::zeros());
        assert!(run(&mut m, |k| if k < 30 { f64::INFINITY } else { 5.0 }, 60).is_empty());
    }

    #[test]
    fn restart_starts_a_new_window() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::zeros());
        assert!(run(&mut m, |_| 20.0, 40).is_empty());
        m.restart(30.0);
        assert_eq!(run(&mut m, |_| 30.0, 50), vec![49]);
    }

    #[test]
    fn a_new_target_starts_a_new_window() {
        let mut m = ProgressMonitor::new(five(), 2.0, Vec2::zeros());
        for k in 0..40 {
            assert!(!m.update(0, 2.0 - 0.05 * k as f64, Vec2::zeros(), 0.1));
        }
        // The next leg starts 10 m away: no progress against the old reference, but a new window.
        for k in 0..49 {
            assert!(!m.update(1, 10.0, Vec2::zeros(), 0.1), "step {k}");
        }
        assert!(m.update(1, 10.0, Vec2::zeros(), 0.1));
    }

    #[test]
    fn the_hold_lasts_its_time() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::zeros());
        m.recovered();
        let held = (0..200).take_while(|_| {
            m.update(0, 20.0, Vec2::zeros(), 0.1);
            m.holds_path()
        });
        // The step of the recovery and the next 79: 8 s.
        assert_eq!(held.count(), (RECOVERY_HOLD / 0.1).round() as usize - 1);
    }

    #[test]
    fn the_way_back_follows_the_track_for_the_backoff_distance() {
        let mut m = ProgressMonitor::new(five(), 20.0, Vec2::new(0.0, 0.0));
        // East along y = 0 to x = 2, then north into a doorway to (2, 1).
        for k in 0..=20 {
            m.update(0, 20.0 - 0.1 * k as f64, Vec2::new(0.1 * k as f64, 0.0), 0.1);
        }
        for k in 1..=10 {
            m.update(0, 18.0, Vec2::new(2.0, 0.1 * k as f64), 0.1);
        }
        let back = m.way_back(Vec2::new(2.0, 1.0));
        let length: f64 = back.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        assert!((BACKOFF_DISTANCE..BACKOFF_DISTANCE + TRACK_SPACING + 1e-9).contains(&length), "{back:?}");
        // Back out of the doorway: it ends on the corridor's line, not further into the doorway.
        let end = *back.last().expect("a way back");
        assert!(end.y < 0.2 && end.y >= 0.0, "{end:?}");
        // No track: the way back is just the position.
        let fresh = ProgressMonitor::new(five(), 20.0, Vec2::new(5.0, 5.0));
        assert_eq!(fresh.way_back(Vec2::new(5.0, 5.0)), vec![Vec2::new(5.0, 5.0)]);
    }

    #[test]
    fn the_track_is_bounded() {
        let mut m = ProgressMonitor::new(five(), 100.0, Vec2::zeros());
        for k in 0..1000 {
            m.update(0, 100.0 - 0.05 * k as f64, Vec2::new(0.05 * k as f64, 0.0), 0.1);
        }
        assert_eq!(m.track.len(), TRACK_POINTS);
    }

    #[test]
    fn the_clearest_point_leaves_a_doorway() {
        // A doorway along x: walls at |y| >= 0.5 for |x| < 0.5; open elsewhere (clearance grows
        // with the distance from the door frame).
        let clearance = |q: Vec2| {
            if q.x.abs() < 0.5 {
                0.5 - q.y.abs()
            } else {
                ((q.x.abs() - 0.5).powi(2) + (q.y.abs() - 0.5).max(0.0).powi(2)).sqrt() + 0.5
            }
        };
        let visible = |_: Vec2, _: Vec2| true;
        let q = clearest_point(Vec2::zeros(), 1.0, &clearance, &visible).expect("a clearer point");
        assert!(q.x.abs() > 0.9, "{q:?}");
        // Nothing clearer: none.
        assert!(clearest_point(Vec2::zeros(), 1.0, &|_| 1.0, &visible).is_none());
        // Hidden: none.
        assert!(clearest_point(Vec2::zeros(), 1.0, &clearance, &|_, _| false).is_none());
    }

    #[test]
    fn blocking_people_are_near_the_robot_or_its_path() {
        let path = vec![Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)];
        let people = vec![
            Vec2::new(1.5, 1.0),  // near the robot
            Vec2::new(3.5, 0.8),  // near the path ahead
            Vec2::new(6.0, 0.5),  // near the path, beyond 4 m
            Vec2::new(-3.0, 0.0), // behind, far
            Vec2::new(3.0, 2.5),  // beside, far
        ];
        assert_eq!(blocking_people(Vec2::zeros(), &path, &people), vec![0, 1]);
        assert_eq!(blocking_people(Vec2::zeros(), &[], &people), vec![0]);
    }

    #[test]
    fn discs_become_lethal_cells() {
        let spec = GridSpec { origin: Vec2::zeros(), resolution: 0.1, width: 50, height: 50 };
        let mut g = CostGrid { spec, cost: vec![0; spec.len()] };
        mark_discs(&mut g, &[(Vec2::new(2.5, 2.5), 0.5), (Vec2::new(f64::NAN, 0.0), 1.0)]);
        let lethal = g.cost.iter().filter(|&&c| c == LETHAL).count();
        // About pi r^2 / res^2 = 78.5 cells.
        assert!((70..=90).contains(&lethal), "{lethal}");
        assert_eq!(g.cost[spec.index(25, 25)], LETHAL);
        assert_eq!(g.cost[spec.index(25, 31)], 0);
        // A disc at the grid's edge is clipped, not a panic.
        mark_discs(&mut g, &[(Vec2::new(0.05, 0.05), 0.3)]);
        assert_eq!(g.cost[0], LETHAL);
    }
}
