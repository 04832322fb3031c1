//! Numbers that can never finish (issue 17): a `dt` so small that the steps cannot be
//! counted exactly (past 2^53, where t = n·dt stops being exact) or that the run's work
//! passes 10^12 body-steps is refused where it is written, in the file or in the `--set`
//! that set it, with exit 2 and nothing written; the frame limit points at `duration`
//! and `fps`; and `check` prints every number in a form a person can read.

use crate::util::{stderr, stdout, Sandbox, GOOD_SCENE as GOOD};

/// Replaces `from` in the good scene with `to`, checking the replacement happened.
fn with(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "the good scene contains `{from}`");
    GOOD.replacen(from, to, 1)
}

/// Runs `render` and then `check` on `text` with `extra` arguments, asserts exit 2 for
/// both, nothing written and no panic, and returns the render's standard error.
fn refused(text: &str, extra: &[&str]) -> String {
    let sandbox = Sandbox::new();
    sandbox.write("bad.toml", text);
    let mut args = vec!["render", "bad.toml", "--out", "frames"];
    args.extend_from_slice(extra);
    let out = sandbox.run(&args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "exit code; stderr:\n{err}");
    assert!(!err.contains("panicked"), "a panic:\n{err}");
    assert!(
        !sandbox.path("frames").exists(),
        "the output folder was created:\n{err}"
    );
    let mut args = vec!["check", "bad.toml"];
    args.extend_from_slice(extra);
    let check = sandbox.run(&args);
    assert_eq!(check.status.code(), Some(2), "check: {}", stderr(&check));
    assert_eq!(stderr(&check), err, "check and render report alike");
    err
}

#[test]
fn a_step_too_small_to_count_is_refused_at_dt_in_the_file() {
    let err = refused(&with("dt = 0.01", "dt = 1e-308"), &[]);
    assert!(
        err.contains("dt = 1e-308 makes 4e306 steps a frame, more than the 9007199254740992 (2^53) a run can count exactly"),
        "{err}"
    );
    assert!(err.contains("bad.toml:3:6"), "located at dt:\n{err}");
    assert!(err.contains("raise `dt` above"), "a hint:\n{err}");
    // The whole-steps rule is not also broken in a message that makes no sense.
    assert!(err.contains("1 problem found"), "{err}");
}

#[test]
fn a_step_too_small_to_count_is_refused_in_the_set_that_set_it() {
    let err = refused(GOOD, &["--set", "simulation.dt=1e-300"]);
    assert!(err.contains("a run can count exactly"), "{err}");
    assert!(
        err.contains("--set #1:1:15"),
        "located in the override:\n{err}"
    );
    assert!(err.contains("simulation.dt=1e-300"), "{err}");
}

#[test]
fn the_smallest_step_of_all_is_refused_like_any_other() {
    // 5e-324 makes 1/(fps·dt) infinite.
    let err = refused(&with("dt = 0.01", "dt = 5e-324"), &[]);
    assert!(err.contains("makes inf steps a frame"), "{err}");
    assert!(err.contains("1 problem found"), "{err}");
}

#[test]
fn a_run_past_the_work_limit_is_refused_with_a_step_that_fits() {
    // 25 frame intervals of 0.04 s at dt = 1e-13: 10^13 steps of one body.
    let err = refused(&with("dt = 0.01", "dt = 1e-13"), &[]);
    assert!(
        err.contains("the run needs 10000000000000 body-steps (10000000000000 steps × 1 body), more than the limit of 10^12"),
        "{err}"
    );
    assert!(err.contains("bad.toml:3:6"), "located at dt:\n{err}");
    // The hint's step is exactly the one that fits: 10^12 steps.
    assert!(
        err.contains("raise `dt` to 1e-12 (40000000000 steps a frame)"),
        "{err}"
    );
    let sandbox = Sandbox::new();
    sandbox.write("fits.toml", &with("dt = 0.01", "dt = 1e-12"));
    let out = sandbox.run(&["check", "fits.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(
        stdout(&out).contains("1000000000000 steps"),
        "{}",
        stdout(&out)
    );
}

#[test]
fn compared_runs_and_swarms_count_in_the_work() {
    // Three integrators run 4·10^11 steps of the one body each: within 10^12 alone,
    // past it together.
    let text = with("dt = 0.01", "dt = 1e-12\ncompare = [\"rk4\", \"heun\"]").replacen(
        "duration = 1.0",
        "duration = 0.4",
        1,
    );
    let err = refused(&text, &[]);
    assert!(
        err.contains("(400000000000 steps × 1 body × 3 runs with `compare`)"),
        "{err}"
    );
    // A swarm of a million bodies over 10^6 steps.
    let swarm = format!(
        "{}[[swarm]]\nname = \"dust\"\ncount = 1000000\nmass = 1.0\nposition = {{ min = [0.0, 0.0], max = [1.0, 1.0] }}\n",
        with("dt = 0.01", "dt = 1e-6")
    );
    let err = refused(&swarm, &[]);
    assert!(err.contains("1000000 steps × 1000001 bodies"), "{err}");
}

#[test]
fn too_many_frames_points_at_duration_and_fps() {
    let err = refused(&with("duration = 1.0", "duration = 40001.0"), &[]);
    assert!(
        err.contains("duration × fps asks for 1000026 frames, more than the limit of 1000000"),
        "{err}"
    );
    assert!(err.contains("bad.toml:4:12"), "located at duration:\n{err}");
    assert!(err.contains("40001 s"), "duration labelled:\n{err}");
    assert!(
        err.contains("fps = 25") && err.contains("× 25 frames a second"),
        "fps labelled:\n{err}"
    );
    // From the command line, each in its own argument.
    let err = refused(
        GOOD,
        &["--set", "render.fps=50", "--set", "simulation.duration=1e5"],
    );
    assert!(err.contains("asks for 5000001 frames"), "{err}");
    assert!(err.contains("--set #2:1:21"), "{err}");
    assert!(err.contains("--set #1:1:12"), "{err}");
    assert!(err.contains("× 50 frames a second"), "{err}");
}

#[test]
fn check_prints_every_number_readably() {
    let text = with("dt = 0.01", "dt = 1e-7")
        .replacen("duration = 1.0", "duration = 0.0004", 1)
        .replacen("fps = 25", "fps = 10000", 1)
        .replacen("mass = 1.0", "mass = 1e-30\nposition = [1e20, -2.5e-9]", 1);
    let sandbox = Sandbox::new();
    sandbox.write("small.toml", &text);
    let out = sandbox.run(&["check", "small.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    for expected in [
        "with dt = 1e-7, duration 0.0004 s, 4000 steps",
        "5 at 10000 fps (1000 steps a frame)",
        "mass 1e-30, centre of mass (1e20, -2.5e-9)",
    ] {
        assert!(text.contains(expected), "`{expected}` in:\n{text}");
    }
    let longest = text
        .split(|c: char| !c.is_ascii_digit())
        .map(str::len)
        .max()
        .unwrap_or(0);
    assert!(longest <= 17, "a run of {longest} digits in:\n{text}");
}

#[test]
fn a_default_step_that_is_not_a_number_is_refused_at_fps() {
    // Found by the mutated-scene tests: without `dt`, dt = 1/(10·fps) is infinite for
    // fps = 5e-324 and zero for fps = 1e308.
    let no_dt = GOOD.replacen("dt = 0.01\n", "", 1);
    for (fps, dt) in [("5e-324", "inf"), ("1e308", "0")] {
        let err = refused(&no_dt.replacen("fps = 25", &format!("fps = {fps}"), 1), &[]);
        assert!(
            err.contains(&format!(
                "with `dt` left out, the step 1/(10·fps) = {dt} is not a finite number > 0"
            )),
            "{err}"
        );
        assert!(err.contains("bad.toml:7:7"), "located at fps:\n{err}");
    }
}
