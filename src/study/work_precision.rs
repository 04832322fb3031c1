//! Work-precision study: for each integrator and each step size (or tolerance), the
//! error at the final time against the time and the force evaluations it cost.
//!
//! As in DifferentialEquations.jl's benchmarks, the error comes from one untimed run,
//! and the cost from repeated timed runs: each sample runs the integration as many times
//! as it takes to last at least `min_sample_seconds` (so that the clock's resolution and
//! the cost of reading it vanish), and the time reported is the median over samples of
//! the time per run (so that a sample disturbed by another process does not count).

use std::fmt::Write as _;
use std::hint::black_box;
use std::io::{self, Write};
use std::time::Instant;

use crate::sim::integrators::Tolerances;
use crate::sim::{IntegratorKind, Simulation};

use super::reference::ReferenceProblem;

/// The header of the CSV that [`write_csv`] writes.
pub const CSV_HEADER: &str = "integrator,h_or_tol,steps,evaluations,error,seconds";

/// What a work-precision study runs, and how it times it.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecisionOptions {
    /// For the fixed-step methods: the numbers of steps n, with h = t_end / n.
    pub step_counts: Vec<u64>,
    /// For the adaptive methods: the tolerances, with rtol = atol = tol.
    pub tolerances: Vec<f64>,
    /// The shortest time one timed sample may last, in seconds.
    pub min_sample_seconds: f64,
    /// The number of timed samples whose median is reported.
    pub samples: usize,
}

impl Default for WorkPrecisionOptions {
    /// Ten steps doubled seven times (10 … 1280), tolerances 10⁻³ … 10⁻¹², samples of
    /// at least 10 ms, and the median of 5.
    fn default() -> Self {
        WorkPrecisionOptions {
            step_counts: (0..8).map(|k| 10u64 << k).collect(),
            tolerances: (3..=12).map(|k| 10f64.powi(-k)).collect(),
            min_sample_seconds: 0.01,
            samples: 5,
        }
    }
}

/// One point of a work-precision diagram.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPrecisionRow {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// The step size h for a fixed-step method, the tolerance for an adaptive one.
    pub h_or_tol: f64,
    /// The steps taken (accepted steps for an adaptive method).
    pub steps: u64,
    /// The force evaluations, rejected steps included.
    pub evaluations: u64,
    /// The largest, over the bodies, of |r - r_exact| at the final time (infinite when
    /// the run blew up).
    pub error: f64,
    /// The median wall-clock time of one run, in seconds.
    pub seconds: f64,
}

/// Runs every integrator on `problem` from t = 0 to `problem.t_end()`: fixed-step
/// methods once per step count, adaptive ones once per tolerance (with the whole
/// interval as the largest step). Runs go through [`Simulation::advance_to`], the path
/// the renderer uses.
pub fn work_precision(
    problem: &ReferenceProblem,
    integrators: &[IntegratorKind],
    options: &WorkPrecisionOptions,
) -> Vec<WorkPrecisionRow> {
    let span = problem.t_end() - problem.initial().t;
    let mut rows = Vec::new();
    for &kind in integrators {
        if kind.is_adaptive() {
            for &tol in &options.tolerances {
                let sim = Simulation::new(
                    problem.system().clone(),
                    problem.initial().clone(),
                    kind,
                    span,
                )
                .with_tolerances(Tolerances::both(tol));
                rows.push(measure(problem, sim, tol, options));
            }
        } else {
            for &n in &options.step_counts {
                let h = span / n.max(1) as f64;
                let sim =
                    Simulation::new(problem.system().clone(), problem.initial().clone(), kind, h);
                rows.push(measure(problem, sim, h, options));
            }
        }
    }
    rows
}

/// Measures one setting: the error and counts from an untimed run, then the median time.
fn measure(
    problem: &ReferenceProblem,
    mut sim: Simulation,
    h_or_tol: f64,
    options: &WorkPrecisionOptions,
) -> WorkPrecisionRow {
    let t_end = problem.t_end();
    let initial = problem.initial();
    let error = match sim.advance_to(t_end) {
        Ok(()) => problem.position_error(sim.state()),
        Err(_) => f64::INFINITY,
    };
    let (steps, evaluations) = (sim.steps(), sim.evaluations());

    // One run, reusing the simulation's buffers: no allocation inside the timed loop.
    let run = |sim: &mut Simulation| {
        sim.reset(initial);
        // A blow-up ends the run early; its time is still the cost of that setting.
        let _ = black_box(sim.advance_to(black_box(t_end)));
    };
    // Double the batch until one batch lasts at least the minimum sample time.
    let mut batch: u64 = 1;
    loop {
        let start = Instant::now();
        for _ in 0..batch {
            run(&mut sim);
        }
        if start.elapsed().as_secs_f64() >= options.min_sample_seconds || batch >= 1 << 40 {
            break;
        }
        batch *= 2;
    }
    let mut per_run: Vec<f64> = (0..options.samples.max(1))
        .map(|_| {
            let start = Instant::now();
            for _ in 0..batch {
                run(&mut sim);
            }
            start.elapsed().as_secs_f64() / batch as f64
        })
        .collect();
    per_run.sort_by(f64::total_cmp);
    let seconds = per_run[per_run.len() / 2];

    WorkPrecisionRow {
        integrator: sim.integrator(),
        h_or_tol,
        steps,
        evaluations,
        error,
        seconds,
    }
}

/// Writes the rows as CSV, with the header [`CSV_HEADER`]. Numbers are written in full
/// precision (Rust's shortest round-trip form), so the file reads back exactly.
pub fn write_csv<W: Write>(rows: &[WorkPrecisionRow], mut out: W) -> io::Result<()> {
    writeln!(out, "{CSV_HEADER}")?;
    for r in rows {
        writeln!(
            out,
            "{},{:e},{},{},{:e},{:e}",
            r.integrator, r.h_or_tol, r.steps, r.evaluations, r.error, r.seconds
        )?;
    }
    out.flush()
}

/// Returns a plain-text table of the rows, one line per setting.
pub fn format_summary(rows: &[WorkPrecisionRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{:<18} {:>10} {:>8} {:>11} {:>10} {:>11}",
        "integrator", "h_or_tol", "steps", "evaluations", "error", "seconds"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "{:<18} {:>10.3e} {:>8} {:>11} {:>10.3e} {:>11.3e}",
            r.integrator.name(),
            r.h_or_tol,
            r.steps,
            r.evaluations,
            r.error,
            r.seconds
        );
    }
    s
}
