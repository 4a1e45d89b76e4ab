//! From the core's errors (and panics) to the exception classes of `proxemic/errors.py`.
//!
//! Every [`CoreError`] variant maps to one class under `proxemic.ProxemicError`, carrying `file`,
//! `field`, `expected` and `found`. A Rust panic is a bug; as a last line of defence it is caught
//! and re-raised as `proxemic.ProxemicError` rather than reaching Python as a `PanicException`.

use std::panic::{AssertUnwindSafe, catch_unwind};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use proxemic_core::CoreError;

/// The Python exception matching a core error (class looked up in `proxemic.errors`).
pub(crate) fn to_py_err(py: Python<'_>, e: CoreError) -> PyErr {
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
pub(crate) fn enter_core<T: Send>(
    py: Python<'_>,
    f: impl FnOnce() -> Result<T, CoreError> + Send,
) -> PyResult<T> {
    let result = py.detach(|| catch_unwind(AssertUnwindSafe(f)));
    match result {
        Ok(Ok(v)) => Ok(v),
        Ok(Err(e)) => Err(to_py_err(py, e)),
        Err(_) => Err(internal_error(py, "internal error in the Rust core (a bug: please report it)")),
    }
}

/// A `proxemic.ProxemicError` saying `message`: a bug of the core or the binding (a panic, a
/// result that cannot be converted), never the caller's fault.
pub(crate) fn internal_error(py: Python<'_>, message: &str) -> PyErr {
    let make = || -> PyResult<PyErr> {
        let cls = py.import("proxemic.errors")?.getattr("ProxemicError")?;
        Ok(PyErr::from_value(cls.call1((message,))?))
    };
    make().unwrap_or_else(|_| PyRuntimeError::new_err(message.to_string()))
}

/// The core's `None` where it promised a value after the binding's checks: a bug.
pub(crate) fn missing(py: Python<'_>, what: &str) -> PyErr {
    internal_error(py, &format!("internal error in the Rust core: no {what} (a bug: please report it)"))
}

/// An `InputError` naming `field`.
pub(crate) fn input_err(py: Python<'_>, field: &str, expected: String, found: String) -> PyErr {
    to_py_err(py, CoreError::input(field, expected, found))
}
