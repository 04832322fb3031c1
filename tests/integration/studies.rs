//! The studies: stability boundaries found on the simulation against linear stability
//! theory, the energy of every integrator on the undamped spring against its closed
//! form or proven bound, and every `physframes study` subcommand run through the real
//! binary.

use std::f64::consts::PI;
use std::path::Path;

use glam::DVec2;
use physframes::sim::Tolerances;
use physframes::sim::{ForceSpec, IntegratorKind, Selection, Simulation, State, System};
use physframes::study::energy::{energy_bound, energy_study, EnergyOptions};
use physframes::study::stability::{
    growth, growth_at, stability, theory, Boundary, StabilityOptions, StabilityProblem,
};
use physframes::study::ReferenceKind;

use crate::util::{stderr, stdout, Sandbox};

use IntegratorKind::*;

/// The boundaries must agree with theory within 1%, as promised; in fact bisection to
/// 10⁻¹² on a growth factor measured to a few ε, with a stability threshold of
/// g ≤ 1 + 10⁻¹², lands within about 10⁻¹²/|dg/ds| of theory's root, so the tests also
/// hold every boundary to 10⁻⁸ (dopri5 on the spring, where dg/ds ≈ 5·10⁻⁴ at the
/// root, is the loosest at 2·10⁻⁹).
const PROMISED: f64 = 0.01;
const BISECTION: f64 = 1e-8;

fn check_boundary(problem: StabilityProblem, kind: IntegratorKind, found: Boundary, expected: f64) {
    let Boundary::At(s) = found else {
        panic!("{kind} on {problem}: no boundary found ({found:?}), theory {expected}");
    };
    let rel = (s - expected).abs() / expected;
    let message = format!(
        "{kind} on {problem}: found s = {s}, theory {expected}, relative difference {rel:e}"
    );
    assert!(rel < PROMISED, "{message}");
    assert!(rel < BISECTION, "{message}");
}

#[test]
fn drag_boundaries_and_sign_flips_match_linear_stability_theory() {
    let table = stability(
        StabilityProblem::Drag,
        IntegratorKind::ALL,
        &StabilityOptions::default(),
    );
    // Theory's values written out, so the test does not only compare the library with
    // itself: |1 - s| ≤ 1 (Euler, and symplectic Euler's velocity update), 1 - s + s²/2 ≤ 1
    // (midpoint, Heun, and Verlet's Heun velocity update on drag), RK4's real root of
    // s³ - 4s² + 12s - 24, and dopri5's |R(-s)| = 1.
    let expected = [
        (Euler, 2.0, Some(1.0)),
        (SymplecticEuler, 2.0, Some(1.0)),
        (Midpoint, 2.0, None),
        (Heun, 2.0, None),
        (Rk4, 2.785_293_563_405_28, None),
        (Verlet, 2.0, None),
        (Dopri5, 3.306_567_892_634_95, None),
    ];
    for (kind, boundary, flip) in expected {
        let row = table
            .rows
            .iter()
            .find(|r| r.integrator == kind)
            .expect("a row per integrator");
        check_boundary(StabilityProblem::Drag, kind, row.found, boundary);
        assert!((row.theory.boundary - boundary).abs() < 1e-12, "{kind}");
        match (flip, row.sign_flip_found) {
            (Some(f), Some(found)) => assert!(
                (found - f).abs() / f < PROMISED.min(BISECTION),
                "{kind}: v flips sign at {found}, theory {f}"
            ),
            (None, None) => {}
            (f, found) => panic!("{kind}: sign flip {found:?}, theory {f:?}"),
        }
        // The measured growth equals theory's |R(-s)| at every step of the sweep, to
        // round-off (a few ε per stage).
        assert!(row.max_growth_deviation < 1e-13, "{kind}: {row:?}");
    }
}

#[test]
fn spring_boundaries_match_linear_stability_theory() {
    let options = StabilityOptions::default();
    let table = stability(StabilityProblem::Spring, IntegratorKind::ALL, &options);
    let expected = [
        (SymplecticEuler, 2.0),
        (Verlet, 2.0),
        (Rk4, 2.0 * 2f64.sqrt()),
        // The first positive root of -1/1800 + u/1600 - u²/14400 + u³/360000 in u = s².
        (Dopri5, 0.997_189_008_632_8),
    ];
    for (kind, boundary) in expected {
        let row = table
            .rows
            .iter()
            .find(|r| r.integrator == kind)
            .expect("a row per integrator");
        check_boundary(StabilityProblem::Spring, kind, row.found, boundary);
        assert!(row.max_growth_deviation < 1e-13, "{kind}: {row:?}");
    }
    // Euler, midpoint and Heun are stable only at s = 0: theory says so, and the
    // measurement finds growth at every step of the sweep.
    for kind in [Euler, Midpoint, Heun] {
        let row = table
            .rows
            .iter()
            .find(|r| r.integrator == kind)
            .expect("a row per integrator");
        assert_eq!(row.found, Boundary::UnstableEverywhere, "{kind}");
        assert_eq!(theory(StabilityProblem::Spring, kind).boundary, 0.0);
    }
}

#[test]
fn euler_midpoint_and_heun_grow_on_the_spring_at_every_step_tried_exactly_as_theory_says() {
    for s in StabilityOptions::default().sweep() {
        let euler = growth(StabilityProblem::Spring, Euler, s);
        // Unstable: the spectral radius is above 1 at every step tried.
        assert!(euler.factor > 1.0, "euler at s = {s}: g = {}", euler.factor);
        // The energy of any state grows by exactly 1 + s² per step; one step's ratio is
        // computed to a few ε.
        let ratio = euler.energy_ratio.expect("the spring reports energy");
        let expected = 1.0 + s * s;
        assert!(
            (ratio / expected - 1.0).abs() < 1e-14,
            "euler at s = {s}: energy ×{ratio}, theory ×{expected}"
        );
        // ρ = (1 + s²)^(1/2) and, for the second-order pair, (1 + s⁴/4)^(1/2); at
        // s = 0.01 the latter is 1 + 1.25·10⁻⁹, still a thousand times the threshold.
        assert!((euler.factor / expected.sqrt() - 1.0).abs() < 1e-14);
        for kind in [Midpoint, Heun] {
            let g = growth(StabilityProblem::Spring, kind, s).factor;
            let expected = (1.0 + s.powi(4) / 4.0).sqrt();
            assert!(g > 1.0 + 1e-12, "{kind} at s = {s}: g = {g}");
            assert!((g / expected - 1.0).abs() < 1e-14, "{kind} at s = {s}");
        }
    }
}

#[test]
fn the_one_step_spectral_radius_is_the_long_run_growth_rate() {
    // The spring's state, started off an eigenvector, grows like ρⁿ times a constant c,
    // so |q_n|^(1/n) → ρ with an error of ln(c)/n: 2000 steps make that well under 1%.
    // For Runge–Kutta methods the map is ρ times a rotation, so the match is exact.
    let omega = 1.0;
    let system = System::new(
        vec![1.0],
        &[ForceSpec::Spring {
            a: 0,
            b: physframes::sim::Anchor::Point(DVec2::ZERO),
            stiffness: omega * omega,
            rest_length: 0.0,
            damping: 0.0,
            a_at: None,
            b_at: None,
        }],
    );
    for (kind, s) in [
        (Rk4, 2.5),
        (Rk4, 2.9),
        (Euler, 0.3),
        (SymplecticEuler, 2.2),
        (Verlet, 2.1),
    ] {
        let rho = growth(StabilityProblem::Spring, kind, s).factor;
        let state = State::new(0.0, vec![DVec2::new(0.3, 0.0)], vec![DVec2::new(0.4, 0.0)]);
        let norm = |st: &State| {
            (st.pos[0].length_squared() + st.vel[0].length_squared() / (omega * omega)).sqrt()
        };
        let mut sim = Simulation::new(system.clone(), state, kind, s / omega);
        // Every 50 steps the state is scaled back to norm 1 and its log growth added
        // up, so that 2000 steps neither overflow nor underflow.
        let mut log_growth = 0.0;
        for _ in 0..40 {
            let n0 = norm(sim.state());
            sim.run_steps(50).expect("finite over 50 steps");
            let n1 = norm(sim.state());
            log_growth += (n1 / n0).ln();
            let mut scaled = sim.state().clone();
            scaled.pos[0] /= n1;
            scaled.vel[0] /= n1;
            sim.reset(&scaled);
        }
        let rate = (log_growth / 2000.0).exp();
        assert!(
            (rate / rho - 1.0).abs() < 0.005,
            "{kind} at s = {s}: |q|^(1/n) = {rate}, one-step ρ = {rho}"
        );
    }
}

#[test]
fn the_growth_per_step_depends_on_h_times_stiffness_alone() {
    for &problem in StabilityProblem::ALL {
        for &kind in IntegratorKind::ALL {
            for s in [0.1, 1.5, 2.5, 4.0] {
                let a = growth_at(problem, kind, s / 8.0, 8.0).factor;
                let b = growth_at(problem, kind, s * 4.0, 0.25).factor;
                assert!(
                    (a / b - 1.0).abs() < 1e-12,
                    "{kind} on {problem} at s = {s}: {a} vs {b}"
                );
            }
        }
    }
}

#[test]
fn adaptive_dopri5_on_stiff_drag_holds_its_step_at_the_stability_limit() {
    // After the transient (v has decayed by e^-1000), accuracy no longer limits the
    // step: only stability does, so the controller hovers at h·k/m ≈ 3.3066 whatever
    // the tolerance. The README and the table quote this.
    let k = 1000.0;
    for tol in [1e-3, 1e-6, 1e-9] {
        let system = System::new(
            vec![1.0],
            &[ForceSpec::Drag {
                k,
                bodies: Selection::All,
            }],
        );
        let state = State::new(0.0, vec![DVec2::ZERO], vec![DVec2::new(1.0, 0.0)]);
        let mut sim =
            Simulation::new(system, state, Dopri5, 10.0).with_tolerances(Tolerances::both(tol));
        sim.advance_to(1.0).expect("finite");
        let (n0, t0) = (sim.steps(), sim.state().t);
        sim.advance_to(11.0).expect("finite");
        let mean_s = (sim.state().t - t0) / (sim.steps() - n0) as f64 * k;
        assert!(
            (mean_s / 3.306_567_892_634_95 - 1.0).abs() < PROMISED,
            "tol {tol}: mean h·k/m = {mean_s}"
        );
    }
}

/// The undamped reference spring (m = 1, ω = 2π about its centre) and its energy.
fn spring() -> (physframes::study::ReferenceProblem, f64, DVec2) {
    let problem = ReferenceKind::Spring.problem();
    let omega = problem.angular_frequency().expect("the spring is undamped");
    assert_eq!(omega, 2.0 * PI);
    (problem, omega, DVec2::new(0.5, -0.25))
}

/// ½m|v|² + ½k|x - c|² with m = 1, k = ω².
fn energy(omega: f64, centre: DVec2, s: &State) -> f64 {
    0.5 * s.vel[0].length_squared() + 0.5 * omega * omega * (s.pos[0] - centre).length_squared()
}

#[test]
fn runge_kutta_energies_follow_their_closed_forms_step_by_step() {
    // E_n = E0·(1 + δ)^n with δ = |R(is)|² - 1: s² for Euler, s⁴/4 for midpoint and
    // Heun, -s⁶/72 + s⁸/576 for RK4. Each step rounds the state by a few ε, so after n
    // steps the relative error is about n·ε; 10⁴ steps leave 10⁻¹² against the 10⁻⁹
    // asked. Euler's energy grows by 10¹⁷ over the run; the ratio is checked anyway.
    let (problem, omega, centre) = spring();
    let h = 0.01;
    let s = h * omega;
    for (kind, delta) in [
        (Euler, s * s),
        (Midpoint, s.powi(4) / 4.0),
        (Heun, s.powi(4) / 4.0),
        (Rk4, -s.powi(6) / 72.0 + s.powi(8) / 576.0),
    ] {
        let mut sim = Simulation::new(problem.system().clone(), problem.initial().clone(), kind, h);
        let e0 = energy(omega, centre, sim.state());
        let mut worst: f64 = 0.0;
        for n in 1..=10_000u32 {
            sim.step().expect("finite");
            let expected = e0 * (f64::from(n) * delta.ln_1p()).exp();
            worst = worst.max((energy(omega, centre, sim.state()) / expected - 1.0).abs());
        }
        assert!(worst < 1e-9, "{kind}: worst relative deviation {worst:e}");
    }
}

/// Runs `kind` for `steps` steps of h on the spring in a tight loop and returns the
/// largest |E - E0|/E0.
fn max_energy_error(kind: IntegratorKind, h: f64, steps: u32) -> f64 {
    let (problem, omega, centre) = spring();
    let mut sim = Simulation::new(problem.system().clone(), problem.initial().clone(), kind, h);
    let e0 = energy(omega, centre, sim.state());
    let mut worst: f64 = 0.0;
    for _ in 0..steps {
        sim.step().expect("finite");
        worst = worst.max((energy(omega, centre, sim.state()) - e0).abs());
    }
    worst / e0
}

#[test]
fn symplectic_euler_and_verlet_keep_the_energy_within_their_bounds_over_a_million_steps() {
    // 10⁶ steps of h = 0.01 are 10⁴ periods. The bounds are derived in
    // `study::energy::energy_bound` from each method's exactly conserved modified
    // energy: s/(1 - s/2) = O(hω) for symplectic Euler, (s²/4)/(1 - s²/4) = O((hω)²)
    // for Verlet. Round-off adds about √n·ε ≈ 10⁻¹³, far inside either. Each bound must
    // also be within a factor 4 of what is reached, so it says something.
    let (_, omega, _) = spring();
    let h = 0.01;
    let s = h * omega;
    for kind in [SymplecticEuler, Verlet] {
        let bound = energy_bound(kind, s).expect("a symplectic method");
        let worst = max_energy_error(kind, h, 1_000_000);
        assert!(
            worst <= bound && worst >= bound / 4.0,
            "{kind}: max |ΔE/E0| = {worst:e}, bound {bound:e}"
        );
    }
    // The orders differ: halving h halves symplectic Euler's band and quarters Verlet's.
    let se = max_energy_error(SymplecticEuler, h, 1000)
        / max_energy_error(SymplecticEuler, h / 2.0, 2000);
    let vv = max_energy_error(Verlet, h, 1000) / max_energy_error(Verlet, h / 2.0, 2000);
    assert!(
        (se - 2.0).abs() < 0.1 && (vv - 4.0).abs() < 0.2,
        "ratios {se}, {vv}"
    );
}

#[test]
fn the_energy_study_reports_theory_and_refuses_problems_without_energy() {
    let (problem, omega, _) = spring();
    let options = EnergyOptions {
        dt: 0.01,
        steps: 2000,
        max_rows: 100,
    };
    let study = energy_study(&problem, &[Euler, Verlet, Dopri5], &options)
        .expect("the spring conserves energy");
    let euler = &study.series[0];
    let expected = (1.0 + (0.01 * omega).powi(2)).powi(2000) - 1.0;
    assert!((euler.final_relative_error() / expected - 1.0).abs() < 1e-9);
    assert_eq!(euler.rows.len(), 100);
    assert_eq!(euler.rows.last().map(|r| r.step), Some(2000));
    // The rows' block maxima cover every step: their largest is the run's.
    let verlet = &study.series[1];
    let row_max = verlet
        .rows
        .iter()
        .map(|r| r.max_abs_relative_error)
        .fold(0.0, f64::max);
    assert_eq!(row_max, verlet.max_abs_relative_error);
    // dopri5 lands on the final time exactly.
    let dopri = &study.series[2];
    let t_last = dopri.rows.last().map_or(0.0, |r| r.t);
    assert!((t_last - 20.0).abs() < 1e-12, "{t_last}");
    let drag = ReferenceKind::Drag.problem();
    let err = energy_study(&drag, &[Euler], &options).expect_err("drag dissipates energy");
    assert!(err.contains("not conserved"), "{err}");
}

/// Returns the size and iTXt chunks of a PNG file.
fn png_info(path: &Path) -> ((u32, u32), Vec<(String, String)>) {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    let info = reader.info();
    let size = (info.width, info.height);
    let text = info
        .utf8_text
        .iter()
        .map(|c| (c.keyword.clone(), c.get_text().expect("text")))
        .collect();
    // Decode the pixels too: the file must be a whole image.
    let mut buf = vec![0; reader.output_buffer_size().expect("a size")];
    reader.next_frame(&mut buf).expect("the pixels decode");
    (size, text)
}

/// Checks that a PNG decodes at `size` and records the study, problem, integrators and
/// program version.
fn check_png(path: &Path, size: (u32, u32), study: &str, problem: &str, integrators: &str) {
    let (actual, text) = png_info(path);
    assert_eq!(actual, size, "{}", path.display());
    let get = |key: &str| {
        text.iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
            .unwrap_or_else(|| panic!("{}: no {key} chunk in {text:?}", path.display()))
    };
    assert_eq!(get("physframes:study"), study);
    assert_eq!(get("physframes:problem"), problem);
    assert_eq!(get("physframes:integrators"), integrators);
    assert_eq!(
        get("Software"),
        format!("physframes {}", env!("CARGO_PKG_VERSION"))
    );
}

/// Returns the first line of a text file.
fn header(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines().next().unwrap_or_default().to_string()
}

#[test]
fn study_convergence_prints_orders_and_writes_csv_and_png() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "study",
        "convergence",
        "--problem",
        "drag",
        "--integrator",
        "euler,rk4",
        "--levels",
        "4",
        "--out",
        "conv",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("convergence on `drag`") && text.contains("rk4"),
        "{text}"
    );
    assert_eq!(
        header(&sandbox.path("conv/convergence.csv")),
        "integrator,nominal_order,steps,h,error,observed_order"
    );
    // Two integrators of four levels each, after the header.
    let rows = std::fs::read_to_string(sandbox.path("conv/convergence.csv")).expect("csv");
    assert_eq!(rows.lines().count(), 9);
    check_png(
        &sandbox.path("conv/convergence.png"),
        (900, 640),
        "convergence",
        "drag",
        "euler,rk4",
    );
    // Without --out nothing is written.
    let out = sandbox.run(&[
        "study",
        "convergence",
        "--levels",
        "2",
        "--integrator",
        "heun",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(!sandbox.path("output").exists());
}

#[test]
fn study_work_precision_writes_csv_and_a_diagram_to_its_default_folder() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "study",
        "work-precision",
        "--integrator",
        "rk4,dopri5",
        "--levels",
        "2",
        "--samples",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let dir = sandbox.path("output/study/work-precision-spring");
    assert_eq!(
        header(&dir.join("work-precision.csv")),
        "integrator,h_or_tol,steps,evaluations,error,seconds"
    );
    // Two step sizes of rk4 and ten tolerances of dopri5.
    let rows = std::fs::read_to_string(dir.join("work-precision.csv")).expect("csv");
    assert_eq!(rows.lines().count(), 13);
    check_png(
        &dir.join("work-precision.png"),
        (900, 640),
        "work-precision",
        "spring",
        "rk4,dopri5",
    );
}

#[test]
fn study_stability_prints_the_table_and_writes_csv_and_heatmaps() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "study",
        "stability",
        "--problem",
        "spring",
        "--integrator",
        "euler,symplectic-euler",
        "--grid",
        "8",
        "--out",
        "st",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(
        text.contains("symplectic-euler    2.0000000000   2.0000000000"),
        "{text}"
    );
    assert!(
        text.contains("euler                   0 (none)       0 (none)"),
        "{text}"
    );
    assert_eq!(
        header(&sandbox.path("st/stability.csv")),
        "problem,integrator,boundary_found,boundary_theory,relative_difference,sign_flip_found,sign_flip_theory,max_growth_deviation,note"
    );
    assert_eq!(
        header(&sandbox.path("st/stability-grid.csv")),
        "problem,integrator,h,stiffness,s,growth"
    );
    let cells = std::fs::read_to_string(sandbox.path("st/stability-grid.csv")).expect("csv");
    assert_eq!(cells.lines().count(), 1 + 2 * 8 * 8);
    // Two panels of 400×380 beside a colour bar 190 wide, under a 64-pixel header.
    check_png(
        &sandbox.path("st/stability.png"),
        (2 * 400 + 190, 64 + 380),
        "stability",
        "spring",
        "euler,symplectic-euler",
    );
}

#[test]
fn study_energy_writes_csv_and_plot() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "study",
        "energy",
        "--problem",
        "spring",
        "--steps",
        "300",
        "--integrator",
        "euler,verlet",
        "--out",
        "en",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stdout(&out).contains("max ≤"), "{}", stdout(&out));
    assert_eq!(
        header(&sandbox.path("en/energy.csv")),
        "integrator,step,t,relative_energy_error,max_abs_relative_error"
    );
    let rows = std::fs::read_to_string(sandbox.path("en/energy.csv")).expect("csv");
    assert_eq!(rows.lines().count(), 1 + 2 * 300);
    check_png(
        &sandbox.path("en/energy.png"),
        (900, 640),
        "energy",
        "spring",
        "euler,verlet",
    );
}

#[test]
fn bad_study_flags_exit_2_with_a_message_and_write_nothing() {
    let cases: &[(&[&str], &str)] = &[
        (
            &["study", "convergence", "--problem", "pendulum"],
            "unknown reference problem `pendulum`",
        ),
        (
            &["study", "convergence", "--integrator", "euler,rk5"],
            "unknown integrator `rk5`",
        ),
        (
            &["study", "convergence", "--levels", "0"],
            "--levels 0 is out of range",
        ),
        (
            &[
                "study",
                "work-precision",
                "--integrator",
                "euler,",
                "--out",
                "x",
            ],
            "empty name",
        ),
        (
            &["study", "stability", "--problem", "orbit", "--out", "x"],
            "`drag` or `spring`, not `orbit`",
        ),
        (
            &[
                "study",
                "stability",
                "--problem",
                "drag",
                "--grid",
                "1",
                "--out",
                "x",
            ],
            "--grid 1",
        ),
        (&["study", "stability", "--out", "x"], "--problem"),
        (
            &[
                "study",
                "energy",
                "--problem",
                "drag",
                "--steps",
                "10",
                "--out",
                "x",
            ],
            "not conserved",
        ),
        (
            &[
                "study", "energy", "--steps", "10", "--dt", "-1", "--out", "x",
            ],
            "--dt",
        ),
        (&["study", "energy", "--out", "x"], "--steps"),
    ];
    for (args, message) in cases {
        let sandbox = Sandbox::new();
        let out = sandbox.run(args);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        assert!(stderr(&out).contains(message), "{args:?}: {}", stderr(&out));
        assert!(
            sandbox.list(".").is_empty(),
            "{args:?} wrote {:?}",
            sandbox.list(".")
        );
    }
}
