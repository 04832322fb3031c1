
#[test]
fn bench_gives_each_scene_its_ratio_to_the_reference_and_trails_their_first_and_last_frames() {
    let sandbox = crate::util::Sandbox::new();
    let trails = sandbox.write("trails.toml", &user_scene(30, 0, true, false));
    let reference = crate::util::example("drag.toml");
    let out = sandbox.run(&[
        "bench",
        &trails.to_string_lossy(),
        "--reference",
        &reference,
        "--repeat",
        "1",
        "--frames",
        "0..6",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", crate::util::stderr(&out));
    let text = crate::util::stdout(&out);
    // The reference, added since it was not listed, comes first with a ratio of 1.
    let row = |name: &str| {
        text.lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no row for {name} in:\n{text}"))
            .split_whitespace()
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    let drag = row("drag");
    assert_eq!(drag[4], "1.00", "{text}");
    assert!(text.contains("(reference)"), "{text}");
    let ratio: f64 = row("trails")[4].parse().expect("a ratio");
    assert!(ratio > 0.0, "{text}");
    // A scene with trails also says what its first and last frames cost.
    assert!(text.contains("first 6 frames") && text.contains("last 6 frames"), "{text}");
    assert!(text.contains("ratio: frames/s over those of drag"), "{text}");
    // Without a reference, no ratio.
    let out = sandbox.run(&[
        "bench",
        &reference,
        "--reference",
        "none",
        "--repeat",
        "1",
        "--frames",
        "0..3",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", crate::util::stderr(&out));
    assert!(crate::util::stdout(&out).contains("ratio: none"), "{}", crate::util::stdout(&out));
}
