//! `physframes study`: accuracy and stability studies of the integrators on reference
//! problems with closed forms, printed as tables and written as CSV and PNG.

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};

use crate::error::{Error, Result};
use crate::numbers::{about, Readable};
use crate::output;
use crate::sim::IntegratorKind;
use crate::study::energy::{self, EnergyOptions};
use crate::study::plots;
use crate::study::stability::{self, StabilityOptions, StabilityProblem};
use crate::study::{
    convergence, work_precision, ConvergenceOptions, ReferenceKind, WorkPrecisionOptions,
};

use super::Verbosity;

#[derive(Debug, Args)]
pub struct StudyArgs {
    #[command(subcommand)]
    command: StudyCommand,
}

#[derive(Debug, Subcommand)]
enum StudyCommand {
    /// Halve h repeatedly and print each integrator's error and observed order.
    Convergence(ConvergenceArgs),
    /// Error against run time for each integrator and step (or tolerance): CSV and a
    /// log-log work-precision diagram.
    WorkPrecision(WorkPrecisionArgs),
    /// The largest stable step of each integrator on drag or an undamped spring, beside
    /// linear stability theory: a table, CSV and heatmaps.
    Stability(StabilityArgs),
    /// The relative energy error of each integrator over time: a table, CSV and a plot.
    Energy(EnergyArgs),
}

/// The integrators to compare.
#[derive(Debug, Args)]
struct IntegratorList {
    /// Comma-separated integrators, e.g. euler,rk4 [default: all of euler,
    /// symplectic-euler, midpoint, heun, rk4, verlet, dopri5].
    #[arg(long = "integrator", value_name = "LIST", value_delimiter = ',')]
    names: Vec<String>,
}

impl IntegratorList {
    /// Parses the names, in the order given, each once; every integrator when none is
    /// given.
    fn parse(&self) -> Result<Vec<IntegratorKind>> {
        if self.names.is_empty() {
            return Ok(IntegratorKind::ALL.to_vec());
        }
        let mut kinds = Vec::new();
        for name in &self.names {
            let name = name.trim();
            if name.is_empty() {
                return Err(Error::Usage(format!(
                    "--integrator has an empty name in its list; expected names separated by commas from: {}",
                    IntegratorKind::names().join(", ")
                )));
            }
            let kind = name.parse::<IntegratorKind>().map_err(Error::Usage)?;
            if !kinds.contains(&kind) {
                kinds.push(kind);
            }
        }
        Ok(kinds)
    }
}

#[derive(Debug, Args)]
struct ConvergenceArgs {
    /// The reference problem: constant-acceleration, drag, drag-gravity, time-force,
    /// spring, damped-spring, orbit, or one whose bodies turn: spin-up, angular-drag or
    /// hanging-box.
    #[arg(long, value_name = "NAME", default_value = "spring")]
    problem: String,
    #[command(flatten)]
    integrators: IntegratorList,
    /// The number of step sizes: 10 steps, then 20, 40, … (1 to 20).
    #[arg(long, value_name = "N", default_value_t = 8)]
    levels: u32,
    /// Also write convergence.csv and convergence.png (error against h) into DIR.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct WorkPrecisionArgs {
    /// The reference problem: constant-acceleration, drag, drag-gravity, time-force,
    /// spring, damped-spring, orbit, or one whose bodies turn: spin-up, angular-drag or
    /// hanging-box.
    #[arg(long, value_name = "NAME", default_value = "spring")]
    problem: String,
    #[command(flatten)]
    integrators: IntegratorList,
    /// The number of step sizes of the fixed-step methods: 10 steps, then 20, 40, …
    /// (1 to 20); dopri5 always runs tolerances 1e-3 to 1e-12.
    #[arg(long, value_name = "N", default_value_t = 8)]
    levels: u32,
    /// The number of timed samples whose median is the run time (each lasts at least
    /// 10 ms; 1 to 100).
    #[arg(long, value_name = "N", default_value_t = 5)]
    samples: usize,
    /// The folder for work-precision.csv and work-precision.png [default:
    /// output/study/work-precision-<problem>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct StabilityArgs {
    /// The test equation: drag (z = -h·k/m) or spring (undamped, z = ±i·h·ω).
    #[arg(long, value_name = "drag|spring")]
    problem: String,
    #[command(flatten)]
    integrators: IntegratorList,
    /// The heatmap's cells along each axis (4 to 400).
    #[arg(long, value_name = "N", default_value_t = 64)]
    grid: usize,
    /// The folder for stability.csv, stability-grid.csv and stability.png [default:
    /// output/study/stability-<problem>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

#[derive(Debug, Args)]
struct EnergyArgs {
    /// A reference problem with a conserved energy: spring, orbit, hanging-box or
    /// constant-acceleration (closed forms and bounds are for spring).
    #[arg(long, value_name = "NAME", default_value = "spring")]
    problem: String,
    /// The number of steps N; the run ends at t = N·dt.
    #[arg(long, value_name = "N")]
    steps: u64,
    /// The step h in seconds (for dopri5, the largest step).
    #[arg(
        long,
        value_name = "H",
        default_value_t = 0.01,
        allow_negative_numbers = true
    )]
    dt: f64,
    #[command(flatten)]
    integrators: IntegratorList,
    /// The folder for energy.csv and energy.png [default: output/study/energy-<problem>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

pub fn run(args: StudyArgs, verbosity: Verbosity) -> Result<()> {
    match args.command {
        StudyCommand::Convergence(a) => run_convergence(a, verbosity),
        StudyCommand::WorkPrecision(a) => run_work_precision(a, verbosity),
        StudyCommand::Stability(a) => run_stability(a, verbosity),
        StudyCommand::Energy(a) => run_energy(a, verbosity),
    }
}

/// Parses a reference problem's name.
fn problem(name: &str) -> Result<ReferenceKind> {
    name.parse::<ReferenceKind>().map_err(Error::Usage)
}

/// Checks that `--flag` lies in `range`.
fn in_range<T: PartialOrd + std::fmt::Display + Copy>(
    flag: &str,
    value: T,
    range: std::ops::RangeInclusive<T>,
) -> Result<T> {
    if range.contains(&value) {
        Ok(value)
    } else {
        Err(Error::Usage(format!(
            "{flag} {value} is out of range; expected {} to {}",
            range.start(),
            range.end()
        )))
    }
}

/// Prints `text` unless `--quiet`.
fn report(verbosity: Verbosity, text: &str) -> Result<()> {
    if verbosity.quiet {
        Ok(())
    } else {
        super::say(text)
    }
}

/// Creates the output folder.
fn create_dir(dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io("cannot create", dir, e))
}

/// Writes `bytes` atomically to `dir/name` and returns the path.
fn write(dir: &Path, name: &str, bytes: &[u8]) -> Result<PathBuf> {
    let path = dir.join(name);
    output::write_atomic(&path, bytes)?;
    Ok(path)
}

/// Renders CSV into memory with a writer function.
fn csv(write: impl FnOnce(&mut Vec<u8>) -> std::io::Result<()>) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    write(&mut bytes).map_err(|e| Error::Runtime(format!("cannot format the CSV: {e}")))?;
    Ok(bytes)
}

/// Lists written files, one per line.
fn wrote(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| format!("wrote {}\n", p.display()))
        .collect()
}

/// Returns the default output folder `output/study/<study>-<problem>`.
fn default_out(study: &str, problem: &str) -> PathBuf {
    PathBuf::from("output")
        .join("study")
        .join(format!("{study}-{problem}"))
}

fn run_convergence(args: ConvergenceArgs, verbosity: Verbosity) -> Result<()> {
    let kind = problem(&args.problem)?;
    let integrators = args.integrators.parse()?;
    let levels = in_range("--levels", args.levels, 1..=20)?;
    let options = ConvergenceOptions {
        levels,
        ..ConvergenceOptions::default()
    };
    let table = convergence(&kind.problem(), &integrators, &options);
    let mut text = table.to_string();
    if let Some(dir) = &args.out {
        create_dir(dir)?;
        let csv_bytes = csv(|w| convergence::write_csv(&table, w))?;
        let provenance = plots::provenance(
            "convergence",
            kind.name(),
            &integrators,
            &[
                ("levels", levels.to_string()),
                ("coarsest-steps", options.coarsest_steps.to_string()),
            ],
        );
        let png = plots::encode(&plots::convergence_chart(&table)?, &provenance)?;
        let paths = [
            write(dir, "convergence.csv", &csv_bytes)?,
            write(dir, "convergence.png", &png)?,
        ];
        text.push('\n');
        text.push_str(&wrote(&paths));
    }
    report(verbosity, &text)
}

fn run_work_precision(args: WorkPrecisionArgs, verbosity: Verbosity) -> Result<()> {
    let kind = problem(&args.problem)?;
    let integrators = args.integrators.parse()?;
    let levels = in_range("--levels", args.levels, 1..=20)?;
    let samples = in_range("--samples", args.samples, 1..=100)?;
    let options = WorkPrecisionOptions {
        step_counts: (0..levels).map(|k| 10u64 << k).collect(),
        samples,
        ..WorkPrecisionOptions::default()
    };
    let dir = args
        .out
        .unwrap_or_else(|| default_out("work-precision", kind.name()));
    let reference = kind.problem();
    let rows = work_precision(&reference, &integrators, &options);
    create_dir(&dir)?;
    let csv_bytes = csv(|w| work_precision::write_csv(&rows, w))?;
    let provenance = plots::provenance(
        "work-precision",
        kind.name(),
        &integrators,
        &[
            ("t-end", reference.t_end().to_string()),
            ("levels", levels.to_string()),
            ("samples", samples.to_string()),
        ],
    );
    let chart = plots::work_precision_chart(kind, reference.t_end(), &rows)?;
    let png = plots::encode(&chart, &provenance)?;
    let paths = [
        write(&dir, "work-precision.csv", &csv_bytes)?,
        write(&dir, "work-precision.png", &png)?,
    ];
    let mut text = format!(
        "work-precision on `{}` to t = {} (error = {}; time = median of {samples} samples of at least 10 ms)\n\n",
        kind.name(),
        reference.t_end(),
        kind.error_measure()
    );
    text.push_str(&work_precision::format_summary(&rows));
    text.push('\n');
    text.push_str(&wrote(&paths));
    report(verbosity, &text)
}

fn run_stability(args: StabilityArgs, verbosity: Verbosity) -> Result<()> {
    let problem = args
        .problem
        .parse::<StabilityProblem>()
        .map_err(Error::Usage)?;
    let integrators = args.integrators.parse()?;
    let cells = in_range("--grid", args.grid, 4..=400)?;
    let options = StabilityOptions::default();
    let table = stability::stability(problem, &integrators, &options);
    // h from 1 ms to 10 s and the stiffness over four decades (m = 1 kg): s = h·k/m or
    // h·ω then spans 10⁻⁴ to 10⁴, with every boundary near the diagonal.
    let grid = stability::stability_grid(problem, &integrators, (1e-3, 10.0), (0.1, 1000.0), cells);
    let dir = args
        .out
        .unwrap_or_else(|| default_out("stability", problem.name()));
    create_dir(&dir)?;
    let table_csv = csv(|w| stability::write_csv(&table, w))?;
    let grid_csv = csv(|w| stability::write_grid_csv(&grid, w))?;
    let provenance = plots::provenance(
        "stability",
        problem.name(),
        &integrators,
        &[("grid", cells.to_string())],
    );
    let png = plots::encode(&plots::stability_chart(&grid, &table)?, &provenance)?;
    let paths = [
        write(&dir, "stability.csv", &table_csv)?,
        write(&dir, "stability-grid.csv", &grid_csv)?,
        write(&dir, "stability.png", &png)?,
    ];
    let mut text = table.to_string();
    text.push('\n');
    text.push_str(&wrote(&paths));
    report(verbosity, &text)
}

fn run_energy(args: EnergyArgs, verbosity: Verbosity) -> Result<()> {
    let kind = problem(&args.problem)?;
    let integrators = args.integrators.parse()?;
    if !(args.dt.is_finite() && args.dt > 0.0) {
        return Err(Error::Usage(format!(
            "--dt {} must be a finite number of seconds > 0",
            Readable(args.dt)
        )));
    }
    let steps = in_range("--steps", args.steps, 1..=1_000_000_000)?;
    let reference = kind.problem();
    energy_run_fits(steps, args.dt, integrators.len(), reference.initial().len())?;
    let options = EnergyOptions {
        dt: args.dt,
        steps,
        ..EnergyOptions::default()
    };
    let study = energy::energy_study(&reference, &integrators, &options).map_err(Error::Usage)?;
    let dir = args
        .out
        .unwrap_or_else(|| default_out("energy", kind.name()));
    create_dir(&dir)?;
    let csv_bytes = csv(|w| energy::write_csv(&study, w))?;
    let provenance = plots::provenance(
        "energy",
        kind.name(),
        &integrators,
        &[("dt", args.dt.to_string()), ("steps", steps.to_string())],
    );
    let png = plots::encode(&plots::energy_chart(&study)?, &provenance)?;
    let paths = [
        write(&dir, "energy.csv", &csv_bytes)?,
        write(&dir, "energy.png", &png)?,
    ];
    let mut text = study.to_string();
    text.push('\n');
    text.push_str(&wrote(&paths));
    report(verbosity, &text)
}

/// Checks, before anything is run or written, that an energy study can finish and be
/// drawn: it ends at t = N·h, which must be a finite normal number (a subnormal time
/// has too few bits to place N steps on, and an infinite one no axis), and its work,
/// steps × integrators × bodies, is within the limit scenes have
/// ([`crate::scene::MAX_BODY_STEPS`]).
fn energy_run_fits(steps: u64, dt: f64, integrators: usize, bodies: usize) -> Result<()> {
    let t_end = steps as f64 * dt;
    if !(t_end.is_finite() && t_end >= f64::MIN_POSITIVE) {
        return Err(Error::Usage(format!(
            "--steps {steps} × --dt {} ends at t = {}, which the study cannot reach and plot; choose a --dt between {} and {}",
            Readable(dt),
            Readable(t_end),
            about(f64::MIN_POSITIVE / steps as f64),
            about(f64::MAX / steps as f64)
        )));
    }
    let work = u128::from(steps) * integrators as u128 * bodies.max(1) as u128;
    if work > u128::from(crate::scene::MAX_BODY_STEPS) {
        return Err(Error::Usage(format!(
            "--steps {steps} for {integrators} integrators on {bodies} bodies is {work} body-steps, more than the limit of 10^12; lower --steps or list fewer integrators"
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrator_lists_keep_order_drop_repeats_and_reject_unknown_names() {
        let parse = |names: &[&str]| {
            IntegratorList {
                names: names.iter().map(|s| s.to_string()).collect(),
            }
            .parse()
        };
        assert_eq!(parse(&[]).ok(), Some(IntegratorKind::ALL.to_vec()));
        assert_eq!(
            parse(&["rk4", "euler", "rk4"]).ok(),
            Some(vec![IntegratorKind::Rk4, IntegratorKind::Euler])
        );
        assert!(parse(&["rk5"]).is_err());
        assert!(parse(&["euler", ""]).is_err());
    }

    #[test]
    fn an_energy_study_must_end_at_a_finite_normal_time_within_the_work_limit() {
        assert!(energy_run_fits(10_000, 0.01, 7, 2).is_ok());
        assert!(energy_run_fits(1_000_000_000, 1e-300, 7, 2).is_ok());
        // 10 × 1e308 overflows; 1000 × 5e-324 is subnormal.
        assert!(energy_run_fits(10, 1e308, 1, 1).is_err());
        assert!(energy_run_fits(1000, 5e-324, 1, 1).is_err());
        assert!(energy_run_fits(1_000_000_000, 0.01, 7, 142).is_ok());
        assert!(energy_run_fits(1_000_000_000, 0.01, 7, 143).is_err());
    }
}
