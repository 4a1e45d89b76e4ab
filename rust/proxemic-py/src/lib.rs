//! Python bindings of `proxemic-core`, exposed as `proxemic._core`.
//!
//! This crate is deliberately thin: it converts values between Python and the core, releases
//! the GIL around the core's work, and maps every core error to an exception. The rules (names,
//! ranges, thresholds) are the core's; the binding holds none of its own. Its modules:
//! - [`errors`]: core errors and panics to the exception classes of `proxemic/errors.py` (all
//!   under `proxemic.ProxemicError`);
//! - [`conversions`]: buffers and arguments in; results out, arrays as numpy arrays and every
//!   other result through one serde-to-Python conversion (`conversions::to_py`);
//! - [`scenario`]: `Scenario`, `generate`, `parse_time_of_day`, `scenario_schema`;
//! - [`world`]: the class `World`;
//! - [`step`]: the two-phase control step around the Python physics, and `step_worlds`;
//! - [`validation`]: the pedestrian model against recorded crowds and the RiMEA tests;
//! - here: `metric_registry` and `zone_distances` (the core's zone distance).
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

use pyo3::prelude::*;

mod conversions;
mod errors;
mod scenario;
mod step;
mod validation;
mod world;

/// The metric reference: one dict per key of an episode's metrics (`key`, `family`, `label`,
/// `unit`, `better` = "higher" | "lower" | "neither", `low` and `high` bounds or None, `per` =
/// "episode" | "person" | "object", `definition`, `formula`, `source`), in the reference's order.
#[pyfunction]
fn metric_registry(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    conversions::to_py(py, "the metric registry", proxemic_core::metrics::METRICS)
}

/// The zone distances (m) of `points` ((N, 2) float64, metres) in the fully asymmetric Gaussian of
/// an individual centred at `centre` facing `heading` (rad) with per-side sigmas `sides` = (front,
/// rear, right, left) (m) and zone scale `zone_scale` (m): the core's
/// `proxemics::zone_distances`, as an (N,) float64 array. Raises `InputError` naming the field.
#[pyfunction]
fn zone_distances<'py>(
    py: Python<'py>,
    centre: (f64, f64),
    heading: f64,
    sides: (f64, f64, f64, f64),
    zone_scale: f64,
    points: numpy::PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    use numpy::PyUntypedArrayMethods;
    let shape = points.shape();
    if shape.len() != 2 || shape[1] != 2 {
        return Err(errors::input_err(
            py,
            "points",
            "an (N, 2) float64 array (m)".into(),
            format!("shape {shape:?}"),
        ));
    }
    let pts: Vec<proxemic_core::math::Vec2> =
        points.as_array().rows().into_iter().map(|r| proxemic_core::math::Vec2::new(r[0], r[1])).collect();
    let centre = proxemic_core::math::Vec2::new(centre.0, centre.1);
    let sides =
        proxemic_core::proxemics::Asymmetric { front: sides.0, rear: sides.1, right: sides.2, left: sides.3 };
    let d = errors::enter_core(py, move || {
        proxemic_core::proxemics::zone_distances(centre, heading, sides, zone_scale, &pts)
    })?;
    Ok(numpy::PyArray1::from_vec(py, d))
}

/// The compiled core of proxemic.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("CONTACT_PERSON", proxemic_core::metrics::CONTACT_PERSON)?;
    m.add("CONTACT_STATIC", proxemic_core::metrics::CONTACT_STATIC)?;
    m.add("CONTACT_ROBOT", proxemic_core::metrics::CONTACT_ROBOT)?;
    m.add("REWARD_TERMS", proxemic_core::world::REWARD_TERMS.to_vec())?;
    m.add("PERSON_FEATURES", proxemic_core::world::PERSON_FEATURES)?;
    m.add("ROBOT_FEATURES", proxemic_core::world::ROBOT_FEATURES)?;
    m.add("PEER_FEATURES", proxemic_core::world::PEER_FEATURES)?;
    m.add("OBS_MAX_SPEED", proxemic_core::world::OBS_MAX_SPEED)?;
    m.add("OBS_MAX_ANGULAR", proxemic_core::world::OBS_MAX_ANGULAR)?;
    m.add("PERSON_OUT", proxemic_core::world::PERSON_OUT)?;
    m.add("CONTACT_RANGE", proxemic_core::world::CONTACT_RANGE)?;
    m.add("PLANNERS", proxemic_core::scenario::PlannerKind::NAMES.to_vec())?;
    m.add("EBAND_GAINS", proxemic_core::scenario::EbandGains::NAMES.to_vec())?;
    m.add("MAX_ROBOTS", proxemic_core::scenario::MAX_ROBOTS)?;
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<world::PyWorld>()?;
    m.add("GENERATE_PARAMS", proxemic_core::scenario::generate::PARAM_NAMES.to_vec())?;
    m.add("FRANCIS2023_ARCHETYPES", proxemic_core::scenario::generate::francis2023::ARCHETYPES.to_vec())?;
    m.add_function(wrap_pyfunction!(scenario::parse_time_of_day, m)?)?;
    m.add_function(wrap_pyfunction!(step::step_worlds, m)?)?;
    m.add_function(wrap_pyfunction!(metric_registry, m)?)?;
    m.add_function(wrap_pyfunction!(zone_distances, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::scenario_schema, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::generate, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::crowdnav_episodes, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::crowdnav_policy_episodes, m)?)?;
    m.add("CROWDNAV_PLANNERS", proxemic_core::world::crowdnav::PLANNERS.to_vec())?;
    m.add("CROWDNAV_FAMILIES", proxemic_core::scenario::generate::crowdnav::FAMILIES.to_vec())?;
    validation::register(m)?;
    Ok(())
}
