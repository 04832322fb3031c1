//! Thin polylines with round joins and caps, covered by the distance of each pixel's
//! centre to the line: many springs' coils a frame, where tiny-skia's stroker and
//! filler spent 37 to 68 µs on each one (1935 coils, 71 to 132 ms a frame), and the
//! trails' segments one by one ([`cover_capsule`]: 65 ns a segment 1.5 pixels wide,
//! where its polygon scan-converted took 280).
//!
//! A stroke w pixels wide with round joins and caps covers the points within w/2 of
//! its polyline. A pixel whose centre lies at distance d from the polyline is covered
//! by the ramp
//!
//!   c = clamp(w/2 + 1/2 − d, 0, 1),
//!
//! which for a straight stroke at least a pixel wide, along a row or a column, is the
//! exact area of the pixel inside it (the strip w/2 each side of the line over the
//! pixel's unit width), and close to it at other angles and round the joins. The
//! distance to the polyline is the least of the distances to its segments, so the
//! coverage is the largest of the segments' coverages: each segment is covered on its
//! own into a buffer over the polyline's bounding box, pixel by pixel keeping the
//! larger, and each pixel is blended once, as tiny-skia blends a stroke ([`Ink`]), with
//! the coverage rounded to 8 bits, ⌊255·c + 1/2⌋.
//!
//! Each segment's pixels within its reach are found and covered by
//! [`super::segment::Walk`]: over the segment's box or row by row, eight pixels a
//! register, a pixel's coverage depending on the pixel and the segment alone.
//!
//! The difference from tiny-skia's stroke of the same points (sixteen samples a pixel,
//! round parts as curves) is bounded in `tests/integration/every_scene.rs`.

use std::cell::RefCell;

use tiny_skia::Pixmap;

use super::segment::Walk;
use crate::render::sprite::Ink;

/// Strokes the polyline through `points` (pixels), `width` pixels wide with round
/// joins and caps, in `ink`, covering each pixel by the distance of its centre to the
/// polyline (the module's documentation). A polyline with a point that is not finite,
/// or wholly outside the image, draws nothing.
pub fn stroke_polyline(pixmap: &mut Pixmap, points: &[(f64, f64)], width: f64, ink: Ink) {
    let finite = points.iter().all(|p| p.0.is_finite() && p.1.is_finite());
    if points.is_empty() || !finite || width.is_nan() || width <= 0.0 {
        return;
    }
    // How far from the line a pixel centre may lie and still be covered.
    let half = 0.5 * width;
    let reach = half + 0.5;
    let (w, h) = (i64::from(pixmap.width()), i64::from(pixmap.height()));
    // The bounding box of the pixels the stroke may cover, within the image.
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for &(x, y) in points {
        (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
    }
    let first_col = ((x0 - reach).floor() as i64).max(0);
    let end_col = ((x1 + reach).ceil() as i64 + 1).min(w);
    let first_row = ((y0 - reach).floor() as i64).max(0);
    let end_row = ((y1 + reach).ceil() as i64 + 1).min(h);
    if first_col >= end_col || first_row >= end_row {
        return;
    }
    let bw = (end_col - first_col) as usize;
    let bh = (end_row - first_row) as usize;
    COVER.with(|cover| {
        let Cover { bytes, spans } = &mut *cover.borrow_mut();
        // The buffer is all zeros between calls (each row's span is cleared after its
        // blend below), so it is only ever grown, never cleared whole: a long coil's
        // box is mostly pixels it does not touch, and clearing and scanning the whole
        // box cost it 40 µs where its stroke took a few (300 springs across the view).
        // Seven bytes past the box, for the last row's last chunk of eight pixels.
        if bytes.len() < bw * bh + 7 {
            bytes.resize(bw * bh + 7, 0);
        }
        spans.clear();
        spans.resize(bh, (bw, 0));
        let segments = points.windows(2).map(|s| (s[0], s[1]));
        // A single point is a dot: a segment of no length.
        let dot = (points.len() == 1).then(|| (points[0], points[0]));
        for (a, b) in segments.chain(dot) {
            cover_segment(bytes, spans, (first_col, first_row, bw, bh), a, b, half);
        }
        let data = pixmap.data_mut();
        // Eight pixels blended at a time where the processor can ([`Ink::blend`]'s
        // bytes): 8.2 → 6.8 ms for the 1935 coils of a cloth (`frame_probe`).
        let avx2 = super::avx2::available();
        for (r, (row, &(lo, hi))) in bytes.chunks_exact_mut(bw).zip(spans.iter()).enumerate() {
            if lo >= hi {
                continue;
            }
            let start = 4 * ((first_row as usize + r) * w as usize + first_col as usize);
            let pixels = &mut data[start + 4 * lo..start + 4 * hi];
            if avx2 {
                // SAFETY: the processor has AVX2.
                unsafe { super::avx2::blend_coverage(pixels, &row[lo..hi], &ink) };
            } else {
                // Eight coverages at a time, skipping eight pixels uncovered at once
                // (the inside of a zigzag's turns).
                for (p8, c8) in pixels.chunks_mut(32).zip(row[lo..hi].chunks(8)) {
                    if c8.iter().all(|&c| c == 0) {
                        continue;
                    }
                    for (p, &c) in p8.chunks_exact_mut(4).zip(c8) {
                        if c != 0 {
                            ink.blend(p, c);
                        }
                    }
                }
            }
            row[lo..hi].fill(0);
        }
        debug_assert!(
            bytes[..bw * bh + 7].iter().all(|&c| c == 0),
            "the buffer is left clear"
        );
    });
}

/// Calls `put(i, c)` with the coverage c > 0 of every pixel i (counted row after row in
/// an image `width` × `height`) within `half` + 1/2 of the segment from `a` to `b`, by
/// the ramp c = ⌊255·clamp(half + 1/2 − d, 0, 1) + 1/2⌋ of the distance d of its centre
/// to the segment (the module's documentation): one segment of a stroke with round
/// caps, pixel by pixel within a row and row after row. A segment that is not finite
/// covers nothing.
pub fn cover_capsule(
    (width, height): (u32, u32),
    a: (f64, f64),
    b: (f64, f64),
    half: f64,
    mut put: impl FnMut(usize, u8),
) {
    let finite = a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite();
    if !finite || half.is_nan() || half <= 0.0 {
        return;
    }
    let (w, h) = (i64::from(width), i64::from(height));
    let Some(walk) = Walk::new(a, b, half, (0, h)) else {
        return;
    };
    walk.cover((0, w), |y, x, _, end, eight| {
        let at = y as usize * width as usize + x as usize;
        for (i, &c) in eight.iter().enumerate().take((end - x) as usize) {
            if c != 0 {
                put(at + i, c);
            }
        }
    });
}

/// Calls `span(y, first, end)` for each pixel row y of an image `width` × `height` with
/// the columns first..end of every pixel whose centre lies within `half` + 1 of the
/// segment from `a` to `b`: every pixel that a shape lying within `half` of the
/// segment may cover. (A point of a pixel's square is within √2/2 of its centre, and
/// the scan converter's quarter-pixel columns reach at most 1/8 pixel past an edge:
/// 0.83 in all, less than 1.) A segment that is not finite covers nothing.
pub(crate) fn capsule_spans(
    (width, height): (u32, u32),
    a: (f64, f64),
    b: (f64, f64),
    half: f64,
    mut span: impl FnMut(usize, usize, usize),
) {
    let finite = a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite();
    if !finite || half.is_nan() || half < 0.0 {
        return;
    }
    // Centres within half + 1/2 + 1/2 of the segment: the walk adds the second 1/2.
    let (w, h) = (i64::from(width), i64::from(height));
    if let Some(walk) = Walk::new(a, b, half + 0.5, (0, h)) {
        walk.each_row((0, w), |y, first, end| {
            span(y as usize, first as usize, end as usize);
        });
    }
}

/// Each thread's coverage buffer over a polyline's bounding box, all zeros between
/// calls, and the columns lo..hi of each of the box's rows that the polyline's
/// segments covered (relative to the box; empty when lo >= hi).
#[derive(Default)]
struct Cover {
    bytes: Vec<u8>,
    spans: Vec<(usize, usize)>,
}

thread_local! {
    static COVER: RefCell<Cover> = RefCell::new(Cover::default());
}

/// Keeps in `cover` (the box of `bw` × `bh` pixels whose top-left pixel is (bx, by))
/// the larger of each pixel's coverage and the coverage by the segment a → b, stroked
/// `half` pixels each side, and widens each row's span in `spans` to the columns the
/// segment may cover there.
fn cover_segment(
    cover: &mut [u8],
    spans: &mut [(usize, usize)],
    (bx, by, bw, bh): (i64, i64, usize, usize),
    a: (f64, f64),
    b: (f64, f64),
    half: f64,
) {
    let (cols, rows) = ((bx, bx + bw as i64), (by, by + bh as i64));
    let Some(walk) = Walk::new(a, b, half, rows) else {
        return;
    };
    // Keeps the larger of each pixel's coverage and the buffer's from pixel (x, y) on,
    // widening the row's span to first..end at its first chunk. The buffer holds 7
    // bytes past the box, so that the last row's last chunk of eight may reach past
    // it; lanes past `end` hold no coverage, which leaves what they reach as it is.
    walk.cover(cols, |y, x, first, end, eight| {
        if x == first {
            let span = &mut spans[(y - by) as usize];
            *span = (
                span.0.min((first - bx) as usize),
                span.1.max((end - bx) as usize),
            );
        }
        let k = (y - by) as usize * bw + (x - bx) as usize;
        for (c, &n) in cover[k..k + 8].iter_mut().zip(&eight) {
            *c = (*c).max(n);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use tiny_skia::Color;

    /// The coverage of white over black: the red channel.
    fn covered(points: &[(f64, f64)], width: f64, w: u32, h: u32) -> Vec<u8> {
        let mut pixmap = Pixmap::new(w, h).expect("a pixmap");
        pixmap.fill(Color::BLACK);
        stroke_polyline(&mut pixmap, points, width, Ink::of(Color::WHITE));
        pixmap.data().chunks_exact(4).map(|p| p[0]).collect()
    }

    #[test]
    fn a_level_stroke_covers_rows_by_their_area_inside_it() {
        // A line through the centres of row 5, 1.3 pixels wide: the strip 4.85..6.15
        // covers row 5 whole and rows 4 and 6 by 0.15 each (⌊0.15·255 + 1/2⌋ = 38),
        // from x = 3 to x = 17, with round caps past the ends.
        let c = covered(&[(3.0, 5.5), (17.0, 5.5)], 1.3, 24, 12);
        let at = |x: usize, y: usize| c[y * 24 + x];
        for x in 4..16 {
            assert_eq!((at(x, 4), at(x, 5), at(x, 6)), (38, 255, 38), "column {x}");
            assert_eq!((at(x, 3), at(x, 7)), (0, 0), "column {x}");
        }
        // The caps: pixel 2's centre lies 0.5 before the start, pixel 1's 1.5.
        assert_eq!(at(2, 5), 166, "⌊(1.15 − 0.5)·255 + 1/2⌋");
        assert_eq!(at(1, 5), 0);
        assert_eq!(at(17, 5), 166);
    }

    #[test]
    fn joins_take_the_nearer_segment_and_blend_each_pixel_once() {
        // An L through pixel centres: every pixel of both arms is covered whole, the
        // corner too, and a translucent ink blended once gives one level everywhere on
        // the line (blended twice, the corner would be darker).
        let points = [(2.5, 2.5), (10.5, 2.5), (10.5, 9.5)];
        let c = covered(&points, 1.3, 16, 16);
        for x in 2..=10 {
            assert_eq!(c[2 * 16 + x], 255, "top arm, x = {x}");
        }
        for y in 2..=9 {
            assert_eq!(c[y * 16 + 10], 255, "right arm, y = {y}");
        }
        let mut pixmap = Pixmap::new(16, 16).expect("a pixmap");
        pixmap.fill(Color::WHITE);
        let grey = Ink::of(Color::from_rgba8(0, 0, 0, 128));
        stroke_polyline(&mut pixmap, &points, 1.3, grey);
        let level = |x: u32, y: u32| pixmap.pixel(x, y).expect("inside").red();
        assert_eq!(level(10, 2), level(5, 2));
        assert_eq!(level(10, 2), level(10, 6));
    }

    #[test]
    fn a_stroke_leaves_no_coverage_behind_for_the_next() {
        // The buffer is reused without being cleared whole: a long zigzag whose box is
        // mostly untouched, then strokes in boxes of other sizes over it, must each
        // draw what they draw on a thread that stroked nothing before.
        let zigzag: Vec<(f64, f64)> = (0..24)
            .map(|k| (4.0 + 9.0 * k as f64, if k % 2 == 0 { 20.0 } else { 50.0 }))
            .collect();
        let others: [&[(f64, f64)]; 3] = [
            &[(30.0, 10.0), (60.0, 40.0), (20.0, 55.0)],
            &[(100.5, 30.5)],
            &[(2.0, 58.0), (230.0, 3.0)],
        ];
        let fresh: Vec<Vec<u8>> = others
            .iter()
            .map(|p| {
                let p = p.to_vec();
                std::thread::spawn(move || covered(&p, 1.3, 240, 64))
                    .join()
                    .expect("a thread of its own")
            })
            .collect();
        assert!(covered(&zigzag, 1.3, 240, 64).iter().any(|&c| c != 0));
        for (p, alone) in others.iter().zip(&fresh) {
            assert!(alone.iter().any(|&c| c != 0));
            assert_eq!(&covered(p, 1.3, 240, 64), alone, "{p:?}");
        }
    }

    #[test]
    fn a_segment_covers_what_a_stroke_of_it_covers() {
        // `cover_capsule` gives each pixel the coverage a stroke of the one segment
        // blends (white over black: the red channel is the coverage), pixel for pixel,
        // for segments of every direction and length, dots, and ones across the edges.
        let (w, h) = (48u32, 40u32);
        for k in 0..200u32 {
            let angle = f64::from(k) * 2.399_963;
            let len = f64::from(k % 9) * 0.4;
            let a = (
                -3.0 + f64::from(k % 23) * 2.3 + 0.17,
                -2.0 + f64::from(k % 19) * 2.3 + 0.41,
            );
            let b = (a.0 + len * angle.cos(), a.1 + len * angle.sin());
            let half = [0.75, 0.5, 1.6][(k % 3) as usize];
            let mut put = vec![0u8; (w * h) as usize];
            let mut order = Vec::new();
            cover_capsule((w, h), a, b, half, |p, c| {
                put[p] = c;
                order.push(p);
            });
            let points = if len == 0.0 { vec![a] } else { vec![a, b] };
            assert_eq!(put, covered(&points, 2.0 * half, w, h), "segment {k}");
            // Row after row, left to right, each pixel once.
            assert!(order.windows(2).all(|p| p[0] < p[1]), "segment {k}");
        }
    }

    #[test]
    fn a_dot_spreads_the_integral_of_its_ramp() {
        // A dot of radius r covers by c = clamp(r + 1/2 − d, 0, 1), whose integral over
        // the plane is π(r − 1/2)² + 2π ∫ (r + 1/2 − ρ) ρ dρ over r − 1/2 ≤ ρ ≤ r + 1/2:
        // 2.029 for r = 0.75 (the disc's area is 1.767). Averaged over 8 × 8 positions
        // across a pixel, the coverage summed over the pixels is that integral, to
        // within the 8-bit rounding (1/510 a pixel) and the grid's sampling.
        let r = 0.75;
        let (lo, hi) = (r - 0.5, r + 0.5);
        let pi = std::f64::consts::PI;
        let integral = pi * lo * lo
            + 2.0 * pi * ((r + 0.5) * (hi * hi - lo * lo) / 2.0 - (hi.powi(3) - lo.powi(3)) / 3.0);
        assert!((integral - 2.029).abs() < 1e-3, "{integral}");
        let mut total = 0.0;
        for i in 0..8 {
            for j in 0..8 {
                let p = (10.0 + f64::from(i) / 8.0, 10.0 + f64::from(j) / 8.0);
                cover_capsule((24, 24), p, p, r, |_, c| total += f64::from(c) / 255.0);
            }
        }
        let mean = total / 64.0;
        eprintln!("a dot's coverage: {mean} on average, the integral {integral}");
        assert!((mean - integral).abs() < 0.01, "{mean} against {integral}");
    }

    #[test]
    fn coverage_blended_eight_at_a_time_is_blended_pixel_by_pixel() {
        // The AVX2 blend of a row of coverages gives `Ink::blend`'s bytes, for opaque
        // and translucent inks, rows of every length up to 40 (eight at a time and the
        // rest one by one), coverages of 0, 255 and between, and groups of eight
        // uncovered pixels (skipped) among covered ones.
        if !super::super::avx2::available() {
            eprintln!("no AVX2 here: nothing to compare");
            return;
        }
        let mut byte = super::super::test_bytes(0x853C_49E6_748F_EA9Bu64);
        let inks = [
            Ink::of(Color::from_rgba8(0x55, 0x55, 0x55, 0xff)),
            Ink::of(Color::from_rgba8(0x1f, 0x77, 0xb4, 0x8c)),
            Ink::of(Color::from_rgba8(0xff, 0x00, 0x80, 0x01)),
        ];
        for ink in inks {
            for len in 0..=40usize {
                for round in 0..20 {
                    let pixels: Vec<u8> = (0..4 * len).map(|_| byte()).collect();
                    let cover: Vec<u8> = (0..len)
                        .map(|i| match (byte() % 4, round % 3, i / 8 % 2) {
                            // Whole groups of eight left uncovered in a third of rows.
                            (_, 0, 1) => 0,
                            (0, _, _) => 0,
                            (1, _, _) => 255,
                            _ => byte(),
                        })
                        .collect();
                    let mut one = pixels.clone();
                    for (p, &c) in one.chunks_exact_mut(4).zip(&cover) {
                        if c != 0 {
                            ink.blend(p, c);
                        }
                    }
                    let mut eight = pixels;
                    // SAFETY: the processor has AVX2 (checked above).
                    unsafe { super::super::avx2::blend_coverage(&mut eight, &cover, &ink) };
                    assert_eq!(eight, one, "{ink:?}, {len} pixels, {cover:?}");
                }
            }
        }
    }

    #[test]
    fn lines_outside_or_not_finite_draw_nothing() {
        let none = |points: &[(f64, f64)]| covered(points, 1.3, 8, 8).iter().all(|&c| c == 0);
        assert!(none(&[(-10.0, -10.0), (-3.0, -2.0)]));
        assert!(none(&[(20.0, 3.0), (30.0, 3.0)]));
        assert!(none(&[(1.0, 1.0), (f64::NAN, 3.0)]));
        assert!(none(&[]));
        // A line from outside into the image is drawn where it is inside.
        assert!(!none(&[(-10.0, 4.5), (4.0, 4.5)]));
    }
}
