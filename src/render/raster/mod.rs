//! A scan converter for small polygons that computes coverage exactly as tiny-skia's
//! anti-aliased filler does, without its per-path set-up.
//!
//! Drawing a thousand small paths a frame through tiny-skia costs far more in setting
//! up each path (a path object, edge lists, a pipeline, a blitter) than in covering its
//! few pixels. What moves every frame in its own way, and so cannot be a sprite (a box
//! at any angle, a translucent outline), is drawn here instead: one
//! or more closed polygons filled with the nonzero rule, which covers a convex shape,
//! and the ring between two nested ones (an outline's stroke), with the coverage blended
//! by tiny-skia's 8-bit arithmetic ([`Ink`]).
//!
//! The scan conversion is tiny-skia's (Skia's supersampler with `SHIFT = 2`), step for
//! step: each point is taken to 1/256 pixel by truncation, each edge gets its first and
//! last sub-row (4 per pixel row) and its slope in 16.16 fixed point, and is stepped
//! sub-row by sub-row; in each sub-row the spans between crossings, rounded to quarter
//! pixels, add 16 per quarter pixel to a pixel's coverage, or 64 (63 in the last
//! sub-row, so that a covered pixel makes 255) when they cover it whole. So a polygon
//! of straight edges inside the image gets, bit for bit, tiny-skia's coverage for the
//! same f32 points (tested). What differs is only the points themselves: curves (a
//! stroke's round joins and caps) are flattened here into chords, where tiny-skia
//! steps quadratic edges, and the corners of a stroke are computed in f64. The
//! difference that makes against tiny-skia's paths is bounded in
//! `tests/integration/perf.rs`.
//!
//! `convex.rs` walks convex shapes quicker than the general scan here (with their
//! rows' coverage and blend eight pixels at a time in `eight.rs`, and in `avx2.rs`
//! with AVX2 where the processor has it, the same bytes), `shapes.rs`
//! builds the polygons of strokes (a line's rectangle, a stroked outline's ring), and
//! `clipper.rs` cuts a shape's edges to the image as tiny-skia does. Two files
//! approximate instead, each within a stated bound of tiny-skia: `lines.rs`, thin
//! round-joined polylines (springs' coils, and trails a segment at a time) covered by
//! the distance of each pixel's centre to the line; and `ramps/`, arrows' shafts and
//! heads covered by the product of a ramp across each side.
//!
//! Coordinates must be near the image: callers clip them to the guard band first, where
//! the fixed-point arithmetic cannot overflow (tiny-skia's limit is 8191 pixels).

#[cfg(target_arch = "x86_64")]
mod avx2;
mod clipper;
mod convex;
mod eight;
mod lines;
mod ramps;
mod segment;
mod shapes;

use std::cell::RefCell;

use tiny_skia::Pixmap;

use super::sprite::Ink;
use clipper::ImageClip;

pub(crate) use avx2::{available as avx2_available, stamp_layer_row, stamp_row};
pub use convex::{cover_convex, fill_convex, fill_layers, fill_turned, fill_turned_apart};
pub(crate) use eight::{prefetch, prefetch_around, AHEAD, PREFETCH_REACH};
pub(crate) use lines::capsule_spans;
pub use lines::{cover_capsule, stroke_polyline};
pub use ramps::{fill_ramps, Ramps};
pub use shapes::{bar, capsule, disc, Ring, DISC_POLYGON_TOLERANCE};

/// A point in pixels.
pub type Point = (f32, f32);

/// One straight edge in tiny-skia's fixed point: x in 16.16 at the centre of its
/// current sub-row, advanced by `dx` per sub-row, over sub-rows `first..=last`.
#[derive(Clone, Copy, Debug)]
struct Edge {
    x: i64,
    dx: i64,
    first: i64,
    last: i64,
    winding: i8,
}

impl Edge {
    /// Builds the edge from `p0` to `p1` as tiny-skia's `LineEdge::new` does with
    /// `shift = 2`, or `None` when it spans no sub-row's centre.
    fn new(p0: Point, p1: Point) -> Option<Edge> {
        Edge::from_fixed(Edge::fixed(p0), Edge::fixed(p1))
    }

    /// A point in 26.6 fixed point of sub-pixels: 256 units a pixel, truncated.
    #[inline(always)]
    fn fixed(p: Point) -> (i64, i64) {
        let fdot6 = |v: f32| i64::from((v * 256.0) as i32);
        (fdot6(p.0), fdot6(p.1))
    }

    /// [`Edge::new`] from its ends already in fixed point ([`Edge::fixed`]), so that a
    /// polygon's points are converted once each, not once for each of their edges.
    #[inline]
    fn from_fixed((x0, y0): (i64, i64), (x1, y1): (i64, i64)) -> Option<Edge> {
        let (mut x0, mut y0, mut x1, mut y1) = (x0, y0, x1, y1);
        let mut winding = 1;
        if y0 > y1 {
            std::mem::swap(&mut x0, &mut x1);
            std::mem::swap(&mut y0, &mut y1);
            winding = -1;
        }
        let round = |v: i64| (v + 32) >> 6;
        let (top, bottom) = (round(y0), round(y1));
        if top == bottom {
            return None;
        }
        let (ddx, ddy) = (x1 - x0, y1 - y0);
        // fdot6::div: 16.16 slope, clamped to 32 bits.
        let slope = ((ddx << 16) / ddy).clamp(i64::from(i32::MIN), i64::from(i32::MAX));
        let dy = (top << 6) + 32 - y0;
        Some(Edge {
            x: (x0 + ((slope * dy) >> 16)) << 10,
            dx: slope,
            first: top,
            last: bottom - 1,
            winding,
        })
    }

    /// The edge's crossing of its current sub-row, rounded to a quarter-pixel column.
    fn column(&self) -> i64 {
        (self.x + 0x8000) >> 16
    }
}

/// What one thread reuses from shape to shape.
#[derive(Default)]
struct Scratch {
    edges: Vec<Edge>,
    active: Vec<Edge>,
    /// The coverage of one pixel row.
    row: Vec<u16>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// Fills closed polygons (each a list of points, closed back to its first) with the
/// nonzero rule, blending `ink` with their coverage. A polygon with a point that is not
/// finite is skipped.
pub fn fill_polygons(pixmap: &mut Pixmap, polygons: &[&[Point]], ink: Ink) {
    SCRATCH.with(|scratch| {
        let scratch = &mut *scratch.borrow_mut();
        scratch.edges.clear();
        let clip = ImageClip::new(pixmap.width() as usize, pixmap.height() as usize, polygons);
        for points in polygons {
            add_polygon(&mut scratch.edges, points, &clip);
        }
        scan(pixmap, scratch, ink);
    });
}

/// Draws an outline of any shape, closed and of straight edges (a polygon that need not
/// be convex), turned and placed by `at`: the polygon `fill` in `fill_ink` with the
/// nonzero rule, the bytes of tiny-skia's fill of the same f32 points (taken through
/// `at` by tiny-skia's own `Transform::map_points`), then its stroke in `edge_ink`: the
/// union of `stroke`'s polygons, the capsules of the outline's edges (the disc of the
/// stroke's half-width swept along each edge, so round joins), which differs from
/// tiny-skia's stroke only where round parts are cut into chords and at the inner
/// corners, which tiny-skia takes round each corner's pivot.
pub fn fill_outline(
    pixmap: &mut Pixmap,
    fill: &[Point],
    stroke: &[Vec<Point>],
    at: tiny_skia::Transform,
    fill_ink: Ink,
    edge_ink: Ink,
) {
    outline(pixmap, None, fill, stroke, at, [fill_ink, edge_ink]);
}

/// Draws an outline like [`fill_outline`], its fill into `fill_pixmap` and its stroke
/// into `edge_pixmap`, both in `ink`: with opaque white over transparent pixmaps, the
/// alpha of each is the coverage, as sprites keep it.
pub fn fill_outline_apart(
    fill_pixmap: &mut Pixmap,
    edge_pixmap: &mut Pixmap,
    fill: &[Point],
    stroke: &[Vec<Point>],
    at: tiny_skia::Transform,
    ink: Ink,
) {
    outline(fill_pixmap, Some(edge_pixmap), fill, stroke, at, [ink, ink]);
}

fn outline(
    pixmap: &mut Pixmap,
    edge_pixmap: Option<&mut Pixmap>,
    fill: &[Point],
    stroke: &[Vec<Point>],
    at: tiny_skia::Transform,
    [fill_ink, edge_ink]: [Ink; 2],
) {
    OUTLINE.with(|buffers| {
        let (scratch, placed) = &mut *buffers.borrow_mut();
        if placed.len() < stroke.len() + 1 {
            placed.resize_with(stroke.len() + 1, Vec::new);
        }
        let (first, rest) = placed.split_at_mut(1);
        place(at, fill, scratch, &mut first[0]);
        fill_polygons(pixmap, &[&first[0]], fill_ink);
        for (from, to) in stroke.iter().zip(rest.iter_mut()) {
            place(at, from, scratch, to);
        }
        let polygons: Vec<&[Point]> = rest[..stroke.len()].iter().map(|p| &p[..]).collect();
        fill_polygons(edge_pixmap.unwrap_or(pixmap), &polygons, edge_ink);
    });
}

/// Takes points through `at` by tiny-skia's own `Transform::map_points` (so that they
/// are, bit for bit, the points tiny-skia would fill) into `to`, with `scratch` reused.
pub(super) fn place(
    at: tiny_skia::Transform,
    from: &[Point],
    scratch: &mut Vec<tiny_skia::Point>,
    to: &mut Vec<Point>,
) {
    scratch.clear();
    scratch.extend(from.iter().map(|&(x, y)| tiny_skia::Point::from_xy(x, y)));
    at.map_points(scratch);
    to.clear();
    to.extend(scratch.iter().map(|p| (p.x, p.y)));
}

thread_local! {
    /// Each thread's transformed points of an outline and of its stroke's polygons.
    static OUTLINE: RefCell<(Vec<tiny_skia::Point>, Vec<Vec<Point>>)> =
        RefCell::new(Default::default());
}

/// Adds the edges of a closed polygon, unless a point is not finite.
fn add_polygon(edges: &mut Vec<Edge>, points: &[Point], clip: &ImageClip) {
    if points.len() < 3 || !points.iter().all(|p| p.0.is_finite() && p.1.is_finite()) {
        return;
    }
    let mut previous = points[points.len() - 1];
    for &p in points {
        clip.cut(previous, p, |a, b| edges.extend(Edge::new(a, b)));
        previous = p;
    }
}

/// Fills the ring between two nested convex polygons, `outer` less `inner`, by filling
/// both with the nonzero rule, the inner one wound against the outer one.
pub fn fill_ring(pixmap: &mut Pixmap, outer: &[Point], inner: &mut [Point], ink: Ink) {
    if inner.len() >= 3 && signed_area(outer) * signed_area(inner) > 0.0 {
        inner.reverse();
    }
    fill_polygons(pixmap, &[outer, inner], ink);
}

/// ⌊v⌋ for a finite v near the image, without a call to the C library (x86-64's
/// baseline has no rounding instruction).
#[inline(always)]
pub(super) fn floor(v: f64) -> i64 {
    let i = v as i64;
    i - i64::from((i as f64) > v)
}

/// ⌈v⌉, likewise.
#[inline(always)]
pub(super) fn ceil(v: f64) -> i64 {
    let i = v as i64;
    i + i64::from((i as f64) < v)
}

/// Twice the signed area of a polygon (the shoelace formula).
pub(super) fn signed_area(points: &[Point]) -> f64 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let (a, b) = (points[i], points[(i + 1) % n]);
            f64::from(a.0) * f64::from(b.1) - f64::from(b.0) * f64::from(a.1)
        })
        .sum()
}

/// Scan-converts the edges sub-row by sub-row, as tiny-skia's `walk_edges` does for the
/// nonzero rule, and blends each pixel row's coverage in `ink` as it is finished.
fn scan(pixmap: &mut Pixmap, scratch: &mut Scratch, ink: Ink) {
    let Scratch { edges, active, row } = scratch;
    if edges.is_empty() {
        return;
    }
    let (width, height) = (pixmap.width() as usize, pixmap.height() as usize);
    let max_column = 4 * width as i64;
    let first = edges.iter().map(|e| e.first).min().unwrap_or(0).max(0);
    let end = (edges.iter().map(|e| e.last).max().unwrap_or(-1) + 1).min(4 * height as i64);
    if first >= end {
        return;
    }
    // Edges in order of their first sub-row, so that each joins the active list once.
    edges.sort_unstable_by_key(|e| e.first);
    if row.len() < width + 1 {
        row.resize(width + 1, 0);
    }
    active.clear();
    let mut next = 0;
    let data = pixmap.data_mut();
    let mut sy = first;
    while sy < end {
        let py = (sy >> 2) as usize;
        let row_end = ((sy >> 2) + 1) * 4;
        let (mut lo, mut hi) = (usize::MAX, 0usize);
        while sy < row_end.min(end) {
            // Edges that start at or above this sub-row join, advanced to it (those
            // starting above the image are stepped down to its first sub-row).
            while next < edges.len() && edges[next].first <= sy {
                let mut e = edges[next];
                next += 1;
                if e.last >= sy {
                    e.x += e.dx * (sy - e.first);
                    active.push(e);
                }
            }
            // Sorted by their fixed-point x; small lists, so insertion sort.
            for i in 1..active.len() {
                let mut j = i;
                while j > 0 && active[j - 1].x > active[j].x {
                    active.swap(j - 1, j);
                    j -= 1;
                }
            }
            let full = 64 - u16::from(sy & 3 == 3);
            let mut w = 0i32;
            let mut left = 0i64;
            for e in active.iter() {
                let x = e.column().clamp(0, max_column);
                if w == 0 {
                    left = x;
                }
                w += i32::from(e.winding);
                if w == 0 && x > left {
                    lo = lo.min((left >> 2) as usize);
                    hi = hi.max(((x + 3) >> 2) as usize);
                    accumulate(row, left, x, full);
                }
            }
            // Step every edge to the next sub-row; drop those that end here.
            active.retain_mut(|e| {
                e.x += e.dx;
                e.last > sy
            });
            sy += 1;
        }
        if lo < hi {
            let base = 4 * py * width;
            for (x, c) in row.iter_mut().enumerate().take(hi.min(width)).skip(lo) {
                let c = std::mem::take(c);
                if c != 0 {
                    let k = base + 4 * x;
                    // Skia's runs cap a sum of 256 at 255: (a - (a >> 8)).
                    ink.blend(&mut data[k..k + 4], (c - (c >> 8)).min(255) as u8);
                }
            }
            row[width] = 0;
        }
    }
}

/// Adds one sub-row's span of quarter-pixel columns a..b to the row's coverage: 16 for
/// each quarter of a pixel covered, and `full` (64, or 63 in a row's last sub-row) for
/// a pixel covered whole, as Skia's supersampler does.
#[inline]
fn accumulate(row: &mut [u16], a: i64, b: i64, full: u16) {
    let (pa, pb) = ((a >> 2) as usize, (b >> 2) as usize);
    let (fa, fb) = ((a & 3) as u16, (b & 3) as u16);
    if pa == pb {
        row[pa] += 16 * (fb - fa);
        return;
    }
    let mut x = pa;
    if fa != 0 {
        row[x] += 16 * (4 - fa);
        x += 1;
    }
    for c in &mut row[x..pb] {
        *c += full;
    }
    if fb != 0 {
        row[pb] += 16 * fb;
    }
}

/// Pseudo-random bytes for the tests that compare a wide loop with its pixel loop: a
/// 64-bit linear congruential generator's top byte, from `state`.
#[cfg(test)]
pub(crate) fn test_bytes(mut state: u64) -> impl FnMut() -> u8 {
    move || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 56) as u8
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::{Color, FillRule, Paint, PathBuilder, Transform};

    fn ink(c: Color) -> Ink {
        Ink::of(c)
    }

    /// Draws a polygon both ways over white and returns the largest channel difference.
    fn largest_difference(points: &[Point]) -> u8 {
        let mut ours = Pixmap::new(48, 40).expect("pixmap");
        ours.fill(Color::WHITE);
        let mut theirs = ours.clone();
        let black = Color::from_rgba8(20, 40, 200, 255);
        fill_polygons(&mut ours, &[points], ink(black));
        let mut pb = PathBuilder::new();
        pb.move_to(points[0].0, points[0].1);
        for p in &points[1..] {
            pb.line_to(p.0, p.1);
        }
        pb.close();
        let path = pb.finish().expect("path");
        let mut paint = Paint {
            anti_alias: true,
            ..Paint::default()
        };
        paint.set_color(black);
        theirs.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        ours.data()
            .iter()
            .zip(theirs.data())
            .map(|(a, b)| a.abs_diff(*b))
            .max()
            .unwrap_or(0)
    }

    #[test]
    fn a_rectangle_on_whole_pixels_covers_them_exactly() {
        let mut p = Pixmap::new(8, 8).expect("pixmap");
        fill_polygons(
            &mut p,
            &[&[(2.0, 1.0), (5.0, 1.0), (5.0, 4.0), (2.0, 4.0)]],
            ink(Color::BLACK),
        );
        for y in 0..8 {
            for x in 0..8 {
                let a = p.pixel(x, y).expect("inside").alpha();
                let inside = (2..5).contains(&x) && (1..4).contains(&y);
                assert_eq!(a, if inside { 255 } else { 0 }, "({x}, {y})");
            }
        }
    }

    #[test]
    fn polygons_cover_exactly_what_tiny_skia_covers() {
        // Triangles, quadrilaterals and pentagons at awkward positions and angles: the
        // same fixed-point steps give the same bytes, and across the pixmap's edge too,
        // where both first cut the edges to the pixmap (clipper.rs).
        let (mut inside, mut across) = (0, 0);
        for k in 0..200 {
            let t = k as f64 * 0.37;
            let (cx, cy) = (20.0 + (k % 7) as f64 * 0.13, 18.0 + (k % 5) as f64 * 0.29);
            let points: Vec<Point> = (0..3 + k % 3)
                .map(|i| {
                    let a = t + i as f64 * std::f64::consts::TAU / (3 + k % 3) as f64;
                    ((cx + 9.0 * a.cos()) as f32, (cy + 7.0 * a.sin()) as f32)
                })
                .collect();
            inside = inside.max(largest_difference(&points));
            // The same shape across the top-left corner.
            let shifted: Vec<Point> = points.iter().map(|p| (p.0 - 22.5, p.1 - 17.25)).collect();
            across = across.max(largest_difference(&shifted));
        }
        assert_eq!(inside, 0, "inside: largest difference {inside}/255");
        assert_eq!(
            across, 0,
            "across the edge: largest difference {across}/255"
        );
    }

    #[test]
    fn convex_fills_eight_pixels_at_a_time_blend_the_coverage_pixel_by_pixel() {
        // fill_convex covers and blends a convex polygon without a hole eight pixels
        // at a time; cover_convex hands out the same scan's coverage pixel by pixel,
        // and Ink::blend of each must give the same bytes: thin bars (arrows' shafts)
        // and triangles (their heads) of every direction, small and wide shapes, over
        // a background that varies from pixel to pixel, opaque and translucent,
        // inside the image and across each of its edges (the right edge, where eight
        // pixels would pass it, goes pixel by pixel). The image is 37 pixels wide, so
        // rows end at every remainder of eight.
        let (w, h) = (37u32, 29u32);
        let mut background = Pixmap::new(w, h).expect("pixmap");
        for (i, px) in background.data_mut().chunks_exact_mut(4).enumerate() {
            let v = (i * 37 % 251) as u8;
            px.copy_from_slice(&[v, 255 - v, v / 2, 255]);
        }
        let inks = [
            Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff),
            Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99),
        ];
        for k in 0..600u32 {
            let a = f64::from(k) * 2.399_963;
            let (cx, cy) = (
                -6.0 + f64::from(k % 17) * 2.9 + 0.13,
                -5.0 + f64::from(k % 13) * 3.1 + 0.29,
            );
            let len = 0.3 + f64::from(k % 23) * 1.7;
            let points: Vec<Point> = match k % 3 {
                0 => {
                    let (dx, dy) = (len * a.cos(), len * a.sin());
                    let end = ((cx + dx) as f32, (cy + dy) as f32);
                    let half = [1.0, 0.75, 1.5][(k / 3 % 3) as usize];
                    match bar((cx as f32, cy as f32), end, half) {
                        Some(q) => q.to_vec(),
                        None => continue,
                    }
                }
                1 => (0..3)
                    .map(|i| {
                        let t = a + f64::from(i) * 2.1;
                        (
                            (cx + len * t.cos()) as f32,
                            (cy + 0.6 * len * t.sin()) as f32,
                        )
                    })
                    .collect(),
                _ => (0..5)
                    .map(|i| {
                        let t = a + f64::from(i) * std::f64::consts::TAU / 5.0;
                        ((cx + len * t.cos()) as f32, (cy + len * t.sin()) as f32)
                    })
                    .collect(),
            };
            let ink = ink(inks[(k % 2) as usize]);
            let mut ours = background.clone();
            fill_convex(&mut ours, &points, ink);
            let mut theirs = background.clone();
            let data = theirs.data_mut();
            cover_convex(w, h, &points, |i, c| {
                ink.blend(&mut data[4 * i..4 * i + 4], c)
            });
            assert!(ours.data() == theirs.data(), "polygon {k}: {points:?}");
        }
    }

    #[test]
    fn rings_blended_a_side_at_a_time_blend_the_coverage_pixel_by_pixel() {
        // A ring's rows with two spans a sub-row, the hole between, are blended as two
        // rows of a polygon without a hole (AVX2, where the processor has it); the
        // other rows, and processors without AVX2, go pixel by pixel. Either way the
        // bytes must be those of the ring's coverage blended pixel by pixel: rings of
        // many sizes and shapes (holes of a ring's width, thin holes, holes off centre
        // that reach the outer side, holes wound either way), opaque and translucent,
        // inside images 37 and 300 pixels wide and across their edges.
        use super::convex::{cover_holed, fill_holed};
        let inks = [
            Color::from_rgba8(0x1f, 0x4e, 0x9c, 0xff),
            Color::from_rgba8(0xc0, 0x39, 0x2b, 0x99),
        ];
        let mut separable = 0;
        for (w, h) in [(37u32, 29u32), (300, 90)] {
            let mut background = Pixmap::new(w, h).expect("pixmap");
            for (i, px) in background.data_mut().chunks_exact_mut(4).enumerate() {
                let v = (i * 37 % 251) as u8;
                px.copy_from_slice(&[v, 255 - v, v / 2, 255]);
            }
            for k in 0..500u32 {
                let a = f64::from(k) * 2.399_963;
                let (cx, cy) = (
                    -8.0 + f64::from(k % 19) * f64::from(w + 16) / 18.0 + 0.13,
                    -8.0 + f64::from(k % 11) * f64::from(h + 16) / 10.0 + 0.29,
                );
                let r = 1.5 + f64::from(k % 29) * 1.9;
                let sides = 3 + k % 9;
                let stretch = 0.4 + f64::from(k % 5) * 0.3;
                // The hole: the outline shrunk by a ring's width or more, or thin, and
                // sometimes moved off centre or wound the same way as the outline.
                let inset = [1.5, 0.3, 0.6 * r, 0.2][(k / 7 % 4) as usize];
                let off = if k % 13 == 0 { 0.5 * r } else { 0.0 };
                let polygon = |radius: f64, dx: f64| -> Vec<Point> {
                    (0..sides)
                        .map(|i| {
                            let t = a + f64::from(i) * std::f64::consts::TAU / f64::from(sides);
                            (
                                (cx + dx + radius * t.cos()) as f32,
                                (cy + stretch * radius * t.sin()) as f32,
                            )
                        })
                        .collect()
                };
                let outer = polygon(r, 0.0);
                let mut hole = polygon((r - inset).max(0.1), off);
                if k % 17 != 0 {
                    hole.reverse();
                }
                let ink = ink(inks[(k % 2) as usize]);
                let mut ours = background.clone();
                fill_holed(&mut ours, &outer, &hole, ink);
                let mut theirs = background.clone();
                let data = theirs.data_mut();
                cover_holed((w as usize, h as usize), &outer, &hole, |i, c| {
                    ink.blend(&mut data[4 * i..4 * i + 4], c)
                });
                assert!(
                    ours.data() == theirs.data(),
                    "ring {k} in {w} × {h}: {outer:?} less {hole:?}"
                );
                separable += usize::from(r - inset > 2.0 && off == 0.0);
            }
        }
        assert!(separable > 300, "{separable} rings with a wide hole");
    }

    #[test]
    fn a_ring_is_the_outer_polygon_less_the_inner() {
        let mut ring = Pixmap::new(16, 16).expect("pixmap");
        let outer = [(2.0, 2.0), (14.0, 2.0), (14.0, 14.0), (2.0, 14.0)];
        // Wound the same way as the outer polygon: fill_ring turns it round.
        let mut inner = [(5.0, 5.0), (11.0, 5.0), (11.0, 11.0), (5.0, 11.0)];
        fill_ring(&mut ring, &outer, &mut inner, ink(Color::BLACK));
        let alpha = |x, y| ring.pixel(x, y).expect("inside").alpha();
        assert_eq!(alpha(3, 3), 255);
        assert_eq!(alpha(7, 7), 0);
        assert_eq!(alpha(12, 8), 255);
        assert_eq!(alpha(15, 15), 0);
    }

    #[test]
    fn shapes_outside_or_not_finite_draw_nothing() {
        let mut p = Pixmap::new(8, 8).expect("pixmap");
        let before = p.clone();
        let far = [(-50.0, -50.0), (-40.0, -50.0), (-45.0, -40.0)];
        fill_polygons(&mut p, &[&far], ink(Color::BLACK));
        let nan = [(1.0, 1.0), (f32::NAN, 2.0), (3.0, 5.0)];
        fill_polygons(&mut p, &[&nan], ink(Color::BLACK));
        assert_eq!(p.data(), before.data());
    }
}
