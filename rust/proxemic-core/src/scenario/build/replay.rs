//! Recorded crowds (`[[replay]]`): each table's CSV file read and checked, every track turned
//! into a person with behaviour [`Behaviour::Replay`].
//!
//! The file format: a header naming the four columns `t`, `id`, `x` and `y` (in any order, each
//! once, nothing else), then one sample per line: the time in seconds, the person's label (any
//! text without a comma), and the position in metres, in the recording's frame. Blank lines and
//! lines starting with `#` are skipped. A track is the rows of one `id`, in file order; its
//! times must increase strictly and it needs at least two samples (one sample has no motion to
//! replay). Every error names the CSV file, the line and the column (1-based, in characters).
//!
//! The recording's frame goes into the scene as `scene = R(rotate) (x, y) + offset`, and its
//! clock as `episode time = t - t0`; every transformed sample must lie inside `scene.bounds`.

use std::path::Path;

use crate::error::Result;
use crate::scenario::check::{Checker, err};
use crate::scenario::model::{Behaviour, Person};
use crate::scenario::raw::RawReplay;

/// The four columns of a replay file.
const COLUMNS: [&str; 4] = ["t", "id", "x", "y"];

/// One parsed row: time (s), label, position (m), and where it was (line, column of `t`).
struct Row<'a> {
    t: f64,
    id: &'a str,
    xy: [f64; 2],
    line: usize,
    t_col: usize,
}

/// The people of every `[[replay]]` table, appended after `first` people already in the scene
/// (their names are `replay<k>:<id>`). `scenario_file` is where relative paths start;
/// `features` the default socialization features every replayed person gets.
pub(super) fn build_replays(
    ck: &Checker<'_>,
    raw: &[RawReplay],
    scenario_file: &str,
    bounds: [f64; 4],
    features: &[f64],
) -> Result<Vec<Person>> {
    let mut people = Vec::new();
    for (k, r) in raw.iter().enumerate() {
        let f = format!("replay[{k}]");
        ck.range(&format!("{f}.react_radius"), r.react_radius, 0.0, 100.0, false)?;
        ck.finite(&format!("{f}.offset"), &r.offset)?;
        ck.range(&format!("{f}.rotate"), r.rotate, -std::f64::consts::TAU, std::f64::consts::TAU, false)?;
        ck.range(&format!("{f}.t0"), r.t0, -1e9, 1e9, false)?;
        ck.range(&format!("{f}.radius"), r.radius, 0.0, 0.5, true)?;
        let base = Path::new(scenario_file).parent().unwrap_or(Path::new("."));
        let path = base.join(&r.file);
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(&path).map_err(|e| {
            err(
                ck.file,
                format!("{f}.file"),
                "a readable UTF-8 CSV file `t,id,x,y` (a path relative to the scenario file)",
                format!("{:?} ({shown}: {e})", r.file),
            )
        })?;
        let rows = parse_rows(&shown, &f, &text)?;
        for (id, track) in tracks(&shown, &f, &rows)? {
            people.push(replay_person(&shown, &f, k, id, &track, r, bounds, features)?);
        }
    }
    Ok(people)
}

/// The tracks of a replay file (the format above) at `path`, in order of first appearance: each
/// track's label and its `[t, x, y]` samples as recorded (no rotation, offset or clock shift).
/// Errors name the file, the line and the column (field `recording`), like a scenario's
/// `[[replay]]` file.
pub fn read_track_file(path: &Path) -> Result<Vec<(String, Vec<[f64; 3]>)>> {
    let shown = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        err(&shown, "recording".to_string(), "a readable UTF-8 CSV file `t,id,x,y`", format!("{e}"))
    })?;
    let rows = parse_rows(&shown, "recording", &text)?;
    Ok(tracks(&shown, "recording", &rows)?
        .into_iter()
        .map(|(id, rows)| (id.to_string(), rows.iter().map(|r| [r.t, r.xy[0], r.xy[1]]).collect()))
        .collect())
}

/// The data rows of a replay file, checked (header, four columns, finite numbers).
fn parse_rows<'a>(file: &str, f: &str, text: &'a str) -> Result<Vec<Row<'a>>> {
    let mut lines = text.lines().enumerate().map(|(n, l)| (n + 1, l)).filter(|(_, l)| !is_skipped(l.trim()));
    let Some((hline, header)) = lines.next() else {
        return Err(err(file, format!("{f}.file"), "a header line `t,id,x,y` and samples", "an empty file"));
    };
    // Which field of a line holds each of t, id, x, y.
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut index = [usize::MAX; 4];
    for (c, name) in names.iter().enumerate() {
        let col = column_of(header, c);
        match COLUMNS.iter().position(|k| k == name) {
            Some(k) if index[k] == usize::MAX => index[k] = c,
            Some(_) => return Err(header_err(file, f, hline, col, &format!("{name:?} a second time"))),
            None => return Err(header_err(file, f, hline, col, &format!("the column {name:?}"))),
        }
    }
    if let Some(k) = index.iter().position(|&c| c == usize::MAX) {
        let col = header.chars().count() + 1;
        return Err(header_err(file, f, hline, col, &format!("no column {:?}", COLUMNS[k])));
    }
    let mut rows = Vec::new();
    for (line, text) in lines {
        let fields: Vec<&str> = text.split(',').collect();
        if fields.len() != 4 {
            let col = if fields.len() < 4 { text.chars().count() + 1 } else { column_of(text, 4) };
            return Err(err(
                file,
                format!("{f}.file line {line}, column {col}"),
                "4 comma-separated values t, id, x, y (in the header's order)",
                format!("{} value(s): {text:?}", fields.len()),
            ));
        }
        let number = |k: usize| -> Result<f64> {
            let c = index[k];
            let s = fields[c].trim();
            match s.parse::<f64>() {
                Ok(v) if v.is_finite() => Ok(v),
                _ => Err(err(
                    file,
                    format!("{f}.file line {line}, column {} ({})", column_of(text, c), COLUMNS[k]),
                    if k == 0 { "a finite time in seconds" } else { "a finite coordinate in metres" },
                    format!("{s:?}"),
                )),
            }
        };
        let id = fields[index[1]].trim();
        if id.is_empty() {
            return Err(err(
                file,
                format!("{f}.file line {line}, column {} (id)", column_of(text, index[1])),
                "a track label (any text without a comma)",
                "an empty value",
            ));
        }
        let t = number(0)?;
        let xy = [number(2)?, number(3)?];
        rows.push(Row { t, id, xy, line, t_col: column_of(text, index[0]) });
    }
    if rows.is_empty() {
        return Err(err(file, format!("{f}.file"), "at least one track of two samples", "a header only"));
    }
    Ok(rows)
}

fn is_skipped(line: &str) -> bool {
    line.is_empty() || line.starts_with('#')
}

fn header_err(file: &str, f: &str, line: usize, col: usize, found: &str) -> crate::error::CoreError {
    err(
        file,
        format!("{f}.file line {line}, column {col} (header)"),
        "the header t,id,x,y (the four columns in any order, each once)",
        found,
    )
}

/// The 1-based character column where field `c` (0-based, comma-separated) of `line` starts.
fn column_of(line: &str, c: usize) -> usize {
    let mut col = 1;
    for (k, field) in line.split(',').enumerate() {
        if k == c {
            break;
        }
        col += field.chars().count() + 1;
    }
    col
}

/// The rows grouped into tracks by `id` (in order of first appearance), each checked: strictly
/// increasing times, at least two samples.
fn tracks<'r, 'a>(file: &str, f: &str, rows: &'r [Row<'a>]) -> Result<Vec<(&'a str, Vec<&'r Row<'a>>)>> {
    let mut out: Vec<(&'a str, Vec<&'r Row<'a>>)> = Vec::new();
    for r in rows {
        let k = match out.iter().position(|(id, _)| *id == r.id) {
            Some(k) => k,
            None => {
                out.push((r.id, Vec::new()));
                out.len() - 1
            }
        };
        if let Some(p) = out[k].1.last().filter(|p| r.t <= p.t) {
            return Err(err(
                file,
                format!("{f}.file line {}, column {} (t)", r.line, r.t_col),
                format!(
                    "a time after {} s, id {:?}'s previous sample (line {}): each track's times increase",
                    p.t, r.id, p.line
                ),
                format!("{} s", r.t),
            ));
        }
        out[k].1.push(r);
    }
    for (id, track) in &out {
        if let [r] = track.as_slice() {
            return Err(err(
                file,
                format!("{f}.file line {}, column {} (t)", r.line, r.t_col),
                format!("at least 2 samples for id {id:?} (a track needs motion to replay)"),
                "1 sample",
            ));
        }
    }
    Ok(out)
}

/// The person replaying `track` (rows of label `id` of table `k`): samples moved into the scene
/// (rotation, offset, clock shift), each inside `bounds`; the pose is the first sample, facing
/// the second.
#[allow(clippy::too_many_arguments)]
fn replay_person(
    file: &str,
    f: &str,
    k: usize,
    id: &str,
    track: &[&Row<'_>],
    r: &RawReplay,
    bounds: [f64; 4],
    features: &[f64],
) -> Result<Person> {
    let (s, c) = r.rotate.sin_cos();
    let mut samples = Vec::with_capacity(track.len());
    for row in track {
        let [x, y] = row.xy;
        let (wx, wy) = (c * x - s * y + r.offset[0], s * x + c * y + r.offset[1]);
        if wx < bounds[0] || wx > bounds[2] || wy < bounds[1] || wy > bounds[3] {
            return Err(err(
                file,
                format!("{f}.file line {}", row.line),
                format!(
                    "a sample inside scene.bounds {bounds:?} once rotated by {f}.rotate and moved by {f}.offset"
                ),
                format!("[{x}, {y}] in the file, [{wx:.3}, {wy:.3}] in the scene"),
            ));
        }
        samples.push([row.t - r.t0, wx, wy]);
    }
    let (a, b) = (samples[0], samples[1]);
    Ok(Person {
        name: format!("replay{k}:{id}"),
        behaviour: Behaviour::Replay,
        pose: [a[1], a[2], (b[2] - a[2]).atan2(b[1] - a[1])],
        radius: r.radius,
        features: features.to_vec(),
        track: samples,
        react_radius: r.react_radius,
        ..Person::default()
    })
}
