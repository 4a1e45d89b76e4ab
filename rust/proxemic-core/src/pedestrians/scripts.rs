//! Behaviour scripts: what each scripted person does, planned once on the static map.
//!
//! [`plan_scripts`] turns every person's behaviour ([`Behaviour`]) into a [`Script`] when the
//! world is built: viewing spots in exhibits' interaction spaces, places around activity objects
//! and in F-formations, the tour's gathering arcs, and collision-free paths (8-connected A* on the
//! static map inflated by the person's radius plus [`PATH_MARGIN`], smoothed) between them. The
//! crowd then only follows these programs, so a step plans nothing.
//!
//! Every place is checked against the static geometry; a place that does not fit, or a path
//! that does not exist, is a [`CoreError::Scenario`] naming the person's field.

use crate::error::{CoreError, Result};
use crate::map::CostGrid;
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::math::Vec2;
use crate::plan::{PathPlanner, SearchMode, nearest_passable, smooth_path};
use crate::scenario::{Behaviour, InteractionShape, Object, Person, Scenario};

/// Extra clearance of planned paths beyond the person's radius (metres).
pub const PATH_MARGIN: f64 = 0.15;

/// Where a staying person looks.
#[derive(Clone, Debug, PartialEq)]
pub enum Face {
    /// Toward a point (an exhibit, an o-space centre, an activity's object).
    Point(Vec2),
    /// Keeps its current heading.
    Keep,
}

/// When a stay ends.
#[derive(Clone, Debug, PartialEq)]
pub enum Until {
    /// After this many seconds of staying.
    For(f64),
    /// At this time (seconds since the episode start).
    At(f64),
    /// Never.
    Forever,
}

/// One step of a program.
#[derive(Clone, Debug, PartialEq)]
pub enum Task {
    /// Walk through these waypoints (the last one is the destination).
    Walk(Vec<Vec2>),
    /// Stand still (not pushable) until the condition holds.
    Stay {
        /// Where to look.
        face: Face,
        /// When to move on.
        until: Until,
    },
}

/// A sequence of tasks, optionally repeated.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    /// The tasks.
    pub tasks: Vec<Task>,
    /// Whether the program starts over after its last task.
    pub cyclic: bool,
    /// Start options: (task index, position), one of which is drawn at spawn when the episode
    /// randomises phases (else the first).
    pub starts: Vec<(usize, Vec2)>,
}

/// What a person does, as the crowd runs it.
#[derive(Clone, Debug, PartialEq)]
pub enum Script {
    /// Walks its route (see [`crate::pedestrians`]).
    Walker,
    /// Never moves (standing and seated people).
    Still,
    /// Follows a program (visitors, conversations, residents, staff).
    Program(Program),
    /// A tour guide: its route, with a stop flag per waypoint.
    Guide {
        /// Whether each route waypoint is a stop.
        stops: Vec<bool>,
        /// Indices of the followers.
        followers: Vec<usize>,
    },
    /// A tour follower.
    Follower {
        /// Index of the guide.
        guide: usize,
        /// This follower's place at each of the guide's waypoints (`None` if not a stop).
        slots: Vec<Option<Vec2>>,
    },
    /// A follower of a robot's tour (its start, waypoints and goal: the tour points). It walks
    /// the robot's trail (see [`crate::pedestrians::Crowd::set_guides`]).
    RobotFollower {
        /// Index of the robot; `None` if it is not in the episode (the follower then stays at
        /// its place at the start).
        robot: Option<usize>,
        /// The robot's start (the first tour point).
        start: Vec2,
        /// The places on the arc at each tour point, one per follower (empty where the robot
        /// does not stop); a follower takes the nearest one not yet taken. The first is this
        /// follower's own at the start.
        places: Vec<Vec<Vec2>>,
    },
    /// A recorded person (see [`crate::pedestrians::replay`]).
    Replay {
        /// The track, `[t, x, y]` samples (seconds after the episode start, metres).
        track: Vec<[f64; 3]>,
        /// The person reacts once a robot's centre comes within this distance (metres; 0: never).
        react_radius: f64,
    },
}

impl Script {
    /// The script of a walker, a standing or a replayed person, which needs no planning
    /// (anything else stands still).
    pub fn basic(p: &Person) -> Self {
        match p.behaviour {
            Behaviour::Walker => Script::Walker,
            Behaviour::Replay => Script::Replay { track: p.track.clone(), react_radius: p.react_radius },
            _ => Script::Still,
        }
    }
}

fn err(s: &Scenario, field: String, expected: impl Into<String>, found: impl Into<String>) -> CoreError {
    CoreError::Scenario { file: s.source.clone(), field, expected: expected.into(), found: found.into() }
}

fn v2(p: [f64; 2]) -> Vec2 {
    Vec2::new(p[0], p[1])
}

/// Distance from `c` along the unit `dir` to where the ray leaves the convex polygon `poly`
/// (containing `c`); 0 if it does not.
fn ray_exit(poly: &[[f64; 2]], c: Vec2, dir: Vec2) -> f64 {
    let n = poly.len();
    let mut best: f64 = 0.0;
    for k in 0..n {
        let (a, b) = (v2(poly[k]), v2(poly[(k + 1) % n]));
        let e = b - a;
        let den = dir.x * e.y - dir.y * e.x;
        if den.abs() < 1e-12 {
            continue;
        }
        let w = a - c;
        let t = (w.x * e.y - w.y * e.x) / den;
        let u = (w.x * dir.y - w.y * dir.x) / den;
        if t > 0.0 && (-1e-9..=1.0 + 1e-9).contains(&u) {
            best = best.max(t);
        }
    }
    best
}

/// A place on the ray from the object's centre at angle `a`: halfway between the footprint and
/// the interaction space's edge, and at least the person's radius plus 0.1 m off the footprint.
fn ring_place(o: &Object, a: f64, radius: f64) -> Vec2 {
    let c = Vec2::new(o.pose[0], o.pose[1]);
    let dir = Vec2::new(a.cos(), a.sin());
    let t_in = ray_exit(&o.footprint, c, dir);
    let t_out = o.interaction.as_ref().map_or(t_in + 1.0, |i| ray_exit(&i.polygon, c, dir));
    c + dir * (0.5 * (t_in + t_out)).max(t_in + radius + 0.1)
}

fn clear(g: &StaticGeometry, p: Vec2, radius: f64) -> bool {
    !g.contains(p) && g.distance(p) >= radius + 0.05
}

/// Paths between places, on grids inflated per person radius (cached).
struct Router<'a> {
    field: &'a DistanceField,
    grids: Vec<(f64, CostGrid)>,
    planner: PathPlanner,
}

impl Router<'_> {
    fn path(&mut self, radius: f64, a: Vec2, b: Vec2) -> Option<Vec<Vec2>> {
        let inflate = radius + PATH_MARGIN;
        let k = match self.grids.iter().position(|(r, _)| (r - inflate).abs() < 1e-12) {
            Some(k) => k,
            None => {
                self.grids.push((inflate, CostGrid::inflated(self.field, inflate)));
                self.grids.len() - 1
            }
        };
        let grid = &self.grids[k].1;
        let snap = |p: Vec2| {
            let cell = grid.spec.cell_of(p)?;
            nearest_passable(grid, cell, (0.6 / grid.spec.resolution).ceil() as usize)
        };
        let (s, g) = (snap(a)?, snap(b)?);
        let cells = self.planner.plan(grid, s, g, SearchMode { weight: 0.0, heuristic: true })?;
        let mut pts = smooth_path(grid, &cells, 0.0);
        if !pts.is_empty() {
            pts.remove(0); // the person is at `a` already
        }
        pts.push(b);
        Some(pts)
    }

    /// Person `p`'s path from `a` to `b`; without one, an error naming `field`.
    fn walk(&mut self, s: &Scenario, p: &Person, field: String, a: Vec2, b: Vec2) -> Result<Vec<Vec2>> {
        self.path(p.radius, a, b).ok_or_else(|| {
            err(
                s,
                field,
                format!("a place reachable on foot (with {:.2} m clearance)", p.radius + PATH_MARGIN),
                format!("no path from [{:.2}, {:.2}] to [{:.2}, {:.2}]", a.x, a.y, b.x, b.y),
            )
        })
    }
}

/// Plans every person's script (see the module docs). `geometry` and `field` are the scenario's
/// static world.
pub fn plan_scripts(s: &Scenario, geometry: &StaticGeometry, field: &DistanceField) -> Result<Vec<Script>> {
    let mut router = Router { field, grids: Vec::new(), planner: PathPlanner::new() };
    let persons = &s.persons;
    let mut out = Vec::with_capacity(persons.len());
    for (i, p) in persons.iter().enumerate() {
        let script = match p.behaviour {
            Behaviour::Walker | Behaviour::Replay => Script::basic(p),
            Behaviour::Standing | Behaviour::Seated => Script::Still,
            Behaviour::Visitor => visitor(s, geometry, &mut router, i)?,
            Behaviour::Conversation => conversation(s, geometry, &mut router, i)?,
            Behaviour::Resident | Behaviour::Staff => attendee(s, geometry, &mut router, i)?,
            Behaviour::Guide => {
                let followers: Vec<usize> =
                    (0..persons.len()).filter(|&k| persons[k].guide == Some(i)).collect();
                Script::Guide { stops: p.stops.clone(), followers }
            }
            Behaviour::Follower if !p.tour.is_empty() => robot_follower(s, geometry, i)?,
            Behaviour::Follower => follower(s, geometry, i)?,
        };
        out.push(script);
    }
    Ok(out)
}

/// A visitor: a viewing spot at each exhibit, stays of `dwell` seconds there facing it, and the
/// walks between them, cyclically; it may start at any exhibit.
fn visitor(s: &Scenario, geometry: &StaticGeometry, router: &mut Router<'_>, i: usize) -> Result<Script> {
    let (p, f) = (&s.persons[i], format!("person[{i}]"));
    let mut places = Vec::with_capacity(p.exhibits.len());
    for (k, &o) in p.exhibits.iter().enumerate() {
        let field = format!("{f}.exhibits[{k}]");
        places.push(viewing_spot(s, geometry, &field, &s.objects[o], i, k, p.radius)?);
    }
    let m = places.len();
    let mut tasks = Vec::with_capacity(2 * m);
    let mut starts = Vec::with_capacity(m);
    for k in 0..m {
        let o = &s.objects[p.exhibits[k]];
        starts.push((tasks.len(), places[k]));
        let face = Face::Point(Vec2::new(o.pose[0], o.pose[1]));
        tasks.push(Task::Stay { face, until: Until::For(p.dwell) });
        if m > 1 {
            let next = (k + 1) % m;
            tasks.push(Task::Walk(router.walk(
                s,
                p,
                format!("{f}.exhibits[{next}]"),
                places[k],
                places[next],
            )?));
        }
    }
    Ok(Script::Program(Program { tasks, cyclic: true, starts }))
}

/// A member of a conversation: its place on a circle around the o-space centre (by rank in the
/// group), the walks from home and back, and the stays until the schedule's start and end.
fn conversation(
    s: &Scenario,
    geometry: &StaticGeometry,
    router: &mut Router<'_>,
    i: usize,
) -> Result<Script> {
    let (p, persons, f) = (&s.persons[i], &s.persons, format!("person[{i}]"));
    let (home, centre) = (v2(p.home.unwrap_or_default()), v2(p.spot.unwrap_or_default()));
    let [t0, t1] = p.schedule.unwrap_or([0.0, 0.0]);
    let members: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].group == p.group).collect();
    let n = members.len();
    let rank = members.iter().position(|&k| k == i).unwrap_or(0);
    let first_home = v2(persons[members[0]].home.unwrap_or_default()) - centre;
    let a = first_home.y.atan2(first_home.x) + std::f64::consts::TAU * rank as f64 / n as f64;
    let r = 0.4 + 0.1 * n as f64;
    let slot = centre + Vec2::new(a.cos(), a.sin()) * r;
    if !clear(geometry, slot, p.radius) {
        return Err(err(
            s,
            format!("{f}.spot"),
            format!("an o-space centre with room for {n} people on a circle of radius {r:.2} m"),
            format!("this person's place [{:.2}, {:.2}] hits a wall or object", slot.x, slot.y),
        ));
    }
    let there = router.walk(s, p, format!("{f}.spot"), home, slot)?;
    let back = router.walk(s, p, format!("{f}.home"), slot, home)?;
    let tasks = vec![
        Task::Stay { face: Face::Point(centre), until: Until::At(t0) },
        Task::Walk(there),
        Task::Stay { face: Face::Point(centre), until: Until::At(t1) },
        Task::Walk(back),
        Task::Stay { face: Face::Keep, until: Until::Forever },
    ];
    let start = if t0 <= 0.0 && t1 > 0.0 {
        (2, slot)
    } else if t1 <= 0.0 {
        (4, home)
    } else {
        (0, home)
    };
    Ok(Script::Program(Program { tasks, cyclic: false, starts: vec![start] }))
}

/// A resident or staff member: for each activity on the objects it attends, in time order, the
/// walk to its place (leaving so as to arrive `lead` seconds early), the stay until the end, home
/// in between when there is a minute or more, and home at the end.
fn attendee(s: &Scenario, geometry: &StaticGeometry, router: &mut Router<'_>, i: usize) -> Result<Script> {
    let (p, f) = (&s.persons[i], format!("person[{i}]"));
    let home = v2(p.home.unwrap_or_default());
    let mut tasks = Vec::new();
    let mut start = None;
    let mut here = home;
    let mut acts: Vec<(usize, usize)> = Vec::new(); // (activity, attends index)
    for (k, &o) in p.attends.iter().enumerate() {
        for (a, act) in s.activities.iter().enumerate() {
            if act.object == s.objects[o].name {
                acts.push((a, k));
            }
        }
    }
    acts.sort_by(|x, y| s.activities[x.0].start.total_cmp(&s.activities[y.0].start));
    let path_length = |from: Vec2, path: &[Vec2]| -> f64 {
        let mut last = from;
        path.iter().map(|&q| ((q - last).norm(), last = q).0).sum()
    };
    // Leave early enough to arrive `lead` before the start: the path at 80 % of the
    // preferred speed (people slow down to pass others), plus 5 s.
    let depart_for = |t0: f64, length: f64| t0 - p.lead - length / (0.8 * p.speed) - 5.0;
    let mut prev_end = f64::NEG_INFINITY;
    for (a, k) in acts {
        let act = &s.activities[a];
        let (t0, t1) = (act.start - s.scene.start_time, act.end - s.scene.start_time);
        if t1 <= 0.0 {
            continue;
        }
        let field = format!("{f}.attends[{k}]");
        let (place, facing) = activity_place(s, geometry, &field, p.attends[k], i)?;
        let mut there = router.walk(s, p, field.clone(), here, place)?;
        let mut depart = depart_for(t0, path_length(here, &there));
        if here != home && depart - prev_end >= 60.0 {
            // A minute or more between two activities: go home in between.
            tasks.push(Task::Walk(router.walk(s, p, format!("{f}.home"), here, home)?));
            here = home;
            there = router.walk(s, p, field.clone(), here, place)?;
            depart = depart_for(t0, path_length(here, &there));
        }
        if depart <= 0.0 && start.is_none() && tasks.is_empty() {
            start = Some((0, place)); // already there when the episode starts
        } else {
            tasks.push(Task::Stay { face: Face::Keep, until: Until::At(depart) });
            tasks.push(Task::Walk(there));
        }
        tasks.push(Task::Stay { face: Face::Point(facing), until: Until::At(t1) });
        here = place;
        prev_end = t1;
    }
    if here != home {
        tasks.push(Task::Walk(router.walk(s, p, format!("{f}.home"), here, home)?));
    }
    tasks.push(Task::Stay { face: Face::Keep, until: Until::Forever });
    let start = start.unwrap_or((0, home));
    Ok(Script::Program(Program { tasks, cyclic: false, starts: vec![start] }))
}

/// A follower of a guide (a person): its place on an arc behind the guide at each of its stops.
fn follower(s: &Scenario, geometry: &StaticGeometry, i: usize) -> Result<Script> {
    let (p, persons) = (&s.persons[i], &s.persons);
    let g = p.guide.unwrap_or(0);
    let guide = &persons[g];
    let followers: Vec<usize> = (0..persons.len()).filter(|&k| persons[k].guide == Some(g)).collect();
    let rank = followers.iter().position(|&k| k == i).unwrap_or(0);
    let m = followers.len() as f64;
    let n = guide.route.len();
    let mut slots = vec![None; n];
    for k in (0..n).filter(|&k| guide.stops[k]) {
        let stop = v2(guide.route[k]);
        let (prev, next) = (v2(guide.route[(k + n - 1) % n]), v2(guide.route[(k + 1) % n]));
        let back = prev - stop;
        let r = p.gather_radius;
        // The arc is centred behind the guide (where the group comes from), one
        // shoulder width (0.75 m) apart, at most a half circle wide.
        let step = (0.75 / r).min(std::f64::consts::PI / m.max(1.0));
        let a = back.y.atan2(back.x) + (rank as f64 - 0.5 * (m - 1.0)) * step;
        let slot = stop + Vec2::new(a.cos(), a.sin()) * r;
        if !clear(geometry, slot, p.radius)
            || geometry.segment_hits(prev, slot)
            || geometry.segment_hits(slot, next)
        {
            return Err(err(
                s,
                format!("person[{g}].route[{k}]"),
                format!(
                    "a stop with room for {m} followers on an arc of radius {r} m behind it, \
                     reachable from route[{}] and toward route[{}] without crossing walls or furniture",
                    (k + n - 1) % n,
                    (k + 1) % n
                ),
                format!("follower {:?}'s place [{:.2}, {:.2}] does not fit", p.name, slot.x, slot.y),
            ));
        }
        slots[k] = Some(slot);
    }
    Ok(Script::Follower { guide: g, slots })
}

/// The script of follower `i` of a robot's tour: a place on an arc of `gather_radius` behind
/// each stop (opening toward where the robot comes from; at the start, away from where it goes),
/// one shoulder width (0.75 m) apart, in sight of the stop.
fn robot_follower(s: &Scenario, geometry: &StaticGeometry, i: usize) -> Result<Script> {
    let p = &s.persons[i];
    let tour: Vec<Vec2> = p.tour.iter().map(|q| v2(*q)).collect();
    let n = tour.len();
    let followers: Vec<usize> = (0..s.persons.len()).filter(|&k| s.persons[k].tour == p.tour).collect();
    let rank = followers.iter().position(|&k| k == i).unwrap_or(0);
    let m = followers.len() as f64;
    // Fields of the tour points in the file: the robot's start, waypoints and goal.
    let point_field = |k: usize| match p.guide_robot {
        Some(j) if k == 0 => format!("robot[{j}].start"),
        Some(j) if k + 1 == n => format!("robot[{j}].goal"),
        Some(j) => format!("robot[{j}].waypoints[{}]", k - 1),
        None => format!("person[{i}].guide"),
    };
    let mut places = vec![Vec::new(); n];
    for k in (0..n).filter(|&k| p.tour_stops.get(k).copied().unwrap_or(false)) {
        let stop = tour[k];
        let back = if k == 0 { tour[0] - tour[1.min(n - 1)] } else { tour[k - 1] - stop };
        let r = p.gather_radius;
        let step = (0.75 / r).min(std::f64::consts::PI / m.max(1.0));
        for place in 0..followers.len() {
            let a = back.y.atan2(back.x) + (place as f64 - 0.5 * (m - 1.0)) * step;
            let slot = stop + Vec2::new(a.cos(), a.sin()) * r;
            if !clear(geometry, slot, p.radius) || geometry.segment_hits(stop, slot) {
                return Err(err(
                    s,
                    point_field(k),
                    format!(
                        "a tour stop with room for {m} followers on an arc of radius {r} m behind it, in sight of it"
                    ),
                    format!("place {place} of its arc, [{:.2}, {:.2}], does not fit", slot.x, slot.y),
                ));
            }
            places[k].push(slot);
        }
    }
    // At the start, each follower stands at its own place (by rank).
    if let Some(first) = places.first_mut().filter(|f| !f.is_empty()) {
        first.swap(0, rank);
    }
    Ok(Script::RobotFollower { robot: p.guide_robot, start: tour[0], places })
}

/// A visitor's viewing place for object `o`: in front of a trapezoid (painting, TV), spread
/// sideways by the visitor's index; around other shapes at an angle set by the indices, the first
/// of eight that is clear.
fn viewing_spot(
    s: &Scenario,
    geometry: &StaticGeometry,
    field: &str,
    o: &Object,
    person: usize,
    stop: usize,
    radius: f64,
) -> Result<Vec2> {
    let theta = o.pose[2];
    let c = Vec2::new(o.pose[0], o.pose[1]);
    let candidates: Vec<Vec2> = match o.interaction.as_ref().map(|i| &i.shape) {
        Some(InteractionShape::Trapezoid { near_width, .. }) => {
            let ahead = ring_place(o, theta, radius) - c;
            let side = Vec2::new(-theta.sin(), theta.cos());
            [((person + 2 * stop) % 3) as f64 - 1.0, 0.0, 1.0, -1.0]
                .iter()
                .map(|&k| c + ahead + side * (k * 0.25 * near_width))
                .collect()
        }
        _ => (0..8)
            .map(|j| {
                let slot = (3 * person + 5 * stop + j) % 8;
                ring_place(o, theta + std::f64::consts::TAU * slot as f64 / 8.0, radius)
            })
            .collect(),
    };
    candidates.iter().copied().find(|&q| clear(geometry, q, radius)).ok_or_else(|| {
        err(
            s,
            field.to_string(),
            format!("an exhibit with a free viewing place in its interaction space ({:?})", o.name),
            format!(
                "no place clear of walls and furniture (tried [{:.2}, {:.2}], ...)",
                candidates[0].x, candidates[0].y
            ),
        )
    })
}

/// The participants of the activities on object `obj` and the angle (from the object's centre)
/// of each one's place: residents spread around the object's front direction, staff on the far
/// side (beside a trapezoid's screen), so that they face the residents.
fn participant_angles(s: &Scenario, obj: usize) -> Vec<(usize, f64)> {
    let o = &s.objects[obj];
    let attending = |b: Behaviour| -> Vec<usize> {
        (0..s.persons.len())
            .filter(|&k| s.persons[k].behaviour == b && s.persons[k].attends.contains(&obj))
            .collect()
    };
    let (residents, staff) = (attending(Behaviour::Resident), attending(Behaviour::Staff));
    let (nr, ns) = (residents.len() as f64, staff.len() as f64);
    let trapezoid =
        matches!(o.interaction.as_ref().map(|i| &i.shape), Some(InteractionShape::Trapezoid { .. }));
    let theta = o.pose[2];
    let step = if trapezoid { 0.35 } else { (std::f64::consts::TAU / (nr + ns).max(1.0)).min(0.9) };
    let mut out: Vec<(usize, f64)> = residents
        .iter()
        .enumerate()
        .map(|(k, &i)| (i, theta + (k as f64 - 0.5 * (nr - 1.0)) * step))
        .collect();
    for (k, &i) in staff.iter().enumerate() {
        let k = k as f64;
        let a = if trapezoid {
            theta + 0.5 * (nr - 1.0) * step + 0.6 + k * step
        } else {
            theta + std::f64::consts::PI + (k - 0.5 * (ns - 1.0)) * step
        };
        out.push((i, a));
    }
    out
}

/// Person `person`'s place at object `obj` (see [`participant_angles`]) and the point it faces:
/// a resident faces the object, a staff member the residents' mean place.
fn activity_place(
    s: &Scenario,
    geometry: &StaticGeometry,
    field: &str,
    obj: usize,
    person: usize,
) -> Result<(Vec2, Vec2)> {
    let o = &s.objects[obj];
    let angles = participant_angles(s, obj);
    let place_of = |k: usize, a: f64| ring_place(o, a, s.persons[k].radius);
    let a = angles.iter().find(|(k, _)| *k == person).map_or(o.pose[2], |(_, a)| *a);
    let q = place_of(person, a);
    if !clear(geometry, q, s.persons[person].radius) {
        return Err(err(
            s,
            field.to_string(),
            format!("an object with a free place for this person in its interaction space ({:?})", o.name),
            format!("the place [{:.2}, {:.2}] hits a wall or object", q.x, q.y),
        ));
    }
    let centre = Vec2::new(o.pose[0], o.pose[1]);
    let residents: Vec<Vec2> = angles
        .iter()
        .filter(|(k, _)| s.persons[*k].behaviour == Behaviour::Resident)
        .map(|&(k, a)| place_of(k, a))
        .collect();
    let face = if s.persons[person].behaviour == Behaviour::Staff && !residents.is_empty() {
        residents.iter().fold(Vec2::zeros(), |acc, &r| acc + r) / residents.len() as f64
    } else {
        centre
    };
    Ok((q, face))
}
