//! The pedestrian model against recorded crowds and the RiMEA known-answer tests
//! (`proxemic_core::pedestrians::{validation, rimea}`), for `proxemic.crowdcard`.

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use proxemic_core::pedestrians::validation::Recording as CoreRecording;
use proxemic_core::pedestrians::{SocialForceParams, rimea};

use crate::conversions::points_to_array;
use crate::errors::{enter_core, input_err};

/// One re-enacted person: its positions (k, 2) at the track's sample times, and its arrival time
/// (s) or None.
type Reenacted<'py> = (Bound<'py, PyArray2<f64>>, Option<f64>);

/// The default social force parameters with `overrides` (name -> value) applied; an unknown
/// name or a bad value raises `InputError` naming it.
fn params_of(py: Python<'_>, overrides: Option<&Bound<'_, PyDict>>) -> PyResult<SocialForceParams> {
    let mut p = SocialForceParams::default();
    if let Some(d) = overrides {
        for (k, v) in d.iter() {
            let name: String = k.extract()?;
            let value: f64 = v.extract().map_err(|_| {
                input_err(py, &format!("social_force.{name}"), "a number".into(), v.to_string())
            })?;
            enter_core(py, || p.set(&name, value))?;
        }
    }
    Ok(p)
}

/// The default social force parameters (name -> value).
#[pyfunction]
fn social_force_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    let p = SocialForceParams::default();
    for name in SocialForceParams::NAMES {
        d.set_item(name, p.get(name))?;
    }
    Ok(d)
}

/// The tracks of a replay CSV file `t,id,x,y`: a list of (label, (n, 3) array of t, x, y).
#[pyfunction]
fn read_tracks(
    py: Python<'_>,
    path: std::path::PathBuf,
) -> PyResult<Vec<(String, Bound<'_, PyArray2<f64>>)>> {
    let tracks = enter_core(py, move || proxemic_core::scenario::read_track_file(&path))?;
    tracks
        .into_iter()
        .map(|(id, s)| {
            let n = s.len();
            let flat: Vec<f64> = s.into_iter().flatten().collect();
            Ok((id, PyArray1::from_vec(py, flat).reshape([n, 3])?))
        })
        .collect()
}

/// A recorded scene in open space (see `proxemic_core::pedestrians::validation`).
#[pyclass(name = "Recording", module = "proxemic._core", frozen)]
pub struct PyRecording {
    inner: CoreRecording,
}

#[pymethods]
impl PyRecording {
    #[new]
    fn new(py: Python<'_>, tracks: Vec<PyReadonlyArray2<'_, f64>>, radius: f64) -> PyResult<Self> {
        let mut ts = Vec::with_capacity(tracks.len());
        for (k, a) in tracks.iter().enumerate() {
            let v = a.as_array();
            let shape = v.shape();
            if shape[1] != 3 {
                return Err(input_err(
                    py,
                    &format!("tracks[{k}]"),
                    "an (n, 3) array of t, x, y".into(),
                    format!("shape {shape:?}"),
                ));
            }
            ts.push((0..shape[0]).map(|i| [v[[i, 0]], v[[i, 1]], v[[i, 2]]]).collect());
        }
        let inner = enter_core(py, move || CoreRecording::new(ts, radius))?;
        Ok(PyRecording { inner })
    }

    /// Re-enacts each of `subjects` (closed loop): a list of (positions (k, 2) at the track's
    /// sample times, arrival time or None).
    #[pyo3(signature = (subjects, params=None, overtime=20.0))]
    fn reenact<'py>(
        &self,
        py: Python<'py>,
        subjects: Vec<usize>,
        params: Option<&Bound<'py, PyDict>>,
        overtime: f64,
    ) -> PyResult<Vec<Reenacted<'py>>> {
        let p = params_of(py, params)?;
        let rec = &self.inner;
        let runs = enter_core(py, move || {
            subjects.iter().map(|&s| rec.reenact(s, p, overtime)).collect::<Result<Vec<_>, _>>()
        })?;
        runs.into_iter().map(|r| Ok((points_to_array(py, &r.positions)?, r.arrival))).collect()
    }

    /// The open-loop protocol: an (m, 6) array, one row per evaluated person and window: track,
    /// time of the last observed sample, the model's ADE and FDE, constant velocity's ADE and FDE.
    #[pyo3(signature = (params=None, observe=8, predict=12, sample_dt=0.4))]
    fn open_loop<'py>(
        &self,
        py: Python<'py>,
        params: Option<&Bound<'py, PyDict>>,
        observe: usize,
        predict: usize,
        sample_dt: f64,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let p = params_of(py, params)?;
        let rec = &self.inner;
        let rows = enter_core(py, move || rec.open_loop(p, observe, predict, sample_dt))?;
        let n = rows.len();
        let flat: Vec<f64> =
            rows.iter().flat_map(|r| [r.track as f64, r.t_obs, r.ade, r.fde, r.ade_cv, r.fde_cv]).collect();
        PyArray1::from_vec(py, flat).reshape([n, 6])
    }
}

/// RiMEA test 1: the time (s) one person takes through a 40 m corridor at 1.33 m/s.
#[pyfunction]
#[pyo3(signature = (params=None, radius=0.2))]
fn rimea1(py: Python<'_>, params: Option<&Bound<'_, PyDict>>, radius: f64) -> PyResult<f64> {
    let p = params_of(py, params)?;
    enter_core(py, move || rimea::rimea1(p, radius))
}

/// RiMEA test 4 in a ring corridor: the mean speed (m/s) at each density (people per m^2).
#[pyfunction]
#[pyo3(signature = (densities, params=None, radius=0.2, seed=0, warmup=20.0, measure=20.0))]
fn rimea4(
    py: Python<'_>,
    densities: Vec<f64>,
    params: Option<&Bound<'_, PyDict>>,
    radius: f64,
    seed: u64,
    warmup: f64,
    measure: f64,
) -> PyResult<Vec<f64>> {
    let p = params_of(py, params)?;
    enter_core(py, move || rimea::rimea4(p, radius, &densities, seed, warmup, measure))
}

/// RiMEA test 6: twenty people round a corner; a dict with `arrived`, `wall_crossings`, `time`
/// (s or None) and `paths` (one (k, 2) array per person).
#[pyfunction]
#[pyo3(signature = (params=None, radius=0.2, seed=0, duration=120.0))]
fn rimea6<'py>(
    py: Python<'py>,
    params: Option<&Bound<'py, PyDict>>,
    radius: f64,
    seed: u64,
    duration: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let p = params_of(py, params)?;
    let c = enter_core(py, move || rimea::rimea6(p, radius, seed, duration))?;
    let d = PyDict::new(py);
    d.set_item("arrived", c.arrived)?;
    d.set_item("wall_crossings", c.wall_crossings)?;
    d.set_item("time", c.time)?;
    let paths: PyResult<Vec<_>> = c.paths.iter().map(|q| points_to_array(py, q)).collect();
    d.set_item("paths", paths?)?;
    Ok(d)
}

/// Adds the validation functions and class to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRecording>()?;
    m.add_function(wrap_pyfunction!(social_force_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(read_tracks, m)?)?;
    m.add_function(wrap_pyfunction!(rimea1, m)?)?;
    m.add_function(wrap_pyfunction!(rimea4, m)?)?;
    m.add_function(wrap_pyfunction!(rimea6, m)?)?;
    Ok(())
}
