//! Sleeping: bodies at rest fall asleep after the sleep time and then stay to the bit;
//! something awake that comes near wakes them; a body that floats free, or that a
//! force changing with time or a spring to another body moves, never sleeps; and
//! `sleep = false` turns it off.

use physframes::scene::Scene;
use physframes::sim::contacts::DEFAULT_SLEEP_TIME;
use physframes::sim::Simulation;

use crate::util::scene;

/// A scene at dt = 1/240 s with a static floor (top at y = 0) under gravity, with
/// `contacts` added to `[contacts]` and the bodies `bodies` after the floor.
fn on_floor(contacts: &str, bodies: &str) -> Scene {
    scene(&on_floor_text(contacts, bodies))
}

/// The text of [`on_floor`]'s scene.
fn on_floor_text(contacts: &str, bodies: &str) -> String {
    format!(
        r#"
        [simulation]
        dt = 0.004166666666666667
        duration = 10.0
        [render]
        width = 160
        height = 120
        view = {{ min = [-3.0, -1.0], max = [3.0, 30.0] }}
        fps = 30
        [contacts]
        restitution = 0.0
        friction = 0.5
        {contacts}
        [[body]]
        name = "floor"
        static = true
        position = [0.0, -0.5]
        shape = {{ box = {{ width = 6.0, height = 1.0 }} }}
        {bodies}
        [[force]]
        kind = "gravity"
        "#
    )
}

const BOX: &str = r#"
        [[body]]
        name = "box"
        mass = 1.0
        position = [0.0, 0.25]
        shape = { box = { width = 0.5, height = 0.5 } }
"#;

/// Returns whether body `b` (a collider) sleeps.
fn asleep(sim: &Simulation, b: usize) -> bool {
    let c = sim.contacts().expect("collides");
    let k = c
        .colliders()
        .iter()
        .position(|c| c.body == b)
        .expect("a collider");
    c.is_asleep(k)
}

#[test]
fn a_box_on_the_floor_falls_asleep_after_the_sleep_time_and_then_stays_to_the_bit() {
    let s = on_floor("", BOX);
    let mut sim = s.simulation();
    let mut fell_asleep = None;
    while fell_asleep.is_none() && sim.state().t < 2.0 {
        sim.step().expect("finite");
        if asleep(&sim, 1) {
            fell_asleep = Some(sim.state().t);
        }
    }
    // It rests from its first step, so it sleeps once a whole sleep time has passed
    // (to the step: the time at rest is a sum of steps).
    let t = fell_asleep.expect("it falls asleep");
    let h = s.simulation.dt;
    assert!(
        t >= DEFAULT_SLEEP_TIME - 1e-9 && t <= DEFAULT_SLEEP_TIME + 2.0 * h,
        "fell asleep at {t}"
    );
    // Asleep, it is held exactly: the same bits for 100 s, at rest.
    let (p, a) = (sim.state().pos[1], sim.state().angle[1]);
    for _ in 0..24_000 {
        sim.step().expect("finite");
        let st = sim.state();
        assert_eq!(
            (st.pos[1].x.to_bits(), st.pos[1].y.to_bits()),
            (p.x.to_bits(), p.y.to_bits())
        );
        assert_eq!(st.angle[1].to_bits(), a.to_bits());
        assert_eq!((st.vel[1], st.omega[1]), (glam::DVec2::ZERO, 0.0));
    }
    // Within the slop of where it rests on the floor.
    assert!((p.y - 0.25).abs() <= 1e-3 * 0.5, "height {}", p.y);
}

/// Three boxes stacked, and a ball dropped from high above them, onto the top box's
/// corner: it falls 20 m, arriving after about 2 s, long after the tower sleeps.
const TOWER: &str = r#"
        [[body]]
        name = "b0"
        mass = 1.0
        position = [0.0, 0.25]
        shape = { box = { width = 0.5, height = 0.5 } }
        [[body]]
        name = "b1"
        mass = 1.0
        position = [0.0, 0.75]
        shape = { box = { width = 0.5, height = 0.5 } }
        [[body]]
        name = "b2"
        mass = 1.0
        position = [0.0, 1.25]
        shape = { box = { width = 0.5, height = 0.5 } }
        [[body]]
        name = "ball"
        mass = 3.0
        position = [0.2, 21.6]
        shape = { circle = { radius = 0.1 } }
    "#;

#[test]
fn a_sleeping_tower_wakes_when_a_ball_falls_on_it_and_sleeps_again_once_it_settles() {
    let s = on_floor("", TOWER);
    let mut sim = s.simulation();
    sim.advance_to(1.0).expect("finite");
    for b in 1..=3 {
        assert!(asleep(&sim, b), "box {b} sleeps at t = 1");
    }
    assert!(!asleep(&sim, 4), "the falling ball is awake");
    let top = sim.state().pos[3];
    // The ball strikes: the top box wakes and is knocked; nothing overlaps past the
    // run's limit (a step that left an overlap would fail).
    let mut woke = None;
    while sim.state().t < 3.0 {
        sim.step().expect("no blow-up, no overlap");
        if woke.is_none() && !asleep(&sim, 3) {
            woke = Some(sim.state().t);
        }
    }
    let t = woke.expect("the top box wakes");
    // Free fall of 20.25 m to the top box's top face: t = √(2·d/g).
    let arrival = (2.0 * (21.5 - 1.5) / 9.81f64).sqrt();
    assert!(
        (t - arrival).abs() < 0.05,
        "woke at {t}, the ball arrives at {arrival}"
    );
    assert!(
        (sim.state().pos[3] - top).length() > 1e-3,
        "the top box was knocked"
    );
    // It all comes to rest and sleeps again.
    sim.advance_to(10.0).expect("finite");
    for b in 1..=4 {
        assert!(asleep(&sim, b), "body {b} sleeps again at t = 10");
        assert_eq!(sim.state().vel[b], glam::DVec2::ZERO);
    }
    // The ball rests on the tower or on the floor, above the floor.
    assert!(sim.state().pos[4].y > 0.09);
}

#[test]
fn a_body_that_floats_free_or_that_time_or_a_spring_moves_never_sleeps() {
    // Without gravity but with contacts that rest (rest_speed given): a disc at rest
    // touches nothing, so it never sleeps.
    let free = scene(
        r#"
        [simulation]
        dt = 0.01
        duration = 3.0
        [render]
        view = { min = [-1.0, -1.0], max = [1.0, 1.0] }
        fps = 20
        [contacts]
        rest_speed = 0.1
        [[body]]
        name = "disc"
        mass = 1.0
        shape = { circle = { radius = 0.1 } }
        [[body]]
        name = "other"
        mass = 1.0
        position = [0.5, 0.5]
        shape = { circle = { radius = 0.1 } }
        "#,
    );
    let mut sim = free.simulation();
    sim.advance_to(3.0).expect("finite");
    assert!(!asleep(&sim, 0) && !asleep(&sim, 1));
    // On the floor: a box pushed by a force that grows with time (from zero, too
    // weakly to move it for the first seconds), and two boxes joined by a spring.
    let pushed = on_floor(
        "",
        &format!(
            "{BOX}\n[[force]]\nkind = \"force\"\nf1 = [1e-3, 0.0]\nbodies = [\"box\"]\n\
             [[body]]\nname = \"a\"\nmass = 1.0\nposition = [1.5, 0.25]\n\
             shape = {{ box = {{ width = 0.5, height = 0.5 }} }}\n\
             [[body]]\nname = \"b\"\nmass = 1.0\nposition = [2.2, 0.25]\n\
             shape = {{ box = {{ width = 0.5, height = 0.5 }} }}\n\
             [[force]]\nkind = \"spring\"\na = \"a\"\nb = \"b\"\nstiffness = 10.0\nrest_length = 0.7"
        ),
    );
    let mut sim = pushed.simulation();
    sim.advance_to(3.0).expect("finite");
    for b in 1..=3 {
        assert!(!asleep(&sim, b), "body {b} must not sleep");
    }
    // The same box without the force does sleep, so the test can tell.
    let mut sim = on_floor("", BOX).simulation();
    sim.advance_to(3.0).expect("finite");
    assert!(asleep(&sim, 1));
}

#[test]
fn sleep_false_keeps_every_body_awake() {
    let s = on_floor("sleep = false", BOX);
    assert_eq!(s.contacts.as_ref().and_then(|c| c.resting.sleep), None);
    let mut sim = s.simulation();
    sim.advance_to(3.0).expect("finite");
    assert!(!asleep(&sim, 1));
    // The keys are checked: a negative sleep speed and a zero sleep time are refused
    // with the line of the key.
    for (key, message) in [
        ("sleep_speed = -1.0", "`sleep_speed` must be ≥ 0"),
        ("sleep_time = 0.0", "`sleep_time` must be > 0"),
    ] {
        let text = format!(
            "[simulation]\ndt = 0.01\nduration = 1.0\n[render]\nfps = 20\nview = {{ min = [-1.0, -1.0], max = [1.0, 1.0] }}\n[contacts]\n{key}\n[[body]]\nname = \"d\"\nmass = 1.0\nshape = {{ circle = {{ radius = 0.1 }} }}\n"
        );
        let err = physframes::scene::parse(std::path::Path::new("t.toml"), &text)
            .expect_err("refused")
            .to_string();
        assert!(err.contains(message), "{err}");
        assert!(err.contains("t.toml:8:"), "{err}");
        assert!(err.contains("1 problem"), "{err}");
    }
}

#[test]
fn shards_that_start_while_the_tower_sleeps_equal_a_single_run() {
    // 3 s at 30 frames/s: the second shard starts from the checkpoint of frame 40
    // (1.33 s), with the tower asleep and the ball still falling.
    let dir = crate::util::Sandbox::new();
    let path = dir.write(
        "tower.toml",
        &on_floor_text("", TOWER).replace("duration = 10.0", "duration = 3.0"),
    );
    crate::util::assert_shards_equal_a_single_run(
        path.to_str().expect("utf-8"),
        "10",
        &[],
        [&[], &[]],
    );
}

#[test]
fn check_says_how_contacts_rest_and_when_bodies_sleep() {
    let dir = crate::util::Sandbox::new();
    let on = dir.write("on.toml", &on_floor_text("", BOX));
    let off = dir.write("off.toml", &on_floor_text("sleep = false", BOX));
    let summary = |path: &std::path::Path| {
        let out = dir.run(&["check", path.to_str().expect("utf-8")]);
        assert!(out.status.success(), "{}", crate::util::stderr(&out));
        crate::util::stdout(&out)
    };
    // The defaults at dt = 1/240 s under g = 9.81: resting speed 3·g·dt = 0.1226 m/s,
    // sleep speed a tenth of it, both to three figures.
    let text = summary(&on);
    assert!(
        text.contains("friction 0.5; contacts approaching at most 0.123 m/s rest"),
        "{text}"
    );
    assert!(
        text.contains("bodies at rest (at most 0.0123 m/s) for 0.5 s fall asleep"),
        "{text}"
    );
    assert!(summary(&off).contains("bodies never sleep"));
}

#[test]
fn a_puck_gliding_slower_than_the_sleep_speed_sleeps_unless_the_threshold_is_lowered() {
    // On a frictionless floor at 1 cm/s, under the default 1.23 cm/s: it stops, as the
    // documentation warns; with sleep_speed = 1 mm/s it glides on at 1 cm/s.
    let puck = "[[body]]\nname = \"puck\"\nmass = 1.0\nposition = [0.0, 0.1]\nvelocity = [0.01, 0.0]\nfriction = 0.0\nshape = { circle = { radius = 0.1 } }";
    let mut sim = on_floor("", puck).simulation();
    sim.advance_to(1.0).expect("finite");
    assert!(asleep(&sim, 1));
    assert_eq!(sim.state().vel[1], glam::DVec2::ZERO);
    let mut sim = on_floor("sleep_speed = 0.001", puck).simulation();
    sim.advance_to(1.0).expect("finite");
    assert!(!asleep(&sim, 1));
    assert!((sim.state().vel[1].x - 0.01).abs() < 1e-12);
}

/// Two islands at rest side by side both sleep. A disc rests on the floor, and a flat
/// box dropped 0.1 m lands beside it a seventh of a second later: their bounding boxes
/// meet (the box's top corner lies in the disc's box), but the box is 6.6 cm from the
/// disc, beyond the contact reach, so each is an island of its own with its own time
/// at rest. The disc falls asleep first; the box, at rest beside it, must not wake it
/// (only a body that moves does), and then falls asleep too. Before, each woke the
/// other the step it fell asleep, and neither slept for long.
#[test]
fn two_islands_at_rest_side_by_side_both_sleep_and_stay_asleep() {
    let s = on_floor(
        "",
        r#"
        [[body]]
        name = "disc"
        mass = 1.0
        position = [1.1, 0.5]
        shape = { circle = { radius = 0.5 } }
        [[body]]
        name = "box"
        mass = 1.0
        position = [0.55, 0.15]
        shape = { box = { width = 0.3, height = 0.1 } }
        "#,
    );
    let (disc, boxed) = (1, 2);
    assert_eq!(s.bodies[disc].name, "disc");
    assert_eq!(s.bodies[boxed].name, "box");
    let mut sim = s.simulation();
    sim.advance_to(3.0).expect("finite");
    for _ in 0..(7 * 240) {
        assert!(
            asleep(&sim, disc) && asleep(&sim, boxed),
            "at t = {}: disc asleep {}, box asleep {}",
            sim.state().t,
            asleep(&sim, disc),
            asleep(&sim, boxed)
        );
        sim.step().expect("finite");
    }
}

#[test]
fn a_scene_asleep_takes_its_steps_at_once_with_the_bits_of_the_full_step() {
    // Three boxes stacked on the floor fall asleep; from then on every step of the
    // scene can only hold them, and takes no integration. The same scene with one more
    // static body left out of `[contacts]` cannot skip the integrator (that body is
    // not the contacts' to hold), so it takes every step in full: both must agree to
    // the bit, at every step.
    let boxes: String = (0..3)
        .map(|k| {
            format!(
                "[[body]]\nname = \"b{k}\"\nmass = 1.0\nposition = [0.0, {}]\n\
                 shape = {{ box = {{ width = 0.5, height = 0.5 }} }}\n",
                0.25 + 0.5 * f64::from(k)
            )
        })
        .collect();
    let marker = "[[body]]\nname = \"marker\"\nstatic = true\nposition = [2.5, 20.0]\n\
                  shape = { circle = { radius = 0.1 } }\n";
    let fast = on_floor("", &boxes);
    let full = on_floor(
        "bodies = [\"floor\", \"b0\", \"b1\", \"b2\"]",
        &format!("{boxes}{marker}"),
    );
    let (mut a, mut b) = (fast.simulation(), full.simulation());
    for _ in 0..fast.total_steps() {
        a.step().expect("finite");
        b.step().expect("finite");
        let (sa, sb) = (a.state(), b.state());
        assert_eq!(sa.t.to_bits(), sb.t.to_bits());
        for i in 0..4 {
            assert_eq!(sa.pos[i], sb.pos[i], "position of {i} at t = {}", sa.t);
            assert_eq!(sa.vel[i], sb.vel[i], "velocity of {i} at t = {}", sa.t);
            assert_eq!(sa.angle[i].to_bits(), sb.angle[i].to_bits());
            assert_eq!(sa.omega[i].to_bits(), sb.omega[i].to_bits());
        }
        let (ca, cb) = (a.contacts(), b.contacts());
        let (ca, cb) = (ca.expect("collides"), cb.expect("collides"));
        assert_eq!(ca.warm_start(), cb.warm_start(), "at t = {}", sa.t);
        assert_eq!(ca.sleep_state(), cb.sleep_state(), "at t = {}", sa.t);
    }
    assert!((1..4).all(|i| asleep(&a, i)), "the tower sleeps");
    // The tower falls asleep within a second or so; every step after was taken at
    // once, and none of the other run's.
    assert!(
        a.held_steps() > fast.total_steps() / 2,
        "{}",
        a.held_steps()
    );
    assert_eq!(b.held_steps(), 0);
}
