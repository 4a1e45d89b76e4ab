//! `World`: the simulated world of a scenario, its episode calls and its inspection calls.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2, PyReadonlyArray3, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use proxemic_core::scenario::check_time_of_day;
use proxemic_core::world::World as CoreWorld;

use crate::conversions::{
    Named, array_of, busy, finite_point, flat_mut, points_to_array, robot_index, robot_indices, seed_arg,
    to_py,
};
use crate::errors::{enter_core, input_err, missing};
use crate::scenario::PyScenario;
use crate::step::{StepBuffers, two_phase_step};

/// The simulated world of a scenario: people, planners, metrics, observations and rewards.
///
/// Buffers: `out` is a C-contiguous float64 array of `num_robots * stride` values (use
/// `layout` to slice it), `people_out` a C-contiguous float64 array of `num_people * PERSON_OUT`
/// values (x, y, heading, contact hint). Both are one-dimensional.
#[pyclass(module = "proxemic._core", name = "World")]
pub(crate) struct PyWorld {
    pub(crate) inner: CoreWorld,
    /// `step` and `reset` calls so far (see `calls`).
    pub(crate) calls: u64,
}

impl PyWorld {
    /// `time_of_day` (checked by the core) or, when `None`, the world's time of day now.
    fn time_of_day_or_now(&self, py: Python<'_>, time_of_day: Option<f64>) -> PyResult<f64> {
        match time_of_day {
            None => Ok(self.inner.time_of_day()),
            Some(t) => enter_core(py, || check_time_of_day(t)),
        }
    }

    /// `robot` if it indexes a robot of the world, else an `InputError` naming `robot` (the one
    /// index check of every binding that takes a robot).
    fn robot(&self, py: Python<'_>, robot: usize) -> PyResult<usize> {
        let n = self.inner.num_robots();
        if robot < n {
            Ok(robot)
        } else {
            Err(input_err(py, "robot", format!("a robot index below {n}"), robot.to_string()))
        }
    }

    /// Robot `robot`'s item `get` returns (after the index check; `None` there is a bug of the
    /// core, reported as an internal error naming `what`).
    fn of_robot<'s, T: ?Sized>(
        &'s self,
        py: Python<'_>,
        robot: usize,
        what: &str,
        get: impl FnOnce(&'s CoreWorld, usize) -> Option<&'s T>,
    ) -> PyResult<&'s T> {
        let i = self.robot(py, robot)?;
        get(&self.inner, i).ok_or_else(|| missing(py, what))
    }
}

#[pymethods]
impl PyWorld {
    /// Builds the world (static map, inflated grids, goal fields, plain A* paths). Raises
    /// `ScenarioError` for a robot or goal inside or too close to walls, a person in a wall or a
    /// route through one, and `PlanningError` for an unreachable goal.
    #[new]
    fn new(py: Python<'_>, scenario: &PyScenario) -> PyResult<Self> {
        let s = scenario.inner.clone();
        let inner = enter_core(py, move || CoreWorld::new(s))?;
        Ok(PyWorld { inner, calls: 0 })
    }

    /// Values per robot row of `out`.
    #[getter]
    fn stride(&self) -> usize {
        self.inner.layout().stride
    }

    /// `{section: (offset, length)}` of a robot row of `out`.
    #[getter]
    fn layout<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let sections: Vec<(&str, (usize, usize))> =
            self.inner.layout().sections().into_iter().map(|(name, s)| (name, (s.offset, s.len))).collect();
        to_py(py, "the layout", &Named(&sections))
    }

    /// Number of robots.
    #[getter]
    fn num_robots(&self) -> usize {
        self.inner.num_robots()
    }

    /// Number of people.
    #[getter]
    fn num_people(&self) -> usize {
        self.inner.num_people()
    }

    /// Control steps since the last reset.
    #[getter]
    fn steps(&self) -> usize {
        self.inner.steps()
    }

    /// Simulation time since the last reset (s).
    #[getter]
    fn time(&self) -> f64 {
        self.inner.time()
    }

    /// Time of day at the current step (seconds after midnight).
    #[getter]
    fn time_of_day(&self) -> f64 {
        self.inner.time_of_day()
    }

    /// Bound on the goal offset in observations (metres): the map diagonal, rounded up.
    #[getter]
    fn obs_position_bound(&self) -> f64 {
        self.inner.obs_position_bound()
    }

    /// Starts an episode from `seed` (a non-negative integer below 2**64).
    fn reset(
        &mut self,
        py: Python<'_>,
        #[pyo3(from_py_with = seed_arg)] seed: u64,
        out: &Bound<'_, PyAny>,
        people_out: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        self.calls += 1;
        let out = array_of::<f64>(py, "out", "float64", out)?;
        let people_out = array_of::<f64>(py, "people_out", "float64", people_out)?;
        let mut out = out.try_readwrite().map_err(|_| busy(py, "out"))?;
        let mut people_out = people_out.try_readwrite().map_err(|_| busy(py, "people_out"))?;
        let o = flat_mut(py, "out", &mut out)?;
        let p = flat_mut(py, "people_out", &mut people_out)?;
        let w = &mut self.inner;
        enter_core(py, move || w.reset(seed, o, p))
    }

    /// One control step for every robot, as one call: executes the normalised `actions` (3 per
    /// robot in [-1, 1], clipped; all three NaN for a robot on autopilot, which executes its
    /// built-in planner's command) by writing the limited commands into `out`'s `command`, calls
    /// `physics()` once (it must execute those commands and the people's poses in `people_out`,
    /// and write the robots' new `state`, 6 float64 per robot: x, y, theta, vx, vy, wz in the
    /// world frame, and `contacts`, one uint8 of CONTACT_* bits per robot), then advances the
    /// people, metrics, rewards, observations and planners into `out` and `people_out`. The
    /// GIL is released except while `physics` runs. Raises `InputError` for bad actions (before
    /// `physics` is called) or buffers; an exception raised by `physics` propagates.
    #[allow(clippy::too_many_arguments)]
    fn step(
        &mut self,
        py: Python<'_>,
        actions: &Bound<'_, PyAny>,
        physics: &Bound<'_, PyAny>,
        state: &Bound<'_, PyAny>,
        contacts: &Bound<'_, PyAny>,
        out: &Bound<'_, PyAny>,
        people_out: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        self.calls += 1;
        let w = &mut self.inner;
        two_phase_step(
            py,
            StepBuffers { actions, physics, state, contacts, out, people_out },
            w,
            |w, a, o| w.command(a, o),
            |w, s, c, o, p| w.step(s, c, o, p),
        )
    }

    /// Calls into the core since the world was built: `step` and `reset` calls (a diagnostic:
    /// one per control step and per episode start).
    #[getter]
    fn calls(&self) -> u64 {
        self.calls
    }

    /// Chooses which robots' built-in planners run (one bool per robot; all by default). A
    /// robot whose planner is off is driven only by `command` (its `planner_action` is a stop
    /// command); it saves the planner's cost when a policy drives it. Kept across resets.
    fn set_planning(&mut self, py: Python<'_>, planning: Vec<bool>) -> PyResult<()> {
        let w = &mut self.inner;
        enter_core(py, move || w.set_planning(&planning))
    }

    /// Every metric of every robot's episode so far (`docs/metrics.md`): a list with one dict
    /// per robot, the outcome and one key per metric (undefined values as None; `d_min` per
    /// person and `psi_object_active` / `psi_object_any` per object with an interaction space as lists).
    /// With `robots` (indices), only those robots' dicts, in that order.
    #[pyo3(signature = (robots = None))]
    fn episode_metrics<'py>(
        &self,
        py: Python<'py>,
        robots: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let robots = robots.filter(|r| !r.is_none()).map(robot_indices).transpose()?;
        let w = &self.inner;
        let reports = enter_core(py, move || match &robots {
            Some(r) => w.robot_metrics(r),
            None => w.episode_metrics(),
        })?;
        to_py(py, "the episode metrics", &reports)
    }

    /// The plain A* path from robot `robot`'s episode start to its goal (Daza et al. 2021's
    /// reference path of `l_ratio`, `smooth_rad2` and `smooth_rad`), as a (K, 2) float64 array.
    fn astar_path<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points_to_array(py, self.of_robot(py, robot, "A* path", CoreWorld::astar_path)?)
    }

    /// Robot `robot`'s poses x, y, theta (m, m, rad, world frame) at every control instant of
    /// the episode so far, the start first, as a (T + 1, 3) float64 array (what its metrics are
    /// computed from; steps after its episode ended are not recorded).
    fn trajectory<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let poses = self.of_robot(py, robot, "trajectory", CoreWorld::trajectory)?;
        let flat: Vec<f64> = poses.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([poses.len(), 3])
    }

    /// The global path robot `robot` is following, as a (K, 2) float64 array.
    fn path<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points_to_array(py, self.of_robot(py, robot, "path", CoreWorld::path)?)
    }

    /// Plans a path for robot `robot`'s footprint: plain A* on the inflated static map, or with
    /// `social=True` social A* on the social cost map (people as perceived now, object spaces at
    /// R(`time_of_day`), default the current time of day). None if there is no path.
    #[pyo3(signature = (robot, start, goal, social = false, time_of_day = None))]
    fn plan<'py>(
        &mut self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
        start: (f64, f64),
        goal: (f64, f64),
        social: bool,
        time_of_day: Option<f64>,
    ) -> PyResult<Option<Bound<'py, PyArray2<f64>>>> {
        let robot = self.robot(py, robot)?;
        let (s, g) = (finite_point(py, "start", start)?, finite_point(py, "goal", goal)?);
        let tod = self.time_of_day_or_now(py, time_of_day)?;
        let w = &mut self.inner;
        let plan = move || if social { w.plan_social(robot, s, g, tod) } else { Ok(w.plan(robot, s, g)) };
        let path = enter_core(py, plan)?;
        match path {
            Some(p) => Ok(Some(points_to_array(py, &p)?)),
            None => Ok(None),
        }
    }

    /// Robot `robot`'s social cost map now (people as perceived now, object spaces at
    /// R(`time_of_day`), default the current time of day), as a dict of (H, W) arrays, row 0 the
    /// lowest y: `static` (uint8, 254 obstacles, 253 inflation), `people` and `objects` (float64
    /// traversal factors, 1 free, inf forbidden), `combined` (uint8, what social A* searches),
    /// plus `grid` (origin_x, origin_y, resolution) and `weight` (the A* cost weight).
    #[pyo3(signature = (robot = 0, time_of_day = None))]
    fn social_layers<'py>(
        &mut self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
        time_of_day: Option<f64>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let robot = self.robot(py, robot)?;
        let tod = self.time_of_day_or_now(py, time_of_day)?;
        {
            let w = &mut self.inner;
            enter_core(py, move || w.update_social_map(robot, tod))?;
        }
        let spec = self.of_robot(py, robot, "cost grid", CoreWorld::cost_grid)?.spec;
        let map = self.inner.social_map_of(robot).ok_or_else(|| missing(py, "social map"))?;
        let shape = [spec.height, spec.width];
        let d = PyDict::new(py);
        d.set_item("static", PyArray1::from_slice(py, &map.static_layer().cost).reshape(shape)?)?;
        d.set_item("people", PyArray1::from_slice(py, map.people_layer()).reshape(shape)?)?;
        d.set_item("objects", PyArray1::from_slice(py, map.object_layer()).reshape(shape)?)?;
        d.set_item("combined", PyArray1::from_slice(py, &map.grid().cost).reshape(shape)?)?;
        d.set_item("grid", to_py(py, "the grid", &(spec.origin.x, spec.origin.y, spec.resolution))?)?;
        d.set_item("weight", to_py(py, "the weight", &map.costs().weight())?)?;
        Ok(d)
    }

    /// What the robots perceive of the people now: `labels` (group index per person),
    /// `groups` (member lists), `robot_joins` (group joined per robot, or None), `individuals`
    /// (dicts with centre, heading, sides = [front, rear, right, left] sigmas, members, robots),
    /// `truth` (the scenario's group id per person, or None) and `accuracy` (precision, recall,
    /// f1 of the detected groups against the truth, GCFF's threshold 2/3; absent when it cannot
    /// be scored).
    fn perception<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let w = &mut self.inner;
        let report = enter_core(py, move || w.perception_report())?;
        to_py(py, "the perception", &report)
    }

    /// R(t) of every object with an interaction space at `time_of_day` (seconds after midnight,
    /// default the current time of day), as a dict name -> cost: the agenda's idle cost outside
    /// activities, up to its active cost during one (Calderita: 1.5 and 3.5).
    #[pyo3(signature = (time_of_day = None))]
    fn object_costs<'py>(&self, py: Python<'py>, time_of_day: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
        let tod = self.time_of_day_or_now(py, time_of_day)?;
        let social = self.inner.social();
        let costs = enter_core(py, || Ok(social.object_factors(tod)))?;
        let named: Vec<(&str, f64)> = social.object_names().iter().map(String::as_str).zip(costs).collect();
        to_py(py, "the object costs", &Named(&named))
    }

    /// How many times robot `robot`'s social path was (re-)planned this episode.
    fn replans(&self, py: Python<'_>, #[pyo3(from_py_with = robot_index)] robot: usize) -> PyResult<usize> {
        let robot = self.robot(py, robot)?;
        Ok(self.inner.replans(robot))
    }

    /// How many social searches ran for robot `robot` this episode: its first plan, its
    /// triggered re-plans and its refreshes, whether the new path was kept or not (0 for a robot
    /// that is not on a social planner). At least :meth:`replans`.
    fn social_searches(
        &self,
        py: Python<'_>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<usize> {
        let robot = self.robot(py, robot)?;
        Ok(self.inner.social_searches(robot))
    }

    /// Calderita et al.'s zone of each point of `track` ((T, 2) float64, m) among `people[t]`
    /// ((T, P, 3) float64: x, y in m, heading in rad): the contours of the summed density `G_d`
    /// (their §4.1, the zones the `calderita` planner plans on, with this world's density
    /// parameters and contour levels), where Hall's zones are circles. A (T,) uint8 array:
    /// 0 intimate, 1 personal, 2 social, 3 public. Raises `InputError` naming the argument for a
    /// wrong shape or a non-finite value.
    fn density_zones_along<'py>(
        &self,
        py: Python<'py>,
        track: PyReadonlyArray2<'py, f64>,
        people: PyReadonlyArray3<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<u8>>> {
        use proxemic_core::groups::PersonState;
        use proxemic_core::math::Vec2;
        use proxemic_core::proxemics::Zone;
        let (ts, ps) = (track.shape().to_vec(), people.shape().to_vec());
        if ts.len() != 2 || ts[1] != 2 {
            return Err(input_err(py, "track", "a (T, 2) float64 array (m)".into(), format!("shape {ts:?}")));
        }
        if ps.len() != 3 || ps[0] != ts[0] || ps[2] != 3 {
            return Err(input_err(
                py,
                "people",
                format!(
                    "a ({}, P, 3) float64 array (x, y in m, heading in rad), one row per track point",
                    ts[0]
                ),
                format!("shape {ps:?}"),
            ));
        }
        let (track, people) = (track.as_array(), people.as_array());
        if let Some(v) = track.iter().find(|v| !v.is_finite()) {
            return Err(input_err(py, "track", "finite coordinates".into(), format!("{v}")));
        }
        if let Some(v) = people.iter().find(|v| !v.is_finite()) {
            return Err(input_err(py, "people", "finite values".into(), format!("{v}")));
        }
        let zones = *self.inner.social().density_zones();
        let mut out = Vec::with_capacity(ts[0]);
        let mut crowd: Vec<PersonState> = Vec::with_capacity(ps[1]);
        for t in 0..ts[0] {
            crowd.clear();
            crowd.extend((0..ps[1]).map(|k| PersonState {
                pos: Vec2::new(people[[t, k, 0]], people[[t, k, 1]]),
                heading: people[[t, k, 2]],
                vel: Vec2::zeros(),
            }));
            let zone = zones.zone_of(&crowd, Vec2::new(track[[t, 0]], track[[t, 1]]));
            out.push(match zone {
                Zone::Intimate => 0,
                Zone::Personal => 1,
                Zone::Social => 2,
                Zone::Public => 3,
            });
        }
        Ok(PyArray1::from_vec(py, out))
    }

    /// The people now: (P, 6) float64 of x, y, heading, vx, vy, radius.
    fn people<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let c = self.inner.crowd();
        let mut data = Vec::with_capacity(c.len() * 6);
        for k in 0..c.len() {
            data.extend_from_slice(&[
                c.pos[k].x,
                c.pos[k].y,
                c.heading[k],
                c.vel[k].x,
                c.vel[k].y,
                c.radius[k],
            ]);
        }
        PyArray1::from_vec(py, data).reshape([c.len(), 6])
    }

    /// Robot `robot`'s inflated cost grid as ((H, W) uint8 array, (origin_x, origin_y,
    /// resolution)); row 0 is the lowest y. 254 marks static obstacles, 253 the inflation.
    fn cost_grid<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyTuple>> {
        let g = self.of_robot(py, robot, "cost grid", CoreWorld::cost_grid)?;
        let arr = PyArray1::from_slice(py, &g.cost).reshape([g.spec.height, g.spec.width])?;
        let meta = to_py(py, "the grid", &(g.spec.origin.x, g.spec.origin.y, g.spec.resolution))?;
        PyTuple::new(py, [arr.into_any(), meta])
    }

    /// Geodesic shortest collision-free distance from robot `robot`'s nominal start to its goal (m).
    fn geodesic_start_distance(
        &self,
        py: Python<'_>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<f64> {
        let robot = self.robot(py, robot)?;
        self.inner.geodesic_start_distance(robot).ok_or_else(|| missing(py, "geodesic distance"))
    }
}
