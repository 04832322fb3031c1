//! `--resume`: which frames already in the folder an interrupted run finished.
//!
//! Frames are written atomically, so a frame file that exists is complete. It is kept
//! only when it is the very frame this run would write: its size is the scene's, and
//! its provenance chunks (scene hash, integrator, dt, t, frame number, program
//! version) are exactly those this run would write into it. Anything else (a frame of
//! an edited scene, of other `--set` overrides or of another integrator) is drawn
//! again.

use std::collections::BTreeSet;
use std::io::BufReader;
use std::ops::Range;
use std::path::Path;

use crate::error::Result;
use crate::render::Provenance;

use super::list_frames;

/// Returns the frames in `range` found in `dir` that can be kept: `width` × `height`
/// PNGs whose text chunks equal `expected(k)`.
pub fn reusable_frames(
    dir: &Path,
    range: Range<u64>,
    width: u32,
    height: u32,
    expected: impl Fn(u64) -> Provenance,
) -> Result<BTreeSet<u64>> {
    let mut keep = BTreeSet::new();
    for (k, path) in list_frames(dir)? {
        if range.contains(&k) && frame_matches(&path, width, height, &expected(k)) {
            keep.insert(k);
        }
    }
    Ok(keep)
}

/// Returns true when the PNG at `path` has the given size and text chunks. Reading
/// stops at the image data: the chunks come before it.
fn frame_matches(path: &Path, width: u32, height: u32, expected: &Provenance) -> bool {
    let Ok(file) = std::fs::File::open(path) else {
        return false;
    };
    let decoder = png::Decoder::new(BufReader::new(file));
    let Ok(reader) = decoder.read_info() else {
        return false;
    };
    let info = reader.info();
    if (info.width, info.height) != (width, height) {
        return false;
    }
    let chunks: Vec<(String, String)> = info
        .utf8_text
        .iter()
        .filter_map(|c| Some((c.keyword.clone(), c.get_text().ok()?)))
        .collect();
    chunks == expected.entries
}
