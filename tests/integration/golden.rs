//! Golden images: both built-in figures and the first, middle and last frame of every
//! example scene, compared with the references in `tests/golden/` pixel for pixel.
//!
//! The output is deterministic, so the tolerance is zero: threshold 0 and no differing
//! pixel. A mismatch writes expected | difference | actual to `tests/golden-failures/`
//! (git-ignored) and fails with the counts. `UPDATE_GOLDEN=1 cargo test golden`
//! rewrites the references after a deliberate change; look at them before committing.

use std::path::{Path, PathBuf};

use physframes::diff::{check_golden_with, DiffOptions, GoldenMode, GOLDEN_FAILURES_DIR};
use physframes::figures::{self, BUILT_INS};
use physframes::render::Compression;
use physframes::scene::Scene;

use crate::util::{example, stderr, Sandbox};

/// The example scenes with golden frames.
const SCENES: &[&str] = &[
    "projectile.toml",
    "drag.toml",
    "terminal-velocity.toml",
    "spring.toml",
    "centre-of-mass.toml",
    "drag-phase.toml",
    "compare.toml",
    // Bodies that turn: a turned box and a disc with its orientation line, a box on a
    // spring at its corner, and turned polygons.
    "spin.toml",
    "pendulum.toml",
    "gears.toml",
    // Collisions: balls of four restitutions, a break shot, an elastic gas, and a box
    // and a triangle landing on their corners; static bodies drawn like the others.
    "bounce.toml",
    "billiards.toml",
    "gas.toml",
    "tumble.toml",
    // Friction and resting contact: coming to rest, rolling, stacks and a pile.
    "rest.toml",
    "roll.toml",
    "tower.toml",
    "pyramid.toml",
    "pour.toml",
];

/// Our references are exact.
const EXACT: DiffOptions = DiffOptions {
    threshold: 0,
    max_pixels: 0,
};

/// The largest a reference may be, so the repository stays small.
const MAX_REFERENCE_BYTES: u64 = 200 * 1024;

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

/// Compares one rendered image with its reference; returns the failure, if any.
fn check(reference: &Path, png: &[u8], failures: &Path) -> Option<String> {
    let result = check_golden_with(reference, png, &EXACT, GoldenMode::from_env(), failures);
    if let Err(e) = result {
        return Some(format!("{}: {e}", reference.display()));
    }
    match std::fs::metadata(reference) {
        Ok(m) if m.len() > MAX_REFERENCE_BYTES => Some(format!(
            "{} is {} bytes, more than {MAX_REFERENCE_BYTES}",
            reference.display(),
            m.len()
        )),
        _ => None,
    }
}

fn fail_with(failures: Vec<String>) {
    assert!(
        failures.is_empty(),
        "{} golden image(s) differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn both_figures_match_their_golden_images() {
    let failures_dir = Path::new(GOLDEN_FAILURES_DIR).join("figures");
    let mut failures = Vec::new();
    for b in BUILT_INS {
        let scene = figures::load(b.name).expect("a built-in figure loads");
        let last = scene.render.frame_count - 1;
        let png = figures::render_png(&scene, last, Compression::Best).expect("renders");
        let reference = golden_dir().join("figures").join(format!("{}.png", b.name));
        failures.extend(check(&reference, &png, &failures_dir));
    }
    fail_with(failures);
}

#[test]
fn example_scene_frames_match_their_golden_images() {
    let mut failures = Vec::new();
    for name in SCENES {
        let scene = Scene::load(Path::new(&example(name))).expect("an example scene loads");
        let n = scene.render.frame_count;
        let failures_dir = Path::new(GOLDEN_FAILURES_DIR).join(&scene.name);
        for k in [0, n / 2, n - 1] {
            let png = figures::render_png(&scene, k, Compression::Best).expect("renders");
            let reference = golden_dir()
                .join(&scene.name)
                .join(format!("frame_{k:06}.png"));
            failures.extend(check(&reference, &png, &failures_dir));
        }
    }
    fail_with(failures);
}

/// The golden frames come from `figures::render_frame`; this keeps it honest by
/// comparing it with what `physframes render` writes, trails and traces included.
#[test]
fn a_frame_drawn_alone_equals_the_same_frame_of_a_render() {
    for (name, k) in [("drag-phase.toml", 40u64), ("projectile.toml", 60)] {
        let sandbox = Sandbox::new();
        let range = format!("{k}");
        let out = sandbox.run(&["render", &example(name), "--out", "f", "--frames", &range]);
        assert_eq!(out.status.code(), Some(0), "{name}: {}", stderr(&out));
        let written = image::open(sandbox.path(&format!("f/frame_{k:06}.png")))
            .expect("the frame decodes")
            .into_rgba8();
        let scene = Scene::load(Path::new(&example(name))).expect("loads");
        let alone = figures::render_frame(&scene, k).expect("renders");
        let alone =
            image::RgbaImage::from_raw(alone.width(), alone.height(), alone.data().to_vec())
                .expect("same size");
        assert!(written == alone, "{name}: frame {k} differs");
    }
}

#[test]
fn a_mismatch_writes_a_diff_image_and_reports_counts() {
    let dir = tempfile::tempdir().expect("temp");
    let scene = figures::load("slope-field").expect("loads");
    let png = figures::render_png(&scene, 0, Compression::Fastest).expect("renders");
    let reference = dir.path().join("ref.png");
    std::fs::write(&reference, &png).expect("write");
    let mut other = scene.clone();
    other.layers.curves.clear();
    let changed = figures::render_png(&other, 0, Compression::Fastest).expect("renders");
    let failures = dir.path().join("failures");
    let e = check_golden_with(&reference, &changed, &EXACT, GoldenMode::Compare, &failures)
        .expect_err("removing the curves changes pixels");
    let text = e.to_string();
    assert!(text.contains("pixels differ"), "{text}");
    let diff = image::open(failures.join("ref.png")).expect("a diff image");
    assert_eq!(diff.width(), 3 * 800 + 8);
}
