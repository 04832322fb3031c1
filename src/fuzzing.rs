//! What the fuzz target (`fuzz/`) and the mutated-scene tests do with one input, so that
//! both hold physframes to the same promises: any text, with any `--set` overrides, is
//! either refused with located errors that render without panicking, or simulated and
//! drawn; nothing panics, and no frame is written behind an error of bad input.
//!
//! An input is a scene file whose last lines may be `#set KEY=VALUE` comments, each
//! taken as a `--set` argument ([`split_overrides`]); the file stays valid TOML, so a
//! fuzzer's dictionary can add overrides to any scene.
//!
//! A scene that validates is drawn at most 200 × 150 pixels (its aspect kept) with
//! every layer it has: bodies, trails, arrows, springs, axes, fields, curves, the HUD
//! and compared runs. Frame 0 is always drawn; frame 1 too when the steps to it are
//! few ([`STEP_BUDGET`]), so that a scene that validates but asks for hours of
//! computing is still drawn at once.

use std::path::Path;

use crate::error::Error;
use crate::pipeline::{self, RenderOptions};
use crate::render::Compression;
use crate::scene::{parse_with_overrides, CompareRun, Scene};

/// The prefix of a line that carries a `--set` argument.
pub const SET_PREFIX: &str = "#set ";

/// The most body-steps spent to reach frame 1; past it only frame 0 is drawn.
pub const STEP_BUDGET: u64 = 200_000;

/// The most pixels a drawn frame has.
const MAX_PIXELS: f64 = 200.0 * 150.0;

/// What became of one input.
#[derive(Debug)]
pub enum Outcome {
    /// The scene was refused; the rendered diagnostics.
    Refused(String),
    /// The scene was drawn: frames 0..`frames`, or the render stopped with an error
    /// (a blow-up is a correct outcome for a scene that is unstable).
    Drawn {
        frames: u64,
        result: Result<(), Error>,
    },
}

/// Returns the `--set` arguments of a scene's trailing `#set KEY=VALUE` lines, in
/// order; the lines stay in the text, where TOML reads them as comments.
pub fn split_overrides(text: &str) -> Vec<String> {
    text.lines()
        .rev()
        .take_while(|l| l.starts_with(SET_PREFIX) || l.trim().is_empty())
        .filter_map(|l| l.strip_prefix(SET_PREFIX))
        .map(str::to_string)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect()
}

/// Parses `text` with its overrides; refused, renders the diagnostics; valid, draws
/// frame 0 (and frame 1 within [`STEP_BUDGET`]) small, into `out` through the render
/// pipeline when given, else in memory as `physframes figure` does.
pub fn exercise(text: &str, out: Option<&Path>) -> Outcome {
    let overrides = split_overrides(text);
    let mut scene = match parse_with_overrides(Path::new("fuzz.toml"), text, &overrides) {
        Ok(scene) => scene,
        Err(e) => return Outcome::Refused(e.render()),
    };
    shrink(&mut scene);
    let frames = frames_within_budget(&scene);
    let result = match out {
        Some(dir) => pipeline::render(
            &scene,
            &RenderOptions {
                out_dir: dir.to_path_buf(),
                frames: Some(0..frames),
                threads: 1,
                compression: Compression::Fastest,
                progress: false,
            },
        )
        .map(drop),
        None => (0..frames).try_for_each(|k| {
            crate::figures::render_png(&scene, k, Compression::Fastest).map(drop)
        }),
    };
    Outcome::Drawn { frames, result }
}

/// Scales the image down to at most [`MAX_PIXELS`], keeping its aspect.
fn shrink(scene: &mut Scene) {
    let r = &mut scene.render;
    let pixels = f64::from(r.width) * f64::from(r.height);
    if pixels > MAX_PIXELS {
        let s = (MAX_PIXELS / pixels).sqrt();
        r.width = ((f64::from(r.width) * s) as u32).max(1);
        r.height = ((f64::from(r.height) * s) as u32).max(1);
    }
}

/// Returns 2 when frame 1 is within [`STEP_BUDGET`] body-steps of the start (for every
/// compared run too), else 1.
fn frames_within_budget(scene: &Scene) -> u64 {
    if scene.render.frame_count < 2 {
        return 1;
    }
    let runs = 1 + scene
        .simulation
        .compare
        .iter()
        .filter(|c| matches!(c, CompareRun::Integrator(_)))
        .count() as u64;
    let bodies = scene.bodies.len().max(1) as u64;
    // An adaptive method takes steps of at most dt, and may take many more: it is given
    // a hundredth of the budget.
    let adaptive = scene.simulation.integrator.is_adaptive()
        || scene
            .simulation
            .compare
            .iter()
            .any(|c| matches!(c, CompareRun::Integrator(k) if k.is_adaptive()));
    let budget = if adaptive {
        STEP_BUDGET / 100
    } else {
        STEP_BUDGET
    };
    let cost = u128::from(scene.render.steps_per_frame) * u128::from(runs * bodies);
    if cost <= u128::from(budget) {
        2
    } else {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trailing_set_lines_are_overrides_in_order() {
        let text = "[render]\nfps = 10\n#set a=1\n\n#set b.c=[0, 1]\n";
        assert_eq!(split_overrides(text), vec!["a=1", "b.c=[0, 1]"]);
        // A `#set` line followed by a line of the scene is a comment, not an override.
        assert!(split_overrides("#set a=1\n[render]\n").is_empty());
    }
}
