//! Hostile input at every layer (issue 17): example scenes mutated at random (numbers
//! set to extremes, lines dropped or doubled, keys of every kind inserted, `--set`
//! overrides added) are refused with located errors or drawn, through the render
//! pipeline into a folder; nothing panics, and no frame is written behind an error of
//! bad input. The same promise holds for every input in `fuzz/seeds/`, the corpus of
//! every crash the fuzzers found.
//!
//! CI runs [`DEFAULT_CASES`] mutations (about a minute); a long run raises the count
//! with `PHYSFRAMES_FUZZ_CASES`, e.g.
//! `PHYSFRAMES_FUZZ_CASES=200000 cargo test --release --test integration mutations`.
//! The mutations come from a fixed seed, so that CI tries the same cases on every run;
//! `PHYSFRAMES_FUZZ_SEED=N` tries others (a failure prints the seed it ran with).
//! `PHYSFRAMES_FUZZ_LOG=1` names each case before it runs: a case that aborts the
//! process (an allocation refused under `ulimit -v`) prints nothing of its own, and
//! the last case named is the one.

use std::path::{Path, PathBuf};

use physframes::error::exit;
use physframes::fuzzing::{exercise, Outcome, SET_PREFIX};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed, TestCaseError, TestRunner};

/// Mutated scenes per CI run.
const DEFAULT_CASES: u32 = 10_000;

/// The seed of CI's mutations.
const DEFAULT_SEED: u64 = 1;

/// Numbers and values a careless or hostile user might write anywhere.
const VALUES: &[&str] = &[
    "0",
    "-0.0",
    "1",
    "-1",
    "0.5",
    "2",
    "1e-308",
    "5e-324",
    "1e-300",
    "1e-12",
    "1e-9",
    "1e12",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    "nan",
    "inf",
    "-inf",
    "9007199254740993",
    "16385",
    "10000001",
    "-9223372036854775808",
    "true",
    "\"x\"",
    "\"\"",
    "[]",
    "[0, 0]",
    "[1e308, -1e308]",
    "[nan, 0]",
    "[1, 2, 3]",
    "[[0, 0], [1, 0]]",
    "[[0, 0], [1, 0], [0, 1]]",
    "[[0, 0], [1e308, 0], [0, 1e308]]",
    "{ min = 0, max = 1e308 }",
    "{ min = [0, 0], max = [1e308, 1e308] }",
    "{ min = 1, max = 0 }",
    "{ circle = { radius = 1e-300 } }",
    "{ box = { width = 1e300, height = 1 } }",
    "[\"euler\", \"rk4\", \"exact\"]",
    "[\"dopri5\", \"verlet\"]",
    "\"dopri5\"",
    "\"torque\"",
    "\"angular-drag\"",
    "\"spring\"",
    "\"body0\"",
    "[\"body0\"]",
    "\"#ff0000\"",
    "\"sin(x)^y\"",
    "\"1/0\"",
    "1e-3",
    "10",
    "1e3",
    "1e6",
    "1e-6",
    "0.01",
    "100",
    "3.14159",
    "-2.5",
    "1e-4",
];

/// Keys of every part of a scene: rigid bodies, swarms, comparisons, layers, and the
/// collision keys about to land (refused as unknown until then).
const KEYS: &[&str] = &[
    "dt",
    "duration",
    "fps",
    "width",
    "height",
    "integrator",
    "rtol",
    "atol",
    "compare",
    "mass",
    "position",
    "velocity",
    "shape",
    "points",
    "color",
    "angle",
    "angular_velocity",
    "inertia",
    "kind",
    "k",
    "c",
    "g",
    "f0",
    "f1",
    "at",
    "a",
    "b",
    "a_at",
    "b_at",
    "stiffness",
    "rest_length",
    "damping",
    "centre",
    "strength",
    "tau",
    "bodies",
    "count",
    "seed",
    "trails",
    "hud",
    "show_springs",
    "show_velocity",
    "show_force",
    "velocity_scale",
    "force_scale",
    "view",
    "grid",
    "f",
    "x",
    "y",
    "h",
    "restitution",
    "tolerance",
    "friction",
    "static",
    "rest_speed",
    "slop",
    "iterations",
    "sleep",
    "sleep_speed",
    "sleep_time",
    "layout",
];

/// `--set` keys, by the paths the command line takes.
const SET_KEYS: &[&str] = &[
    "simulation.dt",
    "simulation.duration",
    "simulation.integrator",
    "simulation.compare",
    "render.fps",
    "render.width",
    "render.height",
    "render.view.min",
    "render.trails",
    "body.body0.mass",
    "body.body0.angle",
    "body.body0.angular_velocity",
    "body.body0.inertia",
    "body.body0.shape",
    "force.0.tau",
    "force.0.k",
    "force.0.at",
    "force.0.kind",
    "swarm.0.count",
    "swarm.0.angle",
    "curve.0.h",
    "field.0.grid",
    "contacts.restitution",
    "contacts.friction",
    "contacts.rest_speed",
    "contacts.slop",
    "contacts.iterations",
    "contacts.sleep",
    "contacts.sleep_speed",
    "contacts.sleep_time",
    "body.body0.static",
    "body.body0.friction",
    "name",
];

/// Whole tables to append: swarms, turning forces, comparisons, contacts.
const BLOCKS: &[&str] = &[
    "[[swarm]]\nname = \"dust\"\ncount = 50\nmass = 1.0\nposition = { min = [-1.0, -1.0], max = [1.0, 1.0] }\nangle = { min = 0.0, max = 6.0 }\nangular_velocity = { min = -5.0, max = 5.0 }\nshape = { box = { width = 0.1, height = 0.05 } }\n",
    "[[force]]\nkind = \"torque\"\ntau = 2.0\n",
    "[[force]]\nkind = \"angular-drag\"\nk = 0.5\n",
    "[[force]]\nkind = \"force\"\nf0 = [1.0, 0.0]\nat = [0.1, 0.1]\n",
    "[[force]]\nkind = \"spring\"\na = \"body0\"\nb = [0.0, 0.0]\nstiffness = 10.0\na_at = [0.1, 0.0]\n",
    "[[body]]\nmass = 1.0\nangular_velocity = 3.0\nshape = { polygon = { points = [[0, 0], [1, 0], [0, 1]] } }\nshow_velocity = true\nshow_force = true\n",
    "[contacts]\nrestitution = 0.5\ntolerance = 1e-6\nfriction = 0.3\n",
    "[contacts]\nrest_speed = 0.1\nslop = 0.01\niterations = 5\nsleep_speed = 0.5\nsleep_time = 0.05\n[[body]]\nname = \"floor\"\nstatic = true\nposition = [0.0, -2.0]\nshape = { box = { width = 10.0, height = 0.5 } }\n[[force]]\nkind = \"gravity\"\nbodies = [\"body0\"]\n",
    "[[swarm]]\nname = \"gas\"\ncount = 20\nmass = 1.0\nlayout = \"grid\"\nfriction = 0.5\nrestitution = 0.9\nposition = { min = [-1.0, 1.0], max = [1.0, 2.0] }\nshape = { circle = { radius = 0.02 } }\n",
    "[axes]\n",
    "[[field]]\nkind = \"slope\"\nf = \"-y\"\n",
    "[[curve]]\nkind = \"trace\"\nx = \"t\"\ny = \"body0.x\"\n",
];

/// One change to a scene's text.
#[derive(Clone, Debug)]
enum Mutation {
    /// Replace the n-th number of the text with a value.
    Number(usize, usize),
    DropLine(usize),
    DoubleLine(usize),
    /// Insert `key = value` after a line.
    Insert(usize, usize, usize),
    Append(usize),
    /// Add a `--set key=value`.
    Set(usize, usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let any_index = 0usize..10_000;
    prop_oneof![
        3 => (any_index.clone(), 0..VALUES.len()).prop_map(|(n, v)| Mutation::Number(n, v)),
        1 => any_index.clone().prop_map(Mutation::DropLine),
        1 => any_index.clone().prop_map(Mutation::DoubleLine),
        3 => (any_index, 0..KEYS.len(), 0..VALUES.len())
            .prop_map(|(l, k, v)| Mutation::Insert(l, k, v)),
        1 => (0..BLOCKS.len()).prop_map(Mutation::Append),
        2 => (0..SET_KEYS.len(), 0..VALUES.len()).prop_map(|(k, v)| Mutation::Set(k, v)),
    ]
}

/// The byte ranges of the number literals in `text`.
fn numbers(text: &str) -> Vec<std::ops::Range<usize>> {
    let bytes = text.as_bytes();
    let mut found = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = bytes[i].is_ascii_digit()
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
        if !starts {
            i += 1;
            continue;
        }
        let start = if i > 0 && bytes[i - 1] == b'-' {
            i - 1
        } else {
            i
        };
        let mut end = i;
        while end < bytes.len()
            && (bytes[end].is_ascii_alphanumeric() || matches!(bytes[end], b'.' | b'-' | b'+'))
        {
            end += 1;
        }
        found.push(start..end);
        i = end;
    }
    found
}

/// Applies the mutations in order; overrides go to the end, as `#set` lines.
fn mutate(seed: &str, mutations: &[Mutation]) -> String {
    let mut text = seed.to_string();
    let mut sets = Vec::new();
    for m in mutations {
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        let line = |n: usize| n % lines.len().max(1);
        match *m {
            Mutation::Number(n, v) => {
                let found = numbers(&text);
                if !found.is_empty() {
                    let r = found[n % found.len()].clone();
                    text.replace_range(r, VALUES[v]);
                }
                continue;
            }
            Mutation::DropLine(n) if !lines.is_empty() => {
                lines.remove(line(n));
            }
            Mutation::DoubleLine(n) if !lines.is_empty() => {
                let l = line(n);
                lines.insert(l, lines[l].clone());
            }
            Mutation::Insert(n, k, v) => {
                let at = if lines.is_empty() { 0 } else { line(n) + 1 };
                lines.insert(at, format!("{} = {}", KEYS[k], VALUES[v]));
            }
            Mutation::Append(b) => lines.push(BLOCKS[b].to_string()),
            Mutation::Set(k, v) => sets.push(format!("{SET_PREFIX}{}={}", SET_KEYS[k], VALUES[v])),
            _ => {}
        }
        text = lines.join("\n");
        text.push('\n');
    }
    for s in sets {
        text.push_str(&s);
        text.push('\n');
    }
    text
}

/// The example scenes and the corpus seeds. The bench scene of a million bodies is
/// left out: its one valid case costs seconds, and `circles-10000.toml` already
/// brings a large swarm.
fn seeds() -> Vec<(PathBuf, String)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["scenes", "scenes/figures", "scenes/bench", "fuzz/seeds"] {
        let Ok(entries) = std::fs::read_dir(root.join(dir)) else {
            continue;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let is_scene = path.extension().is_some_and(|e| e == "toml");
            if is_scene && !path.ends_with("euler-1e6.toml") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).expect("a seed is text");
            (p, text)
        })
        .collect()
}

/// Runs one input and checks the promises: returns what became of it (refused, drawn,
/// stopped by a blow-up), or a description of the failure.
fn holds(text: &str) -> Result<&'static str, String> {
    let dir = tempfile::tempdir().map_err(|e| e.to_string())?;
    let out = dir.path().join("frames");
    let outcome = std::panic::catch_unwind(|| exercise(text, Some(&out)))
        .map_err(|_| "a panic".to_string())?;
    let frames: Vec<String> = std::fs::read_dir(&out)
        .map(|entries| {
            entries
                .flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .filter(|f| f.starts_with("frame_"))
                .collect()
        })
        .unwrap_or_default();
    match outcome {
        Outcome::Refused(message) => {
            if !message.contains("nothing was written") {
                return Err(format!("a refusal that does not say so:\n{message}"));
            }
            if out.exists() {
                return Err("an output folder behind a refused scene".into());
            }
            Ok("refused")
        }
        Outcome::Drawn { frames: n, result } => match result {
            Ok(()) => {
                if frames.len() as u64 != n {
                    return Err(format!("{} frames written, {n} asked", frames.len()));
                }
                for f in &frames {
                    image::open(out.join(f)).map_err(|e| format!("{f} is no PNG: {e}"))?;
                }
                Ok(if n == 2 {
                    "drawn, 2 frames"
                } else {
                    "drawn, frame 0"
                })
            }
            Err(e) if e.exit_code() == exit::BAD_INPUT && !frames.is_empty() => {
                Err(format!("frames written behind exit 2: {e}"))
            }
            Err(e) if e.exit_code() == exit::FAILURE => {
                Err(format!("a valid scene failed to render (exit 1): {e}"))
            }
            Err(e) if e.exit_code() == exit::BLOW_UP => Ok("blew up"),
            Err(e) => Ok(if e.exit_code() == exit::BAD_INPUT {
                "refused by the renderer"
            } else {
                "stopped"
            }),
        },
    }
}

#[test]
fn every_fuzz_seed_and_example_scene_is_refused_or_drawn() {
    for (path, text) in seeds() {
        if let Err(e) = holds(&text) {
            panic!("{}: {e}", path.display());
        }
    }
}

#[test]
fn mutated_scenes_are_refused_or_drawn_and_never_leave_frames_behind_an_error() {
    let cases = std::env::var("PHYSFRAMES_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_CASES);
    let rng_seed = std::env::var("PHYSFRAMES_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_SEED);
    let seeds = seeds();
    let started = std::time::Instant::now();
    let tally = std::sync::Mutex::new(std::collections::BTreeMap::<&str, u32>::new());
    let slowest = std::sync::Mutex::new((0.0, String::new(), Vec::new()));
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(rng_seed),
        ..Config::default()
    });
    let strategy = (0..seeds.len(), prop::collection::vec(mutation(), 1..4));
    // With PHYSFRAMES_FUZZ_LOG set, each case is named before it runs, so that a case
    // that aborts the process (an allocation refused under `ulimit -v`) can be found.
    let log = std::env::var_os("PHYSFRAMES_FUZZ_LOG").is_some();
    let result = runner.run(&strategy, |(seed, mutations)| {
        if log {
            eprintln!("case: {} {mutations:?}", seeds[seed].0.display());
        }
        let text = mutate(&seeds[seed].1, &mutations);
        let case_started = std::time::Instant::now();
        let kind = holds(&text).map_err(|e| {
            TestCaseError::fail(format!(
                "{e}\nseed {}, mutated to:\n{text}",
                seeds[seed].0.display()
            ))
        })?;
        *tally
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .entry(kind)
            .or_default() += 1;
        // The slowest case is reported, not asserted on: a hang would show there.
        let took = case_started.elapsed().as_secs_f64();
        let mut slow = slowest.lock().unwrap_or_else(|p| p.into_inner());
        if took > slow.0 {
            *slow = (took, seeds[seed].0.display().to_string(), mutations.clone());
        }
        Ok(())
    });
    // A long run reports its size and what became of the cases, for the record.
    let slowest = slowest.into_inner().unwrap_or_else(|p| p.into_inner());
    eprintln!(
        "mutated scenes: {cases} cases in {:.1} s: {:?}; slowest {:.2} s: {} {:?}",
        started.elapsed().as_secs_f64(),
        tally.into_inner().unwrap_or_else(|p| p.into_inner()),
        slowest.0,
        slowest.1,
        slowest.2
    );
    if let Err(e) = result {
        panic!("{e}\n(PHYSFRAMES_FUZZ_SEED={rng_seed})");
    }
}

#[test]
fn mutations_reach_numbers_lines_and_overrides() {
    let seed = "[simulation]\ndt = 0.01\n[render]\nfps = 25\n";
    assert_eq!(
        mutate(seed, &[Mutation::Number(0, 6)]),
        "[simulation]\ndt = 1e-308\n[render]\nfps = 25\n"
    );
    assert_eq!(
        numbers("a = [-1.5e3, 2]\nb1 = 7"),
        vec![5..11, 13..14, 21..22]
    );
    let text = mutate(seed, &[Mutation::Set(0, 9), Mutation::DropLine(3)]);
    assert_eq!(
        text,
        "[simulation]\ndt = 0.01\n[render]\n#set simulation.dt=1e-12\n"
    );
    assert_eq!(
        physframes::fuzzing::split_overrides(&text),
        vec!["simulation.dt=1e-12"]
    );
}
