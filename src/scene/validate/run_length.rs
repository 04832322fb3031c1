//! How long a run is: steps per frame, frames, total steps and total work, each counted
//! exactly and held to a limit, so that a scene that validates can finish.
//!
//! Time is kept as a step count, t = n·dt, so n must be an integer that an `f64` holds
//! exactly: at most 2^53 ([`MAX_STEPS`]); past it, n·dt skips steps and a frame
//! interval "of a whole number of steps" passes only because its quotient is too large
//! to have a fraction. The work of a run, steps times bodies times the runs `compare`
//! adds, is held to [`MAX_BODY_STEPS`]: at the 1 ns a body-step the simulation aims
//! for, about 17 minutes, and hours for forces that cost more. Each refusal points at
//! `dt` (or the `--set` that set it), which the counts follow, or at `duration` and
//! `fps` when `dt` is left to its default.

use std::ops::Range;

use toml::Spanned;

use super::{Validator, MAX_FRAMES};
use crate::numbers::{about, Readable};
use crate::scene::raw::{RawRender, RawSimulation};
use crate::scene::{CompareRun, Diagnostic, SimulationSettings};

/// The most steps a run may count: 2^53, the largest n for which every integer up to n
/// is an `f64`, so that t = n·dt is computed from an exact n.
pub const MAX_STEPS: u64 = 1 << 53;

/// The most body-steps (steps times bodies, for every run `compare` adds) a scene may
/// ask for: 10^12.
pub const MAX_BODY_STEPS: u64 = 1_000_000_000_000;

/// The relative allowance that keeps duration·fps = 0.7·30 = 21 from flooring to 20.
const FLOOR_ALLOWANCE: f64 = 1e-9;

/// Where the values that time a run are written, when they are written.
pub(super) struct TimingSpans {
    dt: Option<Range<usize>>,
    duration: Option<Range<usize>>,
    fps: Option<Range<usize>>,
}

impl TimingSpans {
    pub(super) fn new(
        simulation: Option<&Spanned<RawSimulation>>,
        render: Option<&Spanned<RawRender>>,
    ) -> Self {
        let sim = simulation.map(|s| s.get_ref());
        TimingSpans {
            dt: sim.and_then(|s| s.dt.as_ref()).map(|d| d.span()),
            duration: sim.and_then(|s| s.duration.as_ref()).map(|d| d.span()),
            fps: render
                .and_then(|r| r.get_ref().fps.as_ref())
                .map(|f| f.span()),
        }
    }

    /// Returns a diagnostic at the first of `order` that is written in the file, with
    /// the others that are written labelled too; about the whole file when none is.
    fn diagnostic(&self, message: String, order: &[(Option<&Range<usize>>, String)]) -> Diagnostic {
        let mut d: Option<Diagnostic> = None;
        for (span, label) in order {
            let Some(span) = span else { continue };
            d = Some(match d {
                None => Diagnostic::at((*span).clone(), message.clone()).label(label),
                Some(d) => d.also((*span).clone(), label),
            });
        }
        d.unwrap_or_else(|| Diagnostic::whole_file(message))
    }
}

impl Validator {
    /// Returns the step when `dt` is left out, 1/(10·fps): ten steps a frame. An `fps`
    /// so small or so large that this is not a finite positive number (fps = 5e-324
    /// makes it infinite, fps = 1e308 zero) is reported at `fps`.
    pub(super) fn default_dt(&mut self, fps: f64, spans: &TimingSpans) -> Option<f64> {
        let dt = 1.0 / (10.0 * fps);
        if dt.is_finite() && dt > 0.0 {
            return Some(dt);
        }
        let message = format!(
            "with `dt` left out, the step 1/(10·fps) = {} is not a finite number > 0",
            Readable(dt)
        );
        let d = spans.diagnostic(
            message,
            &[(spans.fps.as_ref(), format!("fps = {}", Readable(fps)))],
        );
        self.error(
            d.hint("write `dt` in [simulation], or choose an `fps` between 1e-300 and 1e300"),
        );
        None
    }

    /// Returns the steps between two frames, round(1/(fps·dt)), when it can be counted
    /// exactly; reports it at `dt` otherwise.
    pub(super) fn steps_per_frame(
        &mut self,
        dt: f64,
        fps: f64,
        spans: &TimingSpans,
    ) -> Option<u64> {
        let steps = (1.0 / fps / dt).round().max(1.0);
        if steps <= MAX_STEPS as f64 {
            return Some(steps as u64);
        }
        let interval = 1.0 / fps;
        let d = spans.diagnostic(
            format!(
                "dt = {} makes {} steps a frame, more than the {MAX_STEPS} (2^53) a run can count exactly",
                Readable(dt),
                about(steps)
            ),
            &[
                (spans.dt.as_ref(), format!("{} steps a frame", about(steps))),
                (spans.fps.as_ref(), format!("a frame every {} s", Readable(interval))),
            ],
        );
        self.error(d.hint(format!(
            "time is counted in steps, t = n·dt, and n must stay below 2^53; raise `dt` above {}, and see the limits in docs/scenes.md",
            about(interval / MAX_STEPS as f64),
        )));
        None
    }

    /// Returns the number of frames, floor(duration·fps) + 1, when it is within
    /// [`MAX_FRAMES`]; reports it at `duration` and `fps` otherwise.
    pub(super) fn frame_count(
        &mut self,
        duration: f64,
        fps: f64,
        spans: &TimingSpans,
    ) -> Option<u64> {
        // k = 0 ..= floor(duration·fps).
        let last = (duration * fps * (1.0 + FLOOR_ALLOWANCE)).floor();
        if last + 1.0 <= MAX_FRAMES as f64 {
            return Some(last as u64 + 1);
        }
        let d = spans.diagnostic(
            format!(
                "duration × fps asks for {} frames, more than the limit of {MAX_FRAMES}",
                Readable(last + 1.0)
            ),
            &[
                (spans.duration.as_ref(), format!("{} s", Readable(duration))),
                (
                    spans.fps.as_ref(),
                    format!("× {} frames a second", Readable(fps)),
                ),
            ],
        );
        let defaults = match (&spans.duration, &spans.fps) {
            (None, _) => " (`duration` is 5 s unless given)",
            (_, None) => " (`fps` is 30 unless given)",
            _ => "",
        };
        self.error(d.hint(format!("shorten `duration` or lower `fps`{defaults}")));
        None
    }

    /// Checks that the whole run, every step to the last frame for `bodies` bodies and
    /// for every integrator `compare` adds, can be counted exactly and is within
    /// [`MAX_BODY_STEPS`]; reports it at `dt` otherwise.
    pub(super) fn run_fits(
        &mut self,
        sim: &SimulationSettings,
        fps: f64,
        (steps_per_frame, frame_count): (u64, u64),
        bodies: usize,
        spans: &TimingSpans,
    ) -> Option<()> {
        let steps = u128::from(frame_count - 1) * u128::from(steps_per_frame);
        let runs = 1 + sim
            .compare
            .iter()
            .filter(|c| matches!(c, CompareRun::Integrator(_)))
            .count() as u128;
        // A scene without bodies still steps, so it counts as one.
        let per_step = runs * bodies.max(1) as u128;
        let work = steps * per_step;
        if steps <= u128::from(MAX_STEPS) && work <= u128::from(MAX_BODY_STEPS) {
            return Some(());
        }
        let message = if steps > u128::from(MAX_STEPS) {
            format!(
                "dt = {} makes {} steps to the last frame, more than the {MAX_STEPS} (2^53) a run can count exactly",
                Readable(sim.dt),
                about(steps as f64)
            )
        } else {
            format!(
                "the run needs {work} body-steps ({steps} steps × {bodies} bod{}{}), more than the limit of 10^12",
                if bodies == 1 { "y" } else { "ies" },
                if runs > 1 {
                    format!(" × {runs} runs with `compare`")
                } else {
                    String::new()
                }
            )
        };
        let d = spans.diagnostic(
            message,
            &[
                (
                    spans.dt.as_ref(),
                    format!("{steps_per_frame} steps a frame"),
                ),
                (
                    spans.duration.as_ref(),
                    format!("{} frames after the first", frame_count - 1),
                ),
                (
                    spans.fps.as_ref(),
                    format!("{} frames a second", Readable(fps)),
                ),
            ],
        );
        // The smallest dt that fits: the steps the limit allows for this many bodies,
        // spread over the duration and rounded to a whole number of steps a frame.
        let allowed_steps = (MAX_BODY_STEPS as f64 / per_step as f64).min(MAX_STEPS as f64);
        let frames = (frame_count - 1) as f64;
        let per_frame = (allowed_steps / frames).floor();
        let hint = if per_frame >= 1.0 {
            format!(
                "raise `dt` to {} ({per_frame} steps a frame) or more, shorten `duration`, or use fewer bodies",
                Readable(1.0 / fps / per_frame)
            )
        } else {
            "even one step a frame is too much: shorten `duration`, lower `fps`, or use fewer bodies".to_string()
        };
        self.error(d.hint(hint));
        None
    }
}
