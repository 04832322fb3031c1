//! Fields, curves, axes, the HUD, `physframes figure` and `physframes diff`: geometry
//! measured on the pixels drawn, exact Euler steps, located expression errors, and the
//! commands' files and exit codes.

use std::path::Path;

use physframes::figures;
use physframes::render::layers::{solution_points, Overlay};
use physframes::scene::layers::CurveKind;
use physframes::scene::{parse, Scene};

use crate::util::{scene, stderr, stdout, Sandbox};

/// A small chart scene with one red layer on a non-square view: one data unit across
/// is far more pixels than one unit up.
fn red_layer_scene(view: &str, layer: &str) -> Scene {
    scene(&format!(
        "[render]\nwidth = 400\nheight = 300\nview = {view}\n[axes]\naspect = \"auto\"\nlegend = false\n{layer}color = \"#ff0000\"\nwidth = 2.0\n"
    ))
}

/// The red pixels of a frame, weighted by how red they are.
fn red_ink(scene: &Scene) -> Vec<(f64, f64, f64)> {
    let pixmap = figures::render_frame(scene, 0).expect("renders");
    let mut ink = Vec::new();
    for y in 0..pixmap.height() {
        for x in 0..pixmap.width() {
            let p = pixmap.pixel(x, y).expect("inside").demultiply();
            let redness = f64::from(p.red()) - f64::from(p.green());
            if redness > 40.0 {
                ink.push((f64::from(x) + 0.5, f64::from(y) + 0.5, redness));
            }
        }
    }
    ink
}

/// The angle in degrees (screen, y down) of the principal axis of some weighted points.
fn principal_angle(ink: &[(f64, f64, f64)]) -> f64 {
    let w: f64 = ink.iter().map(|p| p.2).sum();
    let mx = ink.iter().map(|p| p.0 * p.2).sum::<f64>() / w;
    let my = ink.iter().map(|p| p.1 * p.2).sum::<f64>() / w;
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for (x, y, wt) in ink {
        sxx += wt * (x - mx) * (x - mx);
        syy += wt * (y - my) * (y - my);
        sxy += wt * (x - mx) * (y - my);
    }
    0.5 * (2.0 * sxy).atan2(sxx - syy).to_degrees()
}

fn angle_between(a: f64, b: f64) -> f64 {
    // Lines, not arrows: angles modulo 180°.
    let d = (a - b).rem_euclid(180.0);
    d.min(180.0 - d)
}

#[test]
fn a_slope_segment_at_x_1_of_dy_dx_2x_has_slope_2_under_the_axes_scales() {
    // One grid cell centred on (1, 5); x spans 1 unit and y 10 units.
    let s = red_layer_scene(
        "{ min = [0.5, 0.0], max = [1.5, 10.0] }",
        "[[field]]\nkind = \"slope\"\nf = \"2*x\"\ngrid = [1, 1]\nsize = 0.8\n",
    );
    let (_, camera) = Overlay::new(&s);
    let scale = camera.scale_xy();
    // Data slope 2 is the pixel direction (s_x·1, -s_y·2) on screen (y down).
    let expected = (-2.0 * scale.y).atan2(scale.x).to_degrees();
    let measured = principal_angle(&red_ink(&s));
    assert!(
        angle_between(measured, expected) < 1.0,
        "measured {measured:.2}°, expected {expected:.2}° (scales {scale:?})"
    );
    // The pitfall: a direction taken in screen space would be atan(2) = 63.4° steep.
    assert!(
        angle_between(measured, -63.43) > 30.0,
        "measured {measured:.2}°"
    );
}

#[test]
fn vector_arrows_point_along_their_data_direction_on_a_non_square_view() {
    // f = (-y, x) at the cell centre (1, 5) is (-5, 1).
    let s = red_layer_scene(
        "{ min = [0.0, 0.0], max = [2.0, 10.0] }",
        "[[field]]\nkind = \"vector\"\nf = [\"-y\", \"x\"]\ngrid = [1, 1]\nsize = 0.6\n",
    );
    let (_, camera) = Overlay::new(&s);
    let scale = camera.scale_xy();
    let tail = camera.to_pixel_f64(glam::DVec2::new(1.0, 5.0));
    let ink = red_ink(&s);
    let w: f64 = ink.iter().map(|p| p.2).sum();
    let centroid = (
        ink.iter().map(|p| p.0 * p.2).sum::<f64>() / w,
        ink.iter().map(|p| p.1 * p.2).sum::<f64>() / w,
    );
    // An arrow points from its tail through its centroid; the ink lies beside the
    // tail, toward (-5·s_x, -1·s_y) in pixels.
    let measured = (centroid.1 - tail.1)
        .atan2(centroid.0 - tail.0)
        .to_degrees();
    let expected = (-scale.y).atan2(-5.0 * scale.x).to_degrees();
    let d = (measured - expected)
        .abs()
        .min(360.0 - (measured - expected).abs());
    assert!(d < 2.0, "measured {measured:.2}°, expected {expected:.2}°");
}

#[test]
fn euler_points_are_exactly_y_plus_h_f_and_are_drawn() {
    let s = figures::load("drag-field").expect("loads");
    let curve = s
        .layers
        .curves
        .iter()
        .find(|c| matches!(c.kind, CurveKind::Solution { .. }))
        .expect("Figure 3 has a numerical solution");
    let CurveKind::Solution {
        f,
        start,
        h,
        method,
        end,
        ..
    } = &curve.kind
    else {
        unreachable!()
    };
    let mut values = curve.slots.values.clone();
    let points = solution_points(f, &mut values, *start, *h, *method, *end);
    assert_eq!(points.len(), 11, "t = 0, 0.5, …, 5");
    let m = 1.0;
    for w in points.windows(2) {
        let ((t, v), (t1, v1)) = (w[0], w[1]);
        // v_{n+1} = v_n + h·(-v_n/m), bit for bit.
        assert_eq!(v1, v + h * (-v / m), "at t = {t}");
        assert_eq!(t1, t + h);
    }
    // Every step point shows a marker in the curve's colour (#d62728).
    let pixmap = figures::render_frame(&s, 0).expect("renders");
    let (_, camera) = Overlay::new(&s);
    for &(t, v) in &points[1..points.len() - 1] {
        let (x, y) = camera.to_pixel(glam::DVec2::new(t, v));
        let p = pixmap
            .pixel(x.round() as u32, y.round() as u32)
            .expect("inside");
        assert!(
            p.red() > 180 && p.green() < 90,
            "no marker at ({t}, {v}): {p:?}"
        );
    }
}

/// Returns (line, column) of the first diagnostic of an invalid scene.
fn first_error_at(text: &str) -> ((usize, usize), String) {
    match parse(Path::new("bad.toml"), text) {
        Ok(_) => panic!("the scene should be invalid"),
        Err(e) => {
            let d = &e.diagnostics[0];
            let span = d.span.clone().expect("a located diagnostic");
            (
                e.line_column(span.start),
                format!("{}: {:?}", d.message, d.hint),
            )
        }
    }
}

const FIELD_SCENE: &str = "[render]\nview = { min = [0.0, -1.0], max = [5.0, 3.0] }\n[axes]\n[[field]]\nkind = \"vector\"\nvariables = [\"t\", \"v\"]\nparams = { m = 1 }\nf = \"-v/m\"\n";

#[test]
fn expression_errors_point_inside_the_string() {
    let cases = [
        // (the expression, the token the caret should start at, words in the message)
        ("-z/m", "z", "unknown variable `z`"),
        ("-v/(m", "(", "never closed"),
        ("-v//m", "/", "needs a value on its left"),
        ("2 v", "v", "operator is missing"),
        ("-v/m $", "$", "unexpected character"),
    ];
    for (expression, token, words) in cases {
        let text = FIELD_SCENE.replace("\"-v/m\"", &format!("\"{expression}\""));
        let ((line, column), message) = first_error_at(&text);
        let line_text = text.lines().nth(line - 1).expect("line");
        let at: String = line_text
            .chars()
            .skip(column - 1)
            .take(token.chars().count())
            .collect();
        assert_eq!(line, 8, "{expression}: {message}");
        assert_eq!(
            at, token,
            "{expression}: column {column} in `{line_text}`: {message}"
        );
        assert!(message.contains(words), "{expression}: {message}");
    }
}

#[test]
fn unknown_variables_are_errors_naming_the_allowed_ones() {
    let text = FIELD_SCENE.replace("\"-v/m\"", "\"-y/m\"");
    let (_, message) = first_error_at(&text);
    assert!(message.contains("unknown variable `y`"), "{message}");
    assert!(message.contains("`t`, `v`, `m`"), "{message}");
    // Through the real binary: the file, line and column, and a caret.
    let sandbox = Sandbox::new();
    sandbox.write("bad.toml", &text);
    let out = sandbox.run(&["figure", "bad.toml", "--out", "f.png"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("bad.toml:8:7"), "{err}");
    assert!(err.contains('^'), "{err}");
    assert!(!sandbox.path("f.png").exists());
}

#[test]
fn curve_keys_of_another_kind_are_errors() {
    let text = format!("{FIELD_SCENE}[[curve]]\nkind = \"exact\"\ny = \"x\"\nh = 0.5\n");
    let ((line, _), message) = first_error_at(&text);
    assert_eq!(line, 12, "{message}");
    assert!(
        message.contains("`h` does not apply to a `exact` curve"),
        "{message}"
    );
}

#[test]
fn the_hud_shows_in_the_top_left_corner_only() {
    let base = "[simulation]\ndt = 0.01\nduration = 1.0\n[render]\nwidth = 200\nheight = 150\nfps = 25\nview = { min = [-1.0, -1.0], max = [1.0, 1.0] }\n[[body]]\nmass = 1.0\nvelocity = [0.5, 0.0]\n";
    let off = scene(base);
    let on = scene(&base.replace("fps = 25\n", "fps = 25\nhud = true\n"));
    let a = figures::render_frame(&off, 5).expect("renders");
    let b = figures::render_frame(&on, 5).expect("renders");
    let mut changed = 0;
    for y in 0..150 {
        for x in 0..200 {
            if a.pixel(x, y) != b.pixel(x, y) {
                changed += 1;
                assert!(x < 190 && y < 40, "the HUD drew at ({x}, {y})");
            }
        }
    }
    assert!(changed > 100, "the HUD drew {changed} pixels");
}

/// Returns the iTXt chunks of a PNG file as (keyword, text) pairs.
fn text_chunks(path: &Path) -> Vec<(String, String)> {
    let file = std::fs::File::open(path).expect("exists");
    let reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG");
    reader
        .info()
        .utf8_text
        .iter()
        .map(|c| (c.keyword.clone(), c.get_text().expect("text")))
        .collect()
}

#[test]
fn figure_writes_a_png_with_its_provenance_at_the_size_asked() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&[
        "figure",
        "drag-field",
        "--out",
        "f/fig.png",
        "--size",
        "400x300",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let image = image::open(sandbox.path("f/fig.png")).expect("decodes");
    assert_eq!((image.width(), image.height()), (400, 300));
    let chunks = text_chunks(&sandbox.path("f/fig.png"));
    for key in [
        "Software",
        "physframes:scene",
        "physframes:scene-hash",
        "physframes:integrator",
        "physframes:dt",
        "physframes:t",
    ] {
        assert!(
            chunks.iter().any(|(k, _)| k == key),
            "no {key} in {chunks:?}"
        );
    }
    assert!(chunks.contains(&("physframes:scene".into(), "drag-field".into())));
    // The default output goes under output/figures/.
    let out = sandbox.run(&["figure", "slope-field"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(sandbox.path("output/figures/slope-field.png").exists());
}

#[test]
fn figure_lists_the_built_ins_and_rejects_unknown_names() {
    let sandbox = Sandbox::new();
    let out = sandbox.run(&["figure", "--list"]);
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    assert!(
        text.contains("slope-field") && text.contains("drag-field"),
        "{text}"
    );
    let out = sandbox.run(&["figure", "no-such-figure"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("neither a built-in figure"));
    let out = sandbox.run(&["figure", "drag-field", "--size", "0x5"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn diff_exits_0_1_or_2_and_writes_the_three_panel_image() {
    let sandbox = Sandbox::new();
    let run = |args: &[&str]| sandbox.run(args);
    assert_eq!(
        run(&[
            "figure",
            "drag-field",
            "--out",
            "a.png",
            "--size",
            "200x150"
        ])
        .status
        .code(),
        Some(0)
    );
    assert_eq!(
        run(&[
            "figure",
            "drag-field",
            "--out",
            "b.png",
            "--size",
            "200x150"
        ])
        .status
        .code(),
        Some(0)
    );
    assert_eq!(
        run(&[
            "figure",
            "slope-field",
            "--out",
            "c.png",
            "--size",
            "200x150"
        ])
        .status
        .code(),
        Some(0)
    );
    assert_eq!(
        run(&[
            "figure",
            "slope-field",
            "--out",
            "d.png",
            "--size",
            "100x80"
        ])
        .status
        .code(),
        Some(0)
    );

    let same = run(&["diff", "a.png", "b.png"]);
    assert_eq!(same.status.code(), Some(0), "{}", stderr(&same));
    assert!(
        stdout(&same).contains("1 of 1 frame within tolerance"),
        "{}",
        stdout(&same)
    );

    let different = run(&["diff", "a.png", "c.png", "--out", "d/diff.png"]);
    assert_eq!(different.status.code(), Some(1));
    let text = stdout(&different);
    assert!(
        text.contains("DIFFERENT a.png") && text.contains("of 30000 pixels differ"),
        "{text}"
    );
    let diff = image::open(sandbox.path("d/diff.png")).expect("a diff image");
    assert_eq!((diff.width(), diff.height()), (3 * 200 + 8, 150));
    // A diff image carries the expected frame's provenance too.
    let chunks = text_chunks(&sandbox.path("d/diff.png"));
    assert!(
        chunks.contains(&("physframes:scene".into(), "drag-field".into())),
        "{chunks:?}"
    );
    assert!(chunks
        .iter()
        .any(|(k, v)| k == "Software" && v.starts_with("physframes ")));
    // Loose enough limits let the same pair pass.
    let loose = run(&["diff", "a.png", "c.png", "--threshold", "255"]);
    assert_eq!(loose.status.code(), Some(0));

    assert_eq!(
        run(&["diff", "a.png", "d.png"]).status.code(),
        Some(2),
        "size mismatch"
    );
    assert_eq!(
        run(&["diff", "a.png", "missing.png"]).status.code(),
        Some(2)
    );

    // Folders of frames, matched by name.
    for dir in ["x", "y"] {
        std::fs::create_dir_all(sandbox.path(dir)).expect("dir");
        std::fs::copy(
            sandbox.path("a.png"),
            sandbox.path(&format!("{dir}/frame_000000.png")),
        )
        .expect("copy");
    }
    std::fs::copy(sandbox.path("a.png"), sandbox.path("x/frame_000001.png")).expect("copy");
    std::fs::copy(sandbox.path("c.png"), sandbox.path("y/frame_000001.png")).expect("copy");
    let folders = run(&["diff", "x", "y"]);
    assert_eq!(folders.status.code(), Some(1));
    assert!(
        stdout(&folders).contains("DIFFERENT frame_000001.png"),
        "{}",
        stdout(&folders)
    );
    assert!(stdout(&folders).contains("1 of 2 frames within tolerance"));
}

#[test]
fn a_field_that_reads_t_changes_between_frames_and_a_static_one_does_not() {
    let text = |f: &str| {
        format!(
            "[simulation]\nduration = 1.0\n[render]\nwidth = 200\nheight = 150\nview = {{ min = [-1.0, -1.0], max = [1.0, 1.0] }}\n[axes]\n[[field]]\nkind = \"slope\"\nf = \"{f}\"\ngrid = [8, 6]\n"
        )
    };
    let moving = scene(&text("x*sin(3*t)"));
    let still = scene(&text("x"));
    assert!(moving.layers.has_dynamic_layers() && !still.layers.has_dynamic_layers());
    let frame = |s: &Scene, k| figures::render_frame(s, k).expect("renders");
    assert!(frame(&moving, 0) != frame(&moving, 10));
    assert!(frame(&still, 0) == frame(&still, 10));
}

#[test]
fn bad_layer_keys_are_located_errors() {
    let base = "[render]\nview = { min = [0.0, -1.0], max = [5.0, 3.0] }\n[[body]]\nname = \"puck\"\nmass = 1.0\n";
    let cases: &[(&str, &str, &str)] = &[
        // (the table added to the scene, the text the error points at, the message)
        ("[[field]]\nkind = \"flow\"\nf = \"x\"\n", "\"flow\"", "unknown field kind"),
        ("[[field]]\nkind = \"slope\"\nf = \"x\"\ngrid = [0, 5]\n", "[0, 5]", "`grid` must be"),
        ("[[field]]\nkind = \"slope\"\nf = [\"x\", \"y\"]\n", "[\"x\", \"y\"]", "one expression"),
        ("[[field]]\nkind = \"vector\"\nf = \"x\"\nlength = \"huge\"\n", "\"huge\"", "unknown arrow length"),
        ("[[field]]\nkind = \"slope\"\nf = \"x\"\nparams = { e = 1 }\n", "{ e = 1 }", "cannot name a parameter"),
        ("[[curve]]\nkind = \"solution\"\nf = \"-y\"\nstart = [0, 1]\nh = 0.5\nmethod = \"rk7\"\n", "\"rk7\"", "unknown method"),
        ("[[curve]]\nkind = \"solution\"\nf = \"-y\"\nstart = [0, 1]\nh = -0.5\n", "-0.5", "must be > 0"),
        ("[[curve]]\nkind = \"trace\"\nx = \"t\"\ny = \"ghost.vx\"\n", "ghost.vx", "unknown variable `ghost.vx`"),
        ("[[curve]]\nkind = \"exact\"\ny = \"x\"\ndash = \"wavy\"\n", "\"wavy\"", "unknown dash"),
        ("[axes]\nlegend = \"middle\"\n", "\"middle\"", "`legend` must be"),
        ("[axes]\naspect = \"square\"\n", "\"square\"", "unknown aspect"),
    ];
    for (table, at, message) in cases {
        let text = format!("{base}{table}");
        let e = match parse(Path::new("bad.toml"), &text) {
            Ok(_) => panic!("`{table}` should be rejected"),
            Err(e) => e,
        };
        let d = &e.diagnostics[0];
        let span = d.span.clone().expect("located");
        assert_eq!(&text[span.clone()], *at, "{table}: {}", d.message);
        assert!(d.message.contains(message), "{table}: {}", d.message);
    }
}
