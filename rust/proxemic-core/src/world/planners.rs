//! The built-in planners' bookkeeping: perception, the social global planner's re-planning
//! triggers, and the per-step dispatch to the local planners of [`crate::control`].

use super::World;
use crate::control::eband::{ElasticBand, PointMemo};
use crate::control::mode_switch::{
    LocalPlanner, Mode, OtherRobot, Person as CtlPerson, select_mode, social_momentum_step,
};
use crate::control::orca::nonholonomic::{TrackingBound, track};
use crate::control::orca_crowd::{NH_PARAMS, OrcaPeople, OrcaRobot, Unicycle, orca_among_people};
use crate::control::social_momentum::UNICYCLE_TRACKING;
use crate::control::{Drive, FollowerParams, PathFollower, body_command, heading_rate};
use crate::error::{CoreError, Result};
use crate::groups::RobotDisc;
use crate::map::CostGrid;
use crate::math::Vec2;
use crate::metrics::Outcome;
use crate::perception::PerceptionReport;
use crate::plan::social::{PeopleModel, SocialPlanning, Trigger};
use crate::plan::{PathPlanner, SearchMode, smooth_path, snap_to_passable};
use crate::scenario::PlannerKind;

/// Social planners check their path every this many control steps...
const SOCIAL_CHECK_PERIOD: usize = 3;
/// ...and re-plan at most once per this many steps.
const SOCIAL_MIN_REPLAN: usize = 10;
/// Without a trigger, a social path is re-planned every this many steps anyway, and replaced
/// when the new one is cheaper (see [`SOCIAL_REPLAN_GAIN`]): a way that people blocked when the
/// path was made may have cleared.
const SOCIAL_REFRESH: usize = 20;
/// ...unless the robot's last social search expanded more than this many cells per step of
/// [`SOCIAL_REFRESH`]: then the refresh waits one control step per this many cells it expanded, so
/// that refreshes cost at most about this many expanded cells per control step on average
/// (proxemic's choice, for large maps: a refresh of a 100 × 60 m hall of 1000 people expands
/// about 480,000 cells, and every one in our runs was kept out by [`SOCIAL_REPLAN_GAIN`]). No
/// search in a shipped scene, or a generated one of the default size, expands more than 20 × this
/// (the museum's grid, the largest, has 90,720 cells), so their refresh stays every
/// [`SOCIAL_REFRESH`] steps.
const SOCIAL_REFRESH_CELLS_PER_STEP: usize = 5_000;
/// A re-planned social path replaces the current one only when it costs at least this fraction
/// less than what is left of the current one on the same map (or the current one is blocked):
/// without it, two ways of nearly equal cost (around a gallery or along the corridor) took turns
/// as people moved and the robot wandered between them.
const SOCIAL_REPLAN_GAIN: f64 = 0.15;
/// The `social` planner's Social Momentum keeps out of the active object spaces near it as it
/// keeps out of personal zones: each active space enters its comfort term as a standing agent at
/// the space's centroid whose comfort radius is this many times the centroid's farthest vertex
/// distance (dimensionless; 1 covers the polygon). Chosen on the tuning split (scene seeds 0-99 of
/// the claims' generated scenes, episode seeds 0-39 of the museum and care center; see
/// `proxemic.splits`): without it, a robot side-stepping people went through active spaces the
/// global path kept clear of.
const SOCIAL_OBJECT_COMFORT: f64 = 1.0;
/// The largest ratio of the shortest 8-connected grid path to the straight line between its
/// ends, `cos 22.5° + (sqrt 2 - 1) sin 22.5°` (at 22.5°): a grid geodesic divided by it never
/// exceeds the true one.
const GRID_DETOUR: f64 = 1.082_392_200_292_394;

impl World {
    /// The robots as discs for perception (position, radius, velocity).
    fn robot_discs(&self) -> Vec<RobotDisc> {
        self.robots
            .iter()
            .zip(&self.statics)
            .map(|(r, s)| RobotDisc {
                pos: Vec2::new(r.pose[0], r.pose[1]),
                radius: s.radius,
                vel: r.velocity,
            })
            .collect()
    }

    /// Perceives the people's groups and individuals now.
    pub fn perceive(&mut self) -> Result<()> {
        let discs = self.robot_discs();
        self.social.perceive(&self.crowd, &discs)
    }

    /// Perceives the people now and reports it beside the scenario's group ids (the ground
    /// truth), with the detection's GCFF-style accuracy.
    pub fn perception_report(&mut self) -> Result<PerceptionReport> {
        self.perceive()?;
        let truth = self.scenario.persons.iter().map(|p| p.group).collect();
        let perception = self.social.perception().ok_or_else(|| {
            CoreError::input("perception", "a perception after perceive()", "none (a bug of the core)")
        })?;
        Ok(PerceptionReport::new(perception, truth))
    }

    /// The social model, maps and planner.
    pub fn social(&self) -> &SocialPlanning {
        &self.social
    }

    /// The index of robot `i`'s inflated grid (and social map), or an input error.
    fn grid_of(&self, i: usize) -> Result<usize> {
        self.statics.get(i).map(|st| st.grid_index).ok_or_else(|| {
            CoreError::input("robot", format!("an index below {}", self.statics.len()), i.to_string())
        })
    }

    /// Updates robot `i`'s social map for the current people and the agenda at `time_of_day`.
    pub fn update_social_map(&mut self, i: usize, time_of_day: f64) -> Result<()> {
        let k = self.grid_of(i)?;
        if self.social.perception().is_none() {
            self.perceive()?;
        }
        self.social.update_map(k, time_of_day);
        Ok(())
    }

    /// Plans a social A* path for robot `i`'s footprint between two points at `time_of_day`,
    /// with the people as perceived now.
    pub fn plan_social(
        &mut self,
        i: usize,
        start: Vec2,
        goal: Vec2,
        time_of_day: f64,
    ) -> Result<Option<Vec<Vec2>>> {
        let k = self.grid_of(i)?;
        self.perceive()?;
        Ok(self.social.plan(&mut self.planner, k, start, goal, time_of_day).map(|p| p.points))
    }

    /// Robot `i`'s social map (as last updated).
    pub fn social_map_of(&self, i: usize) -> Option<&crate::social_cost_map::SocialMap> {
        self.social.map(self.statics.get(i)?.grid_index)
    }

    /// Number of times robot `i`'s social path was re-planned (and changed) this episode.
    pub fn replans(&self, i: usize) -> usize {
        self.robots.get(i).map_or(0, |r| r.replans)
    }

    /// Number of social searches run for robot `i` this episode: its first plan, its triggered
    /// re-plans and its refreshes, whether the new path was kept or not (0 for a robot that is not
    /// on a social planner, or an index out of range).
    pub fn social_searches(&self, i: usize) -> usize {
        self.robots.get(i).map_or(0, |r| r.searches)
    }

    /// (Re-)plans robot `i`'s social path from `p`; falls back to the plain path when the goal
    /// is unreachable on the social map (for example inside someone's intimate zone). A new
    /// social path replaces the current one only when it is [`SOCIAL_REPLAN_GAIN`] cheaper.
    pub(super) fn social_plan(&mut self, i: usize, p: Vec2, time_of_day: f64) {
        let st = &self.statics[i];
        let k = st.grid_index;
        let goal = st.route[self.robots[i].leg];
        let left = self.robots[i].social_path.as_ref().map(|old| {
            let grid = &self.grids[k].grid;
            self.social.remaining_cost(old, p, time_of_day, |a, b| segment_clear(grid, a, b))
        });
        if let Some(left) = left {
            // No path can cost less than the way's length, and none is shorter than the geodesic
            // distance (the 8-connected field overestimates it by at most 8.24%, and the cost
            // counts the path in samples): when what is left is already within the gain of that,
            // a search could not find a path worth changing to.
            let field = &st.fields[self.robots[i].leg];
            let shortest = field.distance(p) / GRID_DETOUR
                - 2.0 * field.resolution()
                - crate::plan::social::SAMPLE_SPACING;
            if left.is_finite() && (1.0 - SOCIAL_REPLAN_GAIN) * left <= shortest {
                self.robots[i].last_plan_step = self.steps;
                return;
            }
        }
        let model = people_model(st.planner);
        let plan = self.social.plan_with(&mut self.planner, k, p, goal, time_of_day, model);
        self.robots[i].last_search_cells = plan.as_ref().map_or(0, |sp| sp.expansions);
        self.robots[i].searches += 1;
        if let (Some(new), Some(left)) = (&plan, left)
            && left.is_finite()
            && SocialPlanning::planned_cost(new) > (1.0 - SOCIAL_REPLAN_GAIN) * left
        {
            // Not worth a change of way: keep the current path, look again later.
            self.robots[i].last_plan_step = self.steps;
            return;
        }
        let rb = &mut self.robots[i];
        match plan {
            Some(sp) => {
                rb.follower = PathFollower::new(sp.points.clone(), FollowerParams::default());
                rb.social_path = Some(sp);
            }
            None => {
                let grid = &self.grids[k].grid;
                if let Some(path) = plan_path(&mut self.planner, grid, p, goal) {
                    rb.follower = PathFollower::new(path, FollowerParams::default());
                }
                rb.social_path = None;
            }
        }
        if self.statics[i].planner == PlannerKind::Calderita {
            // Calderita §5.3: the elastic band starts from the new global path.
            rb.band = calderita_band(rb.follower.path(), self.statics[i].eband);
        }
        rb.last_plan_step = self.steps;
        rb.replans += 1;
    }

    /// Re-planning triggers of the social planners (every few steps). Returns whether it
    /// perceived the people this step (the perception [`World::plan_all`] needs then is the
    /// same: re-planning moves neither the people nor the robots).
    fn social_checks(&mut self) -> bool {
        let due: Vec<usize> = (0..self.robots.len())
            .filter(|&i| {
                let rb = &self.robots[i];
                self.statics[i].planner.social_global()
                    && self.planning[i]
                    && rb.outcome == Outcome::Running
                    && !rb.dwelling
                    && !rb.progress.holds_path()
                    && self.steps > 0
                    && self.steps.is_multiple_of(SOCIAL_CHECK_PERIOD)
                    && self.steps >= rb.last_plan_step + SOCIAL_MIN_REPLAN
            })
            .collect();
        if due.is_empty() || self.perceive().is_err() {
            return false;
        }
        let tod = self.time_of_day();
        for i in due {
            let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
            let off_path = self.robots[i].follower.step_preview_cross_track(p) > 1.0;
            let trigger = match &self.robots[i].social_path {
                Some(path) => self.social.check(path, p, tod),
                None => Trigger::Blocked, // on the plain fallback: try the social map again
            };
            let stale = self.steps
                >= self.robots[i].last_plan_step + refresh_period(self.robots[i].last_search_cells);
            if trigger != Trigger::None || off_path || stale {
                self.social_plan(i, p, tod);
            }
        }
        true
    }

    /// The people (and robots that joined human interactions) as the local planners see them:
    /// each person keeps the robot's centre out of their intimate zone; each group adds one
    /// heavier individual covering its o-space. Entries carry the robot index they stand for,
    /// if any, so a robot does not avoid itself.
    fn controller_people(&self, robot_radius: f64) -> Vec<ControllerPerson> {
        let intimate = self.social.config().zones.intimate;
        let personal = self.social.config().zones.personal;
        let keep = |r: f64| r.max(intimate - robot_radius);
        let c = &self.crowd;
        let mut out: Vec<ControllerPerson> = Vec::with_capacity(c.len() + 4);
        let per = self.social.perception();
        let group_of =
            |k: usize| per.map(|p| p.groups.members[p.groups.labels[k]].len() > 1).unwrap_or(false);
        for k in 0..c.len() {
            let weight = if group_of(k) { self.control.group_weight } else { 1.0 };
            out.push((
                CtlPerson {
                    pos: c.pos[k],
                    vel: c.vel[k],
                    keep_out: keep(c.radius[k]),
                    weight,
                    comfort: personal,
                },
                None,
            ));
        }
        if let Some(p) = per {
            for ind in &p.individuals {
                if ind.members.len() + ind.robots.len() < 2 {
                    continue;
                }
                let mut pts: Vec<Vec2> = ind.members.iter().map(|&k| c.pos[k]).collect();
                pts.extend(
                    ind.robots
                        .iter()
                        .filter_map(|&r| self.robots.get(r))
                        .map(|r| Vec2::new(r.pose[0], r.pose[1])),
                );
                let ospace = pts.iter().map(|q| (q - ind.centre).norm()).sum::<f64>() / pts.len() as f64;
                let vel = ind.members.iter().fold(Vec2::zeros(), |a, &k| a + c.vel[k])
                    / ind.members.len().max(1) as f64;
                out.push((
                    CtlPerson {
                        pos: ind.centre,
                        vel,
                        keep_out: ospace,
                        weight: self.control.group_weight,
                        comfort: 0.0,
                    },
                    None,
                ));
                for &r in &ind.robots {
                    if let (Some(rb), Some(st)) = (self.robots.get(r), self.statics.get(r)) {
                        let q = Vec2::new(rb.pose[0], rb.pose[1]);
                        out.push((
                            CtlPerson {
                                pos: q,
                                vel: rb.velocity,
                                keep_out: keep(st.radius),
                                weight: 1.0,
                                comfort: personal,
                            },
                            Some(r),
                        ));
                    }
                }
            }
        }
        out
    }

    /// Runs every robot's built-in planner: the next command (written to `command`), the same
    /// command as a normalised action (`planner_action`) and the local planner's `mode`. The
    /// decisions are [`crate::control`]'s: the path follower, each local planner's choice of mode
    /// ([`select_mode`], Daza et al. 2021's switch for the `social` planner; Algorithm 1 as
    /// published for `daza2021` and `sousa2022`, see [`World::daza_step`]), Social Momentum, ORCA
    /// among people ([`orca_among_people`], among the robots only for `daza2021` and `sousa2022`)
    /// and the heading policy ([`heading_rate`]).
    pub(super) fn plan_all(&mut self, out: &mut [f64]) {
        let dt = self.scenario.control_dt();
        let perceived = self.social_checks();
        let n = self.robots.len();
        if !perceived
            && (0..n).any(|i| {
                let k = self.statics[i].planner;
                self.planning[i]
                    && (local_planner(k).is_some() || k == PlannerKind::Eband || k.daza2021_family())
            })
        {
            // Groups and robots joining them, as perceived now (the social planners' perception).
            let _ = self.perceive();
        }
        let mut desired: Vec<Vec2> = vec![Vec2::zeros(); n];
        let mut orca_active: Vec<usize> = Vec::new();
        // Robots in ORCA mode among the robots only (Daza 2021 line 8: people are not agents).
        let mut orca_robots_only: Vec<usize> = Vec::new();
        // Robots of the non-social `astar_orca` baseline: people at their body radius.
        let mut orca_bodies: Vec<usize> = Vec::new();
        let mut partial_goals: Vec<Vec2> = vec![Vec2::zeros(); n];
        // The people as the local planners see them, built once per robot radius this step: the
        // loop below changes neither the people, the perception nor any robot's pose or velocity.
        let mut people_of_radius: Vec<(u64, Vec<ControllerPerson>)> = Vec::new();
        // The `learned` planner's actions: its policy drives the robot (no path, no recovery).
        let mut learned: Vec<Option<[f64; 3]>> = vec![None; n];
        for i in 0..n {
            if self.robots[i].outcome != Outcome::Running || !self.planning[i] {
                self.robots[i].mode = Mode::FollowPath;
                self.robots[i].recovering = false;
                continue;
            }
            if self.statics[i].planner == PlannerKind::Learned {
                self.robots[i].mode = Mode::FollowPath;
                learned[i] = Some(self.learned_action(i, out));
                continue;
            }
            self.watch_progress(i, dt);
            self.robots[i].recovering = self.robots[i].progress.holds_path();
            if self.robots[i].dwelling {
                // At a tour stop: stand still (the desired velocity stays zero).
                self.robots[i].mode = Mode::Wait;
                continue;
            }
            (desired[i], partial_goals[i]) = self.follow_path(i, dt);
            let reference = desired[i];
            let kind = self.statics[i].planner;
            // While a recovery path is held, a planner with a local planner follows it with ORCA
            // among everyone (no social terms): it passes the people it waited for.
            let recovering = self.robots[i].progress.holds_path()
                && (local_planner(kind).is_some() || kind.daza2021_family());
            // `social` keeps its own step through a recovery (the yielding below, on the
            // recovery path, with the active object spaces hard): only the path changes.
            let yields = kind == PlannerKind::Social;
            let mode = match local_planner(kind) {
                _ if recovering && yields => Mode::FollowPath,
                _ if recovering => Mode::Orca,
                Some(local) => {
                    let radius = self.statics[i].radius.to_bits();
                    let k = match people_of_radius.iter().position(|(r, _)| *r == radius) {
                        Some(k) => k,
                        None => {
                            people_of_radius.push((radius, self.controller_people(self.statics[i].radius)));
                            people_of_radius.len() - 1
                        }
                    };
                    self.local_step(i, local, &people_of_radius[k].1, partial_goals[i], &mut desired[i], dt)
                }
                None if kind.daza2021_family() => {
                    self.daza_step(i, &mut partial_goals[i], &mut desired[i], dt)
                }
                None if kind == PlannerKind::AstarStop => self.stop_step(i, &mut desired[i], dt),
                None => Mode::FollowPath,
            };
            let mode =
                if yields && mode != Mode::Orca && self.yield_step(i, reference, &mut desired[i], recovering)
                {
                    Mode::Wait
                } else {
                    mode
                };
            if mode == Mode::Orca {
                match kind {
                    _ if kind.daza2021_family() && !recovering => orca_robots_only.push(i),
                    PlannerKind::AstarOrca => orca_bodies.push(i),
                    _ => orca_active.push(i),
                }
            }
            self.robots[i].mode = mode;
        }
        if !orca_active.is_empty() {
            self.orca_step(&orca_active, &partial_goals, &mut desired, dt, PeopleAs::IntimateZones);
        }
        if !orca_bodies.is_empty() {
            self.orca_step(&orca_bodies, &partial_goals, &mut desired, dt, PeopleAs::Bodies);
        }
        if !orca_robots_only.is_empty() {
            self.orca_step(&orca_robots_only, &partial_goals, &mut desired, dt, PeopleAs::Absent);
        }
        let stride = self.layout.stride;
        for (i, &d) in desired.iter().enumerate() {
            let row = &mut out[i * stride..(i + 1) * stride];
            match learned[i] {
                Some(a) => {
                    let (v, w) = self.limited_action(i, a, dt);
                    self.emit_command(i, v, w, row);
                }
                None => self.write_command(i, d, dt, row),
            }
        }
    }

    /// The `learned` policy's action for robot `i`, from the observation just written to its
    /// row of `out`: the sections in the env's sorted key order (lidar, people, people mask,
    /// robot), then, for a policy trained with it, the subgoal at the policy's own look-ahead,
    /// as the policy was trained on them ([`crate::control::learned`]).
    fn learned_action(&self, i: usize, out: &[f64]) -> [f64; 3] {
        let Some(policy) = self.learned else { return [0.0; 3] };
        let lay = self.layout;
        let row = &out[i * lay.stride..(i + 1) * lay.stride];
        let mut obs: Vec<f64> = [lay.obs_lidar, lay.obs_people, lay.obs_people_mask, lay.obs_robot]
            .iter()
            .flat_map(|s| row[s.range()].iter().copied())
            .collect();
        if policy.subgoal() > 0.0 {
            obs.extend(self.subgoal_offset(i, policy.subgoal()));
        }
        // `start_planners` checked the policy against the layout; a failure cannot happen here.
        policy.act(&obs).unwrap_or([0.0; 3])
    }

    /// Robot `i`'s path following this step (after the elastic band's update, eband planner):
    /// the follower's desired velocity and the partial goal for the local planners. A robot
    /// pushed off its path (by people or contacts) re-plans it from where it is, unless its
    /// global planner is social (which has its own triggers).
    fn follow_path(&mut self, i: usize, dt: f64) -> (Vec2, Vec2) {
        let planner = self.statics[i].planner;
        let p = Vec2::new(self.robots[i].pose[0], self.robots[i].pose[1]);
        let theta = self.robots[i].pose[2];
        if matches!(planner, PlannerKind::Eband | PlannerKind::Calderita) {
            self.update_band(i, p);
        }
        let st = &self.statics[i];
        let grid = &self.grids[st.grid_index].grid;
        let visible = |a: Vec2, b: Vec2| segment_clear(grid, a, b);
        let rb = &mut self.robots[i];
        let mut o =
            rb.follower.step_visible(p, theta, st.limits.max_speed, st.limits.max_accel, dt, &visible);
        if o.cross_track > rb.follower.params().replan_distance
            && !planner.social_global()
            && let Some(path) = plan_path(&mut self.planner, grid, p, st.route[rb.leg])
        {
            rb.follower = PathFollower::new(path, FollowerParams::default());
            o = rb.follower.step(p, theta, st.limits.max_speed, st.limits.max_accel, dt);
            if planner == PlannerKind::Eband {
                rb.band = ElasticBand::new(rb.follower.path(), st.eband).ok();
            }
        }
        (o.velocity, rb.follower.point_ahead(self.control.partial_goal))
    }

    /// Robot `i`'s local planner `local` this step: its mode among the people and the other
    /// robots, and with Social Momentum the new `desired` velocity. ORCA's velocity comes later,
    /// in one batch for all robots in ORCA mode ([`World::orca_step`]). `all_people` is
    /// [`World::controller_people`] for robot `i`'s radius.
    fn local_step(
        &self,
        i: usize,
        local: LocalPlanner,
        all_people: &[ControllerPerson],
        partial_goal: Vec2,
        desired: &mut Vec2,
        dt: f64,
    ) -> Mode {
        let st = &self.statics[i];
        let rb = &self.robots[i];
        let p = Vec2::new(rb.pose[0], rb.pose[1]);
        // Sized up front (with room for the active object spaces' agents): a filtered collect
        // grows, and reallocated, several times per robot and step.
        let mut people: Vec<CtlPerson> =
            Vec::with_capacity(all_people.len() + self.social.object_polygons().len());
        people.extend(all_people.iter().filter(|(_, r)| *r != Some(i)).map(|&(q, _)| q));
        let mut others: Vec<OtherRobot> = Vec::with_capacity(self.robots.len());
        others.extend((0..self.robots.len()).filter(|&j| j != i).map(|j| OtherRobot {
            pos: Vec2::new(self.robots[j].pose[0], self.robots[j].pose[1]),
            vel: self.robots[j].velocity,
            radius: self.statics[j].radius,
        }));
        let mode = select_mode(local, p, rb.exec_v, st.radius, rb.mode, &people, &others, &self.control);
        if mode != Mode::SocialMomentum {
            return mode;
        }
        if local == LocalPlanner::ModeSwitch {
            self.active_object_agents(p, &mut people);
        }
        let (v, m) = social_momentum_step(
            p,
            rb.exec_v,
            st.radius,
            partial_goal,
            &people,
            &others,
            Some(&self.geometry),
            &st.limits,
            dt,
            &self.control,
            self.sm_unicycle(i),
        );
        *desired = v;
        m
    }

    /// Robot `i`'s kinematic constraint for Social Momentum: `Some` for a differential-drive
    /// robot ([`UNICYCLE_TRACKING`]), `None` for a holonomic one.
    pub(super) fn sm_unicycle(&self, i: usize) -> Option<TrackingBound> {
        let st = &self.statics[i];
        (st.drive == Drive::Differential).then(|| TrackingBound {
            heading: self.robots[i].pose[2],
            max_speed: st.limits.max_speed,
            max_turn: st.limits.max_angular_speed,
            params: UNICYCLE_TRACKING,
        })
    }

    /// The active object spaces near `p` as Social Momentum agents of the `social` planner
    /// ([`SOCIAL_OBJECT_COMFORT`]), appended to `people`: a standing agent at each active space's
    /// centroid, no weight in the momentum term, a comfort zone covering the space, and no body
    /// (its keep-out radius is 0, so only the robot's radius and the safety margin around the
    /// centroid are kept clear). Spaces farther than the sensing range are left out.
    fn active_object_agents(&self, p: Vec2, people: &mut Vec<CtlPerson>) {
        let mut active = Vec::new();
        self.social.object_activity(self.time_of_day(), &mut active);
        for (poly, &on) in self.social.object_polygons().iter().zip(&active) {
            if !on || poly.is_empty() {
                continue;
            }
            let c = poly.iter().fold(Vec2::zeros(), |a, q| a + q) / poly.len() as f64;
            let reach = poly.iter().map(|q| (q - c).norm()).fold(0.0, f64::max);
            if (c - p).norm() - reach > self.control.sm.sensing_range {
                continue;
            }
            people.push(CtlPerson {
                pos: c,
                vel: Vec2::zeros(),
                keep_out: 0.0,
                weight: 0.0,
                comfort: SOCIAL_OBJECT_COMFORT * reach,
            });
        }
    }

    /// Limits robot `i`'s `desired` velocity (a stop once its episode has ended), turns it by
    /// the heading policy, and writes the command, the planner action and the mode into `row`.
    fn write_command(&mut self, i: usize, desired: Vec2, dt: f64, row: &mut [f64]) {
        let st = &self.statics[i];
        let rb = &mut self.robots[i];
        let (v, w) = if rb.outcome == Outcome::Running {
            let p = Vec2::new(rb.pose[0], rb.pose[1]);
            // A differential robot faces its way to the very goal: turned to the person a metre
            // short of it, it could not drive the last metre (no sideways motion).
            let face = if st.drive == Drive::Differential { None } else { st.face };
            let wz = heading_rate(p, rb.pose[2], desired, face, st.goal, &FollowerParams::default());
            match st.drive {
                Drive::Holonomic => st.limits.apply(desired, wz, rb.exec_v, rb.exec_wz, dt),
                // NH-ORCA's velocity is one the robot can track: its tracking command.
                Drive::Differential if rb.mode == Mode::Orca && st.nh_set.is_some() => {
                    let (s, w) = track(desired, rb.pose[2], st.limits.max_angular_speed, NH_PARAMS);
                    st.limits.unicycle_world(s, w, rb.pose[2], rb.exec_v, rb.exec_wz, dt)
                }
                // Social Momentum's velocity, too, is one the robot can track.
                Drive::Differential if rb.mode == Mode::SocialMomentum => {
                    let (s, w) = track(desired, rb.pose[2], st.limits.max_angular_speed, UNICYCLE_TRACKING);
                    st.limits.unicycle_world(s, w, rb.pose[2], rb.exec_v, rb.exec_wz, dt)
                }
                Drive::Differential => {
                    st.limits.unicycle_from_holonomic(desired, wz, rb.pose[2], rb.exec_v, rb.exec_wz, dt)
                }
            }
        } else {
            // Finished robots are commanded to stop (within the deceleration limit).
            match st.drive {
                Drive::Holonomic => st.limits.apply(Vec2::zeros(), 0.0, rb.exec_v, rb.exec_wz, dt),
                Drive::Differential => {
                    st.limits.unicycle_world(0.0, 0.0, rb.pose[2], rb.exec_v, rb.exec_wz, dt)
                }
            }
        };
        self.emit_command(i, v, w, row);
    }

    /// Writes robot `i`'s limited world-frame command `(v, w)` as its proposal, its robot-frame
    /// `command`, the same as a normalised `planner_action`, and its `mode`.
    fn emit_command(&mut self, i: usize, v: Vec2, w: f64, row: &mut [f64]) {
        let lay = self.layout;
        let st = &self.statics[i];
        let rb = &mut self.robots[i];
        rb.proposed_v = v;
        rb.proposed_wz = w;
        let b = body_command(st.drive, v, rb.pose[2]);
        let (cmd, act) = (lay.command.offset, lay.planner_action.offset);
        row[cmd] = b.x;
        row[cmd + 1] = b.y;
        row[cmd + 2] = w;
        row[act] = (b.x / st.limits.max_speed).clamp(-1.0, 1.0);
        row[act + 1] = (b.y / st.limits.max_speed).clamp(-1.0, 1.0);
        row[act + 2] = (w / st.limits.max_angular_speed).clamp(-1.0, 1.0);
        row[lay.mode.offset] = f64::from(rb.mode.code());
    }

    /// ORCA for the robots in `active`, among the other robots, the static geometry and the
    /// people as `people` says.
    fn orca_step(
        &mut self,
        active: &[usize],
        partial_goals: &[Vec2],
        desired: &mut [Vec2],
        dt: f64,
        people: PeopleAs,
    ) {
        let robots: Vec<OrcaRobot> = self
            .robots
            .iter()
            .zip(&self.statics)
            .map(|(rb, st)| OrcaRobot {
                pos: Vec2::new(rb.pose[0], rb.pose[1]),
                vel: rb.exec_v,
                radius: st.radius,
                max_speed: st.limits.max_speed,
                unicycle: st.nh_set.as_ref().map(|set| Unicycle { heading: rb.pose[2], set }),
            })
            .collect();
        let n = if people == PeopleAs::Absent { 0 } else { self.crowd.pos.len() };
        let intimate =
            if people == PeopleAs::IntimateZones { self.social.config().zones.intimate } else { 0.0 };
        let people = OrcaPeople {
            pos: &self.crowd.pos[..n],
            vel: &self.crowd.vel[..n],
            radius: &self.crowd.radius[..n],
            intimate,
        };
        let step = self.steps as u64;
        orca_among_people(
            &mut self.orca,
            &self.obstacles,
            &robots,
            people,
            active,
            partial_goals,
            desired,
            dt,
            step,
        );
    }

    /// Moves robot `i`'s elastic band one optimisation pass and follows it.
    fn update_band(&mut self, i: usize, p: Vec2) {
        let field = &self.field;
        // The band's bubbles are free space for the robot's centre: clearance minus its footprint.
        let body = self.statics[i].radius + self.scenario.robots[i].inflation_margin;
        let clearance = |q: Vec2| field.at(q) - body;
        let rb = &mut self.robots[i];
        let Some(band) = rb.band.as_mut() else { return };
        if band.set_start(p).is_err() {
            return;
        }
        if self.statics[i].planner == PlannerKind::Calderita {
            // Calderita: the social cost the band sees is the summed density G_d of the people
            // (their Kirby spaces, as on the map), clamped to [0, 1], wherever they are now.
            let zones = self.social.density_zones();
            let c = &self.crowd;
            // Each person's facing once per update, not once per person and point: the same
            // unit vectors, so the same sums (`DensityZones::density_facing`).
            let people: Vec<(Vec2, Vec2)> = (0..c.len())
                .map(|k| {
                    let p =
                        crate::groups::PersonState { pos: c.pos[k], heading: c.heading[k], vel: c.vel[k] };
                    (p.pos, p.facing())
                })
                .collect();
            let density = |q: Vec2| zones.density_facing_capped(&people, q, 1.0);
            // The people stand still during the update: each point's density once.
            let memo = PointMemo::new(&density);
            let social = |q: Vec2| memo.get(q);
            band.update(&clearance, Some(&social));
            let full = band.points().len() >= band.params().max_bubbles;
            if band.is_connected() || !full {
                rb.follower = PathFollower::new(band.points().to_vec(), FollowerParams::default());
            } else {
                // A broken band that filled its bubbles (bisecting towards a point without
                // clearance, e.g. a doorpost) is dropped, and the robot follows the global path
                // until the next plan makes a new band (the paper's band is re-created from every
                // new plan too). A band broken by a bubble that merely touches the inflation is
                // followed, as the `eband` planner does.
                rb.band = None;
                if let Some(sp) = &rb.social_path {
                    rb.follower = PathFollower::new(sp.points.clone(), FollowerParams::default());
                }
            }
        } else {
            let individuals = self.social.perception().map(|per| per.individuals.clone()).unwrap_or_default();
            let social = |q: Vec2| crate::perception::max_value(&individuals, q);
            band.update(&clearance, Some(&social));
            rb.follower = PathFollower::new(band.points().to_vec(), FollowerParams::default());
        }
    }
}

/// Whether a robot of `drive` and `planner` runs NH-ORCA in ORCA mode: a differential-drive
/// `astar_orca` robot, whose local planner is ORCA. The planners that switch to ORCA as one mode
/// among others keep the one holonomic-to-unicycle rule there (docs/choices.md).
pub(super) fn nh_orca(drive: Drive, planner: PlannerKind) -> bool {
    drive == Drive::Differential && planner == PlannerKind::AstarOrca
}

/// Bubbles per metre of path a `calderita` band may hold: bubbles of the smallest radius
/// (`min_bubble` 0.05 m, overlap 0.7) are 0.07 m apart, 14 per metre; a band that needs more is
/// broken anyway, and the cap keeps its bisection from filling `max_bubbles` (4096) on every step.
const CALDERITA_BUBBLES_PER_METRE: f64 = 64.0;

/// The `calderita` planner's band along `path` with `params`, its bubble count capped by the
/// path's length ([`CALDERITA_BUBBLES_PER_METRE`]); `None` for an invalid path.
fn calderita_band(path: &[Vec2], params: crate::control::eband::EbandParams) -> Option<ElasticBand> {
    let length: f64 = path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let cap = (CALDERITA_BUBBLES_PER_METRE * length).ceil().max(2.0);
    let max_bubbles = params.max_bubbles.min(cap as usize).max(2);
    ElasticBand::new(path, crate::control::eband::EbandParams { max_bubbles, ..params }).ok()
}

/// A person as the local planners see them, with the robot it stands for, if any (see
/// [`World::controller_people`]).
type ControllerPerson = (CtlPerson, Option<usize>);

/// How a batch of robots running ORCA sees the people.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum PeopleAs {
    /// Not at all (Daza 2021 line 8: among the robots only).
    Absent,
    /// Non-cooperating agents whose disc keeps the robot out of their intimate zone (the social
    /// planners in ORCA mode).
    IntimateZones,
    /// Non-cooperating agents at their body radius, no social term (the `astar_orca` baseline).
    Bodies,
}

/// Control steps between a social path's refreshes (re-plans without a trigger) after a search
/// that expanded `cells` cells: [`SOCIAL_REFRESH`], or longer after a search of more than
/// `SOCIAL_REFRESH × SOCIAL_REFRESH_CELLS_PER_STEP` cells.
fn refresh_period(cells: usize) -> usize {
    SOCIAL_REFRESH.max(cells.div_ceil(SOCIAL_REFRESH_CELLS_PER_STEP))
}

/// The people model of a social global planner's map.
fn people_model(kind: PlannerKind) -> PeopleModel {
    if kind == PlannerKind::Calderita { PeopleModel::Density } else { PeopleModel::Individuals }
}

/// The local planner of a built-in planner, if it has one.
fn local_planner(kind: PlannerKind) -> Option<LocalPlanner> {
    match kind {
        PlannerKind::Social => Some(LocalPlanner::ModeSwitch),
        PlannerKind::SocialMomentum => Some(LocalPlanner::SocialMomentum),
        PlannerKind::AstarOrca => Some(LocalPlanner::Orca),
        _ => None,
    }
}

/// Whether the straight segment `ab` crosses only passable cells of `grid` (sampled every half
/// cell; cells the segment starts in are allowed, so a robot already in the inflation can leave).
pub(super) fn segment_clear(grid: &CostGrid, a: Vec2, b: Vec2) -> bool {
    let len = (b - a).norm();
    let n = (len / (0.5 * grid.spec.resolution)).ceil() as usize;
    let start = grid.spec.cell_of(a);
    (1..=n).all(|k| {
        let q = a + (b - a) * (k as f64 / n as f64);
        match grid.spec.cell_of(q) {
            Some(c) => Some(c) == start || grid.passable(c.0, c.1),
            None => false,
        }
    })
}

/// Plain A* (weight 0) from `start` to `goal` on `grid`, smoothed, as world-frame waypoints
/// that start at `start` and end exactly at `goal`.
pub(super) fn plan_path(
    planner: &mut PathPlanner,
    grid: &CostGrid,
    start: Vec2,
    goal: Vec2,
) -> Option<Vec<Vec2>> {
    let s = snap_to_passable(grid, start)?;
    let g = snap_to_passable(grid, goal)?;
    let path = planner.plan(grid, s, g, SearchMode { weight: 0.0, heuristic: true })?;
    let mut pts = smooth_path(grid, &path, 0.0);
    if let Some(first) = pts.first_mut() {
        *first = start;
    }
    pts.push(goal);
    Some(pts)
}
