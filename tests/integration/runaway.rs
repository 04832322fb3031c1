//! Bodies whose contacts a step cannot answer: a path that crosses more pairs than a
//! step's budget (`PAIRS_PER_BODY`), or a body so far out that f64 cannot place it to
//! within its slop. Each stops the run at once with exit 3, naming the body and what to
//! change, instead of asking for gigabytes or spending minutes a step. Both scenes are
//! fuzzing finds, kept in `fuzz/seeds/`.

use crate::util::{stderr, Sandbox};

fn seed(name: &str) -> String {
    let path = format!("{}/fuzz/seeds/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Renders `text` for three frames and returns the exit code, the error and the
/// manifest.
fn render(text: &str) -> (Option<i32>, String, serde_json::Value) {
    let sandbox = Sandbox::new();
    sandbox.write("scene.toml", text);
    let out = sandbox.run(&["render", "scene.toml", "--frames", "0..3", "--out", "f"]);
    (out.status.code(), stderr(&out), sandbox.manifest("f"))
}

#[test]
fn a_bullet_crossing_a_gas_a_thousand_times_a_step_stops_with_exit_3_naming_it() {
    // The bullet moves |(1e6, -3e5)|·dt = 3,480 m a step in a 16 m box of 1000 discs:
    // each of its impacts meets the whole box again, about 1000 pairs, so the step's
    // budget (256 per body + 65,536 = 322,816) runs out after some 320 impacts, where
    // it used to go on to 9,040 impacts and 9 million pairs every step.
    let (code, err, m) = render(&seed("bullet-through-a-gas.toml"));
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("body `bullet` moved 3480 m in step 1"),
        "{err}"
    );
    assert!(err.contains("more than 322816 pairs"), "{err}");
    assert!(
        err.contains("give `bullet` (and any body as fast) a lower speed"),
        "{err}"
    );
    assert_eq!(m["failure"]["body"], "bullet");
    assert_eq!(m["failure"]["step"], 1);
    assert_eq!(m["frames_written"], 1);
}

#[test]
fn a_swarm_too_fast_for_its_box_stops_in_the_broad_phase() {
    // Every disc moves up to 10^6·√2·dt ≈ 4,700 m a step, so every swept box covers
    // the box and the broad phase alone finds 1004·1003/2 ≈ 503,000 pairs, more than
    // the budget; the body named is the one that moved furthest.
    let text = seed("bullet-through-a-gas.toml")
        .replace("max = [1.0, 1.0] }", "max = [1e6, 1e6] }")
        .replace("velocity = [1e6, -3e5]", "velocity = [0.0, 0.0]");
    let (code, err, m) = render(&text);
    assert_eq!(code, Some(3), "{err}");
    assert!(err.contains("body `gas"), "{err}");
    assert!(err.contains("in step 1 "), "{err}");
    assert!(
        err.contains("pairs of bodies (256 per colliding body)"),
        "{err}"
    );
    assert!(err.contains("or take a smaller dt"), "{err}");
    assert_eq!(m["failure"]["step"], 1);
}

#[test]
fn a_body_sent_beyond_what_f64_resolves_stops_at_once() {
    // -9223372036854775808 m/s for 0.01 s puts `runaway` at 9.22·10^16 m, where f64
    // values lie 16 m apart (2^54 ≤ x < 2^57 spaced 2^4 to 2^5; x·ε = 20.5 is the bound
    // reported), far more than its slop of 0.2 mm.
    let text = seed("body-beyond-f64-precision.toml");
    let (code, err, m) = render(&text);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("body `runaway` reached a coordinate of 9.22e16 m at step 1"),
        "{err}"
    );
    assert!(err.contains("f64 numbers lie 20.5 m apart"), "{err}");
    assert!(err.contains("check body `runaway`'s velocity"), "{err}");
    assert_eq!(m["failure"]["body"], "runaway");
    // Without the runaway, the spinner's 10^18 rad/s turns it 10^16 rad in a step,
    // where angles lie 2.2 rad apart.
    let text = text.replace("velocity = [-9223372036854775808, 0.1559]", "");
    let (code, err, m) = render(&text);
    assert_eq!(code, Some(3), "{err}");
    assert!(
        err.contains("body `spinner` reached an angle of 1e16 rad at step 1"),
        "{err}"
    );
    assert_eq!(m["failure"]["body"], "spinner");
}

#[test]
fn a_body_a_billion_metres_out_still_collides() {
    // At 10^9 m f64 values lie 1.2·10^-7 m apart, finer than the slop of a 1 m box
    // (1 mm): the stop must not reach scenes far from the origin that are still
    // resolved. A box resting on a floor there under gravity renders.
    let text = r#"
[simulation]
dt = 0.01
duration = 1.0
[render]
width = 64
height = 48
fps = 10
view = { min = [999999998.0, -1.5], max = [1000000002.0, 1.5] }
[contacts]
[[force]]
kind = "gravity"
[[body]]
name = "floor"
static = true
position = [1e9, -1.0]
shape = { box = { width = 4.0, height = 1.0 } }
[[body]]
name = "box"
mass = 1.0
position = [1e9, 0.0]
shape = { box = { width = 1.0, height = 1.0 } }
"#;
    let (code, err, m) = render(text);
    assert_eq!(code, Some(0), "{err}");
    assert_eq!(m["frames_written"], 3);
}
