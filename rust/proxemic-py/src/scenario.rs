//! `Scenario`: a validated scenario and its overrides; generated scenes; times of day.

use pyo3::prelude::*;
use pyo3::types::PyDict;

use proxemic_core::CoreError;
use proxemic_core::scenario::{Scenario as CoreScenario, TimeOfDay as CoreTimeOfDay};

use crate::conversions::{TimeOfDay, int_in_range, robot_index, to_json_text};
use crate::errors::{enter_core, input_err};

/// A validated scenario (parsed once, from a TOML file or string).
#[pyclass(module = "proxemic._core", name = "Scenario", frozen)]
pub(crate) struct PyScenario {
    pub(crate) inner: CoreScenario,
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

    /// A copy whose robots all have the drive `name` (`"holonomic"` or `"differential"`).
    fn with_drive(&self, py: Python<'_>, name: &str) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_drive(name))?;
        Ok(PyScenario { inner })
    }

    /// A copy whose robot `index` uses the built-in planner `name` (see `PLANNERS`).
    fn with_robot_planner(
        &self,
        py: Python<'_>,
        #[pyo3(from_py_with = robot_index)] index: usize,
        name: &str,
    ) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_robot_planner(index, name))?;
        Ok(PyScenario { inner })
    }

    /// A copy with `n` robots, 1 <= n <= the larger of the file's `[[robot]]` entries and
    /// `MAX_ROBOTS` (8): the file's first `n`, then sampled ones (see the core's
    /// `Scenario::with_robots`). Raises `ScenarioError` naming `robots` for any other count,
    /// negative and huge ones included.
    fn with_robots(&self, py: Python<'_>, n: &Bound<'_, PyAny>) -> PyResult<Self> {
        let count = int_in_range(n)?.and_then(|k| usize::try_from(k).ok());
        let shown = n.to_string();
        let inner = enter_core(py, || match count {
            Some(k) => self.inner.with_robots(k),
            // The core's error for a count below 1, saying what arrived.
            None => self.inner.with_robots(0).map_err(|e| match e {
                CoreError::Scenario { file, field, expected, .. } => {
                    CoreError::Scenario { file, field, expected, found: shown }
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
    /// `eband` planner) are replaced by the keyword arguments, each named after a gain of
    /// `EBAND_GAINS`. Raises `ScenarioError` naming the gain (`eband.<gain>`) for an unknown
    /// name or a value out of range, `InputError` naming it for a value that is not a number.
    #[pyo3(signature = (**gains))]
    fn with_eband_gains(&self, py: Python<'_>, gains: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut named: Vec<(String, f64)> = Vec::new();
        for (key, value) in gains.into_iter().flat_map(|d| d.iter()) {
            let name = key.str()?.to_string();
            let v = value.extract::<f64>().map_err(|_| {
                let found = value.repr().map_or_else(|_| "?".into(), |r| r.to_string());
                input_err(py, &format!("eband.{name}"), "a number".into(), found)
            })?;
            named.push((name, v));
        }
        let pairs: Vec<(&str, f64)> = named.iter().map(|(n, v)| (n.as_str(), *v)).collect();
        let inner = enter_core(py, || self.inner.with_eband_gains(&pairs))?;
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

    /// A copy whose observation has the `subgoal` key: the point `lookahead` metres (in
    /// [0, 10]; 0 leaves the key out) along the shortest path to the robot's current target, in
    /// the robot's frame. Raises `ScenarioError` naming `sensors.subgoal` out of range.
    fn with_subgoal(&self, py: Python<'_>, lookahead: f64) -> PyResult<Self> {
        let inner = enter_core(py, || self.inner.with_subgoal(lookahead))?;
        Ok(PyScenario { inner })
    }

    /// A copy whose episode starts at `time` of day (`"HH:MM"`, `"HH:MM:SS"` or seconds after
    /// midnight in [0, 86400)) instead of the file's `scene.start_time`: the agenda's activities
    /// fall at another point of the episode; times the scenario holds as seconds into the
    /// episode keep their value (a conversation's `start` and `end`, even written as times of
    /// day in the file). Raises `InputError` naming `time_of_day` for a malformed time.
    fn with_start_time(&self, py: Python<'_>, time: TimeOfDay) -> PyResult<Self> {
        let time = CoreTimeOfDay::from(time);
        let inner = enter_core(py, || self.inner.with_start_time(time.seconds()?))?;
        Ok(PyScenario { inner })
    }

    /// The validated scenario as JSON (defaults filled in, world polygons computed).
    fn to_json(&self, py: Python<'_>) -> PyResult<String> {
        to_json_text(py, "the scenario", &self.inner)
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

/// Seconds after midnight of `value` (`"HH:MM"`, `"HH:MM:SS"` or a number of seconds in
/// [0, 86400)), parsed as scenario files are. Raises `InputError` naming `time_of_day`.
#[pyfunction]
pub(crate) fn parse_time_of_day(py: Python<'_>, value: TimeOfDay) -> PyResult<f64> {
    let value = CoreTimeOfDay::from(value);
    enter_core(py, || value.seconds())
}

/// A generated scene from its spec `generated/<seed>[?key=value&...]` or
/// `francis2023/<archetype>[?seed=N&max_time=T]`: the validated scenario and its scenario file
/// text. Raises `ScenarioError` naming the seed, archetype or parameter that is wrong.
#[pyfunction]
pub(crate) fn generate(py: Python<'_>, spec: &str) -> PyResult<(PyScenario, String)> {
    let spec = spec.to_string();
    let g = enter_core(py, move || proxemic_core::scenario::generate::generate_spec(&spec))?;
    Ok((PyScenario { inner: g.scenario }, g.toml))
}

/// The JSON Schema of a scenario file (draft 2020-12), as JSON text: every table and field with
/// its type, default and description (the scenario reference of the docs; `proxemic schema`).
#[pyfunction]
pub(crate) fn scenario_schema(py: Python<'_>) -> PyResult<String> {
    to_json_text(py, "the scenario schema", &proxemic_core::scenario::json_schema())
}

/// The CrowdNav protocol's kinematic episodes of the `crowdnav/<family>[?...]` specs with the
/// built-in `planner` (one of `CROWDNAV_PLANNERS`): one dict per spec (`spec`, `outcome`
/// "success" / "collision" / "timeout", `time` s, `discomfort_steps`, `discomfort_dist_sum` m,
/// `min_dist` m). Raises `ScenarioError` for a bad spec, `InputError` naming `planner`.
#[pyfunction]
pub(crate) fn crowdnav_episodes<'py>(
    py: Python<'py>,
    specs: Vec<String>,
    planner: &str,
) -> PyResult<Bound<'py, PyAny>> {
    use proxemic_core::world::crowdnav::run_episode;
    let planner = planner.to_string();
    let episodes = enter_core(py, move || {
        specs.iter().map(|s| run_episode(s, &planner)).collect::<Result<Vec<_>, CoreError>>()
    })?;
    crate::conversions::to_py(py, "the CrowdNav episodes", &episodes)
}

/// A failure of a policy-driven episode: the core's, or the policy's Python exception.
enum PolicyFail {
    Core(CoreError),
    Py(PyErr),
}

impl From<CoreError> for PolicyFail {
    fn from(e: CoreError) -> Self {
        PolicyFail::Core(e)
    }
}

/// The CrowdNav protocol's kinematic episodes of the specs driven by `policy`, a callable given
/// the robot's output row (a float64 array of the world's `stride` values, the observation in
/// its `obs_*` sections as the env builds it) and returning a normalised action (3 floats, vx,
/// vy, wz in [-1, 1], robot frame), once per step. Records as `crowdnav_episodes`. Raises
/// `ScenarioError` for a bad spec, `InputError` for a non-finite action; an exception raised by
/// `policy` propagates.
#[pyfunction]
pub(crate) fn crowdnav_policy_episodes<'py>(
    py: Python<'py>,
    specs: Vec<String>,
    policy: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    use proxemic_core::world::crowdnav::run_policy_episode;
    use std::panic::{AssertUnwindSafe, catch_unwind};
    let act = |row: &[f64]| -> Result<[f64; 3], PolicyFail> {
        let arr = numpy::PyArray1::from_slice(py, row);
        let a: (f64, f64, f64) = policy.call1((arr,)).and_then(|r| r.extract()).map_err(PolicyFail::Py)?;
        Ok([a.0, a.1, a.2])
    };
    let run = || specs.iter().map(|s| run_policy_episode(s, act)).collect::<Result<Vec<_>, PolicyFail>>();
    let episodes = match catch_unwind(AssertUnwindSafe(run)) {
        Ok(Ok(e)) => e,
        Ok(Err(PolicyFail::Core(e))) => return Err(crate::errors::to_py_err(py, e)),
        Ok(Err(PolicyFail::Py(e))) => return Err(e),
        Err(_) => {
            return Err(crate::errors::internal_error(
                py,
                "internal error in the Rust core (a bug: please report it)",
            ));
        }
    };
    crate::conversions::to_py(py, "the CrowdNav episodes", &episodes)
}
