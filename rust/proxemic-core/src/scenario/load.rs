//! Reading scenario files: TOML text to the raw tables, `extends` chains, and serde errors
//! mapped to scenario errors with the dotted field path and the line and column.

use std::path::Path;

use super::build::build;
use super::check::err;
use super::model::Scenario;
use super::raw::RawScenario;
use super::schema::describe_field;
use crate::error::Result;

/// Arrays of tables a file that `extends` another may add to the base's instead of replacing
/// them, by listing their names in `append` (e.g. `append = ["person"]`).
pub const APPENDABLE: [&str; 6] = ["wall", "object", "person", "robot", "activity", "replay"];

/// How many `extends` links a scenario file may chain.
pub const MAX_EXTENDS: usize = 4;

fn read_text(path: &Path) -> Result<String> {
    std::fs::read_to_string(path)
        .map_err(|e| err(&path.display().to_string(), "<file>", "a readable UTF-8 TOML file", e.to_string()))
}

/// The merged table of a file that `extends` another (None if it does not).
fn extended_table(path: &Path, text: &str, depth: usize) -> Result<Option<toml::Table>> {
    if !text.contains("extends") {
        return Ok(None);
    }
    let file = path.display().to_string();
    let mut table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let (line, col) = e.span().map_or((0, 0), |s| line_col(text, s.start));
        err(&file, format!("<toml line {line}, column {col}>"), "valid TOML", e.message().trim().to_string())
    })?;
    let Some(link) = table.remove("extends") else {
        return Ok(None);
    };
    let Some(name) = link.as_str() else {
        return Err(err(
            &file,
            "extends",
            "a path to a base scenario file (relative to this one)",
            link.to_string(),
        ));
    };
    if depth >= MAX_EXTENDS {
        return Err(err(
            &file,
            "extends",
            format!("at most {MAX_EXTENDS} chained extends"),
            format!("{name:?} at depth {}", depth + 1),
        ));
    }
    let base_path = path.parent().unwrap_or(Path::new(".")).join(name);
    if !base_path.is_file() {
        return Err(err(
            &file,
            "extends",
            "a path to an existing base scenario file (relative to this one)",
            format!("{name:?} ({} does not exist)", base_path.display()),
        ));
    }
    let base_text = read_text(&base_path)?;
    let mut base = match extended_table(&base_path, &base_text, depth + 1)? {
        Some(t) => t,
        None => base_text.parse().map_err(|e: toml::de::Error| {
            err(&base_path.display().to_string(), "<toml>", "valid TOML", e.message().trim().to_string())
        })?,
    };
    let append: Vec<String> = match table.remove("append") {
        None => Vec::new(),
        Some(toml::Value::Array(keys))
            if keys.iter().all(|k| k.as_str().is_some_and(|k| APPENDABLE.contains(&k))) =>
        {
            keys.iter().filter_map(|k| k.as_str().map(str::to_string)).collect()
        }
        Some(v) => {
            return Err(err(
                &file,
                "append",
                format!("a list of table names among {APPENDABLE:?} (their entries are added to the base's)"),
                v.to_string(),
            ));
        }
    };
    for (key, value) in table {
        match (key.as_str(), base.get_mut(&key), value) {
            ("scene", Some(toml::Value::Table(b)), toml::Value::Table(t)) => b.extend(t),
            (k, Some(toml::Value::Array(b)), toml::Value::Array(t)) if append.iter().any(|a| a == k) => {
                b.extend(t)
            }
            (_, _, v) => {
                base.insert(key, v);
            }
        }
    }
    Ok(Some(base))
}

/// Renders a serde path (`person.3.route`) the way the file is written (`person[3].route`).
fn dotted_path(path: &serde_path_to_error::Path) -> String {
    use serde_path_to_error::Segment;
    let mut out = String::new();
    for seg in path.iter() {
        match seg {
            Segment::Seq { index } => out.push_str(&format!("[{index}]")),
            Segment::Map { key } | Segment::Enum { variant: key } => {
                if !out.is_empty() {
                    out.push('.');
                }
                out.push_str(key);
            }
            Segment::Unknown => {}
        }
    }
    if out.is_empty() { "<document>".to_string() } else { out }
}

/// Line and column (1-based) of a byte offset.
fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |s| s.chars().count()) + 1;
    (line, col)
}

impl Scenario {
    /// Reads and validates a scenario file. A file with a top-level `extends = "base.toml"`
    /// (a path relative to it) starts from the base file: its `[scene]` keys override the
    /// base's one by one, and every other table or array it has (`[[robot]]`, `[episode]`,
    /// ...) replaces the base's whole, except the arrays named in its `append` list (among
    /// [`APPENDABLE`]), whose entries follow the base's (so `person[i]` in an error message
    /// counts the base's people first). Bases may extend others, up to [`MAX_EXTENDS`] deep.
    pub fn from_file(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let file = path.display().to_string();
        let text = read_text(path)?;
        match extended_table(path, &text, 0)? {
            None => Self::from_toml_str(&text, &file),
            Some(table) => {
                let raw: RawScenario =
                    serde_path_to_error::deserialize(toml::Value::Table(table)).map_err(|e| {
                        let field = dotted_path(e.path());
                        let msg = e.into_inner().message().trim().to_string();
                        let (expected, found) = explain(&field, &msg);
                        err(&file, field, expected, found)
                    })?;
                build(raw, &file)
            }
        }
    }

    /// Parses and validates scenario text; `source` names it in error messages.
    pub fn from_toml_str(text: &str, source: &str) -> Result<Self> {
        let de = toml::de::Deserializer::parse(text).map_err(|e| {
            let (line, col) = e.span().map_or((0, 0), |s| line_col(text, s.start));
            err(
                source,
                format!("<toml line {line}, column {col}>"),
                "valid TOML",
                e.message().trim().to_string(),
            )
        })?;
        let raw: RawScenario = serde_path_to_error::deserialize(de).map_err(|e| {
            let field = dotted_path(e.path());
            let inner = e.into_inner();
            let where_ = inner.span().map(|s| line_col(text, s.start));
            let msg = inner.message().trim().to_string();
            let (expected, found) = explain(&field, &msg);
            let field = match where_ {
                Some((l, c)) => format!("{field} (line {l}, column {c})"),
                None => field,
            };
            err(source, field, expected, found)
        })?;
        build(raw, source)
    }
}

/// serde's message in our words: Rust type names ("expected struct Randomize", "internally tagged
/// enum RawInteraction") and toml's "wanted string or table" replaced by what the field accepts
/// (from the scenario's JSON Schema: enum names, tagged shapes, table fields).
fn explain(field: &str, msg: &str) -> (String, String) {
    let (expected, found) = split_serde_message(msg);
    let rusty = ["struct ", "enum ", "a valid value"].iter().any(|k| expected.contains(k));
    let missing_tag = expected.starts_with("the required field `shape`");
    if !(rusty || missing_tag) {
        return (expected, found);
    }
    match describe_field(field) {
        Some(words) if missing_tag => (format!("{expected} in {words}"), found),
        Some(words) if found == "wanted string or table" => (words, "a value of another type".to_string()),
        Some(words) => (words, found),
        None => (expected, found),
    }
}

/// serde messages look like "invalid type: string \"x\", expected a number" or
/// "unknown field `foo`, expected one of `a`, `b`"; split them into (expected, found).
fn split_serde_message(msg: &str) -> (String, String) {
    if let Some(idx) = msg.find(", expected ") {
        let found = msg[..idx]
            .trim_start_matches("invalid type: ")
            .trim_start_matches("invalid value: ")
            .trim_start_matches("invalid length: ");
        let expected = &msg[idx + ", expected ".len()..];
        return (expected.to_string(), found.to_string());
    }
    if let Some(rest) = msg.strip_prefix("missing field ") {
        return (format!("the required field {rest}"), "nothing".to_string());
    }
    ("a valid value".to_string(), msg.to_string())
}
