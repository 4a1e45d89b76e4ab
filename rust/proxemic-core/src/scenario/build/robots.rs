//! Robots (`[[robot]]`): limits, goals or approach tasks, tours; start overlaps.

use crate::control::progress::ProgressParams;
use crate::error::Result;
use crate::scenario::check::{Checker, check_unique, err};
use crate::scenario::model::{Approach, Behaviour, EbandGains, Person, Proxemics, Robot};
use crate::scenario::raw::{RawApproach, RawProgress, RawRobot};

/// Checks the robots (at least one, unique names), their goals or approach tasks (to `persons`
/// under the social model `prox`) inside the bounds `b`.
pub(super) fn build_robots(
    ck: &Checker<'_>,
    raw: &[RawRobot],
    persons: &[Person],
    proxemics: &Proxemics,
    b: [f64; 4],
) -> Result<Vec<Robot>> {
    let file = ck.file;
    if raw.is_empty() {
        return Err(err(file, "robot", "at least one [[robot]] table", "none"));
    }
    let mut robots = Vec::with_capacity(raw.len());
    for (i, r) in raw.iter().enumerate() {
        robots.push(build_robot(ck, i, r, persons, proxemics, b)?);
    }
    check_unique(file, "robot", robots.iter().map(|r| r.name.as_str()))?;
    Ok(robots)
}

/// Robot `i`: its limits, goal or approach task, waypoints and dwell, elastic-band gains.
fn build_robot(
    ck: &Checker<'_>,
    i: usize,
    r: &RawRobot,
    persons: &[Person],
    proxemics: &Proxemics,
    b: [f64; 4],
) -> Result<Robot> {
    let file = ck.file;
    let f = format!("robot[{i}]");
    ck.finite(&format!("{f}.start"), &r.start)?;
    ck.inside(&format!("{f}.start"), [r.start[0], r.start[1]], b)?;
    ck.range(&format!("{f}.radius"), r.radius, 0.0, 2.0, true)?;
    ck.range(&format!("{f}.max_speed"), r.max_speed, 0.0, 5.0, true)?;
    ck.range(&format!("{f}.max_angular_speed"), r.max_angular_speed, 0.0, 10.0, true)?;
    ck.range(&format!("{f}.max_accel"), r.max_accel, 0.0, 20.0, true)?;
    ck.range(&format!("{f}.max_angular_accel"), r.max_angular_accel, 0.0, 100.0, true)?;
    ck.range(&format!("{f}.inflation_margin"), r.inflation_margin, 0.0, 1.0, false)?;
    let (goal, approach) = match (&r.goal, &r.approach) {
        (Some(g), None) => {
            ck.inside(&format!("{f}.goal"), *g, b)?;
            (*g, None)
        }
        (None, Some(a)) => {
            let (g, ap) = build_approach(ck, &f, a, persons, proxemics, r.radius)?;
            ck.inside(&format!("{f}.approach"), g, b)?;
            (g, Some(ap))
        }
        (Some(_), Some(_)) => {
            return Err(err(file, format!("{f}.approach"), "either goal or approach, not both", "both"));
        }
        (None, None) => {
            return Err(err(
                file,
                format!("{f}.goal"),
                "goal = [x, y] (or an approach = { person = ... } task)",
                "nothing",
            ));
        }
    };
    for (k, w) in r.waypoints.iter().enumerate() {
        ck.inside(&format!("{f}.waypoints[{k}]"), *w, b)?;
    }
    ck.range(&format!("{f}.dwell"), r.dwell, 0.0, 3600.0, false)?;
    if r.dwell > 0.0 && r.waypoints.is_empty() {
        return Err(err(
            file,
            format!("{f}.dwell"),
            "a dwell only with waypoints = [[x, y], ...] to stop at",
            format!("dwell = {} without waypoints", r.dwell),
        ));
    }
    let progress = build_progress(ck, &f, &r.progress)?;
    Ok(Robot {
        name: r.name.clone().unwrap_or_else(|| format!("robot_{i}")),
        start: r.start,
        goal,
        approach,
        planner: r.planner,
        radius: r.radius,
        max_speed: r.max_speed,
        max_angular_speed: r.max_angular_speed,
        max_accel: r.max_accel,
        max_angular_accel: r.max_angular_accel,
        drive: r.drive,
        inflation_margin: r.inflation_margin,
        eband: EbandGains::default().merged(
            file,
            &format!("{f}.eband"),
            [r.eband.contraction_gain, r.eband.repulsion_gain, r.eband.social_gain],
        )?,
        waypoints: r.waypoints.clone(),
        dwell: r.dwell,
        progress,
    })
}

/// Robot field `f`'s progress monitor: the defaults with the file's values, checked.
fn build_progress(ck: &Checker<'_>, f: &str, raw: &RawProgress) -> Result<ProgressParams> {
    let mut p = ProgressParams::default();
    if let Some(e) = raw.enabled {
        p.enabled = e;
    }
    if let Some(d) = raw.distance {
        ck.range(&format!("{f}.progress.distance"), d, 0.0, ProgressParams::MAX_DISTANCE, true)?;
        p.distance = d;
    }
    if let Some(w) = raw.window {
        ck.range(&format!("{f}.progress.window"), w, 0.0, ProgressParams::MAX_WINDOW, true)?;
        p.window = w;
    }
    Ok(p)
}

/// Robots must not start overlapping: every pair of start discs at least touching-free.
pub(super) fn check_robot_starts(file: &str, robots: &[Robot]) -> Result<()> {
    for (j, b) in robots.iter().enumerate() {
        for (i, a) in robots[..j].iter().enumerate() {
            let d = (a.start[0] - b.start[0]).hypot(a.start[1] - b.start[1]);
            let need = a.radius + b.radius;
            if d < need {
                return Err(err(
                    file,
                    format!("robot[{j}].start"),
                    format!(
                        "a start at least {need:.2} m (the sum of the radii) from robot[{i}]'s start {:?}",
                        [a.start[0], a.start[1]]
                    ),
                    format!("{:?}, {d:.2} m away (overlapping)", [b.start[0], b.start[1]]),
                ));
            }
        }
    }
    Ok(())
}

/// Where the robots start, against their goals, the people standing still and the start jitter:
/// a goal (without waypoints) at least `success_radius` from the start (else the episode is won
/// before it begins); no standing person's body over a robot's start disc; the jitter square
/// (`start ± jitter`) inside `scene.bounds`; and two robots' starts apart by their radii plus the
/// jitter square's diagonal, so no draw can make them overlap.
pub(super) fn check_start_clearances(
    file: &str,
    robots: &[Robot],
    persons: &[Person],
    jitter: f64,
    success_radius: f64,
    bounds: [f64; 4],
) -> Result<()> {
    for (i, r) in robots.iter().enumerate() {
        let (sx, sy) = (r.start[0], r.start[1]);
        let d = (r.goal[0] - sx).hypot(r.goal[1] - sy);
        if r.waypoints.is_empty() && r.approach.is_none() && d < success_radius {
            return Err(err(
                file,
                format!("robot[{i}].goal"),
                format!(
                    "a goal at least episode.success_radius ({success_radius} m) from the start {:?}",
                    [sx, sy]
                ),
                format!("{:?}, {d:.2} m away", r.goal),
            ));
        }
        if sx - jitter < bounds[0]
            || sx + jitter > bounds[2]
            || sy - jitter < bounds[1]
            || sy + jitter > bounds[3]
        {
            return Err(err(
                file,
                "episode.randomize.robot_start_jitter",
                format!(
                    "a jitter that keeps robot[{i}]'s start {:?} inside scene.bounds {bounds:?}",
                    [sx, sy]
                ),
                format!("{jitter} m"),
            ));
        }
        for (k, p) in persons.iter().enumerate() {
            let gap = (p.pose[0] - sx).hypot(p.pose[1] - sy) - p.radius - r.radius;
            if p.behaviour == Behaviour::Standing && gap < 0.0 {
                return Err(err(
                    file,
                    format!("person[{k}].pose"),
                    format!("a place clear of robot[{i}]'s start {:?} (radius {} m)", [sx, sy], r.radius),
                    format!("{:?}, overlapping it by {:.2} m", [p.pose[0], p.pose[1]], -gap),
                ));
            }
        }
        for (j, q) in robots[..i].iter().enumerate() {
            let d = (q.start[0] - sx).hypot(q.start[1] - sy);
            let need = q.radius + r.radius + 2.0 * std::f64::consts::SQRT_2 * jitter;
            if jitter > 0.0 && d < need {
                return Err(err(
                    file,
                    "episode.randomize.robot_start_jitter",
                    format!(
                        "a jitter under which robot[{j}] and robot[{i}] cannot overlap (starts {d:.2} m apart need \
                         {:.2} m or less)",
                        ((d - q.radius - r.radius) / (2.0 * std::f64::consts::SQRT_2)).max(0.0)
                    ),
                    format!("{jitter} m"),
                ));
            }
        }
    }
    Ok(())
}

/// Standing people may not overlap each other (two people at the same place).
pub(super) fn check_people_apart(file: &str, persons: &[Person]) -> Result<()> {
    let standing: Vec<(usize, &Person)> =
        persons.iter().enumerate().filter(|(_, p)| p.behaviour == Behaviour::Standing).collect();
    for (n, &(j, b)) in standing.iter().enumerate() {
        for &(i, a) in &standing[..n] {
            let d = (a.pose[0] - b.pose[0]).hypot(a.pose[1] - b.pose[1]);
            if d < a.radius + b.radius {
                return Err(err(
                    file,
                    format!("person[{j}].pose"),
                    format!("a place clear of person[{i}] at {:?}", [a.pose[0], a.pose[1]]),
                    format!("{:?}, {d:.2} m away (overlapping)", [b.pose[0], b.pose[1]]),
                ));
            }
        }
    }
    Ok(())
}

/// The goal of an approach task: the robot's centre one body radius beyond the edge of the
/// person's (feature-adapted) personal space on the requested side, facing the person. `auto`
/// picks, among front, left and right, the side where that edge is nearest (the side the
/// person's features make most welcoming; never the back).
fn build_approach(
    ck: &Checker<'_>,
    f: &str,
    a: &RawApproach,
    persons: &[Person],
    prox: &Proxemics,
    robot_radius: f64,
) -> Result<([f64; 2], Approach)> {
    use crate::proxemics::PersonalSpace;
    let file = ck.file;
    let members = approach_members(ck, f, a, persons)?;
    let (centre, heading, sides) = approached_space(&members, persons, prox)?;
    let [front, rear, right, left] = prox.sigmas;
    // The personal zone's edge in value terms (see crate::social_cost_map::SpaceFunction).
    let zone_scale = match prox.space.as_str() {
        "calderita" => right,
        "daza2021" => front,
        _ => (front * rear * right * left).powf(0.25),
    };
    let default_level = (-(prox.zones[1] * prox.zones[1]) / (2.0 * zone_scale * zone_scale)).exp();
    let level = a.level.unwrap_or(default_level);
    ck.range(&format!("{f}.approach.level"), level, 0.0, 1.0, true)?;
    let space = PersonalSpace::Asymmetric(sides);
    let extent = |bearing: f64| space.extent(bearing, level).unwrap_or(f64::INFINITY);
    let half_pi = std::f64::consts::FRAC_PI_2;
    let (side, bearing) = match a.side.as_str() {
        "front" => ("front", 0.0),
        "left" => ("left", half_pi),
        "right" => ("right", -half_pi),
        "auto" => [("front", 0.0), ("left", half_pi), ("right", -half_pi)]
            .into_iter()
            .min_by(|x, y| extent(x.1).total_cmp(&extent(y.1)))
            .unwrap_or(("front", 0.0)),
        other => {
            return Err(err(
                file,
                format!("{f}.approach.side"),
                "\"front\", \"left\", \"right\" or \"auto\"",
                format!("{other:?}"),
            ));
        }
    };
    let d = extent(bearing) + robot_radius;
    let dir = heading + bearing;
    let goal = [centre[0] + d * dir.cos(), centre[1] + d * dir.sin()];
    Ok((goal, Approach { people: members, side: side.to_string(), level, face: centre }))
}

/// The people an approach task targets: one named person, or the members of a group; all of
/// them standing.
fn approach_members(ck: &Checker<'_>, f: &str, a: &RawApproach, persons: &[Person]) -> Result<Vec<usize>> {
    let file = ck.file;
    let members: Vec<usize> = match (&a.person, a.group) {
        (Some(name), None) => {
            let k = persons.iter().position(|p| &p.name == name).ok_or_else(|| {
                err(file, format!("{f}.approach.person"), "the name of a [[person]]", format!("{name:?}"))
            })?;
            vec![k]
        }
        (None, Some(g)) => {
            let m: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].group == Some(g)).collect();
            if m.len() < 2 {
                return Err(err(
                    file,
                    format!("{f}.approach.group"),
                    "the id of a group with at least 2 people",
                    format!("group {g} with {} member(s)", m.len()),
                ));
            }
            m
        }
        _ => {
            return Err(err(
                file,
                format!("{f}.approach"),
                "exactly one of person = \"name\" or group = id",
                "neither or both",
            ));
        }
    };
    for &k in &members {
        if persons[k].behaviour != Behaviour::Standing {
            let field = if a.group.is_some() { "group" } else { "person" };
            return Err(err(
                file,
                format!("{f}.approach.{field}"),
                "standing people (approach targets do not move)",
                format!("{:?}, a {:?}", persons[k].name, persons[k].behaviour),
            ));
        }
    }
    Ok(members)
}

/// The approached personal space: its centre, heading and per-side sigmas after the features'
/// adaptation. One person, or the group as one individual.
fn approached_space(
    members: &[usize],
    persons: &[Person],
    prox: &Proxemics,
) -> Result<([f64; 2], f64, crate::proxemics::Asymmetric)> {
    use crate::proxemics::{Asymmetric, SideInfluences, adapt};
    let [front, rear, right, left] = prox.sigmas;
    let base = Asymmetric { front, rear, right, left };
    let [fi, ri, rti, li] = prox.influence.clone();
    let influence = SideInfluences { front: fi, rear: ri, right: rti, left: li };
    // One person, or the group as one individual (Sousa 2022 §3.3.4): its centre, orientation and
    // extents grow the base function; its features are the members' mean.
    let (centre, heading, grown, fv) = if members.len() == 1 {
        let p = &persons[members[0]];
        ([p.pose[0], p.pose[1]], p.pose[2], base, p.features.clone())
    } else {
        use crate::groups::{FeatureAggregate, PersonState, group_as_individual};
        use crate::math::Vec2;
        let states: Vec<PersonState> = members
            .iter()
            .map(|&k| {
                PersonState::standing(Vec2::new(persons[k].pose[0], persons[k].pose[1]), persons[k].pose[2])
            })
            .collect();
        let gi = group_as_individual(&states, &vec![1.0; states.len()], FeatureAggregate::Mean)?;
        let nf = prox.features.len();
        let fv: Vec<f64> = (0..nf)
            .map(|j| members.iter().map(|&k| persons[k].features[j]).sum::<f64>() / members.len() as f64)
            .collect();
        let grown = Asymmetric {
            front: front + gi.front,
            rear: rear + gi.rear,
            right: right + gi.right,
            left: left + gi.left,
        };
        ([gi.centre.x, gi.centre.y], gi.heading, grown, fv)
    };
    let sides = if prox.features.is_empty() { grown } else { adapt(grown, &fv, &influence)? };
    Ok((centre, heading, sides))
}
