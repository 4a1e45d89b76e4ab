//! Stop and wait: the `astar_stop` planner's local rule, the non-social baseline of a robot
//! that follows its plain A* path and stops for whoever stands in its way.
//!
//! Not a paper's method: the field-standard "stop when something is in the way" behaviour of a
//! path-following base, with the re-plan around a blocker that a navigation stack's recovery
//! does. The rule, every control step:
//! - **Corridor ahead.** Someone (a person or another robot) *blocks* the robot when their centre,
//!   now or where their current velocity takes them within [`StopParams::horizon`] (1.5 s, so a
//!   robot or person about to cross in front counts), is within `half_width = r_robot + r_other +
//!   margin` of the path ahead and their projection on it is ahead of the robot (arc length in
//!   `(0, reach]`, so nobody beside or behind the robot counts), with the reach the stopping
//!   distance plus the same clearance: `reach = v^2 / (2 a_max) + v dt + r_robot + r_other +
//!   margin` (`v` the robot's speed, `a_max` its maximum deceleration, `dt` one control period of
//!   reaction). Among robots, only those with the right of way (a lower index) count where they
//!   are about to be; the others count where they are. Past the end of the path (the robot's target, where it stops anyway), only
//!   someone the robot would touch there blocks (closer to the end than `r_robot + r_other`).
//! - **Stop.** A moving robot with a blocker in its corridor (at its current speed's reach) stops
//!   (desired velocity zero: it brakes at its deceleration limit).
//! - **Resume.** A stopped robot moves on when its corridor is clear at the reach of its maximum
//!   speed (the hysteresis keeps it from creeping up to a person standing still).
//! - **Re-plan.** After [`StopParams::wait`] seconds stopped (default 2 s), the robot re-plans its
//!   plain A* path with the blockers as temporary obstacles ([`with_temporary_obstacles`]: discs
//!   of the corridor's half-width plus one grid cell, so the new path's corridor clears them),
//!   then waits again, re-planning every `wait` seconds while blocked.

use crate::map::{CostGrid, INSCRIBED};
use crate::math::Vec2;

/// Parameters of the stop-and-wait rule.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopParams {
    /// Clearance added to the two radii, in the corridor's half-width and in its reach (m);
    /// default 0.3: the robot stops with at least 0.3 m between its body and the other's.
    pub margin: f64,
    /// Seconds stopped before re-planning around the blockers (s); default 2.0.
    pub wait: f64,
    /// Spacing of the points sampled along the path ahead (m); default 0.1.
    pub sample: f64,
    /// How far ahead in time the others' positions are predicted at their current velocities (s);
    /// default 1.5 (sampled every 0.25 s): about the stopping time at full speed (1 s for Pepper)
    /// plus a half-second of reaction.
    pub horizon: f64,
}

impl Default for StopParams {
    fn default() -> Self {
        StopParams { margin: 0.3, wait: 2.0, sample: 0.1, horizon: 1.5 }
    }
}

/// A person or another robot as the rule sees it: a disc.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Centre (m).
    pub pos: Vec2,
    /// Radius (m).
    pub radius: f64,
    /// Velocity (m/s).
    pub vel: Vec2,
    /// Whether its predicted positions count, not only where it is now: true for people and for
    /// robots with the right of way over this one (a lower index); a robot gives way to those
    /// about to cross its path, so that two robots meeting do not both stop for each other.
    pub predicted: bool,
}

/// Step of the prediction of the others' positions (s).
const PREDICTION_STEP: f64 = 0.25;

/// The robot itself this step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Robot {
    /// Radius (m).
    pub radius: f64,
    /// Current speed (m/s, >= 0).
    pub speed: f64,
    /// Maximum speed (m/s, > 0).
    pub max_speed: f64,
    /// Maximum deceleration (m/s^2, > 0).
    pub max_decel: f64,
}

/// What the rule decided for one step.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum StopDecision {
    /// Follow the path.
    Go,
    /// Stand (brake to a stop).
    Stop,
    /// Still stopped after the wait: re-plan around these blockers (indices into the bodies),
    /// and stand this step.
    Replan(Vec<usize>),
}

/// The centre distance along the path within which `other_radius` blocks a robot at `speed`
/// (m/s) that decelerates at `max_decel` (m/s^2), with a reaction of one control period `dt`.
pub fn reach(speed: f64, max_decel: f64, dt: f64, robot_radius: f64, other_radius: f64, margin: f64) -> f64 {
    let v = speed.max(0.0);
    v * v / (2.0 * max_decel.max(1e-9)) + v * dt.max(0.0) + robot_radius + other_radius + margin
}

/// The polyline ahead `ahead` (starting at the robot's centre) as cumulative arc lengths.
fn arc_lengths(ahead: &[Vec2]) -> Vec<f64> {
    let mut s = 0.0;
    let mut out = Vec::with_capacity(ahead.len());
    for (k, p) in ahead.iter().enumerate() {
        if k > 0 {
            s += (p - ahead[k - 1]).norm();
        }
        out.push(s);
    }
    out
}

/// The closest point of the polyline to `q`: (arc length, distance, whether it lies past the
/// polyline's end). A projection before the polyline's start gets a negative arc length (the
/// signed distance along the first segment), so that someone behind or beside the robot is told
/// from someone ahead.
fn project(ahead: &[Vec2], arc: &[f64], q: Vec2) -> (f64, f64, bool) {
    let Some(&first) = ahead.first() else { return (f64::NEG_INFINITY, f64::INFINITY, false) };
    let mut best = (0.0, (q - first).norm());
    if let Some(&second) = ahead.get(1) {
        let d = second - first;
        let len = d.norm();
        if len > 1e-12 {
            let along = (q - first).dot(&d) / len;
            if along <= 0.0 {
                best = (along, (q - first).norm());
            }
        }
    }
    for k in 1..ahead.len() {
        let (a, b) = (ahead[k - 1], ahead[k]);
        let ab = b - a;
        let len2 = ab.norm_squared();
        if len2 <= 1e-24 {
            continue;
        }
        let t = ((q - a).dot(&ab) / len2).clamp(0.0, 1.0);
        let d = (q - (a + ab * t)).norm();
        if k == 1 && t <= 0.0 {
            continue; // at or before the start: the signed value above stands
        }
        if d < best.1 - 1e-12 {
            best = (arc[k - 1] + t * len2.sqrt(), d);
        }
    }
    // Past the end: beyond the last segment of non-zero length (the samples repeat the end).
    let last = ahead.windows(2).rev().find(|w| (w[1] - w[0]).norm_squared() > 1e-24);
    let past_end = last.is_some_and(|w| {
        let (a, b) = (w[0], w[1]);
        (q - b).dot(&(b - a)) > 0.0 && (best.0 - arc[arc.len() - 1]).abs() < 1e-9
    });
    (best.0, best.1, past_end)
}

/// The indices of `others` in the corridor ahead of `robot` along `ahead` (a polyline starting at
/// the robot's centre, along its path), each with the reach of `speed` (see the module docs).
/// `ends_at_goal`: the polyline ends at the robot's target (where it stops), not merely at the
/// reach.
pub fn blockers(
    ahead: &[Vec2],
    ends_at_goal: bool,
    robot: &Robot,
    speed: f64,
    others: &[Body],
    dt: f64,
    params: &StopParams,
) -> Vec<usize> {
    let arc = arc_lengths(ahead);
    let samples = (params.horizon.max(0.0) / PREDICTION_STEP).floor() as usize;
    others
        .iter()
        .enumerate()
        .filter(|(_, o)| {
            let touch = robot.radius + o.radius;
            let half_width = touch + params.margin;
            let limit = reach(speed, robot.max_decel, dt, robot.radius, o.radius, params.margin);
            let samples = if o.predicted { samples } else { 0 };
            (0..=samples).any(|k| {
                let q = o.pos + o.vel * (k as f64 * PREDICTION_STEP);
                let (s, d, past_end) = project(ahead, &arc, q);
                let width = if past_end && ends_at_goal { touch } else { half_width };
                s > 0.0 && s <= limit && d <= width
            })
        })
        .map(|(k, _)| k)
        .collect()
}

/// The longest reach any of `others` can have at `speed`: how far ahead the path must be given.
pub fn max_reach(robot: &Robot, speed: f64, others: &[Body], dt: f64, params: &StopParams) -> f64 {
    let r = others.iter().map(|o| o.radius).fold(0.0, f64::max);
    reach(speed, robot.max_decel, dt, robot.radius, r, params.margin)
}

/// The rule's state for one robot.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StopAndWait {
    /// Whether the robot is stopped for a blocker.
    stopped: bool,
    /// Seconds since it stopped or last re-planned.
    waited: f64,
}

impl StopAndWait {
    /// A moving robot.
    pub fn new() -> Self {
        Self::default()
    }

    /// Whether the robot is stopped for a blocker.
    pub fn stopped(&self) -> bool {
        self.stopped
    }

    /// One control step of `dt` seconds for `robot` among `others`, with `corridors` the polylines
    /// ahead of it, each with whether it ends at the robot's target (see [`blockers`]): its path
    /// ahead (from its centre, at least [`max_reach`] at its maximum speed long, or ending at its
    /// target) and the straight line along its velocity (a robot off its path, after a push or a
    /// re-plan, moves along neither alone). Someone in any of them blocks.
    pub fn update(
        &mut self,
        corridors: &[(&[Vec2], bool)],
        robot: &Robot,
        others: &[Body],
        dt: f64,
        params: &StopParams,
    ) -> StopDecision {
        let blocking = |speed: f64| -> Vec<usize> {
            let mut b: Vec<usize> = corridors
                .iter()
                .flat_map(|&(ahead, end)| blockers(ahead, end, robot, speed, others, dt, params))
                .collect();
            b.sort_unstable();
            b.dedup();
            b
        };
        if !self.stopped {
            if blocking(robot.speed).is_empty() {
                return StopDecision::Go;
            }
            self.stopped = true;
            self.waited = 0.0;
            return StopDecision::Stop;
        }
        let blocking = blocking(robot.max_speed);
        if blocking.is_empty() {
            *self = Self::new();
            return StopDecision::Go;
        }
        self.waited += dt;
        if self.waited + 1e-9 >= params.wait {
            self.waited = 0.0;
            return StopDecision::Replan(blocking);
        }
        StopDecision::Stop
    }
}

/// `grid` with every cell whose centre lies within `clearance(body) + one cell` of a body's centre
/// made impassable: the blockers as temporary obstacles for a re-plan (`clearance` the corridor's
/// half-width for that body, so that the new path's corridor clears it).
pub fn with_temporary_obstacles(grid: &CostGrid, bodies: &[(Body, f64)]) -> CostGrid {
    let mut out = grid.clone();
    let spec = grid.spec;
    let res = spec.resolution;
    for (b, clearance) in bodies {
        let r = clearance + res;
        let n = (r / res).ceil() as i64 + 1;
        let Some((cx, cy)) = spec.cell_of(b.pos) else { continue };
        for dy in -n..=n {
            for dx in -n..=n {
                let (x, y) = (cx as i64 + dx, cy as i64 + dy);
                if x < 0 || y < 0 || !spec.contains_cell(x as usize, y as usize) {
                    continue;
                }
                let (x, y) = (x as usize, y as usize);
                if (spec.center(x, y) - b.pos).norm() <= r {
                    let idx = spec.index(x, y);
                    out.cost[idx] = out.cost[idx].max(INSCRIBED);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::{Bounds, StaticGeometry};
    use crate::map::grid::{DistanceField, GridSpec, OccupancyGrid};
    use crate::plan::{PathPlanner, SearchMode, snap_to_passable};

    const DT: f64 = 0.1;

    fn pepper(speed: f64) -> Robot {
        Robot { radius: 0.24, speed, max_speed: 0.55, max_decel: 0.55 }
    }

    fn person(x: f64, y: f64) -> Body {
        Body { pos: Vec2::new(x, y), radius: 0.2, vel: Vec2::zeros(), predicted: true }
    }

    /// A straight path from the origin along +x, 5 m.
    fn straight() -> Vec<Vec2> {
        (0..=50).map(|k| Vec2::new(0.1 * f64::from(k), 0.0)).collect()
    }

    #[test]
    fn the_reach_is_the_stopping_distance_plus_the_clearance() {
        let p = StopParams::default();
        // 0.55^2 / (2 * 0.55) + 0.055 + 0.24 + 0.2 + 0.3
        let r = reach(0.55, 0.55, DT, 0.24, 0.2, p.margin);
        assert!((r - (0.275 + 0.055 + 0.74)).abs() < 1e-12, "{r}");
        assert!((reach(0.0, 0.55, DT, 0.24, 0.2, p.margin) - 0.74).abs() < 1e-12);
    }

    #[test]
    fn stops_for_a_person_ahead() {
        let p = StopParams::default();
        let mut s = StopAndWait::new();
        let d = s.update(&[(&straight()[..], false)], &pepper(0.55), &[person(1.0, 0.1)], DT, &p);
        assert_eq!(d, StopDecision::Stop);
        assert!(s.stopped());
        // Farther than the reach at full speed (1.07 m): no stop yet.
        let mut s = StopAndWait::new();
        assert_eq!(
            s.update(&[(&straight()[..], false)], &pepper(0.55), &[person(1.2, 0.0)], DT, &p),
            StopDecision::Go
        );
    }

    #[test]
    fn does_not_stop_for_a_person_beside_or_behind() {
        let p = StopParams::default();
        let mut s = StopAndWait::new();
        for q in [person(0.0, 0.5), person(-0.5, 0.0), person(-0.3, 0.3), person(0.8, 0.8)] {
            assert_eq!(
                s.update(&[(&straight()[..], false)], &pepper(0.55), &[q], DT, &p),
                StopDecision::Go,
                "{q:?}"
            );
        }
        assert!(!s.stopped());
    }

    #[test]
    fn stops_for_another_robot_ahead_too() {
        let p = StopParams::default();
        let robot = Body { pos: Vec2::new(0.9, -0.2), radius: 0.24, vel: Vec2::zeros(), predicted: true };
        assert_eq!(
            blockers(&straight(), false, &pepper(0.4), 0.4, &[person(3.0, 0.0), robot], DT, &p),
            vec![1]
        );
    }

    #[test]
    fn stops_for_someone_about_to_cross_ahead() {
        // A robot 1.2 m to the side of the path, 0.8 m ahead, coming at 0.55 m/s: not in the
        // corridor now, in it within the horizon.
        let p = StopParams::default();
        let crossing =
            Body { pos: Vec2::new(0.8, -1.2), radius: 0.24, vel: Vec2::new(0.0, 0.55), predicted: true };
        assert_eq!(blockers(&straight(), false, &pepper(0.55), 0.55, &[crossing], DT, &p), vec![0]);
        let leaving = Body { vel: Vec2::new(0.0, -0.55), ..crossing };
        assert!(blockers(&straight(), false, &pepper(0.55), 0.55, &[leaving], DT, &p).is_empty());
        // A robot without the right of way over this one counts only where it is.
        let giving_way = Body { predicted: false, ..crossing };
        assert!(blockers(&straight(), false, &pepper(0.55), 0.55, &[giving_way], DT, &p).is_empty());
    }

    #[test]
    fn past_the_goal_only_someone_the_robot_would_touch_blocks() {
        // The path ends at the goal 0.5 m ahead; a person 0.6 m beyond it is in the corridor's
        // reach but the robot stops at its goal first.
        let p = StopParams::default();
        let path = [Vec2::new(0.0, 0.0), Vec2::new(0.5, 0.0), Vec2::new(0.5, 0.0)];
        assert!(blockers(&path, true, &pepper(0.3), 0.3, &[person(1.1, 0.0)], DT, &p).is_empty());
        // Not the goal (the path goes on beyond what was sampled): it blocks.
        assert_eq!(blockers(&path, false, &pepper(0.3), 0.3, &[person(1.1, 0.0)], DT, &p), vec![0]);
        // Standing at the goal: it blocks.
        assert_eq!(blockers(&path, true, &pepper(0.3), 0.3, &[person(0.7, 0.0)], DT, &p), vec![0]);
    }

    #[test]
    fn the_corridor_follows_a_turning_path() {
        // The path turns left after 0.5 m: a person straight ahead of the robot's heading, off
        // the path, does not block; one on the path past the corner does.
        let p = StopParams::default();
        let path = [Vec2::new(0.0, 0.0), Vec2::new(0.5, 0.0), Vec2::new(0.5, 2.0)];
        assert!(blockers(&path, false, &pepper(0.55), 0.55, &[person(1.3, 0.0)], DT, &p).is_empty());
        assert_eq!(blockers(&path, false, &pepper(0.55), 0.55, &[person(0.5, 0.5)], DT, &p), vec![0]);
    }

    #[test]
    fn resumes_when_the_person_leaves() {
        let p = StopParams::default();
        let mut s = StopAndWait::new();
        // At 0.3 m/s the reach is 0.85 m.
        assert_eq!(
            s.update(&[(&straight()[..], false)], &pepper(0.3), &[person(0.8, 0.0)], DT, &p),
            StopDecision::Stop
        );
        // Still there (the robot has stopped): stand.
        assert_eq!(
            s.update(&[(&straight()[..], false)], &pepper(0.0), &[person(0.8, 0.0)], DT, &p),
            StopDecision::Stop
        );
        // Stepped just out of the reach at standstill but within the reach at full speed: still
        // stand (no creeping up).
        assert_eq!(
            s.update(&[(&straight()[..], false)], &pepper(0.0), &[person(1.0, 0.0)], DT, &p),
            StopDecision::Stop
        );
        // Gone to the side: go.
        assert_eq!(
            s.update(&[(&straight()[..], false)], &pepper(0.0), &[person(0.9, 1.5)], DT, &p),
            StopDecision::Go
        );
        assert!(!s.stopped());
    }

    #[test]
    fn re_plans_around_after_the_wait() {
        let p = StopParams::default();
        let mut s = StopAndWait::new();
        let me = pepper(0.0);
        let them = [person(0.7, 0.0)];
        assert_eq!(s.update(&[(&straight()[..], false)], &pepper(0.2), &them, DT, &p), StopDecision::Stop);
        let mut replan_at = None;
        for k in 1..=40 {
            match s.update(&[(&straight()[..], false)], &me, &them, DT, &p) {
                StopDecision::Stop => {}
                StopDecision::Replan(b) => {
                    assert_eq!(b, vec![0]);
                    replan_at = Some(k);
                    break;
                }
                StopDecision::Go => panic!("the person is still there"),
            }
        }
        assert_eq!(replan_at, Some(20), "a re-plan after 2 s (20 steps of 0.1 s)");

        // The re-plan on an open room: the new path goes around the person, and its corridor is
        // clear of them, so the robot goes on.
        let bounds = Bounds { min: Vec2::new(-1.0, -3.0), max: Vec2::new(6.0, 3.0) };
        // A room with one small box in a far corner.
        let corner = vec![Vec2::new(5.5, 2.5), Vec2::new(5.9, 2.5), Vec2::new(5.9, 2.9), Vec2::new(5.5, 2.9)];
        let geom = StaticGeometry::new(vec![corner], bounds).expect("geometry");
        let spec = GridSpec::covering(bounds, 0.1).expect("spec");
        let occ = OccupancyGrid::rasterize(&geom, spec);
        let grid = CostGrid::inflated(&DistanceField::from_occupancy(&occ), 0.3);
        let clearance = me.radius + them[0].radius + p.margin;
        let blocked = with_temporary_obstacles(&grid, &[(them[0], clearance)]);
        // The robot stands inside the temporary obstacle: the search starts from the nearest
        // passable cell, as the world's re-plan does (`snap_to_passable`).
        let start = snap_to_passable(&blocked, Vec2::new(0.0, 0.0)).expect("start");
        let goal = spec.cell_of(Vec2::new(4.0, 0.0)).expect("goal");
        let path = PathPlanner::new()
            .plan(&blocked, start, goal, SearchMode { weight: 0.0, heuristic: true })
            .expect("a way around");
        let mut pts = vec![Vec2::new(0.0, 0.0)];
        pts.extend(path.cells.iter().map(|&(x, y)| spec.center(x, y)));
        let closest = pts[1..].iter().map(|q| (q - them[0].pos).norm()).fold(f64::INFINITY, f64::min);
        assert!(closest > clearance, "the new path keeps {closest:.2} m > {clearance:.2} m from the person");
        assert_eq!(s.update(&[(&pts[..], false)], &me, &them, DT, &p), StopDecision::Go);
    }
}
