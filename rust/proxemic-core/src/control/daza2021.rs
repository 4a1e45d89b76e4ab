//! Daza et al. 2021, Algorithm 1 ("Social navigation process"), as a pure decision function.
//!
//! One call decides one control step of one robot: which local planner runs (lines 5-25), the
//! partial goal on the plain A* path it heads for (lines 8, 16, 19), and which other robots get a
//! proxemic zone because they stand in a human group (line 18, §4.3). It does not move anything;
//! the planner that calls it runs the chosen controller (ORCA among robots only, or Social
//! Momentum with no comfort term).
//!
//! Line by line (the paper's numbering):
//! - 1 (A*) is the caller's: `path` is the plain A* path, not a social one.
//! - 3 detection: the mobile objects within [`Daza2021Params::detection_range`] of the robot.
//! - 4 identities: an object with an `id` is a robot, one without is a person (the paper's
//!   "mobile objects without IDs").
//! - 5-11 only robots detected: 6 check the collision cone of each robot; 7-8 a possible collision
//!   runs ORCA toward the partial goal; 9-10 otherwise the path is followed.
//! - 12-22 humans detected: 13 the groups (given by the caller's detector, Movement and
//!   Orientation); 14-16 the nearest mobile object is a person: Social Momentum; 17-19 otherwise,
//!   a group is detected: Social Momentum, the robots taking part in the group treated as people;
//!   20-21 otherwise the path is followed.
//! - 23-24 nothing detected: the path is followed.
//!
//! Where the paper is silent, each choice is documented on its parameter.

use crate::control::mode_switch::in_collision_cone;
use crate::error::{CoreError, Result};
use crate::math::Vec2;
use crate::proxemics::HallZones;

/// A mobile object the robot detects (Algorithm 1 line 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MobileObject {
    /// Position (m, world frame, finite).
    pub pos: Vec2,
    /// Velocity (m/s, finite).
    pub vel: Vec2,
    /// Body radius (m, finite, `>= 0`).
    pub radius: f64,
    /// The identity a robot transmits (line 4); `None` for a person.
    pub id: Option<u64>,
}

impl MobileObject {
    /// Whether this object is a person (no identity, line 4).
    pub fn is_person(&self) -> bool {
        self.id.is_none()
    }
}

/// The robot deciding (its state for this step).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotState {
    /// Position (m, finite).
    pub pos: Vec2,
    /// The velocity it would take following the path (m/s, finite): the collision cone of
    /// line 6 is checked with it.
    pub pref_vel: Vec2,
    /// Body radius (m, finite, `>= 0`).
    pub radius: f64,
}

/// Parameters of [`daza2021_decide`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Daza2021Params {
    /// Hall's radii (m, centre to centre); default [`HallZones::DAZA2021`] (0.5, 1, 4 m, Daza
    /// 2021 §2).
    pub zones: HallZones,
    /// Line 3: objects farther than this are not detected (m, `> 0`). Paper: not given. Ours:
    /// 4.0 m, the social radius, so every object whose social zone holds the robot is seen.
    pub detection_range: f64,
    /// Line 6: the collision cone's time horizon (s, `> 0`). Paper: not given. Ours: 3.0 s, the
    /// value of proxemic's own mode switch.
    pub cone_horizon: f64,
    /// Lines 8, 16, 19: the partial goal lies this far along the A* path beyond the point nearest
    /// the robot (m, `> 0`). Paper: "a point in the planned path", distance not given. Ours:
    /// 1.5 m, the value of proxemic's own planner.
    pub partial_goal_distance: f64,
    /// Line 18 / §4.3: an extra condition we may keep for a robot to join a human group: `Some(s)`
    /// requires its speed to be `<= s` (m/s). Default `None`: the paper's rule only (module
    /// [`daza2021_decide`] docs).
    pub join_max_speed: Option<f64>,
}

impl Default for Daza2021Params {
    fn default() -> Self {
        Daza2021Params {
            zones: HallZones::DAZA2021,
            detection_range: 4.0,
            cone_horizon: 3.0,
            partial_goal_distance: 1.5,
            join_max_speed: None,
        }
    }
}

/// The local planner Algorithm 1 picks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Daza2021Mode {
    /// Follow the A* path (lines 10, 21, 24).
    FollowPath,
    /// ORCA among robots only, toward the partial goal (line 8).
    Orca,
    /// Social Momentum toward the partial goal, no comfort term (lines 16, 19).
    SocialMomentum,
}

/// One step's decision.
#[derive(Clone, Debug, PartialEq)]
pub struct Daza2021Decision {
    /// The planner to run.
    pub mode: Daza2021Mode,
    /// The line of Algorithm 1 that decided (8, 10, 16, 19, 21 or 24).
    pub line: u8,
    /// The partial goal on the A* path (m).
    pub partial_goal: Vec2,
    /// Index (into `objects`) of the nearest detected mobile object, if any.
    pub nearest: Option<usize>,
    /// Indices (into `objects`) of the robots that take part in a human group and get a
    /// proxemic zone, treated as people (line 18); sorted.
    pub robots_in_groups: Vec<usize>,
}

/// Algorithm 1 of Daza et al. 2021 for one step (module docs).
///
/// - `robot`: the deciding robot;
/// - `path`: the plain A* path (line 1), at least one point, finite (m);
/// - `objects`: the other mobile objects (people have no `id`, robots have one);
/// - `groups`: the groups of people the detector found (line 13), as lists of indices into
///   `objects` (people only; singletons may be omitted);
/// - `params`: [`Daza2021Params`].
///
/// A robot takes part in a human group (line 18) when it invades the personal zone of one of the
/// group's people and their intimate areas intersect (§4.3: centre distance `< personal` and
/// `< 2 * intimate`; both 1 m with Daza's radii), and, only if
/// [`Daza2021Params::join_max_speed`] is set, it is that slow. A robot taking part in an
/// interaction with a lone person makes that pair a group too (Fig. 19-21: "groups of people and
/// robots").
///
/// Errors (`CoreError::Input`): a non-finite robot state, path point or object, a negative radius,
/// an empty path, a group index out of range or naming a robot, or an invalid parameter; each
/// names the field.
pub fn daza2021_decide(
    robot: &RobotState,
    path: &[Vec2],
    objects: &[MobileObject],
    groups: &[Vec<usize>],
    params: &Daza2021Params,
) -> Result<Daza2021Decision> {
    validate(robot, path, objects, groups, params)?;
    let pos = robot.pos;
    let partial_goal = point_ahead(path, pos, params.partial_goal_distance);
    // Line 3: detection.
    let detected: Vec<usize> =
        (0..objects.len()).filter(|&i| (objects[i].pos - pos).norm() <= params.detection_range).collect();
    let nearest = detected.iter().copied().min_by(|&a, &b| {
        (objects[a].pos - pos).norm().total_cmp(&(objects[b].pos - pos).norm()).then(a.cmp(&b))
    });
    let all_groups = with_singletons(objects, groups);
    let robots_in_groups: Vec<usize> = (0..objects.len())
        .filter(|&k| !objects[k].is_person())
        .filter(|&k| all_groups.iter().any(|g| joins(objects, g, k, params)))
        .collect();
    let decision = |mode, line| Daza2021Decision {
        mode,
        line,
        partial_goal,
        nearest,
        robots_in_groups: robots_in_groups.clone(),
    };
    // Lines 23-24: nothing detected.
    let Some(nearest_i) = nearest else {
        return Ok(decision(Daza2021Mode::FollowPath, 24));
    };
    // Line 4-5: only robots (every detected object has an identity).
    if detected.iter().all(|&i| !objects[i].is_person()) {
        // Line 6: the collision cone.
        let possible = detected.iter().any(|&i| {
            let o = &objects[i];
            in_collision_cone(pos, robot.pref_vel, robot.radius, o.pos, o.vel, o.radius, params.cone_horizon)
        });
        return Ok(if possible {
            decision(Daza2021Mode::Orca, 8)
        } else {
            decision(Daza2021Mode::FollowPath, 10)
        });
    }
    // Line 12: humans detected. Line 14: the nearest mobile object is a person.
    if objects[nearest_i].is_person() {
        return Ok(decision(Daza2021Mode::SocialMomentum, 16));
    }
    // Line 17: a group is detected (people only, or people with robots taking part), with a
    // detected member.
    let group_detected = all_groups.iter().any(|g| {
        let joined = robots_in_groups.iter().any(|&k| joins(objects, g, k, params));
        (g.len() >= 2 || joined) && g.iter().any(|i| detected.contains(i))
    });
    if group_detected {
        return Ok(decision(Daza2021Mode::SocialMomentum, 19));
    }
    // Lines 20-21.
    Ok(decision(Daza2021Mode::FollowPath, 21))
}

/// Whether robot `k` takes part in the group `g` (§4.3; see [`daza2021_decide`]).
fn joins(objects: &[MobileObject], g: &[usize], k: usize, params: &Daza2021Params) -> bool {
    let r = &objects[k];
    if let Some(s) = params.join_max_speed
        && r.vel.norm() > s
    {
        return false;
    }
    let bound = params.zones.personal.min(2.0 * params.zones.intimate);
    g.iter().any(|&i| (objects[i].pos - r.pos).norm() < bound)
}

/// The caller's groups plus a group of one for every person in none.
fn with_singletons(objects: &[MobileObject], groups: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let mut all = groups.to_vec();
    for (i, o) in objects.iter().enumerate() {
        if o.is_person() && !groups.iter().any(|g| g.contains(&i)) {
            all.push(vec![i]);
        }
    }
    all
}

/// The point `distance` (m) along the polyline `path` beyond the point of the path nearest `pos`
/// (its last point when the path ends sooner).
fn point_ahead(path: &[Vec2], pos: Vec2, distance: f64) -> Vec2 {
    let (mut best_d, mut best_seg, mut best_t) = (f64::INFINITY, 0, 0.0);
    for k in 0..path.len().saturating_sub(1) {
        let (a, b) = (path[k], path[k + 1]);
        let ab = b - a;
        let len2 = ab.norm_squared();
        let t = if len2 > 0.0 { ((pos - a).dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
        let d = (pos - (a + ab * t)).norm();
        if d < best_d {
            (best_d, best_seg, best_t) = (d, k, t);
        }
    }
    if path.len() < 2 {
        return path[0];
    }
    let mut left = distance;
    let mut from = path[best_seg] + (path[best_seg + 1] - path[best_seg]) * best_t;
    for &next in &path[best_seg + 1..] {
        let step = (next - from).norm();
        if step >= left {
            return from + (next - from) * (left / step);
        }
        left -= step;
        from = next;
    }
    path[path.len() - 1]
}

fn validate(
    robot: &RobotState,
    path: &[Vec2],
    objects: &[MobileObject],
    groups: &[Vec<usize>],
    params: &Daza2021Params,
) -> Result<()> {
    let finite = |v: Vec2| v.x.is_finite() && v.y.is_finite();
    let bad = |field: String, expected: &str, found: String| Err(CoreError::input(field, expected, found));
    if !finite(robot.pos) || !finite(robot.pref_vel) {
        return bad("robot".into(), "a finite position and velocity", format!("{robot:?}"));
    }
    if !(robot.radius.is_finite() && robot.radius >= 0.0) {
        return bad("robot.radius".into(), "a finite radius >= 0 (m)", robot.radius.to_string());
    }
    if path.is_empty() {
        return bad("path".into(), "at least one point", "an empty path".into());
    }
    if let Some(k) = path.iter().position(|&p| !finite(p)) {
        return bad(format!("path[{k}]"), "finite coordinates (m)", format!("{:?}", path[k]));
    }
    for (i, o) in objects.iter().enumerate() {
        if !finite(o.pos) || !finite(o.vel) {
            return bad(format!("objects[{i}]"), "a finite position and velocity", format!("{o:?}"));
        }
        if !(o.radius.is_finite() && o.radius >= 0.0) {
            return bad(format!("objects[{i}].radius"), "a finite radius >= 0 (m)", o.radius.to_string());
        }
    }
    for (g, members) in groups.iter().enumerate() {
        if let Some(&i) = members.iter().find(|&&i| i >= objects.len() || !objects[i].is_person()) {
            return bad(format!("groups[{g}]"), "indices of people in objects", i.to_string());
        }
    }
    params.zones.validate()?;
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(params.detection_range) {
        return bad("detection_range".into(), "a finite length > 0 (m)", params.detection_range.to_string());
    }
    if !positive(params.cone_horizon) {
        return bad("cone_horizon".into(), "a finite time > 0 (s)", params.cone_horizon.to_string());
    }
    if !positive(params.partial_goal_distance) {
        return bad(
            "partial_goal_distance".into(),
            "a finite length > 0 (m)",
            params.partial_goal_distance.to_string(),
        );
    }
    if let Some(s) = params.join_max_speed
        && !(s.is_finite() && s >= 0.0)
    {
        return bad("join_max_speed".into(), "a finite speed >= 0 (m/s)", s.to_string());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f64, y: f64) -> Vec2 {
        Vec2::new(x, y)
    }
    fn person(x: f64, y: f64) -> MobileObject {
        MobileObject { pos: v(x, y), vel: Vec2::zeros(), radius: 0.2, id: None }
    }
    fn robot(x: f64, y: f64, vx: f64, vy: f64, id: u64) -> MobileObject {
        MobileObject { pos: v(x, y), vel: v(vx, vy), radius: 0.25, id: Some(id) }
    }
    /// At the origin heading +x at 0.5 m/s along the A* path (0,0) -> (10,0).
    fn me() -> RobotState {
        RobotState { pos: Vec2::zeros(), pref_vel: v(0.5, 0.0), radius: 0.25 }
    }
    const PATH: [Vec2; 2] = [Vec2::new(0.0, 0.0), Vec2::new(10.0, 0.0)];

    fn decide(objects: &[MobileObject], groups: &[Vec<usize>]) -> Daza2021Decision {
        daza2021_decide(&me(), &PATH, objects, groups, &Daza2021Params::default()).expect("valid")
    }

    #[test]
    fn line_24_nothing_detected_follows_the_path() {
        let d = decide(&[], &[]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::FollowPath, 24, None));
        // Beyond the 4 m detection range counts as nothing.
        let d = decide(&[person(4.5, 0.0), robot(0.0, -5.0, 0.0, 0.0, 1)], &[]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::FollowPath, 24, None));
    }

    #[test]
    fn lines_5_to_8_only_robots_on_a_collision_course_run_orca() {
        // A robot 3 m ahead coming straight at us.
        let d = decide(&[robot(3.0, 0.0, -0.5, 0.0, 7)], &[]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::Orca, 8, Some(0)));
    }

    #[test]
    fn lines_9_10_only_robots_and_no_possible_collision_follow_the_path() {
        // A robot 3 m to the side moving away: outside the collision cone.
        let d = decide(&[robot(0.0, 3.0, 0.0, 0.5, 7)], &[]);
        assert_eq!((d.mode, d.line), (Daza2021Mode::FollowPath, 10));
    }

    #[test]
    fn lines_14_to_16_the_nearest_mobile_object_is_a_person_runs_social_momentum() {
        let d = decide(&[robot(3.0, 0.0, -0.5, 0.0, 7), person(2.0, 1.0)], &[]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::SocialMomentum, 16, Some(1)));
    }

    #[test]
    fn lines_17_to_19_a_group_with_the_nearest_object_a_robot_runs_social_momentum() {
        // The nearest object is a robot passing by; a conversation of two people is farther.
        let objects = [robot(1.0, 1.0, 0.0, 0.0, 7), person(3.0, -1.0), person(3.0, -2.2)];
        let d = decide(&objects, &[vec![1, 2]]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::SocialMomentum, 19, Some(0)));
        assert!(d.robots_in_groups.is_empty());
    }

    #[test]
    fn lines_20_21_people_detected_the_nearest_a_robot_and_no_group_follow_the_path() {
        let objects = [robot(1.0, 1.0, 0.0, 0.0, 7), person(3.0, -2.0)];
        let d = decide(&objects, &[]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::FollowPath, 21, Some(0)));
    }

    #[test]
    fn line_18_a_robot_standing_in_a_human_group_gets_a_zone_even_when_moving_by_default() {
        // Robot 7 stands 0.8 m from person 1 (inside the 1 m personal zone, intimate areas of
        // 0.5 m intersect): it takes part. Robot 8 is 1.2 m from everybody: it does not.
        let objects = [person(3.0, 0.0), robot(3.0, 0.8, 0.3, 0.0, 7), robot(3.0, -1.2, 0.0, 0.0, 8)];
        let d = decide(&objects, &[]);
        assert_eq!(d.robots_in_groups, vec![1]);
        // The paper's rule has no speed condition; ours is an option, off by default.
        let slow = Daza2021Params { join_max_speed: Some(0.05), ..Daza2021Params::default() };
        let d = daza2021_decide(&me(), &PATH, &objects, &[], &slow).expect("valid");
        assert!(d.robots_in_groups.is_empty());
        // A lone person with a robot taking part is a group (line 17) when the nearest object is
        // a robot: here robot 7 at 1 m is nearer than the person.
        let objects = [person(2.0, 1.6), robot(1.0, 0.0, 0.0, 0.0, 7), robot(2.0, 0.9, 0.0, 0.0, 8)];
        let d = decide(&objects, &[]);
        assert_eq!(d.robots_in_groups, vec![2]);
        assert_eq!((d.mode, d.line, d.nearest), (Daza2021Mode::SocialMomentum, 19, Some(1)));
    }

    #[test]
    fn the_partial_goal_lies_on_the_a_star_path_ahead_of_the_robot() {
        let path = [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 5.0)];
        let p = Daza2021Params::default();
        let at = |x: f64, y: f64| RobotState { pos: v(x, y), ..me() };
        let d = daza2021_decide(&at(0.0, 0.3), &path, &[], &[], &p).expect("valid");
        // Nearest path point (0, 0); 1.5 m along: 1 m to the corner, 0.5 m up.
        assert!((d.partial_goal - v(1.0, 0.5)).norm() < 1e-12, "{:?}", d.partial_goal);
        let d = daza2021_decide(&at(1.2, 4.0), &path, &[], &[], &p).expect("valid");
        assert!((d.partial_goal - v(1.0, 5.0)).norm() < 1e-12, "the path's end: {:?}", d.partial_goal);
        let d = daza2021_decide(&at(3.0, 3.0), &[v(2.0, 2.0)], &[], &[], &p).expect("valid");
        assert_eq!(d.partial_goal, v(2.0, 2.0));
    }

    #[test]
    fn bad_input_is_a_typed_error_naming_the_field() {
        let p = Daza2021Params::default();
        let field = |r: Result<Daza2021Decision>| match r {
            Err(CoreError::Input { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        assert_eq!(field(daza2021_decide(&me(), &[], &[], &[], &p)), "path");
        assert_eq!(field(daza2021_decide(&me(), &[v(f64::NAN, 0.0)], &[], &[], &p)), "path[0]");
        let nan_robot = RobotState { radius: f64::NAN, ..me() };
        assert_eq!(field(daza2021_decide(&nan_robot, &PATH, &[], &[], &p)), "robot.radius");
        let obj = [person(1.0, 0.0), robot(2.0, 0.0, 0.0, 0.0, 1)];
        assert_eq!(field(daza2021_decide(&me(), &PATH, &obj, &[vec![0, 1]], &p)), "groups[0]");
        assert_eq!(field(daza2021_decide(&me(), &PATH, &obj, &[vec![5]], &p)), "groups[0]");
        let bad = [MobileObject { radius: -1.0, ..obj[0] }];
        assert_eq!(field(daza2021_decide(&me(), &PATH, &bad, &[], &p)), "objects[0].radius");
        let bp = Daza2021Params { detection_range: 0.0, ..p };
        assert_eq!(field(daza2021_decide(&me(), &PATH, &[], &[], &bp)), "detection_range");
        let bp = Daza2021Params { join_max_speed: Some(f64::NAN), ..p };
        assert_eq!(field(daza2021_decide(&me(), &PATH, &[], &[], &bp)), "join_max_speed");
    }
}
