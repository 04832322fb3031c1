//! Shards: frame ranges that start from checkpoints of the simulation's exact state
//! give the same bytes as one run, with trails and with forces that depend on t.

use crate::util::{example, stderr, Sandbox};

/// Renders `scene` into `out` with extra arguments and returns the manifest.
fn render(sandbox: &Sandbox, scene: &str, out: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec!["render", scene, "--out", out];
    args.extend_from_slice(extra);
    let result = sandbox.run(&args);
    assert_eq!(
        result.status.code(),
        Some(0),
        "{args:?}: {}",
        stderr(&result)
    );
    sandbox.manifest(out)
}

#[test]
fn shards_started_from_checkpoints_equal_a_single_run_byte_for_byte() {
    // spring: trails, two bodies; centre-of-mass: F = f0 + f1·t needs t's exact bits;
    // drag: three bodies; pendulum: a box that turns, on a spring at its corner (rk4,
    // trails); gears: polygons spun up by torques against angular drag.
    for (scene, frames) in [
        ("spring.toml", 151u64),
        ("centre-of-mass.toml", 101),
        ("drag.toml", 126),
        ("pendulum.toml", 251),
        ("gears.toml", 301),
    ] {
        let sandbox = Sandbox::new();
        let path = example(scene);
        render(&sandbox, &path, "single", &[]);
        // Stage 1: simulate once, drawing nothing, with a checkpoint every 40 frames.
        let out = sandbox.run(&["checkpoint", &path, "--every", "40", "--out", "shards"]);
        assert_eq!(out.status.code(), Some(0), "{scene}: {}", stderr(&out));
        let saved = sandbox.list("shards/checkpoints");
        assert_eq!(saved.len() as u64, (frames - 1) / 40, "{scene}: {saved:?}");
        // Stage 2: shards in any order, as separate machines would run them.
        for (a, b, start) in [(100, frames, 80), (0, 50, 0), (50, 100, 40)] {
            let range = format!("{a}..{b}");
            let m = render(&sandbox, &path, "shards", &["--frames", &range]);
            assert_eq!(m["started_from_frame"], start, "{scene} {range}");
            assert_eq!(m["frames_written"], b - a, "{scene} {range}");
        }
        sandbox.assert_same_frames("shards", "single");
    }
}

#[test]
fn a_render_writes_checkpoints_as_it_goes_for_later_shards() {
    let sandbox = Sandbox::new();
    let path = example("spring.toml");
    let m = render(&sandbox, &path, "full", &["--checkpoint-every", "50"]);
    assert_eq!(m["checkpoints_written"], 3, "frames 50, 100 and 150");
    assert_eq!(m["started_from_frame"], 0);
    // A shard into another folder reads the same checkpoints.
    let m = render(
        &sandbox,
        &path,
        "shard",
        &[
            "--frames",
            "120..130",
            "--checkpoint-dir",
            "full/checkpoints",
        ],
    );
    assert_eq!(m["started_from_frame"], 100);
    for k in 120..130 {
        let f = format!("frame_{k:06}.png");
        assert!(
            std::fs::read(sandbox.path("shard").join(&f)).expect("shard")
                == std::fs::read(sandbox.path("full").join(&f)).expect("full"),
            "{f} differs"
        );
    }
}

#[test]
fn a_stale_or_damaged_checkpoint_is_never_used() {
    let sandbox = Sandbox::new();
    let text = std::fs::read_to_string(example("drag.toml")).expect("example");
    sandbox.write("drag.toml", &text);
    let out = sandbox.run(&["checkpoint", "drag.toml", "--every", "30", "--out", "f"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let m = render(&sandbox, "drag.toml", "f", &["--frames", "95..100"]);
    assert_eq!(m["started_from_frame"], 90);
    // Other overrides make another scene: its run starts at t = 0.
    let m = render(
        &sandbox,
        "drag.toml",
        "g",
        &[
            "--frames",
            "95..100",
            "--checkpoint-dir",
            "f/checkpoints",
            "--set",
            "force.0.k=0.9",
        ],
    );
    assert_eq!(m["started_from_frame"], 0);
    // So does an edited file.
    sandbox.write("drag.toml", &text.replacen("k = 1.0", "k = 0.9", 1));
    let m = render(
        &sandbox,
        "drag.toml",
        "h",
        &["--frames", "95..100", "--checkpoint-dir", "f/checkpoints"],
    );
    assert_eq!(m["started_from_frame"], 0);
    // The two are the same scene, so their pixels agree (their provenance, which
    // records how each was given, does not).
    for k in 95..100 {
        let f = format!("frame_{k:06}.png");
        let pixels = |dir: &str| {
            image::open(sandbox.path(dir).join(&f))
                .expect("a frame")
                .to_rgba8()
                .into_raw()
        };
        assert!(pixels("g") == pixels("h"), "{f} differs");
    }
    // A damaged checkpoint is passed over for the one before it.
    sandbox.write("drag.toml", &text);
    let last = sandbox
        .list("f/checkpoints")
        .into_iter()
        .find(|f| f.ends_with("-000090.bin"))
        .expect("the checkpoint at frame 90");
    let path = sandbox.path("f/checkpoints").join(last);
    let mut bytes = std::fs::read(&path).expect("checkpoint");
    bytes.truncate(bytes.len() - 1);
    std::fs::write(&path, bytes).expect("damage it");
    let m = render(&sandbox, "drag.toml", "f", &["--frames", "95..100"]);
    assert_eq!(m["started_from_frame"], 60);
    render(&sandbox, "drag.toml", "whole", &[]);
    for k in 95..100 {
        let f = format!("frame_{k:06}.png");
        assert!(
            std::fs::read(sandbox.path("f").join(&f)).expect("f")
                == std::fs::read(sandbox.path("whole").join(&f)).expect("whole"),
            "{f} differs"
        );
    }
}

#[test]
fn a_checkpoint_interval_of_zero_is_a_usage_error() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "render",
        &example("drag.toml"),
        "--checkpoint-every",
        "0",
        "--out",
        "f",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--checkpoint-every must be at least 1"));
    assert!(!sandbox.path("f").exists());
    let out = sandbox.run(&["checkpoint", &example("drag.toml"), "--every", "0"]);
    assert_eq!(out.status.code(), Some(2));
}
