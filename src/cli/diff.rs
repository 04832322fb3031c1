//! `physframes diff`: compare two PNGs, or two folders of frames, pixel by pixel.

use std::path::PathBuf;

use clap::Args;

use crate::diff::{diff_paths, DiffError, DiffOptions, DiffOutcome};
use crate::error::{Error, Result};

#[derive(Debug, Args)]
pub struct DiffArgs {
    /// The expected PNG file, or a folder of frames.
    expected: PathBuf,
    /// The actual PNG file, or a folder of frames with the same names.
    actual: PathBuf,
    /// A pixel differs when some channel differs by more than this (0 to 255).
    #[arg(long, value_name = "N", default_value_t = 0)]
    threshold: u8,
    /// A frame passes when at most this many of its pixels differ.
    #[arg(long, value_name = "N", default_value_t = 0)]
    max_pixels: u64,
    /// Write expected | difference | actual here: a PNG for two files, a folder (one
    /// image per failing frame) for two folders.
    #[arg(long, value_name = "DIFF.png")]
    out: Option<PathBuf>,
}

pub fn run(args: DiffArgs) -> Result<()> {
    let options = DiffOptions {
        threshold: args.threshold,
        max_pixels: args.max_pixels,
    };
    let outcome = diff_paths(&args.expected, &args.actual, &options, args.out.as_deref()).map_err(
        |e| match e {
            // A diff image that cannot be written is a failure at run time; anything
            // else means the input cannot be compared.
            DiffError::Write { .. } => Error::Runtime(e.to_string()),
            _ => Error::Usage(e.to_string()),
        },
    )?;
    super::say(&report(&outcome, &options))?;
    match outcome {
        DiffOutcome::Within { .. } => Ok(()),
        DiffOutcome::Different { frames } => {
            let failing = frames.iter().filter(|f| !f.within).count();
            Err(Error::Runtime(format!(
                "{failing} of {} frame{} differ by more than {} pixel{} (threshold {})",
                frames.len(),
                if frames.len() == 1 { "" } else { "s" },
                options.max_pixels,
                if options.max_pixels == 1 { "" } else { "s" },
                options.threshold
            )))
        }
    }
}

/// One line per frame with differing pixels, then a summary.
fn report(outcome: &DiffOutcome, options: &DiffOptions) -> String {
    let mut text = String::new();
    for f in outcome.frames() {
        if f.pixels.differing_pixels > 0 || !f.within {
            text.push_str(&format!(
                "{} {}: {} of {} pixels differ (largest channel difference {})\n",
                if f.within { "within" } else { "DIFFERENT" },
                f.name,
                f.pixels.differing_pixels,
                f.pixels.total_pixels,
                f.pixels.max_channel_delta
            ));
        }
    }
    let frames = outcome.frames();
    let within = frames.iter().filter(|f| f.within).count();
    text.push_str(&format!(
        "{within} of {} frame{} within tolerance (threshold {}, at most {} differing pixels)\n",
        frames.len(),
        if frames.len() == 1 { "" } else { "s" },
        options.threshold,
        options.max_pixels
    ));
    text
}
