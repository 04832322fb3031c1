//! `physframes render`.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;

use super::{parse_frames, SceneArgs, Verbosity};
use crate::checkpoint::{self, CheckpointOptions};
use crate::error::{Error, Result};
use crate::memory;
use crate::output::{apng, video};
use crate::pipeline::{self, RenderExtras, RenderOptions};
use crate::render::Compression;

#[derive(Debug, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The output folder [default: output/<scene name>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Render only these frames: A..B (B excluded), A..=B, A.., ..B or A. The
    /// simulation starts at t = 0, or at the nearest checkpoint; other frames in the
    /// folder are left alone.
    #[arg(long, value_name = "RANGE")]
    frames: Option<String>,
    /// Threads that draw and encode frames [default: one per core, as many as fit in
    /// memory].
    #[arg(long, value_name = "N", default_value_t = 0, hide_default_value = true)]
    threads: usize,
    /// PNG compression: fastest, fast or best.
    #[arg(long, value_name = "LEVEL", default_value = "fast")]
    compression: String,
    /// Keep the frames an interrupted run of the same scene and settings finished, and
    /// draw only the rest; the result is the same bytes as an uninterrupted run.
    #[arg(long)]
    resume: bool,
    /// Save the simulation's exact state every N frames, so that a later run of a
    /// frame range (a shard) starts from the nearest checkpoint instead of t = 0.
    #[arg(long, value_name = "N")]
    checkpoint_every: Option<u64>,
    /// Where checkpoints are read and written [default: <out>/checkpoints].
    #[arg(long, value_name = "DIR")]
    checkpoint_dir: Option<PathBuf>,
    /// Also write the frames as one lossless animated PNG.
    #[arg(long, value_name = "FILE")]
    apng: Option<PathBuf>,
    /// Also write the collision log to this CSV file: one row per impulse,
    /// `t,a,b,px,py,nx,ny,vn_before,vn_after,impulse,jt`, in the order applied, for the
    /// steps this run simulates (from t = 0, or from the checkpoint it starts at).
    #[arg(long, value_name = "FILE")]
    events: Option<PathBuf>,
    /// Also encode the frames as an MP4 video with ffmpeg, which must be on PATH.
    #[arg(long, value_name = "FILE")]
    mp4: Option<PathBuf>,
}

pub fn run(args: RenderArgs, verbosity: Verbosity) -> Result<()> {
    let scene = args.scene.load()?;
    // Everything that can be refused is refused before a frame is drawn.
    let ffmpeg = match &args.mp4 {
        Some(_) => Some(video::find_ffmpeg().ok_or_else(video::ffmpeg_missing)?),
        None => None,
    };
    let compression = args
        .compression
        .parse::<Compression>()
        .map_err(Error::Usage)?;
    let frames = args
        .frames
        .as_deref()
        .map(|f| parse_frames(f, scene.render.frame_count))
        .transpose()?;
    let out_dir = args
        .out
        .unwrap_or_else(|| PathBuf::from("output").join(&scene.name));
    if args.checkpoint_every == Some(0) {
        return Err(Error::Usage(
            "--checkpoint-every must be at least 1 frame".into(),
        ));
    }
    if args.checkpoint_every.is_some() {
        checkpoint::supports(scene.simulation.integrator).map_err(Error::Usage)?;
    }
    let checkpoints = CheckpointOptions {
        dir: args
            .checkpoint_dir
            .unwrap_or_else(|| out_dir.join("checkpoints")),
        every: args.checkpoint_every,
    };
    let available = memory::available();
    let threads = memory::plan_threads(&scene, args.threads, available)?;
    verbosity.detail(&format!(
        "scene `{}`: hash {}",
        scene.name, scene.source.hash
    ));
    for o in &scene.source.overrides {
        verbosity.detail(&format!("override: --set {o}"));
    }
    verbosity.detail(&format!(
        "{threads} drawing thread{}; memory needed about {}{}",
        if threads == 1 { "" } else { "s" },
        memory::human(memory::Estimate::of(&scene).total(threads)),
        available.map_or_else(String::new, |a| format!(
            " of {} available",
            memory::human(a)
        ))
    ));
    let options = RenderOptions {
        out_dir,
        frames,
        threads,
        compression,
        progress: !verbosity.quiet && std::io::stderr().is_terminal(),
    };
    let extras = RenderExtras {
        resume: args.resume,
        checkpoints: Some(checkpoints),
        events: args.events.clone(),
    };
    let report = pipeline::render_with(&scene, &options, &extras)?;
    let m = &report.manifest;
    if m.started_from_frame > 0 {
        verbosity.detail(&format!(
            "started from the checkpoint at frame {} instead of t = 0",
            m.started_from_frame
        ));
    }
    if m.checkpoints_written > 0 {
        verbosity.detail(&format!(
            "wrote {} checkpoint{} to {}",
            m.checkpoints_written,
            if m.checkpoints_written == 1 { "" } else { "s" },
            extras
                .checkpoints
                .as_ref()
                .map_or_else(String::new, |c| c.dir.display().to_string())
        ));
    }
    let range = m.frames_requested[0]..m.frames_requested[1];
    let mut wrote_also = Vec::new();
    if let Some(path) = &args.apng {
        apng::write_apng(&options.out_dir, range.clone(), scene.render.fps, path)?;
        wrote_also.push(path.display().to_string());
    }
    if let (Some(path), Some(ffmpeg)) = (&args.mp4, &ffmpeg) {
        video::write_mp4(ffmpeg, &options.out_dir, range, scene.render.fps, path)?;
        wrote_also.push(path.display().to_string());
    }
    if !verbosity.quiet {
        let t = &m.timings;
        let kept = if m.frames_reused > 0 {
            format!(" (kept {} already complete)", m.frames_reused)
        } else {
            String::new()
        };
        let also = if wrote_also.is_empty() {
            String::new()
        } else {
            format!(" and {}", wrote_also.join(" and "))
        };
        super::say(&format!(
            "wrote {} frames of `{}` ({}×{}) to {}{kept}{also} in {:.2} s (simulate {:.3} s, draw {:.3} s, encode {:.3} s, write {:.3} s)\n",
            m.frames_written,
            m.scene,
            m.width,
            m.height,
            options.out_dir.display(),
            t.wall_s,
            t.simulate_s,
            t.draw_s,
            t.encode_s,
            t.write_s
        ))?;
    }
    Ok(())
}
