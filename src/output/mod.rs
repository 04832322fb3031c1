//! Files: atomic writes, frame naming, stale frames, and the manifest.
//!
//! A file physframes writes is either absent or complete: each is written to a
//! temporary file in the same folder and renamed into place, so an interrupted run
//! never leaves a half-written frame behind; Ctrl-C removes the temporary file too
//! ([`TempFile`], [`crate::interrupt`]). A device or pipe is written in place
//! ([`Output`], in `file.rs`).

pub mod apng;
mod csv;
pub mod events;
mod file;
mod manifest;
mod resume;
pub mod video;

use std::path::{Path, PathBuf};

pub use csv::write_trajectory;
pub use events::{EventLog, EVENTS_HEADER};
pub use file::{temp_file_beside, write_atomic, Output, TempFile};
pub use manifest::{Failure, Manifest, Timings};
pub use resume::reusable_frames;

use crate::error::{Error, Result};

/// Returns the file name of frame `k`: `frame_000042.png`.
pub fn frame_file_name(k: u64) -> String {
    format!("frame_{k:06}.png")
}

/// Returns the frame number a file name stands for, if it names a frame.
pub fn parse_frame_file_name(name: &str) -> Option<u64> {
    let digits = name.strip_prefix("frame_")?.strip_suffix(".png")?;
    if digits.len() < 6 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

/// Lists the frame files in `dir`, with their numbers, in increasing order.
pub fn list_frames(dir: &Path) -> Result<Vec<(u64, PathBuf)>> {
    let mut frames = Vec::new();
    let entries = match std::fs::read_dir(dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(frames),
        Err(e) => return Err(Error::io("cannot list", dir, e)),
    };
    for entry in entries {
        let entry = entry.map_err(|e| Error::io("cannot list", dir, e))?;
        if let Some(k) = entry.file_name().to_str().and_then(parse_frame_file_name) {
            frames.push((k, entry.path()));
        }
    }
    frames.sort();
    Ok(frames)
}

/// Removes the frame files whose number satisfies `stale`, and any temporary file a
/// killed run left behind. Returns how many frames were removed.
pub fn remove_frames(dir: &Path, stale: impl Fn(u64) -> bool) -> Result<usize> {
    let mut removed = 0;
    for (k, path) in list_frames(dir)? {
        if stale(k) {
            std::fs::remove_file(&path).map_err(|e| Error::io("cannot remove", path, e))?;
            removed += 1;
        }
    }
    if let Ok(entries) = std::fs::read_dir(dir) {
        for entry in entries.flatten() {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            if name.starts_with(".physframes-") && name.ends_with(".tmp") {
                // A leftover temporary file is never a frame; failing to remove one
                // is harmless, so the error is ignored.
                let _ = std::fs::remove_file(entry.path());
            }
        }
    }
    Ok(removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_names_round_trip() {
        assert_eq!(frame_file_name(0), "frame_000000.png");
        assert_eq!(frame_file_name(999_999), "frame_999999.png");
        assert_eq!(parse_frame_file_name("frame_000042.png"), Some(42));
        assert_eq!(parse_frame_file_name("frame_42.png"), None);
        assert_eq!(parse_frame_file_name("frame_00004x.png"), None);
        assert_eq!(parse_frame_file_name("manifest.json"), None);
    }
}
