//! Issue #16: every scene takes the fast paths, not only the benchmark's swarms of one
//! look. Bodies written one `[[body]]` table each, in the default colours and in any
//! order, mixed shapes, velocity arrows, trails and turning boxes are each drawn the
//! fast way, and each is checked here against tiny-skia's paths (the same bytes, or a
//! difference bounded and explained) and for the same bytes with any number of
//! threads. Speed itself is measured by `physframes bench`, not here.

use physframes::render::bodies::{draw_arrow, draw_arrow_path};
use physframes::render::clip::ClipRect;
use tiny_skia::{Color, Pixmap};

use crate::util::{change_outside, diff, diff_beyond};

#[test]
fn arrows_covered_by_ramps_stay_within_their_bound_of_tiny_skias() {
    // Arrows of every direction and of lengths from a pixel to past the image, 2
    // pixels wide as bodies' arrows are, and 1.5 and 3, each drawn alone over the
    // background both ways. `draw_arrow` covers a pixel by the product of ramps
    // (`raster/ramps/`), tiny-skia by four sub-rows of quarter-pixel columns. Along
    // one side the two differ by at most: tiny-skia's columns rounded to a quarter
    // pixel in each sub-row (1/8 of a pixel's coverage at most), its four sub-rows
    // standing for the rows between them (1/8 at most), and a ramp's straight line
    // against the exact area (0.043, at 45°): 0.293 of the ink's contrast with the
    // background, plus a level for rounding. Those errors are spread either way, so on
    // average over the pixels an arrow covers they come to far less: a side pixel
    // errs by 1/16 on average in each of tiny-skia's two roundings, and about half of
    // an arrow's pixels are on a side, so 1/16 of the contrast bounds the mean.
    // (Measured: 0.23 of the contrast at most, 0.020 on average.)
    let (w, h) = (160u32, 120u32);
    let clip = ClipRect::guard(w, h);
    let background = [250u8, 248, 240, 255];
    let colors = [
        Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff),
        Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99),
    ];
    let mut blank = Pixmap::new(w, h).expect("pixmap");
    blank.fill(Color::from_rgba8(
        background[0],
        background[1],
        background[2],
        background[3],
    ));
    let (mut covered, mut sum, mut worst) = (0usize, 0.0f64, 0.0f64);
    for k in 0..600u32 {
        let a = f64::from(k) * 2.399_963; // the golden angle: every direction.
        let len = 1.0 + f64::from(k % 37) * 2.1;
        let at = (
            20.0 + f64::from(k % 13) * 9.37 + 0.13,
            15.0 + f64::from(k % 11) * 8.71 + 0.29,
        );
        // Every other arrow four times as long: many cross the image's edges.
        let d = if k % 2 == 0 {
            (len * a.cos(), len * a.sin())
        } else {
            (4.0 * len * a.cos(), 4.0 * len * a.sin())
        };
        let width = [2.0, 1.5, 3.0][(k % 3) as usize];
        let c = colors[(k / 2 % 2) as usize];
        let (mut ours, mut theirs) = (blank.clone(), blank.clone());
        draw_arrow(&mut ours, &clip, at, d, c, width);
        draw_arrow_path(&mut theirs, &clip, at, d, c, width);
        // The ink's contrast with the background, channel by channel, as drawn over
        // it at full coverage.
        let ink = c.premultiply().to_color_u8();
        let full = [ink.red(), ink.green(), ink.blue(), ink.alpha()];
        let alpha = f64::from(full[3]) / 255.0;
        let contrast = (0..3)
            .map(|i| {
                let over = f64::from(full[i]) + f64::from(background[i]) * (1.0 - alpha);
                (over - f64::from(background[i])).abs()
            })
            .fold(0.0, f64::max);
        for (po, pt) in ours
            .data()
            .chunks_exact(4)
            .zip(theirs.data().chunks_exact(4))
        {
            if po != background || pt != background {
                let d = po
                    .iter()
                    .zip(pt)
                    .map(|(x, y)| f64::from(x.abs_diff(*y)))
                    .fold(0.0, f64::max);
                assert!(
                    d <= 0.293 * contrast + 1.0,
                    "arrow {k}: a pixel differs by {d} of contrast {contrast}"
                );
                covered += 1;
                sum += d / contrast;
                worst = worst.max(d / contrast);
            }
        }
    }
    let mean = sum / covered as f64;
    assert!(covered > 20_000, "{covered} pixels covered");
    assert!(mean <= 1.0 / 16.0, "on average {mean} of the contrast");
    eprintln!("{covered} pixels covered: {worst:.3} of the contrast at most, {mean:.4} on average");
}

#[test]
fn an_arrows_marked_tiles_hold_every_pixel_it_draws() {
    // Arrows of every direction and length, from under a pixel to past the image,
    // 2 pixels wide as bodies' arrows are and 1 and 3, drawn alone over a background:
    // each pixel that changed lies in a tile `mark_arrow` marked, with the scan
    // converter and with tiny-skia's paths.
    use physframes::render::bodies::mark_arrow;
    use physframes::render::damage::TileMask;
    let (w, h) = (160u32, 120u32);
    let clip = ClipRect::guard(w, h);
    let mut background = Pixmap::new(w, h).expect("pixmap");
    background.fill(Color::from_rgba8(250, 248, 240, 255));
    let mut marked = 0;
    for k in 0..600u32 {
        let a = f64::from(k) * 2.399_963;
        let len = 0.3 + f64::from(k % 41) * f64::from(k % 7 + 1) * 0.9;
        let at = (
            -10.0 + f64::from(k % 17) * 10.9 + 0.37,
            -8.0 + f64::from(k % 13) * 10.7 + 0.61,
        );
        let d = (len * a.cos(), len * a.sin());
        let width = [2.0, 1.0, 3.0][(k % 3) as usize];
        let c = Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff);
        let mut mask = TileMask::new(w, h);
        mask.clear();
        mark_arrow(&mut mask, at, d, width);
        for path in [false, true] {
            let mut ours = background.clone();
            if path {
                draw_arrow_path(&mut ours, &clip, at, d, c, width);
            } else {
                draw_arrow(&mut ours, &clip, at, d, c, width);
            }
            let unmarked = change_outside(&mask, &ours, &background);
            assert!(
                unmarked.is_none(),
                "arrow {k} from {at:?} along {d:?}, {width} wide (paths: {path}): pixel {unmarked:?} unmarked"
            );
            marked += diff(&ours, &background).1;
        }
    }
    assert!(marked > 50_000, "the arrows drew {marked} pixels");
    // The arrows of a run that is blowing up (the blow-up test renders one): lengths
    // and places far past any image, finite or not, mark what they may draw and do
    // not panic.
    let far = [1e300, -1e300, 1e18, f64::MAX, f64::INFINITY, f64::NAN, 40.0];
    for &u in &far {
        for &v in &far {
            let mut mask = TileMask::new(w, h);
            mask.clear();
            mark_arrow(&mut mask, (40.0, 30.0), (u, v), 2.0);
            mark_arrow(&mut mask, (u, v), (-u, 3.0), 2.0);
            let mut ours = background.clone();
            draw_arrow(&mut ours, &clip, (40.0, 30.0), (u, v), Color::BLACK, 2.0);
            draw_arrow(&mut ours, &clip, (u, v), (-u, 3.0), Color::BLACK, 2.0);
            let unmarked = change_outside(&mask, &ours, &background);
            assert!(
                unmarked.is_none(),
                "arrow along ({u}, {v}): pixel {unmarked:?} unmarked"
            );
        }
    }
}

/// Draws a turning look both ways at many angles and sub-pixel positions over a light
/// background, and returns the largest channel difference, how many pixels differ, and
/// how many pixels the look covers.
fn turned_difference(shape: physframes::scene::Shape, color: [u8; 4]) -> (u8, usize, usize) {
    use physframes::render::bodies::BodyLook;
    let camera = camera_16_by_9();
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
    over_angles(
        layer_slack(color),
        |p, x, y, theta| look.draw_turned_fast(p, x, y, theta),
        |p, x, y, theta| look.draw_turned(p, x, y, theta),
    )
}

/// The most by which a convex outline in the opaque colour `color` (its fill; the
/// edge is darker) drawn in layers differs from its fill then its stroke, over
/// [`BACKGROUND`], along a straight edge; 0 for a translucent colour, which is not
/// drawn in layers.
///
/// In opaque colours the scan converter fills the stroke's outer side in the edge's
/// colour E and its inner side over it in the fill's F (`raster::fill_layers`),
/// instead of the fill and then the ring. With a pixel's coverages c_f by the fill,
/// c_o and c_i by the two sides, the two differ by c_f·(1 - c_o)·|F - B|, or by
/// c_i·(1 - c_f)·|F - B| (a pixel has c_o = 1 or c_i = 0; see `fill_layers`). Along
/// a straight edge the fill's edge and a side are parallel, 0.75 pixel apart, so a
/// pixel they both cross holds a strip of that width between them, and the two
/// coverages share what the strip leaves: c_f + (1 - c_o) ≤ 1/4 when the edge runs
/// along a row or a column, the largest product then being 1/8 · 1/8 = 1/64 (at any
/// other angle the strip leaves more, but in two corners whose product is smaller:
/// 0.0122 at 45°, the ends being triangles of area a² with a + b = √2 - 0.75). So
/// |F - B|/64, and one level for rounding the two blends. At a corner, where the
/// round join is cut into chords, the sides are not parallel and more is possible;
/// such pixels are few and fall under the chords' count.
fn layer_slack(color: [u8; 4]) -> u8 {
    if color[3] != 255 {
        return 0;
    }
    let spread = (0..3)
        .map(|k| color[k].abs_diff(BACKGROUND[k]))
        .max()
        .unwrap_or(0);
    spread.div_ceil(64) + 1
}

/// The camera of a 1280 × 720 image of the world from (0, 0) to (16, 9).
fn camera_16_by_9() -> physframes::render::Camera {
    physframes::render::Camera::fit(
        physframes::scene::View {
            min: glam::DVec2::ZERO,
            max: glam::DVec2::new(16.0, 9.0),
        },
        1280,
        720,
    )
}

/// The light background the looks are drawn over here.
const BACKGROUND: [u8; 3] = [250, 248, 240];

/// Draws something both ways at 400 angles and sub-pixel positions over a light
/// background, and returns the largest channel difference, how many pixels differ by
/// more than `slack`, and how many pixels the second way covers.
fn over_angles(
    slack: u8,
    fast: impl Fn(&mut Pixmap, f32, f32, f64),
    path: impl Fn(&mut Pixmap, f32, f32, f64),
) -> (u8, usize, usize) {
    let (mut largest, mut count, mut covered) = (0, 0, 0);
    for k in 0..400u32 {
        let theta = f64::from(k) * 0.0157 - 3.0;
        let x = 40.0 + (k % 10) as f32 * 0.113;
        let y = 40.0 + (k / 10 % 10) as f32 * 0.171;
        let mut ours = Pixmap::new(80, 80).expect("pixmap");
        let [r, g, b] = BACKGROUND;
        ours.fill(Color::from_rgba8(r, g, b, 255));
        let mut theirs = ours.clone();
        let background = ours.clone();
        fast(&mut ours, x, y, theta);
        path(&mut theirs, x, y, theta);
        let (l, c) = diff_beyond(&ours, &theirs, slack);
        largest = largest.max(l);
        count += c;
        covered += diff(&theirs, &background).1;
    }
    (largest, count, covered)
}

/// Draws a body of `shape` that never turns, at each of `angles` and at sub-pixel
/// positions over a light background, through the scan converter and as tiny-skia's
/// paths, and returns the largest channel difference, how many pixels differ, and how
/// many pixels the paths cover.
fn fixed_angle_difference(
    shape: &physframes::scene::Shape,
    angles: &[f64],
    slack: u8,
) -> (u8, usize, usize) {
    use physframes::render::bodies::BodyLook;
    let camera = camera_16_by_9();
    let s = crate::util::scene(
        "[render]\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n[[body]]\nmass = 1.0\n",
    );
    let (mut largest, mut count, mut covered) = (0, 0, 0);
    for (k, &angle) in angles.iter().enumerate() {
        let mut body = s.bodies[0].clone();
        body.shape = shape.clone();
        body.turns = false;
        body.angle = angle;
        let look = BodyLook::new(&body, &camera);
        assert!(look.draws_fast(), "{shape:?} at {angle} rad");
        assert!(!look.turns_fast());
        let x = 40.0 + (k % 10) as f32 * 0.113;
        let y = 40.0 + (k / 10 % 10) as f32 * 0.171;
        let mut ours = Pixmap::new(80, 80).expect("pixmap");
        let [r, g, b] = BACKGROUND;
        ours.fill(Color::from_rgba8(r, g, b, 255));
        let mut theirs = ours.clone();
        let background = ours.clone();
        look.draw_fast(&mut ours, x, y);
        look.draw(&mut theirs, x, y);
        let (l, c) = diff_beyond(&ours, &theirs, slack);
        largest = largest.max(l);
        count += c;
        covered += diff(&theirs, &background).1;
    }
    (largest, count, covered)
}

#[test]
fn boxes_and_convex_polygons_at_fixed_angles_from_the_scan_converter_look_like_their_paths() {
    // Bodies that never turn but are not stamped (boxes of many sizes, or each at an
    // angle of its own) go through the same scan converter as turning ones, at their
    // fixed angle, with the same bounds: the stroke's chords differ by a sample or two
    // of 16 in a corner pixel, and in opaque colours the layers (`layer_slack`) by a
    // few levels where the fill's edge crosses a pixel. Measured: 0.3 to 0.5% of the
    // covered pixels differ by more than the layers' 5 levels, by at most 29/255.
    use glam::DVec2;
    use physframes::scene::Shape;
    let shapes = [
        Shape::Box {
            width: 0.16,
            height: 0.08,
        },
        Shape::Box {
            width: 0.37,
            height: 0.05,
        },
        Shape::Polygon {
            points: vec![
                DVec2::new(-0.1, -0.05),
                DVec2::new(0.12, -0.04),
                DVec2::new(0.0, 0.1),
            ],
        },
    ];
    for shape in shapes {
        // Angle 0 too: an upright box is a rectangle path, not a turned polygon.
        let angles: Vec<f64> = (0..200u32)
            .map(|k| {
                if k == 0 {
                    0.0
                } else {
                    f64::from(k) * 0.0313 - 3.1
                }
            })
            .collect();
        // The default colour of the first body, the cycle's first.
        let slack = layer_slack([0x1f, 0x77, 0xb4, 0xff]);
        let (largest, count, covered) = fixed_angle_difference(&shape, &angles, slack);
        eprintln!(
            "{shape:?} at fixed angles: {count} of {covered} covered pixels differ by more than {slack}, by {largest}/255 at most"
        );
        assert!(largest <= 32, "{shape:?}: largest difference {largest}/255");
        assert!(
            count * 50 <= covered,
            "{shape:?}: {count} of {covered} pixels differ"
        );
    }
}

/// An L and a five-pointed star: polygons that are not convex.
fn concave_shapes() -> Vec<physframes::scene::Shape> {
    use glam::DVec2;
    let star = (0..10)
        .map(|k| {
            let a = std::f64::consts::PI * f64::from(k) / 5.0 + 0.3;
            let r = if k % 2 == 0 { 0.15 } else { 0.09 };
            DVec2::new(r * a.cos(), r * a.sin())
        })
        .collect();
    vec![
        physframes::scene::Shape::Polygon {
            points: vec![
                DVec2::new(-0.08, -0.08),
                DVec2::new(0.08, -0.08),
                DVec2::new(0.08, -0.03),
                DVec2::new(-0.03, -0.03),
                DVec2::new(-0.03, 0.08),
                DVec2::new(-0.08, 0.08),
            ],
        },
        physframes::scene::Shape::Polygon { points: star },
    ]
}

#[test]
fn polygons_that_are_not_convex_from_the_general_scan_look_like_their_paths() {
    // The fill is tiny-skia's, byte for byte (the general scan is tiny-skia's nonzero
    // scan of the same f32 points); the stroke is the union of the edges' capsules,
    // which differs from tiny-skia's stroke where the round joins are cut into 30°
    // chords and at the inner corners, which tiny-skia takes round each corner's
    // pivot: a sample or two of 16 in a corner pixel, as for convex outlines.
    // Measured: under 1% of the covered pixels differ, by at most 29/255.
    use physframes::render::bodies::BodyLook;
    let camera = camera_16_by_9();
    let s = crate::util::scene(
        "[render]\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n[[body]]\nmass = 1.0\n",
    );
    for shape in concave_shapes() {
        let mut turning = s.bodies[0].clone();
        turning.shape = shape.clone();
        turning.turns = true;
        let look = BodyLook::new(&turning, &camera);
        assert!(look.turns_general() && !look.turns_fast(), "{shape:?}");
        let (largest, count, covered) = over_angles(
            0,
            |p, x, y, theta| look.draw_turned_fast(p, x, y, theta),
            |p, x, y, theta| look.draw_turned(p, x, y, theta),
        );
        eprintln!("{shape:?} turning: {count} of {covered} covered pixels differ, by {largest}/255 at most");
        assert!(largest <= 32, "{shape:?}: largest difference {largest}/255");
        assert!(
            count * 50 <= covered,
            "{shape:?}: {count} of {covered} pixels differ"
        );
        // At fixed angles of their own, the same way.
        let angles: Vec<f64> = (0..100u32).map(|k| f64::from(k) * 0.0627 - 3.1).collect();
        let (largest, count, covered) = fixed_angle_difference(&shape, &angles, 0);
        eprintln!("{shape:?} at fixed angles: {count} of {covered} covered pixels differ, by {largest}/255 at most");
        assert!(largest <= 32, "{shape:?}: largest difference {largest}/255");
        assert!(
            count * 50 <= covered,
            "{shape:?}: {count} of {covered} pixels differ"
        );
    }
}

#[test]
fn turning_boxes_and_convex_polygons_from_the_scan_converter_look_like_their_paths() {
    // The fill is tiny-skia's, byte for byte; the outline's stroke differs where the
    // scan converter's chords of a rounded corner (15° each, within 0.007 pixel of the
    // arc) and tiny-skia's curves put a sub-row's crossing on different sides of a
    // quarter-pixel column, or where the inner side of the stroke, which tiny-skia
    // takes round each corner's pivot, is cut differently: one or two samples of 16 in
    // a corner pixel. In opaque colours the ring is drawn as two fills, its outer side
    // in the edge's colour and its inner side over it in the fill's, which adds a few
    // levels where the fill's edge crosses a pixel (`layer_slack`: 5 here); the
    // translucent box keeps the fill and the ring. Measured: 0.4 to 1.4% of the pixels
    // they cover differ by more than that, by at most 29/255 (two samples).
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

#[test]
fn turning_circles_orientation_lines_from_the_scan_converter_look_like_their_paths() {
    // The line's body is a rectangle with tiny-skia's corners; its round caps are cut
    // into 30° chords (within 0.026 pixel of the arc) where tiny-skia steps curves, so
    // a sub-row's crossing can land on the other side of a quarter-pixel column: one or
    // two samples of 16 in a cap's edge pixel, at most 2·16 = 32 of 255. Measured:
    // 945 of 50,385 covered pixels (1.9%) differ, by at most 29/255.
    use physframes::render::bodies::BodyLook;
    let camera = camera_16_by_9();
    let (mut largest, mut count, mut covered) = (0, 0, 0);
    for (radius, color) in [(0.05, "#1f77b4"), (0.12, "#ff7f0e"), (0.4, "#2ca02c80")] {
        let s = crate::util::scene(&format!(
            "[render]\nview = {{ min = [0.0, 0.0], max = [16.0, 9.0] }}\n[[body]]\nmass = 1.0\nangular_velocity = 1.0\ncolor = \"{color}\"\nshape = {{ circle = {{ radius = {radius} }} }}\n"
        ));
        let look = BodyLook::new(&s.bodies[0], &camera);
        assert!(look.turns_by_marker(), "a turning circle shows its angle");
        let (l, c, k) = over_angles(
            0,
            |p, x, y, theta| look.draw_orientation_fast(p, x, y, theta),
            |p, x, y, theta| look.draw_orientation(p, x, y, theta),
        );
        largest = largest.max(l);
        count += c;
        covered += k;
    }
    eprintln!(
        "orientation lines: {count} of {covered} covered pixels differ, by {largest}/255 at most"
    );
    assert!(covered > 10_000, "the lines cover {covered} pixels");
    assert!(largest <= 32, "largest difference {largest}/255");
    assert!(count * 20 <= covered, "{count} of {covered} pixels differ");
}

/// A scene of `count` bodies written one `[[body]]` table each, as a user writes them:
/// default colours, shapes in an order that does not repeat with the colours, some
/// turning, every `arrows`-th showing its velocity, with trails when asked.
pub(crate) fn user_scene(count: usize, arrows: usize, trails: bool, turning: bool) -> String {
    let mut text = format!(
        "[simulation]\nduration = 2.0\n[render]\nwidth = 320\nheight = 180\nfps = 20\ntrails = {trails}\nview = {{ min = [0.0, 0.0], max = [16.0, 9.0] }}\n"
    );
    for i in 0..count {
        // A scrambled order: i·7919 mod 97 walks the shapes and places.
        let k = (i * 7919) % 97;
        let shape = match k % 4 {
            0 => "{ circle = { radius = 0.12 } }".to_string(),
            1 => "{ box = { width = 0.3, height = 0.16 } }".to_string(),
            2 => {
                "{ polygon = { points = [[-0.14, -0.1], [0.14, -0.1], [0.0, 0.14]] } }".to_string()
            }
            _ => "{ circle = { radius = 0.2 } }".to_string(),
        };
        text.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{:.3}, {:.3}]\nvelocity = [{:.3}, {:.3}]\nshape = {shape}\n",
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
            ((k % 13) as f64 - 6.0) * 0.4,
            ((i % 11) as f64 - 5.0) * 0.3,
        ));
        if turning && k % 3 == 0 {
            text.push_str(&format!("angular_velocity = {:.2}\n", (k % 7) as f64 - 3.0));
        }
        if arrows > 0 && i % arrows == 0 {
            text.push_str("show_velocity = true\n");
        }
    }
    text
}

/// A scene of `count` bodies in which no two have the same size or angle, as when a
/// user scatters balls and crates of many sizes: discs of radii from 0.05 to 0.2,
/// boxes of their own widths and heights at fixed angles of their own, and triangles
/// of their own sizes, in the default colours.
pub(crate) fn sized_scene(count: usize) -> String {
    let mut text = String::from(
        "[simulation]\nduration = 2.0\n[render]\nwidth = 320\nheight = 180\nfps = 20\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    for i in 0..count {
        let k = (i * 7919) % 97;
        let f = i as f64 / count as f64;
        let shape = match i % 3 {
            0 => format!("{{ circle = {{ radius = {:.4} }} }}", 0.05 + 0.15 * f),
            1 => format!(
                "{{ box = {{ width = {:.4}, height = {:.4} }} }}\nangle = {:.4}",
                0.1 + 0.3 * f,
                0.3 - 0.2 * f,
                6.0 * f - 3.0
            ),
            _ => format!(
                "{{ polygon = {{ points = [[{:.4}, -0.1], [0.14, -0.1], [0.0, 0.14]] }} }}",
                -0.1 - 0.1 * f
            ),
        };
        text.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{:.3}, {:.3}]\nvelocity = [{:.3}, {:.3}]\nshape = {shape}\n",
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
            ((k % 13) as f64 - 6.0) * 0.4,
            ((i % 11) as f64 - 5.0) * 0.3,
        ));
    }
    text
}

#[test]
fn bodies_of_many_sizes_and_angles_take_the_fast_ways_and_look_like_their_paths() {
    use physframes::render::BodyDrawing;
    let s = crate::util::scene(
        &sized_scene(300)
            .replace("width = 320", "width = 1280")
            .replace("height = 180", "height = 720"),
    );
    let looks =
        physframes::render::looks::Looks::new(&s.bodies, &camera_16_by_9(), BodyDrawing::Sprites);
    for (b, &l) in s.bodies.iter().zip(&looks.look_of) {
        let look = &looks.looks[l as usize];
        match b.shape {
            physframes::scene::Shape::Circle { .. } => {
                assert!(look.sprite.is_some(), "a disc of its own radius is stamped")
            }
            _ => assert!(look.body.draws_fast(), "{:?} is scan-converted", b.shape),
        }
    }
    let (fast, paths, background) = crate::util::first_frame_both_ways(&s);
    let (largest, count) = diff(&fast, &paths);
    let covered = diff(&paths, &background).1;
    eprintln!(
        "sizes and angles: {count} of {covered} covered pixels differ, by {largest}/255 at most"
    );
    // The bounds of the parts: a quarter pixel of edge (64/255) for the snapped
    // discs, two samples (32/255) for the chords of the scan-converted corners; and
    // at most a quarter of the covered pixels, as snapping positions alone changes
    // (26,085 of 104,169 in circles-1000, `perf.rs`). Measured: 6%, by 62/255.
    assert!(largest <= 64, "largest difference {largest}/255");
    assert!(count * 4 <= covered, "{count} of {covered} pixels differ");
    assert!(covered > 20_000, "the bodies cover {covered} pixels");
}

/// Renders a scene's first frames through the real binary with 1 and 2 threads, and
/// checks that every frame is the same file.
fn same_bytes_with_one_and_two_threads(name: &str, text: &str, frames: &str) {
    let sandbox = crate::util::Sandbox::new();
    let path = sandbox.write(&format!("{name}.toml"), text);
    let path = path.to_string_lossy();
    for (dir, threads) in [("one", "1"), ("two", "2")] {
        let out = sandbox.run(&[
            "render",
            &path,
            "--out",
            dir,
            "--threads",
            threads,
            "--frames",
            frames,
            "--quiet",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", crate::util::stderr(&out));
    }
    let one = sandbox.frames("one");
    assert!(!one.is_empty());
    assert_eq!(one, sandbox.frames("two"), "{name}: the same frame files");
    for frame in one {
        let a = std::fs::read(sandbox.path(&format!("one/{frame}"))).expect("frame");
        let b = std::fs::read(sandbox.path(&format!("two/{frame}"))).expect("frame");
        assert!(a == b, "{name}: {frame} differs between 1 and 2 threads");
    }
}

#[test]
fn scenes_written_as_users_write_them_give_the_same_bytes_with_one_and_two_threads() {
    // Every fast path at once: sprites shared across colours and orders, turning boxes
    // and triangles, arrows, and, separately, trails over enough frames that each
    // worker's trail layer jumps over frames the other drew.
    let all = user_scene(120, 3, false, true);
    same_bytes_with_one_and_two_threads("bodies", &all, "0..8");
    let trails = user_scene(60, 0, true, false);
    same_bytes_with_one_and_two_threads("trails", &trails, "0..24");
    // Every body a size or an angle of its own: snapped-radius sprites and fixed
    // convex outlines through the scan converter.
    same_bytes_with_one_and_two_threads("sizes", &sized_scene(120), "0..8");
    same_bytes_with_one_and_two_threads("crates", &crates_scene(120, 320, 180), "0..8");
    same_bytes_with_one_and_two_threads("dumbbells", &dumbbells_scene(60, 320, 180), "0..8");
    same_bytes_with_one_and_two_threads("late-trails", &trails, "17..29");
    // Bodies that collide, rest, turn and fall asleep on a ramp and a floor, with
    // trails and arrows (the bench's scene, drawn smaller), after they have settled.
    let contacts = std::fs::read_to_string(crate::util::example("bench/mixed-contacts-300.toml"))
        .expect("readable")
        .replace("width = 1280", "width = 320")
        .replace("height = 720", "height = 180");
    same_bytes_with_one_and_two_threads("contacts", &contacts, "100..106");
}

/// The positions of a scene's bodies at each of its first `frames` frames, as the
/// pipeline's trail history holds them.
pub(crate) fn trail_history(
    s: &physframes::scene::Scene,
    frames: u64,
) -> Vec<physframes::history::PointHistory> {
    use std::sync::Arc;
    let mut sim = s.simulation_with(s.simulation.integrator);
    let mut writer: physframes::history::HistoryWriter<Arc<[glam::DVec2]>> =
        physframes::history::HistoryWriter::new();
    let mut snapshots = Vec::new();
    for k in 0..frames {
        sim.advance_to(s.frame_time(k)).expect("no blow-up");
        writer.push(Arc::from(sim.state().pos.as_slice()));
        snapshots.push(writer.history().clone());
    }
    snapshots
}

/// A scene's renderer with arrows at one world unit per unit of speed and of force.
fn renderer_of(s: &physframes::scene::Scene) -> physframes::render::Renderer {
    physframes::render::Renderer::new(
        s,
        physframes::render::ArrowScales {
            velocity: 1.0,
            force: 1.0,
        },
    )
}

/// Draws frame `k` of a scene with trails from the trail layer given.
fn draw_trail_frame(
    renderer: &physframes::render::Renderer,
    s: &physframes::scene::Scene,
    history: &[physframes::history::PointHistory],
    k: usize,
    layer: &mut Option<physframes::render::trails::TrailLayer>,
) -> Pixmap {
    let pos = history[k].last().expect("a frame").clone();
    let view = physframes::render::FrameView {
        index: k as u64,
        t: s.frame_time(k as u64),
        pos: &pos,
        vel: &[],
        angle: None,
        force: None,
        trail: Some(&history[k]),
        traces: None,
        compare: None,
    };
    let mut pixmap = renderer.new_frame();
    let mut damage = physframes::render::Damage::default();
    renderer.draw_with_trails(&view, &mut pixmap, &mut damage, layer);
    pixmap
}

/// A user's scene of `bodies` bodies with trails, its renderer, and its trail history
/// at each of its first `frames` frames.
fn trail_scene(
    bodies: usize,
    frames: u64,
) -> (
    physframes::scene::Scene,
    physframes::render::Renderer,
    Vec<physframes::history::PointHistory>,
) {
    let s = crate::util::scene(&user_scene(bodies, 0, true, false));
    let renderer = renderer_of(&s);
    let history = trail_history(&s, frames);
    (s, renderer, history)
}

#[test]
fn a_trail_layer_gives_each_frame_the_same_pixels_whatever_frames_came_before() {
    // A worker's layer jumps over the frames other workers drew, and a fresh layer (a
    // resumed or sharded render) starts from nothing: both must give the frame of a
    // layer that saw every frame.
    let (s, renderer, history) = trail_scene(40, 30);
    let mut every = None;
    let mut jumping = None;
    for k in 0..30 {
        let a = draw_trail_frame(&renderer, &s, &history, k, &mut every);
        if k % 7 == 3 || k == 29 {
            let b = draw_trail_frame(&renderer, &s, &history, k, &mut jumping);
            assert!(
                a.data() == b.data(),
                "frame {k}: a layer that jumped differs"
            );
            let c = draw_trail_frame(&renderer, &s, &history, k, &mut None);
            assert!(a.data() == c.data(), "frame {k}: a fresh layer differs");
        }
    }
    // A layer asked for an earlier frame (another render) starts again.
    let early = draw_trail_frame(&renderer, &s, &history, 5, &mut every);
    let fresh = draw_trail_frame(&renderer, &s, &history, 5, &mut None);
    assert!(
        early.data() == fresh.data(),
        "going back to frame 5 differs"
    );
}

#[test]
fn workers_sharing_one_rasterisation_of_the_trails_draw_the_frames_of_a_layer_on_its_own() {
    // The render's workers take each frame's trail pixels from one shared
    // rasterisation: done ahead by the producer for some frames, by the first worker
    // to need them for the others. Two workers drawing alternate frames, and one
    // jumping ahead, must each give the pixels of a layer that rasterised every frame
    // itself; a worker sent back to an earlier frame (another render) starts again on
    // its own. The same when the shared pixels are kept within a limit (none, or a
    // few frames' worth), so that a worker finds the frames it needs forgotten and
    // goes on on its own.
    use physframes::render::trails::SharedTrails;
    let (s, renderer, history) = trail_scene(40, 30);
    for limit in [usize::MAX, 0, 3000] {
        workers_sharing(&s, &renderer, &history, SharedTrails::keeping(2, limit));
    }
    workers_sharing(&s, &renderer, &history, SharedTrails::new(2));
}

/// The frames of two workers sharing `shared`, one jumping, against a layer on its
/// own (`workers_sharing_one_rasterisation_…`).
fn workers_sharing(
    s: &physframes::scene::Scene,
    renderer: &physframes::render::Renderer,
    history: &[physframes::history::PointHistory],
    shared: physframes::render::trails::SharedTrails,
) {
    use physframes::render::trails::TrailFrame;
    use physframes::render::FrameView;
    use std::sync::Arc;
    let shared = Arc::new(shared);
    let (w, h) = (s.render.width, s.render.height);
    let mut workers = [
        (
            TrailFrame::sharing(w, h, Arc::clone(&shared), 0),
            renderer.new_frame(),
        ),
        (
            TrailFrame::sharing(w, h, Arc::clone(&shared), 1),
            renderer.new_frame(),
        ),
    ];
    let mut alone = None;
    let frame = |k: usize, state: &mut TrailFrame, pixmap: &mut Pixmap| {
        let pos = history[k].last().expect("a frame").clone();
        let view = FrameView {
            index: k as u64,
            t: s.frame_time(k as u64),
            pos: &pos,
            vel: &[],
            angle: None,
            force: None,
            trail: Some(&history[k]),
            traces: None,
            compare: None,
        };
        renderer.draw_trail_frame(&view, pixmap, state);
        pixmap.clone()
    };
    // Worker 0 draws the even frames, worker 1 every third odd one, jumping.
    for k in 0..30 {
        if k % 4 == 0 {
            // The producer rasterises ahead, as in a render.
            renderer.rasterise_trails(&shared, &history[(k + 3).min(29)]);
        }
        let expected = draw_trail_frame(renderer, s, history, k, &mut alone);
        let worker = if k % 2 == 0 {
            Some(0)
        } else if k % 6 == 1 {
            Some(1)
        } else {
            None
        };
        if let Some(i) = worker {
            let (state, pixmap) = &mut workers[i];
            let got = frame(k, state, pixmap);
            assert!(
                got.data() == expected.data(),
                "frame {k}: worker {i} differs from a layer on its own"
            );
        }
    }
    let expected = draw_trail_frame(renderer, s, history, 4, &mut None);
    let (state, pixmap) = &mut workers[0];
    let back = frame(4, state, pixmap);
    assert!(
        back.data() == expected.data(),
        "going back to frame 4 differs"
    );
}

#[test]
fn a_trail_drawn_segment_by_segment_looks_like_one_stroke_through_its_points() {
    // Before issue #16 a trail was one translucent stroke (1.5 pixels, round joins and
    // caps) through every point so far; now it is its segments, each pixel keeping the
    // strongest coverage any segment gave it, which for one trail is the coverage by
    // the distance to its whole path, c = clamp(1.25 − d, 0, 1). That ramp is the area
    // a row or column has inside a straight stroke and within 0.045 of the area at any
    // other angle, and tiny-skia's sixteen samples a pixel are within 1/8 of it, so at
    // the trail's 55% opacity over white a channel may differ by about
    // 0.55 · 255 · (0.045 + 0.125) ≈ 24 levels at most, most pixels by a few: the
    // two spread the same ink (the ramp's integral across a straight stroke is its
    // width), so the total darkening may differ only by the round end (the ramp puts
    // 0.13 pixel more over a half disc of radius 0.75: about 30 levels at this colour
    // and opacity), the rounding of each pixel to 8 bits (at most 0.47 levels a pixel,
    // 0.3% over the whole trail) and tiny-skia's own samples: 1% in all. Measured on a
    // thrown body's 121 frames: 683 of 894 pixels differ, by 14/255 at most, and the
    // ink by 0.46% (with segments as polygons filled by tiny-skia's samples, before
    // the eighteenth session: 49 pixels, by 15).
    use tiny_skia::{LineCap, LineJoin, Paint, PathBuilder, Stroke, Transform};
    let text = "[simulation]\nduration = 4.0\n[render]\nwidth = 320\nheight = 180\nfps = 30\ntrails = true\nshow_bodies = true\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n[[body]]\nmass = 1.0\nposition = [2.0, 2.0]\nvelocity = [3.0, 5.5]\nshape = { circle = { radius = 0.01 } }\n[[force]]\nkind = \"gravity\"\ng = [0.0, -3.0]\n";
    let s = crate::util::scene(text);
    let renderer = renderer_of(&s);
    let frames = s.render.frame_count as usize;
    let history = trail_history(&s, frames as u64);
    let ours = draw_trail_frame(&renderer, &s, &history, frames - 1, &mut None);
    // The stroke, then the same tiny body over it.
    let mut stroke = renderer.new_frame();
    let mut pb = PathBuilder::new();
    for (k, p) in history[frames - 1].iter().enumerate() {
        let (x, y) = renderer.camera().to_pixel_f64(p[0]);
        if k == 0 {
            pb.move_to(x as f32, y as f32);
        } else {
            pb.line_to(x as f32, y as f32);
        }
    }
    let mut paint = Paint {
        anti_alias: true,
        ..Paint::default()
    };
    paint.set_color(physframes::render::bodies::color(s.bodies[0].color, 0.55));
    let line = Stroke {
        width: 1.5,
        line_cap: LineCap::Round,
        line_join: LineJoin::Round,
        ..Stroke::default()
    };
    stroke.stroke_path(
        &pb.finish().expect("a path"),
        &paint,
        &line,
        Transform::identity(),
        None,
    );
    let last = history[frames - 1].last().expect("a frame").clone();
    let body = physframes::render::bodies::BodyLook::new(&s.bodies[0], renderer.camera());
    let (x, y) = renderer.camera().to_pixel(last[0]);
    body.draw(&mut stroke, x, y);
    let (largest, count) = diff(&ours, &stroke);
    let background = renderer.new_frame();
    let touched = diff(&stroke, &background).1;
    eprintln!(
        "segments against one stroke: {count} of {touched} pixels differ, by {largest}/255 at most"
    );
    assert!(touched > 300, "the trail covers {touched} pixels");
    assert!(largest <= 24, "largest difference {largest}/255");
    // The ink each spreads: the darkening of every channel below the background,
    // summed over the image (the body, drawn over both alike, adds the same to each).
    let ink = |p: &tiny_skia::Pixmap| -> f64 {
        p.data()
            .iter()
            .zip(background.data())
            .map(|(a, b)| f64::from(*b) - f64::from(*a))
            .sum()
    };
    let (ours_ink, stroke_ink) = (ink(&ours), ink(&stroke));
    eprintln!("ink: segments {ours_ink}, one stroke {stroke_ink}");
    assert!(
        (ours_ink - stroke_ink).abs() <= 0.01 * stroke_ink,
        "the segments spread {ours_ink} of ink, the stroke {stroke_ink}"
    );
}

#[test]
fn hidden_bodies_still_leave_their_trails() {
    // `show_bodies = false` hides the bodies, not the trails a scene asks for: a frame
    // is the frame with the bodies shown, less the bodies. Two discs 6 pixels across
    // each (20 pixels a unit), thrown; every pixel where the two frames differ lies
    // within a body's reach of its last position (its radius and stroke, and a pixel
    // of anti-aliasing), and the trails cover pixels outside those discs.
    let text = |shown: bool| {
        format!(
            "[simulation]\nduration = 2.0\n[render]\nwidth = 320\nheight = 180\nfps = 30\ntrails = true\nshow_bodies = {shown}\nview = {{ min = [0.0, 0.0], max = [16.0, 9.0] }}\n[[body]]\nmass = 1.0\nposition = [2.0, 2.0]\nvelocity = [3.0, 5.5]\nshape = {{ circle = {{ radius = 0.15 }} }}\n[[body]]\nmass = 1.0\nposition = [14.0, 7.0]\nvelocity = [-4.0, -1.0]\nshape = {{ circle = {{ radius = 0.15 }} }}\n[[force]]\nkind = \"gravity\"\ng = [0.0, -3.0]\n"
        )
    };
    let frames = 61;
    let draw = |shown: bool| {
        let s = crate::util::scene(&text(shown));
        let renderer = renderer_of(&s);
        let history = trail_history(&s, frames);
        let frame = draw_trail_frame(&renderer, &s, &history, frames as usize - 1, &mut None);
        let last = history[frames as usize - 1]
            .last()
            .expect("a frame")
            .clone();
        let centres: Vec<(f64, f64)> = last
            .iter()
            .map(|p| renderer.camera().to_pixel_f64(*p))
            .collect();
        (frame, renderer.new_frame(), centres)
    };
    let (hidden, background, centres) = draw(false);
    let (shown, _, _) = draw(true);
    // The radius, 3 pixels, and the stroke's half width and a pixel of anti-aliasing.
    let reach = 3.0 + 1.0 + 1.5;
    let near = |i: usize| {
        let (x, y) = ((i % 320) as f64 + 0.5, (i / 320) as f64 + 0.5);
        centres.iter().any(|c| (x - c.0).hypot(y - c.1) <= reach)
    };
    let (mut trail_pixels, mut differing) = (0, 0);
    for (i, ((h, s), b)) in hidden
        .pixels()
        .iter()
        .zip(shown.pixels())
        .zip(background.pixels())
        .enumerate()
    {
        if h != s {
            assert!(near(i), "pixel {i} differs away from the bodies");
            differing += 1;
        }
        if h != b && !near(i) {
            trail_pixels += 1;
        }
    }
    // Each body's disc, hidden: about π·3² pixels, and at least half of them.
    assert!(differing >= 28, "{differing} pixels differ");
    // Two trails of 60 segments over 50 to 160 pixels of path, 1.5 pixels wide.
    assert!(trail_pixels > 200, "the trails cover {trail_pixels} pixels");
}

#[test]
fn turning_bodies_drawn_from_the_last_frames_damage_give_the_pixels_of_a_whole_redraw() {
    // A turning box's damage is the box of its turned corners, grown for its stroke:
    // tighter than the circle of its reach, it must still hold every pixel drawn. A
    // turning disc's is its sprite's rectangle and the box of its orientation line; a
    // turning body of point masses', the box of its discs and its marker.
    let mut text = String::from(
        "[render]\nwidth = 320\nheight = 180\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    for i in 0..60 {
        let shape = match (i % 8, i % 3) {
            (7, _) => "points = [{ offset = [-0.3, 0.1], mass = 1.0 }, { offset = [0.2, -0.1], mass = 3.0 }]",
            (_, 0) => "mass = 1.0\nshape = { box = { width = 0.5, height = 0.2 } }",
            (_, 1) => "mass = 1.0\nshape = { polygon = { points = [[-0.3, -0.2], [0.3, -0.1], [0.0, 0.3]] } }",
            _ => "mass = 1.0\nshape = { circle = { radius = 0.21 } }",
        };
        text.push_str(&format!(
            "[[body]]\nposition = [{:.2}, {:.2}]\nangular_velocity = 1.0\n{shape}\n",
            0.5 + (i % 10) as f64 * 1.6,
            0.5 + (i / 10) as f64 * 2.2,
        ));
    }
    let s = crate::util::scene(&text);
    let renderer = renderer_of(&s);
    let initial = s.initial_state();
    let mut pixmap = renderer.new_frame();
    let mut damage = physframes::render::Damage::default();
    for k in 0..16 {
        let pos: Vec<glam::DVec2> = initial
            .pos
            .iter()
            .enumerate()
            .map(|(i, p)| *p + k as f64 * glam::DVec2::new(0.011 * i as f64, -0.05))
            .collect();
        let angle: Vec<f64> = (0..pos.len())
            .map(|i| 0.37 * (k * (i + 1)) as f64)
            .collect();
        let view = physframes::render::FrameView {
            index: k as u64,
            t: 0.0,
            pos: &pos,
            vel: &[],
            angle: Some(&angle),
            force: None,
            trail: None,
            traces: None,
            compare: None,
        };
        renderer.draw_damaged(&view, &mut pixmap, &mut damage);
        assert!(
            !damage.is_whole(),
            "frame {k}: the damage should be rectangles"
        );
        let whole = renderer.draw(&view);
        // And those are the pixels of every pass drawn over the whole frame (the
        // path shared by redraws could hide a mistake from the comparison above).
        assert!(
            whole.data() == renderer.draw_every_pass(&view).data(),
            "frame {k} differs from every pass drawn whole"
        );
        assert!(
            pixmap.data() == whole.data(),
            "frame {k} differs from a redraw"
        );
        let mut outside = renderer.static_layer().clone();
        let width = outside.width() as usize;
        for r in damage.rects() {
            for y in r.y0 as usize..r.y1 as usize {
                let span = 4 * (y * width + r.x0 as usize)..4 * (y * width + r.x1 as usize);
                outside.data_mut()[span.clone()].copy_from_slice(&pixmap.data()[span]);
            }
        }
        assert!(
            outside.data() == pixmap.data(),
            "frame {k} drew outside its damage"
        );
    }
}

#[test]
fn turning_sprites_look_like_their_paths_at_the_exact_angle_and_position() {
    // A stamp is the look at its angle rounded to the nearest of N bins (which moves
    // its farthest point by at most 1/8 pixel) and its position rounded to 1/8 pixel
    // (at most 1/16 along each axis), drawn by the scan converter. Against tiny-skia's
    // paths at the exact angle and position, edge pixels change as they would if the
    // look moved by those amounts: tiny-skia samples a pixel at 4 × 4 points, so a
    // shift of 1/8 pixel can change an edge pixel by a few samples of 16/255.
    // Measured over 400 angles and positions: the box differs on 28% of the pixels it
    // covers, by 3.5/255 on average and 59/255 at most; the triangle 2.5 and 42.
    // Polygons that are not convex (an L, a star) are stamped the same way, from the
    // general scan.
    use physframes::render::bodies::BodyLook;
    use physframes::render::turning::{TurningCoverage, TurningSheet};
    use physframes::scene::Shape;
    let camera = camera_16_by_9();
    let s = crate::util::scene(
        "[render]\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n[[body]]\nmass = 1.0\nangular_velocity = 1.0\n",
    );
    for (shape, color) in [
        (
            Shape::Box {
                width: 0.16,
                height: 0.08,
            },
            [0x1f, 0x77, 0xb4, 0xff],
        ),
        (
            Shape::Polygon {
                points: vec![
                    glam::DVec2::new(-0.1, -0.05),
                    glam::DVec2::new(0.12, -0.04),
                    glam::DVec2::new(0.0, 0.1),
                ],
            },
            [0x94, 0x67, 0xbd, 0xc0],
        ),
        (concave_shapes()[0].clone(), [0x2c, 0xa0, 0x2c, 0xff]),
        (concave_shapes()[1].clone(), [0xd6, 0x27, 0x28, 0xff]),
    ] {
        let mut body = s.bodies[0].clone();
        body.shape = shape.clone();
        body.color = physframes::scene::Rgba(color);
        let look = BodyLook::new(&body, &camera);
        let coverage = TurningCoverage::new(&look).expect("small and of straight edges");
        let sheet = TurningSheet::new(coverage, &look);
        let (mut largest, mut count, mut covered, mut total) = (0u8, 0usize, 0usize, 0u64);
        for k in 0..400u32 {
            let theta = f64::from(k) * 0.0173 - 3.3;
            let x = 30.0 + (k % 10) as f32 * 0.113;
            let y = 30.0 + (k / 10 % 10) as f32 * 0.171;
            let mut stamped = Pixmap::new(60, 60).expect("pixmap");
            stamped.fill(Color::from_rgba8(250, 248, 240, 255));
            let mut path = stamped.clone();
            let background = stamped.clone();
            sheet.stamp(&mut stamped, x, y, theta);
            look.draw_turned(&mut path, x, y, theta);
            let (l, c) = diff(&stamped, &path);
            largest = largest.max(l);
            count += c;
            covered += diff(&path, &background).1;
            total += crate::util::total_difference(&stamped, &path);
        }
        let mean = total as f64 / covered as f64;
        eprintln!("{shape:?}: {count} of {covered} covered pixels differ, by {largest}/255 at most, {mean:.2}/255 on average");
        assert!(largest <= 64, "{shape:?}: largest difference {largest}/255");
        assert!(mean < 4.0, "{shape:?}: mean difference {mean}/255");
    }
}

/// `count` moving boxes of one size, triangles of one shape and L shapes (a polygon
/// that is not convex), none turning, each at a fixed angle of its own, in a `width` ×
/// `height` image.
fn crates_scene(count: usize, width: u32, height: u32) -> String {
    let mut text = format!(
        "[simulation]\nduration = 2.0\n[render]\nwidth = {width}\nheight = {height}\nfps = 20\nview = {{ min = [0.0, 0.0], max = [16.0, 9.0] }}\n",
    );
    for i in 0..count {
        let k = (i * 7919) % 293;
        let shape = if i % 5 == 4 {
            "{ polygon = { points = [[-0.08, -0.08], [0.08, -0.08], [0.08, -0.03], [-0.03, -0.03], [-0.03, 0.08], [-0.08, 0.08]] } }"
        } else if i % 3 == 2 {
            "{ polygon = { points = [[-0.1, -0.05], [0.12, -0.04], [0.0, 0.1]] } }"
        } else {
            "{ box = { width = 0.16, height = 0.08 } }"
        };
        text.push_str(&format!(
            "[[body]]\nmass = 1.0\nposition = [{:.3}, {:.3}]\nvelocity = [{:.3}, {:.3}]\nangle = {:.4}\nshape = {shape}\n",
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
            ((k % 13) as f64 - 6.0) * 0.4,
            ((i % 11) as f64 - 5.0) * 0.3,
            6.2 * i as f64 / count as f64 - 3.1,
        ));
    }
    text
}

/// `count` moving bodies of two point masses each (dumbbells), alike, none turning but
/// every fifth, in the default colours, in a `width` × `height` image.
fn dumbbells_scene(count: usize, width: u32, height: u32) -> String {
    let mut text = format!(
        "[simulation]\nduration = 2.0\n[render]\nwidth = {width}\nheight = {height}\nfps = 20\nview = {{ min = [0.0, 0.0], max = [16.0, 9.0] }}\n",
    );
    for i in 0..count {
        let k = (i * 7919) % 293;
        text.push_str(&format!(
            "[[body]]\nposition = [{:.3}, {:.3}]\nvelocity = [{:.3}, {:.3}]\npoints = [{{ offset = [-0.1, 0.0], mass = 1.0 }}, {{ offset = [0.1, 0.0], mass = 2.0 }}]\n",
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
            ((k % 13) as f64 - 6.0) * 0.4,
            ((i % 11) as f64 - 5.0) * 0.3,
        ));
        if i % 5 == 4 {
            text.push_str("angular_velocity = 1.5\n");
        }
    }
    text
}

#[test]
fn dumbbells_that_never_turn_are_pictures_and_look_like_their_paths() {
    // Bodies of point masses that never turn are laid over the frame as pictures
    // (`perf.rs` bounds a picture against its paths at the snapped position by 4/255);
    // against paths at the exact position, as every sprite, edges move by at most
    // 1/16 pixel along each axis, less than the quarter pixel between tiny-skia's
    // samples: one sample a sub-row per edge through a pixel, 64/255 for a pixel an
    // edge crosses (and a few 255ths more where the marker's ring, a hairline whose
    // coverage moves continuously, passes too). The pixel at the centre-of-mass
    // marker's middle holds two lines, the boundaries of its black and white quarters:
    // 2 · 64 = 128/255 at most. Measured: 96/255 there, 67/255 elsewhere, a third of
    // the covered pixels differing. The turning ones, at angle 0 in this first frame,
    // are drawn as their paths (turning ones at other angles: the next test).
    use physframes::render::BodyDrawing;
    let s = crate::util::scene(&dumbbells_scene(200, 1280, 720));
    let looks =
        physframes::render::looks::Looks::new(&s.bodies, &camera_16_by_9(), BodyDrawing::Sprites);
    for (b, &l) in s.bodies.iter().zip(&looks.look_of) {
        let look = &looks.looks[l as usize];
        assert_eq!(
            look.picture.is_some(),
            !b.turns,
            "a picture when it never turns"
        );
    }
    let (fast, paths, background) = crate::util::first_frame_both_ways(&s);
    let (largest, count) = diff(&fast, &paths);
    let covered = diff(&paths, &background).1;
    eprintln!("dumbbells: {count} of {covered} covered pixels differ, by {largest}/255 at most");
    assert!(covered > 20_000, "the bodies cover {covered} pixels");
    assert!(largest <= 128, "largest difference {largest}/255");
    assert!(count * 2 <= covered, "{count} of {covered} pixels differ");
}

/// The text of a scene of `count` bodies of point masses in the default colours, at
/// angles of their own: `body(i)` gives each one's masses and whether it turns.
fn points_scene(count: usize, body: impl Fn(usize) -> (String, bool)) -> String {
    let mut text = String::from(
        "[simulation]\nduration = 2.0\n[render]\nwidth = 1280\nheight = 720\nfps = 20\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    for i in 0..count {
        let k = (i * 7919) % 293;
        let (points, turns) = body(i);
        text.push_str(&format!(
            "[[body]]\nposition = [{:.3}, {:.3}]\nangle = {:.4}\npoints = {points}\n",
            0.3 + (k as f64 * 0.161) % 15.4,
            0.3 + (i as f64 * 0.377) % 8.4,
            0.1 + (i as f64 * 0.731) % 6.0,
        ));
        if turns {
            text.push_str("angular_velocity = 1.5\n");
        }
    }
    text
}

/// 300 turning bodies of point masses: dumbbells whose discs overlap, dumbbells whose
/// discs stand apart, and triangles of three masses.
fn turning_points_scene(count: usize) -> String {
    let shapes = [
        "[{ offset = [-0.05, 0.0], mass = 1.0 }, { offset = [0.05, 0.0], mass = 2.0 }]",
        "[{ offset = [-0.15, 0.0], mass = 1.0 }, { offset = [0.15, 0.0], mass = 1.0 }]",
        "[{ offset = [0.0, 0.12], mass = 1.0 }, { offset = [-0.1, -0.06], mass = 1.0 }, { offset = [0.1, -0.06], mass = 2.0 }]",
    ];
    points_scene(count, |i| (shapes[i % 3].to_string(), true))
}

/// `count` bodies of point masses, no two of the same masses, every other one turning:
/// dumbbells and triangles of masses.
fn unique_points_scene(count: usize) -> String {
    points_scene(count, |i| {
        let m = 1.0 + i as f64 * 0.0137;
        let points = if i % 3 == 2 {
            format!("[{{ offset = [0.0, 0.12], mass = 1.0 }}, {{ offset = [-0.1, -0.06], mass = {m:.4} }}, {{ offset = [0.1, -0.06], mass = 2.0 }}]")
        } else {
            format!("[{{ offset = [-0.1, 0.0], mass = 1.0 }}, {{ offset = [0.1, 0.0], mass = {m:.4} }}]")
        };
        (points, i % 2 == 0)
    })
}

/// Checks that every body of `text` is drawn by layers, and that its first frame
/// differs from exact paths by at most 128/255 on at most half the covered pixels;
/// returns the scene.
fn assert_drawn_by_layers_like_paths(text: &str, what: &str) -> physframes::scene::Scene {
    use physframes::render::BodyDrawing;
    let s = crate::util::scene(text);
    let looks =
        physframes::render::looks::Looks::new(&s.bodies, &camera_16_by_9(), BodyDrawing::Sprites);
    for &l in &looks.look_of {
        let look = &looks.looks[l as usize];
        assert!(
            look.points.is_some() && look.picture.is_none(),
            "drawn by layers"
        );
    }
    let (fast, paths, background) = crate::util::first_frame_both_ways(&s);
    let (largest, count) = diff(&fast, &paths);
    let covered = diff(&paths, &background).1;
    let total = crate::util::total_difference(&fast, &paths);
    let mean = total as f64 / covered as f64;
    eprintln!("{what}: {count} of {covered} covered pixels differ, by {largest}/255 at most, {mean:.2}/255 on average");
    assert!(covered > 40_000, "the bodies cover {covered} pixels");
    assert!(largest <= 128, "largest difference {largest}/255");
    assert!(count * 2 <= covered, "{count} of {covered} pixels differ");
    s
}

#[test]
fn turning_bodies_of_point_masses_are_drawn_layer_by_layer_and_look_like_their_paths() {
    // Turning bodies of point masses that 16 or more share are drawn by layers
    // (`render/points.rs`): bars as tiny-skia's stroke rectangles through the scan
    // converter (its coverage exactly), discs and the marker as sprites at positions
    // snapped by at most 1/16 pixel along each axis. As for every sprite, an edge moving
    // less than the quarter pixel between tiny-skia's samples changes a pixel by at most
    // one sample a sub-row, 64/255. Two more effects reach a pixel: the marker's middle
    // holds two lines (128, as for pictures), and where two discs' anti-aliased rims
    // cross, the path fills their union once where the layers blend each disc in turn:
    // coverages a and b give a + b - ab against about max(a, b), at most a quarter of
    // the contrast, 64/255, on top of the rims' own 64. So 128/255 at most; measured:
    // 96/255, 4.2/255 on average. A body at a multiple of a right angle (none here) is
    // drawn as its path.
    assert_drawn_by_layers_like_paths(&turning_points_scene(300), "turning point masses");
}

#[test]
fn bodies_of_point_masses_of_their_own_are_drawn_by_layers_and_look_like_their_paths() {
    // No two bodies share masses, so none shares a geometry; in a scene of 16 or more
    // bodies of point masses each is drawn by layers, its discs' radii snapped to 1/8
    // pixel. The radius's snap moves a rim by at most 1/16 pixel more, so an edge
    // moves by at most 1/16 + √2/16 = 0.15 pixel, still under the quarter pixel
    // between tiny-skia's samples: the bounds of the test above hold (128/255 at most,
    // where the marker's two lines or two discs' rims meet in one pixel; measured:
    // 110/255). Unturned, the discs' outlines are hairlines in the paths and in the
    // sprites. The frames are the same bytes with one thread and two.
    let text = unique_points_scene(300);
    let s = assert_drawn_by_layers_like_paths(&text, "point masses of their own");
    let looks = physframes::render::looks::Looks::new(
        &s.bodies,
        &camera_16_by_9(),
        physframes::render::BodyDrawing::Sprites,
    );
    assert_eq!(looks.looks.len(), 300, "every body a look of its own");
    let frames = |threads: &str| {
        let sandbox = crate::util::Sandbox::new();
        sandbox.write("points.toml", &text);
        let out = sandbox.run(&[
            "render",
            "points.toml",
            "--frames",
            "0..3",
            "--threads",
            threads,
            "--out",
            "f",
        ]);
        assert_eq!(out.status.code(), Some(0), "{}", crate::util::stderr(&out));
        (0..3)
            .map(|k| std::fs::read(sandbox.path(&format!("f/frame_{k:06}.png"))).expect("a frame"))
            .collect::<Vec<_>>()
    };
    assert!(
        frames("1") == frames("2"),
        "the same bytes with one thread and two"
    );
}

#[test]
fn crates_at_angles_of_their_own_are_stamped_from_the_turning_sprites() {
    // 300 boxes of one size, triangles of one shape and L shapes, none turning, each at
    // a fixed angle of its own: no two share a geometry, but 16 or more share a shape,
    // so each is stamped from its shape's sprites at angle bins, at its angle. The
    // bounds are those of turning sprites against paths (the test above).
    use physframes::render::BodyDrawing;
    let s = crate::util::scene(&crates_scene(300, 1280, 720));
    let looks =
        physframes::render::looks::Looks::new(&s.bodies, &camera_16_by_9(), BodyDrawing::Sprites);
    assert_eq!(looks.looks.len(), 300, "every body a look of its own");
    for (look, body) in looks.looks.iter().zip(&s.bodies) {
        assert!(look.turning.is_some() && look.sprite.is_none());
        assert_eq!(look.fixed_angle, Some(body.angle));
    }
    let (stamped, paths, background) = crate::util::first_frame_both_ways(&s);
    let (largest, count) = diff(&stamped, &paths);
    let covered = diff(&paths, &background).1;
    let total = crate::util::total_difference(&stamped, &paths);
    let mean = total as f64 / covered as f64;
    eprintln!("crates at their own angles: {count} of {covered} covered pixels differ, by {largest}/255 at most, {mean:.2}/255 on average");
    assert!(covered > 20_000, "the bodies cover {covered} pixels");
    assert!(largest <= 64, "largest difference {largest}/255");
    assert!(mean < 4.0, "mean difference {mean}/255");
}

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
    let row = |name: &str| {
        text.lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("no row for {name} in:\n{text}"))
            .split_whitespace()
            .map(str::to_string)
            .collect::<Vec<_>>()
    };
    // The reference, added since it was not listed, has a ratio of 1.
    assert_eq!(row("drag")[4], "1.00", "{text}");
    assert!(text.contains("(reference)"), "{text}");
    let ratio: f64 = row("trails")[4].parse().expect("a ratio");
    assert!(ratio > 0.0, "{text}");
    // A scene with trails also says what its first and last frames cost.
    assert!(
        text.contains("first 6 frames") && text.contains("last 6 frames"),
        "{text}"
    );
    // And what they cost without writing, which is part of what they cost.
    let edges = text
        .lines()
        .find(|l| l.contains("first 6 frames"))
        .expect("the line of the first and last frames");
    // The times are the numbers written with a decimal point.
    let ms: Vec<f64> = edges
        .split_whitespace()
        .filter(|w| w.contains('.'))
        .filter_map(|w| w.trim_end_matches([',', ';']).parse().ok())
        .collect();
    let [first, last, first_unwritten, last_unwritten] = ms[..] else {
        panic!("four times in {edges:?}: {ms:?}");
    };
    assert!(
        edges.contains("without writing")
            && (0.0..=first).contains(&first_unwritten)
            && (0.0..=last).contains(&last_unwritten),
        "{edges}"
    );
    assert!(
        text.contains("ratio: frames/s over those of drag"),
        "{text}"
    );
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
    let text = crate::util::stdout(&out);
    assert!(text.contains("ratio: none (--reference none)"), "{text}");
}

#[test]
fn many_springs_covered_by_distance_look_like_tiny_skias_strokes() {
    // Springs between pairs of bodies at every angle and at distances from 0.1 (a
    // straight line: shorter than its coil is wide) to 6 (a coil stretched long), some
    // crossing the image's edge, drawn both ways over a light background.
    use physframes::render::springs::Springs;
    let mut text = String::from(
        "[render]\nwidth = 320\nheight = 180\nshow_springs = true\nview = { min = [0.0, 0.0], max = [16.0, 9.0] }\n",
    );
    let pairs = 300;
    for k in 0..pairs {
        let a = f64::from(k) * 2.399_963; // the golden angle: every direction.
        let len = 0.1 + f64::from(k % 20) * 0.31;
        let (x, y) = (
            0.4 + f64::from(k % 10) * 1.71 + 0.013 * f64::from(k),
            0.3 + f64::from(k % 7) * 1.37,
        );
        for (i, (px, py)) in [(x, y), (x + len * a.cos(), y + len * a.sin())]
            .into_iter()
            .enumerate()
        {
            text.push_str(&format!(
                "[[body]]\nname = \"b{k}_{i}\"\nmass = 1.0\nposition = [{px}, {py}]\n"
            ));
        }
        text.push_str(&format!(
            "[[force]]\nkind = \"spring\"\na = \"b{k}_0\"\nb = \"b{k}_1\"\nstiffness = 1.0\n"
        ));
    }
    let s = crate::util::scene(&text);
    let springs = Springs::new(&s).expect("the scene shows springs");
    assert_eq!(springs.len(), pairs as usize);
    let camera = physframes::render::Camera::fit(s.render.view, 320, 180);
    let clip = ClipRect::guard(320, 180);
    let pos: Vec<glam::DVec2> = s.bodies.iter().map(|b| b.position).collect();
    let mut fast = Pixmap::new(320, 180).expect("pixmap");
    fast.fill(Color::from_rgba8(250, 248, 240, 255));
    let mut paths = fast.clone();
    let background = fast.clone();
    springs.draw(&mut fast, (&camera, &clip), (&pos, None), true);
    springs.draw(&mut paths, (&camera, &clip), (&pos, None), false);
    let (largest, count) = diff(&fast, &paths);
    let covered = diff(&paths, &background).1;
    let mean = crate::util::total_difference(&fast, &paths) as f64 / covered as f64;
    eprintln!(
        "springs: {covered} pixels covered, {count} differ, by {mean:.2}/255 on average and {largest}/255 at most"
    );
    assert!(covered > 20_000, "the springs cover pixels ({covered})");
    // Measured: 5.4/255 on average and 82/255 at most, where the two sides of a sharp
    // join meet in one pixel (there the distance's ramp falls short of the union's
    // area). Most of the mean is tiny-skia's own: its four sub-rows a pixel put a
    // straight line's edges off by up to 1/8 pixel, 3.5 to 12.5 levels on average.
    assert!(largest <= 96, "springs differ by {largest}/255");
    assert!(mean <= 6.0, "springs differ by {mean:.2}/255 on average");
}
