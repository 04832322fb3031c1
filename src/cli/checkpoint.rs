//! `physframes checkpoint`: simulate without drawing and save checkpoints, the first
//! stage of a render spread over several machines.

use std::path::PathBuf;

use clap::Args;

use super::{parse_frames, SceneArgs, Verbosity};
use crate::checkpoint::save_run;
use crate::error::{Error, Result};

#[derive(Debug, Args)]
pub struct CheckpointArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Save a checkpoint every N frames.
    #[arg(long, value_name = "N")]
    every: u64,
    /// The render's output folder; checkpoints go to <out>/checkpoints
    /// [default: output/<scene name>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Where to write checkpoints instead of <out>/checkpoints.
    #[arg(long, value_name = "DIR")]
    checkpoint_dir: Option<PathBuf>,
    /// Simulate only as far as these frames need (the range's end) [default: all].
    #[arg(long, value_name = "RANGE")]
    frames: Option<String>,
}

pub fn run(args: CheckpointArgs, verbosity: Verbosity) -> Result<()> {
    let scene = args.scene.load()?;
    if args.every == 0 {
        return Err(Error::Usage("--every must be at least 1 frame".into()));
    }
    let end = match args.frames.as_deref() {
        Some(f) => parse_frames(f, scene.render.frame_count)?.end,
        None => scene.render.frame_count,
    };
    let dir = args.checkpoint_dir.unwrap_or_else(|| {
        args.out
            .unwrap_or_else(|| PathBuf::from("output").join(&scene.name))
            .join("checkpoints")
    });
    let report = save_run(&scene, &dir, args.every, end)?;
    if report.started_from_frame > 0 {
        verbosity.detail(&format!(
            "started from the checkpoint at frame {}",
            report.started_from_frame
        ));
    }
    if !verbosity.quiet {
        super::say(&format!(
            "wrote {} checkpoint{} of `{}` (every {} frames, through frame {}) to {}\n",
            report.written,
            if report.written == 1 { "" } else { "s" },
            scene.name,
            args.every,
            end - 1,
            dir.display()
        ))?;
    }
    Ok(())
}
