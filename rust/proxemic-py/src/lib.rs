//! Python bindings of `proxemic-core`, exposed as `proxemic._core`.
//!
//! This crate is deliberately thin: it checks array shapes and dtypes, releases the GIL around
//! the core's work, and maps every [`CoreError`] to one exception class of the hierarchy defined
//! in `proxemic/errors.py` (all under `proxemic.ProxemicError`). A Rust panic would be a bug; as
//! a last line of defence it is caught and re-raised as `proxemic.ProxemicError` rather than
//! reaching Python as a `PanicException`.
//!
//! # Threading model
//! `World.reset` and `World.step` copy nothing: they borrow the numpy buffers (read-only for
//! inputs, read-write for outputs), release the GIL while the core runs, and reacquire it before
//! returning (`World.step` also to call the Python physics between its two halves, with no
//! buffer borrowed). A `World` can be moved to and called from any thread (vector envs and thread
//! pools move envs); pyo3's borrow checking refuses two threads inside the same `World` at once.
//! `step_worlds` is `World.step` of several worlds in one call (a vector env's step): the physics
//! callback runs once for all of them, then the worlds' second halves run in scoped threads
//! (`proxemic_core::world::batch`).

mod validation;

use std::panic::{AssertUnwindSafe, catch_unwind};

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadwriteArray1};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::Scenario as CoreScenario;
use proxemic_core::world::{self, World as CoreWorld};

/// Raises the Python exception matching a core error (class looked up in `proxemic.errors`).
fn to_py_err(py: Python<'_>, e: CoreError) -> PyErr {
    let (class, file, field, expected, found) = match &e {
        CoreError::Scenario { file, field, expected, found } => {
            ("ScenarioError", Some(file.clone()), field.clone(), Some(expected.clone()), Some(found.clone()))
        }
        CoreError::Input { field, expected, found } => {
            ("InputError", None, field.clone(), Some(expected.clone()), Some(found.clone()))
        }
        CoreError::Planning { file, field, message } => {
            ("PlanningError", Some(file.clone()), field.clone(), None, Some(message.clone()))
        }
        CoreError::Invariant { episode, invariant, detail } => {
            ("InvariantError", Some(episode.clone()), invariant.clone(), None, Some(detail.clone()))
        }
    };
    let message = e.to_string();
    let build = || -> PyResult<PyErr> {
        let cls = py.import("proxemic.errors")?.getattr(class)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("file", file)?;
        kwargs.set_item("field", field)?;
        kwargs.set_item("expected", expected)?;
        kwargs.set_item("found", found)?;
        let inst = cls.call((message.clone(),), Some(&kwargs))?;
        Ok(PyErr::from_value(inst))
    };
    build().unwrap_or_else(|err| err)
}

/// Runs core work with the GIL released; maps errors and panics to Python exceptions.
fn enter_core<T: Send>(py: Python<'_>, f: impl FnOnce() -> Result<T, CoreError> + Send) -> PyResult<T> {
    let result = py.detach(|| catch_unwind(AssertUnwindSafe(f)));
    match result {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py_err(py, e)),
        Err(_) => Err(internal_error(py)),
    }
}

fn internal_error(py: Python<'_>) -> PyErr {
    let make = || -> PyResult<PyErr> {
        let cls = py.import("proxemic.errors")?.getattr("ProxemicError")?;
        Ok(PyErr::from_value(cls.call1(("internal error in the Rust core (a bug: please report it)",))?))
    };
    make().unwrap_or_else(|_| PyRuntimeError::new_err("internal error in the Rust core"))
}

fn input_err(py: Python<'_>, field: &str, expected: String, found: String) -> PyErr {
    to_py_err(py, CoreError::input(field, expected, found))
}

/// A robot index argument: a negative or too large Python int is an `InputError` naming `robot`
/// and what arrived (pyo3 alone raises `OverflowError`); a non-int keeps pyo3's `TypeError`.
fn robot_index(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    obj.extract::<usize>().map_err(|e| {
        if obj.is_instance_of::<pyo3::types::PyInt>() {
            input_err(obj.py(), "robot", "a robot index, an integer >= 0".into(), obj.to_string())
        } else {
            e
        }
    })
}

/// A seed argument: a negative Python int or one of 2**64 or more is an `InputError` naming
/// `seed` and what arrived (pyo3 alone raises `OverflowError`).
fn seed_arg(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    obj.extract::<u64>().map_err(|e| {
        if obj.is_instance_of::<pyo3::types::PyInt>() {
            input_err(obj.py(), "seed", "an integer in [0, 2**64)".into(), obj.to_string())
        } else {
            e
        }
    })
}

/// `obj` as a one-dimensional numpy array of `T`, or an `InputError` naming `field` that says
/// what arrived (a float32 state buffer, a list, a 2-D array...).
fn array_of<'py, T: numpy::Element>(
    py: Python<'py>,
    field: &str,
    dtype: &str,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyArray1<T>>> {
    if let Ok(a) = obj.cast::<PyArray1<T>>() {
        return Ok(a.clone());
    }
    let found = match (obj.getattr("dtype"), obj.getattr("ndim")) {
        (Ok(d), Ok(n)) => format!("a {n}-dimensional {d} array"),
        _ => format!("a {}", obj.get_type().name().map_or_else(|_| "value".into(), |n| n.to_string())),
    };
    Err(input_err(py, field, format!("a one-dimensional C-contiguous {dtype} numpy array"), found))
}

/// An `InputError` for a buffer that is already borrowed (the same array passed twice).
fn busy(py: Python<'_>, field: &str) -> PyErr {
    input_err(py, field, "a float64 or uint8 array not borrowed elsewhere".into(), "a borrowed array".into())
}

/// The elastic band's tunable gains, the keyword names of `Scenario.with_eband_gains`.
const EBAND_GAINS: [&str; 3] = ["contraction_gain", "repulsion_gain", "social_gain"];

/// A validated scenario (parsed once, from a TOML file or string).
#[pyclass(module = "proxemic._core", name = "Scenario", frozen)]
struct PyScenario {
    inner: CoreScenario,
}

#[pymethods]
impl PyScenario {
    /// Reads and validates a scenario file. Raises `ScenarioError` naming the file and field.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Self> {
        let inner = enter_core(py, || CoreScenario::from_file(&path))?;
        Ok(PyScenario { inner })
    }

    /// Parses and validates scenario TOML text; `source` names it in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, source = "<string>"))]
    fn from_toml(py: Python<'_>, text: &str, source: &str) -> PyResult<Self> {
        let text = text.to_string();
        let source = source.to_string();
        let inner = enter_core(py, move || CoreScenario::from_toml_str(&text, &source))?;
        Ok(PyScenario { inner })
    }

    /// A copy whose robots all use the built-in planner `name` (see `PLANNERS`).
    fn with_planner(&self, py: Python<'_>, name: &str) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_planner(name))?;
        Ok(PyScenario { inner })
    }

    /// A copy whose robot `index` uses the built-in planner `name` (see `PLANNERS`).
    fn with_robot_planner(&self, py: Python<'_>, index: usize, name: &str) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_robot_planner(index, name))?;
        Ok(PyScenario { inner })
    }

    /// A copy with only the first `n` robots (1 <= n <= the file's `[[robot]]` entries).
    /// Raises `ScenarioError` naming `robots` for any other count, negative ones included.
    fn with_robots(&self, py: Python<'_>, n: i64) -> PyResult<Self> {
        let inner = enter_core(py, || match usize::try_from(n) {
            Ok(k) => self.inner.with_robots(k),
            // The core's error for a count below 1, saying what arrived.
            Err(_) => self.inner.with_robots(0).map_err(|e| match e {
                CoreError::Scenario { file, field, expected, .. } => {
                    CoreError::Scenario { file, field, expected, found: n.to_string() }
                }
                other => other,
            }),
        })?;
        Ok(PyScenario { inner })
    }

    /// Number of robots.
    #[getter]
    fn num_robots(&self) -> usize {
        self.inner.robots.len()
    }

    /// A copy whose robots' elastic-band gains (dimensionless, each in [0, 100]; used by the
    /// `eband` planner; names in `EBAND_GAINS`) are replaced where given. Raises `ScenarioError`
    /// naming the gain (`eband.<gain>`) for a value out of range or an unknown gain name.
    #[pyo3(signature = (contraction_gain = None, repulsion_gain = None, social_gain = None, **unknown))]
    fn with_eband_gains(
        &self,
        py: Python<'_>,
        contraction_gain: Option<f64>,
        repulsion_gain: Option<f64>,
        social_gain: Option<f64>,
        unknown: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Self> {
        let mut names: Vec<String> = Vec::new();
        if let Some(d) = unknown {
            for key in d.keys() {
                names.push(key.str()?.to_string());
            }
        }
        names.sort();
        let source = &self.inner.source;
        let inner = enter_core(py, || match names.first() {
            Some(name) => Err(CoreError::Scenario {
                file: source.clone(),
                field: format!("eband.{name}"),
                expected: format!("an elastic-band gain among {EBAND_GAINS:?}"),
                found: format!("{name:?}"),
            }),
            None => self.inner.with_eband_gains(contraction_gain, repulsion_gain, social_gain),
        })?;
        Ok(PyScenario { inner })
    }

    /// A copy whose robot `robot` goes to `goal` (x, y in metres, inside the scene's bounds)
    /// instead of its file goal. Raises `ScenarioError`; a goal inside a wall or object is
    /// rejected when a `World` is built.
    #[pyo3(signature = (goal, robot = 0))]
    fn with_goal(
        &self,
        py: Python<'_>,
        goal: [f64; 2],
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_goal(robot, goal))?;
        Ok(PyScenario { inner })
    }

    /// A copy whose episode starts at `time` of day (`"HH:MM"`, `"HH:MM:SS"` or seconds after
    /// midnight in [0, 86400)) instead of the file's `scene.start_time`: the agenda's activities
    /// fall at another point of the episode; times the scenario holds as seconds into the
    /// episode keep their value (a conversation's `start` and `end`, even written as times of
    /// day in the file). Raises `InputError` naming `time_of_day` for a malformed time.
    fn with_start_time(&self, py: Python<'_>, time: TimeOfDay) -> PyResult<Self> {
        let t = time.seconds(py)?;
        let inner = enter_core(py, || self.inner.with_start_time(t))?;
        Ok(PyScenario { inner })
    }

    /// The validated scenario as JSON (defaults filled in, world polygons computed).
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        enter_core(py, || Ok(self.inner.to_json()))
    }

    /// Scene name.
    #[getter]
    fn name(&self) -> String {
        self.inner.scene.name.clone()
    }

    /// Where the scenario was read from.
    #[getter]
    fn source(&self) -> String {
        self.inner.source.clone()
    }

    /// Control period (s).
    #[getter]
    fn control_dt(&self) -> f64 {
        self.inner.control_dt()
    }

    /// Physics steps per control step.
    #[getter]
    fn frame_skip(&self) -> usize {
        self.inner.frame_skip()
    }

    /// Maximum control steps per episode.
    #[getter]
    fn max_steps(&self) -> usize {
        self.inner.max_steps()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario(name={:?}, source={:?}, robots={}, people={})",
            self.inner.scene.name,
            self.inner.source,
            self.inner.robots.len(),
            self.inner.persons.len()
        )
    }
}

/// The simulated world of a scenario: people, planners, metrics, observations and rewards.
///
/// Buffers: `out` is a C-contiguous float64 array of `num_robots * stride` values (use
/// `layout` to slice it), `people_out` a C-contiguous float64 array of `num_people * PERSON_OUT`
/// values (x, y, heading, contact hint). Both are one-dimensional.
#[pyclass(module = "proxemic._core", name = "World")]
struct PyWorld {
    inner: CoreWorld,
    /// `step` and `reset` calls so far (see `calls`).
    calls: u64,
}

fn flat_mut<'a>(
    py: Python<'_>,
    name: &str,
    arr: &'a mut PyReadwriteArray1<'_, f64>,
) -> PyResult<&'a mut [f64]> {
    arr.as_slice_mut().map_err(|_| {
        input_err(py, name, "a C-contiguous float64 array".into(), "a non-contiguous array".into())
    })
}

/// `p` as a point, or an `InputError` naming `field` when a coordinate is not finite.
fn finite_point(py: Python<'_>, field: &str, p: (f64, f64)) -> PyResult<Vec2> {
    if p.0.is_finite() && p.1.is_finite() {
        Ok(Vec2::new(p.0, p.1))
    } else {
        Err(input_err(
            py,
            field,
            "a point (x, y) of finite numbers (m)".into(),
            format!("({}, {})", p.0, p.1),
        ))
    }
}

impl PyWorld {
    /// `time_of_day` (seconds after midnight in [0, 86400)) or, when `None`, the world's time of
    /// day now; an `InputError` naming `time_of_day` otherwise (a NaN gave NaN costs).
    fn time_of_day_or_now(&self, py: Python<'_>, time_of_day: Option<f64>) -> PyResult<f64> {
        match time_of_day {
            None => Ok(self.inner.time_of_day()),
            Some(t) if t.is_finite() && (0.0..86400.0).contains(&t) => Ok(t),
            Some(t) => Err(input_err(
                py,
                "time_of_day",
                "seconds after midnight in [0, 86400)".into(),
                t.to_string(),
            )),
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
    /// core, reported as an internal error).
    fn of_robot<'s, T: ?Sized>(
        &'s self,
        py: Python<'_>,
        robot: usize,
        get: impl FnOnce(&'s CoreWorld, usize) -> Option<&'s T>,
    ) -> PyResult<&'s T> {
        let i = self.robot(py, robot)?;
        get(&self.inner, i).ok_or_else(|| internal_error(py))
    }
}

/// A time of day from Python: `"HH:MM"`, `"HH:MM:SS"` or seconds after midnight.
#[derive(FromPyObject)]
enum TimeOfDay {
    Text(String),
    Seconds(f64),
}

impl TimeOfDay {
    /// Seconds after midnight in [0, 86400), or an `InputError` naming `time_of_day`.
    fn seconds(&self, py: Python<'_>) -> PyResult<f64> {
        let t = match self {
            TimeOfDay::Text(s) => proxemic_core::scenario::parse_time_of_day(s),
            TimeOfDay::Seconds(x) => Some(*x).filter(|x| x.is_finite() && (0.0..86400.0).contains(x)),
        };
        t.ok_or_else(|| {
            let found = match self {
                TimeOfDay::Text(s) => format!("{s:?}"),
                TimeOfDay::Seconds(x) => x.to_string(),
            };
            input_err(
                py,
                "time_of_day",
                "\"HH:MM\", \"HH:MM:SS\" or seconds after midnight in [0, 86400)".into(),
                found,
            )
        })
    }
}

/// Seconds after midnight of `value` (`"HH:MM"`, `"HH:MM:SS"` or a number of seconds in
/// [0, 86400)), parsed as scenario files are. Raises `InputError` naming `time_of_day`.
#[pyfunction]
fn parse_time_of_day(py: Python<'_>, value: TimeOfDay) -> PyResult<f64> {
    value.seconds(py)
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
    fn layout<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, s) in self.inner.layout().sections() {
            d.set_item(name, (s.offset, s.len))?;
        }
        Ok(d)
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
        robots: Option<Vec<usize>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let w = &self.inner;
        let text = enter_core(py, move || {
            match &robots {
                Some(r) => w.robot_metrics(r),
                None => w.episode_metrics(),
            }
            .map(|m| serde_json_string(&m))
        })?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// The plain A* path from robot `robot`'s episode start to its goal (Daza et al. 2021's
    /// reference path of `l_ratio`, `smooth_rad2` and `smooth_rad`), as a (K, 2) float64 array.
    fn astar_path<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points_to_array(py, self.of_robot(py, robot, CoreWorld::astar_path)?)
    }

    /// Robot `robot`'s poses x, y, theta (m, m, rad, world frame) at every control instant of
    /// the episode so far, the start first, as a (T + 1, 3) float64 array (what its metrics are
    /// computed from; steps after its episode ended are not recorded).
    fn trajectory<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let poses = self.of_robot(py, robot, CoreWorld::trajectory)?;
        let flat: Vec<f64> = poses.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([poses.len(), 3])
    }

    /// The global path robot `robot` is following, as a (K, 2) float64 array.
    fn path<'py>(
        &self,
        py: Python<'py>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        points_to_array(py, self.of_robot(py, robot, CoreWorld::path)?)
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
        let spec = self.of_robot(py, robot, CoreWorld::cost_grid)?.spec;
        let map = self.inner.social_map_of(robot).ok_or_else(|| internal_error(py))?;
        let shape = [spec.height, spec.width];
        let d = PyDict::new(py);
        d.set_item("static", PyArray1::from_slice(py, &map.static_layer().cost).reshape(shape)?)?;
        d.set_item("people", PyArray1::from_slice(py, map.people_layer()).reshape(shape)?)?;
        d.set_item("objects", PyArray1::from_slice(py, map.object_layer()).reshape(shape)?)?;
        d.set_item("combined", PyArray1::from_slice(py, &map.grid().cost).reshape(shape)?)?;
        d.set_item("grid", (spec.origin.x, spec.origin.y, spec.resolution))?;
        d.set_item("weight", map.costs().weight())?;
        Ok(d)
    }

    /// What the robots perceive of the people now: `labels` (group index per person),
    /// `groups` (member lists), `robot_joins` (group joined per robot, or None), `individuals`
    /// (dicts with centre, heading, sides = [front, rear, right, left] sigmas, members, robots),
    /// `truth` (the scenario's group id per person, or None) and `accuracy` (precision, recall,
    /// f1 of the detected groups against the truth, threshold 2/3).
    fn perception<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        {
            let w = &mut self.inner;
            enter_core(py, move || w.perceive())?;
        }
        let per = self.inner.social().perception().ok_or_else(|| internal_error(py))?;
        let d = PyDict::new(py);
        d.set_item("labels", per.groups.labels.clone())?;
        d.set_item("groups", per.groups.members.clone())?;
        d.set_item("robot_joins", per.robot_joins.clone())?;
        let inds = pyo3::types::PyList::empty(py);
        for ind in &per.individuals {
            let e = PyDict::new(py);
            e.set_item("centre", (ind.centre.x, ind.centre.y))?;
            e.set_item("heading", ind.heading)?;
            e.set_item("sides", (ind.sides.front, ind.sides.rear, ind.sides.right, ind.sides.left))?;
            e.set_item("members", ind.members.clone())?;
            e.set_item("robots", ind.robots.clone())?;
            inds.append(e)?;
        }
        d.set_item("individuals", inds)?;
        // Ground truth beside the detection (the scenario's group ids) and the GCFF-style score
        // (a detected group matches a true one with >= 2/3 of its members and <= 1/3 outsiders).
        let truth: Vec<Option<u32>> = self.inner.scenario().persons.iter().map(|p| p.group).collect();
        d.set_item("truth", truth.clone())?;
        let labels = &per.groups.labels;
        let accuracy =
            enter_core(py, || Ok(proxemic_core::groups::detection_accuracy(labels, &truth, 2.0 / 3.0).ok()))?;
        if let Some(acc) = accuracy {
            let a = PyDict::new(py);
            a.set_item("precision", acc.precision)?;
            a.set_item("recall", acc.recall)?;
            a.set_item("f1", acc.f1)?;
            a.set_item("true_positives", acc.true_positives)?;
            a.set_item("detected", acc.detected)?;
            a.set_item("truth", acc.truth)?;
            d.set_item("accuracy", a)?;
        }
        Ok(d)
    }

    /// R(t) of every object with an interaction space at `time_of_day` (seconds after midnight,
    /// default the current time of day), as a dict name -> cost: the agenda's idle cost outside
    /// activities, up to its active cost during one (Calderita: 1.5 and 3.5).
    #[pyo3(signature = (time_of_day = None))]
    fn object_costs<'py>(&self, py: Python<'py>, time_of_day: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let tod = self.time_of_day_or_now(py, time_of_day)?;
        let social = self.inner.social();
        let costs = enter_core(py, || Ok(social.object_factors(tod)))?;
        let d = PyDict::new(py);
        for (name, cost) in social.object_names().iter().zip(costs) {
            d.set_item(name, cost)?;
        }
        Ok(d)
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
        let g = self.of_robot(py, robot, CoreWorld::cost_grid)?;
        let arr = PyArray1::from_slice(py, &g.cost).reshape([g.spec.height, g.spec.width])?;
        let meta = (g.spec.origin.x, g.spec.origin.y, g.spec.resolution);
        PyTuple::new(py, [arr.into_any(), meta.into_pyobject(py)?.into_any()])
    }

    /// Geodesic shortest collision-free distance from robot `robot`'s nominal start to its goal (m).
    fn geodesic_start_distance(
        &self,
        py: Python<'_>,
        #[pyo3(from_py_with = robot_index)] robot: usize,
    ) -> PyResult<f64> {
        let robot = self.robot(py, robot)?;
        self.inner.geodesic_start_distance(robot).ok_or_else(|| internal_error(py))
    }
}

/// Several worlds stepped as one call (a vector env's step): `World.step` of every world in
/// `worlds` (distinct `World`s, usually of one scenario), with each kind of buffer holding every
/// world's values end to end, world 0 first (`actions`: 3 per robot; `state`: 6 per robot;
/// `contacts`: one uint8 per robot; `out`: `num_robots * stride` per world; `people_out`:
/// `num_people * PERSON_OUT` per world). Executes every world's actions into `out`'s `command`,
/// calls `physics()` once (it must run every world's physics and fill `state` and `contacts`),
/// then advances every world in up to `threads` threads (default: the machine's cores; never
/// more than the worlds; the results are those of stepping the worlds one by one). The GIL is
/// released except while `physics` runs. Raises `InputError` naming the world
/// (`worlds[k].<field>`) for bad actions or state, before any world changes.
#[pyfunction]
#[pyo3(signature = (worlds, actions, physics, state, contacts, out, people_out, threads = None))]
#[allow(clippy::too_many_arguments)]
fn step_worlds(
    py: Python<'_>,
    worlds: &Bound<'_, PyAny>,
    actions: &Bound<'_, PyAny>,
    physics: &Bound<'_, PyAny>,
    state: &Bound<'_, PyAny>,
    contacts: &Bound<'_, PyAny>,
    out: &Bound<'_, PyAny>,
    people_out: &Bound<'_, PyAny>,
    threads: Option<usize>,
) -> PyResult<()> {
    let list: Vec<Bound<'_, PyWorld>> = worlds.extract().map_err(|_| {
        input_err(
            py,
            "worlds",
            "a sequence of proxemic._core.World".into(),
            worlds.repr().map_or_else(|_| "?".into(), |r| r.to_string()),
        )
    })?;
    let mut refs = Vec::with_capacity(list.len());
    for (k, w) in list.iter().enumerate() {
        let r = w.try_borrow_mut().map_err(|_| {
            input_err(
                py,
                &format!("worlds[{k}]"),
                "distinct worlds, each in use nowhere else".into(),
                "a world given twice or in use".into(),
            )
        })?;
        refs.push(r);
    }
    for r in &mut refs {
        r.calls += 1;
    }
    let mut cores: Vec<&mut CoreWorld> = refs.iter_mut().map(|r| &mut r.inner).collect();
    let threads = threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get));
    two_phase_step(
        py,
        StepBuffers { actions, physics, state, contacts, out, people_out },
        &mut cores[..],
        world::batch::command_batch,
        |ws, s, c, o, p| world::batch::step_batch(ws, s, c, o, p, threads),
    )
}

/// The Python buffers of one control step (`World.step`, `step_worlds`).
struct StepBuffers<'a, 'py> {
    actions: &'a Bound<'py, PyAny>,
    physics: &'a Bound<'py, PyAny>,
    state: &'a Bound<'py, PyAny>,
    contacts: &'a Bound<'py, PyAny>,
    out: &'a Bound<'py, PyAny>,
    people_out: &'a Bound<'py, PyAny>,
}

/// One control step in two phases around the Python physics callback: checks the buffers (an
/// `InputError` naming the field for a wrong dtype, shape, layout or a borrowed array), runs
/// `command(target, actions, out)` without the GIL, calls `physics()` with it, then runs
/// `step(target, state, contacts, out, people_out)` without the GIL.
fn two_phase_step<W: Send + ?Sized>(
    py: Python<'_>,
    b: StepBuffers<'_, '_>,
    target: &mut W,
    command: impl FnOnce(&mut W, &[f64], &mut [f64]) -> Result<(), CoreError> + Send,
    step: impl FnOnce(&mut W, &[f64], &[u8], &mut [f64], &mut [f64]) -> Result<(), CoreError> + Send,
) -> PyResult<()> {
    let contiguous = |field: &str| {
        let dtype = if field == "contacts" { "uint8" } else { "float64" };
        input_err(py, field, format!("a C-contiguous {dtype} array"), "a non-contiguous array".into())
    };
    let actions = array_of::<f64>(py, "actions", "float64", b.actions)?;
    let state = array_of::<f64>(py, "state", "float64", b.state)?;
    let contacts = array_of::<u8>(py, "contacts", "uint8", b.contacts)?;
    let out = array_of::<f64>(py, "out", "float64", b.out)?;
    let people_out = array_of::<f64>(py, "people_out", "float64", b.people_out)?;
    {
        let actions = actions.try_readonly().map_err(|_| busy(py, "actions"))?;
        let a = actions.as_slice().map_err(|_| contiguous("actions"))?;
        let mut out_rw = out.try_readwrite().map_err(|_| busy(py, "out"))?;
        let o = flat_mut(py, "out", &mut out_rw)?;
        let t = &mut *target;
        enter_core(py, move || command(t, a, o))?;
    }
    b.physics.call0()?;
    let state_ro = state.try_readonly().map_err(|_| busy(py, "state"))?;
    let contacts_ro = contacts.try_readonly().map_err(|_| busy(py, "contacts"))?;
    let s = state_ro.as_slice().map_err(|_| contiguous("state"))?;
    let c = contacts_ro.as_slice().map_err(|_| contiguous("contacts"))?;
    let mut out_rw = out.try_readwrite().map_err(|_| busy(py, "out"))?;
    let mut people_rw = people_out.try_readwrite().map_err(|_| busy(py, "people_out"))?;
    let o = flat_mut(py, "out", &mut out_rw)?;
    let p = flat_mut(py, "people_out", &mut people_rw)?;
    enter_core(py, move || step(target, s, c, o, p))
}

/// The metric reference: one dict per key of an episode's metrics (`key`, `family`, `label`,
/// `unit`, `better` = "higher" | "lower" | "neither", `low` and `high` bounds or None, `per` =
/// "episode" | "person" | "object", `definition`, `formula`, `source`), in the reference's order.
#[pyfunction]
fn metric_registry(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    let text = serde_json_string(&proxemic_core::metrics::METRICS);
    py.import("json")?.call_method1("loads", (text,))
}

/// The JSON Schema of a scenario file (draft 2020-12), as JSON text: every table and field with
/// its type, default and description (the scenario reference of the docs; `proxemic schema`).
#[pyfunction]
fn scenario_schema() -> String {
    serde_json_string(&proxemic_core::scenario::json_schema())
}

fn serde_json_string<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string(v).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

fn points_to_array<'py>(py: Python<'py>, pts: &[Vec2]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    PyArray1::from_vec(py, flat).reshape([pts.len(), 2])
}

/// A generated scene from its spec `generated/<seed>[?key=value&...]` or
/// `francis2023/<archetype>[?seed=N&max_time=T]`: the validated scenario and its scenario file
/// text. Raises `ScenarioError` naming the seed, archetype or parameter that is wrong.
#[pyfunction]
fn generate(py: Python<'_>, spec: &str) -> PyResult<(PyScenario, String)> {
    let spec = spec.to_string();
    let g = enter_core(py, move || proxemic_core::scenario::generate::generate_spec(&spec))?;
    Ok((PyScenario { inner: g.scenario }, g.toml))
}

/// The compiled core of proxemic.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("CONTACT_PERSON", proxemic_core::metrics::CONTACT_PERSON)?;
    m.add("CONTACT_STATIC", proxemic_core::metrics::CONTACT_STATIC)?;
    m.add("CONTACT_ROBOT", proxemic_core::metrics::CONTACT_ROBOT)?;
    m.add("REWARD_TERMS", world::REWARD_TERMS.to_vec())?;
    m.add("PERSON_FEATURES", world::PERSON_FEATURES)?;
    m.add("ROBOT_FEATURES", world::ROBOT_FEATURES)?;
    m.add("PEER_FEATURES", world::PEER_FEATURES)?;
    m.add("OBS_MAX_SPEED", world::OBS_MAX_SPEED)?;
    m.add("OBS_MAX_ANGULAR", world::OBS_MAX_ANGULAR)?;
    m.add("PERSON_OUT", world::PERSON_OUT)?;
    m.add("CONTACT_RANGE", world::CONTACT_RANGE)?;
    m.add("PLANNERS", proxemic_core::scenario::PlannerKind::NAMES.to_vec())?;
    m.add("EBAND_GAINS", EBAND_GAINS.to_vec())?;
    m.add_class::<PyScenario>()?;
    m.add_class::<PyWorld>()?;
    m.add("GENERATE_PARAMS", proxemic_core::scenario::generate::PARAM_NAMES.to_vec())?;
    m.add("FRANCIS2023_ARCHETYPES", proxemic_core::scenario::generate::francis2023::ARCHETYPES.to_vec())?;
    m.add_function(wrap_pyfunction!(parse_time_of_day, m)?)?;
    m.add_function(wrap_pyfunction!(step_worlds, m)?)?;
    m.add_function(wrap_pyfunction!(metric_registry, m)?)?;
    m.add_function(wrap_pyfunction!(scenario_schema, m)?)?;
    m.add_function(wrap_pyfunction!(generate, m)?)?;
    validation::register(m)?;
    Ok(())
}
