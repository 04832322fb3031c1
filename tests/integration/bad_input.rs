//! Every class of bad input: a clear message that says where, exit code 2, and no
//! output folder created or changed.

use crate::util::{stderr, Sandbox};

/// A valid scene to break one line at a time.
use crate::util::GOOD_SCENE as GOOD;

/// Replaces `from` in the good scene with `to`, checking the replacement happened.
fn broken(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "the good scene contains `{from}`");
    GOOD.replacen(from, to, 1)
}

/// Renders a bad scene and checks exit code 2, the message, the location, and that
/// nothing was written.
fn check(case: &str, text: &str, message: &str, location: &str) {
    let sandbox = Sandbox::new();
    sandbox.write("bad.toml", text);
    let out = sandbox.run(&["render", "bad.toml", "--out", "frames"]);
    let err = stderr(&out);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{case}: exit code; stderr:\n{err}"
    );
    assert!(
        err.contains(message),
        "{case}: stderr should contain `{message}`:\n{err}"
    );
    assert!(
        err.contains(&format!("bad.toml:{location}")),
        "{case}: stderr should point at bad.toml:{location}:\n{err}"
    );
    assert!(!err.contains("panicked"), "{case}: a panic:\n{err}");
    assert!(
        !sandbox.path("frames").exists(),
        "{case}: the output folder was created"
    );
}

#[test]
fn the_good_scene_renders() {
    let sandbox = Sandbox::new();
    sandbox.write("good.toml", GOOD);
    let out = sandbox.run(&["render", "good.toml", "--out", "frames"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert_eq!(
        sandbox.list("frames").len(),
        26 + 1,
        "26 frames and the manifest"
    );
}

#[test]
fn each_class_of_bad_input_is_located_and_writes_nothing() {
    let cases: &[(&str, String, &str, &str)] = &[
        ("syntax error", broken("duration = 1.0", "duration = = 1.0"), "expected", "4:12"),
        ("zero mass", broken("mass = 1.0", "mass = 0.0"), "`mass` must be > 0", "12:8"),
        ("negative mass", broken("mass = 1.0", "mass = -3"), "`mass` must be > 0", "12:8"),
        ("infinite number", broken("velocity = [1.0, 0.0]", "velocity = [inf, 0.0]"), "`velocity` must be two finite numbers", "13:12"),
        ("three numbers for a vector", broken("velocity = [1.0, 0.0]", "velocity = [1.0, 0.0, 2.0]"), "invalid length 3, expected two numbers [x, y]", "13:12"),
        ("nan", broken("k = 1.0", "k = nan"), "`k` must be a finite number", "16:5"),
        ("zero dt", broken("dt = 0.01", "dt = 0.0"), "`dt` must be > 0", "3:6"),
        ("negative duration", broken("duration = 1.0", "duration = -1.0"), "`duration` must be > 0", "4:12"),
        ("zero fps", broken("fps = 25", "fps = 0"), "`fps` must be > 0", "8:7"),
        ("unknown body", broken("k = 1.0", "k = 1.0\nbodies = [\"ghost\"]"), "no body is named `ghost`", "17:11"),
        ("unknown key", broken("mass = 1.0", "mass = 1.0\nmas = 2.0"), "unknown field `mas`", "13:1"),
        ("unknown force kind", broken("kind = \"drag\"", "kind = \"wind\""), "unknown force kind `wind`", "15:8"),
        ("mass and points", broken("mass = 1.0", "mass = 1.0\npoints = [{ offset = [0, 0], mass = 1 }]"), "has both `mass` and `points`", "13:10"),
        ("zero width", broken("width = 64", "width = 0"), "`width` must be from 1 to 16384", "6:9"),
        ("huge height", broken("height = 48", "height = 16385"), "`height` must be from 1 to 16384", "7:10"),
        ("view narrower than a normal number", broken("min = [-1.0, -1.0], max = [1.0, 1.0]", "min = [0.0, -1.0], max = [5e-324, 1.0]"), "the view is too small to draw", "9:8"),
        ("too many frames", broken("duration = 1.0", "duration = 40001.0"), "more than the limit of 1000000", "4:12"),
        ("dt off the frames", broken("dt = 0.01", "dt = 0.015"), "nearest valid values are dt = 0.02 (2 steps a frame) and dt = 0.013333333333333334 (3 steps a frame)", "3:6"),
        ("spring to itself", broken("kind = \"drag\"\nk = 1.0", "kind = \"spring\"\na = \"puck\"\nb = \"puck\"\nstiffness = 1.0"), "joins a body to itself", "14:1"),
        ("key of another kind", broken("k = 1.0", "k = 1.0\ng = [0, 1]"), "`g` does not apply to a `drag` force", "17:5"),
    ];
    for (case, text, message, location) in cases {
        check(case, text, message, location);
    }
}

#[test]
fn each_rigid_body_key_is_checked_where_it_is_written() {
    let force = |text: &str| broken("kind = \"drag\"\nk = 1.0", text);
    let swarm = |range: &str| {
        format!(
            "{GOOD}[[swarm]]\nname = \"dust\"\ncount = 3\nmass = 1.0\n\
             position = {{ min = [0.0, 0.0], max = [1.0, 1.0] }}\n{range}\n"
        )
    };
    let cases: &[(&str, String, &str, &str)] = &[
        ("zero inertia", broken("mass = 1.0", "mass = 1.0\ninertia = 0.0"), "`inertia` must be > 0", "13:11"),
        ("angle not a number", broken("mass = 1.0", "mass = 1.0\nangle = nan"), "`angle` must be a finite number", "13:9"),
        ("infinite spin", broken("mass = 1.0", "mass = 1.0\nangular_velocity = -inf"), "`angular_velocity` must be a finite number", "13:20"),
        ("force at no point", force("kind = \"force\"\nf0 = [1.0, 0.0]\nat = [nan, 0.0]"), "`at` must be two finite numbers", "17:6"),
        ("torque without tau", force("kind = \"torque\""), "a `torque` force needs `tau`", "14:1"),
        ("infinite torque", force("kind = \"torque\"\ntau = inf"), "`tau` must be a finite number", "16:7"),
        ("negative angular drag", force("kind = \"angular-drag\"\nk = -0.5"), "`k` must be ≥ 0", "16:5"),
        ("angular drag without k", force("kind = \"angular-drag\""), "a `angular-drag` force needs `k`", "14:1"),
        ("anchor on a fixed point", force("kind = \"spring\"\na = \"puck\"\nb = [0.0, 0.0]\nstiffness = 1.0\nb_at = [0.1, 0.0]"), "`b_at` places the spring's end on body `b`, but `b` is a fixed point", "19:8"),
        ("anchor not finite", force("kind = \"spring\"\na = \"puck\"\nb = [0.0, 0.0]\nstiffness = 1.0\na_at = [0.1, inf]"), "`a_at` must be two finite numbers", "19:8"),
        ("torque key on drag", broken("k = 1.0", "k = 1.0\ntau = 1.0"), "`tau` does not apply to a `drag` force", "17:7"),
        ("at on gravity", force("kind = \"gravity\"\nat = [0.0, 0.0]"), "`at` does not apply to a `gravity` force", "16:6"),
        ("swarm angles backwards", swarm("angle = { min = 1.0, max = 0.5 }"), "`angle` has min above max", "22:9"),
        ("swarm spin not finite", swarm("angular_velocity = { min = nan, max = 0.5 }"), "`angular_velocity.min` must be a finite number", "22:28"),
        ("polygon crossing itself", broken("mass = 1.0", "mass = 1.0\nshape = { polygon = { points = [[5, 1], [-2, -4], [2, -5], [1, 1]] } }"), "the polygon of body `puck` crosses itself", "10:1"),
        ("a point turned", broken("mass = 1.0", "points = [{ offset = [0.5, 0.5], mass = 2.0 }]\nangular_velocity = 1.0"), "body `puck` is turned but has no moment of inertia", "10:1"),
    ];
    for (case, text, message, location) in cases {
        check(case, text, message, location);
    }
}

#[test]
fn every_problem_of_a_scene_is_reported_in_one_run() {
    let text = broken("mass = 1.0", "mass = -1.0")
        .replacen("width = 64", "width = 0", 1)
        .replacen("k = 1.0", "k = -2.0", 1);
    let sandbox = Sandbox::new();
    sandbox.write("bad.toml", &text);
    let out = sandbox.run(&["check", "bad.toml"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2));
    for expected in [
        "`width` must be",
        "`mass` must be > 0",
        "`k` must be ≥ 0",
        "3 problems found",
    ] {
        assert!(err.contains(expected), "missing `{expected}` in:\n{err}");
    }
}

#[test]
fn a_missing_scene_file_is_bad_input() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["render", "nowhere.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("cannot read scene file nowhere.toml"));
    assert!(!sandbox.path("output").exists());
}

#[test]
fn a_bad_frame_range_is_bad_input_and_writes_nothing() {
    let sandbox = Sandbox::new();
    sandbox.write("good.toml", GOOD);
    for range in ["30..40", "5..2", "x"] {
        let out = sandbox.run(&["render", "good.toml", "--out", "frames", "--frames", range]);
        assert_eq!(
            out.status.code(),
            Some(2),
            "--frames {range}: {}",
            stderr(&out)
        );
        assert!(!sandbox.path("frames").exists());
    }
}

#[test]
fn an_unknown_flag_is_a_usage_error() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["render", "good.toml", "--bogus"]);
    assert_eq!(out.status.code(), Some(2));
}

/// Contacts may not reach (tolerance + slop + rest_speed × dt) farther from a body than
/// ten times its width: an absurd value made every pair of a 10,000-disc scene a
/// contact, 8 GB of them (found by fuzzing `rest_speed = 1.8e308`). Refused at the
/// `[contacts]` table (line 10), nothing written. The puck is a disc 0.2 m wide, and
/// dt = 0.01 s: a resting speed of 1000 m/s reaches 10 m, of 100 m/s 1 m. The slop
/// counts only where contacts rest (a resting speed above 0).
#[test]
fn contacts_that_reach_past_a_body_are_refused() {
    for keys in [
        "rest_speed = 1.7976931348623157e308",
        "rest_speed = 1000.0",
        "rest_speed = 0.1\nslop = 1.0e300",
        "tolerance = 5.0",
    ] {
        let text = broken(
            "[[body]]",
            &format!("[contacts]\n{keys}\n[[body]]\nshape = {{ circle = {{ radius = 0.1 }} }}"),
        );
        check(keys, &text, "contacts would reach", "10:1");
    }
    // Within ten widths the same keys are fine: 100 m/s reaches 1 m, five widths.
    let text = broken(
        "[[body]]",
        "[contacts]\nrest_speed = 100.0\n[[body]]\nshape = { circle = { radius = 0.1 } }",
    );
    assert!(physframes::scene::parse(std::path::Path::new("t.toml"), &text).is_ok());
}
