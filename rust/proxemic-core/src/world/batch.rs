//! Several worlds stepped as one call, their second halves in parallel threads.
//!
//! A vector env runs N independent worlds (usually of one scenario). [`command_batch`] and
//! [`step_batch`] are [`World::command`] and [`World::step`] over all of them, with every
//! world's buffers laid end to end in one flat buffer per kind (world 0's values first). The
//! physics of each world runs between the two calls, outside the core. [`step_batch`] spreads the
//! worlds over scoped threads (`std::thread::scope`, no pool kept between calls); each world is
//! stepped by exactly one thread with its own buffers, so the results are bit for bit those of
//! stepping the worlds one after the other.
//!
//! Both calls check every world's arguments before changing any world: on an error nothing is
//! changed, and the error's field names the world (`worlds[k].<field>`).

use super::World;
use crate::error::{CoreError, Result};
use crate::world::observe::PERSON_OUT;

/// The sizes of one world's parts of the batch buffers.
#[derive(Clone, Copy)]
struct Sizes {
    actions: usize,
    state: usize,
    contacts: usize,
    out: usize,
    people: usize,
}

fn sizes(w: &World) -> Sizes {
    let n = w.num_robots();
    Sizes {
        actions: 3 * n,
        state: 6 * n,
        contacts: n,
        out: n * w.layout().stride,
        people: w.num_people() * PERSON_OUT,
    }
}

/// Renames an error's field to `worlds[k].<field>`.
fn in_world(k: usize, e: CoreError) -> CoreError {
    match e {
        CoreError::Input { field, expected, found } => {
            CoreError::Input { field: format!("worlds[{k}].{field}"), expected, found }
        }
        CoreError::Scenario { file, field, expected, found } => {
            CoreError::Scenario { file, field: format!("worlds[{k}].{field}"), expected, found }
        }
        CoreError::Planning { file, field, message } => {
            CoreError::Planning { file, field: format!("worlds[{k}].{field}"), message }
        }
        CoreError::Invariant { episode, invariant, detail } => {
            CoreError::Invariant { episode: format!("worlds[{k}]: {episode}"), invariant, detail }
        }
    }
}

/// Checks that a batch buffer holds exactly the worlds' values.
fn check_total(field: &str, got: usize, want: usize) -> Result<()> {
    if got == want {
        Ok(())
    } else {
        Err(CoreError::input(
            field,
            format!("{want} values (every world's, end to end)"),
            format!("{got} values"),
        ))
    }
}

/// Splits `buf` into consecutive parts of the given lengths (their sum must be `buf.len()`).
fn split_mut<T>(mut buf: &mut [T], lens: impl Iterator<Item = usize>) -> Vec<&mut [T]> {
    let mut parts = Vec::new();
    for n in lens {
        let (head, tail) = buf.split_at_mut(n);
        parts.push(head);
        buf = tail;
    }
    parts
}

/// Splits `buf` into consecutive parts of the given lengths (their sum must be `buf.len()`).
fn split<T>(mut buf: &[T], lens: impl Iterator<Item = usize>) -> Vec<&[T]> {
    let mut parts = Vec::new();
    for n in lens {
        let (head, tail) = buf.split_at(n);
        parts.push(head);
        buf = tail;
    }
    parts
}

/// [`World::command`] for every world: `actions` holds world 0's `3 * num_robots` values, then
/// world 1's, and so on; `out` every world's output buffer end to end.
///
/// # Errors
/// [`CoreError::Input`] for buffers of the wrong total length or any world's bad actions (its
/// field prefixed with `worlds[k].`); no world is changed then.
pub fn command_batch(worlds: &mut [&mut World], actions: &[f64], out: &mut [f64]) -> Result<()> {
    let sz: Vec<Sizes> = worlds.iter().map(|w| sizes(w)).collect();
    check_total("actions", actions.len(), sz.iter().map(|s| s.actions).sum())?;
    check_total("out", out.len(), sz.iter().map(|s| s.out).sum())?;
    let acts = split(actions, sz.iter().map(|s| s.actions));
    let outs = split_mut(out, sz.iter().map(|s| s.out));
    for (k, (w, (a, o))) in worlds.iter().zip(acts.iter().zip(&outs)).enumerate() {
        w.check_actions(a, o).map_err(|e| in_world(k, e))?;
    }
    for (k, (w, (a, o))) in worlds.iter_mut().zip(acts.into_iter().zip(outs)).enumerate() {
        w.command(a, o).map_err(|e| in_world(k, e))?;
    }
    Ok(())
}

/// One world's part of a batch step.
struct Job<'a> {
    index: usize,
    world: &'a mut World,
    state: &'a [f64],
    contacts: &'a [u8],
    out: &'a mut [f64],
    people: &'a mut [f64],
}

/// [`World::step`] for every world, spread over at most `threads` threads (0 or 1: this thread
/// only; never more threads than worlds). `state`, `contacts`, `out` and `people_out` hold every
/// world's buffer of that kind end to end, world 0 first.
///
/// # Errors
/// [`CoreError::Input`] for buffers of the wrong total length, or a world not reset or given
/// non-finite state (its field prefixed with `worlds[k].`); no world is changed then.
pub fn step_batch(
    worlds: &mut [&mut World],
    state: &[f64],
    contacts: &[u8],
    out: &mut [f64],
    people_out: &mut [f64],
    threads: usize,
) -> Result<()> {
    let sz: Vec<Sizes> = worlds.iter().map(|w| sizes(w)).collect();
    check_total("state", state.len(), sz.iter().map(|s| s.state).sum())?;
    check_total("contacts", contacts.len(), sz.iter().map(|s| s.contacts).sum())?;
    check_total("out", out.len(), sz.iter().map(|s| s.out).sum())?;
    check_total("people_out", people_out.len(), sz.iter().map(|s| s.people).sum())?;
    let states = split(state, sz.iter().map(|s| s.state));
    let contacts = split(contacts, sz.iter().map(|s| s.contacts));
    let outs = split_mut(out, sz.iter().map(|s| s.out));
    let people = split_mut(people_out, sz.iter().map(|s| s.people));
    for (k, w) in worlds.iter().enumerate() {
        let checked = if w.started {
            w.check_out(outs[k], people[k]).and_then(|()| w.check_state(states[k], contacts[k]))
        } else {
            Err(CoreError::input("step", "a call after reset()", "a call before the first reset()"))
        };
        checked.map_err(|e| in_world(k, e))?;
    }
    let mut jobs: Vec<Job<'_>> = worlds
        .iter_mut()
        .zip(states)
        .zip(contacts)
        .zip(outs)
        .zip(people)
        .enumerate()
        .map(|(index, ((((world, state), contacts), out), people))| Job {
            index,
            world,
            state,
            contacts,
            out,
            people,
        })
        .collect();
    let threads = threads.clamp(1, jobs.len().max(1));
    // Contiguous runs of worlds per thread; the first run is stepped on this thread.
    let per = jobs.len().div_ceil(threads).max(1);
    let run = |chunk: &mut [Job<'_>]| -> Result<()> {
        for job in chunk {
            // Checked above; a failure here would be a bug of the world's step, named by world.
            job.world
                .step(job.state, job.contacts, job.out, job.people)
                .map_err(|e| in_world(job.index, e))?;
        }
        Ok(())
    };
    let mut chunks = jobs.chunks_mut(per);
    let first = chunks.next();
    std::thread::scope(|scope| {
        let handles: Vec<_> = chunks.map(|chunk| scope.spawn(|| run(chunk))).collect();
        let mut result = first.map_or(Ok(()), run);
        for h in handles {
            // A panic in a worker is re-raised here, on the caller's thread (the binding turns it
            // into an internal error); the first error in world order is returned.
            let r = h.join().unwrap_or_else(|p| std::panic::resume_unwind(p));
            result = result.and(r);
        }
        result
    })
}
