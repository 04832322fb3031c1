//! Linear stability study: how large a step each integrator can take before a decaying
//! or oscillating solution starts to grow, measured on the simulation and set beside
//! linear stability theory.
//!
//! Two test equations cover the two halves of the complex plane that matter:
//!
//! - drag, m·dv/dt = -k·v (Equation 12 with a coefficient k): one step multiplies v by a
//!   number R(z) with z = -h·k/m on the negative real axis;
//! - an undamped spring, x'' = -ω²·x: one step is a linear map of (x, v) whose
//!   eigenvalues are R(±i·h·ω) for a Runge–Kutta method, on the imaginary axis.
//!
//! A step is stable when the per-step amplification g is at most 1: |R| for drag, the
//! spectral radius of the one-step map for the spring. The study measures g by running
//! the integrator's real step ([`Stepper::step`]) on a real [`System`], sweeps the
//! dimensionless step s (h·k/m or h·ω), and bisects on the measured g to find where the
//! first stable interval ends. Theory's value comes from the stability polynomials,
//! evaluated by code that shares nothing with the integrators.

mod theory;

pub use theory::{stable_step_hint, theory, theory_growth, Theory};

use std::fmt;
use std::io::{self, Write};
use std::str::FromStr;

use glam::DVec2;

use crate::sim::{Anchor, ForceSpec, IntegratorKind, Selection, State, Stepper, System};

/// The header of the table CSV that [`write_csv`] writes.
pub const CSV_HEADER: &str = "problem,integrator,boundary_found,boundary_theory,relative_difference,sign_flip_found,sign_flip_theory,max_growth_deviation,note";

/// The header of the heatmap CSV that [`write_grid_csv`] writes.
pub const GRID_CSV_HEADER: &str = "problem,integrator,h,stiffness,s,growth";

/// The two test equations of linear stability.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StabilityProblem {
    /// Linear drag m·dv/dt = -k·v: z = -h·k/m on the negative real axis.
    Drag,
    /// An undamped spring x'' = -ω²·x: z = ±i·h·ω on the imaginary axis.
    Spring,
}

impl StabilityProblem {
    /// Both problems.
    pub const ALL: &'static [StabilityProblem] =
        &[StabilityProblem::Drag, StabilityProblem::Spring];

    /// Returns the name the command line uses.
    pub fn name(self) -> &'static str {
        match self {
            StabilityProblem::Drag => "drag",
            StabilityProblem::Spring => "spring",
        }
    }

    /// Returns how the dimensionless step s is formed, for tables and titles.
    pub fn step_symbol(self) -> &'static str {
        match self {
            StabilityProblem::Drag => "h·k/m",
            StabilityProblem::Spring => "h·ω",
        }
    }

    /// Returns the name and unit of the stiffness axis of the heatmap (with m = 1 kg).
    pub fn stiffness_label(self) -> &'static str {
        match self {
            StabilityProblem::Drag => "drag coefficient k (kg/s), m = 1 kg",
            StabilityProblem::Spring => "angular frequency ω (rad/s), m = 1 kg",
        }
    }

    /// Returns what the growth factor g measures on this problem.
    pub fn growth_meaning(self) -> &'static str {
        match self {
            StabilityProblem::Drag => "|v(t + h)| / |v(t)|",
            StabilityProblem::Spring => "spectral radius of the one-step map of (x, v)",
        }
    }
}

impl fmt::Display for StabilityProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for StabilityProblem {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .iter()
            .copied()
            .find(|p| p.name() == s)
            .ok_or_else(|| format!("the stability study runs on `drag` or `spring`, not `{s}`"))
    }
}

/// How the sweep and the bisection run.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityOptions {
    /// The smallest dimensionless step tried.
    pub s_min: f64,
    /// The largest dimensionless step tried.
    pub s_max: f64,
    /// How many steps the sweep tries, spaced evenly in log s from `s_min` to `s_max`.
    pub sweep_points: usize,
    /// The bisection stops when the bracket is narrower than this, relative to s.
    pub relative_precision: f64,
    /// A step counts as stable while g ≤ 1 + `tolerance`: the measured g of a neutral
    /// method (symplectic Euler below its limit) is 1 to within a few ε, not exactly 1.
    pub tolerance: f64,
}

impl Default for StabilityOptions {
    /// s from 0.01 to 10 over 400 steps, bisection to 10⁻¹² relative, and a tolerance
    /// of 10⁻¹², a thousand times the round-off of one step (a few ε) and far below the
    /// smallest real growth the sweep meets (midpoint on the spring at s = 0.01 grows by
    /// s⁴/8 ≈ 1.25·10⁻⁹ per step).
    fn default() -> Self {
        StabilityOptions {
            s_min: 0.01,
            s_max: 10.0,
            sweep_points: 400,
            relative_precision: 1e-12,
            tolerance: 1e-12,
        }
    }
}

impl StabilityOptions {
    /// Returns the dimensionless steps the sweep tries, in increasing order.
    pub fn sweep(&self) -> Vec<f64> {
        log_space(self.s_min, self.s_max, self.sweep_points.max(2))
    }
}

/// One step of an integrator on a test equation, measured.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth {
    /// The per-step amplification g: |R| for drag, the spectral radius of the one-step
    /// map for the spring.
    pub factor: f64,
    /// Drag only: the signed ratio v(t + h)/v(t), negative when the step overshoots and
    /// the velocity changes sign.
    pub signed: Option<f64>,
    /// Spring only: the energy after one step over the energy before, from the initial
    /// state x = (1, 0), v = (0, ω).
    pub energy_ratio: Option<f64>,
}

/// Measures one step of `kind` at the dimensionless step `s`, with m = 1 and k = 1
/// (drag) or ω = 1 (spring), so that h = s.
pub fn growth(problem: StabilityProblem, kind: IntegratorKind, s: f64) -> Growth {
    growth_at(problem, kind, s, 1.0)
}

/// Measures one step of `kind` of size `h` on a body of mass 1 with the drag
/// coefficient k = `stiffness` (drag) or the angular frequency ω = `stiffness` (spring,
/// stiffness k = m·ω²).
///
/// One step is enough: both test equations are linear, so the step is a fixed linear
/// map, and every method's carried-over evaluations (velocity Verlet's acceleration,
/// dopri5's last stage) are the evaluations a fresh step would make. dopri5 takes one
/// step of its fifth-order solution without error control (see [`Stepper::step`]).
pub fn growth_at(
    problem: StabilityProblem,
    kind: IntegratorKind,
    h: f64,
    stiffness: f64,
) -> Growth {
    let m = 1.0;
    match problem {
        StabilityProblem::Drag => {
            let system = System::new(
                vec![m],
                &[ForceSpec::Drag {
                    k: stiffness,
                    bodies: Selection::All,
                }],
            );
            // |v0| = 1, in a direction that is neither axis.
            let v0 = DVec2::new(0.6, 0.8);
            let mut state = State::new(0.0, vec![DVec2::ZERO], vec![v0]);
            Stepper::new(kind, &system).step(&system, h, &mut state);
            let vel = &state.vel;
            // v1 = R·v0, so R = v1·v0/|v0|².
            let signed = vel[0].dot(v0) / v0.length_squared();
            Growth {
                factor: vel[0].length() / v0.length(),
                signed: Some(signed),
                energy_ratio: None,
            }
        }
        StabilityProblem::Spring => {
            let omega = stiffness;
            let system = System::new(
                vec![m],
                &[ForceSpec::Spring {
                    a: 0,
                    b: Anchor::Point(DVec2::ZERO),
                    stiffness: m * omega * omega,
                    rest_length: 0.0,
                    damping: 0.0,
                    a_at: None,
                    b_at: None,
                }],
            );
            // A spring of rest length 0 pulls each coordinate on its own, so the x and y
            // coordinates carry two independent initial states of the one-dimensional
            // oscillator, in the scaled coordinates q = (x, v/ω): e1 = (1, 0) along x
            // and e2 = (0, 1) along y.
            let mut state = State::new(0.0, vec![DVec2::X], vec![DVec2::new(0.0, omega)]);
            let e0 = spring_energy(m, omega, state.pos[0], state.vel[0]);
            Stepper::new(kind, &system).step(&system, h, &mut state);
            let (pos, vel) = (&state.pos, &state.vel);
            // The one-step map A in q: its columns are the images of e1 and e2,
            // A = [[x_x, x_y], [v_x/ω, v_y/ω]].
            let a = [[pos[0].x, pos[0].y], [vel[0].x / omega, vel[0].y / omega]];
            Growth {
                factor: spectral_radius(a),
                signed: None,
                energy_ratio: Some(spring_energy(m, omega, pos[0], vel[0]) / e0),
            }
        }
    }
}

/// Returns the energy ½m|v|² + ½m·ω²|x|² of a body on a spring of rest length 0.
fn spring_energy(m: f64, omega: f64, x: DVec2, v: DVec2) -> f64 {
    0.5 * m * v.length_squared() + 0.5 * m * omega * omega * x.length_squared()
}

/// Returns the largest modulus of the eigenvalues of a real 2×2 matrix.
///
/// The eigenvalues are λ = tr/2 ± √(tr²/4 - det). When tr²/4 < det they are a complex
/// pair of modulus √det; otherwise they are real and the larger modulus is
/// |tr|/2 + √(tr²/4 - det).
fn spectral_radius(a: [[f64; 2]; 2]) -> f64 {
    let tr = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let half = 0.5 * tr;
    let disc = half * half - det;
    if disc < 0.0 {
        det.sqrt()
    } else {
        half.abs() + disc.sqrt()
    }
}

/// Returns the end of the interval where `stable` holds, given `stable(lo)` and
/// `!stable(hi)`, to within `relative_precision` of it.
fn bisect(stable: impl Fn(f64) -> bool, mut lo: f64, mut hi: f64, relative_precision: f64) -> f64 {
    debug_assert!(stable(lo) && !stable(hi));
    while hi - lo > relative_precision * hi {
        let mid = 0.5 * (lo + hi);
        if stable(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Where the measured stable interval ends.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Boundary {
    /// Unstable at every step tried: only s = 0 is stable.
    UnstableEverywhere,
    /// Stable from the smallest step tried up to this s, found by bisection.
    At(f64),
    /// Stable at every step tried.
    StableEverywhere,
}

impl Boundary {
    /// Returns the largest stable s: 0 when no step tried is stable, `None` when every
    /// step tried is.
    pub fn value(self) -> Option<f64> {
        match self {
            Boundary::UnstableEverywhere => Some(0.0),
            Boundary::At(s) => Some(s),
            Boundary::StableEverywhere => None,
        }
    }
}

/// One integrator's row of the stability table.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityRow {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Where the measured stable interval ends.
    pub found: Boundary,
    /// Drag only: where the measured signed ratio v(t + h)/v(t) turns negative, found by
    /// bisection like the boundary, or `None` when it never does over the sweep.
    pub sign_flip_found: Option<f64>,
    /// Theory's answer.
    pub theory: Theory,
    /// The largest relative difference, over every step of the sweep, between the
    /// measured growth factor and theory's.
    pub max_growth_deviation: f64,
}

impl StabilityRow {
    /// Returns |found - theory|/theory, when both are positive numbers.
    pub fn relative_difference(&self) -> Option<f64> {
        match self.found {
            Boundary::At(s) if self.theory.boundary > 0.0 => {
                Some((s - self.theory.boundary).abs() / self.theory.boundary)
            }
            _ => None,
        }
    }
}

/// The result of a stability study.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityTable {
    /// The test equation.
    pub problem: StabilityProblem,
    /// The sweep and bisection settings.
    pub options: StabilityOptions,
    /// One row per integrator, in the order asked.
    pub rows: Vec<StabilityRow>,
}

/// Sweeps every integrator over the dimensionless steps of `options` on `problem`,
/// bisects on the measured growth where the first stable interval ends (and, on drag,
/// where the velocity first changes sign), and sets each beside theory.
pub fn stability(
    problem: StabilityProblem,
    integrators: &[IntegratorKind],
    options: &StabilityOptions,
) -> StabilityTable {
    let sweep = options.sweep();
    let rows = integrators
        .iter()
        .map(|&kind| {
            let stable = |s: f64| growth(problem, kind, s).factor <= 1.0 + options.tolerance;
            let found = first_boundary(&sweep, stable, options.relative_precision);
            let sign_flip_found = match problem {
                StabilityProblem::Drag => {
                    let positive = |s: f64| growth(problem, kind, s).signed.unwrap_or(1.0) >= 0.0;
                    match first_boundary(&sweep, positive, options.relative_precision) {
                        Boundary::At(s) => Some(s),
                        _ => None,
                    }
                }
                StabilityProblem::Spring => None,
            };
            let max_growth_deviation = sweep
                .iter()
                .map(|&s| {
                    let measured = growth(problem, kind, s).factor;
                    let expected = theory_growth(problem, kind, s);
                    (measured - expected).abs() / expected
                })
                .fold(0.0, f64::max);
            StabilityRow {
                integrator: kind,
                found,
                sign_flip_found,
                theory: theory(problem, kind),
                max_growth_deviation,
            }
        })
        .collect();
    StabilityTable {
        problem,
        options: options.clone(),
        rows,
    }
}

/// Finds where the first run of `holds` along the increasing `sweep` ends, and bisects
/// between the last step where it holds and the first where it does not.
fn first_boundary(sweep: &[f64], holds: impl Fn(f64) -> bool, relative_precision: f64) -> Boundary {
    let Some(first_fail) = sweep.iter().position(|&s| !holds(s)) else {
        return Boundary::StableEverywhere;
    };
    if first_fail == 0 {
        return Boundary::UnstableEverywhere;
    }
    let (lo, hi) = (sweep[first_fail - 1], sweep[first_fail]);
    Boundary::At(bisect(holds, lo, hi, relative_precision))
}

/// Returns `n` values from `a` to `b` (both included) spaced evenly in log.
pub fn log_space(a: f64, b: f64, n: usize) -> Vec<f64> {
    let (la, lb) = (a.ln(), b.ln());
    (0..n)
        .map(|i| {
            // The ends are returned exactly, not through exp(ln(x)).
            if i == 0 {
                a
            } else if i + 1 == n {
                b
            } else {
                (la + (lb - la) * i as f64 / (n - 1) as f64).exp()
            }
        })
        .collect()
}

/// Formats an optional number for the table: `-` when absent.
fn or_dash(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}"))
}

impl fmt::Display for StabilityTable {
    /// Writes the table: per integrator the largest stable s found and theory's, their
    /// relative difference, on drag the sign flip, and the largest deviation of the
    /// measured growth from theory's over the sweep.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let o = &self.options;
        writeln!(
            f,
            "linear stability on `{}`: s = {}, growth g = {} per step",
            self.problem,
            self.problem.step_symbol(),
            self.problem.growth_meaning()
        )?;
        writeln!(
            f,
            "(stable while g ≤ 1 + {:.0e}; {} steps swept from s = {} to {}, then bisection to {:.0e} relative)",
            o.tolerance, o.sweep_points, o.s_min, o.s_max, o.relative_precision
        )?;
        writeln!(f)?;
        let drag = self.problem == StabilityProblem::Drag;
        write!(
            f,
            "{:<17} {:>14} {:>14} {:>9}",
            "integrator", "largest s found", "theory", "rel. diff"
        )?;
        if drag {
            write!(f, " {:>10} {:>10}", "flip found", "flip th.")?;
        }
        writeln!(f, " {:>11}", "max |Δg|/g")?;
        for r in &self.rows {
            let found = match r.found {
                Boundary::UnstableEverywhere => "0 (none)".to_string(),
                Boundary::At(s) => format!("{s:.10}"),
                Boundary::StableEverywhere => format!("> {}", o.s_max),
            };
            let theory = if r.theory.boundary == 0.0 {
                "0 (none)".to_string()
            } else {
                format!("{:.10}", r.theory.boundary)
            };
            let diff = r
                .relative_difference()
                .map_or_else(|| "-".to_string(), |d| format!("{d:.1e}"));
            write!(
                f,
                "{:<17} {:>14} {:>14} {:>9}",
                r.integrator.name(),
                found,
                theory,
                diff
            )?;
            if drag {
                write!(
                    f,
                    " {:>10} {:>10}",
                    or_dash(r.sign_flip_found, 6),
                    or_dash(r.theory.sign_flip, 6)
                )?;
            }
            writeln!(f, " {:>11.1e}", r.max_growth_deviation)?;
        }
        writeln!(f)?;
        for r in &self.rows {
            writeln!(f, "{:<17} theory: {}", r.integrator.name(), r.theory.reason)?;
            if r.found == Boundary::UnstableEverywhere {
                writeln!(
                    f,
                    "{:<17} measured: g > 1 at every step tried, from s = {}",
                    "", o.s_min
                )?;
            }
            if r.integrator == IntegratorKind::Dopri5 {
                let note = match self.problem {
                    StabilityProblem::Drag => "measured with fixed steps of its fifth-order solution; run adaptively on stiff drag (k/m = 1000) its error control holds the step at this limit: mean h·k/m = 3.306 over t = 1…11 s at every tolerance from 1e-3 to 1e-9",
                    StabilityProblem::Spring => "measured with fixed steps of its fifth-order solution; run adaptively it chooses its own steps, and this is the limit its error control must keep them under",
                };
                writeln!(f, "{:<17} ({note})", "")?;
            }
        }
        Ok(())
    }
}

/// Writes the table as CSV with the header [`CSV_HEADER`]. An absent value is an empty
/// field; a boundary of 0 means only s = 0 is stable.
pub fn write_csv<W: Write>(table: &StabilityTable, mut out: W) -> io::Result<()> {
    writeln!(out, "{CSV_HEADER}")?;
    let opt = |v: Option<f64>| v.map_or_else(String::new, |x| format!("{x:e}"));
    for r in &table.rows {
        let note = match r.found {
            Boundary::UnstableEverywhere => format!(
                "unstable at every step tried from s = {}",
                table.options.s_min
            ),
            Boundary::StableEverywhere => {
                format!(
                    "stable at every step tried up to s = {}",
                    table.options.s_max
                )
            }
            Boundary::At(_) => String::new(),
        };
        writeln!(
            out,
            "{},{},{},{:e},{},{},{},{:e},{}",
            table.problem,
            r.integrator,
            opt(r.found.value()),
            r.theory.boundary,
            opt(r.relative_difference()),
            opt(r.sign_flip_found),
            opt(r.theory.sign_flip),
            r.max_growth_deviation,
            note
        )?;
    }
    out.flush()
}

/// The heatmap: the measured growth per step over a grid of step sizes h and
/// stiffnesses, for each integrator.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityGrid {
    /// The test equation.
    pub problem: StabilityProblem,
    /// The cell edges along h (s), increasing, spaced evenly in log.
    pub h_edges: Vec<f64>,
    /// The cell edges along the stiffness (k in kg/s or ω in rad/s), increasing, spaced
    /// evenly in log.
    pub stiffness_edges: Vec<f64>,
    /// Per integrator, the growth factor of every cell, indexed `[j][i]` for the i-th h
    /// and j-th stiffness, measured at the cell's centre (the geometric mean of its
    /// edges).
    pub growth: Vec<(IntegratorKind, Vec<Vec<f64>>)>,
}

impl StabilityGrid {
    /// Returns the centre of each cell along h.
    pub fn h_centres(&self) -> Vec<f64> {
        centres(&self.h_edges)
    }

    /// Returns the centre of each cell along the stiffness.
    pub fn stiffness_centres(&self) -> Vec<f64> {
        centres(&self.stiffness_edges)
    }
}

/// Returns the geometric means of neighbouring edges.
fn centres(edges: &[f64]) -> Vec<f64> {
    edges.windows(2).map(|w| (w[0] * w[1]).sqrt()).collect()
}

/// Measures the growth per step of each integrator on `cells × cells` cells spanning
/// h in `h_range` and the stiffness in `stiffness_range` (both spaced evenly in log),
/// each with its own h and stiffness, so the heatmap shows that g depends on h·k/m (or
/// h·ω) alone.
pub fn stability_grid(
    problem: StabilityProblem,
    integrators: &[IntegratorKind],
    h_range: (f64, f64),
    stiffness_range: (f64, f64),
    cells: usize,
) -> StabilityGrid {
    let cells = cells.max(1);
    let h_edges = log_space(h_range.0, h_range.1, cells + 1);
    let stiffness_edges = log_space(stiffness_range.0, stiffness_range.1, cells + 1);
    let (hs, ks) = (centres(&h_edges), centres(&stiffness_edges));
    let growth = integrators
        .iter()
        .map(|&kind| {
            let values = ks
                .iter()
                .map(|&k| {
                    hs.iter()
                        .map(|&h| growth_at(problem, kind, h, k).factor)
                        .collect()
                })
                .collect();
            (kind, values)
        })
        .collect();
    StabilityGrid {
        problem,
        h_edges,
        stiffness_edges,
        growth,
    }
}

/// Writes every cell of the heatmap as CSV with the header [`GRID_CSV_HEADER`]: the
/// cell's centre h and stiffness, s = h·stiffness (m = 1), and the growth per step.
pub fn write_grid_csv<W: Write>(grid: &StabilityGrid, mut out: W) -> io::Result<()> {
    writeln!(out, "{GRID_CSV_HEADER}")?;
    let (hs, ks) = (grid.h_centres(), grid.stiffness_centres());
    for (kind, values) in &grid.growth {
        for (j, &k) in ks.iter().enumerate() {
            for (i, &h) in hs.iter().enumerate() {
                writeln!(
                    out,
                    "{},{},{:e},{:e},{:e},{:e}",
                    grid.problem,
                    kind,
                    h,
                    k,
                    h * k,
                    values[j][i]
                )?;
            }
        }
    }
    out.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spectral_radius_of_a_rotation_is_one_and_of_a_shear_its_diagonal() {
        let (s, c) = 0.3f64.sin_cos();
        assert!((spectral_radius([[c, -s], [s, c]]) - 1.0).abs() < 1e-15);
        assert_eq!(spectral_radius([[2.0, 5.0], [0.0, -3.0]]), 3.0);
    }

    #[test]
    fn theory_of_rk4_on_drag_is_the_real_root_of_its_cubic() {
        let s = theory(StabilityProblem::Drag, IntegratorKind::Rk4).boundary;
        // s³ - 4s² + 12s - 24 = 0 at the boundary, where R(-s) = 1 - s·(…) meets 1.
        assert!(
            (s * s * s - 4.0 * s * s + 12.0 * s - 24.0).abs() < 1e-12,
            "{s}"
        );
        assert!((s - 2.785_293_563_405_28).abs() < 1e-12, "{s}");
    }

    #[test]
    fn log_space_hits_both_ends() {
        let v = log_space(0.01, 10.0, 4);
        assert_eq!(v.first().copied(), Some(0.01));
        assert_eq!(v.last().copied(), Some(10.0));
        assert!((v[1] - 0.1).abs() < 1e-15 && (v[2] - 1.0).abs() < 1e-14);
    }

    #[test]
    fn the_hint_names_the_tightest_limit() {
        let forces = [ForceSpec::Drag {
            k: 1000.0,
            bodies: Selection::All,
        }];
        let hint =
            stable_step_hint(IntegratorKind::Euler, &[1.0, 2.0], &[], &forces).expect("a hint");
        assert!(hint.contains("dt ≤ 2·m/k = 0.002"), "{hint}");
        // Angular drag k/I = 4000 on the second body is tighter still: dt ≤ 2·I/k.
        let mut spun = forces.to_vec();
        spun.push(ForceSpec::AngularDrag {
            k: 2.0,
            bodies: Selection::Bodies(vec![1]),
        });
        let hint = stable_step_hint(IntegratorKind::Euler, &[1.0, 2.0], &[1.0, 5e-4], &spun)
            .expect("a hint");
        assert!(
            hint.contains("angular drag with k/I = 4000 needs dt ≤ 2·I/k = 0.0005"),
            "{hint}"
        );
        let spring = [ForceSpec::Spring {
            a: 0,
            b: Anchor::Point(glam::DVec2::ZERO),
            stiffness: 4.0,
            rest_length: 0.0,
            damping: 0.0,
            a_at: None,
            b_at: None,
        }];
        let hint = stable_step_hint(IntegratorKind::Euler, &[1.0], &[], &spring).expect("a hint");
        assert!(hint.contains("never stable"), "{hint}");
        let hint = stable_step_hint(IntegratorKind::SymplecticEuler, &[1.0], &[], &spring)
            .expect("a hint");
        assert!(hint.contains("dt < 2/ω = 1"), "{hint}");
        assert_eq!(
            stable_step_hint(IntegratorKind::Dopri5, &[1.0], &[], &spring),
            None
        );
    }
}
