//! Property tests over random valid scenes: nothing panics, internal forces conserve
//! momentum, and drawing is deterministic.

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec2;
use physframes::render::{encode_png, ArrowScales, Compression, FrameView, Provenance, Renderer};
use physframes::scene::parse;
use physframes::sim::{IntegratorKind, Simulation};
use proptest::prelude::*;

/// One random body: mass, position, velocity, shape choice, and whether it is made of
/// point masses.
#[derive(Clone, Debug)]
struct BodySpec {
    mass: f64,
    pos: (f64, f64),
    vel: (f64, f64),
    shape: u8,
    arrows: bool,
}

fn body() -> impl Strategy<Value = BodySpec> {
    (
        // Masses across 18 decades, as the extremes ask (1e-9 to 1e9).
        -9.0f64..9.0,
        (-50.0f64..50.0, -50.0f64..50.0),
        // Speeds up to 1e6.
        (-1e6f64..1e6, -1e6f64..1e6),
        0u8..4,
        any::<bool>(),
    )
        .prop_map(|(log_mass, pos, vel, shape, arrows)| BodySpec {
            mass: 10f64.powf(log_mass),
            pos,
            vel,
            shape,
            arrows,
        })
}

/// One random force, as TOML lines, for `n` bodies.
fn force(n: usize) -> impl Strategy<Value = String> {
    (0u8..6, 0..n, 0..n, -100.0f64..100.0, 0.0f64..50.0, any::<bool>()).prop_map(
        move |(kind, a, b, x, k, fixed)| match kind {
            0 => format!("kind = \"gravity\"\ng = [{x}, {}]", -k),
            1 => format!("kind = \"drag\"\nk = {k}"),
            2 => format!("kind = \"quadratic-drag\"\nc = {}\nbodies = [\"b{a}\"]", k / 100.0),
            3 => format!("kind = \"force\"\nf0 = [{x}, 0]\nf1 = [0, {k}]"),
            4 if a != b && !fixed => format!(
                "kind = \"spring\"\na = \"b{a}\"\nb = \"b{b}\"\nstiffness = {k}\nrest_length = 1.0\ndamping = 0.1"
            ),
            4 => format!("kind = \"spring\"\na = \"b{a}\"\nb = [{x}, 0]\nstiffness = {k}"),
            _ => format!("kind = \"central\"\ncentre = [{x}, 0]\nstrength = {k}"),
        },
    )
}

/// A random valid scene: bodies, forces, an integrator, and a short run.
fn scene_text() -> impl Strategy<Value = String> {
    prop::collection::vec(body(), 1..6).prop_flat_map(|bodies| {
        let n = bodies.len();
        (
            Just(bodies),
            prop::collection::vec(force(n), 0..5),
            0..IntegratorKind::ALL.len(),
            prop::sample::select(vec![0.001, 0.01, 0.1]),
        )
            .prop_map(|(bodies, forces, integrator, dt)| {
                let mut s = String::new();
                let integrator = IntegratorKind::ALL[integrator];
                let _ = writeln!(
                    s,
                    "[simulation]\nintegrator = \"{integrator}\"\ndt = {dt}\nduration = 0.5\n[render]\nwidth = 64\nheight = 48\nfps = 10\ntrails = true\nview = {{ min = [-60.0, -60.0], max = [60.0, 60.0] }}"
                );
                for (i, b) in bodies.iter().enumerate() {
                    let _ = writeln!(
                        s,
                        "[[body]]\nname = \"b{i}\"\nposition = [{}, {}]\nvelocity = [{}, {}]\nshow_velocity = {}\nshow_force = {}",
                        b.pos.0, b.pos.1, b.vel.0, b.vel.1, b.arrows, b.arrows
                    );
                    match b.shape {
                        0 => {
                            let _ = writeln!(s, "mass = {}\nshape = {{ circle = {{ radius = 0.5 }} }}", b.mass);
                        }
                        1 => {
                            let _ = writeln!(s, "mass = {}\nshape = {{ box = {{ width = 1, height = 2 }} }}", b.mass);
                        }
                        2 => {
                            let _ = writeln!(s, "mass = {}\nshape = {{ polygon = {{ points = [[0, 0], [1, 0], [0, 1]] }} }}", b.mass);
                        }
                        _ => {
                            let _ = writeln!(
                                s,
                                "points = [{{ offset = [-1, 0], mass = {} }}, {{ offset = [1, 0], mass = {} }}]",
                                b.mass,
                                2.0 * b.mass
                            );
                        }
                    }
                }
                for f in forces {
                    let _ = writeln!(s, "[[force]]\n{f}");
                }
                s
            })
    })
}

/// Simulates every frame and draws and encodes it; returns the PNG bytes, or stops
/// quietly at a blow-up (which is a correct outcome for an unstable random scene).
fn render_all(text: &str) -> Vec<Vec<u8>> {
    let scene = parse(Path::new("random.toml"), text)
        .unwrap_or_else(|e| panic!("valid scene:\n{e}\n{text}"));
    let mut sim = Simulation::new(
        scene.system(),
        scene.initial_state(),
        scene.simulation.integrator,
        scene.simulation.dt,
    );
    let mut force = vec![DVec2::ZERO; scene.bodies.len()];
    sim.net_forces(&mut force);
    let renderer = Renderer::new(&scene, ArrowScales::fit(&scene, &sim.state().vel, &force));
    let mut trail = physframes::history::HistoryWriter::new();
    let mut frames = Vec::new();
    for k in 0..scene.render.frame_count {
        if sim.advance_to(scene.frame_time(k)).is_err() {
            break;
        }
        sim.net_forces(&mut force);
        trail.push(std::sync::Arc::from(sim.state().pos.as_slice()));
        let view = FrameView {
            index: k,
            t: sim.state().t,
            pos: &sim.state().pos,
            vel: &sim.state().vel,
            angle: None,
            force: Some(&force),
            trail: Some(trail.history()),
            traces: None,
            compare: None,
        };
        let pixmap = renderer.draw(&view);
        frames.push(
            encode_png(&pixmap, &Provenance::default(), Compression::Fastest).expect("encodes"),
        );
    }
    frames
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn random_valid_scenes_never_panic_and_draw_the_same_bytes_twice(text in scene_text()) {
        let first = render_all(&text);
        let second = render_all(&text);
        prop_assert!(first == second, "two runs of the same scene differ:\n{}", text);
    }

    #[test]
    fn internal_forces_conserve_momentum_for_every_integrator(
        masses in prop::collection::vec(-3.0f64..3.0, 2..6),
        stiffness in 0.1f64..100.0,
        steps in 10u64..400,
    ) {
        for &integrator in IntegratorKind::ALL {
            let mut s = String::from("[simulation]\ndt = 0.001\n[render]\nfps = 25\nview = { min = [-10.0, -10.0], max = [10.0, 10.0] }\n");
            for (i, lm) in masses.iter().enumerate() {
                let _ = writeln!(s, "[[body]]\nname = \"b{i}\"\nmass = {}\nposition = [{}, {}]\nvelocity = [{}, 0.5]", 10f64.powf(*lm), i as f64, (i * i) as f64 * 0.3, 1.0 - i as f64);
            }
            // A chain of damped springs, plus one closing the loop: only internal forces.
            for i in 0..masses.len() {
                let j = (i + 1) % masses.len();
                if i != j {
                    let _ = writeln!(s, "[[force]]\nkind = \"spring\"\na = \"b{i}\"\nb = \"b{j}\"\nstiffness = {stiffness}\nrest_length = 0.5\ndamping = 0.2");
                }
            }
            let scene = parse(Path::new("springs.toml"), &s).expect("valid");
            let mut sim = Simulation::new(scene.system(), scene.initial_state(), integrator, 0.001);
            let p0 = sim.system().momentum(&sim.state().vel);
            // Σ m_i·|v_i| bounds the terms whose round-off can move p; springs trade
            // potential for kinetic energy, so it is tracked over the whole run.
            let momentum_scale = |sim: &Simulation| -> f64 {
                sim.state().vel.iter().zip(sim.system().masses()).map(|(v, m)| m * v.length()).sum()
            };
            let mut scale = momentum_scale(&sim);
            let mut blew_up = false;
            for _ in 0..steps {
                if sim.step().is_err() {
                    blew_up = true;
                    break;
                }
                scale = scale.max(momentum_scale(&sim));
            }
            if blew_up {
                continue;
            }
            let p = sim.system().momentum(&sim.state().vel);
            // Each step adds equal and opposite forces, so p changes only by round-off:
            // a few ulps (16 allowed) of the largest momentum, per step.
            let allowed = f64::EPSILON * scale.max(1e-300) * (steps as f64) * 16.0;
            prop_assert!((p - p0).length() <= allowed, "{integrator}: p moved by {} > {allowed}", (p - p0).length());
        }
    }
}
