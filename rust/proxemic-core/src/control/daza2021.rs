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
use crate::control::orca::nonholonomic::TrackingBound;
use crate::control::social_momentum::{
    Agent, AgentShape, GaussianSpace, SocialMomentumParams, social_momentum_shaped,
};
use crate::control::{Limits, clamp_norm};
use crate::error::{CoreError, Result};
use crate::map::geometry::StaticGeometry;
use crate::math::Vec2;
use crate::perception::Individual;
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

/// How Social Momentum (lines 16 and 19) sees the people.
#[derive(Clone, Copy, Debug)]
pub enum PeopleSpaces<'a> {
    /// Daza 2021 (the `daza2021` planner): every person, and every robot taking part in a human
    /// group, is a disc that keeps the robot's centre out of their intimate zone; every group
    /// (with its robots) adds a disc covering its o-space.
    Intimate,
    /// Sousa 2022 §4.5 (the `sousa2022` planner): the perception's individuals (a person alone,
    /// or a group as one individual), each with its fully asymmetric Gaussian reshaped by the
    /// socialization features; the keep-out region is the Gaussian's **personal** level (zone
    /// distance below Hall's personal radius: Sousa runs Daza's method "for avoiding the personal
    /// space of persons" and its path "respects groups and individual space imposed by Gaussian
    /// functions"). Their `members` index the people of `objects`.
    Gaussians(&'a [Individual]),
}

/// Social Momentum's parameters in Algorithm 1: the project's defaults
/// ([`SocialMomentumParams::default`]) with **no comfort term** (`comfort_weight = 0`): Daza
/// 2021 only keeps the robot out of the intimate zone, Sousa 2022 out of the Gaussians' personal
/// level ([`PeopleSpaces`]), which the collision filter enforces. The other values (λ, action set, horizon, safety margin) are not given by either
/// paper; ours are documented on [`SocialMomentumParams`].
pub fn social_momentum_params() -> SocialMomentumParams {
    SocialMomentumParams { comfort_weight: 0.0, ..SocialMomentumParams::default() }
}

/// The agents (and their keep-out shapes) Social Momentum avoids at lines 16 and 19.
///
/// - `robot`: the deciding robot; `objects`, `groups`: as given to [`daza2021_decide`];
///   `decision`: its result this step (for the robots taking part in human groups);
/// - `spaces`: discs (Daza) or Gaussians (Sousa), see [`PeopleSpaces`].
///
/// Choices where the papers are silent:
/// - a person's disc keeps the robot's **centre** out of the intimate radius (Hall's radii are
///   centre to centre in proxemic), and never less than the body radius;
/// - a group's o-space (Daza's "O" space) is the disc centred on the members' mean position
///   (people and the robots taking part) through their mean distance to it: the robot's body
///   stays outside the circle the members stand on;
/// - momentum weights: 1 for every person (and for a group as one individual with Sousa's
///   Gaussians); the o-space disc, the bodies of the members of a group seen as one individual,
///   and robots outside human groups are obstacles only (weight 0): Social Momentum's momentum
///   term is about people, and no weighting is given by either paper;
/// - with Sousa's Gaussians a robot taking part in a group keeps Daza's disc (it carries no
///   socialization features);
/// - with Sousa's Gaussians the keep-out level is Hall's personal radius of `params.zones` as a
///   zone distance (Sousa 2022 §4.5, see [`PeopleSpaces::Gaussians`]).
pub fn daza2021_agents(
    robot: &RobotState,
    objects: &[MobileObject],
    groups: &[Vec<usize>],
    decision: &Daza2021Decision,
    spaces: PeopleSpaces<'_>,
    params: &Daza2021Params,
) -> (Vec<Agent>, Vec<AgentShape>) {
    let intimate = params.zones.intimate;
    let disc = |o: &MobileObject, weight: f64, person_like: bool| Agent {
        pos: o.pos,
        vel: o.vel,
        radius: if person_like { o.radius.max(intimate - robot.radius) } else { o.radius },
        weight,
        comfort: 0.0,
    };
    let mut agents = Vec::with_capacity(objects.len() + groups.len());
    let mut shapes = Vec::with_capacity(objects.len() + groups.len());
    // Robots: taking part in a human group they are people (line 18); otherwise obstacles.
    for (k, o) in objects.iter().enumerate() {
        if !o.is_person() {
            let joined = decision.robots_in_groups.contains(&k);
            agents.push(disc(o, if joined { 1.0 } else { 0.0 }, joined));
            shapes.push(AgentShape::Disc);
        }
    }
    match spaces {
        PeopleSpaces::Intimate => {
            for o in objects.iter().filter(|o| o.is_person()) {
                agents.push(disc(o, 1.0, true));
                shapes.push(AgentShape::Disc);
            }
            for g in with_singletons(objects, groups) {
                let mut pts: Vec<Vec2> = g.iter().map(|&i| objects[i].pos).collect();
                let vel = g.iter().fold(Vec2::zeros(), |a, &i| a + objects[i].vel) / g.len().max(1) as f64;
                pts.extend(
                    decision
                        .robots_in_groups
                        .iter()
                        .filter(|&&k| joins(objects, &g, k, params))
                        .map(|&k| objects[k].pos),
                );
                if pts.len() < 2 {
                    continue;
                }
                let centre = pts.iter().fold(Vec2::zeros(), |a, &q| a + q) / pts.len() as f64;
                let ospace = pts.iter().map(|q| (q - centre).norm()).sum::<f64>() / pts.len() as f64;
                agents.push(Agent { pos: centre, vel, radius: ospace, weight: 0.0, comfort: 0.0 });
                shapes.push(AgentShape::Disc);
            }
        }
        PeopleSpaces::Gaussians(individuals) => {
            for ind in individuals {
                let members: Vec<&MobileObject> =
                    ind.members.iter().filter_map(|&i| objects.get(i)).filter(|o| o.is_person()).collect();
                let Some(first) = members.first() else { continue };
                let vel = members.iter().fold(Vec2::zeros(), |a, o| a + o.vel) / members.len() as f64;
                // A person alone keeps its body disc; a group as one individual has none of its
                // own, its members' bodies are obstacles below.
                let radius = if members.len() == 1 { first.radius } else { 0.0 };
                let agent = Agent { pos: ind.centre, vel, radius, weight: 1.0, comfort: 0.0 };
                // Sousa 2022 §4.5: Daza's method is used "for avoiding the personal space of
                // persons", and the path "respects groups and individual space imposed by
                // Gaussian functions": the keep-out level is the Gaussian's personal contour
                // (zone distance = Hall's personal radius, 1 m with Daza's radii).
                match GaussianSpace::of_individual(ind, params.zones.personal) {
                    Ok(g) => {
                        agents.push(agent);
                        shapes.push(AgentShape::Gaussian(g));
                    }
                    // An individual whose Gaussian is invalid (it cannot be, from the
                    // perception) falls back to a disc at the personal radius.
                    Err(_) => {
                        agents.push(Agent {
                            radius: radius.max(params.zones.personal - robot.radius),
                            ..agent
                        });
                        shapes.push(AgentShape::Disc);
                    }
                }
                if members.len() > 1 {
                    for o in members {
                        agents.push(disc(o, 0.0, false));
                        shapes.push(AgentShape::Disc);
                    }
                }
            }
        }
    }
    (agents, shapes)
}

/// Lines 16 and 19: one step of Social Momentum toward a partial goal on `path` (the plain A*
/// path of line 1, as given to [`daza2021_decide`]) among [`daza2021_agents`], with
/// [`social_momentum_params`]. `vel` is the robot's executed velocity (m/s), `geometry` the
/// walls, `limits` and `dt` (s) bound the action set.
///
/// The partial goal: the paper sets "a point in the planned path" so that "the A* path will be
/// retaken as conditions and social restrictions allow it" (§4.3, lines 16 and 19). Ours is the
/// decision's partial goal ([`Daza2021Params::partial_goal_distance`] ahead) when the robot could
/// stand there, otherwise the first point on along the path, every 0.1 m, outside every agent's
/// keep-out region (a person's intimate disc, a group's o-space, with Sousa's Gaussians the
/// personal contour; the collision filter's bounds) and in the robot's sight: a goal inside a
/// region the filter forbids would have Social Momentum push the robot against the people
/// standing on the path, and one round a corner would have it cut the corner.
///
/// Returns the desired velocity, or `None` when every sample collides (the robot waits) or
/// stopping is the only safe choice. `unicycle` is `Some` for a differential-drive robot: Social
/// Momentum under its kinematic constraint (see [`social_momentum_shaped`]).
#[allow(clippy::too_many_arguments)]
pub fn daza2021_social_momentum(
    robot: &RobotState,
    path: &[Vec2],
    vel: Vec2,
    objects: &[MobileObject],
    groups: &[Vec<usize>],
    decision: &Daza2021Decision,
    spaces: PeopleSpaces<'_>,
    geometry: Option<&StaticGeometry>,
    limits: &Limits,
    dt: f64,
    params: &Daza2021Params,
    unicycle: Option<TrackingBound>,
) -> Option<Vec2> {
    let (agents, shapes) = daza2021_agents(robot, objects, groups, decision, spaces, params);
    let sm = social_momentum_params();
    let goal = if path.is_empty() {
        decision.partial_goal
    } else {
        clear_partial_goal(
            path,
            robot,
            params.partial_goal_distance,
            &agents,
            &shapes,
            sm.safety_margin,
            geometry,
        )
    };
    let v = social_momentum_shaped(
        robot.pos,
        vel,
        robot.radius,
        goal,
        &agents,
        &shapes,
        geometry,
        limits,
        dt,
        &sm,
        unicycle,
    )?;
    (v.norm() > 1e-6).then(|| clamp_norm(v, limits.max_speed))
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
    points_ahead(path, pos, distance, f64::INFINITY).next().unwrap_or(path[0])
}

/// The points of the polyline `path` from `distance` (m) beyond the point of the path nearest
/// `pos`, then every `step` (m) on along it, ending with its last point (a path of one point
/// gives that point).
fn points_ahead(path: &[Vec2], pos: Vec2, distance: f64, step: f64) -> impl Iterator<Item = Vec2> + '_ {
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
    let single = path.len() < 2;
    let mut seg = best_seg + 1;
    let mut from =
        if single { path[0] } else { path[best_seg] + (path[best_seg + 1] - path[best_seg]) * best_t };
    let mut left = distance;
    let mut done = false;
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        while seg < path.len() {
            let next = path[seg];
            let len = (next - from).norm();
            if len >= left {
                from += (next - from) * (left / len);
                left = step;
                return Some(from);
            }
            left -= len;
            from = next;
            seg += 1;
        }
        done = true;
        Some(path[path.len() - 1])
    })
}

/// How far apart (m) [`clear_partial_goal`] tries the path's points.
const CLEAR_GOAL_STEP: f64 = 0.1;

/// Lines 16 and 19's partial goal, moved on along the path past the keep-out regions of the
/// `agents` Social Momentum avoids (see [`daza2021_social_momentum`]): the first of the path's
/// points from `distance` (m) ahead of the point nearest the robot, then every
/// [`CLEAR_GOAL_STEP`], where the robot's centre would be outside every agent's keep-out region
/// (the collision filter's: a disc's `radius + r_i + margin`, a Gaussian's keep-out zone distance
/// plus `margin`) and that the robot sees (the straight segment to it crosses no wall of
/// `geometry`). The walk stops at the first point out of sight, so the goal never moves round a
/// corner: when no point before it is free, the first point (`distance` ahead) is the goal, as
/// when the path ends first.
fn clear_partial_goal(
    path: &[Vec2],
    robot: &RobotState,
    distance: f64,
    agents: &[Agent],
    shapes: &[AgentShape],
    margin: f64,
    geometry: Option<&StaticGeometry>,
) -> Vec2 {
    let blocked = |p: Vec2| {
        agents.iter().zip(shapes).any(|(a, shape)| shape.holds(p - a.pos, robot.radius, a.radius, margin))
    };
    let seen = |p: Vec2| geometry.is_none_or(|g| !g.segment_hits(robot.pos, p));
    let first = point_ahead(path, robot.pos, distance);
    points_ahead(path, robot.pos, distance, CLEAR_GOAL_STEP)
        .take_while(|&p| seen(p))
        .find(|&p| !blocked(p))
        .unwrap_or(first)
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
    fn the_social_momentum_goal_moves_on_past_a_keep_out_region_on_the_path() {
        let p = Daza2021Params::default();
        let margin = social_momentum_params().safety_margin;
        let goal = |objects: &[MobileObject], groups: &[Vec<usize>]| {
            let d = decide(objects, groups);
            let (agents, shapes) = daza2021_agents(&me(), objects, groups, &d, PeopleSpaces::Intimate, &p);
            clear_partial_goal(&PATH, &me(), p.partial_goal_distance, &agents, &shapes, margin, None)
        };
        // Nobody near the point 1.5 m ahead: the decision's partial goal.
        assert_eq!(goal(&[person(1.5, 3.0)], &[]), v(1.5, 0.0));
        // A person standing on the path at 1.65 m: her keep-out disc (0.25 + 0.25 + 0.1 m) holds
        // the points up to 2.25 m; the goal is the first point every 0.1 m outside it.
        let g = goal(&[person(1.65, 0.0)], &[]);
        assert!((g - v(2.3, 0.0)).norm() < 1e-9, "{g:?}");
        // A conversation across the path: the goal lies beyond its o-space disc (centre 2.05 m,
        // radius 0.55 m, bound 0.25 + 0.55 + 0.1 m: up to 2.95 m).
        let g = goal(&[person(2.05, 0.55), person(2.05, -0.55)], &[vec![0, 1]]);
        assert!((g - v(3.0, 0.0)).norm() < 1e-9, "{g:?}");
        // Every point of the path blocked: the decision's partial goal, 1.5 m ahead.
        let short = [v(0.0, 0.0), v(2.0, 0.0)];
        let d = decide(&[person(1.9, 0.0)], &[]);
        let (agents, shapes) =
            daza2021_agents(&me(), &[person(1.9, 0.0)], &[], &d, PeopleSpaces::Intimate, &p);
        assert_eq!(clear_partial_goal(&short, &me(), 1.5, &agents, &shapes, margin, None), v(1.5, 0.0));
        // The steps continue across the path's corners.
        let bent = [v(0.0, 0.0), v(1.0, 0.0), v(1.0, 5.0)];
        let d = decide(&[person(1.0, 0.65)], &[]);
        let (agents, shapes) =
            daza2021_agents(&me(), &[person(1.0, 0.65)], &[], &d, PeopleSpaces::Intimate, &p);
        let g = clear_partial_goal(&bent, &me(), 1.5, &agents, &shapes, margin, None);
        assert!((g - v(1.0, 1.3)).norm() < 1e-9, "{g:?}");
        // Never round a corner: behind a wall the walk stops, and the goal stays 1.5 m ahead.
        let corner = [v(0.0, 0.0), v(2.0, 0.0), v(2.0, 3.0)];
        let someone = [person(1.65, 0.0)];
        let d = decide(&someone, &[]);
        let (agents, shapes) = daza2021_agents(&me(), &someone, &[], &d, PeopleSpaces::Intimate, &p);
        let open = clear_partial_goal(&corner, &me(), 1.5, &agents, &shapes, margin, None);
        assert!(open.x == 2.0 && open.y > 0.0, "round the corner in the open: {open:?}");
        let bounds = crate::map::geometry::Bounds { min: v(-1.0, -1.0), max: v(4.0, 4.0) };
        let block = vec![v(0.3, 0.2), v(1.7, 0.2), v(1.7, 1.5), v(0.3, 1.5)];
        let walls = StaticGeometry::new(vec![block], bounds).expect("valid geometry");
        let g = clear_partial_goal(&corner, &me(), 1.5, &agents, &shapes, margin, Some(&walls));
        assert_eq!(g, v(1.5, 0.0), "the corner's far side is out of sight");
    }

    #[test]
    fn daza_agents_are_intimate_discs_with_a_group_o_space_and_robots_as_obstacles() {
        // Two people talking 1.2 m apart, a robot standing with them, a robot passing far away.
        let objects = [
            person(3.0, 0.6),
            person(3.0, -0.6),
            robot(3.8, 0.0, 0.0, 0.0, 7),
            robot(0.0, 3.5, 0.0, -0.5, 8),
        ];
        let groups = [vec![0, 1]];
        let p = Daza2021Params::default();
        let d = daza2021_decide(&me(), &PATH, &objects, &groups, &p).expect("valid");
        assert_eq!(d.robots_in_groups, vec![2]);
        let (agents, shapes) = daza2021_agents(&me(), &objects, &groups, &d, PeopleSpaces::Intimate, &p);
        assert!(shapes.iter().all(|s| *s == AgentShape::Disc));
        assert_eq!(agents.len(), 5);
        // Robots first: the one in the group is a person (intimate keep-out, weight 1); the other
        // an obstacle of its body radius.
        assert_eq!((agents[0].radius, agents[0].weight), (0.25, 1.0));
        assert_eq!((agents[1].radius, agents[1].weight), (0.25, 0.0));
        // People: the robot's centre stays 0.5 m away (0.25 m keep-out + 0.25 m robot radius).
        assert!(agents[2..4].iter().all(|a| a.radius == 0.25 && a.weight == 1.0 && a.comfort == 0.0));
        // The o-space of the two people and the robot: centred on their mean, through their mean
        // distance to it; an obstacle only.
        let o = &agents[4];
        let centre = v(9.8 / 3.0, 0.0);
        assert!((o.pos - centre).norm() < 1e-12);
        let mean = ((v(3.0, 0.6) - centre).norm() * 2.0 + (v(3.8, 0.0) - centre).norm()) / 3.0;
        assert!((o.radius - mean).abs() < 1e-12 && o.weight == 0.0);
    }

    #[test]
    fn social_momentum_keeps_out_of_the_o_space_and_has_no_comfort_term() {
        assert_eq!(social_momentum_params().comfort_weight, 0.0);
        // A conversation across the path ahead: the robot never enters its o-space.
        let objects = [person(3.0, 0.55), person(3.0, -0.55)];
        let groups = [vec![0, 1]];
        let p = Daza2021Params::default();
        let (mut pos, mut vel) = (Vec2::zeros(), v(0.3, 0.0));
        let mut closest = f64::INFINITY;
        for _ in 0..300 {
            let r = RobotState { pos, pref_vel: v(0.55, 0.0), radius: 0.25 };
            let d = daza2021_decide(&r, &PATH, &objects, &groups, &p).expect("valid");
            let out = if d.mode == Daza2021Mode::SocialMomentum {
                daza2021_social_momentum(
                    &r,
                    &PATH,
                    vel,
                    &objects,
                    &groups,
                    &d,
                    PeopleSpaces::Intimate,
                    None,
                    &Limits::PEPPER,
                    0.1,
                    &p,
                    None,
                )
                .unwrap_or_else(Vec2::zeros)
            } else {
                clamp_norm(d.partial_goal - pos, 0.55)
            };
            vel = out;
            pos += vel * 0.1;
            closest = closest.min((pos - v(3.0, 0.0)).norm());
        }
        // o-space radius 0.55 m, plus the robot's 0.25 m.
        assert!(closest > 0.55 + 0.25, "closest {closest}");
        assert!(pos.x > 6.0, "it passed: {pos:?}");
    }

    #[test]
    fn sousa_agents_are_the_individuals_gaussians_a_group_as_one() {
        use crate::groups::PersonState;
        use crate::perception::{ProxemicsConfig, perceive};
        use std::f64::consts::PI;
        let objects = [person(3.0, 0.6), person(3.0, -0.6), person(6.0, 3.0)];
        let states = [
            PersonState::standing(objects[0].pos, -PI / 2.0),
            PersonState::standing(objects[1].pos, PI / 2.0),
            PersonState::standing(objects[2].pos, 0.0),
        ];
        let per =
            perceive(&ProxemicsConfig::default(), &states, &[vec![], vec![], vec![]], &[]).expect("valid");
        let groups: Vec<Vec<usize>> = per.groups.multi().cloned().collect();
        assert_eq!(groups, vec![vec![0, 1]]);
        let p = Daza2021Params::default();
        let d = daza2021_decide(&me(), &PATH, &objects, &groups, &p).expect("valid");
        let (agents, shapes) =
            daza2021_agents(&me(), &objects, &groups, &d, PeopleSpaces::Gaussians(&per.individuals), &p);
        // The group: one Gaussian individual at its centre with no body, then its members' bodies
        // as obstacles; the person alone: a Gaussian with its body.
        assert_eq!(agents.len(), 4);
        // Sousa 2022 §4.5: the keep-out level is the Gaussian's personal contour (Daza's 1 m).
        assert!(matches!(shapes[0], AgentShape::Gaussian(g) if g.keep_out() == 1.0));
        assert!(
            (agents[0].pos - v(3.0, 0.0)).norm() < 1e-9 && agents[0].radius == 0.0 && agents[0].weight == 1.0
        );
        assert!(shapes[1..3].iter().all(|s| *s == AgentShape::Disc));
        assert!(agents[1..3].iter().all(|a| a.weight == 0.0 && a.radius == 0.2));
        assert!(matches!(shapes[3], AgentShape::Gaussian(_)) && agents[3].radius == 0.2);
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
