//! Recording an episode: the [`SceneLog`] every robot's metrics share, one [`EpisodeRecorder`]
//! per robot deciding its [`Outcome`] step by step, and its [`EpisodeReport`] at the end (see
//! the module documentation of [`crate::metrics`]).

use serde::Serialize;

use super::fault::{StepContact, Touch, classify_step};
use super::{
    CONTACT_PERSON, CONTACT_ROBOT, CONTACT_STATIC, EvalContext, FullMetrics, Groups, InteractionLink,
    MetricParams, OSpace, ObjectSpaces, PeopleTracks, RobotFreeTracks, Trajectory, evaluate,
};
use crate::error::Result;
use crate::math::Vec2;

/// How an episode ended for a robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// Still running.
    Running,
    /// Reached the goal.
    Success,
    /// Collided with a person, the static geometry or another robot.
    Collision,
    /// Ran out of time.
    Timeout,
}

/// A robot's episode metrics: the outcome and every metric of [`FullMetrics`] (flattened when
/// serialised, one key per metric, in the metric reference's order: [`super::METRICS`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(remote = "Self")]
pub struct EpisodeReport {
    /// How the episode ended (`running` while it runs).
    pub outcome: Outcome,
    /// Episode duration so far (s): control steps times the control period.
    pub duration: f64,
    /// Daza et al. 2021's D_A* (m): length of the plain A* path from the episode's start to the
    /// goal, planned by the world at reset (the denominator of nothing, the numerator of
    /// `l_ratio`).
    pub astar_length: f64,
    /// Geodesic (shortest collision-free) start-goal length `l*` (m) of `path_length_ratio` and
    /// `spl`; `None` when unreachable.
    pub geodesic_length: Option<f64>,
    /// Smallest surface gap to another robot over the episode's instants (m; negative means
    /// overlap; `None` for a robot alone).
    pub min_robot_gap: Option<f64>,
    /// Every metric.
    #[serde(flatten)]
    pub metrics: FullMetrics,
    /// The built-in planner's progress monitor (zero from [`EpisodeRecorder::evaluate`]; the
    /// world fills it in).
    #[serde(flatten)]
    pub recovery: super::RecoveryMetrics,
}

/// One key per metric in the order of the metric reference ([`super::METRICS`], the one source of
/// metric names and of their order), so that records, `episodes.csv` and `metrics.json` list the
/// metrics in one order: the fields' own serialisation, reordered. (A non-finite value, which no
/// metric has: undefined values are `None`, would become `null` here as in JSON text.)
impl Serialize for EpisodeReport {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::{Error, SerializeMap};
        let fields =
            EpisodeReport::serialize(self, serde_json::value::Serializer).map_err(S::Error::custom)?;
        let serde_json::Value::Object(mut fields) = fields else {
            return Err(S::Error::custom("an episode report serialises to a map"));
        };
        let mut map = serializer.serialize_map(Some(fields.len()))?;
        for info in super::METRICS {
            if let Some(value) = fields.remove(info.key) {
                map.serialize_entry(info.key, &value)?;
            }
        }
        // Keys missing from the reference (a test keeps there being none) follow, sorted.
        for (key, value) in &fields {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

/// What stays fixed over a robot's episode.
#[derive(Clone, Debug)]
pub struct RecorderSetup {
    /// Control period (s), > 0.
    pub dt: f64,
    /// Robot disc radius (m).
    pub robot_radius: f64,
    /// Goal position (m).
    pub goal: Vec2,
    /// Success radius around the goal (m, robot centre).
    pub success_radius: f64,
    /// The plain A* path from the start to the goal (Daza et al. 2021's reference path).
    pub astar_path: Vec<Vec2>,
    /// Geodesic start-goal length (m); `f64::INFINITY` when unreachable.
    pub geodesic_length: f64,
    /// The episode, as an invariant's error names it (e.g. `museum, seed 3, robot 0`).
    pub episode: String,
}

/// What the world looks like at one control instant (apart from the robots).
#[derive(Clone, Copy, Debug)]
pub struct Snapshot<'a> {
    /// People's centres (m).
    pub positions: &'a [Vec2],
    /// People's velocities (m/s).
    pub velocities: &'a [Vec2],
    /// People's headings (rad).
    pub headings: &'a [f64],
    /// Whether each person is in the scene (empty: everyone is).
    pub present: &'a [bool],
    /// The groups' o-spaces at this instant.
    pub ospaces: &'a [OSpace],
    /// The interaction segments at this instant.
    pub links: &'a [InteractionLink],
    /// Per object polygon, whether its activity is on.
    pub active: &'a [bool],
}

/// The scene since the episode started, one [`Snapshot`] per control instant: what every
/// robot's metrics share (the people's tracks, the o-spaces, the interaction segments, the object
/// spaces' activity), kept once for all robots. A robot's instant `k` is the log's instant `k`.
#[derive(Clone, Debug)]
pub struct SceneLog {
    people_radii: Vec<f64>,
    object_polygons: Vec<Vec<Vec2>>,
    positions: Vec<Vec2>,
    velocities: Vec<Vec2>,
    headings: Vec<f64>,
    present: Vec<bool>,
    ospace_offsets: Vec<usize>,
    ospaces: Vec<OSpace>,
    link_offsets: Vec<usize>,
    links: Vec<InteractionLink>,
    active: Vec<bool>,
}

impl SceneLog {
    /// An empty log of the people with radii `people_radii` (m) and the objects' interaction
    /// polygons `object_polygons` (world frame, m).
    pub fn new(people_radii: Vec<f64>, object_polygons: Vec<Vec<Vec2>>) -> Self {
        SceneLog {
            people_radii,
            object_polygons,
            positions: Vec::new(),
            velocities: Vec::new(),
            headings: Vec::new(),
            present: Vec::new(),
            ospace_offsets: vec![0],
            ospaces: Vec::new(),
            link_offsets: vec![0],
            links: Vec::new(),
            active: Vec::new(),
        }
    }

    /// Empties the log for a new episode of the people with radii `people_radii` (m), keeping
    /// the buffers' memory (a world reuses its log from episode to episode).
    pub fn restart(&mut self, people_radii: &[f64]) {
        self.people_radii.clear();
        self.people_radii.extend_from_slice(people_radii);
        self.positions.clear();
        self.velocities.clear();
        self.headings.clear();
        self.present.clear();
        self.ospace_offsets.clear();
        self.ospace_offsets.push(0);
        self.ospaces.clear();
        self.link_offsets.clear();
        self.link_offsets.push(0);
        self.links.clear();
        self.active.clear();
    }

    /// Appends the next instant.
    pub fn push(&mut self, s: &Snapshot) {
        let np = self.people_radii.len();
        let nm = self.object_polygons.len();
        // Sizes come from the world, which builds the snapshot from the same crowd and objects;
        // pad or cut defensively so the evaluator's length checks always hold.
        let fill = |dst: &mut Vec<Vec2>, src: &[Vec2]| {
            dst.extend((0..np).map(|i| src.get(i).copied().unwrap_or_else(Vec2::zeros)));
        };
        fill(&mut self.positions, s.positions);
        fill(&mut self.velocities, s.velocities);
        self.headings.extend((0..np).map(|i| s.headings.get(i).copied().unwrap_or(0.0)));
        self.present.extend((0..np).map(|i| s.present.get(i).copied().unwrap_or(true)));
        self.ospaces.extend_from_slice(s.ospaces);
        self.ospace_offsets.push(self.ospaces.len());
        self.links.extend_from_slice(s.links);
        self.link_offsets.push(self.links.len());
        self.active.extend((0..nm).map(|k| s.active.get(k).copied().unwrap_or(false)));
    }

    /// Instants logged.
    pub fn instants(&self) -> usize {
        self.ospace_offsets.len() - 1
    }

    /// The people's centres at instant `t` (m), if logged.
    fn people_at(&self, t: usize) -> Option<&[Vec2]> {
        let np = self.people_radii.len();
        self.positions.get(t * np..(t + 1) * np)
    }

    /// Whether each person is in the scene at instant `t`, if logged.
    fn present_at(&self, t: usize) -> Option<&[bool]> {
        let np = self.people_radii.len();
        self.present.get(t * np..(t + 1) * np)
    }
}

/// Records one robot's episode and decides its outcome (see the module documentation of [`crate::metrics`]). The scene
/// it moves in is in a [`SceneLog`] shared by all robots, which the world extends by one instant
/// before recording each robot's step.
#[derive(Clone, Debug)]
pub struct EpisodeRecorder {
    setup: RecorderSetup,
    poses: Vec<[f64; 3]>,
    contacts: Vec<u8>,
    /// Per step, whether its command followed a held recovery path.
    recovering: Vec<bool>,
    min_robot_gap: f64,
    outcome: Outcome,
    /// Scratch: the last step's touch per person.
    touches: Vec<Touch>,
}

impl EpisodeRecorder {
    /// Starts an episode at the pose `start` (`[x, y, theta]`, m, m, rad) at instant 0.
    pub fn new(setup: RecorderSetup, start: [f64; 3]) -> Self {
        EpisodeRecorder {
            setup,
            poses: vec![start],
            contacts: Vec::new(),
            recovering: Vec::new(),
            min_robot_gap: f64::INFINITY,
            outcome: Outcome::Running,
            touches: Vec::new(),
        }
    }

    /// Starts a new episode as [`EpisodeRecorder::new`] does, keeping the buffers' memory (a
    /// world reuses its robots' recorders from episode to episode).
    pub fn restart(&mut self, setup: RecorderSetup, start: [f64; 3]) {
        self.setup = setup;
        self.poses.clear();
        self.poses.push(start);
        self.contacts.clear();
        self.recovering.clear();
        self.min_robot_gap = f64::INFINITY;
        self.outcome = Outcome::Running;
    }

    /// Notes the surface gap (m) to the closest other robot at an instant (for `min_robot_gap`;
    /// a negative gap is a robot-robot collision, which the caller reports as `CONTACT_ROBOT`).
    pub fn observe_robot_gap(&mut self, gap: f64) {
        self.min_robot_gap = self.min_robot_gap.min(gap);
    }

    /// Adds one control step ending at `pose`, at the instant `log` last received, with the
    /// physics' `CONTACT_*` bits of the step; returns the outcome after it. A collision (a static
    /// or robot contact, or a person contact that is the robot's fault, [`super::fault`]: the
    /// physics' person contact or a negative surface gap anywhere on the relative motion swept
    /// over the step, with the robot moving toward the person) ends the episode before the goal
    /// does; the goal before the time limit. A person walking into the robot does not end it.
    /// `recovering`: the step's command followed a held recovery path (for the recovery
    /// metrics, [`super::recovery`]). Steps after the end are ignored.
    pub fn record(
        &mut self,
        log: &SceneLog,
        pose: [f64; 3],
        contacts: u8,
        out_of_time: bool,
        recovering: bool,
    ) -> Outcome {
        if self.outcome != Outcome::Running {
            return self.outcome;
        }
        let prev_t = self.poses.len() - 1;
        let prev = self.poses[prev_t];
        self.poses.push(pose);
        let (p0, p1) = (Vec2::new(prev[0], prev[1]), Vec2::new(pose[0], pose[1]));
        // A log that does not hold both instants (a caller's error) has no people to sweep past;
        // `evaluate` reports the mismatch.
        // Absent people (replayed people coming or going) are neither swept past nor touched
        // (`classify_step` leaves them out, as the evaluator does).
        let robot_fault = match (log.people_at(prev_t), log.people_at(prev_t + 1)) {
            (Some(before), Some(after)) => {
                let step = StepContact {
                    p0,
                    p1,
                    vel: (p1 - p0) / self.setup.dt,
                    robot_radius: self.setup.robot_radius,
                    before,
                    after,
                    radii: &log.people_radii,
                    physics_person: contacts & CONTACT_PERSON != 0,
                    present_before: log.present_at(prev_t).unwrap_or(&[]),
                    present_after: log.present_at(prev_t + 1).unwrap_or(&[]),
                };
                classify_step(&step, &mut self.touches);
                self.touches.contains(&Touch::RobotFault)
            }
            _ => false,
        };
        // The physics' own bits: the evaluator runs the swept test itself, and a swept overlap
        // is no physics contact (the fault rule reads the physics' person bit as one).
        self.contacts.push(contacts);
        self.recovering.push(recovering);
        self.outcome = if robot_fault || contacts & (CONTACT_STATIC | CONTACT_ROBOT) != 0 {
            Outcome::Collision
        } else if (p1 - self.setup.goal).norm() <= self.setup.success_radius {
            Outcome::Success
        } else if out_of_time {
            Outcome::Timeout
        } else {
            Outcome::Running
        };
        self.outcome
    }

    /// The outcome so far.
    pub fn outcome(&self) -> Outcome {
        self.outcome
    }

    /// Control steps recorded.
    pub fn steps(&self) -> usize {
        self.poses.len() - 1
    }

    /// The recorded robot poses `[x, y, theta]`, instant 0 first.
    pub fn poses(&self) -> &[[f64; 3]] {
        &self.poses
    }

    /// The plain A* reference path.
    pub fn astar_path(&self) -> &[Vec2] {
        &self.setup.astar_path
    }

    /// Evaluates the recording in the scene `log` (its first instants, one per recorded pose):
    /// every metric of [`FullMetrics`], with `clearance` the distance from a point to the static
    /// geometry (m) and `zones` the Hall zone radii (m, centre distance: intimate, personal,
    /// social), and `robot_free` the episode replayed without the robots (for the robot's cost to
    /// people; `None` leaves those metrics `None`).
    ///
    /// # Errors
    /// [`crate::error::CoreError::Input`] when `log` holds fewer instants than the recording,
    /// and from [`evaluate`] when a recorded value is not finite or the zones are not
    /// non-decreasing; [`crate::error::CoreError::Invariant`] when the record breaks one of its
    /// invariants ([`super::invariants`]: a bug).
    pub fn evaluate(
        &self,
        log: &SceneLog,
        clearance: &dyn Fn(Vec2) -> f64,
        zones: [f64; 3],
        params: MetricParams,
        robot_free: Option<RobotFreeTracks>,
    ) -> Result<EpisodeReport> {
        let n = self.poses.len();
        if log.instants() < n {
            return Err(crate::error::CoreError::input(
                "log",
                format!("a scene log of at least the recording's {n} instants"),
                format!("{} instants", log.instants()),
            ));
        }
        let s = &self.setup;
        let traj = Trajectory {
            dt: s.dt,
            robot: &self.poses,
            robot_radius: s.robot_radius,
            goal: s.goal,
            success_radius: s.success_radius,
        };
        let np = log.people_radii.len();
        let people = PeopleTracks {
            positions: &log.positions[..n * np],
            velocities: &log.velocities[..n * np],
            headings: &log.headings[..n * np],
            radii: &log.people_radii,
            count: np,
            present: &log.present[..n * np],
        };
        let groups = Groups {
            ospace_offsets: &log.ospace_offsets[..=n],
            ospaces: &log.ospaces[..log.ospace_offsets[n]],
            link_offsets: &log.link_offsets[..=n],
            links: &log.links[..log.link_offsets[n]],
        };
        let nm = log.object_polygons.len();
        let objects = ObjectSpaces { polygons: &log.object_polygons, active: &log.active[..n * nm] };
        let ctx = EvalContext {
            geodesic_length: s.geodesic_length,
            astar_path: &s.astar_path,
            clearance,
            zones,
            collision_steps: &self.contacts,
            params,
            robot_free,
        };
        let metrics = evaluate(&traj, &people, &groups, &objects, &ctx)?;
        let astar_length = s.astar_path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
        let report = EpisodeReport {
            outcome: self.outcome,
            duration: self.steps() as f64 * s.dt,
            astar_length,
            geodesic_length: s.geodesic_length.is_finite().then_some(s.geodesic_length),
            min_robot_gap: self.min_robot_gap.is_finite().then_some(self.min_robot_gap),
            metrics,
            recovery: super::recovery::evaluate(&traj, &self.recovering, &groups, &objects),
        };
        super::invariants::check(&report, &traj, &people, &groups, &objects, &ctx).map_err(|v| {
            crate::error::CoreError::Invariant {
                episode: s.episode.clone(),
                invariant: v.invariant.to_string(),
                detail: v.detail,
            }
        })?;
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::CONTACT_STATIC;

    fn setup() -> RecorderSetup {
        RecorderSetup {
            dt: 0.1,
            robot_radius: 0.25,
            goal: Vec2::new(3.0, 4.0),
            success_radius: 0.3,
            astar_path: vec![Vec2::zeros(), Vec2::new(3.0, 0.0), Vec2::new(3.0, 4.0)],
            geodesic_length: 7.0,
            episode: "test".into(),
        }
    }

    /// People standing still at `people` (at most 4), facing +x, no groups nor objects.
    fn snapshot(people: &[Vec2]) -> Snapshot<'_> {
        static ZEROS: [Vec2; 4] = [Vec2::new(0.0, 0.0); 4];
        static HEADINGS: [f64; 4] = [0.0; 4];
        let n = people.len();
        Snapshot {
            positions: people,
            velocities: &ZEROS[..n],
            headings: &HEADINGS[..n],
            present: &[],
            ospaces: &[],
            links: &[],
            active: &[],
        }
    }

    /// A robot starting at (0, 0) among people standing still (radius 0.2 m each).
    struct Run {
        people: Vec<Vec2>,
        log: SceneLog,
        rec: EpisodeRecorder,
    }

    impl Run {
        fn new(people: &[Vec2]) -> Self {
            let mut log = SceneLog::new(vec![0.2; people.len()], vec![]);
            log.push(&snapshot(people));
            Run { people: people.to_vec(), log, rec: EpisodeRecorder::new(setup(), [0.0; 3]) }
        }

        /// The scene's next instant, then the robot's step to (x, y).
        fn step(&mut self, x: f64, y: f64, contacts: u8, out_of_time: bool) -> Outcome {
            self.log.push(&snapshot(&self.people));
            self.rec.record(&self.log, [x, y, 0.0], contacts, out_of_time, false)
        }

        fn eval(&self) -> EpisodeReport {
            self.rec
                .evaluate(&self.log, &|_| f64::INFINITY, [0.45, 1.2, 3.6], MetricParams::default(), None)
                .expect("valid")
        }
    }

    #[test]
    fn hand_computed_episode_reaches_the_goal() {
        // (0,0) -> (3,0) -> (3,4): path 7 m = the A* path, so L_ratio = 1; person at (1.5, 1)
        // is 1.0 m from the robot at no sample but (1.5, 0) lies between samples: d_min is over
        // the samples, (0,0) and (3,0) are both sqrt(1.5² + 1) = 1.803 m away.
        let mut run = Run::new(&[Vec2::new(1.5, 1.0)]);
        assert_eq!(run.step(3.0, 0.0, 0, false), Outcome::Running);
        assert_eq!(run.step(3.0, 4.0, 0, false), Outcome::Success);
        // ignored after the end (the scene goes on)
        assert_eq!(run.step(9.0, 9.0, CONTACT_STATIC, true), Outcome::Success);
        assert_eq!(run.log.instants(), 4);
        let r = run.eval();
        assert_eq!(r.outcome, Outcome::Success);
        assert_eq!(r.metrics.collisions.steps, 2);
        assert!((r.metrics.efficiency.path_length - 7.0).abs() < 1e-12);
        assert!((r.astar_length - 7.0).abs() < 1e-12);
        assert!((r.metrics.papers.l_ratio.expect("success") - 1.0).abs() < 1e-12);
        assert!((r.metrics.collisions.time_to_goal.expect("success") - 0.2).abs() < 1e-12);
        assert!((r.duration - 0.2).abs() < 1e-12);
        let dmin = r.metrics.proximity.d_min[0].expect("sampled");
        assert!((dmin - 3.25f64.sqrt()).abs() < 1e-12);
        assert_eq!(r.geodesic_length, Some(7.0));
    }

    #[test]
    fn swept_contact_ends_the_episode_as_the_evaluator_counts_it() {
        // The robot jumps from (0,0) to (2,0) through a person at (1,0): no sample overlaps, the
        // swept relative motion does; the recorder stops and the evaluator agrees (hc = 1).
        let mut run = Run::new(&[Vec2::new(1.0, 0.0)]);
        assert_eq!(run.step(2.0, 0.0, 0, false), Outcome::Collision);
        let r = run.eval();
        assert!(
            r.metrics.collisions.hc
                && r.metrics.collisions.collision
                && !r.metrics.collisions.success
                && !r.metrics.collisions.timeout
        );
        assert_eq!(r.metrics.collisions.hc_count, 1);
        assert_eq!(r.metrics.papers.l_ratio, None);
    }

    #[test]
    fn a_restarted_recorder_equals_a_new_one() {
        let mut old = Run::new(&[Vec2::new(0.3, 0.0)]);
        old.rec.observe_robot_gap(-0.1);
        old.step(0.1, 0.0, CONTACT_STATIC, false);
        old.people = vec![Vec2::new(1.5, 1.0)];
        old.log.restart(&[0.2]);
        old.log.push(&snapshot(&old.people));
        old.rec.restart(setup(), [0.0; 3]);
        let mut new = Run::new(&[Vec2::new(1.5, 1.0)]);
        for run in [&mut old, &mut new] {
            assert_eq!(run.step(3.0, 0.0, 0, false), Outcome::Running);
            assert_eq!(run.step(3.0, 4.0, 0, false), Outcome::Success);
        }
        let json = |run: &Run| serde_json::to_string(&run.eval()).expect("json");
        assert_eq!(json(&old), json(&new));
    }

    #[test]
    fn contact_bits_and_timeout() {
        let mut run = Run::new(&[]);
        assert_eq!(run.step(0.1, 0.0, 0, true), Outcome::Timeout);
        assert!(run.eval().metrics.collisions.timeout);
        let mut run = Run::new(&[]);
        assert_eq!(run.step(0.1, 0.0, CONTACT_STATIC, false), Outcome::Collision);
        let r = run.eval();
        assert!(r.metrics.collisions.wc && !r.metrics.collisions.hc);
    }

    #[test]
    fn a_log_shorter_than_the_recording_is_an_error() {
        let mut run = Run::new(&[Vec2::new(1.5, 1.0)]);
        run.step(1.0, 0.0, 0, false);
        run.log.restart(&[0.2]);
        let e = run.rec.evaluate(&run.log, &|_| 1.0, [0.45, 1.2, 3.6], MetricParams::default(), None);
        assert!(matches!(e, Err(crate::error::CoreError::Input { .. })), "{e:?}");
    }
}
