//! `physframes figure`: one frame of a built-in figure or of any scene, as one PNG.

use std::path::PathBuf;

use clap::Args;

use crate::error::{Error, Result};
use crate::figures::{self, BUILT_INS};
use crate::output;
use crate::render::Compression;
use crate::scene::MAX_IMAGE_SIDE;

#[derive(Debug, Args)]
pub struct FigureArgs {
    /// A built-in figure (see --list) or a scene file.
    #[arg(required_unless_present = "list")]
    name: Option<String>,
    /// The PNG to write [default: output/figures/<scene name>.png].
    #[arg(long, value_name = "FILE.png")]
    out: Option<PathBuf>,
    /// The image size, overriding the scene's; text and lines scale with it.
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// The frame to draw [default: the scene's last, so traces and trails are complete].
    #[arg(long, value_name = "K")]
    frame: Option<u64>,
    /// List the built-in figures.
    #[arg(long, conflicts_with_all = ["out", "size", "frame"])]
    list: bool,
}

pub fn run(args: FigureArgs) -> Result<()> {
    if args.list {
        let mut text = String::new();
        for b in BUILT_INS {
            text.push_str(&format!(
                "{:<12}  {}  ({})\n",
                b.name, b.description, b.path
            ));
        }
        return super::say(&text);
    }
    let name = args.name.as_deref().unwrap_or_default();
    let mut scene = figures::load(name)?;
    if let Some(size) = &args.size {
        let (w, h) = parse_size(size)?;
        scene.render.width = w;
        scene.render.height = h;
    }
    let frame = args
        .frame
        .unwrap_or(scene.render.frame_count.saturating_sub(1));
    let png = figures::render_png(&scene, frame, Compression::Fast)?;
    let out = args.out.unwrap_or_else(|| {
        PathBuf::from("output")
            .join("figures")
            .join(format!("{}.png", scene.name))
    });
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| Error::io("cannot create", dir, e))?;
    }
    output::write_atomic(&out, &png)?;
    super::say(&format!(
        "wrote {} ({}×{}, frame {frame})\n",
        out.display(),
        scene.render.width,
        scene.render.height
    ))
}

/// Parses `WxH` with both sides from 1 to the largest image side.
fn parse_size(text: &str) -> Result<(u32, u32)> {
    let bad = || {
        Error::Usage(format!(
            "--size `{text}` is not WxH with sides from 1 to {MAX_IMAGE_SIDE}, e.g. 1600x1200"
        ))
    };
    let (w, h) = text.split_once(['x', 'X', '×']).ok_or_else(bad)?;
    let side = |s: &str| {
        s.trim()
            .parse::<i64>()
            .ok()
            .filter(|v| (1..=MAX_IMAGE_SIDE).contains(v))
            .map(|v| v as u32)
            .ok_or_else(bad)
    };
    Ok((side(w)?, side(h)?))
}

#[cfg(test)]
mod tests {
    use super::parse_size;

    #[test]
    fn sizes_are_width_x_height() {
        assert_eq!(parse_size("1600x1200").ok(), Some((1600, 1200)));
        assert_eq!(parse_size("640×480").ok(), Some((640, 480)));
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("800").is_err());
        assert!(parse_size("99999x10").is_err());
    }
}
