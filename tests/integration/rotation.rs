//! Rigid bodies that turn, against closed forms: the discrete recurrences explicit
//! Euler obeys for the angle and angular velocity, the torque of a force off the
//! centre of mass, and the conservation laws of bodies joined by springs anchored off
//! their centres of mass.
//!
//! Tolerances: the Euler recurrences are exact in exact arithmetic, so what is left is
//! round-off, a few ulps per step; 1e-12 relative allows for about 10^4 steps of it.
//! Conservation under rk4 is limited by its truncation error, stated where it is used.

use glam::DVec2;
use physframes::sim::rigid::{perp_dot, rotate};
use physframes::sim::{
    Anchor, Coords, ForceSpec, IntegratorKind, Selection, Simulation, State, System,
};

use crate::util::scene;

fn assert_close(actual: f64, expected: f64, relative: f64, what: &str) {
    let scale = expected.abs().max(1e-300);
    assert!(
        (actual - expected).abs() <= relative * scale,
        "{what}: got {actual}, expected {expected} (relative error {:e}, allowed {relative:e})",
        (actual - expected).abs() / scale
    );
}

/// One body of mass `m` and moment of inertia `i` at rest at the origin, turned by
/// `theta0` and spinning at `omega0`.
fn one_body(m: f64, i: f64, theta0: f64, omega0: f64, forces: &[ForceSpec]) -> (System, State) {
    let system = System::rigid(vec![m], vec![i], vec![DVec2::ZERO], forces);
    let mut state = State::new(0.0, vec![DVec2::ZERO], vec![DVec2::ZERO]);
    state.angle[0] = theta0;
    state.omega[0] = omega0;
    (system, state)
}

#[test]
fn euler_under_a_constant_torque_follows_the_discrete_closed_form() {
    // ω_n = ω0 + n·h·τ/I and θ_n = θ0 + n·h·ω0 + h²·(τ/I)·n(n-1)/2.
    for (tau, inertia, theta0, omega0, h) in [
        (2.0, 0.5, 0.0, 0.0, 0.01),
        (-0.3, 1.7, 1.2, 4.0, 0.004),
        (5.0, 0.02, -0.5, -1.0, 0.001),
    ] {
        let torque = [ForceSpec::Torque {
            tau,
            bodies: Selection::All,
        }];
        let (system, state) = one_body(1.0, inertia, theta0, omega0, &torque);
        assert!(system.spins());
        let mut sim = Simulation::new(system, state, IntegratorKind::Euler, h);
        let alpha = tau / inertia;
        for n in 1..=2000u64 {
            sim.step().expect("finite");
            let nf = n as f64;
            let s = sim.state();
            assert_close(s.omega[0], omega0 + nf * h * alpha, 1e-12, "ω_n");
            let theta = theta0 + nf * h * omega0 + h * h * alpha * nf * (nf - 1.0) / 2.0;
            // θ_n passes near zero for some parameters; measure against its scale.
            let scale = theta0.abs() + nf * h * omega0.abs() + h * h * alpha.abs() * nf * nf;
            assert!(
                (s.angle[0] - theta).abs() <= 1e-12 * scale,
                "θ_{n}: got {}, expected {theta}",
                s.angle[0]
            );
            // A torque alone does not move the centre of mass.
            assert_eq!(s.pos[0], DVec2::ZERO);
        }
    }
}

#[test]
fn euler_under_angular_drag_follows_the_discrete_closed_form() {
    // ω_n = ω0·(1 - h·k/I)^n, and θ_n = θ0 + h·Σ_{j<n} ω_j = θ0 + h·ω0·(1 - q^n)/(1 - q).
    for (k, inertia, omega0, h) in [(0.5, 2.0, 3.0, 0.01), (4.0, 0.1, -7.0, 0.002)] {
        let drag = [ForceSpec::AngularDrag {
            k,
            bodies: Selection::All,
        }];
        let (system, state) = one_body(1.0, inertia, 0.25, omega0, &drag);
        // Angular drag cannot start a spin, but this body spins already.
        assert!(!system.spins());
        let mut sim = Simulation::new(system, state, IntegratorKind::Euler, h);
        assert!(sim.system().spins());
        let q = 1.0 - h * k / inertia;
        for n in 1..=1500 {
            sim.step().expect("finite");
            let s = sim.state();
            assert_close(s.omega[0], omega0 * q.powi(n), 1e-12, "ω_n");
            let theta = 0.25 + h * omega0 * (1.0 - q.powi(n)) / (1.0 - q);
            assert_close(s.angle[0], theta, 1e-12, "θ_n");
        }
    }
}

#[test]
fn a_spinning_body_without_torque_turns_at_a_constant_rate() {
    // With ω0 ≠ 0 and nothing acting, every integrator gives θ(t) = θ0 + ω0·t.
    for &kind in IntegratorKind::ALL {
        let (system, state) = one_body(1.0, 1.0, 0.5, 2.5, &[]);
        let mut sim = Simulation::new(system, state, kind, 0.01);
        sim.advance_to(1.0).expect("finite");
        assert_close(sim.state().angle[0], 0.5 + 2.5, 1e-12, kind.name());
        assert_eq!(sim.state().omega[0], 2.5, "{kind}");
    }
}

#[test]
fn a_force_off_the_centre_of_mass_exerts_its_lever_arm_torque() {
    // A body whose centre of mass is c = (0.5, -0.25) in body coordinates, pushed by
    // F = (0, f) at the body point c + (d, 0): the arm is R(θ)·(d, 0), and
    // τ = r⊥·F = d·f·cos θ. The force on the centre of mass is F at every angle.
    let (d, f) = (0.8, 3.0);
    let c = DVec2::new(0.5, -0.25);
    let spec = [ForceSpec::TimeVarying {
        f0: DVec2::new(0.0, f),
        f1: DVec2::ZERO,
        bodies: Selection::All,
        at: Some(c + DVec2::new(d, 0.0)),
    }];
    let system = System::rigid(vec![2.0], vec![0.3], vec![c], &spec);
    assert!(system.spins());
    for theta in [0.0, 0.4, std::f64::consts::FRAC_PI_2, 2.0, -2.7] {
        let mut state = State::new(0.0, vec![DVec2::new(1.0, 1.0)], vec![DVec2::ZERO]);
        state.angle[0] = theta;
        let (mut force, mut torque) = ([DVec2::NAN], [f64::NAN]);
        system.net_forces_and_torques(0.0, Coords::of(&state), &mut force, &mut torque);
        assert_eq!(force[0], DVec2::new(0.0, f));
        assert!(
            (torque[0] - d * f * theta.cos()).abs() <= 4.0 * f64::EPSILON * d * f,
            "θ = {theta}: τ = {}, expected {}",
            torque[0],
            d * f * theta.cos()
        );
        // α = τ/I, and a = F/m.
        let (mut acc, mut alpha) = ([DVec2::NAN], [f64::NAN]);
        system.derivatives(0.0, Coords::of(&state), &mut acc, &mut alpha);
        assert_eq!(acc[0], DVec2::new(0.0, f) * (1.0 / 2.0));
        assert_eq!(alpha[0], torque[0] * (1.0 / 0.3));
    }
}

/// Two bodies joined by a damped spring anchored off both centres of mass, spinning and
/// moving, with no external force: the case where the spring's torques matter.
fn two_bodies_on_an_anchored_spring(damping: f64) -> (System, State) {
    let spring = [ForceSpec::Spring {
        a: 0,
        b: Anchor::Body(1),
        stiffness: 40.0,
        rest_length: 0.5,
        damping,
        a_at: Some(DVec2::new(0.3, 0.1)),
        b_at: Some(DVec2::new(-0.2, 0.25)),
    }];
    let system = System::rigid(
        vec![1.5, 0.7],
        vec![0.2, 0.05],
        vec![DVec2::ZERO, DVec2::new(0.0, 0.05)],
        &spring,
    );
    let mut state = State::new(
        0.0,
        vec![DVec2::new(-0.4, 0.2), DVec2::new(0.6, -0.1)],
        vec![DVec2::new(0.3, -0.2), DVec2::new(-0.5, 0.9)],
    );
    state.angle = vec![0.3, -1.0];
    state.omega = vec![2.0, -3.0];
    (system, state)
}

#[test]
fn an_anchored_spring_conserves_linear_momentum_to_round_off() {
    // Equal and opposite forces: p = Σ m·v changes only by the rounding of each step's
    // sums, a few ulps of the momenta involved per step. With |m·v| ~ 1 and 2000
    // steps, 1e-12 absolute is well above that and far below any physical change.
    for &kind in IntegratorKind::ALL {
        let (system, state) = two_bodies_on_an_anchored_spring(0.3);
        let p0 = system.momentum(&state.vel);
        let mut sim = Simulation::new(system, state, kind, 0.001);
        let mut turned = 0.0f64;
        for _ in 0..2000 {
            sim.step().expect("finite");
            let p = sim.system().momentum(&sim.state().vel);
            assert!((p - p0).length() <= 1e-12, "{kind}: p - p0 = {}", p - p0);
            turned = turned.max((sim.state().omega[0] - 2.0).abs());
        }
        // The torques did change the spins: the test is not of a spring at the
        // centres of mass.
        assert!(turned > 0.1, "{kind}: ω barely changed ({turned})");
    }
}

#[test]
fn an_anchored_spring_conserves_angular_momentum_about_the_origin() {
    // rk4 at h = 1e-4 over 2 s: its truncation error in L is of order (h·ω_max)^4·L
    // per unit time, far below 1e-8 relative; round-off over 2·10^4 steps is ~1e-12.
    let (system, state) = two_bodies_on_an_anchored_spring(0.0);
    let origin = DVec2::ZERO;
    let l0 = system.angular_momentum(&state, origin);
    let e0 = system
        .mechanical_energy(&state)
        .expect("an undamped spring has energy");
    let mut sim = Simulation::new(system, state, IntegratorKind::Rk4, 1e-4);
    let mut spin_exchanged = 0.0f64;
    for k in 1..=20 {
        sim.advance_to(0.1 * f64::from(k)).expect("finite");
        let s = sim.state();
        let l = sim.system().angular_momentum(s, origin);
        assert_close(l, l0, 1e-8, "L about the origin");
        // About another point too: total momentum is conserved, so L about any fixed
        // point is.
        let p = DVec2::new(3.0, -2.0);
        let lp0 = l0 - perp_dot(p, sim.system().momentum(&s.vel));
        assert_close(sim.system().angular_momentum(s, p), lp0, 1e-8, "L about P");
        // Energy with the spin's share, ½·I·ω², is conserved too.
        let e = sim.system().mechanical_energy(s).expect("energy");
        assert_close(e, e0, 1e-8, "E");
        let inertia = sim.system().inertia().expect("rigid");
        spin_exchanged = spin_exchanged.max((inertia[0] * s.omega[0] - 0.2 * 2.0).abs());
    }
    assert!(
        spin_exchanged > 0.01 * l0.abs(),
        "the spring should move angular momentum between orbit and spin"
    );
}

#[test]
fn an_anchored_spring_pulls_its_end_towards_a_fixed_point() {
    // A box hanging at rest from a fixed point by a spring at its corner: its
    // equilibrium has the corner straight below the point and the centre of mass
    // straight below the corner, with the spring stretched by m·g/k. Damped in
    // translation (linear drag, the spring's damping) and rotation (angular drag),
    // rk4 settles there.
    let (m, w, h) = (2.0, 0.4, 0.2);
    let inertia = m * (w * w + h * h) / 12.0;
    let corner = DVec2::new(w / 2.0, h / 2.0);
    let (k, g) = (80.0, 9.81);
    let forces = [
        ForceSpec::Spring {
            a: 0,
            b: Anchor::Point(DVec2::new(0.0, 1.0)),
            stiffness: k,
            rest_length: 0.3,
            damping: 3.0,
            a_at: Some(corner),
            b_at: None,
        },
        ForceSpec::Gravity {
            g: DVec2::new(0.0, -g),
            bodies: Selection::All,
        },
        ForceSpec::AngularDrag {
            k: 0.05,
            bodies: Selection::All,
        },
        ForceSpec::Drag {
            k: 1.0,
            bodies: Selection::All,
        },
    ];
    let system = System::rigid(vec![m], vec![inertia], vec![DVec2::ZERO], &forces);
    let state = State::new(0.0, vec![DVec2::new(0.3, 0.5)], vec![DVec2::ZERO]);
    let mut sim = Simulation::new(system, state, IntegratorKind::Rk4, 1e-3);
    sim.advance_to(60.0).expect("finite");
    let s = sim.state();
    let end = s.pos[0] + rotate(s.angle[0].sin_cos(), corner);
    let stretch = m * g / k;
    assert!(
        (end - DVec2::new(0.0, 1.0 - 0.3 - stretch)).length() < 1e-6,
        "end at {end}"
    );
    // The centre of mass hangs straight below the corner: the arm points up.
    let arm = end - s.pos[0];
    assert!(arm.x.abs() < 1e-6, "arm {arm}");
    assert!(s.omega[0].abs() < 1e-6 && s.vel[0].length() < 1e-6);
}

/// A scene of one body, given as the `[[body]]` table's extra lines, with `forces`.
fn body_scene(body: &str, forces: &str) -> String {
    format!(
        r#"
        [simulation]
        dt = 0.01
        duration = 1.0
        [render]
        width = 64
        height = 64
        fps = 25
        view = {{ min = [-2.0, -2.0], max = [2.0, 2.0] }}
        [[body]]
        name = "b"
        position = [0.5, -0.25]
        {body}
        {forces}
        "#
    )
}

#[test]
fn every_shape_has_the_moment_of_inertia_of_its_formula_and_inertia_overrides_it() {
    for (body, expected) in [
        // Disc: M·r²/2.
        (
            "mass = 2.0\nshape = { circle = { radius = 0.5 } }",
            2.0 * 0.25 / 2.0,
        ),
        // Box: M·(w² + h²)/12.
        (
            "mass = 3.0\nshape = { box = { width = 1.0, height = 0.5 } }",
            3.0 * 1.25 / 12.0,
        ),
        // A right triangle with legs 3 and 1.5 about its centroid: M·(a² + b²)/18.
        (
            "mass = 1.5\nshape = { polygon = { points = [[0.0, 0.0], [3.0, 0.0], [0.0, 1.5]] } }",
            1.5 * (9.0 + 2.25) / 18.0,
        ),
        // Point masses 1 and 3, 2 apart: Σ mᵢ·|rᵢ - r_CM|² = 1·1.5² + 3·0.5².
        (
            "points = [{ offset = [-1.0, 0.0], mass = 1.0 }, { offset = [1.0, 0.0], mass = 3.0 }]",
            1.0 * 2.25 + 3.0 * 0.25,
        ),
        // An explicit moment of inertia wins.
        (
            "mass = 2.0\ninertia = 0.7\nshape = { circle = { radius = 0.5 } }",
            0.7,
        ),
    ] {
        let s = scene(&body_scene(body, ""));
        let i = s.bodies[0].inertia;
        assert!(
            (i - expected).abs() <= 1e-14 * expected,
            "{body}: I = {i}, expected {expected}"
        );
        assert_eq!(s.system().inertia(), Some(&[i][..]));
    }
}

#[test]
fn a_turned_body_starts_with_its_points_turned_about_its_origin() {
    // The triangle's centroid is c = (1, 0.5) in body coordinates. Turned by θ, its
    // centre of mass starts at position + R(θ)·c, and the vertex (3, 0) at
    // position + R(θ)·(3, 0).
    let theta = 0.7f64;
    let s = scene(&body_scene(
        &format!(
            "mass = 1.0\nangle = {theta}\nangular_velocity = -2.0\n\
             shape = {{ polygon = {{ points = [[0.0, 0.0], [3.0, 0.0], [0.0, 1.5]] }} }}"
        ),
        "",
    ));
    let b = &s.bodies[0];
    let start = DVec2::new(0.5, -0.25);
    let c = DVec2::new(1.0, 0.5);
    assert!((b.position - (start + rotate(theta.sin_cos(), c))).length() < 1e-15);
    assert_eq!(b.centre, c);
    assert_eq!((b.angle, b.angular_velocity), (theta, -2.0));
    assert!(b.turns, "a body that spins at the start turns");
    let state = s.initial_state();
    assert_eq!((state.angle[0], state.omega[0]), (theta, -2.0));
}

#[test]
fn a_swarm_draws_angles_and_spins_from_its_seed_within_their_ranges() {
    let swarm = |extra: &str| {
        format!(
            r#"
            [simulation]
            dt = 0.01
            duration = 0.2
            [render]
            fps = 25
            view = {{ min = [0.0, 0.0], max = [10.0, 10.0] }}
            [[swarm]]
            name = "dust"
            count = 200
            seed = 7
            mass = 1.0
            position = {{ min = [0.0, 0.0], max = [10.0, 10.0] }}
            velocity = {{ min = [-1.0, -1.0], max = [1.0, 1.0] }}
            shape = {{ box = {{ width = 0.2, height = 0.1 }} }}
            {extra}
            "#
        )
    };
    let plain = scene(&swarm(""));
    let spun = scene(&swarm(
        "angle = { min = -1.0, max = 1.0 }\nangular_velocity = { min = 2.0, max = 3.0 }",
    ));
    // The positions and velocities are the same bits with or without the new keys.
    for (a, b) in plain.bodies.iter().zip(&spun.bodies) {
        assert_eq!(a.position, b.position);
        assert_eq!(a.velocity, b.velocity);
        assert_eq!((a.angle, a.angular_velocity, a.turns), (0.0, 0.0, false));
        assert!((-1.0..1.0).contains(&b.angle), "{}", b.angle);
        assert!((2.0..3.0).contains(&b.angular_velocity));
        assert!(b.turns);
    }
    // Spread over their ranges, not all alike.
    let mean = spun.bodies.iter().map(|b| b.angle).sum::<f64>() / 200.0;
    assert!(mean.abs() < 0.15, "mean angle {mean}");
    let distinct = spun
        .bodies
        .windows(2)
        .filter(|w| w[0].angle != w[1].angle)
        .count();
    assert_eq!(distinct, 199);
    // Nothing turns the plain swarm: its system does no angular work.
    assert!(!plain.system().spins());
    let sim = plain.simulation();
    assert!(!sim.system().spins());
}

#[test]
fn export_writes_angles_and_spins_equal_to_the_simulation() {
    let text = std::fs::read_to_string(crate::util::example("spin.toml")).expect("example");
    let sandbox = crate::util::Sandbox::new();
    sandbox.write("spin.toml", &text);
    let out = sandbox.run(&["export", "spin.toml", "--out", "t.csv"]);
    assert_eq!(out.status.code(), Some(0), "{}", crate::util::stderr(&out));
    let csv = std::fs::read_to_string(sandbox.path("t.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("t,body,x,y,vx,vy,angle,omega"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let s = scene(&text);
    let mut sim = s.simulation();
    sim.run_steps(s.total_steps()).expect("finite");
    for (i, row) in rows[rows.len() - 2..].iter().enumerate() {
        let num = |j: usize| row[j].parse::<f64>().expect("a number");
        assert_eq!(num(6), sim.state().angle[i]);
        assert_eq!(num(7), sim.state().omega[i]);
    }
    // The box (I = 2·(1 + 0.25)/12) spins up at α = τ/I = 2.4 rad/s²: after n = 400
    // Euler steps of 0.01 s, ω = n·h·α = 9.6 and θ = h²·α·n(n-1)/2 = 19.152.
    let last_box = &rows[rows.len() - 2];
    let (theta, omega): (f64, f64) = (last_box[6].parse().unwrap(), last_box[7].parse().unwrap());
    assert!((omega - 9.6).abs() < 1e-12 * 9.6, "ω = {omega}");
    assert!((theta - 19.152).abs() < 1e-12 * 19.152, "θ = {theta}");
}

#[test]
fn a_spin_that_blows_up_stops_with_exit_3_naming_the_body_and_the_stable_step() {
    // Angular drag with k/I = 1000 and dt = 0.01: explicit Euler multiplies ω by
    // 1 - h·k/I = -9 each step. The energy, which counts ½·I·ω², grows tenfold within
    // steps, and the message names the body and the step that would be stable.
    let text = body_scene(
        "mass = 1.0\ninertia = 0.001\nangular_velocity = 1.0\nshape = { circle = { radius = 0.1 } }",
        "[[force]]\nkind = \"angular-drag\"\nk = 1.0",
    );
    let sandbox = crate::util::Sandbox::new();
    sandbox.write("spin.toml", &text);
    let out = sandbox.run(&["render", "spin.toml", "--out", "frames"]);
    let err = crate::util::stderr(&out);
    assert_eq!(out.status.code(), Some(3), "{err}");
    assert!(err.contains("body `b`"), "{err}");
    assert!(
        err.contains("angular drag with k/I = 1000 needs dt ≤ 2·I/k = 0.002"),
        "{err}"
    );
}
