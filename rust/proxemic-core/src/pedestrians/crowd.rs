//! The crowd as a structure of arrays, its neighbour bins, and the stepping: every substep plans
//! each person's motion from its script, sums the forces from a snapshot (Jacobi), and integrates
//! them under the hard constraints.

use super::force::interaction_term;
use super::scripts::Script;
use super::{ReactionParams, SocialForceParams, TRAIL_SPACING, TURN_RATE, interaction_force};
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::math::{Vec2, wrap_angle};
use crate::scenario::Reaction;

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
    /// Whether each person is in the scene (false for a replayed person before its track's
    /// first sample and after its last: it is then parked far away, see
    /// [`super::replay::parked_at`]).
    pub present: Vec<bool>,
    /// Replayed people: whether they react to a robot (walk with the forces).
    pub(super) reacting: Vec<bool>,
    pub(super) speed: Vec<f64>,
    pub(super) target: Vec<usize>,
    pub(super) dwell_left: Vec<f64>,
    pub(super) routes: Vec<Vec<Vec2>>,
    pub(super) dwell: Vec<f64>,
    /// Walkers: whether they dwell at each waypoint (empty: at every one).
    pub(super) stops: Vec<Vec<bool>>,
    pub(super) walker: Vec<bool>,
    /// Each person's reaction to robots, how far it may shift aside when standing (m), where it
    /// stood before shifting, and its curiosity left (s); see [`super::react`].
    pub(super) reaction: Vec<Reaction>,
    pub(super) shift: Vec<f64>,
    pub(super) anchor: Vec<Option<Vec2>>,
    /// Per substep: the robot (index) a person squeezes past and the hard gap it keeps to it
    /// then (m); see `pedestrians::react`.
    pub(super) squeeze: Vec<Option<(usize, f64)>>,
    pub(super) curious_left: Vec<f64>,
    pub(super) react_params: ReactionParams,
    pub(super) params: SocialForceParams,
    pub(super) scratch: Vec<Vec2>,
    /// Each person's script, and its program state: task, waypoint within a walk, time in the
    /// current stay, time stuck near a destination; for followers, the stop last gathered at.
    pub(super) script: Vec<Script>,
    pub(super) task: Vec<usize>,
    pub(super) leg: Vec<usize>,
    pub(super) clock: Vec<f64>,
    pub(super) stuck: Vec<f64>,
    pub(super) gathered: Vec<Option<usize>>,
    /// Per substep: whether the person moves (else it stands still, not pushable), its desired
    /// velocity, and the heading it turns to when not walking.
    pub(super) moving: Vec<bool>,
    pub(super) desired: Vec<Vec2>,
    pub(super) face_want: Vec<Option<f64>>,
    /// Seconds since the spawn.
    pub(super) time: f64,
    /// Members of each walking group (index lists), and each person's group slot.
    pub(super) groups: Vec<Vec<usize>>,
    pub(super) group_slot: Vec<Option<usize>>,
    /// Neighbour bins (rebuilt every substep for large crowds).
    pub(super) bins: NeighbourBins,
    /// The robots as their tours' followers see them (see [`Crowd::set_guides`]), and each
    /// robot's trail: where it went, a point every [`TRAIL_SPACING`] metres.
    pub(super) guides: Vec<GuideState>,
    pub(super) trails: Vec<Vec<Vec2>>,
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

/// Uniform grid of people for the neighbour search (cell = cutoff); used above
/// [`BRUTE_FORCE_MAX`] people.
#[derive(Clone, Debug, Default)]
pub(super) struct NeighbourBins {
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
    /// Bins the people at `pos` who are `present` (absent people are left out).
    fn rebuild(&mut self, pos: &[Vec2], present: &[bool], cell: f64) {
        let (mut lo, mut hi) =
            (Vec2::new(f64::INFINITY, f64::INFINITY), Vec2::new(f64::NEG_INFINITY, f64::NEG_INFINITY));
        let here = |i: usize| present.get(i).copied().unwrap_or(true);
        for p in pos.iter().enumerate().filter(|(i, _)| here(*i)).map(|(_, p)| p) {
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
        for p in pos.iter().enumerate().filter(|(i, _)| here(*i)).map(|(_, p)| p) {
            let k = self.key(*p);
            self.start[k + 1] += 1;
        }
        for c in 0..cells {
            self.start[c + 1] += self.start[c];
        }
        let mut fill = self.start.clone();
        self.items.clear();
        self.items.resize(self.start[cells], 0);
        for (i, p) in pos.iter().enumerate().filter(|(i, _)| here(*i)) {
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

    /// Advances every person by `dt` seconds (in whole steps of `params.dt`, the last one
    /// shortened). `robots` holds each robot's (centre, radius, velocity); people react to them
    /// by their [`Reaction`] (`pedestrians::react`). `geometry` is the static world.
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

    /// One substep of `h` seconds: scripts, forces from the snapshot, integration.
    fn substep(
        &mut self,
        h: f64,
        robots: &[(Vec2, f64, Vec2)],
        geometry: &StaticGeometry,
        field: &DistanceField,
    ) {
        let n = self.len();
        // 1. Scripts: waypoints, dwelling, programs (from the snapshot, in index order).
        for i in 0..n {
            self.plan_step(i, h, robots);
            if !robots.is_empty() {
                self.react(i, h, robots, geometry);
            }
        }
        self.time += h;
        // 2. Forces from the snapshot (Jacobi).
        self.sum_forces(robots, field);
        // 3. Integrate (semi-implicit Euler), with the hard constraints.
        self.integrate(h, robots, geometry, field);
        // 4. Replayed people on their tracks at the new time (or parked while absent).
        self.place_replays();
    }

    /// The force on every moving person from the snapshot (into `scratch`): driving, other
    /// people, robots (all but `ignore` people), walls and furniture, walking group.
    fn sum_forces(&mut self, robots: &[(Vec2, f64, Vec2)], field: &DistanceField) {
        let n = self.len();
        let p = self.params;
        self.scratch.clear();
        self.scratch.resize(n, Vec2::zeros());
        let binned = n > BRUTE_FORCE_MAX;
        if binned {
            self.bins.rebuild(&self.pos, &self.present, p.cutoff);
        }
        for i in 0..n {
            if !self.moving[i] {
                continue;
            }
            let (pi, vi) = (self.pos[i], self.vel[i]);
            let desired = self.desired[i];
            let mut f = (desired - vi) / p.tau;
            // The zero terms (people beyond the cutoff, most of them) are skipped. Adding +0.0
            // changes nothing but a -0.0 into +0.0: `acc` starts at +0.0 and so never holds a
            // -0.0, and for `f` one addition of zero after its loop (if a term was skipped) does
            // what they did. The sums are the same bit for bit.
            if binned {
                let mut acc = Vec2::zeros();
                self.bins.for_near(pi, |j| {
                    if j != i
                        && let Some(t) = interaction_term(pi, vi, self.pos[j], self.vel[j], &p)
                    {
                        acc += t;
                    }
                });
                f += acc;
            } else {
                let mut skipped = false;
                for j in 0..n {
                    if j != i {
                        match interaction_term(pi, vi, self.pos[j], self.vel[j], &p) {
                            Some(t) => f += t,
                            None => skipped = true,
                        }
                    }
                }
                if skipped {
                    f += Vec2::zeros();
                }
            }
            if self.reaction[i] != Reaction::Ignore {
                for (k, &(c, rr, v)) in robots.iter().enumerate() {
                    match self.squeeze[i] {
                        Some((j, hard)) if j == k => {
                            // Squeezing past the robot (`pedestrians::react`): its body repels
                            // as a wall does, across the person's way (a round body would also
                            // push it back), and only nearer than the middle of the gap (twice
                            // the squeezing hard gap).
                            let (away, s) = (pi - c, desired.norm());
                            let d = away.norm();
                            let gap = d - rr - self.radius[i];
                            if d > 1e-9 && s > 1e-9 && gap < 2.0 * hard {
                                let u = desired / s;
                                let a =
                                    (away - u * away.dot(&u)).try_normalize(1e-9).unwrap_or(Vec2::zeros());
                                f += a * (p.wall_strength * (-gap.max(0.0) / p.wall_range).exp());
                            }
                        }
                        _ => f += interaction_force(pi, vi, c, v, &p),
                    }
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
    }

    /// Moves every person by `h` seconds of its force (speed capped), cancelling steps into the
    /// static geometry or too near a robot (all but `ignore` people), and turns it.
    fn integrate(
        &mut self,
        h: f64,
        robots: &[(Vec2, f64, Vec2)],
        geometry: &StaticGeometry,
        field: &DistanceField,
    ) {
        let n = self.len();
        let p = self.params;
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
            // A reacting person never steps to within its hard gap of a robot's body, nor closer
            // to a robot it is already that near (it may step away).
            let here = self.pos[i];
            let squeeze = self.squeeze[i];
            let blocked_robot = self.react_params.hard(self.reaction[i]).is_some_and(|hard| {
                robots.iter().enumerate().any(|(k, &(c, rr, _))| {
                    let hard = match squeeze {
                        Some((j, g)) if j == k => hard.min(g),
                        _ => hard,
                    };
                    let gap_next = (next - c).norm() - r - rr;
                    gap_next < hard && gap_next < (here - c).norm() - r - rr
                })
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
}
