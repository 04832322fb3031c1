//! Issue #16: explicit Euler on a swarm of one mass under gravity and linear drag takes
//! its own loop (`System::uniform_linear`), with the constants of the general force sum
//! taken out of it and the finiteness check summed as it goes. It must give the bits of
//! the general step, for any number of threads and with or without AVX2, and still find
//! and name a blow-up.

use glam::DVec2;
use physframes::scene::Scene;
use physframes::sim::chunks::use_wide_vectors;
use physframes::sim::{Simulation, State};

use crate::util::{assert_same_bits, run, scene};

/// A swarm large enough to run on several threads, all of one mass, under `forces`.
fn swarm(forces: &str) -> Scene {
    scene(&format!(
        r##"
[simulation]
dt = 0.001
[render]
fps = 100
view = {{ min = [-10.0, -10.0], max = [10.0, 10.0] }}
[[swarm]]
name = "dust"
count = 150001
seed = 9
mass = 0.7
position = {{ min = [-5.0, -5.0], max = [5.0, 5.0] }}
velocity = {{ min = [-1.0, -1.0], max = [1.0, 1.0] }}
{forces}
"##
    ))
}

/// Explicit Euler written out over whole arrays, with the system's general force sum.
fn written_out(s: &Scene, steps: u64) -> State {
    let system = s.system();
    let h = s.simulation.dt;
    let mut state = s.initial_state();
    let mut acc = vec![DVec2::ZERO; state.len()];
    for n in 0..steps {
        system.accelerations(n as f64 * h, &state.pos, &state.vel, &mut acc);
        for ((r, v), a) in state.pos.iter_mut().zip(&mut state.vel).zip(&acc) {
            *r += h * *v;
            *v += h * *a;
        }
    }
    state
}

#[test]
fn the_uniform_swarm_loop_gives_the_bits_of_the_general_step() {
    // Gravity and drag; gravity alone; two gravities, one with a negative zero (whose
    // sign the general sum 0 + m·g turns); drag alone.
    for forces in [
        "[[force]]\nkind = \"gravity\"\n[[force]]\nkind = \"drag\"\nk = 0.3\n",
        "[[force]]\nkind = \"gravity\"\ng = [1.5, -2.0]\n",
        "[[force]]\nkind = \"gravity\"\ng = [-0.0, -9.81]\n[[force]]\nkind = \"gravity\"\ng = [0.25, -0.0]\n[[force]]\nkind = \"drag\"\nk = 2.0\n",
        "[[force]]\nkind = \"drag\"\nk = 0.5\n",
    ] {
        let s = swarm(forces);
        let one = run(&s, 7, 1);
        assert_same_bits(&written_out(&s, 7), &one, "written out and the loop");
        assert_same_bits(&one, &run(&s, 7, 2), "1 and 2 threads");
        use_wide_vectors(false);
        let narrow = run(&s, 7, 2);
        use_wide_vectors(true);
        assert_same_bits(&one, &narrow, "with and without AVX2");
    }
}

#[test]
fn a_blow_up_in_the_uniform_swarm_loop_is_found_at_its_step_and_named() {
    // h·k/m = 0.001·3000/0.7 > 2: every velocity grows by |1 - h·k/m| ≈ 3.29 a step
    // until it overflows. The first body to overflow, at the first step any does, is
    // named: the one whose velocity is largest after the last finite step.
    let s = swarm("[[force]]\nkind = \"drag\"\nk = 3000.0\n");
    let mut sim = Simulation::new(
        s.system(),
        s.initial_state(),
        s.simulation.integrator,
        s.simulation.dt,
    );
    let b = sim.run_steps(2000).expect_err("it blows up");
    // The same step and body written out.
    let h = s.simulation.dt;
    let mut state = s.initial_state();
    let system = s.system();
    let mut acc = vec![DVec2::ZERO; state.len()];
    let mut step = 0;
    let body = loop {
        system.accelerations(step as f64 * h, &state.pos, &state.vel, &mut acc);
        for ((r, v), a) in state.pos.iter_mut().zip(&mut state.vel).zip(&acc) {
            *r += h * *v;
            *v += h * *a;
        }
        step += 1;
        let bad = state
            .pos
            .iter()
            .zip(&state.vel)
            .position(|(r, v)| !(r.is_finite() && v.is_finite()));
        if let Some(i) = bad {
            break i;
        }
    };
    assert_eq!((b.step, b.body), (step, body), "{b:?}");
}
