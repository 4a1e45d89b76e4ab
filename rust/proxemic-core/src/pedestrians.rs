//! Scripted pedestrians driven by a social force model.
//!
//! Every walker follows its closed route of waypoints, pausing `dwell` seconds at each; its
//! motion comes from the social force model, integrated with a fixed time step
//! ([`SocialForceParams::dt`], 0.1 s by default) in a Jacobi (snapshot) update so that the result does not
//! depend on the order of the people:
//! - **driving force** toward the current waypoint, `(v0 e - v) / tau` (Helbing & Molnar 1995);
//! - **interaction with other people** (and with the robots, for *aware* people) after
//!   Moussaid et al. 2009: an exponential repulsion along the interaction direction
//!   `t = D / |D|`, `D = lambda (v_i - v_j) + e_ij`, and a lateral term that makes people pass
//!   each other; at exact symmetry the lateral term takes the project's passing convention
//!   (pass on the right, [`PASS_ON_RIGHT`]);
//! - **walls and furniture**: `F_o exp(-d / sigma_o)` along the gradient of the static
//!   distance field, with `d` the gap between the body and the nearest obstacle (pedsim's
//!   parameters), plus a hard constraint checked on the exact geometry: a step that would bring
//!   a person's centre closer than half its radius to it is cancelled;
//! - **walking groups** (people with the same group id): gaze, coherence and repulsion terms
//!   of Moussaid et al. 2010.
//!
//! Other behaviours ([`Behaviour`]: exhibit visitors, conversations, tour guides and followers,
//! seated people, care-center residents and staff) run [`scripts::Script`]s planned once when
//! the world is built ([`scripts::plan_scripts`]): they walk with the same forces and hard
//! constraints, and while they stay somewhere (dwelling at an exhibit, talking, sitting, taking
//! part in an activity, gathered at a tour stop) they stand still like standing people, turned
//! toward what they attend to.
//!
//! Standing people stay where they are (other people and the robot go around them). Aware
//! people additionally never step to within [`YIELD_GAP`] of a robot's body: such a step is
//! cancelled and they wait.
//!
//! Every random draw (initial route phase, speed jitter) comes from the episode's seeded
//! generator; the force sums run over neighbours in index order, so runs are bit-identical.

pub mod scripts;

use rand::Rng;

use self::scripts::{Face, Script, Task, Until};
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::math::{Vec2, wrap_angle};
use crate::scenario::{Person, Randomize};

/// Surface gap (metres) below which an aware person does not step toward a robot.
pub const YIELD_GAP: f64 = 0.1;

/// Maximum rate at which people turn their body toward their walking direction (rad/s).
pub const TURN_RATE: f64 = 4.0;

pub use crate::control::PASS_ON_RIGHT;

/// Parameters of the social force model (defaults from the sources named in the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SocialForceParams {
    /// Integration step (s); default 0.1, the control period (control periods are split into
    /// whole steps). Explicit Euler on the relaxation term needs `dt < 2 tau`; design/algorithms.md
    /// suggests 0.05 for the stiff interaction terms. At 0.1 every pedestrian test (Moussaid's
    /// known answers, no wall penetration in long crowded runs, passing side, group cohesion,
    /// determinism) still holds and a person costs half as much, which keeps the whole per-step
    /// Rust call under a tenth of an env step on the museum; set 0.05 for finer dynamics.
    pub dt: f64,
    /// Relaxation time of the driving force (s); default 0.5 (Helbing & Molnar 1995).
    pub tau: f64,
    /// Interaction strength A (m/s^2); default 4.5 (Moussaid et al. 2009).
    pub strength: f64,
    /// Weight of the relative velocity in the interaction direction, lambda; default 2.0.
    pub lambda: f64,
    /// Range factor gamma of the interaction (B = gamma |D|); default 0.35.
    pub gamma: f64,
    /// Angular width n of the lateral term; default 2.0.
    pub n: f64,
    /// Angular width n' of the deceleration term; default 3.0.
    pub n_prime: f64,
    /// Neighbours farther than this are ignored (m); default 4.0 (their force is below 1e-4).
    pub cutoff: f64,
    /// Wall force magnitude F_o (m/s^2); default 10 (pedsim_ros).
    pub wall_strength: f64,
    /// Wall force range sigma_o (m); default 0.2 (pedsim_ros).
    pub wall_range: f64,
    /// Group gaze weight beta_1; default 4.0 (Moussaid et al. 2010 as in PySocialForce).
    pub group_gaze: f64,
    /// Group coherence weight beta_2; default 3.0.
    pub group_coherence: f64,
    /// Group repulsion weight beta_3; default 1.0.
    pub group_repulsion: f64,
    /// Group repulsion distance d0 (m); default 0.55.
    pub group_d0: f64,
    /// A waypoint counts as reached within this distance (m); default 0.3.
    pub arrival: f64,
    /// Maximum speed as a multiple of the preferred speed; default 1.3 (Helbing & Molnar 1995).
    pub max_speed_factor: f64,
}

impl Default for SocialForceParams {
    fn default() -> Self {
        SocialForceParams {
            dt: 0.1,
            tau: 0.5,
            strength: 4.5,
            lambda: 2.0,
            gamma: 0.35,
            n: 2.0,
            n_prime: 3.0,
            cutoff: 4.0,
            wall_strength: 10.0,
            wall_range: 0.2,
            group_gaze: 4.0,
            group_coherence: 3.0,
            group_repulsion: 1.0,
            group_d0: 0.55,
            arrival: 0.3,
            max_speed_factor: 1.3,
        }
    }
}

/// Interaction force on a pedestrian at `pi` with velocity `vi` from an agent at `pj` with
/// velocity `vj` (Moussaid, Helbing, Garnier, Johansson, Combe & Theraulaz 2009, Proc. R. Soc. B
/// 276). Centre-to-centre distances; m/s^2.
pub fn interaction_force(pi: Vec2, vi: Vec2, pj: Vec2, vj: Vec2, p: &SocialForceParams) -> Vec2 {
    let diff = pj - pi;
    let d2 = diff.norm_squared();
    if d2 < 1e-18 || d2 > p.cutoff * p.cutoff {
        return Vec2::zeros();
    }
    let d = d2.sqrt();
    let e = diff / d;
    let big_d = (vi - vj) * p.lambda + e;
    let dn = big_d.norm();
    if dn < 1e-12 {
        return Vec2::zeros();
    }
    let t = big_d / dn;
    let n = Vec2::new(-t.y, t.x);
    let theta = (t.x * e.y - t.y * e.x).atan2(t.dot(&e));
    let b = p.gamma * dn;
    // sign(theta), with exact symmetry resolved by the passing convention: K = +1 pushes i to
    // its right (-n), so both agents of a head-on encounter pass on the right.
    let k = if theta > 0.0 {
        1.0
    } else if theta < 0.0 {
        -1.0
    } else if PASS_ON_RIGHT {
        1.0
    } else {
        -1.0
    };
    let magnitude = p.strength * (-d / b).exp();
    if magnitude < 1e-6 {
        return Vec2::zeros();
    }
    let decel = (-(p.n_prime * b * theta).powi(2)).exp();
    let lateral = (-(p.n * b * theta).powi(2)).exp();
    -(t * decel + n * (k * lateral)) * magnitude
}

/// The scripted crowd, as a structure of arrays.
#[derive(Clone, Debug, Default)]
pub struct Crowd {
    /// Positions (metres).
    pub pos: Vec<Vec2>,
    /// Velocities (m/s).
    pub vel: Vec<Vec2>,
    /// Body orientation (radians).
    pub heading: Vec<f64>,
    /// Body radius (metres).
    pub radius: Vec<f64>,
    /// Ground-truth group ids.
    pub group: Vec<Option<u32>>,
    speed: Vec<f64>,
    target: Vec<usize>,
    dwell_left: Vec<f64>,
    routes: Vec<Vec<Vec2>>,
    dwell: Vec<f64>,
    /// Walkers: whether they dwell at each waypoint (empty: at every one).
    stops: Vec<Vec<bool>>,
    walker: Vec<bool>,
    aware: Vec<bool>,
    params: SocialForceParams,
    scratch: Vec<Vec2>,
    /// Each person's script, and its program state: task, waypoint within a walk, time in the
    /// current stay, time stuck near a destination; for followers, the stop last gathered at.
    script: Vec<Script>,
    task: Vec<usize>,
    leg: Vec<usize>,
    clock: Vec<f64>,
    stuck: Vec<f64>,
    gathered: Vec<Option<usize>>,
    /// Per substep: whether the person moves (else it stands still, not pushable), its desired
    /// velocity, and the heading it turns to when not walking.
    moving: Vec<bool>,
    desired: Vec<Vec2>,
    face_want: Vec<Option<f64>>,
    /// Seconds since the spawn.
    time: f64,
    /// Members of each walking group (index lists), and each person's group slot.
    groups: Vec<Vec<usize>>,
    group_slot: Vec<Option<usize>>,
    /// Neighbour bins (rebuilt every substep for large crowds).
    bins: NeighbourBins,
    /// The robots as their tours' followers see them (see [`Crowd::set_guides`]), and each
    /// robot's trail: where it went, a point every [`TRAIL_SPACING`] metres.
    guides: Vec<GuideState>,
    trails: Vec<Vec<Vec2>>,
}

/// A robot as the followers of its tour see it (see [`Crowd::set_guides`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GuideState {
    /// Position (metres).
    pub pos: Vec2,
    /// The tour point it walks to or stands at: 0 its start, then its waypoints, then its goal.
    pub target: usize,
    /// Whether it stands at `target` (dwelling at a waypoint, or arrived at its goal).
    pub dwelling: bool,
}

/// How close (metres, centre to centre) a follower walks behind its robot guide.
pub const FOLLOW_GAP: f64 = 1.2;

/// How near (metres) a follower of a robot gets to its place on a gathering arc (places are
/// 0.75 m apart, so followers in place never overlap).
pub const SLOT_REACHED: f64 = 0.1;

/// Within this distance (metres) of a robot standing at a stop, its followers walk straight to
/// their places on the arc instead of along its trail.
pub const GATHER_REACH: f64 = 3.0;

/// Centre distance (metres) a follower keeps from its robot guide: closer, it steps back.
pub const ROBOT_SPACE: f64 = 1.0;

/// Spacing (metres) of the points of a robot's trail, which its followers walk.
pub const TRAIL_SPACING: f64 = 0.3;

/// How near (metres) a follower passes a trail point before heading for the next.
pub const TRAIL_REACHED: f64 = 0.4;

/// Uniform grid of people for the neighbour search (cell = cutoff); used above
/// [`BRUTE_FORCE_MAX`] people.
#[derive(Clone, Debug, Default)]
struct NeighbourBins {
    origin: Vec2,
    cell: f64,
    nx: usize,
    ny: usize,
    start: Vec<usize>,
    items: Vec<usize>,
}

/// Up to this many people, every pair is visited (cheaper than binning).
const BRUTE_FORCE_MAX: usize = 64;

impl NeighbourBins {
    fn rebuild(&mut self, pos: &[Vec2], cell: f64) {
        let (mut lo, mut hi) =
            (Vec2::new(f64::INFINITY, f64::INFINITY), Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY));
        for p in pos {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        self.origin = lo;
        self.cell = cell;
        self.nx = (((hi.x - lo.x) / cell).floor() as usize + 1).min(4096);
        self.ny = (((hi.y - lo.y) / cell).floor() as usize + 1).min(4096);
        let cells = self.nx * self.ny;
        self.start.clear();
        self.start.resize(cells + 1, 0);
        for p in pos {
            let k = self.key(*p);
            self.start[k + 1] += 1;
        }
        for c in 0..cells {
            self.start[c + 1] += self.start[c];
        }
        let mut fill = self.start.clone();
        self.items.clear();
        self.items.resize(pos.len(), 0);
        for (i, p) in pos.iter().enumerate() {
            let k = self.key(*p);
            self.items[fill[k]] = i;
            fill[k] += 1;
        }
    }

    fn key(&self, p: Vec2) -> usize {
        let x = (((p.x - self.origin.x) / self.cell).floor().max(0.0) as usize).min(self.nx - 1);
        let y = (((p.y - self.origin.y) / self.cell).floor().max(0.0) as usize).min(self.ny - 1);
        y * self.nx + x
    }

    /// Calls `f(j)` for every person in the 3x3 cells around `p`, in increasing cell order.
    fn for_near(&self, p: Vec2, mut f: impl FnMut(usize)) {
        let cx = (((p.x - self.origin.x) / self.cell).floor().max(0.0) as usize).min(self.nx - 1);
        let cy = (((p.y - self.origin.y) / self.cell).floor().max(0.0) as usize).min(self.ny - 1);
        for y in cy.saturating_sub(1)..=(cy + 1).min(self.ny - 1) {
            for x in cx.saturating_sub(1)..=(cx + 1).min(self.nx - 1) {
                let c = y * self.nx + x;
                for &j in &self.items[self.start[c]..self.start[c + 1]] {
                    f(j);
                }
            }
        }
    }
}

impl Crowd {
    /// Number of people.
    pub fn len(&self) -> usize {
        self.pos.len()
    }

    /// Whether there are no people.
    pub fn is_empty(&self) -> bool {
        self.pos.is_empty()
    }

    /// Tells the followers of robot tours where each robot is (one entry per robot, by index;
    /// followers of a robot without an entry wait where they are). Call before every
    /// [`Crowd::step`]: each robot's trail (a point every [`TRAIL_SPACING`] metres of its way
    /// since the crowd was spawned) is what its followers walk, so they keep to where it went.
    pub fn set_guides(&mut self, guides: &[GuideState]) {
        self.guides.clear();
        self.guides.extend_from_slice(guides);
        self.trails.resize(guides.len(), Vec::new());
        for (trail, g) in self.trails.iter_mut().zip(guides) {
            if trail.last().is_none_or(|q| (g.pos - q).norm() >= TRAIL_SPACING) {
                trail.push(g.pos);
            }
        }
    }

    /// The social force parameters.
    pub fn params(&self) -> &SocialForceParams {
        &self.params
    }

    /// Builds a crowd of walkers and standing people for a new episode, drawing the randomised
    /// parts from `rng`; people of other behaviours stand still at their pose (use
    /// [`Crowd::spawn_scripted`] with [`scripts::plan_scripts`] for them).
    pub fn spawn<R: Rng>(
        persons: &[Person],
        randomize: &Randomize,
        params: SocialForceParams,
        rng: &mut R,
    ) -> Self {
        let scripts: Vec<Script> = persons.iter().map(Script::basic).collect();
        Self::spawn_scripted(persons, &scripts, randomize, params, &[], rng)
    }

    /// Builds the crowd for a new episode with one planned script per person, drawing the
    /// randomised parts (walkers' route phase, visitors' first exhibit and dwell phase, speed
    /// jitter of everyone who walks) from `rng`. A walker's random start on its route is drawn
    /// again (up to [`SPAWN_TRIES`] times) while it lies within `keep_clear`'s discs (centre,
    /// radius in m) widened by the person's radius: the robots' start areas, so that no episode
    /// begins with a person on top of a robot.
    pub fn spawn_scripted<R: Rng>(
        persons: &[Person],
        scripts: &[Script],
        randomize: &Randomize,
        params: SocialForceParams,
        keep_clear: &[(Vec2, f64)],
        rng: &mut R,
    ) -> Self {
        let mut c = Crowd { params, ..Crowd::default() };
        for (p, script) in persons.iter().zip(scripts) {
            let route: Vec<Vec2> = p.route.iter().map(|w| Vec2::new(w[0], w[1])).collect();
            let walker = *script == Script::Walker;
            let jitter = randomize.speed_jitter;
            let speed = if *script != Script::Still && jitter > 0.0 {
                p.speed * rng.random_range(1.0 - jitter..=1.0 + jitter)
            } else {
                p.speed
            };
            let (mut task, mut clock) = (0, 0.0);
            let (pos, target, heading) = match script {
                Script::Walker if randomize.person_phase => {
                    let blocked = |q: Vec2| keep_clear.iter().any(|(c, r)| (q - c).norm() < r + p.radius);
                    let (mut pos, mut target) = point_at_fraction(&route, rng.random::<f64>());
                    for _ in 1..SPAWN_TRIES {
                        if !blocked(pos) {
                            break;
                        }
                        (pos, target) = point_at_fraction(&route, rng.random::<f64>());
                    }
                    let d = route[target] - pos;
                    (pos, target, d.y.atan2(d.x))
                }
                Script::Walker => (route[0], 1, p.pose[2]),
                Script::Program(prog) => {
                    let k = if randomize.person_phase && prog.starts.len() > 1 {
                        rng.random_range(0..prog.starts.len())
                    } else {
                        0
                    };
                    let (t, at) = prog.starts[k];
                    task = t;
                    let mut heading = p.pose[2];
                    if let Some(Task::Stay { face, until }) = prog.tasks.get(t) {
                        if let (Until::For(d), true) = (until, randomize.person_phase) {
                            clock = rng.random::<f64>() * d;
                        }
                        if let Face::Point(q) = face {
                            heading = (q.y - at.y).atan2(q.x - at.x);
                        }
                    }
                    (at, 0, heading)
                }
                Script::Follower { slots, .. } => {
                    let at = slots.first().copied().flatten().unwrap_or(Vec2::new(p.pose[0], p.pose[1]));
                    (at, 0, p.pose[2])
                }
                Script::RobotFollower { places, start, .. } => {
                    // Gathered behind the robot at its start, facing it.
                    let at = places.first().and_then(|p| p.first()).copied().unwrap_or(*start);
                    let d = start - at;
                    (at, usize::MAX, d.y.atan2(d.x))
                }
                Script::Guide { .. } => (route[0], 0, p.pose[2]),
                Script::Still => (Vec2::new(p.pose[0], p.pose[1]), 0, p.pose[2]),
            };
            c.script.push(script.clone());
            c.task.push(task);
            c.leg.push(0);
            c.clock.push(clock);
            c.stuck.push(0.0);
            c.gathered.push(matches!(script, Script::RobotFollower { .. }).then_some(0));
            c.pos.push(pos);
            c.vel.push(Vec2::zeros());
            c.heading.push(heading);
            c.radius.push(p.radius);
            c.group.push(p.group);
            c.speed.push(speed);
            c.target.push(target);
            c.dwell_left.push(0.0);
            c.routes.push(route);
            c.dwell.push(p.dwell);
            c.stops.push(if walker { p.stops.clone() } else { Vec::new() });
            c.walker.push(walker);
            c.aware.push(p.aware);
        }
        let mut ids: Vec<u32> = c.group.iter().flatten().copied().collect();
        ids.sort_unstable();
        ids.dedup();
        c.group_slot = vec![None; c.len()];
        let n = c.len();
        c.moving = vec![false; n];
        c.desired = vec![Vec2::zeros(); n];
        c.face_want = vec![None; n];
        for id in ids {
            // Walking groups: walkers. (Conversation members walk to their places at the same
            // time but without the group terms, whose coherence would pull them into the
            // o-space.)
            let members: Vec<usize> = (0..n).filter(|&k| c.group[k] == Some(id) && c.walker[k]).collect();
            if members.len() >= 2 {
                for &k in &members {
                    c.group_slot[k] = Some(c.groups.len());
                }
                c.groups.push(members);
            }
        }
        c
    }

    /// Advances every person by `dt` seconds (in whole steps of `params.dt`, the last one
    /// shortened). `robots` holds each robot's (centre, radius, velocity); aware people react to
    /// them. `geometry` is the static world.
    pub fn step(
        &mut self,
        dt: f64,
        robots: &[(Vec2, f64, Vec2)],
        geometry: &StaticGeometry,
        field: &DistanceField,
    ) {
        let mut left = dt;
        while left > 1e-12 {
            let h = left.min(self.params.dt);
            self.substep(h, robots, geometry, field);
            left -= h;
        }
    }

    fn substep(
        &mut self,
        h: f64,
        robots: &[(Vec2, f64, Vec2)],
        geometry: &StaticGeometry,
        field: &DistanceField,
    ) {
        let n = self.len();
        let p = self.params;
        // 1. Scripts: waypoints, dwelling, programs (from the snapshot, in index order).
        for i in 0..n {
            self.plan_step(i, h);
        }
        self.time += h;
        // 2. Forces from the snapshot (Jacobi).
        self.scratch.clear();
        self.scratch.resize(n, Vec2::zeros());
        let binned = n > BRUTE_FORCE_MAX;
        if binned {
            self.bins.rebuild(&self.pos, p.cutoff);
        }
        for i in 0..n {
            if !self.moving[i] {
                continue;
            }
            let (pi, vi) = (self.pos[i], self.vel[i]);
            let desired = self.desired[i];
            let mut f = (desired - vi) / p.tau;
            if binned {
                let mut acc = Vec2::zeros();
                self.bins.for_near(pi, |j| {
                    if j != i {
                        acc += interaction_force(pi, vi, self.pos[j], self.vel[j], &p);
                    }
                });
                f += acc;
            } else {
                for j in 0..n {
                    if j != i {
                        f += interaction_force(pi, vi, self.pos[j], self.vel[j], &p);
                    }
                }
            }
            if self.aware[i] {
                for &(c, _, v) in robots {
                    f += interaction_force(pi, vi, c, v, &p);
                }
            }
            let gap = field.at(pi) - self.radius[i];
            if gap < 1.0 {
                let g = field.gradient(pi);
                let gn = g.norm();
                if gn > 1e-9 {
                    f += g * (p.wall_strength * (-gap.max(0.0) / p.wall_range).exp() / gn);
                }
            }
            if let Some(slot) = self.group_slot[i] {
                f += self.group_force(i, slot);
            }
            self.scratch[i] = f;
        }
        // 3. Integrate (semi-implicit Euler), with the hard constraints.
        for i in 0..n {
            if !self.moving[i] {
                self.vel[i] = Vec2::zeros();
                if let Some(want) = self.face_want[i] {
                    let turn = wrap_angle(want - self.heading[i]).clamp(-TURN_RATE * h, TURN_RATE * h);
                    self.heading[i] = wrap_angle(self.heading[i] + turn);
                }
                continue;
            }
            let vmax = self.speed[i] * p.max_speed_factor;
            let mut v = self.vel[i] + self.scratch[i] * h;
            let s = v.norm();
            if s > vmax {
                v *= vmax / s;
            }
            if self.desired[i] == Vec2::zeros() && v.norm() < 0.05 {
                v = Vec2::zeros();
            }
            let next = self.pos[i] + v * h;
            let r = self.radius[i];
            // Exact test on the nearby edges only, where the distance field says obstacles are
            // near. People move a few centimetres per step, so a point inside a polygon is
            // necessarily within 0.5 r of its boundary first.
            let near_static = field.at(next) < r + field.spec.resolution;
            let blocked_static = near_static && geometry.boundary_distance_within(next, 0.5 * r) < 0.5 * r;
            // An aware person never steps to within YIELD_GAP of a robot's body, nor closer to a
            // robot it is already that near (it may step away).
            let here = self.pos[i];
            let blocked_robot = self.aware[i]
                && robots.iter().any(|&(c, rr, _)| {
                    let gap_next = (next - c).norm() - r - rr;
                    gap_next < YIELD_GAP && gap_next < (here - c).norm() - r - rr
                });
            if blocked_static || blocked_robot {
                self.vel[i] = Vec2::zeros();
            } else {
                self.vel[i] = v;
                self.pos[i] = next;
            }
            // Facing: the walking direction, else what the script attends to (for a dwelling
            // walker, the next leg's direction).
            let facing = if self.vel[i].norm() > 0.1 {
                Some(self.vel[i].y.atan2(self.vel[i].x))
            } else {
                self.face_want[i]
            };
            if let Some(want) = facing {
                let turn = wrap_angle(want - self.heading[i]).clamp(-TURN_RATE * h, TURN_RATE * h);
                self.heading[i] = wrap_angle(self.heading[i] + turn);
            }
        }
    }

    /// Advances person `i`'s script by `h` seconds and sets its motion for this substep:
    /// `moving`, `desired` (velocity) and `face_want`.
    fn plan_step(&mut self, i: usize, h: f64) {
        let arrival = self.params.arrival;
        let pos = self.pos[i];
        let toward = |q: Vec2, speed: f64| {
            let d = q - pos;
            let n = d.norm();
            if n > 1e-9 { d * (speed / n) } else { Vec2::zeros() }
        };
        let bearing = |q: Vec2| {
            let d = q - pos;
            (d.norm() > 1e-6).then(|| d.y.atan2(d.x))
        };
        self.moving[i] = true;
        self.face_want[i] = None;
        self.desired[i] = Vec2::zeros();
        // Taken out for the match (the arms update the other per-person arrays), put back below.
        let script = std::mem::replace(&mut self.script[i], Script::Still);
        match &script {
            Script::Still => self.moving[i] = false,
            Script::Walker => {
                if self.dwell_left[i] > 0.0 {
                    self.dwell_left[i] = (self.dwell_left[i] - h).max(0.0);
                } else if (self.routes[i][self.target[i]] - pos).norm() <= arrival {
                    let k = self.target[i];
                    self.target[i] = (k + 1) % self.routes[i].len();
                    let stop = self.stops[i].get(k).copied().unwrap_or(true);
                    self.dwell_left[i] = if stop { self.dwell[i] } else { 0.0 };
                }
                let next = self.routes[i][self.target[i]];
                if self.dwell_left[i] > 0.0 {
                    self.face_want[i] = bearing(next);
                } else {
                    self.desired[i] = toward(next, self.speed[i]);
                }
            }
            Script::Guide { stops, followers } => {
                if self.dwell_left[i] > 0.0 {
                    self.dwell_left[i] = (self.dwell_left[i] - h).max(0.0);
                } else if (self.routes[i][self.target[i]] - pos).norm() <= arrival {
                    let k = self.target[i];
                    self.target[i] = (k + 1) % self.routes[i].len();
                    self.dwell_left[i] = if stops[k] { self.dwell[i].max(h) } else { 0.0 };
                }
                if self.dwell_left[i] > 0.0 {
                    // At a stop: stand facing the followers.
                    self.moving[i] = false;
                    if !followers.is_empty() {
                        let c = followers.iter().fold(Vec2::zeros(), |a, &k| a + self.pos[k]);
                        self.face_want[i] = bearing(c / followers.len() as f64);
                    }
                } else {
                    self.desired[i] = toward(self.routes[i][self.target[i]], self.speed[i]);
                }
            }
            Script::Follower { guide, slots } => {
                let g = *guide;
                let n = slots.len();
                // The guide's place in its route: the stop it dwells at, or the waypoint it
                // walks to.
                let (at_stop, gk) = if self.dwell_left[g] > 0.0 {
                    (true, (self.target[g] + n - 1) % n)
                } else {
                    (false, self.target[g])
                };
                let f = self.target[i];
                if at_stop && (f == gk || self.gathered[i] == Some(gk)) {
                    let slot = slots[gk].unwrap_or(self.pos[g]);
                    if self.gathered[i] == Some(gk) || (slot - pos).norm() <= arrival {
                        // Gathered: stand facing the guide.
                        self.gathered[i] = Some(gk);
                        self.target[i] = (gk + 1) % n;
                        self.moving[i] = false;
                        self.face_want[i] = bearing(self.pos[g]);
                    } else {
                        self.desired[i] = toward(slot, self.speed[i]);
                    }
                } else if f == gk {
                    // Right behind the guide: follow it, waiting within a metre of it.
                    if (self.pos[g] - pos).norm() > 1.0 {
                        self.desired[i] = toward(self.pos[g], self.speed[i]);
                    }
                    self.face_want[i] = bearing(self.pos[g]);
                } else {
                    // Behind: walk the guide's route (its waypoints are clear of walls).
                    let q = self.routes[g][f];
                    if (q - pos).norm() <= 2.0 * arrival {
                        self.target[i] = (f + 1) % n;
                    }
                    self.desired[i] = toward(self.routes[g][self.target[i]], self.speed[i]);
                }
            }
            Script::RobotFollower { robot, start, places } => {
                let n = places.len();
                let guide =
                    robot.filter(|&j| j < self.trails.len()).and_then(|j| Some((j, *self.guides.get(j)?)));
                match guide {
                    // No robot to follow: wait at the place, facing the tour's start.
                    None => {
                        self.moving[i] = false;
                        self.face_want[i] = bearing(*start);
                    }
                    Some((j, g)) => {
                        // Taken out for the borrow checker, put back below.
                        let trail = std::mem::take(&mut self.trails[j]);
                        let gk = g.target.min(n - 1);
                        // Along the robot's trail, up to FOLLOW_GAP from it.
                        let mut k = self.leg[i];
                        while k < trail.len() && (trail[k] - pos).norm() <= TRAIL_REACHED {
                            k += 1;
                        }
                        // Caught up: the trail ahead ends at the robot, or it is this near (at a
                        // stop, within GATHER_REACH: the place on the arc is in reach).
                        let reach = if g.dwelling { GATHER_REACH } else { FOLLOW_GAP };
                        let caught_up = k >= trail.len()
                            || (trail[k] - g.pos).norm() <= FOLLOW_GAP
                            || (pos - g.pos).norm() <= reach;
                        // A place on the arc is claimed on arriving near the robot at a stop.
                        let slot = if g.dwelling && caught_up {
                            self.choose_place(i, *robot, &places[gk])
                        } else {
                            if !g.dwelling {
                                self.target[i] = usize::MAX; // walking: no place claimed
                            }
                            None
                        };
                        if self.gathered[i] == Some(gk) && g.dwelling {
                            // Gathered: stand facing the robot until it moves on.
                            self.moving[i] = false;
                            self.face_want[i] = bearing(g.pos);
                        } else if let (Some(slot), true) = (slot, caught_up) {
                            // The robot stands at a stop: take the place on its arc, or as near
                            // as the others let it get after 2 s within 1.5 m of it (but not
                            // within ROBOT_SPACE of the robot: from there it first steps out).
                            let d = (slot - pos).norm();
                            let away = pos - g.pos;
                            let near_robot = away.norm() < ROBOT_SPACE;
                            if d < 1.5 && self.vel[i].norm() < 0.1 && !near_robot {
                                self.stuck[i] += h;
                            } else {
                                self.stuck[i] = 0.0;
                            }
                            if d <= SLOT_REACHED || self.stuck[i] > 2.0 {
                                self.stuck[i] = 0.0;
                                self.gathered[i] = Some(gk);
                                k = trail.len(); // the way to here is behind
                                self.moving[i] = false;
                                self.face_want[i] = bearing(g.pos);
                            } else {
                                let mut dir = (slot - pos) / d;
                                if away.norm() < FOLLOW_GAP && away.norm() > 1e-9 {
                                    dir += away / away.norm(); // round the robot, not past it
                                }
                                self.desired[i] = toward(pos + dir, self.speed[i]);
                            }
                        } else if caught_up {
                            let away = pos - g.pos;
                            if away.norm() < ROBOT_SPACE && away.norm() > 1e-9 {
                                self.desired[i] = away * (0.5 * self.speed[i] / away.norm()); // step back
                            }
                            self.face_want[i] = bearing(g.pos);
                        } else {
                            self.desired[i] = toward(trail[k], self.speed[i]);
                        }
                        self.leg[i] = k;
                        self.trails[j] = trail;
                    }
                }
            }
            Script::Program(prog) => {
                let len = prog.tasks.len();
                // Finished tasks are skipped within the substep (bounded by one pass).
                for _ in 0..=len {
                    match &prog.tasks[self.task[i]] {
                        Task::Walk(path) => {
                            let leg = self.leg[i];
                            let q = path[leg];
                            let d = (q - pos).norm();
                            let last = leg + 1 == path.len();
                            // A destination taken by someone else counts as reached after 2 s
                            // of standing within a metre of it.
                            if last && d < 1.0 && self.vel[i].norm() < 0.1 {
                                self.stuck[i] += h;
                            } else {
                                self.stuck[i] = 0.0;
                            }
                            if d <= arrival || (last && self.stuck[i] > 2.0) {
                                self.leg[i] += 1;
                                if last {
                                    self.advance(i, len, prog.cyclic);
                                    continue;
                                }
                            }
                            self.desired[i] = toward(path[self.leg[i]], self.speed[i]);
                        }
                        Task::Stay { face, until } => {
                            let done = match until {
                                Until::For(d) => self.clock[i] >= *d,
                                Until::At(t) => self.time >= *t,
                                Until::Forever => false,
                            };
                            if done {
                                self.advance(i, len, prog.cyclic);
                                continue;
                            }
                            self.clock[i] += h;
                            self.moving[i] = false;
                            if let Face::Point(q) = face {
                                self.face_want[i] = bearing(*q);
                            }
                        }
                    }
                    break;
                }
            }
        }
        self.script[i] = script;
    }

    /// Moves person `i` to the next task of its program (`len` tasks).
    /// Follower `i`'s place on `places` (a robot's gathering arc at a tour stop): the one it
    /// claimed before, else one no other follower of the robot has claimed, the arc's ends first
    /// (the claim, an index into `places`, is kept in `target` while the robot stands there).
    fn choose_place(&mut self, i: usize, robot: Option<usize>, places: &[Vec2]) -> Option<Vec2> {
        if let Some(&q) = places.get(self.target[i]) {
            return Some(q);
        }
        let claimed = |c: &Crowd, place: usize| {
            (0..c.len()).any(|k| {
                k != i
                    && c.target[k] == place
                    && matches!(&c.script[k], Script::RobotFollower { robot: r, .. } if *r == robot)
            })
        };
        // The ends of the arc first (whoever comes later finds the places nearest the way in,
        // in the middle, free), the nearer of equal ones.
        let pos = self.pos[i];
        let mid = 0.5 * (places.len() as f64 - 1.0);
        let best = (0..places.len()).filter(|&k| !claimed(self, k)).min_by(|&a, &b| {
            let end = |k: usize| -(k as f64 - mid).abs();
            end(a).total_cmp(&end(b)).then((places[a] - pos).norm().total_cmp(&(places[b] - pos).norm()))
        });
        self.target[i] = best.unwrap_or(usize::MAX);
        best.map(|k| places[k])
    }

    fn advance(&mut self, i: usize, len: usize, cyclic: bool) {
        self.leg[i] = 0;
        self.clock[i] = 0.0;
        self.stuck[i] = 0.0;
        self.task[i] = if self.task[i] + 1 < len {
            self.task[i] + 1
        } else if cyclic {
            0
        } else {
            self.task[i]
        };
    }

    /// Moussaid et al. 2010 group terms for person `i` of the walking group in `slot`.
    fn group_force(&self, i: usize, slot: usize) -> Vec2 {
        let p = &self.params;
        let members = &self.groups[slot];
        let pi = self.pos[i];
        let mut f = Vec2::zeros();
        let others = members.iter().filter(|&&k| k != i).map(|&k| self.pos[k]);
        let c_others = others.clone().fold(Vec2::zeros(), |a, b| a + b) / (members.len() - 1) as f64;
        let walk = self.vel[i];
        if walk.norm() > 1e-6 {
            // Gaze: turn the walking direction toward the others (phi_v = 90 degrees).
            let to = c_others - pi;
            if to.norm() > 1e-9 {
                let alpha = wrap_angle(to.y.atan2(to.x) - walk.y.atan2(walk.x)).abs();
                let phi_v = std::f64::consts::FRAC_PI_2;
                if alpha > phi_v {
                    f -= walk.normalize() * (p.group_gaze * (alpha - phi_v));
                }
            }
        }
        // Coherence: toward the centre of all members beyond (|G| - 1) / 2 metres.
        let c_all = members.iter().fold(Vec2::zeros(), |a, &k| a + self.pos[k]) / members.len() as f64;
        let to = c_all - pi;
        if to.norm() > (members.len() as f64 - 1.0) / 2.0 {
            f += to.normalize() * p.group_coherence;
        }
        // Repulsion between members closer than d0.
        for q in others {
            let away = pi - q;
            let d = away.norm();
            if d < p.group_d0 && d > 1e-9 {
                f += away / d * p.group_repulsion;
            }
        }
        f
    }
}

/// The point at `frac` (in [0, 1)) of a closed route's length, and the index of the waypoint
/// that follows it.
/// Draws of a walker's start on its route before the last one is kept even if it is not clear
/// of the robots' start areas (see [`Crowd::spawn_scripted`]).
pub const SPAWN_TRIES: usize = 32;

fn point_at_fraction(route: &[Vec2], frac: f64) -> (Vec2, usize) {
    let n = route.len();
    let lens: Vec<f64> = (0..n).map(|k| (route[(k + 1) % n] - route[k]).norm()).collect();
    let total: f64 = lens.iter().sum();
    let mut s = frac.clamp(0.0, 1.0) * total;
    for k in 0..n {
        if s < lens[k] || k == n - 1 {
            let t = (s / lens[k].max(1e-12)).min(1.0);
            return (route[k] + (route[(k + 1) % n] - route[k]) * t, (k + 1) % n);
        }
        s -= lens[k];
    }
    (route[0], 1 % n)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::map::geometry::Bounds;
    use crate::map::grid::{GridSpec, OccupancyGrid};
    use crate::scenario::Behaviour;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn walker(route: &[[f64; 2]], speed: f64, dwell: f64) -> Person {
        Person {
            name: "p".into(),
            behaviour: Behaviour::Walker,
            pose: [route[0][0], route[0][1], 0.0],
            route: route.to_vec(),
            speed,
            dwell,
            radius: 0.2,
            height: 1.7,
            group: None,
            aware: true,
            features: vec![],
            ..Person::default()
        }
    }

    #[test]
    fn walkers_never_start_in_a_robot_start_area() {
        // A 10 m out-and-back route; the robot's start area covers its first 3 m (plus the
        // person's radius). Over many seeds no walker starts inside it, and without the area
        // some do (the check can fail).
        let persons = vec![walker(&[[0.0, 0.0], [10.0, 0.0]], 1.2, 0.0); 8];
        let scripts: Vec<Script> = persons.iter().map(Script::basic).collect();
        let random = Randomize { person_phase: true, speed_jitter: 0.0, robot_start_jitter: 0.0 };
        let area = [(Vec2::new(0.0, 0.0), 3.0)];
        let inside = |c: &Crowd| c.pos.iter().filter(|q| q.norm() < 3.0 + 0.2).count();
        let (mut with_area, mut without) = (0, 0);
        for seed in 0..50 {
            let spawn = |clear: &[(Vec2, f64)]| {
                let mut rng = ChaCha8Rng::seed_from_u64(seed);
                let params = SocialForceParams::default();
                Crowd::spawn_scripted(&persons, &scripts, &random, params, clear, &mut rng)
            };
            with_area += inside(&spawn(&area));
            without += inside(&spawn(&[]));
        }
        assert_eq!(with_area, 0);
        assert!(without > 50, "{without}");
    }

    fn fixed() -> Randomize {
        Randomize { person_phase: false, speed_jitter: 0.0, robot_start_jitter: 0.0 }
    }

    fn room() -> StaticGeometry {
        // 20 x 10 m room with 0.2 m walls.
        let b = Bounds { min: Vec2::new(-1.0, -1.0), max: Vec2::new(21.0, 11.0) };
        let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
            vec![Vec2::new(x0, y0), Vec2::new(x1, y0), Vec2::new(x1, y1), Vec2::new(x0, y1)]
        };
        StaticGeometry::new(
            vec![
                rect(-0.2, -0.2, 20.2, 0.0),
                rect(-0.2, 10.0, 20.2, 10.2),
                rect(-0.2, 0.0, 0.0, 10.0),
                rect(20.0, 0.0, 20.2, 10.0),
            ],
            b,
        )
        .expect("valid room")
    }

    struct Room {
        geom: StaticGeometry,
        field: DistanceField,
    }

    impl Room {
        fn step(&self, c: &mut Crowd, dt: f64, robots: &[(Vec2, f64, Vec2)]) {
            c.step(dt, robots, &self.geom, &self.field);
        }
    }

    fn room_with_field() -> Room {
        let geom = room();
        let spec = GridSpec::covering(geom.bounds(), 0.1).expect("valid grid");
        let field = DistanceField::from_occupancy(&OccupancyGrid::rasterize(&geom, spec));
        Room { geom, field }
    }

    fn spawn(persons: &[Person]) -> Crowd {
        Crowd::spawn(persons, &fixed(), SocialForceParams::default(), &mut ChaCha8Rng::seed_from_u64(0))
    }

    #[test]
    fn moussaid_known_answers() {
        // algorithms.md §4.4 (A = 4.5)
        let p = SocialForceParams { cutoff: 10.0, ..SocialForceParams::default() };
        let f = interaction_force(
            Vec2::zeros(),
            Vec2::new(1.3, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(-1.3, 0.0),
            &p,
        );
        assert!((f.x + 1.7904).abs() < 1e-4, "{f:?}");
        // exact symmetry: the passing convention adds a push to the right (negative y)
        assert!(f.y < 0.0);
        let f = interaction_force(
            Vec2::zeros(),
            Vec2::new(1.3, 0.0),
            Vec2::new(2.0, 0.3),
            Vec2::new(-1.3, 0.0),
            &p,
        );
        assert!((f.x + 0.8832).abs() < 1e-4 && (f.y + 1.3415).abs() < 1e-4, "{f:?}");
        let f = interaction_force(Vec2::zeros(), Vec2::new(1.3, 0.0), Vec2::new(1.0, 0.0), Vec2::zeros(), &p);
        assert!((f.x + 2.0349).abs() < 1e-4, "{f:?}");
    }

    #[test]
    fn lone_walker_relaxes_to_its_speed() {
        let room = room_with_field();
        let mut c = spawn(&[walker(&[[2.0, 5.0], [18.0, 5.0]], 1.2, 0.0)]);
        room.step(&mut c, 0.5, &[]);
        let v = c.vel[0].norm();
        // v(t) = v0 (1 - exp(-t / tau)) up to the Euler discretisation
        let want = 1.2 * (1.0 - (-1.0f64).exp());
        assert!((v - want).abs() < 0.05, "{v} vs {want}");
        room.step(&mut c, 3.0, &[]);
        assert!((c.vel[0].norm() - 1.2).abs() < 0.01);
        assert!((c.heading[0]).abs() < 1e-6);
    }

    #[test]
    fn walkers_follow_their_routes_and_dwell() {
        let room = room_with_field();
        let mut c = spawn(&[walker(&[[2.0, 2.0], [8.0, 2.0], [8.0, 8.0]], 1.0, 3.0)]);
        let mut reached_second = false;
        let mut dwelt = 0;
        for _ in 0..400 {
            room.step(&mut c, 0.1, &[]);
            if (c.pos[0] - Vec2::new(8.0, 2.0)).norm() < 0.35 {
                reached_second = true;
                if c.vel[0].norm() < 1e-9 {
                    dwelt += 1;
                }
            }
        }
        assert!(reached_second);
        assert!(dwelt >= 20, "dwelt {dwelt} steps");
    }

    #[test]
    fn walkers_dwell_only_at_their_stops() {
        let room = room_with_field();
        let mut w = walker(&[[2.0, 2.0], [8.0, 2.0], [8.0, 8.0]], 1.0, 3.0);
        w.stops = vec![false, false, true];
        let mut c = spawn(&[w]);
        let (mut still_at_corner, mut still_at_stop) = (0, 0);
        for _ in 0..400 {
            room.step(&mut c, 0.1, &[]);
            let still = c.vel[0].norm() < 1e-9;
            if still && (c.pos[0] - Vec2::new(8.0, 2.0)).norm() < 0.35 {
                still_at_corner += 1;
            }
            if still && (c.pos[0] - Vec2::new(8.0, 8.0)).norm() < 0.35 {
                still_at_stop += 1;
            }
        }
        assert_eq!(still_at_corner, 0, "dwelt at a waypoint that is not a stop");
        assert!(still_at_stop >= 20, "dwelt {still_at_stop} steps at the stop");
    }

    #[test]
    fn nobody_enters_the_walls_in_a_crowded_long_run() {
        let room = room_with_field();
        let mut persons = Vec::new();
        for k in 0..30 {
            let y = 0.5 + (k % 10) as f64 * 0.9;
            let (a, b) = if k % 2 == 0 { ([1.0, y], [19.0, 9.5 - y]) } else { ([19.0, y], [1.0, 9.5 - y]) };
            persons.push(walker(&[a, b], 1.0 + 0.01 * k as f64, 0.0));
        }
        let mut c = Crowd::spawn(
            &persons,
            &Randomize::default(),
            SocialForceParams::default(),
            &mut ChaCha8Rng::seed_from_u64(3),
        );
        for _ in 0..1200 {
            room.step(&mut c, 0.1, &[]);
            for (i, q) in c.pos.iter().enumerate() {
                assert!(!room.geom.contains(*q), "person {i} inside the walls at {q:?}");
                assert!(room.geom.distance(*q) >= 0.5 * c.radius[i] - 1e-9);
            }
        }
    }

    #[test]
    fn head_on_walkers_pass_on_their_right() {
        let room = room_with_field();
        let mut c = spawn(&[
            walker(&[[2.0, 5.0], [18.0, 5.0]], 1.2, 0.0),
            walker(&[[18.0, 5.0], [2.0, 5.0]], 1.2, 0.0),
        ]);
        let mut min_d = f64::INFINITY;
        for _ in 0..80 {
            room.step(&mut c, 0.1, &[]);
            min_d = min_d.min((c.pos[0] - c.pos[1]).norm());
        }
        assert!(min_d > 0.4, "they collided: {min_d}");
        // walker 0 heads +x: its right is -y; walker 1 heads -x: its right is +y.
        assert!(c.pos[0].y < 5.0 && c.pos[1].y > 5.0, "{:?}", c.pos);
    }

    #[test]
    fn aware_walker_goes_around_a_standing_robot_and_oblivious_does_not_avoid_it() {
        let room = room_with_field();
        let robot = [(Vec2::new(8.0, 5.0), 0.24, Vec2::zeros())];
        let mut p = walker(&[[2.0, 5.0], [16.0, 5.0]], 1.0, 0.0);
        let mut c = spawn(std::slice::from_ref(&p));
        let mut min_gap = f64::INFINITY;
        for _ in 0..200 {
            room.step(&mut c, 0.1, &robot);
            min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
        }
        assert!(min_gap >= YIELD_GAP - 1e-9, "gap {min_gap}");
        assert!(c.pos[0].x > 10.0, "stuck behind the robot at {:?}", c.pos[0]);
        p.aware = false;
        let mut c = spawn(&[p]);
        let mut min_gap = f64::INFINITY;
        for _ in 0..200 {
            room.step(&mut c, 0.1, &robot);
            min_gap = min_gap.min((c.pos[0] - robot[0].0).norm() - 0.44);
        }
        assert!(min_gap < 0.0);
    }

    #[test]
    fn walking_group_stays_together() {
        let room = room_with_field();
        let mut a = walker(&[[2.0, 4.5], [18.0, 4.5]], 1.0, 0.0);
        let mut b = walker(&[[2.0, 5.5], [18.0, 5.5]], 1.2, 0.0);
        a.group = Some(1);
        b.group = Some(1);
        let mut c = spawn(&[a, b]);
        for _ in 0..100 {
            room.step(&mut c, 0.1, &[]);
            assert!((c.pos[0] - c.pos[1]).norm() < 2.0);
        }
    }

    #[test]
    fn same_seed_same_crowd_bit_for_bit() {
        let room = room_with_field();
        let persons: Vec<Person> =
            (0..12).map(|k| walker(&[[1.0 + k as f64, 1.0], [18.0 - k as f64, 9.0]], 1.0, 1.0)).collect();
        let run = |seed| {
            let mut c = Crowd::spawn(
                &persons,
                &Randomize::default(),
                SocialForceParams::default(),
                &mut ChaCha8Rng::seed_from_u64(seed),
            );
            for _ in 0..300 {
                room.step(&mut c, 0.1, &[]);
            }
            c.pos.iter().flat_map(|p| [p.x.to_bits(), p.y.to_bits()]).collect::<Vec<u64>>()
        };
        assert_eq!(run(4), run(4));
        assert_ne!(run(4), run(5));
    }

    #[test]
    fn standing_person_stays() {
        let room = room_with_field();
        let p = Person {
            name: "s".into(),
            behaviour: Behaviour::Standing,
            pose: [3.0, 2.0, 1.0],
            route: vec![],
            speed: 1.0,
            dwell: 0.0,
            radius: 0.2,
            height: 1.7,
            group: None,
            aware: true,
            features: vec![],
            ..Person::default()
        };
        let mut c = spawn(&[p]);
        room.step(&mut c, 1.0, &[]);
        assert_eq!(c.pos[0], Vec2::new(3.0, 2.0));
        assert_eq!(c.heading[0], 1.0);
    }

    #[test]
    fn random_phase_is_on_the_route_and_seeded() {
        let p = walker(&[[0.0, 0.0], [4.0, 0.0], [4.0, 3.0]], 1.0, 0.0);
        let r = Randomize::default();
        let sp = SocialForceParams::default();
        let a = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(7));
        let b = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(7));
        let c = Crowd::spawn(std::slice::from_ref(&p), &r, sp, &mut ChaCha8Rng::seed_from_u64(8));
        assert_eq!(a.pos, b.pos);
        assert_ne!(a.pos, c.pos);
        let q = a.pos[0];
        let on = (q.y.abs() < 1e-9 && (0.0..=4.0).contains(&q.x))
            || ((q.x - 4.0).abs() < 1e-9 && (0.0..=3.0).contains(&q.y))
            || ((q.y - 0.75 * q.x).abs() < 1e-9);
        assert!(on, "{q:?}");
    }
}
