//! Issue #16: every scene takes the fast paths, not only the benchmark's swarms of one
//! look. Bodies written one `[[body]]` table each, in the default colours and in any
//! order, mixed shapes, velocity arrows, trails and turning boxes are each drawn the
//! fast way, and each is checked here against tiny-skia's paths (the same bytes, or a
//! difference bounded and explained) and for the same bytes with any number of
//! threads. Speed itself is measured by `physframes bench`, not here.

use physframes::render::bodies::{draw_arrow, draw_arrow_path};
use physframes::render::clip::ClipRect;
use tiny_skia::{Color, Pixmap};

/// Returns the largest channel difference between two pixmaps and how many pixels
/// differ at all.
fn diff(a: &Pixmap, b: &Pixmap) -> (u8, usize) {
    let mut largest = 0;
    let mut count = 0;
    for (p, q) in a.data().chunks_exact(4).zip(b.data().chunks_exact(4)) {
        let d = p
            .iter()
            .zip(q)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        largest = largest.max(d);
        count += usize::from(d > 0);
    }
    (largest, count)
}

#[test]
fn arrows_from_the_scan_converter_are_tiny_skias_arrows() {
    // Arrows of every direction and of lengths from a pixel to past the image, 2
    // pixels wide as bodies' arrows are, and 1.5 and 3: inside the image the bytes are
    // tiny-skia's; an arrow that crosses the image's edge may differ by one
    // quarter-pixel sample there (tiny-skia cuts its edges in f32 first), which
    // changes a channel by at most 16·(255 - 0)/255 = 16 levels.
    let (w, h) = (160u32, 120u32);
    let clip = ClipRect::guard(w, h);
    let colors = [
        Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff),
        Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99),
    ];
    let mut ours = Pixmap::new(w, h).expect("pixmap");
    ours.fill(Color::from_rgba8(250, 248, 240, 255));
    let mut theirs = ours.clone();
    let mut crossing = ours.clone();
    let mut crossing_theirs = ours.clone();
    for k in 0..300u32 {
        let a = f64::from(k) * 2.399_963; // the golden angle: every direction.
        let len = 1.0 + f64::from(k % 37) * 2.1;
        let at = (
            20.0 + f64::from(k % 13) * 9.37 + 0.13,
            15.0 + f64::from(k % 11) * 8.71 + 0.29,
        );
        let d = (len * a.cos(), len * a.sin());
        let width = [2.0, 1.5, 3.0][(k % 3) as usize];
        let c = colors[(k % 2) as usize];
        // Arrows kept inside the image, and others sent across its edges.
        if at.0 + d.0 > 2.0 && at.0 + d.0 < 158.0 && at.1 + d.1 > 2.0 && at.1 + d.1 < 118.0 {
            draw_arrow(&mut ours, &clip, at, d, c, width);
            draw_arrow_path(&mut theirs, &clip, at, d, c, width);
        } else {
            draw_arrow(&mut crossing, &clip, at, (4.0 * d.0, 4.0 * d.1), c, width);
            draw_arrow_path(
                &mut crossing_theirs,
                &clip,
                at,
                (4.0 * d.0, 4.0 * d.1),
                c,
                width,
            );
        }
    }
    let (largest, count) = diff(&ours, &theirs);
    assert_eq!((largest, count), (0, 0), "arrows inside the image");
    let (largest, count) = diff(&crossing, &crossing_theirs);
    eprintln!("arrows across the edge: {count} pixels differ, by {largest}/255 at most");
    assert!(largest <= 16, "arrows across the edge: {largest}/255");
}

/// Draws a turning look both ways at many angles and sub-pixel positions over a light
/// background, and returns the largest channel difference, how many pixels differ, and
/// how many pixels the look covers.
fn turned_difference(shape: physframes::scene::Shape, color: [u8; 4]) -> (u8, usize, usize) {
    use physframes::render::bodies::BodyLook;
    use physframes::render::Camera;
    let camera = Camera::fit(
        physframes::scene::View {
            min: glam::DVec2::ZERO,
            max: glam::DVec2::new(16.0, 9.0),
        },
        1280,
        720,
    );
    let s = crate::util::scene(
        r#"
[render]
view = { min = [0.0, 0.0], max = [16.0, 9.0] }
[[body]]
mass = 1.0
angular_velocity = 1.0
"#,
    );
    let mut body = s.bodies[0].clone();
    body.shape = shape;
    body.color = physframes::scene::Rgba(color);
    let look = BodyLook::new(&body, &camera);
    assert!(
        look.turns_fast(),
        "{:?} should take the fast way",
        body.shape
    );
    let (mut largest, mut count, mut covered) = (0, 0, 0);
    for k in 0..400u32 {
        let theta = f64::from(k) * 0.0157 - 3.0;
        let x = 40.0 + (k % 10) as f32 * 0.113;
        let y = 40.0 + (k / 10 % 10) as f32 * 0.171;
        let mut fast = Pixmap::new(80, 80).expect("pixmap");
        fast.fill(Color::from_rgba8(250, 248, 240, 255));
        let mut path = fast.clone();
        let background = fast.clone();
        look.draw_turned_fast(&mut fast, x, y, theta);
        look.draw_turned(&mut path, x, y, theta);
        let (l, c) = diff(&fast, &path);
        largest = largest.max(l);
        count += c;
        covered += diff(&path, &background).1;
    }
    (largest, count, covered)
}

#[test]
fn turning_boxes_and_convex_polygons_from_the_scan_converter_look_like_their_paths() {
    // The fill is tiny-skia's, byte for byte; the outline's stroke differs where the
    // scan converter's chords of a rounded corner (15° each, within 0.007 pixel of the
    // arc) and tiny-skia's curves put a sub-row's crossing on different sides of a
    // quarter-pixel column, or where the inner side of the stroke, which tiny-skia
    // takes round each corner's pivot, is cut differently: one or two samples of 16 in
    // a corner pixel. Measured: 0.3 to 1.4% of the pixels they cover, by at most
    // 29/255 (two samples).
    use glam::DVec2;
    use physframes::scene::Shape;
    let shapes = [
        (
            Shape::Box {
                width: 0.16,
                height: 0.08,
            },
            [0x1f, 0x77, 0xb4, 0xff],
        ),
        (
            Shape::Box {
                width: 0.5,
                height: 0.02,
            },
            [0xff, 0x7f, 0x0e, 0xff],
        ),
        (
            Shape::Box {
                width: 0.3,
                height: 0.3,
            },
            [0x2c, 0xa0, 0x2c, 0x80],
        ),
        (
            Shape::Polygon {
                points: vec![
                    DVec2::new(-0.1, -0.05),
                    DVec2::new(0.12, -0.04),
                    DVec2::new(0.0, 0.1),
                ],
            },
            [0x94, 0x67, 0xbd, 0xff],
        ),
    ];
    for (shape, color) in shapes {
        let (largest, count, covered) = turned_difference(shape.clone(), color);
        eprintln!(
            "{shape:?}: {count} of {covered} covered pixels differ, by {largest}/255 at most"
        );
        assert!(largest <= 32, "{shape:?}: largest difference {largest}/255");
        assert!(
            count * 50 <= covered,
            "{shape:?}: {count} of {covered} pixels differ"
        );
    }
}
