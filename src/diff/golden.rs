//! Golden-image tests: a rendered image compared with its reference under
//! `tests/golden/`, the expected | difference | actual image written on a mismatch, and
//! references rewritten only when `UPDATE_GOLDEN=1` asks.

use std::path::{Path, PathBuf};

use super::*;

/// Where golden-test failures are written: a git-ignored folder in the crate.
pub const GOLDEN_FAILURES_DIR: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden-failures");

/// What [`check_golden_with`] does with the reference image.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GoldenMode {
    /// Compare against the reference and fail on a mismatch.
    Compare,
    /// (Re)write the reference from the actual image.
    Update,
}

impl GoldenMode {
    /// `Update` when the environment variable `UPDATE_GOLDEN` is `1`, else `Compare`.
    pub fn from_env() -> Self {
        if std::env::var_os("UPDATE_GOLDEN").is_some_and(|v| v == "1") {
            GoldenMode::Update
        } else {
            GoldenMode::Compare
        }
    }
}

/// Why a golden test failed.
#[derive(Debug, thiserror::Error)]
pub enum GoldenError {
    /// There is no reference image yet.
    #[error("the reference image {} does not exist; run with UPDATE_GOLDEN=1 to create it", reference.display())]
    MissingReference {
        /// The reference path.
        reference: PathBuf,
    },
    /// Too many pixels differ.
    #[error(
        "{} of {} pixels differ from {} by more than {} (at most {} may; largest channel difference {}); expected | difference | actual written to {}",
        pixels.differing_pixels,
        pixels.total_pixels,
        reference.display(),
        options.threshold,
        options.max_pixels,
        pixels.max_channel_delta,
        diff.display()
    )]
    Mismatch {
        /// The reference path.
        reference: PathBuf,
        /// The counts.
        pixels: PixelDiff,
        /// The limits.
        options: DiffOptions,
        /// Where the diff image was written.
        diff: PathBuf,
    },
    /// The images could not be compared.
    #[error(transparent)]
    Input(#[from] DiffError),
}

/// Checks a rendered PNG against its reference image, for tests.
///
/// With `UPDATE_GOLDEN=1` in the environment the reference is (re)written. Otherwise a
/// mismatch writes expected | difference | actual to `tests/golden-failures/` under the
/// reference's file name and returns an error that gives the counts and that path.
pub fn check_golden(
    reference: &Path,
    actual_png: &[u8],
    threshold: u8,
    max_pixels: u64,
) -> Result<(), GoldenError> {
    let options = DiffOptions {
        threshold,
        max_pixels,
    };
    check_golden_with(
        reference,
        actual_png,
        &options,
        GoldenMode::from_env(),
        Path::new(GOLDEN_FAILURES_DIR),
    )
}

/// [`check_golden`] with the mode and the failures folder given explicitly.
pub fn check_golden_with(
    reference: &Path,
    actual_png: &[u8],
    options: &DiffOptions,
    mode: GoldenMode,
    failures_dir: &Path,
) -> Result<(), GoldenError> {
    let actual = decode_png(actual_png, Path::new("<actual image>"))?;
    if mode == GoldenMode::Update {
        write_atomic(reference, actual_png)?;
        return Ok(());
    }
    if !reference.exists() {
        return Err(GoldenError::MissingReference {
            reference: reference.to_owned(),
        });
    }
    let expected = load_png(reference)?;
    let name = reference
        .file_name()
        .map_or_else(|| "golden.png".into(), |n| n.to_string_lossy().into_owned());
    let size_error = |mismatch| DiffError::SizeMismatch {
        name: name.clone(),
        mismatch,
    };
    let pixels = compare_images(&expected, &actual, options.threshold).map_err(size_error)?;
    let diff_path = failures_dir.join(&name);
    if pixels.differing_pixels <= options.max_pixels {
        // A stale failure image from an earlier run would only mislead.
        let _ = std::fs::remove_file(&diff_path);
        return Ok(());
    }
    let image = diff_image(&expected, &actual, options.threshold).map_err(size_error)?;
    let expected_bytes = std::fs::read(reference).unwrap_or_default();
    let chunks = diff_provenance(reference, &expected_bytes, Path::new("<actual image>"));
    write_diff_png(&image, &diff_path, &chunks)?;
    Err(GoldenError::Mismatch {
        reference: reference.to_owned(),
        pixels,
        options: *options,
        diff: diff_path,
    })
}
