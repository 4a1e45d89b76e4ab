//! People (`[[person]]`): the checks every person shares, one builder per behaviour, and the
//! links between people (followers and their guides, conversations, groups) and to robots.

use crate::error::Result;
use crate::scenario::check::{Checker, check_unique, err, parse_time_of_day};
use crate::scenario::model::{
    Behaviour, Object, ObjectKind, Person, Reaction, Robot, SEAT_SPACING, SPEED_PRESETS,
};
use crate::scenario::raw::{RawGroup, RawPerson, d_person_speed};

/// Which per-behaviour fields a person may carry; any other one set is an error.
fn behaviour_fields(b: Behaviour) -> &'static [&'static str] {
    match b {
        Behaviour::Walker => &["route", "dwell", "stops"],
        Behaviour::Standing => &["pose"],
        Behaviour::Visitor => &["exhibits", "dwell"],
        Behaviour::Conversation => &["home", "spot", "start", "end"],
        Behaviour::Guide => &["route", "dwell", "stops"],
        Behaviour::Follower => &["guide", "gather_radius"],
        Behaviour::Seated => &["seat", "place"],
        Behaviour::Resident | Behaviour::Staff => &["home", "attends", "lead_minutes"],
        Behaviour::Replay => &[],
    }
}

/// A speed in m/s or a preset name.
fn parse_speed(ck: &Checker<'_>, field: &str, v: Option<&toml::Value>) -> Result<f64> {
    let names: Vec<&str> = SPEED_PRESETS.iter().map(|(n, _)| *n).collect();
    let expected = format!("a number in (0, 2.5] (m/s) or one of the presets {names:?}");
    let speed = match v {
        None => d_person_speed(),
        Some(toml::Value::Float(x)) => *x,
        Some(toml::Value::Integer(x)) => *x as f64,
        Some(toml::Value::String(name)) => SPEED_PRESETS
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, s)| *s)
            .ok_or_else(|| err(ck.file, field, expected.clone(), format!("{name:?}")))?,
        Some(other) => return Err(err(ck.file, field, expected, other.to_string())),
    };
    ck.range(field, speed, 0.0, 2.5, true)?;
    Ok(speed)
}

/// A time as seconds into the episode (a number) or a time of day ("HH:MM"), to seconds after
/// the episode start.
fn parse_episode_time(ck: &Checker<'_>, field: &str, v: &toml::Value, start_time: f64) -> Result<f64> {
    let expected = "seconds into the episode (a number) or a time of day \"HH:MM\"";
    match v {
        toml::Value::Float(x) if x.is_finite() => Ok(*x),
        toml::Value::Integer(x) => Ok(*x as f64),
        toml::Value::String(s) => parse_time_of_day(s)
            .map(|t| t - start_time)
            .ok_or_else(|| err(ck.file, field, expected, format!("{s:?}"))),
        other => Err(err(ck.file, field, expected, other.to_string())),
    }
}

/// An object named (string) or indexed (integer) by `v`.
fn object_ref(ck: &Checker<'_>, field: &str, v: &toml::Value, objects: &[Object]) -> Result<usize> {
    let expected = format!("the name or index of an [[object]] ({} defined)", objects.len());
    match v {
        toml::Value::String(name) => objects
            .iter()
            .position(|o| &o.name == name)
            .ok_or_else(|| err(ck.file, field, expected, format!("{name:?}"))),
        toml::Value::Integer(k) if *k >= 0 && (*k as usize) < objects.len() => Ok(*k as usize),
        other => Err(err(ck.file, field, expected, other.to_string())),
    }
}

/// Checks the people, each by its behaviour, their unique names and the links between them.
pub(super) fn build_people(
    ck: &Checker<'_>,
    raw: &[RawPerson],
    objects: &[Object],
    start_time: f64,
    b: [f64; 4],
) -> Result<Vec<Person>> {
    let mut persons = Vec::with_capacity(raw.len());
    for (i, p) in raw.iter().enumerate() {
        persons.push(build_person(ck, i, p, objects, start_time, b)?);
    }
    check_unique(ck.file, "person", persons.iter().map(|p| p.name.as_str()))?;
    link_people(ck, raw, &mut persons)?;
    Ok(persons)
}

/// One raw person with what its behaviour's builder checks it against.
struct PersonInput<'a> {
    ck: &'a Checker<'a>,
    /// The field prefix, `person[i]`.
    f: String,
    p: &'a RawPerson,
    objects: &'a [Object],
    /// The scene bounds.
    b: [f64; 4],
}

impl PersonInput<'_> {
    /// A point the behaviour requires (`home`, `spot`), inside the bounds.
    fn need(&self, field: &str, v: Option<[f64; 2]>) -> Result<[f64; 2]> {
        let (f, p, file) = (self.f.as_str(), self.p, self.ck.file);
        let v = v.ok_or_else(|| {
            err(file, format!("{f}.{field}"), format!("{field} = [x, y] for a {:?}", p.behaviour), "nothing")
        })?;
        self.ck.inside(&format!("{f}.{field}"), v, self.b)?;
        Ok(v)
    }
}

/// Checks the settings every person has, then builds the person by its behaviour.
fn build_person(
    ck: &Checker<'_>,
    i: usize,
    p: &RawPerson,
    objects: &[Object],
    start_time: f64,
    b: [f64; 4],
) -> Result<Person> {
    let f = format!("person[{i}]");
    let name = p.name.clone().unwrap_or_else(|| format!("person_{i}"));
    ck.range(&format!("{f}.radius"), p.radius, 0.0, 0.5, true)?;
    ck.range(&format!("{f}.height"), p.height, 0.3, 2.5, false)?;
    let speed = parse_speed(ck, &format!("{f}.speed"), p.speed.as_ref())?;
    ck.range(&format!("{f}.dwell"), p.dwell, 0.0, 3600.0, false)?;
    ck.range(&format!("{f}.lead_minutes"), p.lead_minutes, 0.0, 120.0, false)?;
    ck.range(&format!("{f}.gather_radius"), p.gather_radius, 0.5, 5.0, false)?;
    check_behaviour_fields(ck, &f, p)?;
    for (k, w) in p.route.iter().enumerate() {
        ck.inside(&format!("{f}.route[{k}]"), *w, b)?;
    }
    let mut person = Person {
        name,
        behaviour: p.behaviour,
        speed,
        dwell: p.dwell,
        radius: p.radius,
        height: p.height,
        group: p.group,
        gather_radius: p.gather_radius,
        lead: p.lead_minutes * 60.0,
        ..Person::default()
    };
    let x = PersonInput { ck, f, p, objects, b };
    let pose = match p.behaviour {
        Behaviour::Walker | Behaviour::Guide => route_pose(&x, &mut person)?,
        Behaviour::Standing => standing_pose(&x)?,
        Behaviour::Visitor => visitor_pose(&x, &mut person)?,
        Behaviour::Conversation => conversation_pose(&x, start_time, &mut person)?,
        Behaviour::Follower => follower_pose(&x)?,
        Behaviour::Seated => seated_pose(&x)?,
        Behaviour::Resident | Behaviour::Staff => attendee_pose(&x, &mut person)?,
        Behaviour::Replay => return Err(replay_in_person(ck, &x.f)),
    };
    person.pose = pose;
    person.route.clone_from(&p.route);
    Ok(person)
}

/// Fields that do not belong to the behaviour are errors (a typo would otherwise be ignored).
fn check_behaviour_fields(ck: &Checker<'_>, f: &str, p: &RawPerson) -> Result<()> {
    let set: [(&str, bool); 12] = [
        ("route", !p.route.is_empty()),
        ("pose", p.pose.is_some()),
        ("exhibits", !p.exhibits.is_empty()),
        ("home", p.home.is_some()),
        ("spot", p.spot.is_some()),
        ("start", p.start.is_some()),
        ("end", p.end.is_some()),
        ("seat", p.seat.is_some()),
        ("guide", p.guide.is_some()),
        ("stops", p.stops.is_some()),
        ("attends", !p.attends.is_empty()),
        ("place", p.place != 0),
    ];
    let allowed = behaviour_fields(p.behaviour);
    if let Some((field, _)) = set.iter().find(|(n, on)| *on && !allowed.contains(n)) {
        let what = match *field {
            "pose" if p.behaviour == Behaviour::Walker => {
                "no pose for a walker (it starts on its route)".into()
            }
            "route" if p.behaviour == Behaviour::Standing => "no route for a standing person".into(),
            _ => format!("no {field} for a {:?} (its fields: {allowed:?})", p.behaviour),
        };
        return Err(err(ck.file, format!("{f}.{field}"), what, "a value"));
    }
    Ok(())
}

/// Walker and guide: a closed route of distinct waypoints and its stops; the pose is the first
/// waypoint, facing the second.
fn route_pose(x: &PersonInput<'_>, person: &mut Person) -> Result<[f64; 3]> {
    let (f, p, file) = (x.f.as_str(), x.p, x.ck.file);
    if p.route.len() < 2 {
        return Err(err(
            file,
            format!("{f}.route"),
            format!("at least 2 waypoints for a {:?}", p.behaviour),
            format!("{} waypoint(s)", p.route.len()),
        ));
    }
    for k in 0..p.route.len() {
        let a = p.route[k];
        let c = p.route[(k + 1) % p.route.len()];
        if (a[0] - c[0]).hypot(a[1] - c[1]) < 1e-6 {
            return Err(err(
                file,
                format!("{f}.route[{}]", (k + 1) % p.route.len()),
                "a waypoint different from the previous one",
                format!("{c:?}"),
            ));
        }
    }
    if p.behaviour == Behaviour::Guide || p.stops.is_some() {
        let n = p.route.len();
        let stops = p.stops.clone().unwrap_or_else(|| (0..n).collect());
        person.stops = vec![false; n];
        for (k, &s) in stops.iter().enumerate() {
            if s >= n {
                return Err(err(
                    file,
                    format!("{f}.stops[{k}]"),
                    format!("a waypoint index below {n} (the route's length)"),
                    s.to_string(),
                ));
            }
            person.stops[s] = true;
        }
        if p.behaviour == Behaviour::Guide && !person.stops[0] {
            return Err(err(
                file,
                format!("{f}.stops"),
                "a list that includes waypoint 0 (the tour starts with a stop there)",
                format!("{stops:?}"),
            ));
        }
    }
    let (a, c) = (p.route[0], p.route[1]);
    Ok([a[0], a[1], (c[1] - a[1]).atan2(c[0] - a[0])])
}

/// `behaviour = "replay"` in a `[[person]]`: recorded people come from `[[replay]]` files.
fn replay_in_person(ck: &Checker<'_>, f: &str) -> crate::error::CoreError {
    err(
        ck.file,
        format!("{f}.behaviour"),
        "a scripted behaviour (recorded people come from a [[replay]] table's file)",
        "\"replay\"",
    )
}

/// Standing: the given pose.
fn standing_pose(x: &PersonInput<'_>) -> Result<[f64; 3]> {
    let (ck, f, p, file) = (x.ck, x.f.as_str(), x.p, x.ck.file);
    let pose = p.pose.ok_or_else(|| {
        err(file, format!("{f}.pose"), "pose = [x, y, theta] for a standing person", "nothing")
    })?;
    ck.finite(&format!("{f}.pose"), &pose)?;
    ck.inside(&format!("{f}.pose"), [pose[0], pose[1]], x.b)?;
    Ok(pose)
}

/// Visitor: the exhibits, objects with a viewing space; the pose is a reference point.
fn visitor_pose(x: &PersonInput<'_>, person: &mut Person) -> Result<[f64; 3]> {
    let (ck, f, p, file) = (x.ck, x.f.as_str(), x.p, x.ck.file);
    if p.exhibits.is_empty() {
        return Err(err(file, format!("{f}.exhibits"), "at least one exhibit for a visitor", "none"));
    }
    for (k, v) in p.exhibits.iter().enumerate() {
        let field = format!("{f}.exhibits[{k}]");
        let o = object_ref(ck, &field, v, x.objects)?;
        if x.objects[o].interaction.is_none() {
            return Err(err(
                file,
                field,
                "an object with an interaction (viewing) space",
                format!("{:?} (has none)", x.objects[o].name),
            ));
        }
        person.exhibits.push(o);
    }
    let o = &x.objects[person.exhibits[0]];
    Ok([o.pose[0], o.pose[1], 0.0]) // replaced by the viewing spot when the world is built
}

/// Conversation: home, the o-space centre and the schedule (relative to the episode start,
/// `start_time` seconds after midnight); the pose is home.
fn conversation_pose(x: &PersonInput<'_>, start_time: f64, person: &mut Person) -> Result<[f64; 3]> {
    let (ck, f, p, file) = (x.ck, x.f.as_str(), x.p, x.ck.file);
    let home = x.need("home", p.home)?;
    person.home = Some(home);
    person.spot = Some(x.need("spot", p.spot)?);
    let time = |field: &str, v: &Option<toml::Value>| -> Result<f64> {
        let v = v
            .as_ref()
            .ok_or_else(|| err(file, format!("{f}.{field}"), "a time for a conversation", "nothing"))?;
        parse_episode_time(ck, &format!("{f}.{field}"), v, start_time)
    };
    let (t0, t1) = (time("start", &p.start)?, time("end", &p.end)?);
    if t1 <= t0 {
        return Err(err(file, format!("{f}.end"), format!("a time after start ({t0} s)"), format!("{t1} s")));
    }
    person.schedule = Some([t0, t1]);
    if p.group.is_none() {
        return Err(err(file, format!("{f}.group"), "the conversation's group id", "nothing"));
    }
    Ok([home[0], home[1], 0.0])
}

/// Follower: a guide is named (resolved by `link_people` or `link_robot_guides`).
fn follower_pose(x: &PersonInput<'_>) -> Result<[f64; 3]> {
    let (f, p, file) = (x.f.as_str(), x.p, x.ck.file);
    if p.guide.is_none() {
        return Err(err(
            file,
            format!("{f}.guide"),
            "the name of a guide [[person]], or \"robot:<name>\" of a [[robot]]",
            "nothing",
        ));
    }
    Ok([0.0; 3]) // placed at the guide's first stop by link_people
}

/// Seated: the pose of seat `place` on the named bench, sofa or chair.
fn seated_pose(x: &PersonInput<'_>) -> Result<[f64; 3]> {
    let (f, p, file) = (x.f.as_str(), x.p, x.ck.file);
    let seat = p.seat.as_ref().ok_or_else(|| {
        err(file, format!("{f}.seat"), "the name of a bench, sofa or chair [[object]]", "nothing")
    })?;
    let o = x.objects.iter().find(|o| &o.name == seat).ok_or_else(|| {
        err(file, format!("{f}.seat"), "the name of a bench, sofa or chair [[object]]", format!("{seat:?}"))
    })?;
    if !matches!(o.kind, ObjectKind::Bench | ObjectKind::Sofa | ObjectKind::Chair) {
        return Err(err(
            file,
            format!("{f}.seat"),
            "a bench, sofa or chair",
            format!("{seat:?}, a {:?}", o.kind),
        ));
    }
    let places = ((o.size[1] / SEAT_SPACING).floor() as usize).max(1);
    if p.place >= places {
        return Err(err(
            file,
            format!("{f}.place"),
            format!("a seat index below {places} ({seat:?} seats {places})"),
            p.place.to_string(),
        ));
    }
    let along = (p.place as f64 - (places as f64 - 1.0) * 0.5) * SEAT_SPACING;
    let (s, c) = o.pose[2].sin_cos();
    Ok([o.pose[0] - s * along, o.pose[1] + c * along, o.pose[2]])
}

/// Resident and staff: home and the objects whose activities the person attends; the pose is
/// home.
fn attendee_pose(x: &PersonInput<'_>, person: &mut Person) -> Result<[f64; 3]> {
    let (ck, f, p, file) = (x.ck, x.f.as_str(), x.p, x.ck.file);
    let home = x.need("home", p.home)?;
    person.home = Some(home);
    if p.attends.is_empty() {
        return Err(err(
            file,
            format!("{f}.attends"),
            format!("the names of the objects whose activities the {:?} attends", p.behaviour),
            "none",
        ));
    }
    for (k, name) in p.attends.iter().enumerate() {
        let field = format!("{f}.attends[{k}]");
        let o = object_ref(ck, &field, &toml::Value::String(name.clone()), x.objects)?;
        if x.objects[o].interaction.is_none() {
            return Err(err(
                file,
                field,
                "an object with an interaction space (where its activities take place)",
                format!("{name:?} (has none)"),
            ));
        }
        person.attends.push(o);
    }
    Ok([home[0], home[1], 0.0])
}

/// Prefix of a follower's `guide` naming a robot (`guide = "robot:<name>"`).
pub const ROBOT_GUIDE: &str = "robot:";

/// Followers of robots: the robot's index, its tour and stops, and the follower's reference
/// pose (the robot's start; its place is planned when the world is built).
pub(super) fn link_robot_guides(
    ck: &Checker<'_>,
    raw: &[RawPerson],
    persons: &mut [Person],
    robots: &[Robot],
) -> Result<()> {
    for (i, (rp, person)) in raw.iter().zip(persons.iter_mut()).enumerate() {
        let Some(name) = rp.guide.as_ref().and_then(|n| n.strip_prefix(ROBOT_GUIDE)) else { continue };
        let j = robots.iter().position(|r| r.name == name).ok_or_else(|| {
            err(
                ck.file,
                format!("person[{i}].guide"),
                format!(
                    "\"robot:<name>\" naming a [[robot]] (one of {:?}), or the name of a person with behaviour = \"guide\"",
                    robots.iter().map(|r| r.name.as_str()).collect::<Vec<_>>()
                ),
                format!("{:?}", rp.guide.as_deref().unwrap_or_default()),
            )
        })?;
        let r = &robots[j];
        person.guide_robot = Some(j);
        person.tour = std::iter::once([r.start[0], r.start[1]])
            .chain(r.waypoints.iter().copied())
            .chain(std::iter::once(r.goal))
            .collect();
        let n = person.tour.len();
        person.tour_stops = (0..n).map(|k| k == 0 || k + 1 == n || r.dwell > 0.0).collect();
        person.pose = [r.start[0], r.start[1], 0.0];
    }
    Ok(())
}

/// Cross-person checks: followers' guides, conversations' shared spot and schedule, and groups
/// of at least two people.
fn link_people(ck: &Checker<'_>, raw: &[RawPerson], persons: &mut [Person]) -> Result<()> {
    let file = ck.file;
    for i in 0..persons.len() {
        let f = format!("person[{i}]");
        if let Some(name) = raw[i].guide.as_ref().filter(|n| !n.starts_with(ROBOT_GUIDE)) {
            let g = persons.iter().position(|q| &q.name == name && q.behaviour == Behaviour::Guide);
            let g = g.ok_or_else(|| {
                err(
                    file,
                    format!("{f}.guide"),
                    "the name of a person with behaviour = \"guide\", or \"robot:<name>\" of a [[robot]]",
                    format!("{name:?}"),
                )
            })?;
            persons[i].guide = Some(g);
            let r = persons[g].route[0];
            persons[i].pose = [r[0], r[1], 0.0]; // the slot is computed when the world is built
        }
        if let Some(g) = persons[i].group {
            let members: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].group == Some(g)).collect();
            if members.len() < 2 {
                return Err(err(
                    file,
                    format!("{f}.group"),
                    "a group id shared by at least 2 people",
                    format!("group {g} with 1 member"),
                ));
            }
            if persons[i].behaviour == Behaviour::Conversation {
                let first = members[0];
                for &k in &members {
                    if persons[k].behaviour != Behaviour::Conversation {
                        return Err(err(
                            file,
                            format!("person[{k}].behaviour"),
                            format!("\"conversation\" like the rest of group {g}"),
                            format!("{:?}", persons[k].behaviour),
                        ));
                    }
                }
                for (field, same) in [
                    ("spot", persons[i].spot == persons[first].spot),
                    ("start", persons[i].schedule.map(|s| s[0]) == persons[first].schedule.map(|s| s[0])),
                    ("end", persons[i].schedule.map(|s| s[1]) == persons[first].schedule.map(|s| s[1])),
                ] {
                    if !same {
                        return Err(err(
                            file,
                            format!("{f}.{field}"),
                            format!("the same {field} as person[{first}] (the same conversation, group {g})"),
                            "a different value",
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Sets every person's reaction to robots: its own `reaction` (or `aware = false`, the older
/// spelling of `ignore`), else its group's (`[[group]]`), else the scene's `default`. Recorded
/// people (after the `[[person]]` ones) take the scene's. Errors name `group[i].id` (an id no
/// person has, or a repeated one) and `person[i].reaction` (`aware = false` with another
/// reaction).
pub(super) fn assign_reactions(
    ck: &Checker,
    raw: &[RawPerson],
    groups: &[RawGroup],
    default: Reaction,
    persons: &mut [Person],
) -> Result<()> {
    for (k, g) in groups.iter().enumerate() {
        if !raw.iter().any(|p| p.group == Some(g.id)) {
            return Err(err(
                ck.file,
                format!("group[{k}].id"),
                "the group id of some person",
                g.id.to_string(),
            ));
        }
        if groups[..k].iter().any(|h| h.id == g.id) {
            return Err(err(
                ck.file,
                format!("group[{k}].id"),
                "a group id not listed before",
                g.id.to_string(),
            ));
        }
    }
    for (i, person) in persons.iter_mut().enumerate() {
        let Some(p) = raw.get(i) else {
            person.reaction = default;
            continue;
        };
        let group = || groups.iter().find(|g| Some(g.id) == p.group).map(|g| g.reaction);
        person.reaction = match (p.aware, p.reaction) {
            (false, Some(r)) if r != Reaction::Ignore => {
                return Err(err(
                    ck.file,
                    format!("person[{i}].reaction"),
                    "\"ignore\" or no reaction with aware = false (its older spelling)",
                    format!("{:?}", r.name()),
                ));
            }
            (false, _) => Reaction::Ignore,
            (true, Some(r)) => r,
            (true, None) => group().unwrap_or(default),
        };
    }
    Ok(())
}
