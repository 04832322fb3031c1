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
