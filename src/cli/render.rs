//! `physframes render`.

use std::io::IsTerminal;
use std::path::PathBuf;

use clap::Args;

use super::{parse_frames, SceneArgs};
use crate::error::{Error, Result};
use crate::pipeline::{self, RenderOptions};
use crate::render::Compression;

#[derive(Debug, Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// The output folder [default: output/<scene name>].
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
    /// Render only these frames: A..B (B excluded), A..=B, A.., ..B or A. The
    /// simulation still starts at t = 0; other frames in the folder are left alone.
    #[arg(long, value_name = "RANGE")]
    frames: Option<String>,
    /// Threads that draw and encode frames [default: one per core].
    #[arg(long, value_name = "N", default_value_t = 0)]
    threads: usize,
    /// PNG compression: fastest, fast or best.
    #[arg(long, value_name = "LEVEL", default_value = "fast")]
    compression: String,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: RenderArgs) -> Result<()> {
    let scene = args.scene.load()?;
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
    let options = RenderOptions {
        out_dir,
        frames,
        threads: args.threads,
        compression,
        progress: !args.quiet && std::io::stderr().is_terminal(),
    };
    let report = pipeline::render(&scene, &options)?;
    if !args.quiet {
        let m = &report.manifest;
        let t = &m.timings;
        super::say(&format!(
            "wrote {} frames of `{}` ({}×{}) to {} in {:.2} s (simulate {:.3} s, draw {:.3} s, encode {:.3} s, write {:.3} s)\n",
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
