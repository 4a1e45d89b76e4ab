//! A mutation fuzzer for the scenario parser and the world builder: no input may make
//! [`Scenario::from_toml_str`], [`World::new`], [`World::reset`], [`World::step`] or
//! [`World::episode_metrics`] panic, nor make an episode's record break one of its invariants
//! ([`proxemic_core::metrics::invariants`]: a [`CoreError::Invariant`] is a finding too).
//!
//! Three kinds of input, in turn: scenario files (TOML), the names of generated scenes
//! (`generated/<seed>?key=value&...`, `francis2023/<archetype>?seed=N&max_time=T&drive=D`,
//! `crowdnav/<family>?humans=N&visible=B&seed=S&drive=D`, whose kinematic protocol episode also runs: mutated as
//! text and as key=value pairs, with keys repeated, added, dropped and given extreme values), and
//! the CSV track files of `[[replay]]` tables (written to a temporary folder beside a scenario
//! naming them).
//!
//! Each validated scenario also goes through an override the Python API exposes, with extreme
//! arguments (`with_robots` from 0 to `usize::MAX`, `with_goal` of a robot out of range or at a
//! non-finite point, `with_robot_planner` with any name), and each built world is reset with an
//! extreme seed (0, 7, 2^63, `u64::MAX`) and asked for robot indices out of range (path,
//! trajectory, A* path, cost grid, metrics...): none of this may panic.
//!
//! `cargo fuzz` needs a nightly toolchain, which cannot be installed here, so this is a
//! structure-aware mutation fuzzer on the stable toolchain: it starts from the bundled scenario
//! files and a few small ones, and applies seeded mutations that keep the text TOML-like (numbers
//! replaced by interesting values — zero, negatives, NaN, infinities, huge and tiny magnitudes —,
//! array elements dropped or added, lines deleted, duplicated or swapped, kind and behaviour names
//! swapped, strings replaced, bytes inserted, the text truncated). Each mutant is parsed, and if it
//! validates, its world is built, reset and stepped a few control steps (the robots moved
//! kinematically by their commands) and its records made, all under `catch_unwind`. A panic is a finding: the
//! input is written to `fuzz-findings/` and the run exits with code 1. Errors are expected and
//! fine: they are what validation is for.
//!
//! A mutant that validates but describes a world too large to build quickly (over the grid limit
//! the scenario enforces, or thousands of people) is still built: that is part of what is tested.
//!
//! Run: `make fuzz` (`FUZZ_SECONDS`, default 600; `FUZZ_ARGS=--keep-going` records every finding
//! and runs to the end, exiting 1 if there was any), or
//! `cargo run --release -p proxemic-core --example fuzz_scenario -- --seconds N [--seed S] [--keep-going]`.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use proxemic_core::CoreError;
use proxemic_core::math::Vec2;
use proxemic_core::scenario::generate::{self, crowdnav, francis2023};
use proxemic_core::scenario::{MAX_ROBOTS, Scenario};
use proxemic_core::world::World;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng as StdRng;

mod common;

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
    "holonomic",
    "differential",
    "",
    "robot:r0",
    "fast",
    "elderly",
    "x",
    "museum.toml",
    "../../../etc/passwd",
];

/// Scene names the name mutants start from.
const SCENE_NAMES: &[&str] = &[
    "generated/0",
    "generated/3?robots=2&max_time=60",
    "generated/7?rooms=2&people_per_room=4&objects_per_room=1",
    "francis2023/frontal_approach",
    "francis2023/crossing_90?seed=2&max_time=30",
    "francis2023/pedestrian_obstruction?seed=5",
    "crowdnav/circle_crossing",
    "crowdnav/circle_crossing?humans=20&visible=true&seed=4",
    "crowdnav/square_crossing?humans=5&seed=9",
    "generated/5?drive=differential",
    "francis2023/crossing_90?seed=2&drive=differential",
    "crowdnav/square_crossing?humans=5&seed=3&drive=differential",
];

/// A scene name mutated as `prefix?key=value&...`: a pair repeated (a duplicate key, refused),
/// a known key added with an interesting value, a pair dropped, a value replaced, the archetype
/// or seed segment replaced; or, one time in four, as text ([`mutate`]).
fn mutate_name(name: &str, rng: &mut StdRng) -> String {
    if rng.random_bool(0.25) {
        return mutate(name, rng).replace('\n', "&");
    }
    let (head, query) = name.split_once('?').unwrap_or((name, ""));
    let mut head = head.to_string();
    let mut pairs: Vec<String> = query.split('&').filter(|p| !p.is_empty()).map(str::to_string).collect();
    let value = |rng: &mut StdRng| {
        if rng.random_bool(0.2) {
            NAMES[rng.random_range(0..NAMES.len())].to_string()
        } else {
            NUMBERS[rng.random_range(0..NUMBERS.len())].trim_matches('"').to_string()
        }
    };
    for _ in 0..rng.random_range(1..=3) {
        match rng.random_range(0..6) {
            0 if !pairs.is_empty() => {
                let p = pairs[rng.random_range(0..pairs.len())].clone();
                pairs.insert(rng.random_range(0..=pairs.len()), p);
            }
            1 | 2 => {
                let keys: Vec<&str> = generate::PARAM_NAMES
                    .iter()
                    .copied()
                    .chain(["seed", "max_time", "humans", "visible", "x"])
                    .collect();
                let k = keys[rng.random_range(0..keys.len())];
                let v = value(rng);
                pairs.insert(rng.random_range(0..=pairs.len()), format!("{k}={v}"));
            }
            3 if !pairs.is_empty() => {
                pairs.remove(rng.random_range(0..pairs.len()));
            }
            4 if !pairs.is_empty() => {
                let i = rng.random_range(0..pairs.len());
                let k = pairs[i].split('=').next().unwrap_or("").to_string();
                pairs[i] = format!("{k}={}", value(rng));
            }
            _ => {
                let last = if head.starts_with(francis2023::PREFIX) && rng.random_bool(0.7) {
                    francis2023::ARCHETYPES[rng.random_range(0..francis2023::ARCHETYPES.len())].to_string()
                } else {
                    value(rng)
                };
                let prefix = head.rsplit_once('/').map_or("generated", |(p, _)| p).to_string();
                head = format!("{prefix}/{last}");
            }
        }
    }
    if pairs.is_empty() { head } else { format!("{head}?{}", pairs.join("&")) }
}

/// A track file the CSV mutants start from (three people crossing a 12 m x 8 m hall).
const TRACKS: &str = "t,id,x,y\n0.0,a,1.0,4.0\n0.0,b,11.0,4.2\n0.4,a,1.5,4.0\n0.4,b,10.5,4.2\n0.8,a,2.0,4.0\n\
                      0.8,b,10.0,4.1\n1.2,b,9.5,4.0\n2.0,c,6.0,1.0\n2.4,c,6.0,1.5\n2.8,c,6.0,2.0\n";

/// The scenario around the track files (its `replay.file` is `tracks.csv` beside it).
const REPLAY_SCENE: &str = "[scene]\nname = \"fuzz_replay\"\nbounds = [0, 0, 12, 8]\n[[robot]]\nstart = [0.5, 4, 0]\n\
                            goal = [11.5, 4]\n[[replay]]\nfile = \"tracks.csv\"\nreact_radius = 1.5\n\
                            [episode]\nmax_time = 10\n";

fn corpus(root: &Path) -> Vec<String> {
    let mut out = vec![
        "[scene]\nname = \"a\"\nbounds = [0, 0, 4, 4]\n[[robot]]\nstart = [1, 1, 0]\ngoal = [3, 3]\n"
            .to_string(),
        String::new(),
        "[[robot]]\nstart = [1, 1, 0]\ngoal = [3, 3]\n".to_string(),
        "[scene]\nname = \"d\"\nbounds = [0, 0, 6, 4]\n[[person]]\nroute = [[5, 2], [1, 2]]\n[[robot]]\nstart = [1, 1, 0]\n\
         goal = [5, 3]\ndrive = \"differential\"\nmax_angular_accel = 5.0\nplanner = \"social\"\n"
            .to_string(),
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

/// Control steps each built world is stepped before its records are made.
const STEPS: usize = 12;

/// What one input is.
enum Input<'a> {
    /// A scenario file's text.
    Toml(&'a str),
    /// A generated or Francis et al. 2023 scene's name.
    Name(&'a str),
    /// A replay track file's text (beside [`REPLAY_SCENE`] in `dir`).
    Tracks(&'a str, &'a Path),
}

/// Episode seeds a world is reset with (the binding takes any of [0, 2^64)).
const SEEDS: [u64; 4] = [7, 0, 1 << 63, u64::MAX];

/// An override of the Python API applied to a validated scenario, with extreme arguments.
#[derive(Clone, Copy, Debug)]
enum Override {
    /// None: the scenario as it is.
    Keep,
    /// `Scenario::with_robots(n)`.
    Robots(usize),
    /// `Scenario::with_goal(robot, goal)`.
    Goal(usize, [f64; 2]),
    /// `Scenario::with_robot_planner(robot, name)`.
    Planner(usize, &'static str),
}

/// Interesting coordinates of a goal override.
const COORDS: [f64; 8] = [0.0, -1.0, 1.5, 4.0, 1e9, f64::NAN, f64::INFINITY, -0.0];

fn pick_override(rng: &mut StdRng) -> Override {
    let index = |rng: &mut StdRng| [0, 1, 2, MAX_ROBOTS, usize::MAX][rng.random_range(0..5)];
    match rng.random_range(0..8) {
        0 => Override::Robots(
            [0, 1, 2, 3, MAX_ROBOTS, MAX_ROBOTS + 1, 1 << 20, usize::MAX][rng.random_range(0..8)],
        ),
        1 => {
            let goal = [COORDS[rng.random_range(0..COORDS.len())], COORDS[rng.random_range(0..COORDS.len())]];
            Override::Goal(index(rng), goal)
        }
        2 => Override::Planner(index(rng), NAMES[rng.random_range(0..NAMES.len())]),
        _ => Override::Keep,
    }
}

/// `scenario` with `o` applied; `None` when the override is refused (an error, as it should be).
fn apply(scenario: Scenario, o: Override) -> Option<Scenario> {
    match o {
        Override::Keep => Some(scenario),
        Override::Robots(n) => scenario.with_robots(n).ok(),
        Override::Goal(robot, goal) => scenario.with_goal(robot, goal).ok(),
        Override::Planner(robot, name) => scenario.with_robot_planner(robot, name).ok(),
    }
}

/// Asks `world` (of `n` robots) about robot indices out of range: every accessor must answer
/// `None`, zero or an error, never panic.
fn probe_indices(world: &mut World, n: usize) {
    for i in [n, n + 1, usize::MAX] {
        let _ = world.path(i).map(<[Vec2]>::len);
        let _ = world.trajectory(i).map(<[[f64; 3]]>::len);
        let _ = world.astar_path(i).map(<[Vec2]>::len);
        let _ = world.cost_grid(i).is_some();
        let _ = world.geodesic_start_distance(i);
        let _ = world.replans(i) + world.social_searches(i);
        let _ = world.plan(i, Vec2::new(1.0, 1.0), Vec2::new(2.0, 2.0));
        let _ = world.robot_metrics(&[0, i]).is_ok();
    }
}

/// Builds, resets (from `seed`) and steps the world of `scenario`, then makes its records; `Err`
/// carries an invariant's error (a finding).
fn run_world(scenario: Scenario, seed: u64) -> Result<(), String> {
    let Ok(mut world) = World::new(scenario) else {
        return Ok(());
    };
    let stride = world.layout().stride;
    let n = world.num_robots();
    let mut out = vec![0.0; n * stride];
    let mut people = vec![0.0; world.num_people() * proxemic_core::world::PERSON_OUT];
    if world.reset(seed, &mut out, &mut people).is_err() {
        return Ok(());
    }
    let mut state = vec![0.0; 6 * n];
    let contacts = vec![0u8; n];
    let actions = vec![f64::NAN; 3 * n];
    let dt = world.scenario().control_dt();
    for _ in 0..STEPS {
        if world.command(&actions, &mut out).is_err() {
            break;
        }
        common::kinematics(&world, &out, &mut state, dt);
        if world.step(&state, &contacts, &mut out, &mut people).is_err() {
            break;
        }
    }
    probe_indices(&mut world, n);
    match world.episode_metrics() {
        Err(e @ CoreError::Invariant { .. }) => Err(format!("invariant broken: {e}")),
        _ => Ok(()),
    }
}

/// Parses one input, applies `o` to it, builds, resets (from `seed`) and steps it; `Ok(true)`
/// when it validated and `o` was accepted, `Err` carries the panic message or the broken invariant.
fn exercise(input: &Input, o: Override, seed: u64) -> Result<bool, String> {
    let run = catch_unwind(AssertUnwindSafe(|| -> Result<bool, String> {
        let scenario = match input {
            Input::Toml(text) => Scenario::from_toml_str(text, "fuzz.toml"),
            Input::Name(name) if name.starts_with(francis2023::PREFIX) => {
                francis2023::generate(name).map(|g| g.scenario)
            }
            Input::Name(name) if name.starts_with(crowdnav::PREFIX) => {
                // CrowdNav's own kinematic episode of the name too, with one of the planners.
                let planner = proxemic_core::world::crowdnav::PLANNERS
                    [seed as usize % proxemic_core::world::crowdnav::PLANNERS.len()];
                match proxemic_core::world::crowdnav::run_episode(name, planner) {
                    Err(e @ CoreError::Invariant { .. }) => return Err(format!("invariant broken: {e}")),
                    Ok(ep) if !(ep.time.is_finite() && ep.time > 0.0) => {
                        return Err(format!("{name} with {planner}: episode time {}", ep.time));
                    }
                    _ => {}
                }
                crowdnav::generate(name).map(|g| g.scenario)
            }
            Input::Name(name) => generate::parse_spec(name)
                .and_then(|(seed, p)| generate::generate(seed, &p))
                .map(|g| g.scenario),
            Input::Tracks(text, dir) => {
                let _ = std::fs::write(dir.join("tracks.csv"), text);
                let source = dir.join("fuzz.toml");
                Scenario::from_toml_str(REPLAY_SCENE, &source.display().to_string())
            }
        };
        let Ok(scenario) = scenario else {
            return Ok(false);
        };
        let Some(scenario) = apply(scenario, o) else {
            return Ok(false); // the override refused: an error, as it should be
        };
        run_world(scenario, seed).map(|()| true)
    }));
    run.map_err(|e| {
        let msg = e
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| (*s).to_string()))
            .unwrap_or_else(|| "a panic".to_string());
        format!("panic {msg:?}")
    })?
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
    // --keep-going: record every finding (the first 50 inputs written) and run to the end.
    let keep_going = args.iter().any(|a| a == "--keep-going");
    let mut findings: Vec<String> = Vec::new();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../python/proxemic/data/envs");
    let seeds = corpus(&root);
    // Quiet the default panic hook: findings are reported once, below.
    std::panic::set_hook(Box::new(|_| {}));
    let mut rng = StdRng::seed_from_u64(seed);
    let tmp = std::env::temp_dir().join(format!("proxemic-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&tmp);
    let deadline = Instant::now() + Duration::from_secs(seconds);
    let (mut runs, mut valid) = (0u64, 0u64);
    let (mut kinds, mut valid_kinds) = ([0u64; 3], [0u64; 3]);
    let start = Instant::now();
    while Instant::now() < deadline {
        // Scenario files most of the time; names and track files one input in five each.
        let kind = match rng.random_range(0..5) {
            0 => 1,
            1 => 2,
            _ => 0,
        };
        let text = match kind {
            1 => mutate_name(SCENE_NAMES[rng.random_range(0..SCENE_NAMES.len())], &mut rng),
            2 => mutate(TRACKS, &mut rng),
            _ => mutate(&seeds[rng.random_range(0..seeds.len())], &mut rng),
        };
        let input = match kind {
            1 => Input::Name(&text),
            2 => Input::Tracks(&text, &tmp),
            _ => Input::Toml(&text),
        };
        let o = pick_override(&mut rng);
        let world_seed = SEEDS[rng.random_range(0..SEEDS.len())];
        runs += 1;
        kinds[kind] += 1;
        match exercise(&input, o, world_seed) {
            Ok(ok) => {
                valid += u64::from(ok);
                valid_kinds[kind] += u64::from(ok);
            }
            Err(msg) => {
                let msg = format!("{msg} (override {o:?}, reset seed {world_seed})");
                findings.push(msg.clone());
                if findings.len() <= 50 {
                    let dir = Path::new("fuzz-findings");
                    let _ = std::fs::create_dir_all(dir);
                    let ext = ["toml", "name.txt", "csv"][kind];
                    let path = dir.join(format!("finding-{seed}-{runs}.{ext}"));
                    let _ = std::fs::write(&path, &text);
                    eprintln!("FINDING after {runs} inputs: {msg}; input written to {}", path.display());
                }
                if !keep_going {
                    let _ = std::fs::remove_dir_all(&tmp);
                    std::process::exit(1);
                }
            }
        }
        if runs % 2000 == 0 {
            eprintln!("{runs} inputs ({valid} built) in {:.0} s", start.elapsed().as_secs_f64());
        }
    }
    let _ = std::fs::remove_dir_all(&tmp);
    let verdict = if findings.is_empty() {
        "no panic, no broken invariant".to_string()
    } else {
        format!("{} findings (inputs in fuzz-findings/)", findings.len())
    };
    println!(
        "fuzz_scenario: {runs} inputs ({} scenario files, {} scene names, {} replay track files; {valid} valid, \
         built and stepped: {}, {} and {}) in {:.0} s, seed {seed}: {verdict}",
        kinds[0],
        kinds[1],
        kinds[2],
        valid_kinds[0],
        valid_kinds[1],
        valid_kinds[2],
        start.elapsed().as_secs_f64()
    );
    if !findings.is_empty() {
        std::process::exit(1);
    }
}
