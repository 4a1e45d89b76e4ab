//! A mutation fuzzer for the scenario parser and the world builder: no input may make
//! [`Scenario::from_toml_str`], [`World::new`] or [`World::reset`] panic.
//!
//! `cargo fuzz` needs a nightly toolchain, which cannot be installed here, so this is a
//! structure-aware mutation fuzzer on the stable toolchain: it starts from the bundled scenario
//! files and a few small ones, and applies seeded mutations that keep the text TOML-like (numbers
//! replaced by interesting values — zero, negatives, NaN, infinities, huge and tiny magnitudes —,
//! array elements dropped or added, lines deleted, duplicated or swapped, kind and behaviour names
//! swapped, strings replaced, bytes inserted, the text truncated). Each mutant is parsed, and if it
//! validates, its world is built and reset, all under `catch_unwind`. A panic is a finding: the
//! input is written to `fuzz-findings/` and the run exits with code 1. Errors are expected and
//! fine: they are what validation is for.
//!
//! A mutant that validates but describes a world too large to build quickly (over the grid limit
//! the scenario enforces, or thousands of people) is still built: that is part of what is tested.
//!
//! Run: `make fuzz` (`FUZZ_SECONDS`, default 600), or
//! `cargo run --release -p proxemic-core --example fuzz_scenario -- --seconds N [--seed S]`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use proxemic_core::scenario::Scenario;
use proxemic_core::world::World;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng as StdRng;

/// Values a number may be replaced with.
const NUMBERS: &[&str] = &[
    "0",
    "-0.0",
    "1",
    "-1",
    "0.5",
    "-0.5",
    "2",
    "3",
    "7",
    "100",
    "-100",
    "1e9",
    "-1e9",
    "1e308",
    "-1e308",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "65536",
    "4294967296",
    "18446744073709551615",
    "-9223372036854775808",
    "0.0001",
    "1000",
    "\"1\"",
    "true",
    "[]",
    "[1]",
    "{}",
];

/// Names a quoted string may be replaced with (kinds, behaviours, planners, presets, times).
const NAMES: &[&str] = &[
    "exhibit",
    "painting",
    "poster",
    "tv",
    "table",
    "round_table",
    "bed",
    "stretcher",
    "sofa",
    "bench",
    "plinth",
    "pillar",
    "cabinet",
    "chair",
    "walker",
    "standing",
    "visitor",
    "conversation",
    "guide",
    "follower",
    "seated",
    "resident",
    "staff",
    "astar",
    "social",
    "social_astar",
    "astar_orca",
    "astar_stop",
    "eband",
    "social_momentum",
    "daza2021",
    "hall",
    "kirby",
    "asymmetric",
    "delaunay",
    "density",
    "fformation",
    "trapezoid",
    "rectangle",
    "circle",
    "polygon",
    "10:00",
    "25:61",
    "",
    "robot:r0",
    "fast",
    "elderly",
    "x",
    "museum.toml",
    "../../../etc/passwd",
];

fn corpus(root: &Path) -> Vec<String> {
    let mut out = vec![
        "[scene]\nname = \"a\"\nbounds = [0, 0, 4, 4]\n[[robot]]\nstart = [1, 1, 0]\ngoal = [3, 3]\n"
            .to_string(),
        String::new(),
        "[[robot]]\nstart = [1, 1, 0]\ngoal = [3, 3]\n".to_string(),
    ];
    let mut files: Vec<PathBuf> = std::fs::read_dir(root)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.sort();
    for f in files {
        if f.extension().is_some_and(|e| e == "toml")
            && let Ok(text) = std::fs::read_to_string(&f)
        {
            // `extends` names files relative to the scenario; the fuzzer parses from a string.
            out.push(
                text.lines()
                    .filter(|l| !l.trim_start().starts_with("extends"))
                    .collect::<Vec<_>>()
                    .join("\n"),
            );
        }
    }
    out
}

/// Byte ranges of the numbers in `text` (a digit run with sign, point and exponent).
fn number_spans(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut spans = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit() || (b[i] == b'-' && i + 1 < b.len() && b[i + 1].is_ascii_digit());
        if starts && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_')) {
            let s = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit() || matches!(b[i], b'.' | b'e' | b'E' | b'+' | b'-' | b'_'))
            {
                i += 1;
            }
            spans.push((s, i));
        } else {
            i += 1;
        }
    }
    spans
}

/// Byte ranges of the double-quoted strings in `text` (contents only).
fn string_spans(text: &str) -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut open = None;
    for (i, c) in text.char_indices() {
        if c == '"' {
            match open.take() {
                Some(s) => spans.push((s, i)),
                None => open = Some(i + 1),
            }
        } else if c == '\n' {
            open = None;
        }
    }
    spans
}

fn mutate(text: &str, rng: &mut StdRng) -> String {
    let mut t = text.to_string();
    for _ in 0..rng.random_range(1..=4) {
        t = mutate_once(&t, rng);
    }
    t
}

fn mutate_once(text: &str, rng: &mut StdRng) -> String {
    let lines: Vec<&str> = text.lines().collect();
    match rng.random_range(0..9) {
        0..=2 => replace_span(text, &number_spans(text), NUMBERS, rng),
        3 => replace_span(text, &string_spans(text), NAMES, rng),
        4 if !lines.is_empty() => {
            let mut v = lines.clone();
            v.remove(rng.random_range(0..lines.len()));
            v.join("\n")
        }
        5 if !lines.is_empty() => duplicate_block(&lines, rng),
        6 if lines.len() > 1 => {
            let mut v = lines.clone();
            let (a, b) = (rng.random_range(0..v.len()), rng.random_range(0..v.len()));
            v.swap(a, b);
            v.join("\n")
        }
        7 => resize_array(text, rng),
        _ => corrupt_bytes(text, rng),
    }
}

/// One of `spans` replaced by one of `values`.
fn replace_span(text: &str, spans: &[(usize, usize)], values: &[&str], rng: &mut StdRng) -> String {
    if spans.is_empty() {
        return text.to_string();
    }
    let (s, e) = spans[rng.random_range(0..spans.len())];
    format!("{}{}{}", &text[..s], values[rng.random_range(0..values.len())], &text[e..])
}

/// A block of up to 6 lines copied elsewhere.
fn duplicate_block(lines: &[&str], rng: &mut StdRng) -> String {
    let k = rng.random_range(0..lines.len());
    let n = rng.random_range(1..=6).min(lines.len() - k);
    let mut v = lines.to_vec();
    let at = rng.random_range(0..=v.len());
    for (j, l) in lines[k..k + n].iter().enumerate() {
        v.insert(at + j, l);
    }
    v.join("\n")
}

/// An array grows or shrinks by one element.
fn resize_array(text: &str, rng: &mut StdRng) -> String {
    let opens: Vec<usize> = text.match_indices('[').map(|(i, _)| i).filter(|&i| i + 1 < text.len()).collect();
    if opens.is_empty() {
        return text.to_string();
    }
    let at = opens[rng.random_range(0..opens.len())] + 1;
    if rng.random_bool(0.5) {
        return format!("{}{}, {}", &text[..at], NUMBERS[rng.random_range(0..NUMBERS.len())], &text[at..]);
    }
    match text[at..].find(',') {
        Some(c) if !text[at..at + c].contains(['[', ']', '\n']) => {
            format!("{}{}", &text[..at], &text[at + c + 1..])
        }
        _ => text.to_string(),
    }
}

/// The text truncated, or a fragment of TOML syntax (or an invalid byte) inserted.
fn corrupt_bytes(text: &str, rng: &mut StdRng) -> String {
    let mut bytes = text.as_bytes().to_vec();
    if !bytes.is_empty() && rng.random_bool(0.3) {
        bytes.truncate(rng.random_range(0..bytes.len()));
    } else {
        let at = rng.random_range(0..=bytes.len());
        let junk: &[u8] = [b"=".as_slice(), b"[[person]]\n", b"\"", b"]", b"\n[", b"\xff", b"#", b"{", b"."]
            [rng.random_range(0..9)];
        bytes.splice(at..at, junk.iter().copied());
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// Parses, builds and resets one input; `Err` carries the panic message.
fn exercise(text: &str) -> Result<bool, String> {
    catch_unwind(AssertUnwindSafe(|| {
        let Ok(scenario) = Scenario::from_toml_str(text, "fuzz.toml") else {
            return false;
        };
        let Ok(mut world) = World::new(scenario) else {
            return true;
        };
        let stride = world.layout().stride;
        let mut out = vec![0.0; world.num_robots() * stride];
        let mut people = vec![0.0; world.num_people() * proxemic_core::world::PERSON_OUT];
        let _ = world.reset(7, &mut out, &mut people);
        true
    }))
    .map_err(|e| {
        e.downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| (*s).to_string()))
            .unwrap_or_else(|| "a panic".to_string())
    })
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str, default: u64| -> u64 {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    let seconds = arg("--seconds", 600);
    let seed = arg("--seed", 1);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../python/proxemic/data/envs");
    let seeds = corpus(&root);
    // Quiet the default panic hook: findings are reported once, below.
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = StdRng::seed_from_u64(seed);
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let (mut runs, mut valid) = (0u64, 0u64);
    let start = Instant::now();
    while Instant::now() < deadline {
        let base = &seeds[rng.random_range(0..seeds.len())];
        let input = mutate(base, &mut rng);
        runs += 1;
        match exercise(&input) {
            Ok(ok) => valid += u64::from(ok),
            Err(msg) => {
                let dir = Path::new("fuzz-findings");
                let _ = std::fs::create_dir_all(dir);
                let path = dir.join(format!("panic-{seed}-{runs}.toml"));
                let _ = std::fs::write(&path, &input);
                eprintln!("FINDING after {runs} inputs: panic {msg:?}; input written to {}", path.display());
                std::process::exit(1);
            }
        }
        if runs % 2000 == 0 {
            eprintln!("{runs} inputs ({valid} built) in {:.0} s", start.elapsed().as_secs_f64());
        }
    }
    println!(
        "fuzz_scenario: {runs} inputs ({valid} valid and built) in {:.0} s, seed {seed}: no panic",
        start.elapsed().as_secs_f64()
    );
}
