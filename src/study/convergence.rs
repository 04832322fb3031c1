//! Convergence study: halve the step, measure the error at the final time against the
//! closed form, and estimate the order of each integrator.

use std::fmt;
use std::io::{self, Write};

use crate::sim::{IntegratorKind, Stepper};

use super::reference::{ReferenceKind, ReferenceProblem};

/// The header of the CSV that [`write_csv`] writes.
pub const CSV_HEADER: &str = "integrator,nominal_order,steps,h,error,observed_order";

/// How a convergence study chooses its steps.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceOptions {
    /// The number of steps at the coarsest level; h = t_end / steps.
    pub coarsest_steps: u64,
    /// The number of levels; each halves h (doubles the steps) of the one before.
    pub levels: u32,
    /// Errors at or below this are taken as round-off: no order is estimated from them.
    pub error_floor: f64,
}

impl Default for ConvergenceOptions {
    /// Ten steps at the coarsest level, eight levels (10 … 1280 steps), and a floor of
    /// 10⁻¹² (a thousand times ε for quantities of order 1, where round-off starts to
    /// dominate the error of a run of a thousand steps).
    fn default() -> Self {
        ConvergenceOptions {
            coarsest_steps: 10,
            levels: 8,
            error_floor: 1e-12,
        }
    }
}

/// One run of a convergence study.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceRow {
    /// The number of steps.
    pub steps: u64,
    /// The step size h = t_end / steps.
    pub h: f64,
    /// The largest, over the bodies, of the position error |r - r_exact| (and, for a
    /// problem whose bodies turn, of the angle error |θ - θ_exact|) at the final time
    /// (infinite when the run blew up).
    pub error: f64,
    /// log2(e_prev / e) against the level before, when both errors are finite and above
    /// the floor.
    pub observed_order: Option<f64>,
}

/// The runs of one integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceSeries {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Its nominal order.
    pub nominal_order: u32,
    /// One row per level, coarsest first.
    pub rows: Vec<ConvergenceRow>,
}

impl ConvergenceSeries {
    /// Returns every observed order, coarsest pair first.
    pub fn observed_orders(&self) -> Vec<f64> {
        self.rows.iter().filter_map(|r| r.observed_order).collect()
    }

    /// Returns the observed order of the finest pair of levels above the error floor.
    pub fn final_order(&self) -> Option<f64> {
        self.rows.iter().rev().find_map(|r| r.observed_order)
    }
}

/// The result of a convergence study.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceTable {
    /// The reference problem's name.
    pub problem: &'static str,
    /// The reference problem.
    pub kind: ReferenceKind,
    /// The final time.
    pub t_end: f64,
    /// The error floor the orders ignore.
    pub error_floor: f64,
    /// One series per integrator, in the order asked.
    pub series: Vec<ConvergenceSeries>,
}

/// Runs every integrator on `problem` from t = 0 to `problem.t_end()` with
/// `coarsest_steps · 2^k` fixed steps for each level k, and measures the position error
/// at the final time.
///
/// Every method takes fixed steps here, dopri5 included (its fifth-order solution,
/// without error control), so that each level has exactly the h it names.
pub fn convergence(
    problem: &ReferenceProblem,
    integrators: &[IntegratorKind],
    options: &ConvergenceOptions,
) -> ConvergenceTable {
    let series = integrators
        .iter()
        .map(|&kind| {
            let mut rows: Vec<ConvergenceRow> = Vec::with_capacity(options.levels as usize);
            for level in 0..options.levels {
                let steps = options.coarsest_steps.max(1) << level;
                let (h, error) = run_fixed(problem, kind, steps);
                let observed_order = rows.last().and_then(|prev| {
                    let usable = |e: f64| e.is_finite() && e > options.error_floor;
                    (usable(prev.error) && usable(error)).then(|| (prev.error / error).log2())
                });
                rows.push(ConvergenceRow {
                    steps,
                    h,
                    error,
                    observed_order,
                });
            }
            ConvergenceSeries {
                integrator: kind,
                nominal_order: kind.order(),
                rows,
            }
        })
        .collect();
    ConvergenceTable {
        problem: problem.name(),
        kind: problem.kind(),
        t_end: problem.t_end(),
        error_floor: options.error_floor,
        series,
    }
}

/// Integrates `problem` with `steps` fixed steps of `kind`; returns h and the final
/// position error (infinite if the state stopped being finite).
fn run_fixed(problem: &ReferenceProblem, kind: IntegratorKind, steps: u64) -> (f64, f64) {
    let system = problem.system();
    let mut state = problem.initial().clone();
    let t0 = state.t;
    let h = (problem.t_end() - t0) / steps as f64;
    let mut stepper = Stepper::new(kind, system);
    for n in 0..steps {
        // t_n = t0 + n·h, as the simulation computes it.
        state.t = t0 + n as f64 * h;
        stepper.step(system, h, &mut state);
    }
    state.t = problem.t_end();
    (h, problem.position_error(&state))
}

/// Writes the table as CSV with the header [`CSV_HEADER`], one row per run, in full
/// precision; the observed order is empty where none was estimated.
pub fn write_csv<W: Write>(table: &ConvergenceTable, mut out: W) -> io::Result<()> {
    writeln!(out, "{CSV_HEADER}")?;
    for s in &table.series {
        for r in &s.rows {
            let order = r.observed_order.map_or_else(String::new, |p| p.to_string());
            writeln!(
                out,
                "{},{},{},{:e},{:e},{}",
                s.integrator, s.nominal_order, r.steps, r.h, r.error, order
            )?;
        }
    }
    out.flush()
}

impl fmt::Display for ConvergenceTable {
    /// Writes one block per integrator: steps, h, error and the observed order against
    /// the level above, then the order of the finest pair.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "convergence on `{}` to t = {}: error = {} at the final time",
            self.problem,
            self.t_end,
            self.kind.error_measure()
        )?;
        writeln!(
            f,
            "(orders are log2 of successive error ratios; errors at or below {:.0e} are not used)",
            self.error_floor
        )?;
        for s in &self.series {
            writeln!(f)?;
            writeln!(f, "{} (nominal order {})", s.integrator, s.nominal_order)?;
            writeln!(
                f,
                "{:>8}  {:>10}  {:>10}  {:>8}",
                "steps", "h", "error", "order"
            )?;
            for r in &s.rows {
                let order = r
                    .observed_order
                    .map_or_else(|| "-".to_string(), |p| format!("{p:.3}"));
                writeln!(
                    f,
                    "{:>8}  {:>10.3e}  {:>10.3e}  {:>8}",
                    r.steps, r.h, r.error, order
                )?;
            }
        }
        writeln!(f)?;
        writeln!(f, "{:<18} {:>7} {:>9}", "integrator", "nominal", "observed")?;
        for s in &self.series {
            let observed = s
                .final_order()
                .map_or_else(|| "-".to_string(), |p| format!("{p:.3}"));
            writeln!(
                f,
                "{:<18} {:>7} {:>9}",
                s.integrator.name(),
                s.nominal_order,
                observed
            )?;
        }
        Ok(())
    }
}
