//! `--mp4 FILE`: the rendered frames piped, in order, to ffmpeg.
//!
//! physframes does not encode video itself; it finds `ffmpeg` on PATH before rendering
//! anything (and stops with exit code 2 when there is none), then after the render
//! writes each frame file's PNG bytes to ffmpeg's standard input. ffmpeg writes to a
//! temporary file that is renamed into place, so the video is absent or complete.

use std::io::{Read, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::error::{Error, Result};

use super::frame_file_name;

/// Returns the path of `ffmpeg` on PATH, if there is one.
pub fn find_ffmpeg() -> Option<PathBuf> {
    let name = if cfg!(windows) {
        "ffmpeg.exe"
    } else {
        "ffmpeg"
    };
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path)
        .map(|dir| dir.join(name))
        .find(|candidate| is_executable(candidate))
}

/// Returns the error for `--mp4` without ffmpeg.
pub fn ffmpeg_missing() -> Error {
    Error::Usage(
        "--mp4 needs ffmpeg, and no `ffmpeg` was found on PATH; nothing was rendered\nhint: install ffmpeg (e.g. `apt install ffmpeg` or `brew install ffmpeg`), or use --apng FILE, which needs nothing else".into(),
    )
}

#[cfg(unix)]
fn is_executable(path: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(path).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(path: &Path) -> bool {
    path.is_file()
}

/// Encodes frames `frames` of `dir` into the MP4 file `out` at `fps` with `ffmpeg`:
/// H.264 (or ffmpeg's default MP4 codec), yuv420p so that every player can show it,
/// sides padded to even numbers as yuv420p needs.
pub fn write_mp4(
    ffmpeg: &Path,
    dir: &Path,
    frames: Range<u64>,
    fps: f64,
    out: &Path,
) -> Result<()> {
    let tmp = super::Output::create(out)?;
    let mut child = Command::new(ffmpeg)
        .args(["-hide_banner", "-loglevel", "error", "-y"])
        .args(["-f", "image2pipe", "-c:v", "png", "-framerate"])
        .arg(fps.to_string())
        .args(["-i", "-"])
        .args([
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
            "-pix_fmt",
            "yuv420p",
        ])
        .args(["-movflags", "+faststart", "-f", "mp4"])
        .arg(tmp.writing_path())
        .stdin(Stdio::piped())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| Error::io("cannot run", ffmpeg, e))?;
    // ffmpeg's messages are read on another thread, so that neither side can block the
    // other on a full pipe.
    let stderr = child.stderr.take();
    let messages = std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(mut s) = stderr {
            let _ = s.read_to_string(&mut text);
        }
        text
    });
    let mut piped = Ok(());
    if let Some(mut stdin) = child.stdin.take() {
        for k in frames {
            let path = dir.join(frame_file_name(k));
            let bytes = std::fs::read(&path).map_err(|e| Error::io("cannot read", path, e))?;
            if let Err(e) = stdin.write_all(&bytes) {
                // ffmpeg stopped reading; its own message says why.
                piped = Err(e);
                break;
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| Error::io("cannot wait for", ffmpeg, e))?;
    let messages = messages.join().unwrap_or_default();
    if !status.success() || piped.is_err() {
        return Err(Error::Runtime(format!(
            "ffmpeg could not write {} ({status}): {}",
            out.display(),
            messages.trim()
        )));
    }
    tmp.finish()
        .map_err(|e| Error::io("cannot move the finished file to", out, e))?;
    Ok(())
}
