//! The simulation against the article's closed forms. Explicit Euler is exact for
//! some problems in a discrete sense, so these tolerances are round-off, not
//! truncation error: each step adds a few ulps, and 1e-12 relative leaves room for
//! about 10^4 steps of them.

use glam::DVec2;
use physframes::sim::Simulation;

use crate::util::scene;

/// A drag scene with the given mass, drag coefficient, step and frame rate.
fn drag_scene(m: f64, k: f64, dt: f64, fps: f64) -> String {
    format!(
        r#"
        [simulation]
        dt = {dt}
        duration = 5.0
        [render]
        fps = {fps}
        view = {{ min = [-1.0, -3.0], max = [10.0, 3.0] }}
        [[body]]
        name = "puck"
        mass = {m}
        velocity = [3.0, -1.0]
        [[force]]
        kind = "drag"
        k = {k}
        "#
    )
}

fn assert_close(actual: f64, expected: f64, relative: f64, what: &str) {
    let scale = expected.abs().max(1e-300);
    assert!(
        (actual - expected).abs() <= relative * scale,
        "{what}: got {actual}, expected {expected} (relative error {:e}, allowed {relative:e})",
        (actual - expected).abs() / scale
    );
}

#[test]
fn euler_on_drag_equals_the_discrete_closed_form_at_every_frame() {
    for (m, k, dt, fps) in [
        (1.0, 1.0, 0.01, 25.0),
        (2.0, 0.5, 0.004, 50.0),
        (0.5, 3.0, 0.02, 10.0),
    ] {
        let scene = scene(&drag_scene(m, k, dt, fps));
        let mut sim = Simulation::new(
            scene.system(),
            scene.initial_state(),
            scene.simulation.integrator,
            dt,
        );
        let v0 = DVec2::new(3.0, -1.0);
        for frame in 0..scene.render.frame_count {
            sim.advance_to(scene.frame_time(frame))
                .expect("drag stays finite");
            let n = sim.steps() as i32;
            // v_n = v0·(1 - h·k/m)^n, exact for explicit Euler on dv/dt = -k·v/m.
            let expected = v0 * (1.0 - dt * k / m).powi(n);
            let v = sim.state().vel[0];
            assert_close(
                v.x,
                expected.x,
                1e-12,
                &format!("vx at frame {frame}, m={m} k={k}"),
            );
            assert_close(
                v.y,
                expected.y,
                1e-12,
                &format!("vy at frame {frame}, m={m} k={k}"),
            );
        }
    }
}

#[test]
fn euler_under_constant_acceleration_matches_its_exact_discrete_form() {
    let text = r#"
        [simulation]
        dt = 0.01
        duration = 4.0
        [render]
        fps = 25
        view = { min = [-1.0, -1.0], max = [17.0, 11.0] }
        [[body]]
        name = "ball"
        mass = 2.0
        position = [0.5, 1.0]
        velocity = [4.0, 10.0]
        [[force]]
        kind = "gravity"
        g = [1.5, -5.0]
    "#;
    let scene = scene(text);
    let h = scene.simulation.dt;
    let (r0, v0, a) = (
        DVec2::new(0.5, 1.0),
        DVec2::new(4.0, 10.0),
        DVec2::new(1.5, -5.0),
    );
    let mut sim = Simulation::new(
        scene.system(),
        scene.initial_state(),
        scene.simulation.integrator,
        h,
    );
    for frame in 0..scene.render.frame_count {
        sim.advance_to(scene.frame_time(frame)).expect("finite");
        let t = sim.state().t;
        // Euler sums r_n = r0 + Σ h·v_i with v_i = v0 + i·h·a, which is exactly
        // r0 + v0·t + a·t²/2 - a·h·t/2 at t = n·h: the article's Equation 5, less
        // Euler's first-order lag.
        let expected = r0 + v0 * t + a * t * t / 2.0 - a * h * t / 2.0;
        let r = sim.state().pos[0];
        // Relative to the size of the terms being summed, which stays near 20.
        let scale = (r0.length() + (v0 * t).length() + (a * t * t / 2.0).length()).max(1.0);
        assert!(
            (r - expected).length() <= 1e-12 * scale,
            "frame {frame}, t = {t}: got {r}, expected {expected}"
        );
        // v_n = v0 + a·t exactly (Equation 4).
        let v = sim.state().vel[0];
        assert!((v - (v0 + a * t)).length() <= 1e-12 * (v0.length() + (a * t).length()));
    }
}

#[test]
fn a_body_of_point_masses_has_the_mass_and_centre_of_equation_8() {
    let text = r#"
        [render]
        view = { min = [-5.0, -5.0], max = [5.0, 5.0] }
        [[body]]
        name = "dumbbell"
        position = [2.0, 1.0]
        velocity = [0.5, -0.25]
        points = [{ offset = [-1.0, 0.0], mass = 1.0 }, { offset = [1.0, 0.0], mass = 3.0 }, { offset = [0.0, 2.0], mass = 4.0 }]
    "#;
    let scene = scene(text);
    let body = &scene.bodies[0];
    // M = Σ m_i = 8.
    assert_eq!(body.mass, 8.0);
    // r_CM = position + Σ m_i·o_i / M = (2, 1) + ((-1 + 3 + 0)/8, (0 + 0 + 8)/8).
    assert_eq!(body.position, DVec2::new(2.25, 2.0));
    // Offsets are kept relative to the centre of mass, so Σ m_i·o_i = 0 around it.
    let physframes::scene::Shape::Points { points } = &body.shape else {
        panic!("a body of points keeps its points");
    };
    let moment = points
        .iter()
        .fold(DVec2::ZERO, |acc, p| acc + p.mass * p.offset);
    assert!(
        moment.length() < 1e-15,
        "Σ m_i·o_i about the centre = {moment}"
    );
    // Equations 7 and 10: every point moves with the centre of mass (no rotation), so
    // p_T = Σ m_i·v_i = M·v_CM.
    let p_points: DVec2 = points.iter().map(|p| p.mass * body.velocity).sum();
    let system = scene.system();
    assert_eq!(system.momentum(&[body.velocity]), p_points);
    assert_eq!(p_points, 8.0 * DVec2::new(0.5, -0.25));
}

#[test]
fn a_time_varying_force_changes_momentum_by_eulers_sum_of_impulses() {
    let scene = scene(
        &std::fs::read_to_string(crate::util::example("centre-of-mass.toml")).expect("example"),
    );
    let h = scene.simulation.dt;
    let m = scene.bodies[0].mass;
    assert_eq!(m, 4.0);
    let mut sim = Simulation::new(
        scene.system(),
        scene.initial_state(),
        scene.simulation.integrator,
        h,
    );
    let steps = scene.total_steps();
    sim.run_steps(steps).expect("finite");
    // Equation 11 with explicit Euler: p_n = Σ_{i<n} h·F(t_i), F = 2t, t_i = i·h, so
    // p_n = 2h²·n(n-1)/2 = h²·n·(n-1).
    let n = steps as f64;
    let expected = h * h * n * (n - 1.0);
    let p = sim.system().momentum(&sim.state().vel);
    assert_close(p.x, expected, 1e-12, "momentum");
    assert_eq!(p.y, 0.0);
    // And against the article's closed form v = t²/M, Euler lags by h·t/M.
    let t = sim.state().t;
    assert_close(
        sim.state().vel[0].x,
        t * t / m - h * t / m,
        1e-12,
        "velocity",
    );
}

#[test]
fn springs_between_bodies_keep_total_momentum_to_round_off() {
    let scene =
        scene(&std::fs::read_to_string(crate::util::example("spring.toml")).expect("example"));
    let mut sim = Simulation::new(
        scene.system(),
        scene.initial_state(),
        scene.simulation.integrator,
        scene.simulation.dt,
    );
    let p0 = sim.system().momentum(&sim.state().vel);
    // Σ m_i·|v_i| bounds the size of the terms whose round-off could move p.
    let scale = |sim: &Simulation| {
        sim.state()
            .vel
            .iter()
            .zip(sim.system().masses())
            .map(|(v, m)| m * v.length())
            .sum::<f64>()
    };
    let mut worst = 0.0f64;
    for _ in 0..scene.total_steps() {
        sim.step().expect("finite");
        let drift = (sim.system().momentum(&sim.state().vel) - p0).length() / scale(&sim);
        worst = worst.max(drift);
    }
    // 3000 steps of a few ulps each stay far below 1e-12.
    assert!(worst < 1e-12, "momentum drifted by {worst:e} relative");
    // The spring did work: the bodies' velocities changed, so this is not vacuous.
    assert!((sim.state().vel[0] - scene.bodies[0].velocity).length() > 0.1);
}

#[test]
fn a_comparison_measures_each_integrator_against_the_exact_path() {
    let text = drag_scene(1.0, 1.0, 0.01, 25.0).replace(
        "duration = 5.0",
        "duration = 5.0\ncompare = [\"euler\", \"rk4\", \"exact\"]",
    );
    let scene = scene(&text);
    let mut comparison = physframes::compare::Comparison::new(&scene).expect("compare is set");
    let frames: Vec<_> = (0..scene.render.frame_count)
        .map(|k| comparison.advance_to(scene.frame_time(k)))
        .collect();
    let frame = frames.last().expect("frames");
    assert_eq!(frame.reference, "exact");
    assert_eq!(frame.error_labels, vec!["euler", "rk4"]);
    let (t, errors) = frame.errors.last().expect("a row per frame").clone();
    assert_eq!(frame.errors.len() as u64, scene.render.frame_count);
    // Every frame sees the history up to its own time, the rows later frames see too,
    // and none after, though all frames share the history.
    let all: Vec<_> = frame.errors.iter().collect();
    for (k, earlier) in frames.iter().enumerate() {
        let seen: Vec<_> = earlier.errors.iter().collect();
        assert_eq!(seen, all[..=k], "frame {k}");
        let own = earlier.errors.last().expect("its own row").0;
        assert_eq!(own, scene.frame_time(k as u64), "frame {k}");
    }
    // The puck's exact x at t: v0·m/k·(1 - e^(-kt/m)) with v0 = 3; Euler's is
    // Σ h·v0·(1 - h)^i = v0·(1 - (1 - h)^n), so its error is known in closed form.
    let n = (t / 0.01).round() as i32;
    let v0 = DVec2::new(3.0, -1.0);
    let exact = v0 * (1.0 - (-t).exp());
    let euler = v0 * (1.0 - (1.0f64 - 0.01).powi(n));
    let expected = (euler - exact).length();
    assert_close(
        errors[0],
        expected,
        1e-9,
        "Euler's error against the exact path",
    );
    // RK4 is far closer to the exact path than Euler at the same step.
    assert!(
        errors[1] < 1e-6 * errors[0],
        "rk4 {} vs euler {}",
        errors[1],
        errors[0]
    );
}
