//! Friction and resting contact against their closed forms: a box sliding to a stop,
//! a disc skidding until it rolls, a disc rolling and a box sliding down a slope, a
//! ball bouncing to rest, a tower and a pyramid that stand, a pile that settles, and
//! checkpoints that carry the solver's warm start.
//!
//! Tolerances: explicit Euler's friction is exact arithmetic on exact inputs (the
//! solver's one contact converges in one sweep), so the sliding box's recurrence holds
//! to a few ulps a step: 1e-12 relative over hundreds of steps. Where a closed form is
//! of the continuous motion, the step's own error is allowed and stated.

use physframes::scene::Scene;
use physframes::sim::contacts::DEFAULT_SLOP;

use crate::util::{example, scene};

const G: f64 = 9.81;

fn load(name: &str) -> Scene {
    Scene::load(std::path::Path::new(&example(name))).expect("the example is valid")
}

fn index(s: &Scene, name: &str) -> usize {
    s.bodies
        .iter()
        .position(|b| b.name == name)
        .expect("a body of that name")
}

/// A body on a level static floor (top at y = 0), with friction μ, under gravity.
fn on_floor(mu: f64, body: &str, dt: f64, duration: f64) -> Scene {
    scene(&format!(
        r#"
        [simulation]
        dt = {dt}
        duration = {duration}
        [render]
        view = {{ min = [-1.0, -1.0], max = [9.0, 4.0] }}
        fps = 10
        [contacts]
        restitution = 0.0
        friction = {mu}
        [[body]]
        name = "floor"
        static = true
        position = [4.0, -0.5]
        shape = {{ box = {{ width = 12.0, height = 1.0 }} }}
        {body}
        [[force]]
        kind = "gravity"
        "#
    ))
}

#[test]
fn a_box_slides_to_a_stop_at_mu_g_and_stays() {
    let (mu, v0, h) = (0.5, 3.0, 0.01);
    let s = on_floor(
        mu,
        "[[body]]\nname = \"box\"\nmass = 2.0\nposition = [0.0, 0.15]\nvelocity = [3.0, 0.0]\nshape = { box = { width = 0.4, height = 0.3 } }",
        h,
        100.0,
    );
    let mut sim = s.simulation();
    // While it slides, explicit Euler gives exactly v_n = v0 - n·h·μ·g.
    let stop = v0 / (mu * G);
    let mut n = 0u64;
    let mut stopped_at = None;
    while sim.state().t < 100.0 - 0.5 * h {
        sim.step().expect("no blow-up");
        n += 1;
        let v = sim.state().vel[1];
        let expected = v0 - n as f64 * h * mu * G;
        if expected > 0.0 {
            assert!(
                (v.x - expected).abs() <= 1e-12 * v0,
                "step {n}: v = {} for {expected}",
                v.x
            );
        } else if stopped_at.is_none() {
            // The step it stops in: friction takes what speed is left, to the
            // solver's convergence over the box's two corners.
            stopped_at = Some(sim.state().t);
            assert!(v.x.abs() < 1e-4, "stopping: {}", v.x);
        } else {
            assert!(
                v.x.abs() < 1e-9,
                "at rest after it stops (t = {}): {}",
                sim.state().t,
                v.x
            );
        }
        assert!(v.y.abs() < 1e-9 && sim.state().omega[1].abs() < 1e-9);
    }
    let t = stopped_at.expect("it stops");
    // It stops within the step in which v0 - t·μ·g reaches zero.
    assert!((t - stop).abs() <= h, "stopped at {t}, closed form {stop}");
    // No creep: 100 s later it is where it stopped, to the bit.
    let x = sim.state().pos[1].x;
    sim.advance_to(100.0).expect("finite");
    assert_eq!(sim.state().pos[1].x, x);
}

#[test]
fn a_disc_thrown_sliding_ends_up_rolling_at_two_thirds_of_its_speed() {
    let (mu, v0, r, h) = (0.3, 3.0, 0.2, 0.001);
    let s = on_floor(
        mu,
        "[[body]]\nname = \"disc\"\nmass = 2.0\nposition = [0.0, 0.2]\nvelocity = [3.0, 0.0]\nshape = { circle = { radius = 0.2 } }",
        h,
        1.0,
    );
    let mut sim = s.simulation();
    let t_roll = v0 / (3.0 * mu * G);
    let mut rolled_at = None;
    while sim.state().t < 1.0 - 0.5 * h {
        sim.step().expect("no blow-up");
        let (v, w) = (sim.state().vel[1].x, sim.state().omega[1]);
        // v + ω·r is the contact point's slip; it reaches zero and stays there.
        if rolled_at.is_none() && (v + w * r).abs() < 1e-9 {
            rolled_at = Some(sim.state().t);
        }
    }
    let t = rolled_at.expect("it rolls");
    assert!(
        (t - t_roll).abs() <= h,
        "rolls from {t}, closed form {t_roll}"
    );
    let (v, w) = (sim.state().vel[1].x, sim.state().omega[1]);
    // v = 2·v0/3 and ω = -v/r: Euler's sliding phase is exact to the step in which
    // rolling begins, where it is off by at most h·μ·g = 3e-3 of it.
    assert!((v - 2.0 * v0 / 3.0).abs() <= h * mu * G, "v = {v}");
    assert!((w + v / r).abs() < 1e-9, "ω = {w}, -v/r = {}", -v / r);
}

/// Returns the speed along the slope of a body at times t1 < t2 of a run of `s`.
fn speeds(s: &Scene, body: usize, t1: f64, t2: f64) -> (f64, f64) {
    let mut sim = s.simulation();
    sim.advance_to(t1).expect("finite");
    let v1 = sim.state().vel[body].length();
    sim.advance_to(t2).expect("finite");
    (v1, sim.state().vel[body].length())
}

#[test]
fn on_a_slope_a_disc_rolls_at_two_thirds_g_sin_alpha_and_a_box_slides_or_stays() {
    let s = load("roll.toml");
    let alpha = 20f64.to_radians();
    let (roller, slider) = (index(&s, "roller"), index(&s, "slider"));
    let (t1, t2) = (0.2, 1.2);
    // Uniform accelerations, so the speed gained over [t1, t2] is a·(t2 - t1) exactly:
    // explicit Euler adds h·a every step, rolling or sliding alike.
    let h = s.simulation.dt;
    let (a, b) = speeds(&s, roller, t1, t2);
    let rolling = 2.0 / 3.0 * G * alpha.sin();
    assert!(
        ((b - a) / (t2 - t1) - rolling).abs() <= 1e-6 * rolling,
        "disc: {}",
        (b - a) / (t2 - t1)
    );
    let (a, b) = speeds(&s, slider, t1, t2);
    let sliding = G * (alpha.sin() - 0.3 * alpha.cos());
    assert!(
        ((b - a) / (t2 - t1) - sliding).abs() <= 1e-6 * sliding,
        "box: {}",
        (b - a) / (t2 - t1)
    );
    assert!(a > 0.0 && h > 0.0);
    // With μ = 0.5 > tan 20° = 0.36 the box stays put.
    let text = std::fs::read_to_string(example("roll.toml")).expect("readable");
    let sticky = scene(&text.replace("friction = 0.3", "friction = 0.5"));
    let mut sim = sticky.simulation();
    let start = sim.state().pos[slider];
    for _ in 0..sticky.total_steps() {
        sim.step().expect("finite");
        // It settles onto the slope by round-off in the solver's sweeps over its two
        // corners, and goes nowhere: a micrometre at most.
        let moved = (sim.state().pos[slider] - start).length();
        assert!(
            moved < 1e-6,
            "the box moved {moved} by t = {}",
            sim.state().t
        );
    }
}

#[test]
fn a_ball_dropped_with_e_one_half_comes_to_rest_and_stays() {
    let s = on_floor(
        0.5,
        "[[body]]\nname = \"ball\"\nmass = 0.5\nposition = [2.0, 1.1]\nrestitution = 0.5\nshape = { circle = { radius = 0.1 } }",
        0.002,
        110.0,
    );
    let mut sim = s.simulation();
    sim.advance_to(10.0).expect("finite");
    let slop = DEFAULT_SLOP * 0.2;
    for _ in 0..50_000 {
        sim.step().expect("finite");
        let st = sim.state();
        assert!(
            st.vel[1].length() < 1e-9,
            "moving at t = {}: {}",
            st.t,
            st.vel[1]
        );
        assert!(
            (st.pos[1].y - 0.1).abs() <= slop,
            "height {} at t = {}",
            st.pos[1].y,
            st.t
        );
    }
}

/// Runs `s` to t and returns each body's largest displacement and turn from its start.
fn drift(s: &Scene, t: f64) -> (f64, f64) {
    let mut sim = s.simulation();
    let start = sim.state().clone();
    sim.advance_to(t).expect("no blow-up, no overlap");
    let end = sim.state();
    let mut worst = (0.0f64, 0.0f64);
    for (i, b) in s.bodies.iter().enumerate() {
        if b.is_static || b.name == "ball" {
            continue;
        }
        worst.0 = worst.0.max((end.pos[i] - start.pos[i]).length());
        worst.1 = worst.1.max((end.angle[i] - start.angle[i]).abs());
    }
    worst
}

#[test]
fn a_tower_of_ten_boxes_and_a_pyramid_of_twenty_rows_stand_for_a_minute() {
    let text = std::fs::read_to_string(example("tower.toml")).expect("readable");
    let pyramid = std::fs::read_to_string(example("pyramid.toml")).expect("readable");
    // Asleep, a standing stack is held where it fell asleep; awake (`sleep = false`),
    // the solver alone must hold it, step after step, for the whole minute.
    for sleep in ["", "sleep = false\n"] {
        let awake = |text: &str| {
            let s = scene(&text.replace("[contacts]\n", &format!("[contacts]\n{sleep}")));
            let sleeps = s.contacts.as_ref().and_then(|c| c.resting.sleep).is_some();
            assert_eq!(sleeps, sleep.is_empty(), "the scene's `sleep` is {sleep:?}");
            s
        };
        let (moved, turned) = drift(&awake(&tower_text(&text)), 60.0);
        assert!(moved < 0.01 * 0.6, "a tower box moved {moved} ({sleep})");
        assert!(turned < 0.01, "a tower box turned {turned} ({sleep})");
        let (moved, turned) = drift(&awake(&pyramid), 60.0);
        assert!(moved < 0.01 * 1.0, "a pyramid box moved {moved} ({sleep})");
        assert!(turned < 0.01, "a pyramid box turned {turned} ({sleep})");
    }
}

/// Six boxes of 1 to 10 kg stacked on a floor, an 8 kg box on a 0.2 kg plank among
/// them: (name, mass, width, height).
const HEAVY_ON_LIGHT: [(&str, f64, f64, f64); 6] = [
    ("a", 1.0, 1.0, 0.5),
    ("plank", 0.2, 2.0, 0.2),
    ("heavy", 8.0, 1.0, 0.5),
    ("light", 0.5, 0.8, 0.5),
    ("heaviest", 10.0, 1.2, 0.5),
    ("top", 2.0, 0.6, 0.5),
];

#[test]
fn a_stack_of_heavy_boxes_on_light_ones_comes_to_rest_and_stays() {
    // Mass ratios of 40 between touching bodies converge slowest; awake, with the
    // default sweeps, the stack must still come to rest and stay. (While a box's two
    // contact points shared one warm-start key, this stack jittered at 1.5 mm/s and
    // crept 29 mm in a minute.)
    let mut bodies = String::new();
    let mut y = 0.0;
    for (name, mass, w, h) in HEAVY_ON_LIGHT {
        bodies += &format!(
            "[[body]]\nname = \"{name}\"\nmass = {mass}\nposition = [0.0, {}]\n\
             shape = {{ box = {{ width = {w}, height = {h} }} }}\n",
            y + 0.5 * h
        );
        y += h;
    }
    let text = format!(
        "[simulation]\ndt = {}\nduration = 30.0\n\
         [render]\nview = {{ min = [-3.0, -0.5], max = [3.0, 3.0] }}\nfps = 10\n\
         [contacts]\nfriction = 0.6\nsleep = false\n\
         [[body]]\nname = \"floor\"\nstatic = true\nposition = [0.0, -0.25]\n\
         shape = {{ box = {{ width = 10.0, height = 0.5 }} }}\n\
         {bodies}[[force]]\nkind = \"gravity\"\n",
        1.0 / 240.0
    );
    let s = scene(&text);
    let mut sim = s.simulation();
    let start = sim.state().clone();
    sim.advance_to(5.0).expect("no blow-up, no overlap");
    while sim.state().t < 30.0 {
        sim.step().expect("no blow-up, no overlap");
        let st = sim.state();
        for (name, _, w, h) in HEAVY_ON_LIGHT {
            let i = index(&s, name);
            // At rest: no faster than round-off from 5 s on.
            assert!(
                st.vel[i].length() < 1e-9 && st.omega[i].abs() < 1e-9,
                "{name} moving at t = {}: {}, {}",
                st.t,
                st.vel[i],
                st.omega[i]
            );
            // Standing, by the tower's measure: within 1% of its size of its start
            // and turned less than 0.01 rad.
            let moved = (st.pos[i] - start.pos[i]).length();
            assert!(moved < 0.01 * w.min(h), "{name} moved {moved} m");
            assert!((st.angle[i] - start.angle[i]).abs() < 0.01, "{name} turned");
        }
    }
}

/// A 1 m box at rest, sunk `depth` into a static floor (top at y = 0) at angle `angle`,
/// with no gravity (a resting speed is given instead), after one step. A scene may not
/// start overlapping, so the box is sunk into the scene's first state by hand, as a
/// step that left it so would have.
fn sunk_box_after_one_step(depth: f64, angle: f64) -> (physframes::sim::State, usize) {
    let s = scene(
        r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        view = { min = [-2.0, -1.0], max = [2.0, 2.0] }
        fps = 10
        [contacts]
        rest_speed = 0.05
        slop = 0.001
        [[body]]
        name = "floor"
        static = true
        position = [0.0, -0.5]
        shape = { box = { width = 4.0, height = 1.0 } }
        [[body]]
        name = "box"
        mass = 1.0
        position = [0.0, 0.6]
        shape = { box = { width = 1.0, height = 1.0 } }
        "#,
    );
    let b = index(&s, "box");
    let mut state = s.initial_state();
    state.pos[b].y = 0.5 - depth;
    state.angle[b] = angle;
    let mut sim = s.simulation_from(state, s.simulation.integrator);
    sim.step().expect("the overlap is within the limit");
    (sim.state().clone(), b)
}

/// The relaxation pushes a sunk box out along the normal and never turns it (turning
/// it about a corner would also slide it sideways, past friction: `solver::relaxation`).
/// Level, both corners are pushed by β = 0.2 of the excess over the slop found at the
/// start of a pass, so each of the 3 passes leaves (1 - 2β) of the excess: the box
/// ends sunk by slop + 0.6³·(depth - slop), to rounding (1e-12 m).
#[test]
fn relaxation_pushes_a_sunk_box_out_without_turning_it() {
    let (depth, slop) = (0.01, 0.001);
    let (st, b) = sunk_box_after_one_step(depth, 0.0);
    let expected = 0.5 - (slop + 0.6f64.powi(3) * (depth - slop));
    assert!(
        (st.pos[b].y - expected).abs() < 1e-12,
        "y = {}, expected {expected}",
        st.pos[b].y
    );
    assert_eq!(st.pos[b].x, 0.0, "pushed straight up");
    assert_eq!(st.angle[b], 0.0, "not turned");
    // Tilted, one corner sunk deeper than the other: still moved, never turned.
    let tilt = 0.004;
    let (st, b) = sunk_box_after_one_step(depth, tilt);
    assert_eq!(st.angle[b], tilt, "not turned");
    assert_eq!(st.vel[b], glam::DVec2::ZERO, "positions only");
    assert!(st.pos[b].y > 0.5 - depth, "pushed up: y = {}", st.pos[b].y);
}

/// The tower example without the ball that knocks it over: the ball rests on the
/// floor beside it.
fn tower_text(text: &str) -> String {
    text.replace("velocity = [6.0, 1.0]", "velocity = [0.0, 0.0]")
        .replace("position = [-2.6, 5.2]", "position = [-2.6, 0.15]")
}

/// Runs a pour of discs of radius `r` into a bucket whose walls' inner faces are at
/// x = ±`half_width` and whose floor's top is at y = 0, checking at every step that no
/// disc leaves it, that no two overlap past the run's limit (a step that left one would
/// fail), and that none outruns a free fall from the highest start; returns the
/// discs' speeds at the end, slowest first.
fn pour(s: &Scene, r: f64, half_width: f64) -> Vec<f64> {
    let mut sim = s.simulation();
    let discs: Vec<usize> = (0..s.bodies.len())
        .filter(|&i| !s.bodies[i].is_static)
        .collect();
    // The fastest a disc can go: its starting speed and a fall from the highest start
    // to the bottom, v² = v0² + 2·g·Δh.
    let top = discs
        .iter()
        .map(|&i| s.bodies[i].position.y)
        .fold(0.0, f64::max);
    let v0 = discs
        .iter()
        .map(|&i| s.bodies[i].velocity.length())
        .fold(0.0, f64::max);
    let bound = (v0 * v0 + 2.0 * G * top).sqrt();
    for _ in 0..s.total_steps() {
        sim.step().expect("no overlap ever passes the limit");
        for &i in &discs {
            let (p, v) = (sim.state().pos[i], sim.state().vel[i]);
            assert!(
                v.length() <= bound,
                "disc {i} at {} m/s, over {bound}",
                v.length()
            );
            // Inside the walls, overlapping them by no more than the run's limit for
            // resting bodies, a tenth of a disc.
            let limit = 0.1 * 2.0 * r;
            assert!(
                p.x.abs() <= half_width - r + limit && p.y >= r - limit,
                "disc {i} left: {p}"
            );
        }
    }
    let mut speeds: Vec<f64> = discs.iter().map(|&i| sim.state().vel[i].length()).collect();
    speeds.sort_by(f64::total_cmp);
    speeds
}

#[test]
fn discs_poured_into_a_bucket_settle_inside_it_and_never_outrun_a_free_fall() {
    // Settled: every disc nearly still at the end.
    let speeds = pour(&load("pour.toml"), 0.06, 3.0);
    let fastest = speeds.last().copied().unwrap_or(0.0);
    assert!(fastest < 0.05, "still moving at {fastest}");
}

/// Ten thousand discs dropped from a loose grid up to 8 m above the floor (the
/// benchmark's pile): the same checks at every step, through the first second's
/// thousands of impacts a step. After 4 s the pile has settled: a pile this deep still
/// has a disc slipping into a gap now and then (sampled every 0.2 s over 6 s: at most 27 discs of
/// 10,000 over 5 cm/s after 2 s, at most 1 after 2.8 s, none after 4.6 s), so settled
/// means no disc faster than a fall through one diameter, √(2·g·2r) = 1.4 m/s, at most
/// one in a thousand faster than 5 cm/s, and the median under 5 mm/s.
#[test]
fn ten_thousand_discs_dropped_into_a_bucket_settle_inside_it() {
    let path = example("bench/pile-10000.toml");
    let text = std::fs::read_to_string(&path).expect("the bench scene");
    let s = physframes::scene::parse_with_overrides(
        std::path::Path::new(&path),
        &text,
        &["simulation.duration=4.0".to_string()],
    )
    .expect("a valid scene");
    let r = 0.05;
    let speeds = pour(&s, r, 8.0);
    let fastest = speeds.last().copied().unwrap_or(0.0);
    assert!(
        fastest < (2.0 * G * 2.0 * r).sqrt(),
        "a disc at {fastest} m/s"
    );
    let moving = speeds.iter().filter(|&&v| v > 0.05).count();
    assert!(moving <= speeds.len() / 1000, "{moving} discs over 5 cm/s");
    let median = speeds[speeds.len() / 2];
    assert!(median < 0.005, "the median disc at {median} m/s");
}

#[test]
fn the_log_records_collisions_not_resting_contacts() {
    let s = load("rest.toml");
    let mut sim = s.simulation();
    sim.record_contacts(true);
    sim.advance_to(4.0).expect("finite");
    let events = sim.take_contact_events();
    let rest = s.contacts.as_ref().expect("collides").resting.speed;
    // A few bounces of the ball, not a row for every step it lies on the floor.
    assert!(
        !events.is_empty() && events.len() < 30,
        "{} rows",
        events.len()
    );
    for e in &events {
        assert!(e.vn_before < -rest, "a resting contact logged: {e:?}");
        let mu = 0.5;
        assert!(
            e.jt.abs() <= mu * e.impulse * (1.0 + 1e-12),
            "Coulomb: {e:?}"
        );
    }
}

#[test]
fn shards_of_a_resting_scene_carry_the_warm_start_and_equal_a_single_run() {
    crate::util::assert_shards_equal_a_single_run(&example("tower.toml"), "20", &[], [&[], &[]]);
}
