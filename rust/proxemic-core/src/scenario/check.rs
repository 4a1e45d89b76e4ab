//! The error constructor and value checks shared by loading and building.

use crate::error::{CoreError, Result};

/// Builds a scenario error.
pub(super) fn err(
    file: &str,
    field: impl Into<String>,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> CoreError {
    CoreError::Scenario {
        file: file.to_string(),
        field: field.into(),
        expected: expected.into(),
        found: found.into(),
    }
}

/// Checks values of the file `file`; every failure is a scenario error naming the field.
pub(super) struct Checker<'a> {
    pub(super) file: &'a str,
}

impl Checker<'_> {
    pub(super) fn finite(&self, field: &str, values: &[f64]) -> Result<()> {
        if let Some(v) = values.iter().find(|v| !v.is_finite()) {
            return Err(err(self.file, field, "finite numbers", format!("{v}")));
        }
        Ok(())
    }

    pub(super) fn range(&self, field: &str, v: f64, lo: f64, hi: f64, lo_open: bool) -> Result<()> {
        let ok_lo = if lo_open { v > lo } else { v >= lo };
        if !v.is_finite() || !ok_lo || v > hi {
            let l = if lo_open { "(" } else { "[" };
            return Err(err(self.file, field, format!("a number in {l}{lo}, {hi}]"), format!("{v}")));
        }
        Ok(())
    }

    pub(super) fn inside(&self, field: &str, p: [f64; 2], b: [f64; 4]) -> Result<()> {
        self.finite(field, &p)?;
        if p[0] < b[0] || p[0] > b[2] || p[1] < b[1] || p[1] > b[3] {
            return Err(err(
                self.file,
                field,
                format!("a point inside scene.bounds [{}, {}, {}, {}]", b[0], b[1], b[2], b[3]),
                format!("[{}, {}]", p[0], p[1]),
            ));
        }
        Ok(())
    }
}

/// Whether `t` is a time of day in seconds after midnight: finite and in `[0, 86400)`.
pub fn is_time_of_day(t: f64) -> bool {
    t.is_finite() && (0.0..crate::chronemics::DAY).contains(&t)
}

/// `t` if it is a time of day in seconds after midnight ([`is_time_of_day`]), else an input
/// error naming `time_of_day` (a NaN would give NaN costs).
pub fn check_time_of_day(t: f64) -> Result<f64> {
    if is_time_of_day(t) {
        Ok(t)
    } else {
        Err(CoreError::input("time_of_day", "seconds after midnight in [0, 86400)", t.to_string()))
    }
}

/// A time of day as a caller writes it: text (`"HH:MM"`, `"HH:MM:SS"`) or seconds after midnight.
#[derive(Clone, Debug, PartialEq)]
pub enum TimeOfDay {
    /// `"HH:MM"` or `"HH:MM:SS"` ([`parse_time_of_day`]).
    Text(String),
    /// Seconds after midnight, in `[0, 86400)`.
    Seconds(f64),
}

impl TimeOfDay {
    /// Seconds after midnight in `[0, 86400)`, or an input error naming `time_of_day`.
    pub fn seconds(&self) -> Result<f64> {
        let t = match self {
            TimeOfDay::Text(s) => parse_time_of_day(s),
            TimeOfDay::Seconds(x) => Some(*x).filter(|&x| is_time_of_day(x)),
        };
        t.ok_or_else(|| {
            let found = match self {
                TimeOfDay::Text(s) => format!("{s:?}"),
                TimeOfDay::Seconds(x) => x.to_string(),
            };
            CoreError::input(
                "time_of_day",
                "\"HH:MM\", \"HH:MM:SS\" or seconds after midnight in [0, 86400)",
                found,
            )
        })
    }
}

/// Parses `HH:MM` or `HH:MM:SS` into seconds after midnight.
pub fn parse_time_of_day(s: &str) -> Option<f64> {
    let parts: Vec<&str> = s.trim().split(':').collect();
    if parts.len() < 2 || parts.len() > 3 {
        return None;
    }
    let h: u32 = parts[0].parse().ok()?;
    let m: u32 = parts[1].parse().ok()?;
    let sec: u32 = if parts.len() == 3 { parts[2].parse().ok()? } else { 0 };
    if h > 23 || m > 59 || sec > 59 {
        return None;
    }
    Some(f64::from(h * 3600 + m * 60 + sec))
}

/// Names of a table's entries must be unique.
pub(super) fn check_unique<'a>(file: &str, table: &str, names: impl Iterator<Item = &'a str>) -> Result<()> {
    let names: Vec<&str> = names.collect();
    for (i, n) in names.iter().enumerate() {
        if let Some(j) = names[..i].iter().position(|m| m == n) {
            return Err(err(
                file,
                format!("{table}[{i}].name"),
                format!("a unique name ({table}[{j}] is also called that)"),
                format!("{n:?}"),
            ));
        }
    }
    Ok(())
}
