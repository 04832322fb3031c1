//! Energy study: the relative energy error E(t)/E0 - 1 of each integrator on a
//! conservative reference problem, step after step.
//!
//! On the undamped spring every number here has a closed form. Write s = h·ω. A
//! Runge–Kutta method maps the scaled state q = (x, v/ω) of each coordinate by R(hA),
//! where A = ω·[[0, 1], [-1, 0]] generates rotations; R(hA) is then |R(is)| times a
//! rotation, and since E = ½m·ω²·|q|², every step multiplies the energy by exactly
//! |R(is)|²:
//!
//! - explicit Euler: |1 + is|² = 1 + s², so E_n = E0·(1 + s²)^n, growing without bound;
//! - midpoint and Heun: |1 + is - s²/2|² = 1 + s⁴/4, growing more slowly;
//! - RK4: 1 - s⁶/72 + s⁸/576, decaying slowly for s < 2√2.
//!
//! The symplectic methods conserve a modified energy instead, so their true energy
//! error oscillates within a band that does not grow with n (see [`energy_bound`]).

use std::fmt;
use std::io::{self, Write};

use crate::sim::integrators::Tolerances;
use crate::sim::{IntegratorKind, Simulation, State, System};

use super::reference::ReferenceProblem;

/// The header of the CSV that [`write_csv`] writes.
pub const CSV_HEADER: &str = "integrator,step,t,relative_energy_error,max_abs_relative_error";

/// What an energy study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyOptions {
    /// The step h (for dopri5, the largest step allowed).
    pub dt: f64,
    /// The number of steps N; the run ends at t = N·h.
    pub steps: u64,
    /// At most this many rows per integrator; each row also carries the largest
    /// |ΔE/E0| since the row before, so nothing between rows is lost.
    pub max_rows: usize,
}

impl Default for EnergyOptions {
    /// h = 0.01 (h·ω = 0.063 on the spring, 100 steps a period), 10 000 steps and at
    /// most 1000 rows per integrator.
    fn default() -> Self {
        EnergyOptions {
            dt: 0.01,
            steps: 10_000,
            max_rows: 1000,
        }
    }
}

/// One sampled point of an energy series.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnergyRow {
    /// Steps taken so far (accepted steps for dopri5).
    pub step: u64,
    /// The time.
    pub t: f64,
    /// (E - E0)/E0 at this step.
    pub relative_error: f64,
    /// The largest |E - E0|/E0 over the steps since the row before (this one included).
    pub max_abs_relative_error: f64,
}

/// The energy error of one integrator over the run.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergySeries {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// The sampled rows, first at the first sample time, last at the end of the run.
    pub rows: Vec<EnergyRow>,
    /// The largest |E - E0|/E0 over every step of the run.
    pub max_abs_relative_error: f64,
    /// The steps taken.
    pub steps: u64,
    /// Why the run stopped early, when it did (the energy overflowed, or the state
    /// stopped being finite).
    pub stopped: Option<String>,
}

impl EnergySeries {
    /// Returns (E - E0)/E0 at the last row.
    pub fn final_relative_error(&self) -> f64 {
        self.rows.last().map_or(0.0, |r| r.relative_error)
    }
}

/// The result of an energy study.
#[derive(Clone, Debug, PartialEq)]
pub struct EnergyStudy {
    /// The reference problem's name.
    pub problem: &'static str,
    /// ω when the problem is the undamped spring, for the closed forms.
    pub omega: Option<f64>,
    /// The settings.
    pub options: EnergyOptions,
    /// The energy at t = 0.
    pub e0: f64,
    /// One series per integrator, in the order asked.
    pub series: Vec<EnergySeries>,
}

/// Returns the total energy, kinetic plus potential, or `None` when some force has no
/// potential (drag, forces that change in time).
pub fn total_energy(system: &System, state: &State) -> Option<f64> {
    let potential = system.potential_energy(state)?;
    Some(system.kinetic_energy(state) + potential)
}

/// Runs every integrator on `problem` for `options.steps` steps of `options.dt` and
/// records the relative energy error after every step.
///
/// dopri5 runs adaptively with steps of at most h (default tolerances) to the same final
/// time N·h, landing exactly on each sample time, so its rows are at those times.
///
/// Fails when the problem's forces have no potential energy, or its energy is zero.
pub fn energy_study(
    problem: &ReferenceProblem,
    integrators: &[IntegratorKind],
    options: &EnergyOptions,
) -> Result<EnergyStudy, String> {
    let e0 = total_energy(problem.system(), problem.initial()).ok_or_else(|| {
        format!(
            "the problem `{}` has a force without potential energy (drag or a force that changes in time), so its energy is not conserved; try spring, orbit or constant-acceleration",
            problem.name()
        )
    })?;
    if !(e0.is_finite() && e0 != 0.0) {
        return Err(format!(
            "the energy of `{}` at t = 0 is {e0}, so a relative error is undefined",
            problem.name()
        ));
    }
    let series = integrators
        .iter()
        .map(|&kind| run_series(problem, kind, options, e0))
        .collect();
    Ok(EnergyStudy {
        problem: problem.name(),
        omega: problem.angular_frequency(),
        options: options.clone(),
        e0,
        series,
    })
}

/// Runs one integrator and samples its relative energy error.
fn run_series(
    problem: &ReferenceProblem,
    kind: IntegratorKind,
    options: &EnergyOptions,
    e0: f64,
) -> EnergySeries {
    let h = options.dt;
    let n = options.steps.max(1);
    let rows_wanted = (options.max_rows.max(1) as u64).min(n);
    // Each row closes a block of about n/rows steps.
    let per_row = n.div_ceil(rows_wanted);
    let mut sim = Simulation::new(problem.system().clone(), problem.initial().clone(), kind, h)
        .with_tolerances(Tolerances::default());
    let mut rows = Vec::with_capacity(rows_wanted as usize + 1);
    let mut worst: f64 = 0.0;
    let mut block_worst: f64 = 0.0;
    let mut stopped = None;
    let relative = |sim: &Simulation| {
        total_energy(sim.system(), sim.state()).map_or(f64::NAN, |e| (e - e0) / e0)
    };
    if kind.is_adaptive() {
        // Sample times j·T/rows, each landed on exactly.
        let t_end = n as f64 * h;
        for j in 1..=rows_wanted {
            let t = t_end * j as f64 / rows_wanted as f64;
            if let Err(e) = sim.advance_to(t) {
                stopped = Some(e.to_string());
                break;
            }
            let rel = relative(&sim);
            if !rel.is_finite() {
                stopped = Some(format!("the energy overflowed at t = {}", sim.state().t));
                break;
            }
            worst = worst.max(rel.abs());
            rows.push(EnergyRow {
                step: sim.steps(),
                t: sim.state().t,
                relative_error: rel,
                max_abs_relative_error: rel.abs(),
            });
        }
    } else {
        for step in 1..=n {
            if let Err(e) = sim.step() {
                stopped = Some(e.to_string());
                break;
            }
            let rel = relative(&sim);
            if !rel.is_finite() {
                stopped = Some(format!(
                    "the energy overflowed at step {step} (t = {})",
                    sim.state().t
                ));
                break;
            }
            block_worst = block_worst.max(rel.abs());
            if step % per_row == 0 || step == n {
                worst = worst.max(block_worst);
                rows.push(EnergyRow {
                    step,
                    t: sim.state().t,
                    relative_error: rel,
                    max_abs_relative_error: block_worst,
                });
                block_worst = 0.0;
            }
        }
        worst = worst.max(block_worst);
    }
    EnergySeries {
        integrator: kind,
        rows,
        max_abs_relative_error: worst,
        steps: sim.steps(),
        stopped,
    }
}

/// What theory says about the energy of `kind` on an undamped spring after `n` steps
/// of s = h·ω.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EnergyTheory {
    /// A Runge–Kutta method: (E_n - E0)/E0 = |R(is)|^(2n) - 1 exactly.
    Exact(f64),
    /// A symplectic method: |E_n - E0|/E0 stays at most this bound for every n.
    Bound(f64),
}

/// Returns theory's energy error of `kind` on an undamped spring after `n` fixed steps
/// of s = h·ω, or `None` for dopri5 (adaptive, so its steps are not all s).
pub fn spring_energy_theory(kind: IntegratorKind, s: f64, n: u64) -> Option<EnergyTheory> {
    use IntegratorKind::*;
    let s2 = s * s;
    // δ = |R(is)|² - 1, written without cancellation for small s.
    let delta = match kind {
        Euler => s2,
        Midpoint | Heun => s2 * s2 / 4.0,
        Rk4 => -s2 * s2 * s2 / 72.0 + s2 * s2 * s2 * s2 / 576.0,
        SymplecticEuler | Verlet => return energy_bound(kind, s).map(EnergyTheory::Bound),
        Dopri5 => return None,
    };
    // (1 + δ)^n - 1 = exp(n·ln(1 + δ)) - 1, accurate for small n·δ too.
    Some(EnergyTheory::Exact((n as f64 * delta.ln_1p()).exp_m1()))
}

/// Returns a bound on |E_n - E0|/E0 over every step n of a symplectic method on an
/// undamped spring with s = h·ω < 2 (with unit mass, k = ω²), or `None` for a method
/// that is not symplectic.
///
/// Symplectic Euler (v first, then x) conserves H̃ = E - (h/2)·k·(x·v) exactly, so
/// E_n - E0 = (h/2)·k·(x_n·v_n - x0·v0). Since ω|x·v| ≤ ½(ω²|x|² + |v|²) = E,
/// |E_n - E0| ≤ (s/2)·(E_n + E0), which solved for E_n gives
///
///   |E_n - E0|/E0 ≤ s/(1 - s/2) = O(h·ω).
///
/// Velocity Verlet conserves Q = |v|² + ω²·(1 - s²/4)·|x|² (its map has
/// c² + s²·(1 - s²/4) = 1 with c = 1 - s²/2), so 2E_n - Q = (s²/4)·ω²|x_n|², and
/// E_n - E0 = (s²/8)·ω²·(|x_n|² - |x0|²). With ω²|x|² ≤ Q/(1 - s²/4) and Q ≤ 2E0,
///
///   |E_n - E0|/E0 ≤ (s²/4)/(1 - s²/4) = O((h·ω)²).
pub fn energy_bound(kind: IntegratorKind, s: f64) -> Option<f64> {
    match kind {
        IntegratorKind::SymplecticEuler if s < 2.0 => Some(s / (1.0 - 0.5 * s)),
        IntegratorKind::Verlet if s < 2.0 => {
            let q = 0.25 * s * s;
            Some(q / (1.0 - q))
        }
        _ => None,
    }
}

impl fmt::Display for EnergyStudy {
    /// Writes one line per integrator: the largest |ΔE/E0| over the run, the final
    /// ΔE/E0, and on the spring theory's value or bound.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let o = &self.options;
        writeln!(
            f,
            "energy on `{}`: {} steps of h = {} to t = {} (E0 = {:.6e})",
            self.problem,
            o.steps,
            o.dt,
            o.steps as f64 * o.dt,
            self.e0
        )?;
        if let Some(omega) = self.omega {
            writeln!(f, "h·ω = {:.6}", o.dt * omega)?;
        }
        writeln!(f)?;
        writeln!(
            f,
            "{:<17} {:>9} {:>13} {:>13} {:>26}",
            "integrator", "steps", "max |ΔE/E0|", "final ΔE/E0", "theory (spring)"
        )?;
        for s in &self.series {
            let theory = self
                .omega
                .and_then(|w| spring_energy_theory(s.integrator, o.dt * w, s.steps))
                .map_or_else(
                    || "-".to_string(),
                    |t| match t {
                        EnergyTheory::Exact(v) => format!("final = {v:.6e}"),
                        EnergyTheory::Bound(b) => format!("max ≤ {b:.6e}"),
                    },
                );
            writeln!(
                f,
                "{:<17} {:>9} {:>13.3e} {:>13.3e} {:>26}",
                s.integrator.name(),
                s.steps,
                s.max_abs_relative_error,
                s.final_relative_error(),
                theory
            )?;
            if let Some(why) = &s.stopped {
                writeln!(f, "{:<17} stopped early: {why}", "")?;
            }
        }
        Ok(())
    }
}

/// Writes every series as CSV with the header [`CSV_HEADER`], in full precision.
pub fn write_csv<W: Write>(study: &EnergyStudy, mut out: W) -> io::Result<()> {
    writeln!(out, "{CSV_HEADER}")?;
    for s in &study.series {
        for r in &s.rows {
            writeln!(
                out,
                "{},{},{:e},{:e},{:e}",
                s.integrator, r.step, r.t, r.relative_error, r.max_abs_relative_error
            )?;
        }
    }
    out.flush()
}
