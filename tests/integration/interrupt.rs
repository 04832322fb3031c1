//! Ctrl-C (issue 17): a command stopped by SIGINT exits with 130 at once, every file it
//! wrote is complete, no temporary file is left, and `render --resume` then ends with
//! the bytes of an uninterrupted run.

use std::process::Child;
use std::time::{Duration, Instant};

use crate::util::{stderr, Sandbox};

/// A render of 1001 frames that is still running when its first frames appear (as in
/// `resume.rs`); trails make every frame depend on all the earlier ones.
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

/// Waits, polling, until `ready` holds, failing if the child ends first.
fn wait_until(child: &mut Child, what: &str, ready: impl Fn() -> bool) {
    let started = Instant::now();
    while !ready() {
        assert!(
            started.elapsed() < Duration::from_secs(120),
            "{what} never happened"
        );
        assert!(
            child.try_wait().expect("poll").is_none(),
            "the command ended before {what}"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// Sends SIGINT, as Ctrl-C in a terminal does, and returns the exit code.
fn interrupt(child: Child) -> Option<i32> {
    signal(child, "INT")
}

/// Sends the signal of that name (`kill -NAME`) and returns the exit code.
fn signal(mut child: Child, name: &str) -> Option<i32> {
    let sent = std::process::Command::new("kill")
        .args([&format!("-{name}"), &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(sent.success(), "SIG{name} sent");
    child.wait().expect("reap").code()
}

/// Returns the temporary files physframes names `.physframes-*.tmp` in a folder.
fn temporary_files(sandbox: &Sandbox, dir: &str) -> Vec<String> {
    sandbox
        .list(dir)
        .into_iter()
        .filter(|f| f.starts_with(".physframes-") && f.ends_with(".tmp"))
        .collect()
}

#[test]
fn an_interrupted_render_leaves_complete_frames_that_resume_finishes() {
    let sandbox = Sandbox::new();
    sandbox.write("long.toml", LONG);
    let mut child = sandbox.spawn(&["render", "long.toml", "--out", "stopped"]);
    wait_until(&mut child, "20 frames were written", || {
        sandbox.frames("stopped").len() >= 20
    });
    assert_eq!(interrupt(child), Some(130), "the exit code of Ctrl-C");
    let frames = sandbox.frames("stopped");
    assert!(frames.len() < 1001, "the render was stopped part-way");
    assert_eq!(temporary_files(&sandbox, "stopped"), Vec::<String>::new());
    // Every frame present is a whole PNG of the scene's size.
    for f in &frames {
        let image = image::open(sandbox.path("stopped").join(f))
            .unwrap_or_else(|e| panic!("{f} is a complete PNG: {e}"));
        assert_eq!((image.width(), image.height()), (160, 120), "{f}");
    }

    let out = sandbox.run(&["render", "long.toml", "--out", "stopped", "--resume"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let m = sandbox.manifest("stopped");
    assert_eq!(m["status"], "complete");
    assert_eq!(m["frames_reused"], frames.len() as u64);
    let out = sandbox.run(&["render", "long.toml", "--out", "whole"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    sandbox.assert_same_frames("stopped", "whole");
    assert_eq!(
        sandbox.list("stopped"),
        sandbox.list("whole"),
        "no stray file"
    );
}

#[test]
fn an_interrupted_export_removes_its_temporary_file_and_writes_nothing() {
    // 10^8 rows: the CSV's temporary file exists for as long as the export runs.
    let sandbox = Sandbox::new();
    sandbox.write(
        "long.toml",
        &LONG.replacen("dt = 0.01", "dt = 1e-6", 1).replacen(
            "duration = 40.0",
            "duration = 100.0",
            1,
        ),
    );
    std::fs::create_dir_all(sandbox.path("csv")).expect("a folder for the CSV");
    let mut child = sandbox.spawn(&[
        "export",
        "long.toml",
        "--every-step",
        "--out",
        "csv/long.csv",
    ]);
    wait_until(&mut child, "the CSV's temporary file appeared", || {
        !temporary_files(&sandbox, "csv").is_empty()
    });
    assert_eq!(interrupt(child), Some(130), "the exit code of Ctrl-C");
    assert_eq!(
        sandbox.list("csv"),
        Vec::<String>::new(),
        "neither a CSV nor a temporary file"
    );
}

/// SIGTERM (`kill`, a batch scheduler's time limit) and SIGHUP (a closed terminal) stop
/// a command as Ctrl-C does, with 128 plus the signal's number: 143 and 129.
#[test]
fn sigterm_and_sighup_stop_a_render_as_ctrl_c_does() {
    for (name, code) in [("TERM", 143), ("HUP", 129)] {
        let sandbox = Sandbox::new();
        sandbox.write("long.toml", LONG);
        let mut child = sandbox.spawn(&["render", "long.toml", "--out", "stopped"]);
        wait_until(&mut child, "10 frames were written", || {
            sandbox.frames("stopped").len() >= 10
        });
        assert_eq!(
            signal(child, name),
            Some(code),
            "the exit code of SIG{name}"
        );
        let frames = sandbox.frames("stopped");
        assert!(frames.len() < 1001, "SIG{name}: stopped part-way");
        assert_eq!(temporary_files(&sandbox, "stopped"), Vec::<String>::new());
        for f in &frames {
            let image = image::open(sandbox.path("stopped").join(f))
                .unwrap_or_else(|e| panic!("SIG{name}: {f} is a complete PNG: {e}"));
            assert_eq!((image.width(), image.height()), (160, 120), "{f}");
        }
    }
}
