//! The core's error type. Every variant carries enough context for a message that names the file,
//! the field, what was expected and what arrived; the Python layer maps each variant to one
//! exception class under `proxemic.ProxemicError`.

use thiserror::Error;

/// Result alias used throughout the core.
pub type Result<T> = std::result::Result<T, CoreError>;

/// Everything that can go wrong in the core.
#[derive(Debug, Clone, Error, PartialEq)]
pub enum CoreError {
    /// A scenario file could not be read, parsed, or failed validation.
    #[error("{file}: {field}: expected {expected}, got {found}")]
    Scenario {
        /// The scenario file (path, or `<string>` for inline text).
        file: String,
        /// The dotted field path, e.g. `robot[0].goal`.
        field: String,
        /// What a valid value looks like.
        expected: String,
        /// What arrived.
        found: String,
    },
    /// A runtime input (an action, a state array) was malformed.
    #[error("{field}: expected {expected}, got {found}")]
    Input {
        /// The argument or array name.
        field: String,
        /// What a valid value looks like.
        expected: String,
        /// What arrived.
        found: String,
    },
    /// A path could not be planned (goal unreachable from start).
    #[error("{file}: {field}: {message}")]
    Planning {
        /// The scenario file.
        file: String,
        /// The field whose value made planning impossible.
        field: String,
        /// What happened.
        message: String,
    },
    /// An episode's record broke one of its invariants ([`crate::metrics::invariants`]): a bug in
    /// proxemic, reported instead of a record whose numbers contradict each other.
    #[error("{episode}: invariant {invariant} broken: {detail} (a bug in proxemic: please report it)")]
    Invariant {
        /// The episode (scene, seed, robot).
        episode: String,
        /// The invariant's name ([`crate::metrics::invariants::INVARIANTS`]).
        invariant: String,
        /// What the record says that breaks it.
        detail: String,
    },
}

impl CoreError {
    /// Builds a [`CoreError::Input`].
    pub fn input(field: impl Into<String>, expected: impl Into<String>, found: impl Into<String>) -> Self {
        CoreError::Input { field: field.into(), expected: expected.into(), found: found.into() }
    }
}
