//! The command line: clap definitions, and one handler per subcommand.
//!
//! Raw flags are turned into checked options here; the library does the work. Every
//! error is printed once, with its cause, and mapped to a documented exit code.

mod bench;
mod check;
mod checkpoint;
mod completions;
mod diff;
mod export;
mod figure;
mod new_scene;
mod render;
mod study;

use std::ops::Range;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};

use crate::error::{exit, Error, Result};
use crate::scene::Scene;
use crate::sim::IntegratorKind;

/// Simulate 2-D bodies under forces and render every frame to PNG.
#[derive(Debug, Parser)]
#[command(name = "physframes", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    #[command(flatten)]
    verbosity: Verbosity,
}

/// How much the commands print besides their results; errors are always printed.
#[derive(Clone, Copy, Debug, Args)]
pub struct Verbosity {
    /// Print nothing but errors.
    #[arg(
        long,
        short,
        global = true,
        conflicts_with = "verbose",
        display_order = 900
    )]
    pub quiet: bool,
    /// Print more: the scene hash and overrides, threads, frames kept and checkpoints.
    #[arg(long, short, global = true, display_order = 900)]
    pub verbose: bool,
}

impl Verbosity {
    /// Prints a detail to standard error, with `--verbose` only.
    pub fn detail(&self, text: &str) {
        if self.verbose {
            eprintln!("{text}");
        }
    }
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Simulate a scene and write every frame as PNG, with a manifest.
    Render(render::RenderArgs),
    /// Validate a scene and print a summary of it.
    Check(check::CheckArgs),
    /// Simulate a scene and write its trajectory as CSV, drawing nothing.
    Export(export::ExportArgs),
    /// Simulate a scene, drawing nothing, and save checkpoints for sharded renders.
    Checkpoint(checkpoint::CheckpointArgs),
    /// Write a commented scene template NAME.toml that renders as it is.
    New(new_scene::NewArgs),
    /// Print a shell completion script: bash, zsh, fish, elvish or powershell.
    Completions(completions::CompletionsArgs),
    /// Draw a built-in figure, or one frame of a scene, to one PNG.
    Figure(figure::FigureArgs),
    /// Compare two PNGs or two folders of frames; exit 0 when within tolerance, 1 when
    /// different, 2 when they cannot be compared.
    Diff(diff::DiffArgs),
    /// Study the integrators on problems with closed forms: convergence,
    /// work-precision, stability and energy, as tables, CSV and PNG.
    Study(study::StudyArgs),
    /// Measure frames per second (or simulation speed) on this machine.
    Bench(bench::BenchArgs),
}

/// Flags shared by the commands that load a scene.
#[derive(Debug, Args)]
struct SceneArgs {
    /// The scene file (TOML).
    scene: PathBuf,
    /// Use this integrator instead of the scene's.
    #[arg(long, value_name = "NAME")]
    integrator: Option<String>,
    /// Override a scene value, e.g. simulation.dt=0.001, body.puck.mass=2,
    /// force.0.k=0.5 or render.view.min=[0,0]; repeatable, applied in order. The value
    /// is TOML; a bare word is a string.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

impl SceneArgs {
    /// Loads and validates the scene, applying command-line overrides.
    fn load(&self) -> Result<Scene> {
        let mut scene = Scene::load_with(&self.scene, &self.set)?;
        if let Some(name) = &self.integrator {
            scene.simulation.integrator = name.parse::<IntegratorKind>().map_err(Error::Usage)?;
        }
        Ok(scene)
    }
}

/// Parses a frame range: `A..B` (half-open), `A..=B`, `A..`, `..B`, or one frame `A`.
/// An open end stands for the scene's frame count.
fn parse_frames(text: &str, frame_count: u64) -> Result<Range<u64>> {
    let bad = || {
        Error::Usage(format!(
            "--frames `{text}` is not a range; write A..B (B excluded), A..=B, A.., ..B or A"
        ))
    };
    let number = |s: &str| s.trim().parse::<u64>().map_err(|_| bad());
    let range = if let Some((a, b)) = text.split_once("..=") {
        let a = if a.is_empty() { 0 } else { number(a)? };
        a..number(b)?.checked_add(1).ok_or_else(bad)?
    } else if let Some((a, b)) = text.split_once("..") {
        let a = if a.is_empty() { 0 } else { number(a)? };
        let b = if b.is_empty() {
            frame_count
        } else {
            number(b)?
        };
        a..b
    } else {
        let a = number(text)?;
        a..a.saturating_add(1)
    };
    if range.start >= range.end || range.end > frame_count {
        return Err(Error::Usage(format!(
            "--frames {text} asks for frames {}..{} but the scene has frames 0..{frame_count} (0..={})",
            range.start,
            range.end,
            frame_count - 1
        )));
    }
    Ok(range)
}

/// Writes text to standard output. A closed pipe (as with `| head`) is not an error
/// worth a panic: the reader has all it wanted.
fn say(text: &str) -> Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(Error::io("cannot write to", "standard output", e))
        }
        _ => Ok(()),
    }
}

/// Runs the command line and returns the process's exit code.
pub fn main() -> ExitCode {
    // Ctrl-C stops any command at once, removing the temporary file of a write in
    // progress (exit code 130).
    crate::interrupt::install();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap prints help and version to stdout with success, and usage errors to
            // stderr with exit code 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() {
                exit::BAD_INPUT
            } else {
                exit::SUCCESS
            });
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::from(exit::SUCCESS),
        Err(e) => {
            let text = e.to_string();
            if matches!(e, Error::Scene(_)) {
                eprint!("{text}");
            } else {
                eprintln!("error: {text}");
            }
            ExitCode::from(e.exit_code())
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    let verbosity = cli.verbosity;
    match cli.command {
        Command::Render(args) => render::run(args, verbosity),
        Command::Check(args) => check::run(args, verbosity),
        Command::Export(args) => export::run(args),
        Command::Checkpoint(args) => checkpoint::run(args, verbosity),
        Command::New(args) => new_scene::run(args, verbosity),
        Command::Completions(args) => completions::run(args),
        Command::Figure(args) => figure::run(args),
        Command::Diff(args) => diff::run(args),
        Command::Study(args) => study::run(args, verbosity),
        Command::Bench(args) => bench::run(args),
    }
}

#[cfg(test)]
mod tests {
    use super::parse_frames;

    #[test]
    fn frame_ranges_follow_rust() {
        assert_eq!(parse_frames("0..10", 151).ok(), Some(0..10));
        assert_eq!(parse_frames("5..=10", 151).ok(), Some(5..11));
        assert_eq!(parse_frames("140..", 151).ok(), Some(140..151));
        assert_eq!(parse_frames("..3", 151).ok(), Some(0..3));
        assert_eq!(parse_frames("7", 151).ok(), Some(7..8));
        assert!(parse_frames("10..5", 151).is_err());
        assert!(parse_frames("0..152", 151).is_err());
        assert!(parse_frames("0..=151", 151).is_err());
        assert!(parse_frames("a..b", 151).is_err());
    }
}
