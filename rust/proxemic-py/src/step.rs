//! One control step across the Python physics: `World.step`'s two phases, and `step_worlds`,
//! the step of several worlds in one call (a vector env's step).

use numpy::PyArrayMethods;
use pyo3::prelude::*;

use proxemic_core::CoreError;
use proxemic_core::world::{self, World as CoreWorld};

use crate::conversions::{array_of, busy, flat_mut, index_arg};
use crate::errors::{enter_core, input_err};
use crate::world::PyWorld;

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
pub(crate) fn step_worlds(
    py: Python<'_>,
    worlds: &Bound<'_, PyAny>,
    actions: &Bound<'_, PyAny>,
    physics: &Bound<'_, PyAny>,
    state: &Bound<'_, PyAny>,
    contacts: &Bound<'_, PyAny>,
    out: &Bound<'_, PyAny>,
    people_out: &Bound<'_, PyAny>,
    threads: Option<&Bound<'_, PyAny>>,
) -> PyResult<()> {
    let threads = match threads.filter(|t| !t.is_none()) {
        Some(t) => Some(index_arg(t, "threads", "a number of threads, an integer >= 1")?),
        None => None,
    };
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
pub(crate) struct StepBuffers<'a, 'py> {
    pub(crate) actions: &'a Bound<'py, PyAny>,
    pub(crate) physics: &'a Bound<'py, PyAny>,
    pub(crate) state: &'a Bound<'py, PyAny>,
    pub(crate) contacts: &'a Bound<'py, PyAny>,
    pub(crate) out: &'a Bound<'py, PyAny>,
    pub(crate) people_out: &'a Bound<'py, PyAny>,
}

/// One control step in two phases around the Python physics callback: checks the buffers (an
/// `InputError` naming the field for a wrong dtype, shape, layout or a borrowed array), runs
/// `command(target, actions, out)` without the GIL, calls `physics()` with it, then runs
/// `step(target, state, contacts, out, people_out)` without the GIL.
pub(crate) fn two_phase_step<W: Send + ?Sized>(
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
