//! One segment of a thin line and the pixels within its reach, walked row by row:
//! what [`super::lines`] covers a coil's zigzag and a trail's step with.
//!
//! A pixel is covered by the distance of its centre to the segment (the ramp of
//! `lines.rs`), computed in f32 relative to the segment's start a: pixel x's centre
//! less a.x is the integer x − ⌊a.x⌋ plus 1/2 − (a.x − ⌊a.x⌋), one rounding in all, so
//! that a pixel's coverage depends on the pixel and the segment alone, and not on how
//! its row was walked. A segment whose box (grown by the reach) is at most sixteen
//! columns wider than its widest row can be, a coil's zigzag, a trail's step or a
//! segment near the level, is walked row by row over the whole box; a steeper, longer
//! one over each row's own span. Both go eight pixels a register where the processor
//! has AVX2, four SSE2 lanes at a time where not. Working out each row's span, in f64
//! with a division, cost more than covering a row of a few pixels: the cloth's 1935
//! coils drew in 6.5 ms a frame that way and in 4.0 ms now (`frame_probe`,
//! twenty-sixth session). A unit test holds every way of walking a row, on every
//! processor, to the same bytes.

use super::{ceil, floor};

/// How many pixels of a row a segment's box may cover beyond the widest span a row of
/// it may have, and still be covered row by row whole instead of each row's own span:
/// a coil's zigzag and a trail's step are rows of a few pixels, where working out each
/// row's span (in f64, with a division) cost more than covering the row, and sixteen
/// pixels are two AVX2 registers.
const SLACK: f64 = 16.0;

/// How the rows of a segment are walked: over the columns first..end of its box in
/// every row, or over each row's own span.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Way {
    Box(i64, i64),
    Spans,
}

/// A segment from a to b stroked `half` pixels each side, and the rows its pixels
/// may lie in: what covering it needs before its first row.
pub(super) struct Walk {
    seg: Segment,
    /// The unit normal, and how far from the line a covered centre may lie, in f64.
    nx: f64,
    ny: f64,
    reach: f64,
    /// The segment's start.
    a: (f64, f64),
    /// The columns of the segment's box, grown by the reach, as f64.
    sx0: f64,
    sx1: f64,
    /// The pixel rows first..end whose centres may lie within the reach.
    rows: (i64, i64),
}

/// Keeps `v` within a pixel of the columns or rows lo..hi before it becomes an integer,
/// which changes no span: a segment of a run that is blowing up reaches 10^300 pixels
/// away, and a NaN (of inf − inf) is ordered with nothing.
#[inline(always)]
fn near(v: f64, (lo, hi): (i64, i64)) -> f64 {
    v.clamp(lo as f64 - 1.0, hi as f64 + 1.0)
}

impl Walk {
    /// The walk of the segment a → b stroked `half` each side over the pixel rows
    /// rows.0..rows.1, or None when no row's centre lies within its reach.
    #[inline(always)]
    pub(super) fn new(a: (f64, f64), b: (f64, f64), half: f64, rows: (i64, i64)) -> Option<Walk> {
        let reach = half + 0.5;
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt();
        let (ux, uy) = if len > 1e-12 {
            (dx / len, dy / len)
        } else {
            (1.0, 0.0)
        };
        // The segment's box, grown by the reach.
        let (sx0, sx1) = (a.0.min(b.0) - reach, a.0.max(b.0) + reach);
        let (sy0, sy1) = (a.1.min(b.1) - reach, a.1.max(b.1) + reach);
        let (top, bottom) = (near(sy0 - 0.5, rows), near(sy1 - 0.5, rows));
        if top.partial_cmp(&bottom).is_none_or(|o| o.is_gt()) {
            return None;
        }
        let rows = (ceil(top).max(rows.0), (floor(bottom) + 1).min(rows.1));
        // Pixel x's centre less a.x is (x − ⌊a.x⌋) + (1/2 − (a.x − ⌊a.x⌋)): an integer,
        // exact in f32, and a number below a pixel, one rounding each.
        let xa = a.0.floor();
        let seg = Segment {
            ux: ux as f32,
            uy: uy as f32,
            len: len as f32,
            reach: reach as f32,
            base: (0.5 - (a.0 - xa)) as f32,
            xa: xa as i64,
            ay: a.1,
        };
        // The unit normal n = (-uy, ux).
        let walk = Walk {
            seg,
            nx: -uy,
            ny: ux,
            reach,
            a,
            sx0,
            sx1,
            rows,
        };
        (rows.0 < rows.1).then_some(walk)
    }

    /// How to walk the segment's rows within columns cols.0..cols.1: over its box when
    /// that is at most [`SLACK`] pixels wider than the widest a row's span may be
    /// (2·reach/|n.x| + 1), which takes in every segment whose box is at most sixteen
    /// columns and every segment near the level, whose rows are its box.
    #[inline(always)]
    fn way(&self, cols: (i64, i64)) -> Way {
        let (lo, hi) = (near(self.sx0 - 0.5, cols), near(self.sx1 - 0.5, cols));
        let first = ceil(lo).max(cols.0);
        let end = (floor(hi) + 1).min(cols.1);
        if first >= end {
            return Way::Spans;
        }
        let widest = if self.nx.abs() > 1e-9 {
            2.0 * self.reach / self.nx.abs() + 1.0
        } else {
            f64::INFINITY
        };
        if (end - first) as f64 <= widest + SLACK {
            Way::Box(first, end)
        } else {
            Way::Spans
        }
    }

    /// The columns first..end (within cols.0..cols.1) of row y's pixels whose centres
    /// may lie within the reach of the segment, if any.
    #[inline(always)]
    fn row_span(&self, y: i64, cols: (i64, i64)) -> Option<(i64, i64)> {
        let (nx, ny, a, reach) = (self.nx, self.ny, self.a, self.reach);
        let yc = y as f64 + 0.5;
        let (mut lo, mut hi) = (self.sx0, self.sx1);
        if nx.abs() > 1e-9 {
            // A centre within the reach of the segment is within it of the line,
            // |n·(p − a)| ≤ reach: nx·(x − ax) + ny·(yc − ay) = ±reach.
            let mid = a.0 - ny * (yc - a.1) / nx;
            let spread = reach / nx.abs();
            (lo, hi) = (lo.max(mid - spread), hi.min(mid + spread));
        }
        let (lo, hi) = (near(lo - 0.5, cols), near(hi - 0.5, cols));
        if lo.partial_cmp(&hi).is_none_or(|o| o.is_gt()) {
            return None;
        }
        let first = ceil(lo).max(cols.0);
        let end = (floor(hi) + 1).min(cols.1);
        (first < end).then_some((first, end))
    }

    /// Calls `row(y, first, end)` for each of the walk's rows y whose pixel centres
    /// first..end (within columns cols.0..cols.1) may lie within the reach of the
    /// segment.
    #[inline(always)]
    pub(super) fn each_row(&self, cols: (i64, i64), mut row: impl FnMut(i64, i64, i64)) {
        for y in self.rows.0..self.rows.1 {
            if let Some((first, end)) = self.row_span(y, cols) {
                row(y, first, end);
            }
        }
    }

    /// Calls `chunk(y, x, first, end, eight)` with the coverage `eight` of pixels
    /// x..x + 8 of row y (those at or past `end` zero), for x = first, first + 8, ...
    /// below end, where first..end are the columns of the row walked ([`Walk::way`]):
    /// every pixel within the reach, rows in order and each row left to right.
    #[inline(always)]
    pub(super) fn cover(&self, cols: (i64, i64), chunk: impl FnMut(i64, i64, i64, i64, [u8; 8])) {
        #[cfg(target_arch = "x86_64")]
        let avx2 = super::avx2::available();
        #[cfg(not(target_arch = "x86_64"))]
        let avx2 = false;
        self.cover_with(avx2, self.way(cols), cols, chunk);
    }

    /// [`Walk::cover`] the way given, with AVX2 when `avx2` says so (the processor must
    /// have it) and four SSE2 lanes at a time otherwise.
    #[inline(always)]
    fn cover_with(
        &self,
        avx2: bool,
        way: Way,
        cols: (i64, i64),
        mut chunk: impl FnMut(i64, i64, i64, i64, [u8; 8]),
    ) {
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            // SAFETY: the processor has AVX2.
            unsafe { cover_avx2(self, way, cols, &mut chunk) };
            return;
        }
        // Without x86-64 there is no AVX2 to ask for.
        #[cfg(not(target_arch = "x86_64"))]
        let _ = avx2;
        let seg = &self.seg;
        let mut row = |y: i64, first: i64, end: i64| {
            let py = seg.py(y);
            let k = seg.k(first);
            let mut x = first;
            while x < end {
                let j = (x - first) as i32;
                let lanes = (end - x) as usize;
                let mut eight = [0u8; 8];
                eight[..4].copy_from_slice(&seg.cover4(py, k + j, lanes.min(4)));
                if lanes > 4 {
                    eight[4..].copy_from_slice(&seg.cover4(py, k + j + 4, (lanes - 4).min(4)));
                }
                chunk(y, x, first, end, eight);
                x += 8;
            }
        };
        match way {
            Way::Box(first, end) => (self.rows.0..self.rows.1).for_each(|y| row(y, first, end)),
            Way::Spans => self.each_row(cols, row),
        }
    }
}

/// One segment, in f32 relative to its start a.
struct Segment {
    /// The unit direction, and the length.
    ux: f32,
    uy: f32,
    len: f32,
    /// w/2 + 1/2: how far from the line a covered centre may lie.
    reach: f32,
    /// 1/2 − (a.x − ⌊a.x⌋): the centre of pixel column ⌊a.x⌋ less a.x.
    base: f32,
    /// ⌊a.x⌋, and a.y.
    xa: i64,
    ay: f64,
}

impl Segment {
    /// Row y's centre less a.y.
    #[inline(always)]
    fn py(&self, y: i64) -> f32 {
        (y as f64 + 0.5 - self.ay) as f32
    }

    /// Pixel column x counted from ⌊a.x⌋ (kept well inside i32, where columns far
    /// from the segment give no coverage whatever their rounding).
    #[inline(always)]
    fn k(&self, x: i64) -> i32 {
        x.saturating_sub(self.xa).clamp(-(1 << 30), 1 << 30) as i32
    }

    /// The coverage of pixels k + i (i = 0..4, counted from ⌊a.x⌋) of the row whose
    /// centre less a.y is `py`, for the first `lanes` of them (the others zero): with
    /// p = (f32(k + i) + base, py), t = clamp(p·u, 0, len), e = p − t·u, d = |e|,
    /// c = ⌊255·clamp(reach − d, 0, 1) + 1/2⌋. The same operations in SSE2 lanes as
    /// one by one, and in AVX2 lanes ([`cover_avx2`]), so the same bytes: a
    /// pixel's coverage depends on the pixel and the segment, not on how its row was
    /// walked.
    #[inline(always)]
    fn cover4(&self, py: f32, k: i32, lanes: usize) -> [u8; 4] {
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: every x86-64 processor has SSE2, which the target enables.
            unsafe { self.cover4_sse2(py, k, lanes) }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let mut quad = [0u8; 4];
            for (i, q) in quad.iter_mut().enumerate().take(lanes) {
                let px = (k + i as i32) as f32 + self.base;
                let dot = px * self.ux + py * self.uy;
                let t = dot.max(0.0).min(self.len);
                let (ex, ey) = (px - t * self.ux, py - t * self.uy);
                let d = (ex * ex + ey * ey).sqrt();
                let c = (self.reach - d).max(0.0).min(1.0);
                *q = (c * 255.0 + 0.5) as i32 as u8;
            }
            quad
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn cover4_sse2(&self, py: f32, k: i32, lanes: usize) -> [u8; 4] {
        use std::arch::x86_64::*;
        let i = _mm_setr_epi32(0, 1, 2, 3);
        let px = _mm_add_ps(
            _mm_cvtepi32_ps(_mm_add_epi32(_mm_set1_epi32(k), i)),
            _mm_set1_ps(self.base),
        );
        let (ux, uy, py) = (_mm_set1_ps(self.ux), _mm_set1_ps(self.uy), _mm_set1_ps(py));
        let dot = _mm_add_ps(_mm_mul_ps(px, ux), _mm_mul_ps(py, uy));
        let t = _mm_min_ps(_mm_max_ps(dot, _mm_setzero_ps()), _mm_set1_ps(self.len));
        let ex = _mm_sub_ps(px, _mm_mul_ps(t, ux));
        let ey = _mm_sub_ps(py, _mm_mul_ps(t, uy));
        let d = _mm_sqrt_ps(_mm_add_ps(_mm_mul_ps(ex, ex), _mm_mul_ps(ey, ey)));
        let c = _mm_sub_ps(_mm_set1_ps(self.reach), d);
        let c = _mm_min_ps(_mm_max_ps(c, _mm_setzero_ps()), _mm_set1_ps(1.0));
        let v = _mm_cvttps_epi32(_mm_add_ps(
            _mm_mul_ps(c, _mm_set1_ps(255.0)),
            _mm_set1_ps(0.5),
        ));
        // Lanes past the row's end: no coverage.
        let keep = _mm_cmplt_epi32(i, _mm_set1_epi32(lanes as i32));
        let v = _mm_and_si128(v, keep);
        // Four 32-bit lanes of 0..=255 to four bytes.
        let v = _mm_packus_epi16(_mm_packs_epi32(v, v), _mm_setzero_si128());
        _mm_cvtsi128_si32(v).to_le_bytes()
    }
}

/// [`Walk::cover_with`] with AVX2: eight pixels a register, by [`Segment::cover4`]'s
/// operations lane for lane (so the same bytes).
///
/// # Safety
/// The processor must have AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn cover_avx2(
    walk: &Walk,
    way: Way,
    cols: (i64, i64),
    chunk: &mut impl FnMut(i64, i64, i64, i64, [u8; 8]),
) {
    use std::arch::x86_64::*;
    let seg = &walk.seg;
    let i = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let base = _mm256_set1_ps(seg.base);
    let (ux, uy) = (_mm256_set1_ps(seg.ux), _mm256_set1_ps(seg.uy));
    let (len, reach) = (_mm256_set1_ps(seg.len), _mm256_set1_ps(seg.reach));
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    let (scale, half) = (_mm256_set1_ps(255.0), _mm256_set1_ps(0.5));
    // Row y's pixels first..end, eight at a time (a macro, not a closure, so that its
    // intrinsics are compiled with AVX2 in this function's body).
    macro_rules! row {
        ($y:expr, $first:expr, $end:expr) => {{
            let (y, first, end) = ($y, $first, $end);
            let py = _mm256_set1_ps(seg.py(y));
            let pyy = _mm256_mul_ps(py, uy);
            let k = seg.k(first);
            let mut x = first;
            while x < end {
                let j = _mm256_set1_epi32(k + (x - first) as i32);
                let px = _mm256_add_ps(_mm256_cvtepi32_ps(_mm256_add_epi32(j, i)), base);
                let dot = _mm256_add_ps(_mm256_mul_ps(px, ux), pyy);
                let t = _mm256_min_ps(_mm256_max_ps(dot, zero), len);
                let ex = _mm256_sub_ps(px, _mm256_mul_ps(t, ux));
                let ey = _mm256_sub_ps(py, _mm256_mul_ps(t, uy));
                let d = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(ex, ex), _mm256_mul_ps(ey, ey)));
                let c = _mm256_min_ps(_mm256_max_ps(_mm256_sub_ps(reach, d), zero), one);
                let v = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(c, scale), half));
                // Lanes at or past the row's end: no coverage.
                let lanes = _mm256_set1_epi32((end - x).min(8) as i32);
                let v = _mm256_and_si256(v, _mm256_cmpgt_epi32(lanes, i));
                // Eight 32-bit lanes of 0..=255 to eight bytes.
                let words =
                    _mm_packs_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
                let eight = _mm_cvtsi128_si64(_mm_packus_epi16(words, words)).to_le_bytes();
                chunk(y, x, first, end, eight);
                x += 8;
            }
        }};
    }
    match way {
        Way::Box(first, end) => {
            for y in walk.rows.0..walk.rows.1 {
                row!(y, first, end);
            }
        }
        Way::Spans => {
            for y in walk.rows.0..walk.rows.1 {
                if let Some((first, end)) = walk.row_span(y, cols) {
                    row!(y, first, end);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pixels_coverage_does_not_depend_on_how_its_row_is_walked() {
        // A segment's rows are walked over its box or over each row's span, with AVX2
        // where the processor has it or four SSE2 lanes at a time: every pixel must
        // get the same coverage every way, for segments of every direction, length,
        // width and position (so the bytes of a frame do not depend on the processor),
        // and the chunks must come row after row, left to right, each pixel once.
        let (w, h) = (72i64, 60i64);
        let mut byte = super::super::test_bytes(0x2545_F491_4F6C_DD1Du64);
        let mut unit = || f64::from(byte()) / 255.0;
        let mut ways = vec![false];
        #[cfg(target_arch = "x86_64")]
        if super::super::avx2::available() {
            ways.push(true);
        }
        let (mut boxes, mut spans) = (0, 0);
        for k in 0..600 {
            let a = (-4.0 + 80.0 * unit(), -4.0 + 68.0 * unit());
            let (len, angle) = (60.0 * unit(), 7.0 * unit());
            let b = (a.0 + len * angle.cos(), a.1 + len * angle.sin());
            let half = 0.3 + 2.0 * unit();
            let Some(walk) = Walk::new(a, b, half, (0, h)) else {
                continue;
            };
            // Pixel by pixel over each row's span: the definition.
            let mut one = vec![0u8; (w * h) as usize];
            walk.each_row((0, w), |y, first, end| {
                let py = walk.seg.py(y);
                for x in first..end {
                    one[(y * w + x) as usize] = walk.seg.cover4(py, walk.seg.k(x), 1)[0];
                }
            });
            let chosen = walk.way((0, w));
            match chosen {
                Way::Box(..) => boxes += 1,
                Way::Spans => spans += 1,
            }
            let mut each = vec![Way::Spans];
            if let Way::Box(..) = chosen {
                each.push(chosen);
            }
            for &way in &each {
                for &avx2 in &ways {
                    let mut got = vec![0u8; (w * h) as usize];
                    let mut last = None;
                    walk.cover_with(avx2, way, (0, w), |y, x, first, end, eight| {
                        assert!((first..end).contains(&x) && (x - first) % 8 == 0);
                        assert!(last < Some((y, x)), "{last:?} then {:?}", (y, x));
                        last = Some((y, x));
                        for (i, &c) in eight.iter().enumerate() {
                            if x + (i as i64) < end {
                                got[(y * w + x) as usize + i] = c;
                            } else {
                                assert_eq!(c, 0, "past the end");
                            }
                        }
                    });
                    assert_eq!(got, one, "segment {k}: {a:?} → {b:?}, {way:?}, AVX2 {avx2}");
                }
            }
        }
        assert!(boxes > 300 && spans > 100, "{boxes} boxes, {spans} spans");
    }
}
