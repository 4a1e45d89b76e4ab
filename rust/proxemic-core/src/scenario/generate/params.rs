//! The generator's parameters: defaults, ranges, and the `generated/<seed>?key=value&...` spec.

use crate::control::Drive;
use crate::error::{CoreError, Result};
use crate::scenario::model::Reaction;

/// Parameters of a generated scene. Every value has a default and a checked range
/// ([`GenParams::check`]); an out-of-range or unknown value is a [`CoreError::Scenario`] naming
/// the parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct GenParams {
    /// Scene width along x (m), in [12, 60]; default 24.
    pub width: f64,
    /// Scene height along y (m), in [10, 40]; default 16. It must leave two rooms of at least
    /// 3.5 m depth on either side of the corridor.
    pub height: f64,
    /// Clear width of the east-west corridor (m), in [2.4, 6]; default 3.
    pub corridor_width: f64,
    /// Clear width of every doorway (m), in [1.4, 3]; default 1.8.
    pub door_width: f64,
    /// People per 100 m^2 of floor, in [0, 6]; default 1.5.
    pub density: f64,
    /// Share of the people standing in conversation groups (F-formations of 2-6), in [0, 1];
    /// default 0.3.
    pub group_share: f64,
    /// Share of the other people who walk routes between rooms, in [0, 1]; default 0.4.
    pub walker_share: f64,
    /// Share of the other people seated on benches, in [0, 1] (with `walker_share` at most 1;
    /// the rest stand); default 0.2. Limited by the benches' seats.
    pub seated_share: f64,
    /// Objects (paintings, exhibits, plinths, benches) per room, in [0, 8]; default 3.
    pub objects_per_room: usize,
    /// Robots, each with a start and goal sampled free and reachable, in [1, 8]; default 1.
    pub robots: usize,
    /// Episode length (s), in [30, 3600]; default 180.
    pub max_time: f64,
    /// Conversation groups (2-3 people) placed on each robot's shortest way, in [0, 1]; default
    /// 0: an encounter a social planner has room to go round and plain A* walks into (as the
    /// museum's gallery talk). Placed where the way has room for it, else left out.
    pub encounters: usize,
    /// The people's reaction to robots (the scene's `reaction`): `ignore`, `aware`, `yield`,
    /// `curious` or `cautious`; default `aware`.
    pub reaction: Reaction,
    /// Every robot's `drive`: `holonomic` or `differential`; default `holonomic`.
    pub drive: Drive,
}

impl Default for GenParams {
    fn default() -> Self {
        GenParams {
            width: 24.0,
            height: 16.0,
            corridor_width: 3.0,
            door_width: 1.8,
            density: 1.5,
            group_share: 0.3,
            walker_share: 0.4,
            seated_share: 0.2,
            objects_per_room: 3,
            robots: 1,
            max_time: 180.0,
            encounters: 0,
            reaction: Reaction::Aware,
            drive: Drive::Holonomic,
        }
    }
}

/// Minimum clear depth of a room on either side of the corridor (m).
pub(super) const MIN_ROOM_DEPTH: f64 = 3.5;

/// The parameter names a spec or `proxemic.generate` accepts.
pub const PARAM_NAMES: [&str; 14] = [
    "width",
    "height",
    "corridor_width",
    "door_width",
    "density",
    "group_share",
    "walker_share",
    "seated_share",
    "objects_per_room",
    "robots",
    "max_time",
    "encounters",
    "reaction",
    "drive",
];

/// Hands each `key=value` pair of the spec `spec`'s `query` (the part after `?`, pairs joined by
/// `&`) to `set`, in order; errors name a pair that is not `key=value` and a key given twice.
pub(super) fn each_parameter<'q>(
    spec: &str,
    query: &'q str,
    mut set: impl FnMut(&'q str, &'q str) -> Result<()>,
) -> Result<()> {
    let mut seen: Vec<&str> = Vec::new();
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        let (k, v) = pair
            .split_once('=')
            .ok_or_else(|| perr(spec, "<spec>", "key=value pairs after '?'", format!("{pair:?}")))?;
        if seen.contains(&k) {
            return Err(perr(spec, k, "each parameter at most once", format!("{k:?} twice")));
        }
        seen.push(k);
        set(k, v)?;
    }
    Ok(())
}

/// The value of a spec's `drive` key (a name of [`Drive::NAMES`]); errors name `drive`.
pub(super) fn parse_drive(source: &str, value: &str) -> Result<Drive> {
    Drive::parse(value.trim())
        .ok_or_else(|| perr(source, "drive", format!("one of {:?}", Drive::NAMES), format!("{value:?}")))
}

/// A scenario error of the spec `source` naming `field`.
pub(super) fn perr(
    source: &str,
    field: &str,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> CoreError {
    CoreError::Scenario {
        file: source.to_string(),
        field: field.to_string(),
        expected: expected.into(),
        found: found.into(),
    }
}

impl GenParams {
    /// Sets parameter `key` from its text `value` (a number; an integer for `objects_per_room`
    /// and `robots`; a name of [`Reaction::NAMES`] for `reaction`, of [`Drive::NAMES`] for `drive`). Errors name `key` (unknown names list [`PARAM_NAMES`]); `source` names the
    /// spec in the error.
    pub fn set(&mut self, source: &str, key: &str, value: &str) -> Result<()> {
        let number = || -> Result<f64> {
            value
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| perr(source, key, "a finite number", format!("{value:?}")))
        };
        let integer = || -> Result<usize> {
            value
                .trim()
                .parse::<usize>()
                .map_err(|_| perr(source, key, "a non-negative integer", format!("{value:?}")))
        };
        match key {
            "width" => self.width = number()?,
            "height" => self.height = number()?,
            "corridor_width" => self.corridor_width = number()?,
            "door_width" => self.door_width = number()?,
            "density" => self.density = number()?,
            "group_share" => self.group_share = number()?,
            "walker_share" => self.walker_share = number()?,
            "seated_share" => self.seated_share = number()?,
            "objects_per_room" => self.objects_per_room = integer()?,
            "robots" => self.robots = integer()?,
            "max_time" => self.max_time = number()?,
            "encounters" => self.encounters = integer()?,
            "reaction" => {
                self.reaction = Reaction::parse(value.trim()).ok_or_else(|| {
                    perr(source, key, format!("one of {:?}", Reaction::NAMES), format!("{value:?}"))
                })?;
            }
            "drive" => self.drive = parse_drive(source, value)?,
            _ => {
                return Err(perr(
                    source,
                    key,
                    format!("a parameter among {PARAM_NAMES:?}"),
                    format!("{key:?}"),
                ));
            }
        }
        Ok(())
    }

    /// Checks every value against its range; errors name the parameter (`source` names the spec).
    pub fn check(&self, source: &str) -> Result<()> {
        let range = |field: &str, v: f64, lo: f64, hi: f64| -> Result<()> {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(perr(source, field, format!("a number in [{lo}, {hi}]"), format!("{v}")));
            }
            Ok(())
        };
        range("width", self.width, 12.0, 60.0)?;
        range("height", self.height, 10.0, 40.0)?;
        range("corridor_width", self.corridor_width, 2.4, 6.0)?;
        range("door_width", self.door_width, 1.4, 3.0)?;
        range("density", self.density, 0.0, 6.0)?;
        range("group_share", self.group_share, 0.0, 1.0)?;
        range("walker_share", self.walker_share, 0.0, 1.0)?;
        range("seated_share", self.seated_share, 0.0, 1.0)?;
        range("max_time", self.max_time, 30.0, 3600.0)?;
        if self.walker_share + self.seated_share > 1.0 {
            return Err(perr(
                source,
                "seated_share",
                format!("at most 1 - walker_share = {}", 1.0 - self.walker_share),
                format!("{}", self.seated_share),
            ));
        }
        if self.objects_per_room > 8 {
            return Err(perr(
                source,
                "objects_per_room",
                "an integer in [0, 8]",
                self.objects_per_room.to_string(),
            ));
        }
        if self.encounters > 1 {
            return Err(perr(source, "encounters", "an integer in [0, 1]", self.encounters.to_string()));
        }
        if !(1..=8).contains(&self.robots) {
            return Err(perr(source, "robots", "an integer in [1, 8]", self.robots.to_string()));
        }
        let need = 2.0 * (MIN_ROOM_DEPTH + 0.5) + self.corridor_width + 0.6;
        if self.height < need {
            return Err(perr(
                source,
                "height",
                format!(
                    "at least {need:.2} m (two rooms of {MIN_ROOM_DEPTH} m and the corridor of {} m)",
                    self.corridor_width
                ),
                format!("{}", self.height),
            ));
        }
        Ok(())
    }
}

/// Parses a generated-scene spec `generated/<seed>` or `generated/<seed>?key=value&key=value`
/// (keys among [`PARAM_NAMES`]) into the seed and the checked parameters. Errors are
/// [`CoreError::Scenario`] naming the spec and the part that is wrong.
pub fn parse_spec(spec: &str) -> Result<(u64, GenParams)> {
    let expected_form = "generated/<seed>[?key=value&...], e.g. generated/3?robots=2";
    let rest = spec
        .strip_prefix("generated/")
        .ok_or_else(|| perr(spec, "<spec>", expected_form, format!("{spec:?}")))?;
    let (seed_text, query) = match rest.split_once('?') {
        Some((s, q)) => (s, Some(q)),
        None => (rest, None),
    };
    let seed = seed_text
        .parse::<u64>()
        .map_err(|_| perr(spec, "seed", "a non-negative integer seed", format!("{seed_text:?}")))?;
    let mut params = GenParams::default();
    if let Some(q) = query {
        each_parameter(spec, q, |k, v| params.set(spec, k, v))?;
    }
    params.check(spec)?;
    Ok((seed, params))
}
