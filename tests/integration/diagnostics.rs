//! Scene errors like a compiler's, all in one run, and `--set` overrides checked like
//! the file, with errors that point at the argument.

use crate::util::{example, stderr, stdout, Sandbox};

/// A valid scene to break one line at a time.
use crate::util::GOOD_SCENE as GOOD;

/// Runs `check` on `text` with extra arguments; returns the exit code and stderr.
fn check(text: &str, extra: &[&str]) -> (Option<i32>, String) {
    let sandbox = Sandbox::new();
    sandbox.write("s.toml", text);
    let mut args = vec!["check", "s.toml"];
    args.extend_from_slice(extra);
    let out = sandbox.run(&args);
    (out.status.code(), stderr(&out))
}

fn assert_contains(text: &str, expected: &[&str]) {
    for e in expected {
        assert!(text.contains(e), "missing `{e}` in:\n{text}");
    }
}

#[test]
fn every_unknown_key_and_wrong_type_is_reported_in_one_run() {
    let text = GOOD
        .replacen("duration = 1.0", "duration = \"long\"", 1)
        .replacen("fps = 25", "fps = 25\nfsp = 3", 1)
        .replacen("mass = 1.0", "mass = 1.0\nmas = 2.0\ncolor = 3", 1)
        .replacen("k = 1.0", "k = -2.0", 1);
    let (code, err) = check(&text, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert_contains(
        &err,
        &[
            // A wrong type, with its place and its key.
            "invalid type: string \"long\", expected f64",
            "s.toml:4:12",
            "in `simulation.duration`",
            // Unknown keys, with the nearest known key.
            "unknown field `fsp`",
            "s.toml:9:1",
            "did you mean `fps`?",
            "unknown field `mas`",
            "s.toml:14:1",
            "did you mean `mass`?",
            "invalid type: integer `3`, expected a string",
            "s.toml:15:9",
            // A broken rule is still found beside them.
            "`k` must be ≥ 0",
            "s.toml:19:5",
            "5 problems found",
        ],
    );
}

#[test]
fn a_value_of_the_wrong_type_does_not_also_report_its_consequences() {
    // Without its mass the body "has no mass", and without fps dt "misses the frames";
    // both only follow from the one mistake each.
    let text = GOOD.replacen("mass = 1.0", "mass = \"heavy\"", 1).replacen(
        "fps = 25",
        "fps = \"fast\"",
        1,
    );
    let (code, err) = check(&text, &[]);
    assert_eq!(code, Some(2), "{err}");
    assert_contains(&err, &["\"heavy\"", "\"fast\"", "2 problems found"]);
    assert!(!err.contains("has no mass"), "{err}");
    assert!(!err.contains("whole number of steps"), "{err}");
}

#[test]
fn set_overrides_values_by_body_name_force_index_and_table_path() {
    let sandbox = Sandbox::new();
    sandbox.write("s.toml", GOOD);
    let edited = GOOD
        .replacen("mass = 1.0", "mass = 2.5", 1)
        .replacen("k = 1.0", "k = 0.5", 1)
        .replacen("dt = 0.01", "dt = 0.02", 1)
        .replacen("[-1.0, -1.0]", "[-2, -1.0]", 1);
    sandbox.write("edited.toml", &edited);
    let set = [
        "--set",
        "body.puck.mass=2.5",
        "--set",
        "force.0.k=0.5",
        "--set",
        "simulation.dt=0.02",
        "--set",
        "render.view.min=[-2, -1.0]",
    ];
    let mut args = vec!["export", "s.toml", "--out", "set.csv"];
    args.extend_from_slice(&set);
    let out = sandbox.run(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let out = sandbox.run(&["export", "edited.toml", "--out", "edited.csv"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let read = |f: &str| std::fs::read_to_string(sandbox.path(f)).expect("csv");
    assert_eq!(read("set.csv"), read("edited.csv"));
    assert_ne!(
        read("set.csv"),
        {
            sandbox.run(&["export", "s.toml", "--out", "plain.csv"]);
            read("plain.csv")
        },
        "the overrides change the trajectory"
    );
}

#[test]
fn set_addresses_a_swarm_by_its_name_or_its_index() {
    let sandbox = Sandbox::new();
    let text = r#"
[simulation]
dt = 0.01
duration = 0.1
[render]
fps = 10
view = { min = [-1.0, -1.0], max = [1.0, 1.0] }
[[swarm]]
name = "dust"
count = 5
seed = 1
mass = 1.0
position = { min = [-0.5, -0.5], max = [0.5, 0.5] }
"#;
    sandbox.write("s.toml", text);
    let run = |out: &str, set: &str| {
        let o = sandbox.run(&["export", "s.toml", "--out", out, "--set", set]);
        (o.status.code(), stderr(&o))
    };
    assert_eq!(run("name.csv", "swarm.dust.seed=7").0, Some(0));
    assert_eq!(run("index.csv", "swarm.0.seed=7").0, Some(0));
    assert_eq!(run("plain.csv", "swarm.0.seed=1").0, Some(0));
    let read = |f: &str| std::fs::read_to_string(sandbox.path(f)).expect("csv");
    assert_eq!(read("name.csv"), read("index.csv"));
    assert_ne!(
        read("name.csv"),
        read("plain.csv"),
        "the seed places the swarm"
    );
    // A name that is not there: exit 2, and the names that are.
    let (code, err) = run("typo.csv", "swarm.dusty.seed=7");
    assert_eq!(code, Some(2), "{err}");
    assert_contains(&err, &["no table `dusty`", "holds 1 item, named dust"]);
    assert!(!sandbox.path("typo.csv").exists(), "nothing written");
}

#[test]
fn the_manifest_records_the_overrides_and_the_hash_covers_them() {
    let sandbox = Sandbox::new();
    sandbox.write("s.toml", GOOD);
    let out = sandbox.run(&["render", "s.toml", "--out", "plain", "--frames", "0..2"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // A bare word that is not TOML is a string: the scene's name here.
    let out = sandbox.run(&[
        "render",
        "s.toml",
        "--frames",
        "0..2",
        "--set",
        "name=swept",
        "--set",
        "body.puck.mass=2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let plain = sandbox.manifest("plain");
    let swept = sandbox.manifest("output/swept");
    assert_eq!(swept["scene"], "swept");
    assert_eq!(
        swept["scene_overrides"],
        serde_json::json!(["name=swept", "body.puck.mass=2"])
    );
    assert_eq!(plain["scene_overrides"], serde_json::json!([]));
    let text = std::fs::read_to_string(sandbox.path("s.toml")).expect("scene");
    let expected = physframes::scene::hash_with_overrides(
        &text,
        &["name=swept".to_string(), "body.puck.mass=2".to_string()],
    );
    assert_eq!(swept["scene_hash"], expected.as_str());
    assert_ne!(swept["scene_hash"], plain["scene_hash"]);
}

#[test]
fn set_errors_point_at_the_argument_and_write_nothing() {
    let sandbox = Sandbox::new();
    sandbox.write("s.toml", GOOD);
    let out = sandbox.run(&[
        "render",
        "s.toml",
        "--out",
        "f",
        "--set",
        "body.ghost.mass=1",
        "--set",
        "simulation.dt=-1",
        "--set",
        "render.widht=3",
        "--set",
        "force.3.k=1",
        "--set",
        "render.width=wide",
        "--set",
        "nothing",
    ]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_contains(
        &err,
        &[
            "no body is named `ghost`",
            "--set #1:1:6",
            "bodies in this scene: puck",
            "`dt` must be > 0",
            "--set #2:1:15",
            "unknown field `widht`",
            "--set #3:1:8",
            "did you mean `width`?",
            "there is no force 3",
            "--set #4:1:7",
            "this scene has 1 force: force.0 to force.0",
            "invalid type: string \"wide\", expected i64",
            "--set #5:1:14",
            "`--set` expects KEY=VALUE",
            "--set #6:1:1",
            "6 problems found",
        ],
    );
    // The offending argument is shown with a caret under the bad part.
    assert_contains(&err, &["simulation.dt=-1", "^^"]);
    assert!(!sandbox.path("f").exists(), "nothing is written");
}

#[test]
fn check_verbose_prints_the_overrides_and_the_hash() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "check",
        &example("drag.toml"),
        "--verbose",
        "--set",
        "simulation.duration=2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert_contains(
        &text,
        &["override: --set simulation.duration=2", "scene hash: "],
    );
    let out = sandbox.run(&["check", &example("drag.toml"), "--quiet"]);
    assert_eq!(out.status.code(), Some(0));
    assert_eq!(stdout(&out), "", "--quiet prints nothing");
}
