//! Eight pixels of a row covered and blended at once, without a branch on the data.
//!
//! A pixel row of a convex polygon without a hole is at most four spans of
//! quarter-pixel columns, one per sub-row. A span a..b adds to pixel x the overlap
//! o = min(b, 4x + 4) - max(a, 4x), when positive, times 16, or its sub-row's full
//! weight (64, or 63 in a row's last sub-row) when o = 4, as tiny-skia's supersampler
//! adds it. Since a < b (or a = b for a sub-row without a span), the overlap is
//! clamp(b - 4x, 0, 4) - clamp(a - 4x, 0, 4), which is a few vector operations on
//! eight 16-bit lanes. The blend is [`Ink::blend`]'s arithmetic, which leaves a pixel
//! of no coverage as it is, so the eight pixels may reach past the ones a row touches.
//!
//! Scalar code branches on every span's ends (a span within one pixel, a partial first
//! or last pixel), and those branches follow the shape's edges, which the processor
//! cannot predict: for a thin shape, that costs more than the arithmetic.

use crate::render::sprite::Ink;

/// A sub-row's span: quarter-pixel columns a..b (a = b for none) and the weight of a
/// pixel it covers whole.
pub(super) type Span = (i64, i64, u16);

/// Blends `ink` into the eight pixels `px` (RGBA) that start at pixel x0, with the
/// coverage of `spans`: the bytes that summing each pixel's coverage, capping it as
/// Skia does (a sum of 256 becomes 255) and [`Ink::blend`] give.
#[inline(always)]
pub(super) fn blend8(px: &mut [u8; 32], x0: i64, spans: &[Span; 4], ink: &Ink) {
    imp::blend8(px, x0, spans, ink);
}

/// Asks for the cache line of `data[i]` to be loaded, when `i` is in range.
#[inline(always)]
pub(crate) fn prefetch<T>(data: &[T], i: usize) {
    #[cfg(target_arch = "x86_64")]
    if let Some(p) = data.get(i) {
        // SAFETY: a prefetch reads nothing the program sees and cannot fault; the
        // pointer is to an element of `data`.
        unsafe {
            std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(
                (p as *const T).cast(),
            )
        };
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (data, i);
}

/// How many bodies ahead the renderer asks for a body's pixels ([`prefetch_around`]),
/// and the largest reach in pixels of a body whose pixels it asks for (larger ones
/// cost their drawing, not the wait).
pub(crate) const AHEAD: usize = 4;
pub(crate) const PREFETCH_REACH: f32 = 24.0;

/// Asks for the cache lines of the pixels within `reach` of pixel (x, y), row by row,
/// of an image `width` × `height` whose pixels are `data`; nothing for a position
/// outside the image or not finite.
pub(crate) fn prefetch_around(data: &[u8], width: u32, height: u32, x: f32, y: f32, reach: f32) {
    if !(x + reach >= 0.0
        && y + reach >= 0.0
        && x - reach < width as f32
        && y - reach < height as f32)
    {
        return;
    }
    let (w, h) = (width as i64, height as i64);
    let x0 = ((x - reach) as i64).clamp(0, w - 1) as usize;
    let x1 = ((x + reach) as i64).clamp(0, w - 1) as usize;
    let y0 = ((y - reach) as i64).clamp(0, h - 1) as usize;
    let y1 = ((y + reach) as i64).clamp(0, h - 1) as usize;
    let stride = 4 * width as usize;
    for row in y0..=y1 {
        let at = row * stride;
        // Every line of the row's stretch: one each 64 bytes, and the last.
        for k in (4 * x0..4 * x1).step_by(64) {
            prefetch(data, at + k);
        }
        prefetch(data, at + 4 * x1);
    }
}

/// Returns column `v` relative to pixel x0's first (4·x0), clamped where every lane's
/// clamp gives the same and 16 bits hold it: lane j looks at columns 4j..4j + 4, j < 8.
#[inline(always)]
fn relative(v: i64, x0: i64) -> i16 {
    (v - 4 * x0).clamp(-8, 40) as i16
}

#[cfg(target_arch = "x86_64")]
mod imp {
    use std::arch::x86_64::*;

    use super::{relative, Span};
    use crate::render::sprite::Ink;

    /// The SSE2 version (every x86-64 processor has SSE2).
    #[inline(always)]
    pub(super) fn blend8(px: &mut [u8; 32], x0: i64, spans: &[Span; 4], ink: &Ink) {
        // SAFETY: every x86-64 processor has SSE2, which the target enables; the only
        // memory touched is `px`, 32 bytes, by two unaligned 16-byte loads and stores.
        unsafe { blend8_sse2(px, x0, spans, ink) }
    }

    /// The body of [`blend8`], unsafe only in that the processor must have SSE2.
    #[inline(always)]
    unsafe fn blend8_sse2(px: &mut [u8; 32], x0: i64, spans: &[Span; 4], ink: &Ink) {
        let lanes = _mm_setr_epi16(0, 4, 8, 12, 16, 20, 24, 28);
        let (zero, four) = (_mm_setzero_si128(), _mm_set1_epi16(4));
        let clamp = |v: __m128i| _mm_min_epi16(_mm_max_epi16(v, zero), four);
        let mut sum = zero;
        for &(a, b, full) in spans {
            let (a, b, short) = (relative(a, x0), relative(b, x0), 64 - full as i16);
            let oa = clamp(_mm_sub_epi16(_mm_set1_epi16(a), lanes));
            let ob = clamp(_mm_sub_epi16(_mm_set1_epi16(b), lanes));
            let o = _mm_sub_epi16(ob, oa);
            // 16·o, less 1 where the last sub-row covers the pixel whole (63, not 64).
            let whole = _mm_and_si128(_mm_cmpeq_epi16(o, four), _mm_set1_epi16(short));
            sum = _mm_add_epi16(sum, _mm_sub_epi16(_mm_slli_epi16(o, 4), whole));
        }
        // Skia's runs cap a sum of 256 at 255: (c - (c >> 8)), at most 255.
        let c = _mm_sub_epi16(sum, _mm_srli_epi16(sum, 8));
        let c = _mm_min_epi16(c, _mm_set1_epi16(255));
        // Each pixel's coverage in its four channels' lanes: pixels 0-1, 2-3, 4-5, 6-7.
        let (low, high) = (_mm_unpacklo_epi16(c, c), _mm_unpackhi_epi16(c, c));
        let cover = [
            _mm_unpacklo_epi32(low, low),
            _mm_unpackhi_epi32(low, low),
            _mm_unpacklo_epi32(high, high),
            _mm_unpackhi_epi32(high, high),
        ];
        let ptr = px.as_mut_ptr() as *mut __m128i;
        let (p0, p1) = (_mm_loadu_si128(ptr), _mm_loadu_si128(ptr.add(1)));
        let d = [
            _mm_unpacklo_epi8(p0, zero),
            _mm_unpackhi_epi8(p0, zero),
            _mm_unpacklo_epi8(p1, zero),
            _mm_unpackhi_epi8(p1, zero),
        ];
        let [r, g, b, a] = ink.rgba().map(|v| v as i16);
        let s = _mm_setr_epi16(r, g, b, a, r, g, b, a);
        let (ff, div) = (_mm_set1_epi16(255), |v: __m128i| {
            _mm_srli_epi16(_mm_add_epi16(v, _mm_set1_epi16(255)), 8)
        });
        let out: [__m128i; 4] = if ink.is_opaque() {
            // div255(d·(255 - c) + s·c).
            std::array::from_fn(|k| {
                let keep = _mm_mullo_epi16(d[k], _mm_sub_epi16(ff, cover[k]));
                div(_mm_add_epi16(keep, _mm_mullo_epi16(s, cover[k])))
            })
        } else {
            // s' = div255(s·c), then s' + div255(d·(255 - s'_a)).
            std::array::from_fn(|k| {
                let src = div(_mm_mullo_epi16(s, cover[k]));
                let alpha = _mm_shufflehi_epi16(_mm_shufflelo_epi16(src, 0xff), 0xff);
                let inv = _mm_sub_epi16(ff, alpha);
                _mm_add_epi16(src, div(_mm_mullo_epi16(d[k], inv)))
            })
        };
        _mm_storeu_si128(ptr, _mm_packus_epi16(out[0], out[1]));
        _mm_storeu_si128(ptr.add(1), _mm_packus_epi16(out[2], out[3]));
    }
}

#[cfg(not(target_arch = "x86_64"))]
mod imp {
    use super::{relative, Span};
    use crate::render::sprite::Ink;

    /// The same arithmetic lane by lane.
    #[inline(always)]
    pub(super) fn blend8(px: &mut [u8; 32], x0: i64, spans: &[Span; 4], ink: &Ink) {
        for (j, p) in px.chunks_exact_mut(4).enumerate() {
            let t = 4 * j as i16;
            let mut c = 0i16;
            for &(a, b, full) in spans {
                let (a, b, short) = (relative(a, x0), relative(b, x0), 64 - full as i16);
                let o = (b - t).clamp(0, 4) - (a - t).clamp(0, 4);
                c += 16 * o - if o == 4 { short } else { 0 };
            }
            let c = c as u16;
            ink.blend(p, (c - (c >> 8)).min(255) as u8);
        }
    }
}
