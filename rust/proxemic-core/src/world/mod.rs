//! The world: ties scenario, map, planners, pedestrians and metrics together.
//!
//! The Python env owns the physics. Python makes one binding call per control step
//! (`World.step`), in which the binding runs three parts:
//! 1. [`World::command`]: turns the policies' normalised actions into limited robot-frame
//!    commands; robots without an action (NaN) keep their built-in planner's command, computed
//!    at the end of the previous step;
//! 2. a call back into Python, where MuJoCo executes the commands and the people's poses and
//!    steps the physics (the GIL is held only here);
//! 3. [`World::step`] with the robots' new poses, velocities and contact flags, which in order:
//!    moves the people to the same instant and logs the scene's ground truth (groups,
//!    interactions, object activities); advances the robots' tours ([`tours`]); records each
//!    running robot's metrics and computes its outcome, reward terms ([`reward`]) and flags;
//!    builds the observations ([`observe`]); runs each robot's built-in planner for the next
//!    command ([`planners`], which dispatches to [`crate::control`]); and writes the people's
//!    poses and the contact hints.
//!
//! All outputs are written into caller-owned buffers: one `f64` buffer of one row of
//! [`Layout::stride`] values per robot, laid out as described by [`Layout`], and a
//! `(people, PERSON_OUT)` buffer of the people's poses and contact hints. No output array is
//! allocated per step, but the core's step does allocate small working vectors (the people's
//! guides, the local planners' views of the people and robots, ORCA's agents).
//!
//! Files: [`layout`] (the output row), [`reward`] (reward terms and each robot's record of the
//! step), [`observe`] (observations and the people buffer), [`tours`], `build` (construction
//! and its checks), `access` (accessors and queries), [`planners`] (the built-in planners'
//! bookkeeping and dispatch to [`crate::control`]), `stop` (the `astar_stop` planner's step), [`batch`] (several worlds stepped in one call,
//! in parallel threads).

mod access;
pub mod batch;
mod build;
pub mod crowdnav;
mod daza;
pub mod kinematic;
pub mod layout;
pub mod observe;
pub mod planners;
mod recovery;
pub mod reward;
mod stop;
pub mod tours;
mod yield_step;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::control::eband::{EbandParams, ElasticBand};
use crate::control::mode_switch::{Mode, ModeSwitchParams};
use crate::control::orca::{ObstacleSet, Orca};
use crate::control::progress::ProgressMonitor;
use crate::control::stop_and_wait::StopAndWait;
use crate::control::{Drive, FollowerParams, Limits, PathFollower, body_command, body_to_world};
use crate::error::{CoreError, Result};
use crate::map::CostGrid;
use crate::map::geometry::StaticGeometry;
use crate::map::grid::DistanceField;
use crate::map::lidar::Scanner;
use crate::math::{Vec2, wrap_angle};
use crate::metrics::{
    EpisodeRecorder, InteractionLink, InteractionObject, OSpace, Outcome, RecorderSetup, SceneLog, Snapshot,
};
use crate::pedestrians::scripts::Script;
use crate::pedestrians::{Crowd, GuideState, RobotFree, SocialForceParams};
use crate::plan::PathPlanner;
use crate::plan::geodesic::GoalField;
use crate::plan::social::{SocialPath, SocialPlanning};
use crate::scenario::{PlannerKind, Scenario};

pub use build::START_CLEARANCE;
pub use layout::{Layout, Section};
pub use observe::{
    CONTACT_RANGE, OBS_MAX_ANGULAR, OBS_MAX_SPEED, PEER_FEATURES, PERSON_FEATURES, PERSON_OUT, ROBOT_FEATURES,
};
use planners::plan_path;
pub use reward::{PERSONAL_ZONE, REWARD_TERMS, RewardTerms};

/// Per-robot state that does not change between episodes.
struct RobotStatic {
    planner: PlannerKind,
    /// The elastic band's parameters (eband planner only).
    eband: EbandParams,
    /// For approach tasks, the point to face near the goal (the person approached).
    face: Option<Vec2>,
    limits: Limits,
    /// How the base moves: a differential drive's commands are turned into `(v, wz)` along the
    /// heading ([`Limits::unicycle_from_holonomic`]).
    drive: crate::control::Drive,
    /// The velocities it can track, for a robot running NH-ORCA (a differential `astar_orca`
    /// robot, [`planners::nh_orca`]); `None` otherwise.
    nh_set: Option<crate::control::orca::nonholonomic::TrackableSet>,
    radius: f64,
    goal: Vec2,
    grid_index: usize,
    /// The targets in order: the waypoints of a tour, then the goal (just the goal otherwise).
    route: Vec<Vec2>,
    /// The geodesic distance field of each target of `route`.
    fields: Vec<GoalField>,
    /// Seconds the robot stands at each waypoint (0: it passes through).
    dwell: f64,
    /// Geodesic length from the nominal start through the route (m).
    geodesic_from_start: f64,
    /// The plain A* path from the nominal start to the first target (cached: the start only
    /// changes with jitter).
    nominal_path: Vec<Vec2>,
    /// The plain A* paths between consecutive targets (`legs[k]` from target k to k + 1).
    legs: Vec<Vec<Vec2>>,
}

/// Per-robot state of the running episode.
struct RobotRuntime {
    pose: [f64; 3],
    velocity: Vec2,
    wz: f64,
    /// Last executed command, world frame.
    exec_v: Vec2,
    exec_wz: f64,
    /// The built-in planner's proposed command, world frame.
    proposed_v: Vec2,
    proposed_wz: f64,
    follower: PathFollower,
    /// The episode's recording, from which the metrics are computed.
    recorder: EpisodeRecorder,
    outcome: Outcome,
    geodesic: f64,
    user_command: bool,
    /// The social path (social planners only) and when it was last planned.
    social_path: Option<SocialPath>,
    last_plan_step: usize,
    /// Cells expanded by the robot's last social search (kept or not; 0 before the first and
    /// after one that found nothing): sets the refresh period.
    last_search_cells: usize,
    /// Social searches run this episode (the first plan, re-plans and refreshes, kept or not).
    searches: usize,
    replans: usize,
    /// The elastic band (eband planner only).
    band: Option<ElasticBand>,
    mode: Mode,
    /// Index in the route of the current target.
    leg: usize,
    /// Whether the robot stands at its current target (a tour stop), and for how much longer (s).
    dwelling: bool,
    dwell_left: f64,
    /// The progress monitor ([`crate::control::progress`]).
    progress: ProgressMonitor,
    /// Whether the command computed for the next step follows a held recovery path (recorded
    /// with that step, for the recovery metrics).
    recovering: bool,
    /// The stop-and-wait rule's state (astar_stop planner only).
    stop: StopAndWait,
}

/// A cost grid shared by all robots with the same inflation radius.
struct InflatedGrid {
    radius: f64,
    grid: CostGrid,
}

/// The simulated world of one scenario.
pub struct World {
    scenario: Scenario,
    geometry: StaticGeometry,
    /// Distance from every cell to the static geometry (for the people's wall forces).
    field: DistanceField,
    /// The social model, maps and global planner.
    social: SocialPlanning,
    /// Local planners.
    control: ModeSwitchParams,
    orca: Orca,
    obstacles: ObstacleSet,
    grids: Vec<InflatedGrid>,
    statics: Vec<RobotStatic>,
    robots: Vec<RobotRuntime>,
    crowd: Crowd,
    /// Each person's behaviour script, planned once on the static map.
    scripts: Vec<Script>,
    planner: PathPlanner,
    layout: Layout,
    rng: ChaCha8Rng,
    /// The seed of the running episode (names it in an invariant's error).
    seed: u64,
    steps: usize,
    started: bool,
    scratch_people: Vec<(f64, usize)>,
    scratch_discs: Vec<(Vec2, f64)>,
    /// The `learned` planner's policy, once a robot runs it ([`crate::control::learned::shipped`]).
    learned: Option<&'static crate::control::learned::LearnedPolicy>,
    /// Per robot, its lidar (buffers, and the static part of its last scan).
    scanners: Vec<Scanner>,
    /// Per robot, whether its episode had ended before the current step (its observation is
    /// then no longer updated).
    ended: Vec<bool>,
    /// Per robot: whether its built-in planner runs (see [`World::set_planning`]).
    planning: Vec<bool>,
    /// The objects with an interaction space (metrics: person-object interactions, object
    /// spaces), in the order of the social planner's object names.
    interaction_objects: Vec<InteractionObject>,
    /// The current instant's ground-truth o-spaces, interactions and object activities.
    now: GroundTruth,
    /// The scene since the reset, for every robot's metrics.
    log: SceneLog,
    /// The episode's people replayed without the robots (the robot's cost to people), stepped
    /// lazily when the metrics are asked for (behind a lock: [`World::episode_metrics`] takes
    /// `&self`).
    robot_free: std::sync::Mutex<RobotFree>,
    /// Wall-clock time spent stepping the people this episode (to compare with the robot-free
    /// run's, [`World::people_step_times`]).
    crowd_time: std::time::Duration,
}

/// The ground truth of one instant that the metrics need: the groups' o-spaces, the interaction
/// segments and, per object with an interaction space, whether its activity is on.
#[derive(Clone, Debug, Default)]
struct GroundTruth {
    ospaces: Vec<OSpace>,
    links: Vec<InteractionLink>,
    active: Vec<bool>,
}

impl GroundTruth {
    /// This instant among `crowd`, for the scene log.
    fn snapshot<'a>(&'a self, crowd: &'a Crowd) -> Snapshot<'a> {
        Snapshot {
            positions: &crowd.pos,
            velocities: &crowd.vel,
            headings: &crowd.heading,
            present: &crowd.present,
            ospaces: &self.ospaces,
            links: &self.links,
            active: &self.active,
        }
    }
}

impl World {
    /// Checks the sizes of the `out` and `people_out` buffers.
    fn check_out(&self, out: &[f64], people_out: &[f64]) -> Result<()> {
        let want = self.layout.stride * self.num_robots();
        if out.len() != want {
            return Err(CoreError::input(
                "out",
                format!("{want} values ({} robots x {})", self.num_robots(), self.layout.stride),
                format!("{} values", out.len()),
            ));
        }
        let want_p = self.num_people() * PERSON_OUT;
        if people_out.len() != want_p {
            return Err(CoreError::input(
                "people_out",
                format!("{want_p} values ({} people x {PERSON_OUT})", self.num_people()),
                format!("{} values", people_out.len()),
            ));
        }
        Ok(())
    }

    /// Starts a new episode from `seed`: respawns the people, places the robots (with the
    /// scenario's start jitter), plans their paths and fills `out` (observations at the start,
    /// the first planner command, the start poses in `pose`) and `people_out` ([`PERSON_OUT`]
    /// values per person).
    pub fn reset(&mut self, seed: u64, out: &mut [f64], people_out: &mut [f64]) -> Result<()> {
        self.check_out(out, people_out)?;
        self.rng = ChaCha8Rng::seed_from_u64(seed);
        self.seed = seed;
        let clear = self.start_areas();
        self.crowd = Crowd::spawn_scripted(
            &self.scenario.persons,
            &self.scripts,
            &self.scenario.episode.randomize,
            SocialForceParams::default(),
            &clear,
            &mut self.rng,
        );
        self.steps = 0;
        // The last episode's recorders are restarted (their buffers keep their memory).
        let mut recorders: Vec<Option<EpisodeRecorder>> =
            self.robots.drain(..).map(|r| Some(r.recorder)).collect();
        self.observe_interactions();
        self.log.restart(&self.crowd.radius);
        self.log.push(&self.now.snapshot(&self.crowd));
        *self.robot_free.get_mut().unwrap_or_else(std::sync::PoisonError::into_inner) =
            RobotFree::new(&self.crowd, self.statics.len(), self.scenario.control_dt());
        self.crowd_time = std::time::Duration::ZERO;
        for i in 0..self.statics.len() {
            let robot = self.start_robot(i, recorders.get_mut(i).and_then(Option::take));
            self.robots.push(robot);
        }
        self.started = true;
        self.ended.fill(false);
        self.start_planners()?;
        let stride = self.layout.stride;
        for i in 0..self.robots.len() {
            let row = &mut out[i * stride..(i + 1) * stride];
            row.fill(0.0);
        }
        self.observe_all(out);
        self.plan_all(out);
        self.write_people(out, people_out);
        Ok(())
    }

    /// Robot `i` at the start of an episode: its start (the nominal one moved by the start
    /// jitter, drawn until clear of the static geometry), its plain path, and its metrics'
    /// recorder (`recorder`, the last episode's, restarted, or a new one).
    fn start_robot(&mut self, i: usize, recorder: Option<EpisodeRecorder>) -> RobotRuntime {
        let jitter = self.scenario.episode.randomize.robot_start_jitter;
        let r = &self.scenario.robots[i];
        let nominal = Vec2::new(r.start[0], r.start[1]);
        let mut start = nominal;
        if jitter > 0.0 {
            // Draw until the jittered start is clear of the static geometry (bounded tries).
            for _ in 0..16 {
                let c = nominal
                    + Vec2::new(
                        self.rng.random_range(-jitter..=jitter),
                        self.rng.random_range(-jitter..=jitter),
                    );
                if !self.geometry.contains(c) && self.geometry.distance(c) >= self.statics[i].radius {
                    start = c;
                    break;
                }
            }
        }
        let st = &self.statics[i];
        let path = if start == nominal {
            st.nominal_path.clone()
        } else {
            let grid = &self.grids[st.grid_index].grid;
            plan_path(&mut self.planner, grid, start, st.route[0]).unwrap_or_else(|| st.nominal_path.clone())
        };
        let pose = [start.x, start.y, wrap_angle(r.start[2])];
        let geodesic = st.fields[0].distance(start);
        // The reference path and length of a tour run through its waypoints.
        let mut astar_path = path.clone();
        let mut geodesic_length = geodesic;
        for (k, leg) in st.legs.iter().enumerate() {
            astar_path.extend_from_slice(&leg[1..]);
            geodesic_length += st.fields[k + 1].distance(st.route[k]);
        }
        let setup = RecorderSetup {
            dt: self.scenario.control_dt(),
            robot_radius: st.radius,
            goal: st.goal,
            success_radius: self.scenario.episode.success_radius,
            astar_path,
            geodesic_length,
            episode: format!("{}, seed {}, robot {i}", self.scenario.scene.name, self.seed),
        };
        let recorder = match recorder {
            Some(mut r) => {
                r.restart(setup, pose);
                r
            }
            None => EpisodeRecorder::new(setup, pose),
        };
        RobotRuntime {
            pose,
            velocity: Vec2::zeros(),
            wz: 0.0,
            exec_v: Vec2::zeros(),
            exec_wz: 0.0,
            proposed_v: Vec2::zeros(),
            proposed_wz: 0.0,
            follower: PathFollower::new(path, FollowerParams::default()),
            recorder,
            outcome: Outcome::Running,
            geodesic,
            user_command: false,
            social_path: None,
            last_plan_step: 0,
            last_search_cells: 0,
            searches: 0,
            replans: 0,
            band: None,
            mode: Mode::FollowPath,
            leg: 0,
            dwelling: false,
            dwell_left: 0.0,
            progress: ProgressMonitor::new(r.progress, geodesic, start),
            recovering: false,
            stop: StopAndWait::new(),
        }
    }

    /// The planners' state at the start of an episode: the elastic bands, and the first social
    /// paths (with the people as perceived at the start).
    fn start_planners(&mut self) -> Result<()> {
        if self.learned.is_none() && self.statics.iter().any(|st| st.planner == PlannerKind::Learned) {
            let policy = crate::control::learned::shipped()?;
            let lay = self.layout;
            let subgoal = if policy.subgoal() > 0.0 { 2 } else { 0 };
            let inputs = lay.obs_lidar.len
                + lay.obs_people.len
                + lay.obs_people_mask.len
                + lay.obs_robot.len
                + subgoal;
            if policy.inputs() != inputs {
                return Err(CoreError::input(
                    "planner learned: sensors",
                    format!(
                        "the observation the shipped policy was trained on ({} values: lidar_rays 72, k_nearest 8)",
                        policy.inputs()
                    ),
                    format!("{inputs} values from this scenario's [sensors]"),
                ));
            }
            self.learned = Some(policy);
        }
        for i in 0..self.robots.len() {
            if self.statics[i].planner == PlannerKind::Eband {
                self.robots[i].band =
                    ElasticBand::new(self.robots[i].follower.path(), self.statics[i].eband).ok();
            }
        }
        if (0..self.robots.len()).any(|i| self.planning[i] && self.statics[i].planner.social_global()) {
            self.perceive()?;
            let tod = self.time_of_day();
            for i in 0..self.robots.len() {
                if self.planning[i] && self.statics[i].planner.social_global() {
                    let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
                    self.social_plan(i, p, tod);
                    self.robots[i].replans = 0;
                }
            }
        }
        Ok(())
    }

    /// The first half of a control step: executes normalised actions instead of the built-in
    /// planners' commands. `actions` holds 3 values per robot in [-1, 1] (vx, vy scaled by the
    /// robot's max speed, wz by its max angular speed, robot frame); values outside are clipped
    /// to [-1, 1] as in Gymnasium's MuJoCo environments. All three values NaN let the robot's
    /// built-in planner drive it (autopilot). The limited commands are written to `out`'s
    /// `command`, which the physics then executes before [`World::step`]. The Python binding
    /// makes the two halves and the physics between them one call (`World.step`).
    ///
    /// # Errors
    /// [`CoreError::Input`] before the first reset, for a wrong number of values, or for a robot
    /// whose values are partly non-finite; nothing is changed then.
    pub fn command(&mut self, actions: &[f64], out: &mut [f64]) -> Result<()> {
        self.check_actions(actions, out)?;
        let dt = self.scenario.control_dt();
        let cmd = self.layout.command.offset;
        for (i, a) in actions.chunks_exact(3).enumerate() {
            if a.iter().all(|v| v.is_nan()) {
                continue;
            }
            if self.robots[i].outcome != Outcome::Running {
                continue;
            }
            let (v, w) = self.limited_action(i, [a[0], a[1], a[2]], dt);
            let rb = &mut self.robots[i];
            rb.proposed_v = v;
            rb.proposed_wz = w;
            rb.user_command = true;
            let b = body_command(self.statics[i].drive, v, rb.pose[2]);
            let row = &mut out[i * self.layout.stride..];
            row[cmd] = b.x;
            row[cmd + 1] = b.y;
            row[cmd + 2] = w;
        }
        Ok(())
    }

    /// Robot `i`'s world-frame command `(v, wz)` for a normalised robot-frame action `a` (each
    /// value clipped to [-1, 1], scaled by the robot's maximum speeds), within its limits. A
    /// differential-drive robot's action is `(v, 0, wz)`: `a[0]` its forward speed (negative:
    /// reverse), `a[1]` (zero, checked by [`World::command`]) unused.
    pub(super) fn limited_action(&self, i: usize, a: [f64; 3], dt: f64) -> (Vec2, f64) {
        let (st, rb) = (&self.statics[i], &self.robots[i]);
        let wz = a[2].clamp(-1.0, 1.0) * st.limits.max_angular_speed;
        match st.drive {
            Drive::Holonomic => {
                let body = Vec2::new(a[0].clamp(-1.0, 1.0), a[1].clamp(-1.0, 1.0)) * st.limits.max_speed;
                st.limits.apply(body_to_world(body, rb.pose[2]), wz, rb.exec_v, rb.exec_wz, dt)
            }
            Drive::Differential => {
                let s = a[0].clamp(-1.0, 1.0) * st.limits.max_speed;
                st.limits.unicycle_world(s, wz, rb.pose[2], rb.exec_v, rb.exec_wz, dt)
            }
        }
    }

    /// Checks [`World::command`]'s arguments (after a reset, 3 values per robot, each robot's
    /// three all NaN or all finite, `out` of the layout's size) without changing anything.
    fn check_actions(&self, actions: &[f64], out: &[f64]) -> Result<()> {
        let n = self.num_robots();
        if !self.started {
            return Err(CoreError::input(
                "command",
                "a call after reset()",
                "a call before the first reset()",
            ));
        }
        if actions.len() != 3 * n || out.len() != self.layout.stride * n {
            return Err(CoreError::input(
                "actions",
                format!("{} values ({n} robots x 3)", 3 * n),
                format!("{} values", actions.len()),
            ));
        }
        for (i, a) in actions.chunks_exact(3).enumerate() {
            if !a.iter().all(|v| v.is_nan()) && a.iter().any(|v| !v.is_finite()) {
                return Err(CoreError::input(
                    format!("action[{i}]"),
                    "3 finite numbers in [-1, 1] (vx, vy, wz normalised), or 3 NaN (autopilot)",
                    format!("[{}, {}, {}]", a[0], a[1], a[2]),
                ));
            }
            if self.statics[i].drive == Drive::Differential && a[1].is_finite() && a[1] != 0.0 {
                return Err(CoreError::input(
                    format!("action[{i}][1]"),
                    "0 for a differential-drive robot (its action is (v, 0, wz): no sideways motion)",
                    format!("{}", a[1]),
                ));
            }
        }
        Ok(())
    }

    /// The second half of a control step, after the physics executed `out`'s `command`: `state`
    /// holds 6 values per robot (x, y, theta, and the world-frame velocities vx, vy, wz),
    /// `contacts` one byte of `CONTACT_*` bits ([`crate::metrics::CONTACT_PERSON`] etc.) per
    /// robot. Moves the people, advances the tours, records the metrics and rewards, builds the
    /// observations and runs the built-in planners for the next command; fills `out` and
    /// `people_out` (see [`Layout`] and [`PERSON_OUT`]).
    pub fn step(
        &mut self,
        state: &[f64],
        contacts: &[u8],
        out: &mut [f64],
        people_out: &mut [f64],
    ) -> Result<()> {
        if !self.started {
            return Err(CoreError::input("step", "a call after reset()", "a call before the first reset()"));
        }
        self.check_out(out, people_out)?;
        self.check_state(state, contacts)?;
        let dt = self.scenario.control_dt();
        self.ingest(state);
        self.move_people(dt);
        self.advance_tours(dt);
        let out_of_time = self.time() >= self.scenario.episode.max_time - 1e-9;
        let stride = self.layout.stride;
        for i in 0..self.num_robots() {
            let row = &mut out[i * stride..(i + 1) * stride];
            self.record(i, contacts[i], out_of_time, row);
        }
        self.observe_all(out);
        self.plan_all(out);
        self.write_people(out, people_out);
        Ok(())
    }

    /// Checks `step`'s `state` (6 finite values per robot) and `contacts` (one per robot).
    fn check_state(&self, state: &[f64], contacts: &[u8]) -> Result<()> {
        let n = self.num_robots();
        if state.len() != 6 * n {
            return Err(CoreError::input(
                "state",
                format!("{} values ({n} robots x 6)", 6 * n),
                format!("{} values", state.len()),
            ));
        }
        if contacts.len() != n {
            return Err(CoreError::input(
                "contacts",
                format!("{n} values"),
                format!("{} values", contacts.len()),
            ));
        }
        if let Some(k) = state.iter().position(|v| !v.is_finite()) {
            return Err(CoreError::input(
                format!("state[{}][{}]", k / 6, k % 6),
                "finite robot poses and velocities",
                format!("{}", state[k]),
            ));
        }
        Ok(())
    }

    /// Takes the robots' poses and velocities after the physics; notes which episodes had ended.
    fn ingest(&mut self, state: &[f64]) {
        for (e, rb) in self.ended.iter_mut().zip(&self.robots) {
            *e = rb.outcome != Outcome::Running;
        }
        // The executed command becomes the reference for the acceleration limit.
        for rb in &mut self.robots {
            rb.exec_v = rb.proposed_v;
            rb.exec_wz = rb.proposed_wz;
            rb.user_command = false;
        }
        for (i, rb) in self.robots.iter_mut().enumerate() {
            let s = &state[6 * i..6 * i + 6];
            rb.pose = [s[0], s[1], wrap_angle(s[2])];
            rb.velocity = Vec2::new(s[3], s[4]);
            rb.wz = s[5];
        }
    }

    /// Moves the people to the same instant as the robots (the followers of a tour see its
    /// robot) and logs the instant's ground truth.
    fn move_people(&mut self, dt: f64) {
        let guides: Vec<GuideState> = self
            .robots
            .iter()
            .map(|rb| GuideState {
                pos: Vec2::new(rb.pose[0], rb.pose[1]),
                target: rb.leg + 1,
                dwelling: rb.dwelling || rb.outcome == Outcome::Success,
            })
            .collect();
        self.crowd.set_guides(&guides);
        let robots: Vec<(Vec2, f64, Vec2)> = self
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(rb, st)| (Vec2::new(rb.pose[0], rb.pose[1]), st.radius, rb.velocity))
            .collect();
        let start = std::time::Instant::now();
        self.crowd.step(dt, &robots, &self.geometry, &self.field);
        self.crowd_time += start.elapsed();
        self.robot_free
            .get_mut()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .record(&guides, &self.crowd);
        self.steps += 1;
        self.observe_interactions();
        self.log.push(&self.now.snapshot(&self.crowd));
    }
}
