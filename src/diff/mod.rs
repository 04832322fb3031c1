//! Golden-image comparison: the library behind `physframes diff` and the golden tests.
//!
//! Two PNGs are decoded to 8-bit RGBA and compared channel by channel. A pixel differs
//! when any of its four channels differs by more than `threshold`; a frame passes when
//! at most `max_pixels` of its pixels differ. Folders of frames are matched by file name.
//!
//! The outcome is typed so a command line can map it to exit codes: a comparison that
//! ran returns [`DiffOutcome::Within`] (exit 0) or [`DiffOutcome::Different`] (exit 1),
//! and input that cannot be compared (a missing or undecodable file, a size mismatch,
//! frames present on one side only) is a [`DiffError`] (exit 2). The golden-test harness
//! built on it is in `golden.rs`.
//!
//! A diff image is laid out expected | difference | actual; the difference panel shows
//! differing pixels in magenta over a faded grey copy of the expected image, as resvg's
//! reference-image harness does. Images are written atomically: to a temporary file in
//! the destination folder, then renamed over the destination.

mod golden;
#[cfg(test)]
mod tests;

pub use golden::{check_golden, check_golden_with, GoldenError, GoldenMode, GOLDEN_FAILURES_DIR};

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

/// Compares two images pixel by pixel: a pixel differs when one of its channels differs
/// by more than `threshold`.
///
/// ```
/// use image::{Rgba, RgbaImage};
/// use physframes::diff::compare_images;
///
/// let expected = RgbaImage::from_pixel(4, 3, Rgba([10, 20, 30, 255]));
/// let mut actual = expected.clone();
/// actual.put_pixel(1, 1, Rgba([10, 25, 30, 255]));
/// let diff = compare_images(&expected, &actual, 2).expect("same size");
/// assert_eq!((diff.differing_pixels, diff.max_channel_delta), (1, 5));
/// // Within a threshold of 5, the images are alike.
/// assert_eq!(compare_images(&expected, &actual, 5).expect("same size").differing_pixels, 0);
/// ```
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
    let file = crate::output::Output::create(path)
        .map_err(|e| write_error(path, std::io::Error::other(e.to_string())))?;
    let mut writer = BufWriter::new(file);
    writer.write_all(bytes).map_err(|e| write_error(path, e))?;
    let file = writer
        .into_inner()
        .map_err(|e| write_error(path, e.into_error()))?;
    file.sync().map_err(|e| write_error(path, e))?;
    file.finish().map_err(|e| write_error(path, e))?;
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
