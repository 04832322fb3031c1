//! `--resume`: a render killed at any moment, run again with `--resume`, ends with the
//! bytes of an uninterrupted run and draws only the frames that were missing.

use std::time::{Duration, Instant, SystemTime};

use crate::util::{stderr, Sandbox};

/// A scene with enough frames (1001) that a render is still running when the test has
/// seen its first frames appear. Trails make every frame depend on all earlier ones.
const LONG: &str = r#"name = "long"
[simulation]
dt = 0.01
duration = 40.0
[render]
width = 160
height = 120
fps = 25
trails = true
view = { min = [-3.0, -3.0], max = [3.0, 3.0] }
[[body]]
name = "planet"
mass = 1.0
position = [1.0, 0.0]
velocity = [0.0, 1.0]
[[force]]
kind = "central"
strength = 1.0
"#;

/// Returns the modification time of every frame in a folder of the sandbox.
fn mtimes(sandbox: &Sandbox, dir: &str) -> Vec<(String, SystemTime)> {
    sandbox
        .frames(dir)
        .into_iter()
        .map(|f| {
            let meta = std::fs::metadata(sandbox.path(dir).join(&f)).expect("metadata");
            (f, meta.modified().expect("mtime"))
        })
        .collect()
}

#[test]
fn a_killed_render_resumed_ends_with_the_bytes_of_an_uninterrupted_one() {
    let sandbox = Sandbox::new();
    sandbox.write("long.toml", LONG);
    let mut child = sandbox.spawn(&["render", "long.toml", "--out", "killed", "--threads", "1"]);
    // Kill the render once some frames are on disk: at no particular frame, mid-write
    // of the next one or not.
    let started = Instant::now();
    while sandbox.frames("killed").len() < 20 {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "no frames appeared"
        );
        assert!(
            child.try_wait().expect("poll").is_none(),
            "the render ended before it could be killed"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
    child.kill().expect("kill the render");
    child.wait().expect("reap the render");
    let before = mtimes(&sandbox, "killed");
    assert!(
        before.len() >= 20 && before.len() < 1001,
        "{} frames at the kill",
        before.len()
    );
    assert!(
        !sandbox.path("killed/manifest.json").exists(),
        "a killed run writes no manifest"
    );

    let out = sandbox.run(&["render", "long.toml", "--out", "killed", "--resume"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let m = sandbox.manifest("killed");
    assert_eq!(m["status"], "complete");
    assert_eq!(m["frames_reused"], before.len() as u64);
    assert_eq!(m["frames_written"], 1001 - before.len() as u64);
    // The frames the killed run finished were not drawn again: not one was rewritten.
    let after = mtimes(&sandbox, "killed");
    for (f, t) in &before {
        let now = after.iter().find(|(g, _)| g == f).map(|(_, t)| *t);
        assert_eq!(now, Some(*t), "{f} was rewritten");
    }

    let out = sandbox.run(&["render", "long.toml", "--out", "whole"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    sandbox.assert_same_frames("killed", "whole");
    assert_eq!(
        sandbox.list("killed"),
        sandbox.list("whole"),
        "no stray file"
    );
    let whole = sandbox.manifest("whole");
    for key in ["scene_hash", "frame_count", "frames_requested", "status"] {
        assert_eq!(m[key], whole[key], "{key}");
    }
}

#[test]
fn resume_draws_again_the_frames_of_another_scene_or_setting() {
    let sandbox = Sandbox::new();
    let short = LONG.replacen("duration = 40.0", "duration = 0.4", 1);
    sandbox.write("s.toml", &short);
    let render = |extra: &[&str]| {
        let mut args = vec!["render", "s.toml", "--out", "f", "--resume"];
        args.extend_from_slice(extra);
        let out = sandbox.run(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        sandbox.manifest("f")
    };
    let m = render(&[]);
    assert_eq!(
        (m["frames_reused"].as_u64(), m["frames_written"].as_u64()),
        (Some(0), Some(11))
    );
    // The same scene and settings: every frame is kept.
    let m = render(&[]);
    assert_eq!(
        (m["frames_reused"].as_u64(), m["frames_written"].as_u64()),
        (Some(11), Some(0))
    );
    // An override changes the scene hash: every frame is drawn again, and differs.
    let first = std::fs::read(sandbox.path("f/frame_000010.png")).expect("frame");
    let m = render(&["--set", "body.planet.velocity=[0, 1.2]"]);
    assert_eq!(
        (m["frames_reused"].as_u64(), m["frames_written"].as_u64()),
        (Some(0), Some(11))
    );
    assert_ne!(
        std::fs::read(sandbox.path("f/frame_000010.png")).expect("frame"),
        first
    );
    // A file that is not this run's frame (here not even a PNG) is drawn again.
    let m = render(&["--set", "body.planet.velocity=[0, 1.2]"]);
    assert_eq!(m["frames_reused"], 11);
    sandbox.write("f/frame_000003.png", "not a frame");
    let m = render(&["--set", "body.planet.velocity=[0, 1.2]"]);
    assert_eq!(
        (m["frames_reused"].as_u64(), m["frames_written"].as_u64()),
        (Some(10), Some(1))
    );
    assert!(image::open(sandbox.path("f/frame_000003.png")).is_ok());
    // An edited file changes the hash too.
    sandbox.write("s.toml", &short.replacen("mass = 1.0", "mass = 1.5", 1));
    let m = render(&[]);
    assert_eq!(m["frames_reused"], 0);
}
