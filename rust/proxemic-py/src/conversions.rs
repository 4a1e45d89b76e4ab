//! Values crossing between Python and the core, both ways.
//!
//! Into the core: numpy buffers (checked for dtype, shape and layout, each failure an
//! `InputError` naming the argument), points and times of day. Out of the core: numeric arrays
//! as numpy arrays ([`points_to_array`] and `PyArray1::reshape`), and **every other result**
//! through [`to_py`], which turns any `serde::Serialize` value of the core into plain Python
//! objects (see [`to_py`] for the mapping). A value that cannot be converted raises
//! `proxemic.ProxemicError`; no call returns an error as data.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadwriteArray1};
use pyo3::prelude::*;
use serde::Serialize;
use serde::ser::SerializeMap;

use proxemic_core::math::Vec2;
use proxemic_core::scenario::TimeOfDay as CoreTimeOfDay;

use crate::errors::{input_err, internal_error};

mod pyser;

/// `value` as Python objects: a struct or map becomes a `dict` (fields in declaration order), a
/// sequence a `list`, a tuple a `tuple`, `None` and `()` become `None`, integers `int`, finite
/// floats `float`, **non-finite floats `None`** (as the JSON the results used to cross as: an
/// undefined metric is None), strings `str`, a unit enum variant its name, any other enum variant
/// `{name: value}`. Raises `proxemic.ProxemicError` naming `what` if `value` cannot be converted.
pub(crate) fn to_py<'py, T: Serialize + ?Sized>(
    py: Python<'py>,
    what: &str,
    value: &T,
) -> PyResult<Bound<'py, PyAny>> {
    value.serialize(pyser::PySerializer { py }).map_err(|e| match e {
        pyser::Error::Python(err) => err,
        pyser::Error::Custom(msg) => internal_error(
            py,
            &format!("internal error: {what} cannot be converted to Python objects: {msg}"),
        ),
    })
}

/// `value` as JSON text (a document the API returns as text: a scenario, a schema). Raises
/// `proxemic.ProxemicError` naming `what` if `value` cannot be serialised.
pub(crate) fn to_json_text<T: Serialize + ?Sized>(py: Python<'_>, what: &str, value: &T) -> PyResult<String> {
    serde_json::to_string(value)
        .map_err(|e| internal_error(py, &format!("internal error: {what} cannot be serialised to JSON: {e}")))
}

/// Pairs serialised as a map, in their order (a `dict` keyed by name through [`to_py`]).
pub(crate) struct Named<'a, K, V>(pub(crate) &'a [(K, V)]);

impl<K: Serialize, V: Serialize> Serialize for Named<'_, K, V> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

/// `obj` as a `u64`: `Some` for an int in [0, 2**64), `None` for an int that is negative or
/// too large (pyo3 alone raises `OverflowError` there); a value that is not an int keeps pyo3's
/// `TypeError`. The one conversion of the bindings' index, count and seed arguments.
pub(crate) fn int_in_range(obj: &Bound<'_, PyAny>) -> PyResult<Option<u64>> {
    match obj.extract::<u64>() {
        Ok(v) => Ok(Some(v)),
        Err(_) if obj.is_instance_of::<pyo3::types::PyInt>() => Ok(None),
        Err(e) => Err(e),
    }
}

/// A non-negative integer argument `field` (an index or a count): a negative Python int or one
/// of 2**64 or more is an `InputError` naming `field`, saying `expected` and what arrived.
pub(crate) fn index_arg(obj: &Bound<'_, PyAny>, field: &str, expected: &str) -> PyResult<usize> {
    int_in_range(obj)?
        .and_then(|v| usize::try_from(v).ok())
        .ok_or_else(|| input_err(obj.py(), field, expected.into(), obj.to_string()))
}

/// A robot index argument (`robot`); see [`index_arg`]. Too large an index is refused by
/// `World.robot`, which knows the number of robots.
pub(crate) fn robot_index(obj: &Bound<'_, PyAny>) -> PyResult<usize> {
    index_arg(obj, "robot", "a robot index, an integer in [0, the number of robots)")
}

/// A list of robot indices (`robots`): each one as [`robot_index`] checks it, named `robots[k]`.
pub(crate) fn robot_indices(obj: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
    let items: Vec<Bound<'_, PyAny>> = obj.extract()?;
    let expected = "a robot index, an integer in [0, the number of robots)";
    items.iter().enumerate().map(|(k, r)| index_arg(r, &format!("robots[{k}]"), expected)).collect()
}

/// A seed argument: a negative Python int or one of 2**64 or more is an `InputError` naming
/// `seed` and what arrived (pyo3 alone raises `OverflowError`).
pub(crate) fn seed_arg(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    int_in_range(obj)?
        .ok_or_else(|| input_err(obj.py(), "seed", "an integer in [0, 2**64)".into(), obj.to_string()))
}

/// `obj` as a one-dimensional numpy array of `T`, or an `InputError` naming `field` that says
/// what arrived (a float32 state buffer, a list, a 2-D array...).
pub(crate) fn array_of<'py, T: numpy::Element>(
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
pub(crate) fn busy(py: Python<'_>, field: &str) -> PyErr {
    input_err(py, field, "a float64 or uint8 array not borrowed elsewhere".into(), "a borrowed array".into())
}

/// The values of a writable float64 buffer, or an `InputError` naming `name` when it is not
/// C-contiguous.
pub(crate) fn flat_mut<'a>(
    py: Python<'_>,
    name: &str,
    arr: &'a mut PyReadwriteArray1<'_, f64>,
) -> PyResult<&'a mut [f64]> {
    arr.as_slice_mut().map_err(|_| {
        input_err(py, name, "a C-contiguous float64 array".into(), "a non-contiguous array".into())
    })
}

/// `p` as a point, or an `InputError` naming `field` when a coordinate is not finite.
pub(crate) fn finite_point(py: Python<'_>, field: &str, p: (f64, f64)) -> PyResult<Vec2> {
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

/// Points as a (K, 2) float64 array of x, y.
pub(crate) fn points_to_array<'py>(py: Python<'py>, pts: &[Vec2]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let flat: Vec<f64> = pts.iter().flat_map(|p| [p.x, p.y]).collect();
    PyArray1::from_vec(py, flat).reshape([pts.len(), 2])
}

/// A time of day from Python: `"HH:MM"`, `"HH:MM:SS"` or seconds after midnight (checked by
/// the core, [`CoreTimeOfDay::seconds`]).
#[derive(FromPyObject)]
pub(crate) enum TimeOfDay {
    /// Text.
    Text(String),
    /// Seconds after midnight.
    Seconds(f64),
}

impl From<TimeOfDay> for CoreTimeOfDay {
    fn from(t: TimeOfDay) -> Self {
        match t {
            TimeOfDay::Text(s) => CoreTimeOfDay::Text(s),
            TimeOfDay::Seconds(x) => CoreTimeOfDay::Seconds(x),
        }
    }
}
