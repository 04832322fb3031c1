//! The integrators against closed forms: convergence and observed orders, the exact
//! discrete solution of explicit Euler on drag, the bounded energy error of symplectic
//! Euler, dopri5's tolerance and output times, conservation of momentum, and every
//! force kind with every integrator.

use std::f64::consts::PI;

use glam::DVec2;
use physframes::sim::integrators::Tolerances;
use physframes::sim::{
    Anchor, Coords, ForceSpec, IntegratorKind, Selection, Simulation, State, System,
};
use physframes::study::{
    convergence, work_precision, write_csv, ConvergenceOptions, ReferenceKind, ReferenceProblem,
    WorkPrecisionOptions, CSV_HEADER,
};

use IntegratorKind::*;

/// Runs `problem` to its final time with `kind` (fixed step `h`, or at most `h` with
/// tolerances `tol` for dopri5) and returns the final simulation.
fn run(problem: &ReferenceProblem, kind: IntegratorKind, h: f64, tol: f64) -> Simulation {
    let mut sim = Simulation::new(problem.system().clone(), problem.initial().clone(), kind, h)
        .with_tolerances(Tolerances::both(tol));
    sim.advance_to(problem.t_end())
        .unwrap_or_else(|e| panic!("{kind} on {}: {e}", problem.name()));
    sim
}

#[test]
fn every_integrator_converges_on_every_reference_problem() {
    // From 320 to 2560 steps, the error must fall at every halving of h, unless it has
    // reached round-off (1e-11: several thousand ε for quantities of order 10, after up
    // to a few thousand steps), and the observed order of the finest pair must be at
    // least the nominal order less 0.15 (coarser pairs of explicit Euler on the orbit are
    // still approaching the asymptotic regime). The error at 2560 steps must be below a
    // bound for the order, about ten times what was measured on the worst problem (the
    // orbit): 1, 1e-4 and 1e-9 for orders 1, 2, and 4 or more.
    let options = ConvergenceOptions {
        coarsest_steps: 320,
        levels: 4,
        error_floor: 1e-11,
    };
    for &reference in ReferenceKind::ALL {
        let problem = reference.problem();
        let table = convergence(&problem, IntegratorKind::ALL, &options);
        for s in &table.series {
            let nominal = f64::from(s.nominal_order);
            for pair in s.rows.windows(2) {
                assert!(
                    pair[1].error < pair[0].error || pair[1].error <= options.error_floor,
                    "{} on {}: the error did not fall at {} steps\n{table}",
                    s.integrator,
                    problem.name(),
                    pair[1].steps
                );
            }
            if let Some(p) = s.final_order() {
                assert!(
                    p >= nominal - 0.15,
                    "{} on {}: final order {p:.3}, nominal {nominal}\n{table}",
                    s.integrator,
                    problem.name()
                );
            }
            let finest = s.rows.last().map_or(f64::NAN, |r| r.error);
            let bound = match s.nominal_order {
                1 => 1.0,
                2 => 1e-4,
                _ => 1e-9,
            };
            assert!(
                finest <= bound,
                "{} on {}: error {finest:.3e} > {bound:.0e} at 2560 steps\n{table}",
                s.integrator,
                problem.name()
            );
        }
    }
}

/// Asserts that every observed order of `kind` on `reference`, from `coarsest` steps
/// over `levels` levels, is within ±0.15 of the nominal order, and that at least
/// `min_orders` of them were measured (above the round-off floor of 1e-12).
fn check_order(
    reference: ReferenceKind,
    kind: IntegratorKind,
    coarsest: u64,
    levels: u32,
    min_orders: usize,
) {
    let problem = reference.problem();
    let options = ConvergenceOptions {
        coarsest_steps: coarsest,
        levels,
        error_floor: 1e-12,
    };
    let table = convergence(&problem, &[kind], &options);
    let series = &table.series[0];
    let orders = series.observed_orders();
    let nominal = f64::from(kind.order());
    assert!(
        orders.len() >= min_orders,
        "{kind} on {reference}: only {} orders measured\n{table}",
        orders.len()
    );
    for p in &orders {
        assert!(
            (p - nominal).abs() <= 0.15,
            "{kind} on {reference}: observed order {p:.3}, nominal {nominal}\n{table}"
        );
    }
}

#[test]
fn observed_orders_on_the_spring_are_within_0_15_of_nominal() {
    // The spring over 1¼ periods (period 1). Each method starts where its error is in
    // the asymptotic regime (explicit Euler's error grows by (1 + (ωh)²)^(n/2) per run,
    // so it needs the smallest steps) and stops before its error reaches 1e-12.
    check_order(ReferenceKind::Spring, Euler, 320, 7, 6);
    check_order(ReferenceKind::Spring, SymplecticEuler, 80, 8, 7);
    check_order(ReferenceKind::Spring, Midpoint, 20, 8, 7);
    check_order(ReferenceKind::Spring, Heun, 20, 8, 7);
    check_order(ReferenceKind::Spring, Rk4, 20, 7, 6);
    check_order(ReferenceKind::Spring, Verlet, 10, 8, 7);
    check_order(ReferenceKind::Spring, Dopri5, 80, 4, 2);
}

#[test]
fn observed_orders_on_the_turning_problems_are_within_0_15_of_nominal() {
    // The angle and angular velocity must take each method's stages: a Runge–Kutta
    // method that advanced them with an Euler step inside its stages would show order 1
    // here. Angular drag is smooth from the first step; the hanging box, whose swing and
    // spin are coupled through the spring, needs finer steps before explicit Euler and
    // the first stages of the others are in their asymptotic regime.
    for (kind, coarsest, levels, min_orders) in [
        (Euler, 20, 7, 6),
        (SymplecticEuler, 20, 7, 6),
        (Midpoint, 20, 7, 6),
        (Heun, 20, 7, 6),
        (Rk4, 20, 6, 4),
        (Verlet, 20, 7, 6),
        // Dopri5 is still above order 5 at 20 steps and at round-off from 160.
        (Dopri5, 40, 3, 1),
    ] {
        check_order(
            ReferenceKind::AngularDrag,
            kind,
            coarsest,
            levels,
            min_orders,
        );
    }
    for (kind, coarsest, levels, min_orders) in [
        (Euler, 640, 4, 3),
        (SymplecticEuler, 40, 6, 5),
        (Midpoint, 20, 7, 6),
        (Heun, 40, 6, 5),
        (Rk4, 40, 6, 5),
        (Verlet, 20, 7, 6),
    ] {
        check_order(
            ReferenceKind::HangingBox,
            kind,
            coarsest,
            levels,
            min_orders,
        );
    }
}

#[test]
fn velocity_verlet_stays_second_order_with_velocity_dependent_forces() {
    // Drag, drag with gravity, and a damped spring all depend on velocity; the predicted
    // end-of-step velocity keeps Verlet second order on each.
    check_order(ReferenceKind::Drag, Verlet, 10, 8, 7);
    check_order(ReferenceKind::DragGravity, Verlet, 10, 8, 7);
    check_order(ReferenceKind::DampedSpring, Verlet, 20, 7, 6);
}

#[test]
fn observed_orders_on_the_orbit_and_drag_are_within_0_15_of_nominal() {
    check_order(ReferenceKind::Orbit, Euler, 20_000, 4, 3);
    check_order(ReferenceKind::Orbit, SymplecticEuler, 1000, 5, 4);
    check_order(ReferenceKind::Orbit, Midpoint, 400, 5, 4);
    check_order(ReferenceKind::Orbit, Heun, 400, 5, 4);
    check_order(ReferenceKind::Orbit, Rk4, 400, 4, 3);
    check_order(ReferenceKind::Orbit, Verlet, 100, 6, 5);
    // Dopri5 reaches the round-off floor after two halvings on drag.
    for &kind in IntegratorKind::ALL {
        let min_orders = if kind == Dopri5 { 2 } else { 4 };
        check_order(ReferenceKind::Drag, kind, 20, 5, min_orders);
    }
}

#[test]
fn print_the_convergence_table_of_the_spring() {
    // `cargo test --test integrators print_the_convergence -- --nocapture` prints it.
    let problem = ReferenceKind::Spring.problem();
    let table = convergence(
        &problem,
        IntegratorKind::ALL,
        &ConvergenceOptions::default(),
    );
    println!("{table}");
    assert_eq!(table.series.len(), IntegratorKind::ALL.len());
    assert!(table.series.iter().all(|s| s.rows.len() == 8));
}

#[test]
fn explicit_euler_on_drag_equals_the_discrete_solution() {
    // Euler on dv/dt = -k·v/m multiplies v by (1 - h·k/m) every step, so v_n is
    // v0·(1 - h·k/m)^n up to the rounding of n products (n·ε ≈ 1e-14 relative for n = 40).
    let problem = ReferenceKind::Drag.problem();
    let (k, m) = (1.0, 2.0);
    for (h, n) in [(0.1, 40u64), (0.5, 8), (1.5, 4), (3.0, 3)] {
        let mut sim = Simulation::new(
            problem.system().clone(),
            problem.initial().clone(),
            Euler,
            h,
        );
        sim.run_steps(n).expect("finite");
        let factor = (1.0 - h * k / m).powi(n as i32);
        let expected = problem.initial().vel[0] * factor;
        let got = sim.state().vel[0];
        let rel = (got - expected).length() / expected.length().max(f64::MIN_POSITIVE);
        assert!(
            rel <= 1e-12,
            "h = {h}, n = {n}: v = {got}, expected {expected}"
        );
    }
}

#[test]
fn symplectic_euler_keeps_the_spring_energy_bounded_over_100000_steps() {
    // Symplectic Euler on x'' = -ω²x conserves H̃ = ½m|v|² + ½k|x|² - (h/2)·k·(x·v)
    // exactly (in exact arithmetic; the map is linear with that quadratic invariant), so
    // the true energy error stays O(h) for ever. Explicit Euler's grows without bound.
    let problem = ReferenceKind::Spring.problem();
    let (m, k) = (1.0, 4.0 * PI * PI);
    let centre = DVec2::new(0.5, -0.25);
    let h = 0.01;
    let energy = |s: &State| {
        let x = s.pos[0] - centre;
        0.5 * m * s.vel[0].length_squared() + 0.5 * k * x.length_squared()
    };
    let modified = |s: &State| energy(s) - 0.5 * h * k * (s.pos[0] - centre).dot(s.vel[0]);
    let mut sim = Simulation::new(
        problem.system().clone(),
        problem.initial().clone(),
        SymplecticEuler,
        h,
    );
    let (e0, m0) = (energy(sim.state()), modified(sim.state()));
    let mut worst_energy: f64 = 0.0;
    let mut worst_modified: f64 = 0.0;
    let mut worst_early: f64 = 0.0;
    for n in 0..100_000u64 {
        sim.step().expect("finite");
        let s = sim.state();
        let de = (energy(s) - e0).abs() / e0;
        worst_energy = worst_energy.max(de);
        if n < 1000 {
            worst_early = worst_early.max(de);
        }
        worst_modified = worst_modified.max((modified(s) - m0).abs() / m0);
    }
    // The energy error is bounded by about ωh = 0.063, and reached within the first ten
    // periods: it does not grow afterwards (1% slack for the envelope being sampled).
    assert!(worst_energy <= 2.0 * PI * h, "energy error {worst_energy}");
    assert!(
        worst_energy <= 1.01 * worst_early,
        "the energy error grew: {worst_early} early, {worst_energy} over the run"
    );
    // The modified energy is conserved up to round-off accumulated over 10⁵ steps.
    assert!(
        worst_modified <= 1e-10,
        "modified energy drift {worst_modified}"
    );

    // For contrast: explicit Euler gains energy by (1 + (ωh)²) per step.
    let mut euler = Simulation::new(
        problem.system().clone(),
        problem.initial().clone(),
        Euler,
        h,
    );
    euler.run_steps(1000).expect("finite");
    let growth = energy(euler.state()) / e0;
    let expected = (1.0 + (2.0 * PI * h).powi(2)).powi(1000);
    assert!(
        (growth / expected - 1.0).abs() < 1e-9,
        "{growth} vs {expected}"
    );
}

#[test]
fn dopri5_meets_its_tolerance_on_the_orbit_and_lands_on_every_frame_time() {
    // The controller bounds the error of each step (weighted by atol + rtol·|y|), not the
    // global error: over 3¼ periods (≈ 100–1000 steps) the local errors add up and the
    // orbit's phase drifts, and the measured position error is 64–164·tol for tolerances
    // 1e-7 to 1e-12. We allow 300·tol, and also require the error to fall with tol.
    let problem = ReferenceKind::Orbit.problem().with_t_end(3.25);
    let mut previous = f64::INFINITY;
    for tol in [1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12] {
        // Frames at 30 per unit of time, as the renderer asks for them.
        let mut sim = Simulation::new(
            problem.system().clone(),
            problem.initial().clone(),
            Dopri5,
            1.0,
        )
        .with_tolerances(Tolerances::both(tol));
        let mut worst: f64 = 0.0;
        for frame in 1..=(3.25f64 * 30.0) as u64 {
            let t = frame as f64 / 30.0;
            sim.advance_to(t).expect("finite");
            assert_eq!(sim.state().t, t, "dopri5 must land exactly on t = {t}");
            worst = worst.max(problem.position_error(sim.state()));
        }
        sim.advance_to(3.25).expect("finite");
        assert_eq!(sim.state().t, 3.25);
        worst = worst.max(problem.position_error(sim.state()));
        assert!(worst <= 300.0 * tol, "tol {tol:e}: error {worst:.3e}");

        // One call to the final time: landing on frames must not make the error worse
        // than without them by more than a factor of 1.5 (it is usually smaller, since
        // frames shorten the steps).
        let single = run(&problem, Dopri5, 1.0, tol);
        let single_error = problem.position_error(single.state());
        assert!(
            single_error <= 300.0 * tol,
            "tol {tol:e}: error {single_error:.3e}"
        );
        assert!(
            worst <= 1.5 * single_error.max(1e-3 * tol),
            "tol {tol:e}: frames {worst:.3e}, single run {single_error:.3e}"
        );
        assert!(single_error < previous, "error did not fall with tol");
        previous = single_error;
    }
}

#[test]
fn dopri5_counts_the_evaluations_of_rejected_steps() {
    // An orbit of eccentricity 0.9 (a tenth of the circular speed... squared, at apoapsis)
    // forces the controller to shrink steps sharply at periapsis, with rejections. The
    // count is 2 for the starting-step heuristic (its first slope is reused as the first
    // stage), then 6 for every attempted step, accepted or rejected (FSAL).
    let mu = 4.0 * PI * PI;
    let system = System::new(
        vec![1.0],
        &[ForceSpec::Central {
            centre: DVec2::ZERO,
            strength: mu,
            bodies: Selection::All,
        }],
    );
    let initial = State::new(
        0.0,
        vec![DVec2::new(1.0, 0.0)],
        vec![DVec2::new(0.0, (0.1 * mu).sqrt())],
    );
    let mut sim =
        Simulation::new(system, initial, Dopri5, 0.5).with_tolerances(Tolerances::both(1e-8));
    sim.advance_to(2.0).expect("finite");
    assert!(sim.rejected_steps() > 0, "no step was rejected");
    assert_eq!(
        sim.evaluations(),
        2 + 6 * (sim.steps() + sim.rejected_steps()),
        "{} steps, {} rejected",
        sim.steps(),
        sim.rejected_steps()
    );
}

#[test]
fn fixed_step_methods_count_their_evaluations() {
    // Verlet carries its end-of-step acceleration over when no force depends on
    // velocity (one evaluation per step plus the first), and pays two per step otherwise.
    for (reference, verlet) in [
        (ReferenceKind::Spring, 100 + 1),
        (ReferenceKind::Drag, 2 * 100),
    ] {
        let problem = reference.problem();
        for &kind in IntegratorKind::ALL.iter().filter(|k| !k.is_adaptive()) {
            let mut sim = Simulation::new(
                problem.system().clone(),
                problem.initial().clone(),
                kind,
                0.01,
            );
            sim.run_steps(100).expect("finite");
            let expected = if kind == Verlet {
                verlet
            } else {
                100 * u64::from(kind.evaluations_per_step())
            };
            assert_eq!(sim.evaluations(), expected, "{kind} on {reference}");
            assert_eq!(sim.steps(), 100);
        }
    }
}

/// Two bodies joined by a damped spring of positive rest length, and nothing else.
fn spring_pair() -> (System, State) {
    let system = System::new(
        vec![1.0, 3.0],
        &[ForceSpec::Spring {
            a: 0,
            b: Anchor::Body(1),
            stiffness: 50.0,
            rest_length: 0.5,
            damping: 0.7,
            a_at: None,
            b_at: None,
        }],
    );
    let initial = State::new(
        0.0,
        vec![DVec2::new(0.0, 0.0), DVec2::new(1.2, 0.3)],
        vec![DVec2::new(0.5, 2.0), DVec2::new(-1.0, 0.25)],
    );
    (system, initial)
}

#[test]
fn a_spring_between_two_bodies_keeps_total_momentum_for_every_integrator() {
    // Every stage applies F and -F to the two bodies, and every update is linear in the
    // stage accelerations, so Σ m·v changes only by rounding: ε·|p| ≈ 1e-16 per step,
    // a random walk of about 1e-15 over 1000 steps. We allow 1e-12.
    let (system, initial) = spring_pair();
    let p0 = system.momentum(&initial.vel);
    for &kind in IntegratorKind::ALL {
        let mut sim = Simulation::new(system.clone(), initial.clone(), kind, 0.01)
            .with_tolerances(Tolerances::both(1e-9));
        sim.advance_to(10.0).expect("finite");
        let drift = (system.momentum(&sim.state().vel) - p0).length();
        assert!(drift <= 1e-12, "{kind}: momentum drifted by {drift:e}");
    }
}

/// A scene with every force kind: three bodies, uniform gravity, linear drag on two,
/// quadratic drag, a force growing in time, a damped spring between two bodies and one
/// to a fixed point, both with positive rest length, and a central force.
fn every_force() -> Vec<ForceSpec> {
    vec![
        ForceSpec::Gravity {
            g: DVec2::new(0.0, -9.81),
            bodies: Selection::All,
        },
        ForceSpec::Drag {
            k: 0.3,
            bodies: Selection::Bodies(vec![0, 2]),
        },
        ForceSpec::QuadraticDrag {
            c: 0.05,
            bodies: Selection::All,
        },
        ForceSpec::TimeVarying {
            f0: DVec2::new(1.0, 0.0),
            f1: DVec2::new(0.0, 2.0),
            bodies: Selection::Bodies(vec![1]),
            at: None,
        },
        ForceSpec::Spring {
            a: 0,
            b: Anchor::Body(1),
            stiffness: 20.0,
            rest_length: 1.0,
            damping: 0.5,
            a_at: None,
            b_at: None,
        },
        ForceSpec::Spring {
            a: 2,
            b: Anchor::Point(DVec2::new(0.0, 3.0)),
            stiffness: 10.0,
            rest_length: 0.5,
            damping: 0.2,
            a_at: None,
            b_at: None,
        },
        ForceSpec::Central {
            centre: DVec2::new(0.0, -5.0),
            strength: 50.0,
            bodies: Selection::Bodies(vec![2]),
        },
    ]
}

#[test]
fn every_integrator_handles_every_force_kind() {
    // Each force alone, and all together, with every integrator at h = 1e-3 to t = 1,
    // against dopri5 at tolerance 1e-13. The run must finish with finite states, and agree
    // with the reference within a bound for the order: the global error is about C·h^p
    // with C of order 1–10 here, so 5e-2 for first order, 1e-4 for second, and 1e-8 for
    // fourth and fifth (whose errors are ~1e-12, below the reference's own ~1e-10).
    let initial = State::new(
        0.0,
        vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.5, 0.5),
            DVec2::new(2.0, 1.0),
        ],
        vec![
            DVec2::new(1.0, 2.0),
            DVec2::new(-0.5, 0.0),
            DVec2::new(0.0, -1.0),
        ],
    );
    let masses = vec![1.0, 2.0, 0.5];
    let all = every_force();
    let mut cases: Vec<(String, Vec<ForceSpec>)> = all
        .iter()
        .map(|f| (f.kind_name().to_string(), vec![f.clone()]))
        .collect();
    cases.push(("all forces".to_string(), all));
    for (label, forces) in &cases {
        let system = System::new(masses.clone(), forces);
        let mut reference = Simulation::new(system.clone(), initial.clone(), Dopri5, 0.01)
            .with_tolerances(Tolerances::both(1e-13));
        reference.advance_to(1.0).expect("finite");
        for &kind in IntegratorKind::ALL {
            let mut sim = Simulation::new(system.clone(), initial.clone(), kind, 1e-3)
                .with_tolerances(Tolerances::both(1e-10));
            sim.advance_to(1.0)
                .unwrap_or_else(|e| panic!("{kind} with {label}: {e}"));
            let s = sim.state();
            assert!(
                s.pos.iter().chain(&s.vel).all(|v| v.is_finite()),
                "{kind} with {label}: non-finite state"
            );
            let error = s
                .pos
                .iter()
                .zip(&reference.state().pos)
                .map(|(a, b)| (*a - *b).length())
                .fold(0.0, f64::max);
            let bound = match kind.order() {
                1 => 5e-2,
                2 => 1e-4,
                _ => 1e-8,
            };
            assert!(
                error <= bound,
                "{kind} with {label}: differs from the reference by {error:.3e}"
            );
        }
    }
}

#[test]
fn integrator_names_round_trip_and_unknown_names_are_rejected() {
    for &kind in IntegratorKind::ALL {
        assert_eq!(kind.name().parse::<IntegratorKind>(), Ok(kind));
    }
    let err = "rk5".parse::<IntegratorKind>().unwrap_err();
    assert!(
        err.contains("symplectic-euler") && err.contains("dopri5"),
        "{err}"
    );
    for &reference in ReferenceKind::ALL {
        assert_eq!(reference.name().parse::<ReferenceKind>(), Ok(reference));
    }
}

#[test]
fn the_closed_forms_match_the_article_and_their_own_derivatives() {
    // The article's own numbers: a = 5 gives r = 5/2·t² + v0·t + r0 (Equation 5).
    let ca = ReferenceKind::ConstantAcceleration.problem();
    let s = ca.exact(2.0);
    assert!((s.pos[0] - DVec2::new(0.5 * 5.0 * 4.0 + 2.0 * 2.0, 0.0)).length() < 1e-15);
    // Drag: v = v0·exp(-k·t/m), with k = 1, m = 2.
    let drag = ReferenceKind::Drag.problem();
    let v = drag.exact(1.0).vel[0];
    assert!((v - DVec2::new(3.0, -1.0) * (-0.5f64).exp()).length() < 1e-15);
    // Drag with gravity tends to the terminal velocity m·g/k = (0, -29.43).
    let dg = ReferenceKind::DragGravity.problem();
    assert!((dg.exact(200.0).vel[0] - DVec2::new(0.0, -29.43)).length() < 1e-9);
    // F = 2t on m = 2: v = v0 + t²/m.
    let tf = ReferenceKind::TimeForce.problem();
    assert!((tf.exact(2.0).vel[0] - DVec2::new(1.0 + 2.0, 0.5)).length() < 1e-15);
    // The circular orbit keeps its radius and speed.
    let orbit = ReferenceKind::Orbit.problem();
    let o = orbit.exact(0.3);
    assert!(((o.pos[0] - DVec2::new(0.5, 0.25)).length() - 1.0).abs() < 1e-15);
    assert!((o.vel[0].length() - 2.0 * PI).abs() < 1e-13);
    // Every closed form is consistent: dr/dt = v and dv/dt = a(t, r, v), checked by
    // central differences (error ~ (δ²)·|r'''| ≈ 1e-8 with δ = 1e-4, plus ε/δ ≈ 1e-12).
    for &reference in ReferenceKind::ALL {
        let p = reference.problem();
        let t = 0.37;
        let d = 1e-4;
        let (before, now, after) = (p.exact(t - d), p.exact(t), p.exact(t + d));
        let mut acc = vec![DVec2::ZERO; now.len()];
        let mut alpha = vec![0.0; now.len()];
        p.system()
            .derivatives(t, Coords::of(&now), &mut acc, &mut alpha);
        for (i, (v, a)) in now.vel.iter().zip(&acc).enumerate() {
            let dr = (after.pos[i] - before.pos[i]) / (2.0 * d);
            let dv = (after.vel[i] - before.vel[i]) / (2.0 * d);
            let scale = 1.0 + v.length() + a.length();
            assert!((dr - *v).length() < 1e-6 * scale, "{reference}: dr/dt");
            assert!((dv - *a).length() < 1e-6 * scale, "{reference}: dv/dt");
            // dθ/dt = ω and dω/dt = α = τ/I (both zero for a body that does not turn).
            let dtheta = (after.angle[i] - before.angle[i]) / (2.0 * d);
            let domega = (after.omega[i] - before.omega[i]) / (2.0 * d);
            let spin_scale = 1.0 + now.omega[i].abs() + alpha[i].abs();
            assert!(
                (dtheta - now.omega[i]).abs() < 1e-6 * spin_scale,
                "{reference}: dθ/dt"
            );
            assert!(
                (domega - alpha[i]).abs() < 1e-6 * spin_scale,
                "{reference}: dω/dt"
            );
        }
    }
}

#[test]
fn work_precision_rows_report_errors_that_fall_with_h_and_tolerance() {
    let problem = ReferenceKind::Spring.problem();
    let options = WorkPrecisionOptions {
        step_counts: vec![50, 100, 200],
        tolerances: vec![1e-4, 1e-6, 1e-8],
        min_sample_seconds: 1e-4,
        samples: 3,
    };
    let rows = work_precision(&problem, &[Rk4, Dopri5], &options);
    assert_eq!(rows.len(), 6);
    for pair in rows
        .windows(2)
        .filter(|w| w[0].integrator == w[1].integrator)
    {
        assert!(pair[1].error < pair[0].error, "{pair:?}");
        assert!(pair[1].evaluations > pair[0].evaluations, "{pair:?}");
    }
    for r in &rows {
        assert!(r.seconds > 0.0 && r.seconds.is_finite(), "{r:?}");
        if r.integrator == Rk4 {
            assert_eq!(r.evaluations, 4 * r.steps);
            assert!((r.h_or_tol * r.steps as f64 - problem.t_end()).abs() < 1e-12);
        }
    }
    let mut csv = Vec::new();
    write_csv(&rows, &mut csv).expect("writing to memory");
    let csv = String::from_utf8(csv).expect("utf-8");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER));
    let first: Vec<&str> = lines.next().expect("a row").split(',').collect();
    assert_eq!(first.len(), 6);
    assert_eq!(first[0], "rk4");
    assert_eq!(first[2], "50");
    assert_eq!(first[3], "200");
    assert_eq!(first[4].parse::<f64>().ok(), Some(rows[0].error));
}

#[test]
fn reset_reproduces_a_run_bit_for_bit() {
    let problem = ReferenceKind::Orbit.problem();
    for &kind in IntegratorKind::ALL {
        let mut sim = run(&problem, kind, 0.01, 1e-8);
        let first = sim.state().clone();
        let (steps, evaluations) = (sim.steps(), sim.evaluations());
        sim.reset(problem.initial());
        sim.advance_to(problem.t_end()).expect("finite");
        assert_eq!(sim.state(), &first, "{kind}");
        assert_eq!(
            (sim.steps(), sim.evaluations()),
            (steps, evaluations),
            "{kind}"
        );
    }
}

#[test]
fn every_integrator_reports_a_blow_up_instead_of_panicking() {
    // Quadratic drag on a speed of 1e160 is a force of 1e320, which overflows to
    // infinity: every method must stop with a BlowUp naming the body, and dopri5 must not
    // loop for ever shrinking its step (it accepts a step at the smallest size, and the
    // check after it reports the non-finite state).
    let system = System::new(
        vec![1.0, 1.0],
        &[ForceSpec::QuadraticDrag {
            c: 1.0,
            bodies: Selection::Bodies(vec![1]),
        }],
    );
    let initial = State::new(
        0.0,
        vec![DVec2::ZERO, DVec2::ZERO],
        vec![DVec2::new(1.0, 0.0), DVec2::new(1e160, 0.0)],
    );
    for &kind in IntegratorKind::ALL {
        let mut sim = Simulation::new(system.clone(), initial.clone(), kind, 0.01);
        let err = sim
            .advance_to(1.0)
            .expect_err(&format!("{kind} should blow up"));
        assert_eq!(err.body, 1, "{kind}: {err}");
        assert!(err.step >= 1, "{kind}: {err}");
    }
}
