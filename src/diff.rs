//! Golden-image comparison: the library behind `physframes diff` and the golden tests.
//!
//! Two PNGs are decoded to 8-bit RGBA and compared channel by channel. A pixel differs
//! when any of its four channels differs by more than `threshold`; a frame passes when
//! at most `max_pixels` of its pixels differ. Folders of frames are matched by file name.
//!
//! The outcome is typed so a command line can map it to exit codes: a comparison that
//! ran returns [`DiffOutcome::Within`] (exit 0) or [`DiffOutcome::Different`] (exit 1),
//! and input that cannot be compared (a missing or undecodable file, a size mismatch,
//! frames present on one side only) is a [`DiffError`] (exit 2).
//!
//! A diff image is laid out expected | difference | actual; the difference panel shows
//! differing pixels in magenta over a faded grey copy of the expected image, as resvg's
//! reference-image harness does. Images are written atomically: to a temporary file in
//! the destination folder, then renamed over the destination.

use std::collections::BTreeSet;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use image::{ImageEncoder, Rgba, RgbaImage};

/// How strictly two images are compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct DiffOptions {
    /// A pixel differs when any channel differs by more than this.
    pub threshold: u8,
    /// A frame passes when at most this many pixels differ.
    pub max_pixels: u64,
}

/// The comparison of one pair of same-sized images.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct PixelDiff {
    /// Pixels with some channel differing by more than the threshold.
    pub differing_pixels: u64,
    /// Pixels in each image.
    pub total_pixels: u64,
    /// The largest difference in any channel of any pixel.
    pub max_channel_delta: u8,
}

/// The comparison of one frame, named by its file name.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameDiff {
    /// The frame's file name.
    pub name: String,
    /// The pixel counts.
    pub pixels: PixelDiff,
    /// Whether at most `max_pixels` pixels differ.
    pub within: bool,
}

/// The result of a comparison that could be carried out.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DiffOutcome {
    /// Every frame is within the limits. Holds every frame, sorted by name.
    Within {
        /// Per-frame counts.
        frames: Vec<FrameDiff>,
    },
    /// At least one frame has more differing pixels than allowed. Holds every frame,
    /// sorted by name; the failing ones have `within == false`.
    Different {
        /// Per-frame counts.
        frames: Vec<FrameDiff>,
    },
}

impl DiffOutcome {
    fn from_frames(frames: Vec<FrameDiff>) -> Self {
        if frames.iter().all(|f| f.within) {
            DiffOutcome::Within { frames }
        } else {
            DiffOutcome::Different { frames }
        }
    }

    /// Every compared frame, sorted by name.
    pub fn frames(&self) -> &[FrameDiff] {
        match self {
            DiffOutcome::Within { frames } | DiffOutcome::Different { frames } => frames,
        }
    }

    /// The frames with more differing pixels than allowed.
    pub fn failing(&self) -> impl Iterator<Item = &FrameDiff> {
        self.frames().iter().filter(|f| !f.within)
    }

    /// The documented exit code: 0 when within the limits, 1 when different.
    pub fn exit_code(&self) -> u8 {
        match self {
            DiffOutcome::Within { .. } => 0,
            DiffOutcome::Different { .. } => 1,
        }
    }
}

/// Two images that cannot be compared because their sizes differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected is {}×{} pixels but actual is {}×{}", expected.0, expected.1, actual.0, actual.1)]
pub struct SizeMismatch {
    /// Width and height of the expected image.
    pub expected: (u32, u32),
    /// Width and height of the actual image.
    pub actual: (u32, u32),
}

/// Input that cannot be compared, or a diff image that cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum DiffError {
    /// A file or folder cannot be read.
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// A file is not a decodable PNG.
    #[error("cannot decode {} as a PNG: {source}", path.display())]
    Decode {
        /// The path.
        path: PathBuf,
        /// Why.
        source: image::ImageError,
    },
    /// Two frames with the same name have different sizes.
    #[error("{name}: {mismatch}")]
    SizeMismatch {
        /// The frame's name.
        name: String,
        /// The two sizes.
        mismatch: SizeMismatch,
    },
    /// The folders do not hold the same frame names.
    #[error(
        "the folders hold different frames: missing from actual [{}], extra in actual [{}]",
        missing.join(", "),
        extra.join(", ")
    )]
    FrameSetMismatch {
        /// Names present only in the expected folder.
        missing: Vec<String>,
        /// Names present only in the actual folder.
        extra: Vec<String>,
    },
    /// One path is a folder and the other is not.
    #[error("{} and {} must both be PNG files or both be folders", expected.display(), actual.display())]
    KindMismatch {
        /// The expected path.
        expected: PathBuf,
        /// The actual path.
        actual: PathBuf,
    },
    /// A folder holds no PNG files.
    #[error("{} holds no .png frames", path.display())]
    NoFrames {
        /// The folder.
        path: PathBuf,
    },
    /// A diff image cannot be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The path.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl DiffError {
    /// The documented exit code for input that cannot be compared.
    pub const EXIT_CODE: u8 = 2;
}

/// Compares two images pixel by pixel.
pub fn compare_images(
    expected: &RgbaImage,
    actual: &RgbaImage,
    threshold: u8,
) -> Result<PixelDiff, SizeMismatch> {
    check_sizes(expected, actual)?;
    let mut diff = PixelDiff {
        total_pixels: u64::from(expected.width()) * u64::from(expected.height()),
        ..PixelDiff::default()
    };
    for (e, a) in expected.pixels().zip(actual.pixels()) {
        let delta = channel_delta(e, a);
        diff.max_channel_delta = diff.max_channel_delta.max(delta);
        if delta > threshold {
            diff.differing_pixels += 1;
        }
    }
    Ok(diff)
}

/// Builds the image expected | difference | actual, with a 4-pixel grey gap between the
/// panels. In the difference panel, differing pixels are magenta and the rest is a faded
/// grey copy of the expected image.
pub fn diff_image(
    expected: &RgbaImage,
    actual: &RgbaImage,
    threshold: u8,
) -> Result<RgbaImage, SizeMismatch> {
    check_sizes(expected, actual)?;
    const GAP: u32 = 4;
    const GAP_COLOR: Rgba<u8> = Rgba([128, 128, 128, 255]);
    const MARK: Rgba<u8> = Rgba([255, 0, 255, 255]);
    let (w, h) = expected.dimensions();
    let mut out = RgbaImage::from_pixel(3 * w + 2 * GAP, h, GAP_COLOR);
    for (x, y, e) in expected.enumerate_pixels() {
        let a = actual.get_pixel(x, y);
        out.put_pixel(x, y, *e);
        let mark = if channel_delta(e, a) > threshold {
            MARK
        } else {
            faded_grey(e)
        };
        out.put_pixel(w + GAP + x, y, mark);
        out.put_pixel(2 * (w + GAP) + x, y, *a);
    }
    Ok(out)
}

/// Decodes PNG bytes to RGBA; `path` names the source in errors.
pub fn decode_png(bytes: &[u8], path: &Path) -> Result<RgbaImage, DiffError> {
    image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
        .map(|image| image.into_rgba8())
        .map_err(|source| DiffError::Decode {
            path: path.to_owned(),
            source,
        })
}

/// Reads and decodes a PNG file.
pub fn load_png(path: &Path) -> Result<RgbaImage, DiffError> {
    let bytes = std::fs::read(path).map_err(|source| DiffError::Read {
        path: path.to_owned(),
        source,
    })?;
    decode_png(&bytes, path)
}

/// Encodes `image` as a PNG and writes it atomically: to a temporary file in the same
/// folder, which is then renamed over `path`. Creates missing parent folders.
pub fn write_png_atomic(image: &RgbaImage, path: &Path) -> Result<(), DiffError> {
    let mut bytes = Vec::new();
    image::codecs::png::PngEncoder::new(&mut bytes)
        .write_image(
            image.as_raw(),
            image.width(),
            image.height(),
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| write_error(path, std::io::Error::other(e)))?;
    write_atomic(path, &bytes)
}

/// Returns the text chunks (iTXt and tEXt) of PNG bytes; none when they cannot be read.
pub fn text_chunks(bytes: &[u8]) -> Vec<(String, String)> {
    let Ok(reader) = png::Decoder::new(std::io::Cursor::new(bytes)).read_info() else {
        return Vec::new();
    };
    let info = reader.info();
    let mut chunks: Vec<(String, String)> = info
        .uncompressed_latin1_text
        .iter()
        .map(|c| (c.keyword.clone(), c.text.clone()))
        .collect();
    chunks.extend(
        info.utf8_text
            .iter()
            .filter_map(|c| Some((c.keyword.clone(), c.get_text().ok()?))),
    );
    chunks
}

/// The provenance of a diff image: the program, what was compared, and the `physframes:`
/// chunks (scene, scene hash, integrator, dt, t, frame) of the expected image.
fn diff_provenance(expected: &Path, expected_bytes: &[u8], actual: &Path) -> Vec<(String, String)> {
    let mut chunks = vec![
        (
            "Software".to_string(),
            format!("physframes {}", env!("CARGO_PKG_VERSION")),
        ),
        (
            "physframes:diff-expected".into(),
            expected.display().to_string(),
        ),
        (
            "physframes:diff-actual".into(),
            actual.display().to_string(),
        ),
    ];
    chunks.extend(
        text_chunks(expected_bytes)
            .into_iter()
            .filter(|(k, _)| k.starts_with("physframes:")),
    );
    chunks
}

/// Encodes a diff image with text chunks and writes it atomically.
fn write_diff_png(
    image: &RgbaImage,
    path: &Path,
    chunks: &[(String, String)],
) -> Result<(), DiffError> {
    let mut bytes = Vec::new();
    let error = |e: png::EncodingError| write_error(path, std::io::Error::other(e));
    {
        let mut encoder = png::Encoder::new(&mut bytes, image.width(), image.height());
        encoder.set_color(png::ColorType::Rgba);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Fast);
        for (key, value) in chunks {
            encoder
                .add_itxt_chunk(key.clone(), value.clone())
                .map_err(error)?;
        }
        let mut writer = encoder.write_header().map_err(error)?;
        writer.write_image_data(image.as_raw()).map_err(error)?;
        writer.finish().map_err(error)?;
    }
    write_atomic(path, &bytes)
}

/// Writes `bytes` to `path` atomically, creating missing parent folders.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), DiffError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    std::fs::create_dir_all(dir).map_err(|e| write_error(path, e))?;
    let file = tempfile::NamedTempFile::new_in(dir).map_err(|e| write_error(path, e))?;
    let mut writer = BufWriter::new(file);
    writer.write_all(bytes).map_err(|e| write_error(path, e))?;
    let file = writer
        .into_inner()
        .map_err(|e| write_error(path, e.into_error()))?;
    file.as_file()
        .sync_all()
        .map_err(|e| write_error(path, e))?;
    file.persist(path).map_err(|e| write_error(path, e.error))?;
    Ok(())
}

/// Compares two PNG files, or two folders of PNG frames matched by file name.
///
/// With `out`, diff images are written: for two files, to `out` itself; for two folders,
/// into the folder `out` (created if missing), one image per failing frame under the
/// frame's name.
pub fn diff_paths(
    expected: &Path,
    actual: &Path,
    options: &DiffOptions,
    out: Option<&Path>,
) -> Result<DiffOutcome, DiffError> {
    let is_dir = |p: &Path| {
        std::fs::metadata(p)
            .map(|m| m.is_dir())
            .map_err(|source| DiffError::Read {
                path: p.to_owned(),
                source,
            })
    };
    match (is_dir(expected)?, is_dir(actual)?) {
        (false, false) => {
            let name = expected.file_name().map_or_else(
                || expected.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            );
            let frame = diff_frame(&name, expected, actual, options, out)?;
            Ok(DiffOutcome::from_frames(vec![frame]))
        }
        (true, true) => diff_folders(expected, actual, options, out),
        _ => Err(DiffError::KindMismatch {
            expected: expected.to_owned(),
            actual: actual.to_owned(),
        }),
    }
}

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

fn diff_frame(
    name: &str,
    expected_path: &Path,
    actual_path: &Path,
    options: &DiffOptions,
    out: Option<&Path>,
) -> Result<FrameDiff, DiffError> {
    let expected = load_png(expected_path)?;
    let actual = load_png(actual_path)?;
    let size_error = |mismatch| DiffError::SizeMismatch {
        name: name.to_owned(),
        mismatch,
    };
    let pixels = compare_images(&expected, &actual, options.threshold).map_err(size_error)?;
    let within = pixels.differing_pixels <= options.max_pixels;
    if let Some(out) = out {
        let image = diff_image(&expected, &actual, options.threshold).map_err(size_error)?;
        let expected_bytes = std::fs::read(expected_path).unwrap_or_default();
        let chunks = diff_provenance(expected_path, &expected_bytes, actual_path);
        write_diff_png(&image, out, &chunks)?;
    }
    Ok(FrameDiff {
        name: name.to_owned(),
        pixels,
        within,
    })
}

fn diff_folders(
    expected: &Path,
    actual: &Path,
    options: &DiffOptions,
    out: Option<&Path>,
) -> Result<DiffOutcome, DiffError> {
    let expected_names = png_names(expected)?;
    let actual_names = png_names(actual)?;
    let missing: Vec<String> = expected_names.difference(&actual_names).cloned().collect();
    let extra: Vec<String> = actual_names.difference(&expected_names).cloned().collect();
    if !missing.is_empty() || !extra.is_empty() {
        return Err(DiffError::FrameSetMismatch { missing, extra });
    }
    if expected_names.is_empty() {
        return Err(DiffError::NoFrames {
            path: expected.to_owned(),
        });
    }
    let mut frames = Vec::with_capacity(expected_names.len());
    for name in &expected_names {
        let (e, a) = (expected.join(name), actual.join(name));
        let frame = diff_frame(name, &e, &a, options, None)?;
        if let (Some(out), false) = (out, frame.within) {
            // Decoding twice only for failing frames keeps the common case fast.
            let image = diff_image(&load_png(&e)?, &load_png(&a)?, options.threshold).map_err(
                |mismatch| DiffError::SizeMismatch {
                    name: name.clone(),
                    mismatch,
                },
            )?;
            let chunks = diff_provenance(&e, &std::fs::read(&e).unwrap_or_default(), &a);
            write_diff_png(&image, &out.join(name), &chunks)?;
        }
        frames.push(frame);
    }
    Ok(DiffOutcome::from_frames(frames))
}

/// The names of the `.png` files (any letter case) directly inside `dir`, sorted.
fn png_names(dir: &Path) -> Result<BTreeSet<String>, DiffError> {
    let read_error = |source| DiffError::Read {
        path: dir.to_owned(),
        source,
    };
    let mut names = BTreeSet::new();
    for entry in std::fs::read_dir(dir).map_err(read_error)? {
        let entry = entry.map_err(read_error)?;
        let path = entry.path();
        let is_png = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        if is_png && path.is_file() {
            names.insert(entry.file_name().to_string_lossy().into_owned());
        }
    }
    Ok(names)
}

fn check_sizes(expected: &RgbaImage, actual: &RgbaImage) -> Result<(), SizeMismatch> {
    if expected.dimensions() == actual.dimensions() {
        Ok(())
    } else {
        Err(SizeMismatch {
            expected: expected.dimensions(),
            actual: actual.dimensions(),
        })
    }
}

/// The largest absolute difference between corresponding channels.
fn channel_delta(a: &Rgba<u8>, b: &Rgba<u8>) -> u8 {
    a.0.iter()
        .zip(b.0.iter())
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0)
}

/// A light grey of the pixel's luma after compositing over white, so the picture stays
/// recognisable under the magenta marks.
fn faded_grey(p: &Rgba<u8>) -> Rgba<u8> {
    let [r, g, b, a] = p.0.map(u32::from);
    let over_white = |c: u32| (c * a + 255 * (255 - a)) / 255;
    let luma = (299 * over_white(r) + 587 * over_white(g) + 114 * over_white(b)) / 1000;
    let faded = 255 - (255 - luma) / 3;
    let v = faded as u8;
    Rgba([v, v, v, 255])
}

fn write_error(path: &Path, source: std::io::Error) -> DiffError {
    DiffError::Write {
        path: path.to_owned(),
        source,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32) -> RgbaImage {
        RgbaImage::from_fn(w, h, |x, y| {
            Rgba([(x * 20) as u8, (y * 30) as u8, 100, 255])
        })
    }

    fn write(path: &Path, image: &RgbaImage) {
        write_png_atomic(image, path).expect("the test image is written");
    }

    fn png_bytes(image: &RgbaImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        image::codecs::png::PngEncoder::new(&mut bytes)
            .write_image(
                image.as_raw(),
                image.width(),
                image.height(),
                image::ExtendedColorType::Rgba8,
            )
            .expect("the test image encodes");
        bytes
    }

    #[test]
    fn identical_images_are_within() {
        let dir = tempfile::tempdir().expect("a temp dir");
        let (e, a) = (dir.path().join("e.png"), dir.path().join("a.png"));
        write(&e, &image(8, 6));
        write(&a, &image(8, 6));
        let outcome = diff_paths(&e, &a, &DiffOptions::default(), None).expect("comparable");
        assert_eq!(outcome.exit_code(), 0);
        let DiffOutcome::Within { frames } = outcome else {
            panic!("identical images differ: {outcome:?}");
        };
        assert_eq!(frames[0].name, "e.png");
        assert_eq!(
            frames[0].pixels,
            PixelDiff {
                differing_pixels: 0,
                total_pixels: 48,
                max_channel_delta: 0
            }
        );
    }

    #[test]
    fn one_changed_pixel_counts_once_above_the_threshold() {
        let expected = image(8, 6);
        let mut actual = expected.clone();
        actual.get_pixel_mut(3, 2).0[1] += 10;
        let check = |threshold, differing| {
            let d = compare_images(&expected, &actual, threshold).expect("same size");
            assert_eq!(
                (d.differing_pixels, d.max_channel_delta),
                (differing, 10),
                "threshold {threshold}"
            );
        };
        check(0, 1);
        check(9, 1);
        // "Differs by more than N": a difference of exactly N is within.
        check(10, 0);
        // The pixel limit decides the outcome.
        let dir = tempfile::tempdir().expect("a temp dir");
        let (e, a) = (dir.path().join("e.png"), dir.path().join("a.png"));
        write(&e, &expected);
        write(&a, &actual);
        let strict = DiffOptions {
            threshold: 0,
            max_pixels: 0,
        };
        let outcome = diff_paths(&e, &a, &strict, None).expect("comparable");
        assert_eq!(outcome.exit_code(), 1);
        assert_eq!(outcome.failing().count(), 1);
        let lenient = DiffOptions {
            threshold: 0,
            max_pixels: 1,
        };
        assert_eq!(
            diff_paths(&e, &a, &lenient, None)
                .expect("comparable")
                .exit_code(),
            0
        );
    }

    #[test]
    fn the_diff_image_is_expected_difference_actual() {
        let expected = image(5, 4);
        let mut actual = expected.clone();
        actual.put_pixel(1, 2, Rgba([0, 0, 0, 0]));
        let d = diff_image(&expected, &actual, 0).expect("same size");
        assert_eq!(d.dimensions(), (3 * 5 + 8, 4));
        for (x, y, p) in expected.enumerate_pixels() {
            assert_eq!(d.get_pixel(x, y), p, "left panel is expected");
            assert_eq!(
                d.get_pixel(18 + x, y),
                actual.get_pixel(x, y),
                "right panel is actual"
            );
            let mid = d.get_pixel(9 + x, y).0;
            if (x, y) == (1, 2) {
                assert_eq!(mid, [255, 0, 255, 255]);
            } else {
                assert!(
                    mid[0] == mid[1] && mid[1] == mid[2] && mid[0] >= 170,
                    "faded grey {mid:?}"
                );
            }
        }
        assert_eq!(d.get_pixel(5, 0).0, [128, 128, 128, 255], "gap");
    }

    #[test]
    fn bad_input_is_an_error() {
        let dir = tempfile::tempdir().expect("a temp dir");
        let p = |n: &str| dir.path().join(n);
        write(&p("small.png"), &image(4, 4));
        write(&p("large.png"), &image(5, 4));
        std::fs::write(p("junk.png"), b"not a png").expect("written");
        let options = DiffOptions::default();
        assert!(matches!(
            diff_paths(&p("small.png"), &p("large.png"), &options, None),
            Err(DiffError::SizeMismatch {
                mismatch: SizeMismatch {
                    expected: (4, 4),
                    actual: (5, 4)
                },
                ..
            })
        ));
        assert!(matches!(
            diff_paths(&p("small.png"), &p("absent.png"), &options, None),
            Err(DiffError::Read { .. })
        ));
        assert!(matches!(
            diff_paths(&p("small.png"), &p("junk.png"), &options, None),
            Err(DiffError::Decode { .. })
        ));
        assert!(matches!(
            diff_paths(&p("small.png"), dir.path(), &options, None),
            Err(DiffError::KindMismatch { .. })
        ));
        let empty = (p("e"), p("a"));
        std::fs::create_dir_all(&empty.0).expect("created");
        std::fs::create_dir_all(&empty.1).expect("created");
        assert!(matches!(
            diff_paths(&empty.0, &empty.1, &options, None),
            Err(DiffError::NoFrames { .. })
        ));
    }

    #[test]
    fn folders_are_matched_by_frame_name() {
        let dir = tempfile::tempdir().expect("a temp dir");
        let (e, a, out) = (
            dir.path().join("e"),
            dir.path().join("a"),
            dir.path().join("out"),
        );
        for name in ["frame_0001.png", "frame_0000.png", "frame_0002.png"] {
            write(&e.join(name), &image(6, 6));
            write(&a.join(name), &image(6, 6));
        }
        std::fs::write(e.join("notes.txt"), "ignored").expect("written");
        let mut changed = image(6, 6);
        changed.put_pixel(0, 0, Rgba([255, 255, 255, 255]));
        changed.put_pixel(5, 5, Rgba([255, 255, 255, 255]));
        write(&a.join("frame_0001.png"), &changed);

        let outcome = diff_paths(&e, &a, &DiffOptions::default(), Some(&out)).expect("comparable");
        let counts: Vec<(&str, u64, bool)> = outcome
            .frames()
            .iter()
            .map(|f| (f.name.as_str(), f.pixels.differing_pixels, f.within))
            .collect();
        assert_eq!(
            counts,
            [
                ("frame_0000.png", 0, true),
                ("frame_0001.png", 2, false),
                ("frame_0002.png", 0, true)
            ]
        );
        assert_eq!(outcome.exit_code(), 1);
        // Only the failing frame gets a diff image, and no temporary file is left behind.
        let written: Vec<String> = png_names(&out).expect("readable").into_iter().collect();
        assert_eq!(written, ["frame_0001.png"]);
        assert_eq!(std::fs::read_dir(&out).expect("readable").count(), 1);
        assert_eq!(
            load_png(&out.join("frame_0001.png"))
                .expect("a PNG")
                .width(),
            3 * 6 + 8
        );

        // A frame on one side only is bad input that names it.
        std::fs::remove_file(a.join("frame_0002.png")).expect("removed");
        write(&a.join("frame_0003.png"), &image(6, 6));
        match diff_paths(&e, &a, &DiffOptions::default(), None) {
            Err(DiffError::FrameSetMismatch { missing, extra }) => {
                assert_eq!(
                    (missing, extra),
                    (
                        vec!["frame_0002.png".to_owned()],
                        vec!["frame_0003.png".to_owned()]
                    )
                );
            }
            other => panic!("expected a frame set mismatch, got {other:?}"),
        }
    }

    #[test]
    fn golden_checks_update_compare_and_report() {
        let dir = tempfile::tempdir().expect("a temp dir");
        let reference = dir.path().join("golden").join("chart.png");
        let failures = dir.path().join("failures");
        let options = DiffOptions {
            threshold: 2,
            max_pixels: 0,
        };
        let original = png_bytes(&image(6, 4));
        let check =
            |bytes: &[u8], mode| check_golden_with(&reference, bytes, &options, mode, &failures);

        assert!(matches!(
            check(&original, GoldenMode::Compare),
            Err(GoldenError::MissingReference { .. })
        ));
        check(&original, GoldenMode::Update).expect("the reference is written");
        check(&original, GoldenMode::Compare).expect("the same image passes");

        let mut changed = image(6, 4);
        changed.get_pixel_mut(2, 1).0[0] += 3;
        changed.get_pixel_mut(4, 3).0[2] += 2; // Within the threshold.
        let error = check(&png_bytes(&changed), GoldenMode::Compare).expect_err("a mismatch");
        let message = error.to_string();
        let diff = failures.join("chart.png");
        assert!(message.contains("1 of 24 pixels"), "{message}");
        assert!(message.contains(&diff.display().to_string()), "{message}");
        assert_eq!(
            load_png(&diff).expect("the diff image").dimensions(),
            (3 * 6 + 8, 4)
        );

        // Passing again removes the stale failure image.
        check(&original, GoldenMode::Compare).expect("the same image passes");
        assert!(!diff.exists());
        assert!(matches!(
            check(b"junk", GoldenMode::Compare),
            Err(GoldenError::Input(DiffError::Decode { .. }))
        ));
    }
}
